"""`scriptc fmt`: in-place rewriting, --check, --diff, stdin, refusals, --skip-invalid, folders,
line endings and the byte order mark, through click's CliRunner (and one real process)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli

MESSY = "[a]\n[goal:g]\n[action]\n[b##blk_inst:MV() LD() AO()]\n"
TIDY = "[a]\n[goal:g]\n  [action]\n    [b##blk_inst: MV() LD() AO()]\n"
BROKEN = "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV( LD() AO()]\n"


def run(*args: str, input: bytes | str | None = None):
    return CliRunner().invoke(cli, list(args), input=input, catch_exceptions=False)


@pytest.fixture
def tree(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "messy.script").write_text(MESSY, encoding="utf-8")
    (tmp_path / "tidy.script").write_text(TIDY, encoding="utf-8")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "deep.script").write_text(MESSY, encoding="utf-8")
    (tmp_path / "sub" / "notes.txt").write_text(MESSY, encoding="utf-8")
    return tmp_path


def test_help_lists_fmt() -> None:
    assert "  fmt " in run("--help").stdout


def test_rewrites_in_place_only_what_changes(tree: Path) -> None:
    before = (tree / "tidy.script").stat().st_mtime_ns
    result = run("fmt", "messy.script", "tidy.script")
    assert result.exit_code == 0, result.output
    assert (tree / "messy.script").read_text(encoding="utf-8") == TIDY
    assert (tree / "tidy.script").stat().st_mtime_ns == before
    assert "reformatted messy.script" in result.stderr
    assert "tidy.script" not in result.stderr
    assert run("fmt", "messy.script").stderr == ""  # a second run changes nothing


def test_keeps_permissions(tree: Path) -> None:
    os.chmod(tree / "messy.script", 0o640)
    run("fmt", "messy.script")
    assert (tree / "messy.script").stat().st_mode & 0o777 == 0o640


def test_folders_recurse_over_scripts(tree: Path) -> None:
    result = run("fmt", ".")
    assert result.exit_code == 0
    assert (tree / "sub" / "deep.script").read_text(encoding="utf-8") == TIDY
    assert (tree / "sub" / "notes.txt").read_text(encoding="utf-8") == MESSY


def test_check_lists_and_writes_nothing(tree: Path) -> None:
    result = run("fmt", "--check", ".")
    assert result.exit_code == 1
    # Named as every output names files: relative to the working folder, without `./`.
    assert result.stdout.splitlines() == ["would reformat messy.script",
                                          f"would reformat {os.path.join('sub', 'deep.script')}"]
    assert (tree / "messy.script").read_text(encoding="utf-8") == MESSY
    assert run("fmt", "--check", "tidy.script").exit_code == 0


def test_diff_shows_and_writes_nothing(tree: Path) -> None:
    result = run("fmt", "--diff", "messy.script")
    assert result.exit_code == 1
    assert result.stdout.startswith("--- messy.script\n+++ messy.script\n@@")
    assert "-[action]\n-[b##blk_inst:MV() LD() AO()]\n+  [action]\n" in result.stdout
    assert (tree / "messy.script").read_text(encoding="utf-8") == MESSY
    assert run("fmt", "--diff", "tidy.script").stdout == ""


def test_diff_marks_a_missing_final_newline(tree: Path) -> None:
    (tree / "x.script").write_text("[a]", encoding="utf-8")
    assert run("fmt", "--diff", "x.script").stdout.endswith(
        "-[a]\n\\ No newline at end of file\n+[a]\n"
    )


def test_syntax_errors_refuse_and_leave_the_file_alone(tree: Path) -> None:
    (tree / "broken.script").write_bytes(BROKEN.encode())
    result = run("fmt", "broken.script", "messy.script")
    assert result.exit_code == 1
    assert "error[P002]" in result.stderr
    assert "`broken.script` was not formatted" in result.stderr
    assert (tree / "broken.script").read_bytes() == BROKEN.encode()
    assert (tree / "messy.script").read_text(encoding="utf-8") == TIDY  # the others go on


def test_skip_invalid_names_the_file_and_passes(tree: Path) -> None:
    (tree / "broken.script").write_bytes(BROKEN.encode())
    result = run("fmt", "--skip-invalid", "broken.script", "messy.script")
    assert result.exit_code == 0
    assert "warning: skipped `broken.script`: it has syntax errors" in result.stderr
    assert "error[" not in result.stderr
    assert (tree / "broken.script").read_bytes() == BROKEN.encode()


def test_files_that_are_not_text_are_refused(tree: Path) -> None:
    data = b"[a]\n\xff\xfe[goal:g]\n"
    (tree / "bin.script").write_bytes(data)
    result = run("fmt", "bin.script")
    assert result.exit_code == 1 and "P007" in result.stderr
    assert (tree / "bin.script").read_bytes() == data


def test_crlf_and_bom_are_kept(tree: Path) -> None:
    data = b"\xef\xbb\xbf" + MESSY.replace("\n", "\r\n").encode()
    (tree / "win.script").write_bytes(data)
    assert run("fmt", "win.script").exit_code == 0
    assert ((tree / "win.script").read_bytes()
            == b"\xef\xbb\xbf" + TIDY.replace("\n", "\r\n").encode())


def test_stdin_to_stdout() -> None:
    result = run("fmt", "-", input=MESSY)
    assert result.exit_code == 0
    assert result.stdout == TIDY


def test_stdin_refused_is_echoed_unchanged() -> None:
    result = run("fmt", "-", "--stdin-filename", "edited.script", input=BROKEN)
    assert result.exit_code == 1
    assert result.stdout == BROKEN
    assert "edited.script:4:" in result.stderr


def test_stdin_check_prints_no_text() -> None:
    result = run("fmt", "--check", "-", input=MESSY)
    assert result.exit_code == 1
    assert result.stdout == "would reformat <stdin>\n"


def test_missing_path_is_a_usage_problem(tree: Path) -> None:
    result = run("fmt", "nowhere.script")
    assert result.exit_code == 2
    assert "`nowhere.script` does not exist" in result.stderr


def test_no_scripts_found_warns(tree: Path) -> None:
    (tree / "empty").mkdir()
    result = run("fmt", "empty")
    assert result.exit_code == 0
    assert "no script files found" in result.stderr


@pytest.mark.slow
def test_real_process_pipes_bytes(tmp_path: Path) -> None:
    data = MESSY.replace("\n", "\r\n").encode()
    done = subprocess.run([sys.executable, "-m", "scriptc", "fmt", "-"], input=data,
                          capture_output=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout == TIDY.replace("\n", "\r\n").encode()


def test_a_formatter_bug_writes_nothing(tree: Path, monkeypatch) -> None:
    import scriptc.emit.printer as layout

    monkeypatch.setattr(layout, "_space", lambda *args: "")
    text = "[a]\n[goal:g]\n[action]\n[b##blk_jump: CND({VAR @v U F: now()} !) TRJMP() FLSJMP()]\n"
    (tree / "x.script").write_text(text, encoding="utf-8")
    result = CliRunner().invoke(cli, ["fmt", "x.script"])
    assert result.exit_code == 2
    assert "internal error: FormatterError" in result.stderr
    assert (tree / "x.script").read_text(encoding="utf-8") == text


def test_folders_are_walked_as_lint_walks_them(tmp_path: Path) -> None:
    """`scriptc fmt DIR` skips what .gitignore ignores, like `scriptc lint DIR`."""
    from scriptc.cli.main import cli

    (tmp_path / ".git").mkdir()
    (tmp_path / ".gitignore").write_text("generated/\n", encoding="utf-8")
    (tmp_path / "generated").mkdir()
    (tmp_path / "generated" / "messy.script").write_text(
        "[a]   [goal:g][action][b##blk_terminus]\n", encoding="utf-8")
    (tmp_path / "tidy.script").write_text("[a]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n",
                                          encoding="utf-8")
    result = CliRunner().invoke(cli, ["fmt", "--check", str(tmp_path)])
    assert result.exit_code == 0, result.output
    # A file named on the command line is read whatever ignores it.
    named = CliRunner().invoke(cli, ["fmt", "--check",
                                     str(tmp_path / "generated" / "messy.script")])
    assert named.exit_code == 1
