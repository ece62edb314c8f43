"""The options of `scriptc lint` that ruff users expect: `--select`, `--extend-select` and
`--ignore` over the configuration, `--exit-zero`, `--statistics`, `--output-file`, `--diff`,
`--unsafe-fixes`; and where the cache lives (the project's root, from wherever scriptc runs)
and `scriptc clean`. Through click's CliRunner (in this process)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import settings as hsettings
from hypothesis import strategies as st

# The scripts and helpers of the repository-wide lint tests: CLEAN, WARNS (F001, a warning),
# FIXABLE (R007 with a safe fix, R003 with an unsafe one).
from test_lint_repo import CLEAN, FIXABLE, WARNS, run, write

from scriptc.diagnostics.codes import lint_codes
from scriptc.project.config import RuleSelection, Settings

SAFELY_FIXED = FIXABLE.replace("#Human u", "#Human U")
ALL_FIXED = SAFELY_FIXED.replace("nea(1)", "near(1)")
# M004 (an alfa message omega does not undo: a warning, with an unsafe fix).
NO_UNDO = ('[undo]\n[alfa:16,my_rule,"\\\\in","\\\\out",A,M]\n[alfa:0,kick,"","",R,U]\n'
           '[omega:0,kick,"","",C,L]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n'
           '[b##blk_terminus]\n')


def codes(result) -> list[str]:
    return sorted(r["code"] for r in json.loads(result.stdout))


@pytest.fixture
def project(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    write(tmp_path, {"scriptc.toml": '[lint]\nignore = ["F001"]\n', "w.script": WARNS,
                     "u.script": NO_UNDO, "c/c.script": FIXABLE})
    return tmp_path


# ---------------------------------------------------------------------------------------------
# --select, --extend-select, --ignore: a layer over the configuration, as ruff's


def test_the_configuration_alone(project: Path) -> None:
    assert codes(run("lint", ".", "--format", "json")) == ["M004", "R003", "R007"]


def test_select_starts_again_from_nothing(project: Path) -> None:
    # The configuration ignores F001; --select F reports it (ruff: the command line's select
    # replaces the configuration's select and ignore). Errors are reported whatever it says.
    result = run("lint", ".", "--format", "json", "--select", "F")
    assert codes(result) == ["F001", "R003", "R007"]
    assert codes(run("lint", ".", "--format", "json", "--select", "M004")) == [
        "M004", "R003", "R007"]


def test_extend_select_and_ignore_go_over_the_configuration(project: Path) -> None:
    assert codes(run("lint", ".", "--format", "json", "--extend-select", "F001")) == [
        "F001", "M004", "R003", "R007"]
    assert codes(run("lint", ".", "--format", "json", "--ignore", "M")) == ["R003", "R007"]
    # Within the layer the more specific selector wins, ignore winning a tie.
    assert codes(run("lint", ".", "--format", "json", "--ignore", "F",
                     "--extend-select", "F001")) == ["F001", "M004", "R003", "R007"]
    assert codes(run("lint", ".", "--format", "json", "--ignore", "F001",
                     "--extend-select", "F001")) == ["M004", "R003", "R007"]


def test_selectors_are_comma_separated_and_repeatable(project: Path) -> None:
    one = run("lint", ".", "--format", "json", "--select", "F001, unreachable-block,,M004,").stdout
    two = run("lint", ".", "--format", "json", "--select", "F001", "--select", "M004").stdout
    assert one == two and sorted(r["code"] for r in json.loads(one)) == [
        "F001", "M004", "R003", "R007"]


def test_a_selector_naming_no_code_is_a_usage_error_with_the_closest(project: Path) -> None:
    result = run("lint", ".", "--select", "F0001")
    assert result.exit_code == 2
    assert "`F0001` names no diagnostic code; did you mean `F001`" in result.stderr
    assert run("lint", ".", "--ignore", "nothing-like-it").exit_code == 2


def test_errors_cannot_be_ignored_from_the_command_line(project: Path) -> None:
    result = run("lint", ".", "--ignore", "R007")
    assert result.exit_code == 2 and "errors cannot be ignored" in result.stderr


def _policy(settings: Settings) -> dict:
    return {code: reported for code, (reported, _severity) in settings.policy().items()}


SELECTORS = st.lists(st.sampled_from(["ALL", "F", "F00", "F001", "M", "M004", "A", "R",
                                      "unreachable-block", "no-terminus"]), max_size=4)


@hsettings(max_examples=60, deadline=None)
@given(SELECTORS, SELECTORS, SELECTORS, SELECTORS, SELECTORS)
def test_the_command_lines_layer_laws(config_select, config_ignore, select, extend,
                                      ignore) -> None:
    base = Settings(select=tuple(config_select), ignore=tuple(config_ignore))
    # --select forgets the configuration's select and ignore.
    layered = base.with_selection(RuleSelection(tuple(select), tuple(extend), tuple(ignore)))
    alone = Settings(select=()).with_selection(RuleSelection(tuple(select), tuple(extend),
                                                             tuple(ignore)))
    assert _policy(layered) == _policy(alone)
    # Without --select: what the layer names neither way is as the configuration says, and
    # errors are always reported.
    over = _policy(base.with_selection(RuleSelection(None, tuple(extend), tuple(ignore))))
    below = _policy(base)
    names = set(extend) | set(ignore)
    for entry in lint_codes():
        if entry.severity.value == "error":
            assert over[entry.code]
        elif not any(s == "ALL" or entry.code.startswith(s) or s == entry.name for s in names):
            assert over[entry.code] == below[entry.code]
    assert _policy(base.with_selection(RuleSelection())) == below


# ---------------------------------------------------------------------------------------------
# --exit-zero


def test_exit_zero_passes_errors_but_not_unreadable_files(project: Path) -> None:
    assert run("lint", ".").exit_code == 1
    result = run("lint", ".", "--exit-zero")
    assert result.exit_code == 0 and "error[R007]" in result.stdout
    assert run("lint", ".", "-e").exit_code == 0
    os.symlink(project / "gone.script", project / "dangling.script")
    assert run("lint", ".", "--exit-zero").exit_code == 2


# ---------------------------------------------------------------------------------------------
# --statistics


def test_statistics_count_each_code(project: Path) -> None:
    write(project, {f"c/d{i}.script": FIXABLE for i in range(9)})
    result = run("lint", ".", "--statistics")
    assert result.exit_code == 1
    assert result.stdout == ("10\tR003\t    unknown-function\n"
                             "10\tR007\t[*] invalid-scope\n"
                             " 1\tM004\t    omega-leak\n")
    # Without a fixable code, no column is kept for the mark.
    assert run("lint", "w.script", "--extend-select", "F001", "--statistics").stdout == \
        "1\tF001\tunreachable-block\n"
    # With --unsafe-fixes R003 is fixable too; as JSON, the same counts.
    unsafe = run("lint", ".", "--statistics", "--unsafe-fixes", "--format", "json")
    assert json.loads(unsafe.stdout) == [
        {"code": "R003", "name": "unknown-function", "severity": "error", "count": 10,
         "fixable": True},
        {"code": "R007", "name": "invalid-scope", "severity": "error", "count": 10,
         "fixable": True},
        {"code": "M004", "name": "omega-leak", "severity": "warning", "count": 1,
         "fixable": True},
    ]


def test_statistics_of_a_clean_file_and_in_formats_that_cannot_hold_them(project: Path) -> None:
    write(project, {"clean.script": CLEAN})
    assert (run("lint", "clean.script", "--statistics").stdout,
            run("lint", "clean.script", "--statistics", "--format", "json").stdout) == ("", "[]\n")
    for format_ in ("sarif", "github"):
        assert run("lint", ".", "--statistics", "--format", format_).exit_code == 2
    assert run("lint", ".", "--statistics", "--diff").exit_code == 2


# ---------------------------------------------------------------------------------------------
# --output-file


def test_output_file_holds_what_stdout_would(project: Path) -> None:
    plain = run("lint", ".", "--format", "grouped")
    result = run("--color", "always", "lint", ".", "--format", "grouped", "-o", "report.txt")
    assert result.exit_code == plain.exit_code == 1
    assert result.stdout == ""
    assert (project / "report.txt").read_text(encoding="utf-8") == plain.stdout
    assert result.stderr.startswith("checked 3 files")  # the summary stays on stderr
    run("--color", "always", "lint", ".", "--output-file", "report.txt")
    text = (project / "report.txt").read_text(encoding="utf-8")
    assert "error[R007]" in text and "\x1b[" not in text  # a file is never coloured
    run("lint", ".", "--format", "json", "-o", "report.json")
    assert {r["code"] for r in json.loads((project / "report.json").read_text())} >= {"R007"}


def test_output_file_never_replaces_a_script_being_linted(project: Path) -> None:
    for target in ("c/c.script", "w.script"):
        result = run("lint", ".", "-o", target)
        assert result.exit_code == 2 and "refusing to overwrite" in result.stderr
        assert run("lint", target, "-o", target).exit_code == 2
    assert (project / "c" / "c.script").read_text() == FIXABLE
    assert (project / "w.script").read_text() == WARNS


def test_output_file_with_stdin(project: Path) -> None:
    result = run("lint", "-", "-o", "w.script", "--format", "json", input=WARNS.encode())
    assert result.exit_code == 0  # stdin is no file: w.script is only the output here
    assert json.loads((project / "w.script").read_text()) == []


def test_output_file_in_a_missing_folder_fails_before_linting(project: Path, monkeypatch) -> None:
    import scriptc.ops.lint

    def never(*args, **kwargs):
        raise AssertionError("linted before the output was checked")

    monkeypatch.setattr(scriptc.ops.lint, "lint_paths", never)
    result = run("lint", ".", "-o", "no/such/folder/report.txt")
    assert result.exit_code == 2 and "no/such/folder" in result.stderr


# ---------------------------------------------------------------------------------------------
# --diff and --unsafe-fixes


def test_diff_shows_what_fix_would_change_and_writes_nothing(project: Path) -> None:
    path = project / "c" / "c.script"
    before = path.stat().st_mtime_ns
    result = run("lint", ".", "--diff")
    assert result.exit_code == 1
    assert result.stdout == (
        "--- c/c.script\n+++ c/c.script\n@@ -1,5 +1,5 @@\n [fixable]\n [goal:g]\n [action]\n"
        f"-{FIXABLE.splitlines()[3]}\n+{SAFELY_FIXED.splitlines()[3]}\n [b##blk_terminus]\n")
    assert result.stderr == "would fix 1 problem in 1 file (2 more fixes with `--unsafe-fixes`)\n"
    assert path.read_text() == FIXABLE and path.stat().st_mtime_ns == before
    # --diff wins over --fix: still nothing written.
    assert run("lint", ".", "--diff", "--fix").stdout == result.stdout
    assert path.read_text() == FIXABLE


def test_diff_with_unsafe_fixes_and_on_stdin(project: Path) -> None:
    unsafe = run("lint", "c/c.script", "--diff", "--unsafe-fixes")
    assert f"+{ALL_FIXED.splitlines()[3]}\n" in unsafe.stdout
    assert unsafe.stderr == "would fix 2 problems in 1 file\n"
    piped = run("lint", "-", "--diff", "--stdin-filename", "c/c.script", input=FIXABLE.encode())
    assert piped.exit_code == 1 and piped.stdout == run("lint", "c/c.script", "--diff").stdout


def test_diff_with_nothing_to_fix_passes(project: Path) -> None:
    result = run("lint", "w.script", "--diff")
    assert (result.exit_code, result.stdout, result.stderr) == (0, "", "nothing to fix\n")
    hidden = run("lint", "u.script", "--diff")  # M004's fix is unsafe
    assert (hidden.exit_code, hidden.stdout, hidden.stderr) == (
        0, "", "nothing to fix (1 more fix with `--unsafe-fixes`)\n")
    assert run("lint", "c/c.script", "--diff", "--exit-zero").exit_code == 0


def test_diff_still_says_what_is_wrong_in_the_configuration(project: Path) -> None:
    (project / "scriptc.toml").write_text('[lint]\nselct = ["F"]\n')
    result = run("lint", "w.script", "--diff")
    assert (result.exit_code, result.stdout) == (1, "")
    assert result.stderr.startswith("error[C001]: unknown key `selct` in `[lint]`")
    assert result.stderr.endswith("nothing to fix\n")


def test_fix_applies_unsafe_fixes_only_when_asked(project: Path) -> None:
    path = project / "c" / "c.script"
    safe = run("lint", "c/c.script", "--fix")
    assert path.read_text() == SAFELY_FIXED and safe.exit_code == 1  # R003 is left
    path.write_text(FIXABLE)
    both = run("lint", "c/c.script", "--fix", "--unsafe-fixes")
    assert path.read_text() == ALL_FIXED
    assert (both.exit_code, both.stdout, both.stderr) == (0, "", "fixed 2 problems in 1 file\n")
    path.write_text(FIXABLE)
    run("lint", "c/c.script", "--fix", "--unsafe-fixes", "--no-unsafe-fixes")
    assert path.read_text() == SAFELY_FIXED


def test_unsafe_fixes_are_marked_and_counted_when_asked(project: Path) -> None:
    plain = run("lint", "c/c.script", "w.script", "--format", "grouped")
    assert "R003 error" in plain.stdout and "R007 [*] error" in plain.stdout
    assert plain.stderr.endswith("1 fix available (`scriptc lint --fix` applies it), 1 more "
                                 "with `--unsafe-fixes`\n")
    unsafe = run("lint", "c/c.script", "w.script", "--format", "grouped", "--unsafe-fixes")
    assert "R003 [*] error" in unsafe.stdout
    assert unsafe.stderr.endswith("2 fixes available (`scriptc lint --fix --unsafe-fixes` "
                                  "applies them)\n")
    (project / "c" / "c.script").write_text(SAFELY_FIXED)
    only_unsafe = run("lint", "c/c.script", "w.script")
    assert only_unsafe.stderr.endswith("1 unsafe fix available (`scriptc lint --fix "
                                       "--unsafe-fixes` applies it)\n")


# ---------------------------------------------------------------------------------------------
# the cache: one folder at the project's root


def _cache_entries(folder: Path) -> int:
    return sum(1 for _ in (folder / ".scriptc_cache").rglob("*.json"))


def test_the_cache_is_at_the_root_from_a_subfolder_or_from_outside(project: Path,
                                                                   tmp_path_factory) -> None:
    outside = tmp_path_factory.mktemp("elsewhere")
    os.chdir(outside)
    first = run("lint", str(project))
    assert "from the cache" not in first.stderr
    os.chdir(project / "c")
    second = run("lint", str(project))
    assert "(3 unchanged, from the cache)" in second.stderr
    os.chdir(project)
    assert "(3 unchanged, from the cache)" in run("lint", ".").stderr
    # stdin named into the project: the project's cache too.
    os.chdir(outside)
    piped = run("lint", "-", "--stdin-filename", str(project / "w.script"), "--format", "json",
                input=WARNS.encode())
    assert piped.exit_code == 0 and _cache_entries(project) == 4
    assert not (outside / ".scriptc_cache").exists()
    assert not (project / "c" / ".scriptc_cache").exists()
    assert (project / ".scriptc_cache" / ".gitignore").read_text().splitlines()[-1] == "*"
    # compile (through the configuration's checked cache) uses the same folder.
    before = _cache_entries(project)
    (project / "scriptc.toml").write_text('[lint]\nignore = ["F001", "F003"]\n')
    os.chdir(outside)
    assert run("compile", str(project / "w.script"), "-o", "-").exit_code == 0
    assert _cache_entries(project) == before + 1
    assert not (outside / ".scriptc_cache").exists()


def test_without_a_configuration_the_cache_is_here(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    write(tmp_path, {"sub/w.script": WARNS})
    run("lint", "sub")
    assert (tmp_path / ".scriptc_cache").is_dir()
    assert not (tmp_path / "sub" / ".scriptc_cache").exists()


def test_config_and_isolated_contradict_each_other(project: Path) -> None:
    result = run("lint", ".", "--config", "scriptc.toml", "--isolated")
    assert result.exit_code == 2 and "contradict" in result.stderr


def test_config_option_puts_the_cache_beside_that_file(project: Path) -> None:
    write(project, {"other/strict.toml": "", "other/x.script": WARNS})
    run("lint", "other/x.script", "--config", "other/strict.toml")
    assert (project / "other" / ".scriptc_cache").is_dir()
    assert not (project / ".scriptc_cache").exists()
    run("lint", "c", "--isolated")
    assert (project / ".scriptc_cache").is_dir()  # no configuration: the working folder


# ---------------------------------------------------------------------------------------------
# scriptc clean


def test_clean_removes_the_projects_cache_and_says_so(project: Path) -> None:
    write(project, {"sub/scriptc.toml": "", "sub/s.script": WARNS})
    run("lint", ".")
    run("lint", "sub")  # a sub-project: its own cache
    assert (project / "sub" / ".scriptc_cache").is_dir()
    result = run("clean")
    assert result.exit_code == 0
    lines = result.stderr.splitlines()
    assert [line.split(" (")[0] for line in lines] == [
        "removed `.scriptc_cache`", "removed `sub/.scriptc_cache`"]
    assert all(line.endswith((" bytes)", " KB)")) and " files, " in line for line in lines)
    assert not (project / ".scriptc_cache").exists()
    assert not (project / "sub" / ".scriptc_cache").exists()
    assert (project / "w.script").read_text() == WARNS  # nothing else touched
    again = run("clean", "c")
    assert (again.exit_code, again.stderr) == (
        0, "nothing to remove: no cache at `.scriptc_cache`\n")


def test_clean_from_a_subfolder_finds_the_root(project: Path) -> None:
    run("lint", ".")
    os.chdir(project / "c")
    result = run("clean")
    assert result.exit_code == 0 and not (project / ".scriptc_cache").exists()


def test_clean_says_what_it_cannot_remove(project: Path, monkeypatch) -> None:
    import shutil

    run("lint", ".")

    def refuse(path, *args, **kwargs):
        raise PermissionError(13, "Permission denied", path)

    monkeypatch.setattr(shutil, "rmtree", refuse)
    result = run("clean")
    assert (result.exit_code, result.stderr) == (
        2, "error: cannot remove `.scriptc_cache`: Permission denied\n")


def test_sizes_as_people_read_them() -> None:
    from scriptc.cli.clean import human_size

    assert [human_size(n) for n in (0, 1023, 1024, 62_669, 3 * 1024 ** 2, 1024 ** 3 * 3 // 2)] == [
        "0 bytes", "1023 bytes", "1.0 KB", "61.2 KB", "3.0 MB", "1.5 GB"]


def test_clean_never_removes_a_folder_scriptc_did_not_make(project: Path) -> None:
    precious = project / "precious"
    write(precious, {"notes.txt": "mine"})
    result = run("clean", "--cache-dir", str(precious))
    assert result.exit_code == 2 and "is not a cache of scriptc" in result.stderr
    assert (precious / "notes.txt").read_text() == "mine"
    run("lint", ".", "--cache-dir", "made")
    assert run("clean", "--cache-dir", "made").exit_code == 0 and not (project / "made").exists()
