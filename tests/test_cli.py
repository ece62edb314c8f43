"""The `scriptc` command: every verb, exit status and format, through click's CliRunner, and a
few real processes (`python -m scriptc`) for what only a process shows: the entry point,
stdin and stdout as bytes, the absence of tracebacks."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc import __version__
from scriptc.cli.main import cli

DATA = Path(__file__).parent / "data"

CLEAN = "[clean_act]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
# The thesis example: valid, with a warning (M004) and an info (F003), so it still passes.
WARNS = (
    "[example_act]\n"
    '[alfa:16,my_rule,"\\\\myinputtopic","\\\\myoutputtopic",A,M]\n'
    '[alfa:0,kick_starter,"","",R,U]\n'
    '[omega:0,kick_starter,"","",C,L]\n'
    "[goal:blinking_and_stop]\n"
    "[action]\n"
    '[b##blk_inst: MV() LD("0, 0, 1, 1, 0, 100", "0, 0, 1, 1, 0, 100") AO()]\n'
)
BROKEN = ("[bad_act]\n[goal:g]\n[action]\n"
          "[b#a#blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n[b##blk_terminus]\n")


def run(*args: str, input: bytes | str | None = None, env: dict | None = None):
    return CliRunner().invoke(cli, list(args), input=input, env=env, catch_exceptions=False)


def process(*args: str, input: bytes | None = None, cwd: Path | None = None,
            env: dict | None = None) -> subprocess.CompletedProcess:
    full_env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "NO_COLOR")}
    full_env.update(env or {})
    return subprocess.run([sys.executable, "-m", "scriptc", *args], input=input,
                          capture_output=True, cwd=cwd, env=full_env, timeout=60, check=False)


@pytest.fixture
def files(tmp_path: Path, monkeypatch) -> Path:
    """A working folder with a clean, a warning-only and a broken script."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "clean.script").write_text(CLEAN, encoding="utf-8")
    (tmp_path / "warns.script").write_text(WARNS, encoding="utf-8")
    (tmp_path / "broken.script").write_text(BROKEN, encoding="utf-8")
    return tmp_path


# ---------------------------------------------------------------------------------------------
# the group


def test_version() -> None:
    result = run("--version")
    assert result.exit_code == 0
    assert result.stdout == f"scriptc {__version__}\n"


def test_help_lists_every_verb() -> None:
    result = run("--help")
    assert result.exit_code == 0
    for verb in ("compile", "lint", "check", "decompile", "explain"):
        assert f"  {verb} " in result.stdout


@pytest.mark.parametrize("args", [["frobnicate"], ["lint"], ["lint", "--format", "xml", "x"],
                                  ["compile"], ["--color", "sometimes", "lint", "x"]])
def test_usage_errors_exit_2(args: list[str]) -> None:
    assert run(*args).exit_code == 2


def test_an_internal_error_is_reported_without_a_traceback(files: Path, monkeypatch) -> None:
    def broken(*args, **kwargs):
        raise RuntimeError("the checks fell over")

    monkeypatch.setattr("scriptc.analysis.analyze.finish", broken)
    result = run("lint", "clean.script")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: internal error: RuntimeError: the checks fell over\n")
    assert "please report it" in result.stderr
    assert "Traceback" not in result.output


def test_an_interrupt_exits_130_quietly(files: Path, monkeypatch) -> None:
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("scriptc.analysis.analyze.finish", interrupted)
    result = run("compile", "clean.script")
    assert (result.exit_code, result.stderr) == (130, "error: interrupted\n")
    # lint says how far it got.
    linted = run("lint", "clean.script")
    assert (linted.exit_code, linted.stderr) == (
        130, ("error: interrupted (Ctrl-C) while linting, 0 of 1 file analysed: nothing was "
              "reported, and no file was left half-written\n"))


# ---------------------------------------------------------------------------------------------
# lint


def test_lint_clean_file_prints_nothing(files: Path) -> None:
    result = run("lint", "clean.script")
    assert (result.exit_code, result.stdout, result.stderr) == (0, "", "")


def test_lint_warnings_alone_pass(files: Path) -> None:
    result = run("lint", "warns.script")
    assert result.exit_code == 0
    assert "warning[M004]" in result.stdout
    assert result.stdout.endswith("warning: 1 warning, 1 info message emitted\n")


def test_lint_errors_exit_1(files: Path) -> None:
    result = run("lint", "broken.script")
    assert result.exit_code == 1
    assert "error[L003]" in result.stdout
    assert " --> broken.script:4:36\n" in result.stdout
    assert result.stdout.endswith("error: 1 error emitted\n")


def test_lint_a_folder_recursively_sorted_skipping_hidden(files: Path) -> None:
    (files / "sub" / "deeper").mkdir(parents=True)
    (files / "sub" / "deeper" / "a.script").write_text(BROKEN, encoding="utf-8")
    (files / ".hidden").mkdir()
    (files / ".hidden" / "x.script").write_text(BROKEN, encoding="utf-8")
    (files / ".lock.script").write_text(BROKEN, encoding="utf-8")
    (files / "notes.txt").write_text("not a script", encoding="utf-8")
    result = run("lint", ".", "--format", "json")
    assert result.exit_code == 1
    seen = list(dict.fromkeys(Path(r["file"]).as_posix() for r in json.loads(result.stdout)))
    assert seen == ["broken.script", "sub/deeper/a.script", "warns.script"]


def test_lint_reads_a_named_file_whatever_its_suffix_and_each_file_once(files: Path) -> None:
    (files / "script.txt").write_text(BROKEN, encoding="utf-8")
    result = run("lint", "script.txt", "broken.script", "./broken.script", "--format", "json")
    assert result.exit_code == 1
    assert [r["file"] for r in json.loads(result.stdout)] == ["script.txt", "broken.script"]


def test_lint_a_path_that_does_not_exist_exits_2(files: Path) -> None:
    result = run("lint", "clean.script", "nowhere.script")
    assert result.exit_code == 2
    assert result.stderr == "error: `nowhere.script` does not exist\n"
    assert result.stdout == ""


def test_every_path_is_reported_beside_the_missing_ones(files: Path) -> None:
    result = run("lint", "nothere.script", "broken.script", "gone/", "--format", "json")
    assert result.exit_code == 2
    assert result.stderr == ("error: `nothere.script` does not exist\n"
                             "error: `gone` does not exist\n")
    assert [r["code"] for r in json.loads(result.stdout)] == ["L003"]
    (files / "messy.script").write_text("[m]\n[goal:g]\n[action]\n[b##blk_terminus]   \n",
                                        encoding="utf-8")
    formatted = run("fmt", "nothere.script", "messy.script")
    assert formatted.exit_code == 2
    assert formatted.stderr == ("error: `nothere.script` does not exist\n"
                                "reformatted messy.script\n")
    assert (files / "messy.script").read_text(encoding="utf-8").endswith("[b##blk_terminus]\n")


def without_root_powers() -> None:
    """A child's start: even as root, file permissions apply to it (the capabilities that
    override them are dropped from its bounding set, so the program it runs lacks them)."""
    if os.geteuid() != 0:
        return
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    PR_CAPBSET_DROP, CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH = 24, 1, 2
    for capability in (CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH):
        if libc.prctl(PR_CAPBSET_DROP, capability, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")


@pytest.mark.slow
def test_a_folder_that_cannot_be_read_is_an_error(files: Path) -> None:
    locked = files / "locked"
    locked.mkdir()
    (locked / "bad.script").write_text(BROKEN, encoding="utf-8")
    locked.chmod(0)
    try:
        result = subprocess.run([sys.executable, "-m", "scriptc", "lint", ".", "--format",
                                 "json"], capture_output=True, cwd=files, timeout=60,
                                preexec_fn=without_root_powers, check=False)
        formatted = subprocess.run([sys.executable, "-m", "scriptc", "fmt", "--check", "."],
                                   capture_output=True, cwd=files, timeout=60,
                                   preexec_fn=without_root_powers, check=False)
    finally:
        locked.chmod(0o755)
    message = (b"error: cannot read the folder `locked`: permission denied; the scripts in it "
               b"were not checked (make it readable, or exclude it in the configuration)\n")
    assert result.returncode == 2
    assert result.stderr.startswith(message)
    assert b"checked 3 files: 1 error" in result.stderr  # the readable ones are reported
    assert {r["file"] for r in json.loads(result.stdout)} == {"broken.script", "warns.script"}
    assert formatted.returncode == 2 and formatted.stderr.startswith(message)


def test_lint_an_unreadable_file_exits_2_and_still_reports_the_others(files: Path) -> None:
    os.symlink(files / "gone.script", files / "dangling.script")
    result = run("lint", ".")
    assert result.exit_code == 2
    assert "error: `dangling.script` does not exist" in result.stderr
    assert "error[L003]" in result.stdout


def test_lint_permission_denied_is_a_clear_error(files: Path, monkeypatch) -> None:
    # Tests may run as root, who reads any file: make `open` refuse instead.
    def refuse(path, mode="r", *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr("scriptc.analysis.read.open", refuse, raising=False)
    result = run("lint", "clean.script")
    assert result.exit_code == 2
    assert result.stderr == "error: cannot read `clean.script`: permission denied\n"


def test_lint_an_empty_folder_warns_and_passes(files: Path) -> None:
    (files / "empty").mkdir()
    result = run("lint", "empty")
    assert result.exit_code == 0
    assert result.stderr == "warning: no script files found under the given paths\n"


def test_lint_stdin(files: Path) -> None:
    result = run("lint", "-", input=BROKEN.encode())
    assert result.exit_code == 1
    assert " --> <stdin>:4:36\n" in result.stdout
    named = run("lint", "-", "--stdin-filename", "mine.script", input=BROKEN.encode())
    assert " --> mine.script:4:36\n" in named.stdout


def test_lint_empty_file_is_an_error(files: Path) -> None:
    (files / "empty.script").write_bytes(b"")
    result = run("lint", "empty.script", "--format", "json")
    assert result.exit_code == 1
    (record,) = json.loads(result.stdout)
    assert (record["code"], record["line"], record["column"]) == ("S001", 1, 1)


def test_lint_a_bom_is_ignored(files: Path) -> None:
    (files / "bom.script").write_bytes(b"\xef\xbb\xbf" + BROKEN.encode())
    result = run("lint", "bom.script", "--format", "json")
    assert [(r["code"], r["line"], r["column"]) for r in json.loads(result.stdout)] == [
        ("L003", 4, 36)]


def test_lint_invalid_utf8_is_p007_at_the_bad_byte(files: Path) -> None:
    # `ù` in Latin-1 (0xF9) on line 4, after the multi-byte `é` (two bytes, one column).
    data = "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO(\"é/pi".encode() + \
        b"\xf9.mp3, 0, 1\")]\n"
    (files / "latin1.script").write_bytes(data)
    result = run("lint", "latin1.script", "--format", "json")
    assert result.exit_code == 1
    (record,) = json.loads(result.stdout)
    assert (record["code"], record["line"], record["column"]) == ("P007", 4, 33)
    assert "0xf9" in record["message"]
    bad = data.index(b"\xf9")
    assert record["notes"] == [f"at byte offset {bad} of the file"]
    text = run("lint", "latin1.script")
    assert "error[P007]" in text.stdout and " --> latin1.script:4:33\n" in text.stdout


def test_lint_a_binary_file_is_p007_not_a_crash(files: Path) -> None:
    (files / "image.script").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)))
    result = run("lint", "image.script")
    assert result.exit_code == 1
    assert "error[P007]" in result.stdout
    assert "\x00" not in result.stdout and "\x1a" not in result.stdout
    json_result = run("lint", "image.script", "--format", "json")
    (record,) = json.loads(json_result.stdout)
    assert (record["line"], record["column"]) == (1, 1)  # 0x89 is not UTF-8


def test_lint_utf16_file_says_so(files: Path) -> None:
    (files / "wide.script").write_bytes(CLEAN.encode("utf-16"))
    (record,) = json.loads(run("lint", "wide.script", "--format", "json").stdout)
    assert record["code"] == "P007"
    assert any("UTF-16" in note for note in record["notes"])


def test_lint_a_file_of_megabytes(files: Path) -> None:
    comment = "% " + "a line of a long comment\n" * 200_000 + "%\n"  # about 5 MB
    (files / "big.script").write_text(comment + BROKEN, encoding="utf-8")
    (record,) = json.loads(run("lint", "big.script", "--format", "json").stdout)
    assert (record["code"], record["line"]) == ("L003", 200_001 + 4)
    (files / "bigbad.script").write_bytes((comment + "[a]\n").encode() + b"\xc3(")
    (record,) = json.loads(run("lint", "bigbad.script", "--format", "json").stdout)
    assert (record["code"], record["line"], record["column"]) == ("P007", 200_003, 1)


@pytest.mark.parametrize("format_", ["text", "json", "sarif", "github"])
def test_lint_every_format(files: Path, format_: str) -> None:
    result = run("lint", "broken.script", "warns.script", "clean.script", "--format", format_)
    assert result.exit_code == 1
    out = result.stdout
    if format_ == "text":
        assert "error[L003]" in out and "warning[M004]" in out
    elif format_ == "json":
        assert {r["code"] for r in json.loads(out)} >= {"L003", "M004"}
    elif format_ == "sarif":
        log = json.loads(out)
        assert log["version"] == "2.1.0"
        results = log["runs"][0]["results"]
        assert {r["ruleId"] for r in results} >= {"L003", "M004"}
        uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
        assert uris == {"broken.script", "warns.script"}
    else:
        assert ("::error file=broken.script,line=4,col=36,endLine=4,endColumn=43,title=L003::"
                in out)
        assert "::warning file=warns.script," in out
        assert "::notice file=warns.script," in out


@pytest.mark.parametrize("format_", ["json", "sarif"])
def test_lint_clean_machine_formats_are_still_documents(files: Path, format_: str) -> None:
    result = run("lint", "clean.script", "--format", format_)
    assert result.exit_code == 0
    assert json.loads(result.stdout) is not None


def test_colour_only_when_asked_or_forced(files: Path) -> None:
    plain = run("lint", "broken.script")
    assert "\x1b[" not in plain.stdout  # CliRunner's stdout is not a terminal
    assert "\x1b[" in run("--color", "always", "lint", "broken.script").stdout
    assert "\x1b[" in run("lint", "broken.script", env={"FORCE_COLOR": "1"}).stdout
    assert "\x1b[" not in run("lint", "broken.script",
                              env={"FORCE_COLOR": "1", "NO_COLOR": "1"}).stdout
    assert "\x1b[" not in run("--color", "never", "lint", "broken.script",
                              env={"FORCE_COLOR": "1"}).stdout
    # Machine formats are never coloured.
    json.loads(run("--color", "always", "lint", "broken.script", "--format", "json").stdout)


# ---------------------------------------------------------------------------------------------
# compile


def test_compile_writes_beside_the_input(files: Path) -> None:
    result = run("compile", "warns.script")
    assert result.exit_code == 0
    assert result.stdout == ""
    assert "warning[M004]" in result.stderr  # diagnostics go to stderr
    out = json.loads((files / "warns.json").read_text(encoding="utf-8"))
    assert out["activityname"] == "example_act"


def test_compile_output_is_exactly_the_emitted_text(files: Path) -> None:
    from scriptc.analysis.analyze import analyze_script
    from scriptc.emit.json import emit_json
    from scriptc.source import SourceFile

    expected = emit_json(analyze_script(SourceFile("clean.script", CLEAN)).script)
    assert run("compile", "clean.script", "-o", "out.json").exit_code == 0
    assert (files / "out.json").read_bytes() == expected.encode("utf-8")
    stdout = run("compile", "clean.script", "-o", "-")
    assert stdout.exit_code == 0 and stdout.stdout == expected
    assert not (files / "clean.json").exists()
    piped = run("compile", "-", input=CLEAN.encode())
    assert piped.exit_code == 0 and piped.stdout == expected


def test_compile_errors_write_nothing(files: Path) -> None:
    result = run("compile", "broken.script")
    assert result.exit_code == 1
    assert "error[L003]" in result.stderr
    assert not (files / "broken.json").exists()
    # An existing output stays as it was, and no temporary file is left behind.
    (files / "old.json").write_text("old", encoding="utf-8")
    assert run("compile", "broken.script", "-o", "old.json").exit_code == 1
    assert (files / "old.json").read_text(encoding="utf-8") == "old"
    assert sorted(p.name for p in files.iterdir()) == [
        "broken.script", "clean.script", "old.json", "warns.script"]


def test_compile_replaces_an_existing_output_keeping_its_mode(files: Path) -> None:
    target = files / "clean.json"
    target.write_text("old", encoding="utf-8")
    target.chmod(0o640)
    assert run("compile", "clean.script").exit_code == 0
    assert target.read_text(encoding="utf-8") != "old"
    assert target.stat().st_mode & 0o777 == 0o640
    assert sorted(p.name for p in files.iterdir() if p.name.startswith(".")) == []


def test_compile_refuses_to_overwrite_its_input(files: Path) -> None:
    (files / "script.scb").write_text(CLEAN, encoding="utf-8")
    # The default output is the input itself.
    result = run("compile", "script.scb", "--emit", "bytecode")
    assert result.exit_code == 2
    assert "refusing to overwrite" in result.stderr
    assert (files / "script.scb").read_text(encoding="utf-8") == CLEAN
    assert run("compile", "clean.script", "-o", "./clean.script").exit_code == 2
    assert (files / "clean.script").read_text(encoding="utf-8") == CLEAN


def test_compile_unwritable_output_exits_2(files: Path) -> None:
    result = run("compile", "clean.script", "-o", "no/such/folder/out.json")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: cannot write `no/such/folder/out.json`")
    (files / "adir").mkdir()
    assert run("compile", "clean.script", "-o", "adir").exit_code == 2


def test_compile_bad_input_paths_exit_2(files: Path) -> None:
    missing = run("compile", "missing.script")
    assert (missing.exit_code, missing.stderr) == (2, "error: `missing.script` does not exist\n")
    (files / "folder").mkdir()
    folder = run("compile", "folder")
    assert (folder.exit_code, folder.stderr) == (2, "error: `folder` is a directory, not a file\n")


def test_compile_emit_is_a_choice(files: Path) -> None:
    assert run("compile", "clean.script", "--emit", "json", "-o", "-").exit_code == 0
    assert run("compile", "clean.script", "--emit", "wasm").exit_code == 2


def test_compile_invalid_utf8_writes_nothing(files: Path) -> None:
    (files / "bad.script").write_bytes(b"[a\xff]\n")
    result = run("compile", "bad.script")
    assert result.exit_code == 1 and "error[P007]" in result.stderr
    assert not (files / "bad.json").exists()


# ---------------------------------------------------------------------------------------------
# check and decompile


@pytest.fixture
def thesis(files: Path) -> Path:
    for name in ("test_act.json", "dance_example.json"):
        (files / name).write_bytes((DATA / name).read_bytes())
    return files


def test_check_thesis_files(thesis: Path) -> None:
    result = run("check", "test_act.json", "dance_example.json", "--format", "json")
    assert result.exit_code == 0, result.stdout
    assert all(r["severity"] != "error" for r in json.loads(result.stdout))


def test_check_errors_and_formats(thesis: Path) -> None:
    (thesis / "bad.json").write_text('{"activityname": "a", ', encoding="utf-8")
    for format_ in ("text", "json", "sarif", "github"):
        result = run("check", "bad.json", "--format", format_)
        assert result.exit_code == 1
        assert "J001" in result.stdout
    stdin = run("check", "-", "--format", "json", input=b'{"activityname": 3}')
    assert stdin.exit_code == 1 and json.loads(stdin.stdout)[0]["file"] == "<stdin>"


def test_check_bad_paths_exit_2(thesis: Path) -> None:
    missing = run("check", "missing.json", "test_act.json", "--format", "json")
    assert (missing.exit_code, missing.stderr) == (2, "error: `missing.json` does not exist\n")
    # The file named beside the missing one is still checked and reported.
    assert {r["file"] for r in json.loads(missing.stdout)} == {"test_act.json"}


def test_check_a_folder_checks_every_json_script_under_it(thesis: Path) -> None:
    folder = thesis / "repo"
    (folder / "deep").mkdir(parents=True)
    (folder / "a.json").write_bytes((DATA / "test_act.json").read_bytes())
    (folder / "deep" / "broken.json").write_text('{"activityname": "b", "goal0": ',
                                                 encoding="utf-8")
    # Not scripts: a scenario, a list, a package description; a hidden folder is skipped.
    (folder / "scenario.json").write_text('{"updates": []}', encoding="utf-8")
    (folder / "deep" / "list.json").write_text("[1, 2]", encoding="utf-8")
    (folder / "deep" / "not-json.json").write_text("{oops", encoding="utf-8")
    (folder / ".hidden").mkdir()
    (folder / ".hidden" / "h.json").write_bytes((DATA / "test_act.json").read_bytes())
    (folder / "x.script").write_text(BROKEN, encoding="utf-8")
    result = run("check", "repo", "--format", "json")
    assert result.exit_code == 1
    files = sorted({Path(r["file"]).as_posix() for r in json.loads(result.stdout)})
    assert files == ["repo/a.json", "repo/deep/broken.json"]
    assert "checked 2 files:" in result.stderr
    empty = thesis / "empty"
    empty.mkdir()
    (empty / "scenario.json").write_text('{"updates": []}', encoding="utf-8")
    nothing = run("check", "empty")
    assert (nothing.exit_code, nothing.stderr) == (
        0, "warning: no script files found under the given paths\n")


def test_compile_refuses_thesis_json_and_says_what_reads_it(thesis: Path) -> None:
    before = sorted(p.name for p in thesis.iterdir())
    result = run("compile", "test_act.json", "-o", "out.json")
    assert (result.exit_code, result.stderr) == (
        2, ("error: `test_act.json` is thesis JSON, not script syntax: `scriptc check "
            "test_act.json` checks it, `scriptc decompile test_act.json` turns it into a script\n"))
    piped = run("compile", "-", "--stdin-filename", "mine.JSON", input=b"{}")
    assert piped.exit_code == 2 and "`scriptc check mine.JSON`" in piped.stderr
    assert sorted(p.name for p in thesis.iterdir()) == before


def test_check_invalid_utf8(thesis: Path) -> None:
    (thesis / "bad.json").write_bytes(b'{"activityname": "\xe0"}')
    result = run("check", "bad.json", "--format", "json")
    assert result.exit_code == 1
    assert [(r["code"], r["column"]) for r in json.loads(result.stdout)] == [("P007", 19)]


def test_decompile_to_stdout_and_to_a_file(thesis: Path) -> None:
    result = run("decompile", "test_act.json")
    assert result.exit_code == 0, result.stderr
    assert result.stdout.startswith("[test_act]")
    assert run("decompile", "test_act.json", "-o", "test_act.script").exit_code == 0
    assert (thesis / "test_act.script").read_text(encoding="utf-8") == result.stdout
    # The decompiled script compiles back.
    assert run("lint", "test_act.script").exit_code == 0


def test_decompile_refuses_bad_input(thesis: Path) -> None:
    (thesis / "bad.json").write_text("[1, 2", encoding="utf-8")
    result = run("decompile", "bad.json", "-o", "bad.script")
    assert result.exit_code == 1 and "J001" in result.stderr
    assert not (thesis / "bad.script").exists()
    assert run("decompile", "test_act.json", "-o", "test_act.json").exit_code == 2
    assert run("decompile", "missing.json").exit_code == 2


# ---------------------------------------------------------------------------------------------
# explain


def test_explain_a_code() -> None:
    result = run("explain", "P007")
    assert result.exit_code == 0
    assert result.stdout.startswith("P007 (unreadable-file): the file is not UTF-8 text\n")
    assert "## How to fix" in result.stdout
    # Names and lower case work too.
    assert run("explain", "unreadable-file").stdout == result.stdout
    assert run("explain", "p007").stdout == result.stdout


def test_explain_an_unknown_code_suggests() -> None:
    result = run("explain", "L03")
    assert result.exit_code == 2
    assert result.stderr.startswith(
        "error: unknown code `L03`; did you mean `L003` (unknown-label)")
    assert run("explain", "unknown-labl").stderr.count("`L003` (unknown-label)") == 1


def test_explain_all() -> None:
    from scriptc.diagnostics.codes import all_codes

    text = run("explain", "--all")
    assert text.exit_code == 0
    assert len(text.stdout.splitlines()) == len(all_codes())
    assert text.stdout.startswith("P001  error    unexpected-token")
    records = json.loads(run("explain", "--all", "--format", "json").stdout)
    assert records[0] == {"code": "P001", "name": "unexpected-token", "severity": "error",
                          "summary": "the parser found a token where another was expected"}
    assert [r["code"] for r in records] == [c.code for c in all_codes()]


@pytest.mark.parametrize("args", [["explain"], ["explain", "L003", "--all"]])
def test_explain_needs_a_code_or_all(args: list[str]) -> None:
    assert run(*args).exit_code == 2


# ---------------------------------------------------------------------------------------------
# real processes


@pytest.mark.slow
def test_process_lint_exit_codes(files: Path) -> None:
    assert process("lint", "clean.script", cwd=files).returncode == 0
    assert process("lint", "warns.script", cwd=files).returncode == 0
    broken = process("lint", "broken.script", cwd=files)
    assert broken.returncode == 1
    assert b"error[L003]" in broken.stdout and b"\x1b[" not in broken.stdout
    missing = process("lint", "nope.script", cwd=files)
    assert (missing.returncode, missing.stderr) == (2, b"error: `nope.script` does not exist\n")


@pytest.mark.slow
def test_process_stdin_and_binary_input(files: Path) -> None:
    piped = process("lint", "-", "--format", "github", input=BROKEN.encode(), cwd=files)
    assert piped.returncode == 1 and piped.stdout.startswith(b"::error file=<stdin>,line=4,")
    (files / "bin.script").write_bytes(bytes(range(256)) * 10)
    binary = process("lint", "bin.script", cwd=files)
    assert binary.returncode == 1 and b"error[P007]" in binary.stdout
    assert b"Traceback" not in binary.stderr


@pytest.mark.slow
def test_process_compile_and_version(files: Path) -> None:
    out = process("compile", "clean.script", "-o", "-", cwd=files)
    assert out.returncode == 0 and json.loads(out.stdout)["activityname"] == "clean_act"
    assert process("--version").stdout == f"scriptc {__version__}\n".encode()


def test_process_internal_error_has_no_traceback(files: Path) -> None:
    # A file that decodes but whose analysis is forced to fail: patch the analysis in a child.
    code = ("import sys, scriptc.analysis.analyze as d\n"
            "def boom(*a, **k): raise ValueError('boom')\n"
            "d.finish = boom\n"
            "from scriptc.cli.main import main\n"
            "sys.argv = ['scriptc', 'lint', 'clean.script']\n"
            "main()\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, cwd=files,
                            timeout=60, check=False)
    assert result.returncode == 2
    assert result.stderr.startswith(b"error: internal error: ValueError: boom\n")
    assert b"Traceback" not in result.stderr


def test_process_broken_pipe_is_quiet(files: Path) -> None:
    proc = subprocess.Popen([sys.executable, "-m", "scriptc", "explain", "--all"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader goes away, as with `| head -0`
    stderr = proc.stderr.read()
    proc.wait(timeout=60)
    assert b"Traceback" not in stderr and b"internal error" not in stderr
