"""The one writer (`scriptc.writing`) and every verb that writes through it: what a path *is*
decides how it is written (a link's target, a device or FIFO directly, a regular file
atomically with its mode kept), a folder or a missing parent is refused before any work, and a
write that fails leaves the old file as it was, with no temporary file behind.

Real files, links, FIFOs, devices and sockets; the failed writes are real too (a child
process whose file-size limit is too small for the output)."""

from __future__ import annotations

import json
import os
import signal
import socket
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc import writing
from scriptc.cli.main import cli

CLEAN = "[clean_act]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
BROKEN = ("[bad_act]\n[goal:g]\n[action]\n"
          "[b#a#blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n[b##blk_terminus]\n")
# Not in the canonical layout: `fmt` rewrites it.
MESSY = "[messy]\n[goal:g]\n[action]\n[b##blk_inst:   MV()  LD() AO()]\n[b##blk_terminus]\n"
# R007 (a lowercase scope) has a safe fix.
FIXABLE = ("[fixable]\n[goal:g]\n[action]\n"
           "[b##blk_jump: CND({CLASS #Human u ?kid (B: near(1))} ! {TRUE}) TRJMP() FLSJMP()]\n"
           "[b##blk_terminus]\n")


def run(*args: str, input: bytes | None = None):
    return CliRunner().invoke(cli, list(args), input=input, catch_exceptions=False)


@pytest.fixture
def here(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    (tmp_path / "clean.script").write_text(CLEAN, encoding="utf-8")
    (tmp_path / "broken.script").write_text(BROKEN, encoding="utf-8")
    return tmp_path


def expected_json() -> bytes:
    from scriptc.analysis.analyze import analyze_script
    from scriptc.emit.json import emit_json
    from scriptc.source import SourceFile

    return emit_json(analyze_script(SourceFile("clean.script", CLEAN)).script).encode("utf-8")


def leftovers(folder: Path) -> list[str]:
    """Temporary files the writer may have left in `folder` (recursively)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*.tmp"))


# ---------------------------------------------------------------------------------------------
# what the path is


def test_a_link_is_followed_and_stays_a_link(here: Path) -> None:
    (here / "real").mkdir()
    target = here / "real" / "out.json"
    target.write_text("old", encoding="utf-8")
    target.chmod(0o640)
    os.symlink(os.path.join("real", "out.json"), here / "link.json")
    result = run("compile", "clean.script", "-o", "link.json")
    assert result.exit_code == 0, result.output
    assert (here / "link.json").is_symlink()
    assert os.readlink(here / "link.json") == os.path.join("real", "out.json")
    assert target.read_bytes() == expected_json()
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert leftovers(here) == []


def test_a_dangling_link_gets_its_target_made(here: Path) -> None:
    (here / "real").mkdir()
    os.symlink(os.path.join("real", "new.json"), here / "link.json")
    assert run("compile", "clean.script", "-o", "link.json").exit_code == 0
    assert (here / "link.json").is_symlink()
    assert (here / "real" / "new.json").read_bytes() == expected_json()


def test_fmt_and_fix_rewrite_the_target_of_a_linked_script(here: Path) -> None:
    (here / "src").mkdir()
    messy, fixable = here / "src" / "messy.script", here / "src" / "fixable.script"
    messy.write_text(MESSY, encoding="utf-8")
    fixable.write_text(FIXABLE, encoding="utf-8")
    messy.chmod(0o604)
    os.symlink(os.path.join("src", "messy.script"), here / "messy.script")
    os.symlink(os.path.join("src", "fixable.script"), here / "fixable.script")
    formatted = run("fmt", "messy.script")
    assert formatted.exit_code == 0, formatted.output
    assert (here / "messy.script").is_symlink()
    assert "MV() LD() AO()]" in messy.read_text(encoding="utf-8")
    assert stat.S_IMODE(messy.stat().st_mode) == 0o604
    fixed = run("lint", "--fix", "fixable.script")
    assert "fixed 1 problem in 1 file" in fixed.stderr
    assert (here / "fixable.script").is_symlink()
    assert "#Human U ?kid" in fixable.read_text(encoding="utf-8")
    assert leftovers(here) == []


def test_a_fifo_is_written_to_not_replaced(here: Path) -> None:
    fifo = here / "out.fifo"
    os.mkfifo(fifo)
    # A reader opened first (without blocking), so the writer's open does not wait; the data
    # is small enough for the pipe's buffer.
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        result = run("compile", "clean.script", "-o", "out.fifo")
        assert result.exit_code == 0, result.output
        received = b""
        while chunk := os.read(reader, 65536):
            received += chunk
    finally:
        os.close(reader)
    assert received == expected_json()
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert leftovers(here) == []


def character_device(here: Path) -> Path:
    """A null device: made here where the tests may (root), else the system's /dev/null. Made
    here, a writer that replaced devices could never break the machine running the tests."""
    made = here / "null"
    try:
        os.mknod(made, stat.S_IFCHR | 0o666, os.makedev(1, 3))
        with open(made, "wb"):
            pass
        return made
    except OSError:
        if made.exists():
            made.unlink()
        return Path(os.devnull)


def test_a_device_is_written_to_not_replaced(here: Path) -> None:
    device = character_device(here)
    result = run("compile", "clean.script", "-o", str(device))
    assert result.exit_code == 0, result.output
    assert stat.S_ISCHR(os.lstat(device).st_mode)
    traced = run("run", "clean.script", "--robot", "kinematic", "--trace", str(device))
    assert traced.exit_code == 0, traced.output
    assert stat.S_ISCHR(os.lstat(device).st_mode)
    assert leftovers(here) == []


def test_a_socket_is_sent_the_data(tmp_path: Path) -> None:
    path = str(tmp_path / "out.sock")
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(path)
    server.listen(1)
    received = []

    def accept() -> None:
        connection, _ = server.accept()
        with connection:
            data = b""
            while chunk := connection.recv(65536):
                data += chunk
            received.append(data)

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        writing.write_file(path, "through a socket\n")
        thread.join(timeout=10)
    finally:
        server.close()
    assert received == [b"through a socket\n"]
    assert stat.S_ISSOCK(os.lstat(path).st_mode)


@pytest.mark.slow
def test_the_name_of_a_descriptor_is_written_to(here: Path) -> None:
    """`-o /dev/stdout`: to whatever stdout is open on, a pipe or a file the shell opened to
    append to (never replaced: what was in it stays)."""
    piped = subprocess.run([sys.executable, "-m", "scriptc", "compile", "clean.script", "-o",
                            "/dev/stdout"], capture_output=True, cwd=here, timeout=60, check=False)
    assert (piped.returncode, piped.stdout, piped.stderr) == (0, expected_json(), b"")
    log = here / "log.txt"
    log.write_bytes(b"before\n")
    with open(log, "ab") as appended:
        result = subprocess.run([sys.executable, "-m", "scriptc", "compile", "clean.script",
                                 "-o", "/dev/stdout"], stdout=appended, stderr=subprocess.PIPE,
                                cwd=here, timeout=60, check=False)
    assert (result.returncode, result.stderr) == (0, b"")
    assert log.read_bytes() == b"before\n" + expected_json()
    assert leftovers(here) == []


@pytest.mark.slow
def test_dash_is_stdout(here: Path) -> None:
    result = subprocess.run([sys.executable, "-m", "scriptc", "compile", "clean.script",
                             "--emit", "bytecode", "-o", "-"], capture_output=True, cwd=here,
                            timeout=60, check=False)
    assert result.returncode == 0 and result.stdout.startswith(b"SCB")
    assert not (here / "-").exists()
    decompiled = run("decompile", "-", "-o", "-", input=expected_json())
    assert decompiled.exit_code == 0 and decompiled.stdout.startswith("[clean_act]")
    assert not (here / "-").exists()


# ---------------------------------------------------------------------------------------------
# refused before any work


def test_a_folder_or_a_missing_folder_is_refused_before_the_work(here: Path) -> None:
    # The script is broken: had the compilation run, its diagnostics would show (exit 1).
    missing = run("compile", "broken.script", "-o", "nodir/x.json")
    assert (missing.exit_code, missing.stderr) == (
        2, ("error: cannot write `nodir/x.json`: the folder `nodir` does not exist (create it "
            "first: mkdir -p nodir)\n"))
    (here / "adir").mkdir()
    folder = run("compile", "broken.script", "-o", "adir")
    assert folder.exit_code == 2
    assert folder.stderr.startswith("error: cannot write `adir`: it is a folder")
    (here / "file").write_text("", encoding="utf-8")
    under_a_file = run("decompile", "x.json", "-o", "file/x.script")
    assert (under_a_file.exit_code, under_a_file.stderr) == (
        2, ("error: cannot write `file/x.script`: `file` is not a folder (choose another "
            "path)\n"))
    assert not (here / "nodir").exists() and list((here / "adir").iterdir()) == []


def test_run_refuses_an_unwritable_plot_or_trace_before_the_run(here: Path, monkeypatch) -> None:
    from scriptc.runtime.session import Session

    def must_not_run(self, *args, **kwargs):
        raise AssertionError("the run started")

    monkeypatch.setattr(Session, "run", must_not_run)
    plot = run("run", "clean.script", "--robot", "kinematic", "--plot", "nodir/run.png")
    assert (plot.exit_code, plot.stderr) == (
        2, ("error: cannot write `nodir/run.png`: the folder `nodir` does not exist (create it "
            "first: mkdir -p nodir)\n"))
    (here / "traces").mkdir()
    trace = run("run", "clean.script", "--robot", "kinematic", "--trace", "traces")
    assert trace.exit_code == 2 and "cannot write `traces`: it is a folder" in trace.stderr


@pytest.mark.slow
def test_a_plot_that_cannot_be_written_at_the_end_keeps_the_summary(here: Path,
                                                                    monkeypatch) -> None:
    from scriptc.runtime.session import Session

    (here / "out").mkdir()
    real_run = Session.run

    def run_then_lose_the_folder(self, *args, **kwargs):
        result = real_run(self, *args, **kwargs)
        (here / "out").rmdir()  # gone while the session ran
        return result

    monkeypatch.setattr(Session, "run", run_then_lose_the_folder)
    result = run("run", "clean.script", "--robot", "kinematic", "--plot", "out/run.png")
    assert result.exit_code == 2
    assert result.stdout.startswith("completed at 0 ms")  # the summary is not lost
    assert result.stderr.startswith("error: cannot write `out/run.png`:")
    assert "internal error" not in result.stderr


# ---------------------------------------------------------------------------------------------
# a failed write leaves the old file as it was


def limited(max_bytes: int):
    """A child's start: files may not grow beyond `max_bytes` (a write past it fails with
    EFBIG, as on a full disk, instead of killing the process)."""
    def start() -> None:
        import resource

        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (max_bytes, max_bytes))
    return start


def scriptc(*args: str, cwd: Path, max_bytes: int) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "scriptc", *args], capture_output=True,
                          cwd=cwd, timeout=120, preexec_fn=limited(max_bytes), check=False)


def test_a_failed_write_leaves_the_old_file(here: Path) -> None:
    (here / "out.json").write_text("old", encoding="utf-8")
    result = scriptc("compile", "clean.script", "-o", "out.json", cwd=here, max_bytes=100)
    assert result.returncode == 2
    assert result.stderr == b"error: cannot write `out.json`: file too large\n"
    assert (here / "out.json").read_text(encoding="utf-8") == "old"
    assert leftovers(here) == []


@pytest.mark.slow
def test_a_failed_plot_leaves_the_old_picture(here: Path) -> None:
    (here / "run.png").write_bytes(b"old picture")
    result = scriptc("run", "clean.script", "--robot", "kinematic", "--plot", "run.png",
                     cwd=here, max_bytes=1000)
    assert result.returncode == 2
    assert result.stdout.startswith(b"completed at 0 ms")
    # (matplotlib may have its own say on stderr first)
    assert result.stderr.endswith(b"error: cannot write `run.png`: file too large\n")
    assert b"internal error" not in result.stderr
    assert (here / "run.png").read_bytes() == b"old picture"
    assert leftovers(here) == []


@pytest.mark.slow
def test_cache_entries_that_cannot_be_written_leave_nothing_behind(here: Path) -> None:
    from scriptc.project.cache import Cache

    Cache(str(here / ".scriptc_cache"))._prepare()  # its tag and .gitignore, made here
    # Entries of a few hundred bytes against a limit of 100: they fail part way.
    result = scriptc("lint", "broken.script", "clean.script", cwd=here, max_bytes=100)
    assert result.returncode == 1 and b"error[L003]" in result.stdout
    assert leftovers(here / ".scriptc_cache") == []


def test_an_interrupt_while_a_file_is_put_in_place_comes_after_it(tmp_path: Path,
                                                                   monkeypatch) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old", encoding="utf-8")
    real_fsync = os.fsync

    def fsync_then_ctrl_c(fd: int) -> None:
        real_fsync(fd)
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C while the new file is half in place

    monkeypatch.setattr(os, "fsync", fsync_then_ctrl_c)
    with pytest.raises(KeyboardInterrupt):
        writing.write_file(str(target), "new")
    # The interrupt was held until the file was whole and in place.
    assert target.read_text(encoding="utf-8") == "new"
    assert leftovers(tmp_path) == []


def test_exclusive_creation_never_replaces(tmp_path: Path) -> None:
    path = tmp_path / "x.txt"
    writing.write_file(str(path), "first", exclusive=True)
    with pytest.raises(FileExistsError):
        writing.write_file(str(path), "second", exclusive=True)
    os.symlink(tmp_path / "elsewhere", tmp_path / "link.txt")
    with pytest.raises(FileExistsError):
        writing.write_file(str(tmp_path / "link.txt"), "third", exclusive=True)
    assert path.read_text(encoding="utf-8") == "first"
    assert not (tmp_path / "elsewhere").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.txt", "x.txt"]


def test_a_new_file_gets_the_usual_mode(tmp_path: Path) -> None:
    old = os.umask(0o027)
    try:
        writing._umask = None  # read again
        writing.write_file(str(tmp_path / "new.txt"), "x")
    finally:
        os.umask(old)
        writing._umask = None
    assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == 0o640


def test_nothing_else_in_scriptc_writes_files() -> None:
    """Every write of a file goes through `scriptc.writing`: no other module replaces,
    creates or opens a file for writing."""
    import re

    root = Path(writing.__file__).parent
    pattern = re.compile(r"os\.replace\(|os\.rename\(|tempfile\.|NamedTemporaryFile|"
                         r"\.write_text\(|\.write_bytes\(|savefig\(\s*path|"
                         r"open\([^)]*['\"][wax]b?['\"]")
    offenders = []
    for module in sorted(root.rglob("*.py")):
        if module.name == "writing.py":
            continue
        for number, line in enumerate(module.read_text(encoding="utf-8").splitlines(), 1):
            if pattern.search(line):
                offenders.append(f"{module.relative_to(root)}:{number}: {line.strip()}")
    assert offenders == []


def test_init_writes_through_the_writer(tmp_path: Path) -> None:
    os.symlink(tmp_path / "nowhere.toml", tmp_path / "scriptc.toml")  # a link is a file there
    result = run("init", str(tmp_path))
    assert result.exit_code == 0
    assert "skipped scriptc.toml (it exists)" in result.stdout
    assert not (tmp_path / "nowhere.toml").exists()
    assert json.loads((tmp_path / "scenarios" / "hello.json").read_text(encoding="utf-8"))
    assert leftovers(tmp_path) == []
