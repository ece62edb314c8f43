"""`scriptc compile --emit bytecode` and `scriptc dis`: outputs, exit statuses, refusals as one
line on stderr (never a traceback)."""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.analysis.analyze import analyze_file
from scriptc.bytecode import decode, disassemble, load
from scriptc.cli.main import cli
from scriptc.emit.codegen import codegen

ROOT = Path(__file__).parent.parent
EXAMPLE = ROOT / "examples" / "test_act.script"
BROKEN = "[bad_act]\n[goal:g]\n[action]\n[b#a#blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n"


def run(*args: str, input: bytes | None = None):
    return CliRunner().invoke(cli, list(args), input=input, catch_exceptions=False)


@pytest.fixture
def folder(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "test_act.script").write_bytes(EXAMPLE.read_bytes())
    (tmp_path / "broken.script").write_text(BROKEN, encoding="utf-8")
    return tmp_path


def test_help_lists_dis() -> None:
    assert "  dis " in run("--help").stdout


def test_compile_writes_scb_beside_the_input(folder: Path) -> None:
    result = run("compile", "--emit", "bytecode", "test_act.script")
    assert result.exit_code == 0, result.stderr
    program = load((folder / "test_act.scb").read_bytes()).program
    analysis = analyze_file(EXAMPLE)
    expected = codegen(analysis.script, analysis.source)
    # The same code and tables as codegen makes (with or without the source's positions).
    assert (program.code, program.blocks, program.alfa, program.omega) == \
        (expected.code, expected.blocks, expected.alfa, expected.omega)
    assert run("compile", "--emit", "bytecode", "test_act.script", "-o", "x.scb").exit_code == 0
    assert (folder / "x.scb").read_bytes() == (folder / "test_act.scb").read_bytes()


def test_compile_errors_write_no_scb(folder: Path) -> None:
    result = run("compile", "--emit", "bytecode", "broken.script")
    assert result.exit_code == 1
    assert "nowhere" in result.stderr
    assert not (folder / "broken.scb").exists()


def test_dis_prints_the_listing(folder: Path) -> None:
    assert run("compile", "--emit", "bytecode", "test_act.script").exit_code == 0
    result = run("dis", "test_act.scb")
    assert result.exit_code == 0
    data = (folder / "test_act.scb").read_bytes()
    assert result.stdout == disassemble(decode(data))
    assert "goal0/act0/blk3  jump" in result.stdout
    assert "GOTO            goal0/act0/blk0 (dance)" in result.stdout
    assert run("dis", "-", input=data).stdout == result.stdout


def _corrupt(data: bytes, how: str) -> bytes:
    if how == "truncated":
        return data[:-7]
    if how == "checksum":
        return data[:-1] + bytes([data[-1] ^ 1])
    if how == "version":
        return data[:4] + struct.pack("<H", 9) + data[6:]
    if how == "text":
        return EXAMPLE.read_bytes()
    raise AssertionError(how)


@pytest.mark.parametrize("how,message", [
    ("truncated", "malformed bytecode: the file is truncated"),
    ("checksum", "malformed bytecode: checksum mismatch"),
    ("version", "malformed bytecode: unsupported format version 9"),
    ("text", "malformed bytecode: not a scriptc bytecode file"),
])
def test_dis_refuses_bad_files(folder: Path, how: str, message: str) -> None:
    assert run("compile", "--emit", "bytecode", "test_act.script").exit_code == 0
    (folder / "bad.scb").write_bytes(_corrupt((folder / "test_act.scb").read_bytes(), how))
    result = run("dis", "bad.scb")
    assert result.exit_code == 1
    assert result.stdout == ""
    assert result.stderr.startswith(f"error: bad.scb: {message}")
    assert result.stderr.count("\n") == 1


def test_dis_of_a_file_that_cannot_be_read_exits_2(folder: Path) -> None:
    for path in ("missing.scb", "."):
        result = run("dis", path)
        assert result.exit_code == 2
        assert result.stderr.startswith("error: ")


def test_dis_in_a_real_process_never_shows_a_traceback(folder: Path) -> None:
    (folder / "bad.scb").write_bytes(b"SCB\0" + bytes(40))
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "NO_COLOR")}
    done = subprocess.run([sys.executable, "-m", "scriptc", "dis", "bad.scb"],
                          capture_output=True, text=True, cwd=folder, env=env, timeout=60,
                          check=False)
    assert done.returncode == 1
    assert "Traceback" not in done.stderr
    assert done.stderr.startswith("error: bad.scb: malformed bytecode: ")


PROBE = """
import json, sys
from scriptc.cli.main import main
sys.argv = ["scriptc", "dis", sys.argv[1]]
try:
    main()
except SystemExit:
    pass
sys.stdout.flush()
sys.__stderr__.write("\\nMODULES " + json.dumps(sorted(sys.modules)))
"""


def test_dis_imports_no_parser(folder: Path) -> None:
    """A runtime needs no parser: listing a program does not load lark or the front end."""
    assert run("compile", "--emit", "bytecode", "test_act.script").exit_code == 0
    done = subprocess.run([sys.executable, "-c", PROBE, "test_act.scb"], capture_output=True,
                          text=True, cwd=folder, timeout=60, check=False)
    modules = json.loads(done.stderr[done.stderr.rindex("MODULES ") + 8:])
    assert not [m for m in modules if m.split(".")[0] == "lark" or
                m.startswith(("scriptc.syntax", "scriptc.emit", "scriptc.check"))]
