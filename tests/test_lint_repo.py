"""`scriptc lint DIR` over a repository: which files (.gitignore, exclusions), the cache,
worker processes, `--fix`, the grouped format, the summary, and the configuration of each
file. Through click's CliRunner (in this process) unless a process is the point."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli
from scriptc.ops import lint

CLEAN = "[clean]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
WARNS = ("[warns]\n[goal:g]\n[action]\n[b##blk_jump: CND(! {TRUE}) TRJMP(end) FLSJMP()]\n"
         "[b##blk_inst: MV() LD() AO()]\n[b#end#blk_terminus]\n")
# R007 (lowercase scope) has a safe fix; R003 (`nea` for `near`) an unsafe one.
FIXABLE = ("[fixable]\n[goal:g]\n[action]\n"
           "[b##blk_jump: CND({CLASS #Human u ?kid (B: nea(1))} ! {TRUE}) TRJMP() FLSJMP()]\n"
           "[b##blk_terminus]\n")


def run(*args: str, input: bytes | None = None, env: dict | None = None):
    return CliRunner().invoke(cli, list(args), input=input, env=env, catch_exceptions=False)


def write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")


def linted(root: Path, *args: str) -> list[str]:
    """The files `scriptc lint` reads under `root`, relative to it."""
    records = json.loads(run("lint", str(root), "--format", "json", "--no-cache", *args).stdout)
    return sorted({Path(os.path.abspath(r["file"])).relative_to(root).as_posix()
                   for r in records})


@pytest.fixture
def repo(tmp_path: Path, monkeypatch) -> Path:
    """A git repository (a `.git` folder is all it takes) full of scripts, each with F001 so
    that every file read shows up in the JSON output."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / ".git" / "info").mkdir(parents=True)
    (tmp_path / ".git" / "info" / "exclude").write_text("private.script\n")
    write(tmp_path, {
        ".gitignore": "# build output\nbuild/\n*.gen.script\n/anchored.script\n"
                      "docs/*.script\n!docs/keep.script\n",
        "a.script": WARNS, "private.script": WARNS, "anchored.script": WARNS,
        "x.gen.script": WARNS, "build/b.script": WARNS, "build.script": WARNS,
        "docs/d.script": WARNS, "docs/keep.script": WARNS, "docs/deep/d.script": WARNS,
        "sub/.gitignore": "local.script\n!special.gen.script\n",
        "sub/anchored.script": WARNS, "sub/local.script": WARNS, "sub/special.gen.script": WARNS,
        "sub/other.gen.script": WARNS, "sub/build/c.script": WARNS,
        ".hidden/h.script": WARNS,
    })
    return tmp_path


KEPT = ["a.script", "build.script", "docs/deep/d.script", "docs/keep.script",
        "sub/anchored.script", "sub/special.gen.script"]


def test_gitignore_rules(repo: Path) -> None:
    # Directory patterns (build/ at any depth, not the file build.script), globs, anchored
    # patterns, a pattern with a slash (docs/*.script: not docs/deep/), negation, nested
    # .gitignore files overriding their parents, .git/info/exclude, hidden folders.
    assert linted(repo) == KEPT


def test_gitignore_files_above_the_folder_linted_apply(repo: Path) -> None:
    assert linted(repo / "sub") == ["anchored.script", "special.gen.script"]


def test_outside_a_repository_only_the_folders_own_gitignore_files_apply(repo: Path) -> None:
    (repo / ".git" / "info" / "exclude").unlink()
    (repo / ".git" / "info").rmdir()
    (repo / ".git").rmdir()
    assert linted(repo / "sub") == ["anchored.script", "build/c.script", "other.gen.script",
                                    "special.gen.script"]
    assert "private.script" in linted(repo)


def test_configuration_excludes_and_respect_gitignore(repo: Path) -> None:
    (repo / "scriptc.toml").write_text('exclude = ["docs/", "a.script"]\n')
    assert linted(repo) == ["build.script", "sub/anchored.script", "sub/special.gen.script"]
    (repo / "scriptc.toml").write_text("respect-gitignore = false\n")
    assert len(linted(repo)) == 14  # every script but the hidden folder's


def test_links_to_folders_are_not_followed(repo: Path) -> None:
    os.symlink(repo, repo / "sub" / "loop")
    os.symlink(repo / "a.script", repo / "sub" / "link.script")  # a link to a file is read
    assert linted(repo / "sub") == ["anchored.script", "link.script", "special.gen.script"]


def test_named_files_are_linted_unless_force_exclude(repo: Path) -> None:
    (repo / "scriptc.toml").write_text('exclude = ["a.script"]\n')
    assert "error" not in run("lint", "a.script").stdout
    assert "F001" in run("lint", "a.script", "--format", "grouped").stdout
    forced = run("lint", "a.script", "--force-exclude")
    assert (forced.exit_code, forced.stdout) == (0, "")


# ---------------------------------------------------------------------------------------------
# the cache


@pytest.fixture
def project(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SCRIPTC_CACHE_DIR", raising=False)
    write(tmp_path, {"scriptc.toml": '[lint]\nignore = ["F003"]\n', "a.script": CLEAN,
                     "b.script": WARNS, "c/c.script": FIXABLE})
    return tmp_path


def test_the_second_run_comes_from_the_cache(project: Path) -> None:
    first = run("lint", ".", "--format", "json")
    assert "checked 3 files: 2 errors, 1 warning" in first.stderr
    assert "from the cache" not in first.stderr
    second = run("lint", ".", "--format", "json")
    assert "checked 3 files (3 unchanged, from the cache): 2 errors, 1 warning" in second.stderr
    assert second.stdout == first.stdout and second.exit_code == first.exit_code == 1
    cache = project / ".scriptc_cache"
    assert (cache / "CACHEDIR.TAG").read_text().startswith(
        "Signature: 8a477f597d28d172789f06886806bc55")
    assert (cache / ".gitignore").read_text().splitlines()[-1] == "*"


def test_cached_results_keep_everything(project: Path) -> None:
    fresh = run("lint", ".", "--format", "json", "--no-cache").stdout
    run("lint", ".")
    assert run("lint", ".", "--format", "json").stdout == fresh  # fixes, labels, notes, help


def test_a_changed_file_or_configuration_is_analysed_again(project: Path) -> None:
    run("lint", ".")
    (project / "a.script").write_text(CLEAN.replace("clean", "changed"))
    assert "(2 unchanged, from the cache)" in run("lint", ".").stderr
    (project / "scriptc.toml").write_text('[lint]\nignore = ["F003", "M004"]\n')
    assert "from the cache" not in run("lint", ".").stderr


@pytest.mark.slow
def test_the_policy_is_applied_after_the_cache(project: Path, monkeypatch) -> None:
    # Two files with the same content are analysed once and share one cache entry; the
    # per-file policy still differs.
    (project / "scriptc.toml").write_text('[lint]\nper-file-ignores = { "legacy/**" = ["F001"] }\n')
    write(project, {"legacy/b.script": WARNS})
    analysed = []
    real = lint._analyze_task
    monkeypatch.setattr(lint, "_analyze_task",
                        lambda task: analysed.append(task[0]) or real(task))
    first = run("lint", "b.script", "legacy/b.script", "--format", "grouped")
    assert analysed == ["b.script"]
    assert "b.script:\n  5:1 F001" in first.stdout and "legacy/b.script:" not in first.stdout
    assert "1 warning" in first.stderr


def test_no_cache_writes_nothing_and_a_broken_cache_is_a_miss(project: Path) -> None:
    run("lint", ".", "--no-cache")
    assert not (project / ".scriptc_cache").exists()
    expected = run("lint", ".", "--format", "json").stdout
    for entry in (project / ".scriptc_cache").rglob("*.json"):
        entry.write_text("not json")
    assert run("lint", ".", "--format", "json").stdout == expected


def test_cache_dir_option_and_variable(project: Path, tmp_path_factory) -> None:
    elsewhere = tmp_path_factory.mktemp("cache")
    run("lint", ".", "--cache-dir", str(elsewhere / "c1"))
    assert (elsewhere / "c1" / "CACHEDIR.TAG").exists()
    run("lint", ".", env={"SCRIPTC_CACHE_DIR": str(elsewhere / "c2")})
    assert (elsewhere / "c2" / "CACHEDIR.TAG").exists()
    assert not (project / ".scriptc_cache").exists()


def test_the_cache_goes_to_the_project_root(project: Path) -> None:
    os.chdir(project / "c")
    run("lint", "c.script")
    assert (project / ".scriptc_cache").exists() and not (project / "c" / ".scriptc_cache").exists()


# ---------------------------------------------------------------------------------------------
# workers


def test_workers_give_the_same_results(project: Path, monkeypatch) -> None:
    for i in range(6):
        (project / f"w{i}.script").write_text(WARNS if i % 2 else FIXABLE)
    serial = run("lint", ".", "--format", "json", "--no-cache", "-j", "1").stdout
    monkeypatch.setattr(lint, "PARALLEL_MIN_BYTES", 0)
    parallel = run("lint", ".", "--format", "json", "--no-cache", "-j", "2").stdout
    assert parallel == serial


def test_without_worker_processes_one_process_does_it_all(project: Path, monkeypatch) -> None:
    import concurrent.futures

    def refuse(*args, **kwargs):
        raise OSError("no processes here")

    monkeypatch.setattr(lint, "PARALLEL_MIN_BYTES", 0)
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", refuse)
    result = run("lint", ".", "--no-cache", "-j", "2", "--format", "json")
    assert result.exit_code == 1 and {r["code"] for r in json.loads(result.stdout)} >= {"F001"}


# ---------------------------------------------------------------------------------------------
# --fix


def test_fix_applies_the_safe_fixes_only(project: Path) -> None:
    path = project / "c" / "c.script"
    path.write_bytes(b"\xef\xbb\xbf" + FIXABLE.replace("\n", "\r\n").encode())
    result = run("lint", "c/c.script", "--fix", "--format", "grouped")
    assert result.exit_code == 1  # R003 is left: its fix is not safe
    assert "R007" not in result.stdout and "R003" in result.stdout
    assert result.stderr == "fixed 1 problem in 1 file\n"
    data = path.read_bytes()
    assert data.startswith(b"\xef\xbb\xbf") and b"#Human U ?kid" in data and b"\r\n" in data
    assert b"nea(1)" in data
    # Nothing left to fix: the file is not touched.
    before = path.stat().st_mtime_ns
    again = run("lint", "c/c.script", "--fix")
    assert again.stderr == "" and path.stat().st_mtime_ns == before


def test_fix_reports_the_text_it_wrote(project: Path) -> None:
    (project / "u.script").write_text(
        "[u]\n[goal:g]\n[action]\n[b##blk_terminus]   % scriptc: ignore[F001] %\n")
    result = run("lint", ".", "--fix")
    assert "fixed 2 problems in 2 files" in result.stderr
    assert (project / "u.script").read_text() == "[u]\n[goal:g]\n[action]\n[b##blk_terminus]\n"
    assert "1 fix available" not in result.stderr


def test_fix_applies_a_fix_that_inserts_twice_at_one_place(project: Path) -> None:
    # S008's fix inserts ` LD()` then ` AO()` after the move: one change, in that order.
    path = project / "t.script"
    path.write_text('[t]\n[goal:g]\n[action]\n[b##blk_inst: MV("0, 0, 0.5, 0, 1000")]\n'
                    "[b##blk_terminus]\n")
    result = run("lint", "t.script", "--fix")
    assert result.stderr == "fixed 1 problem in 1 file\n"
    assert 'MV("0, 0, 0.5, 0, 1000") LD() AO()]' in path.read_text()


def test_fix_refuses_stdin(project: Path) -> None:
    result = run("lint", "-", "--fix", input=FIXABLE.encode())
    assert result.exit_code == 2 and "stdin" in result.stderr


# ---------------------------------------------------------------------------------------------
# output


def test_grouped_format(project: Path) -> None:
    result = run("lint", "b.script", "c/c.script", "--format", "grouped", "--no-cache")
    assert result.stdout == (
        "b.script:\n"
        "  5:1 F001 warning: unreachable block\n"
        "\n"
        "c/c.script:\n"
        "  4:33 R007 [*] error: unknown scope `u`\n"
        "  4:44 R003 error: unknown B function `nea`\n"
        "\n"
        "error: 2 errors, 1 warning emitted\n"
    )
    assert result.stderr == ("checked 2 files: 2 errors, 1 warning; 1 fix available "
                             "(`scriptc lint --fix` applies it), 1 more with `--unsafe-fixes`\n")


def test_a_single_file_gets_no_summary_and_quiet_none_at_all(project: Path) -> None:
    assert run("lint", "b.script").stderr == ""
    assert run("lint", ".", "-q").stderr == ""
    assert run("lint", "a.script", "b.script").stderr.startswith("checked 2 files")


def test_clean_repository_summary(project: Path) -> None:
    (project / "b.script").unlink()
    (project / "c" / "c.script").unlink()
    result = run("lint", ".")
    assert (result.exit_code, result.stdout, result.stderr) == (
        0, "", "checked 1 file: no problems\n")


def test_configuration_problems_come_first_and_fail_the_run(project: Path) -> None:
    (project / "scriptc.toml").write_text('[lint]\nignore = ["F003"]\nselct = []\n')
    result = run("lint", "a.script", "--format", "grouped")
    assert result.exit_code == 1
    assert result.stdout.startswith("scriptc.toml:\n  3:1 C001 error: unknown key `selct` in "
                                    "`[lint]`\n")


def test_progress_bar_only_on_a_terminal_and_for_many_files(capsys) -> None:
    from scriptc.cli.common import Progress

    quiet = Progress()
    assert not quiet.enabled  # pytest's stderr is not a terminal
    bar = Progress()
    bar.enabled = True
    bar(10, 20)
    assert bar._bar is None  # few files: no bar
    bar(10, 100)
    bar(100, 100)
    bar.close()
    assert bar._bar is None


# ---------------------------------------------------------------------------------------------
# each file's configuration


def test_stdin_takes_the_configuration_and_the_name_given(project: Path) -> None:
    (project / "scriptc.toml").write_text('[lint]\nper-file-ignores = { "legacy/**" = ["F001"] }\n')
    named = run("lint", "-", "--stdin-filename", "legacy/x.script", input=WARNS.encode())
    assert named.exit_code == 0 and named.stdout == ""
    plain = run("lint", "-", input=WARNS.encode())
    assert "F001" in plain.stdout


def test_nested_configurations_do_not_merge(project: Path) -> None:
    write(project, {"sub/scriptc.toml": "", "sub/w.script": WARNS, "top.script": WARNS})
    (project / "scriptc.toml").write_text('[lint]\nignore = ["F001"]\n')
    out = run("lint", ".", "--format", "grouped").stdout
    assert "sub/w.script:\n  5:1 F001" in out and "top.script" not in out


def test_compile_uses_the_configuration(project: Path) -> None:
    (project / "scriptc.toml").write_text(
        '[[functions]]\nname = "waving"\nkind = "B"\narity = 0\nimplementation = "m:w"\n'
        '[lint]\nseverity = { F001 = "error" }\n')
    (project / "f.script").write_text(CLEAN.replace("[b##blk_inst", "[b##blk_jump: CND("
                                                    "{CLASS #Human U ?k (B: waving())} ! {TRUE}) "
                                                    "TRJMP() FLSJMP()]\n[b##blk_inst"))
    assert run("compile", "f.script", "-o", "-").exit_code == 0
    refused = run("compile", "b.script", "-o", "-")  # its F001 is an error here
    assert refused.exit_code == 1 and "error[F001]" in refused.stderr
