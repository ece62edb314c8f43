"""The verbs as library calls (`scriptc.ops`), the repository's setup (`scriptc.project.setup`)
and the kind of a source: what the CLI used to decide, called directly. Nothing here goes
through click, and the library prints nothing."""

from __future__ import annotations

from pathlib import Path

import pytest

from scriptc.analysis.analyze import Analysis
from scriptc.analysis.read import ReadError
from scriptc.ops import format as format_ops
from scriptc.ops import lint, programs
from scriptc.ops.build import emit, read_configured
from scriptc.project.config import Settings, build_settings
from scriptc.project.setup import Setup, function_registry, setup_for
from scriptc.runtime.loading import LoadError
from scriptc.source import SourceKind

CLEAN = "[clean]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n"
TIDY = "[clean]\n[goal:g]\n  [action]\n    [b##blk_inst: MV() LD() AO()]\n    [b##blk_terminus]\n"
WARNS = ("[warns]\n[goal:g]\n[action]\n[b##blk_jump: CND(! {TRUE}) TRJMP(end) FLSJMP()]\n"
         "[b##blk_inst: MV() LD() AO()]\n[b#end#blk_terminus]\n")
# R007 (a lowercase scope): a safe fix.
FIXABLE = ("[fixable]\n[goal:g]\n[action]\n"
           "[b##blk_jump: CND({CLASS #Human u ?kid (B: near(1))} ! {TRUE}) TRJMP() FLSJMP()]\n"
           "[b##blk_terminus]\n")
BROKEN = "[broken]\n[goal:g\n"
BROKEN_CONFIG = "[robot]\nmax-linear-speed = 0\n"  # an error: a limit of zero
FUNCTIONS = ('[[functions]]\nname = "mood"\nkind = "F"\narity = 1\n'
             'implementation = "activity_functions:mood"\n')


def write(root: Path, files: dict[str, str | bytes]) -> None:
    for name, content in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")


@pytest.fixture
def here(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ---------------------------------------------------------------------------------------------
# the kind of a source


@pytest.mark.parametrize("name, kind", [
    ("a.script", SourceKind.SCRIPT), ("a.json", SourceKind.JSON), ("A.JSON", SourceKind.JSON),
    ("a.scb", SourceKind.BYTECODE), ("a.txt", SourceKind.SCRIPT), ("json", SourceKind.SCRIPT),
])
def test_the_kind_of_a_file_is_its_suffixs(name: str, kind: SourceKind) -> None:
    assert SourceKind.of_path(name) is kind


def test_a_kind_is_the_word_the_cache_and_messages_use() -> None:
    assert [str(k) for k in SourceKind] == ["script", "json", "scb"]
    assert SourceKind("json") is SourceKind.JSON


# ---------------------------------------------------------------------------------------------
# project/setup: settings -> registry -> profile, once


def test_the_registry_is_built_one_way_once_per_set_of_functions() -> None:
    first = build_settings(_functions_table(), path=None, root=".")
    second = build_settings(_functions_table(), path=None, root=".")
    assert first is not second
    setup = Setup(first)
    assert setup.functions.get("mood").signature == "F: mood(arg1)"
    # The parent's registry and a worker's (built from the signatures alone) are one object.
    assert Setup(second).functions is setup.functions
    assert function_registry(setup.signatures) is setup.functions
    from scriptc.ir.builtins import STANDARD

    assert Setup(Settings()).functions is STANDARD and function_registry(()) is STANDARD


def _functions_table() -> dict:
    import tomllib

    return tomllib.loads(FUNCTIONS)


def test_a_setup_says_whether_its_configuration_failed(here: Path) -> None:
    write(here, {"ok/scriptc.toml": "[robot]\nmax-linear-speed = 0.3\n",
                 "bad/scriptc.toml": BROKEN_CONFIG})
    ok = setup_for(str(here / "ok" / "a.script"), cache=False)
    assert not ok.failed and ok.problems == [] and ok.profile.max_linear_speed == 0.3
    bad = setup_for(str(here / "bad" / "a.script"), cache=False)
    assert bad.failed
    (problem,) = bad.problems
    assert problem.source.path.endswith("scriptc.toml") and problem.diagnostics
    # stdin (and its default name) is the working folder's file.
    assert setup_for("-", cache=False).settings.path is None
    assert setup_for("<stdin>", cache=False).settings.path is None


# ---------------------------------------------------------------------------------------------
# ops/lint


def test_lint_paths_is_a_library_call(here: Path, capsys) -> None:
    write(here, {"scriptc.toml": BROKEN_CONFIG, "a.script": WARNS, "b.script": FIXABLE,
                 "c.script": b"[c]\xff\n"})
    run = lint.lint_paths([str(here)], options=lint.LintOptions(cache=False, jobs=1))
    assert capsys.readouterr() == ("", "")
    assert run.files == 3 and run.configs == 1 and run.problems == []
    assert run.results[0].source.path.endswith("scriptc.toml")
    assert [Path(r.path).name for r in run.reports] == ["a.script", "b.script", "c.script"]
    assert all(isinstance(r, Analysis) and r.script is None for r in run.reports)
    codes = [[d.code for d in r.diagnostics] for r in run.reports]
    assert codes[0] == ["F001"] and "R007" in codes[1] and codes[2] == ["P007"]
    assert run.exit_code == 1  # the configuration's error and c.script's P007
    assert run.fixable == 1 and run.reports[1].fixable == 1


def test_check_finds_thesis_json_only(here: Path) -> None:
    from scriptc.ops.build import emit

    analysis = read_configured(str(_script(here, "a.script", CLEAN)), SourceKind.SCRIPT,
                               setup_for("a.script", cache=False))
    write(here, {"json/act.json": emit(analysis.script, "json"),
                 "json/world.json": '{"updates": []}'})
    run = lint.lint_paths([str(here / "json")], SourceKind.JSON,
                          options=lint.LintOptions(cache=False))
    assert [Path(r.path).name for r in run.reports] == ["act.json"]
    assert run.exit_code == 0


def _script(root: Path, name: str, text: str) -> Path:
    write(root, {name: text})
    return root / name


def test_each_linted_file_is_decoded_once(here: Path, monkeypatch) -> None:
    """Decoding is the analysis's first step and the report's too: one decode serves both,
    whether the result is analysed now or comes from the cache."""
    import scriptc.analysis.analyze
    import scriptc.analysis.read

    decoded: list[str] = []
    real = scriptc.analysis.read.decode_source

    def counted(name, data):
        decoded.append(name)
        return real(name, data)

    for module in (lint, scriptc.analysis.analyze, scriptc.analysis.read):
        monkeypatch.setattr(module, "decode_source", counted)
    write(here, {"a.script": WARNS, "b.script": FIXABLE, "c.script": CLEAN})
    lint.lint_paths(["."], options=lint.LintOptions(cache=True, jobs=1))
    assert sorted(decoded) == ["a.script", "b.script", "c.script"]
    decoded.clear()
    cached = lint.lint_paths(["."], options=lint.LintOptions(cache=True, jobs=1))
    assert cached.cached == 3 and sorted(decoded) == ["a.script", "b.script", "c.script"]


def test_fix_and_diff_are_library_calls(here: Path) -> None:
    path = _script(here, "b.script", FIXABLE)
    diff = lint.lint_paths([str(path)], options=lint.LintOptions(cache=False, diff=True))
    (report,) = diff.reports
    assert path.read_text(encoding="utf-8") == FIXABLE  # --diff writes nothing
    assert report.fixed == 1 and "CLASS #Human U ?kid" in report.fixed_text
    assert diff.diff_exit_code == 1
    fixed = lint.lint_paths([str(path)], options=lint.LintOptions(cache=False, fix=True))
    assert fixed.fixed == 1 and fixed.fixed_files == 1
    assert path.read_text(encoding="utf-8") == report.fixed_text
    assert "R007" not in [d.code for d in fixed.reports[0].diagnostics]


# ---------------------------------------------------------------------------------------------
# ops/programs


def test_load_programs_reads_each_configuration_once(here: Path, monkeypatch) -> None:
    write(here, {"a.script": CLEAN, "b.script": WARNS})
    asked: list[str] = []

    def configured(path: str) -> Setup:
        asked.append(Path(path).name)
        return setup_for(path, cache=False)

    def again(*_args, **_kwargs):
        raise AssertionError("the first file's setup was read a second time")

    monkeypatch.setattr(programs, "setup_for", again)
    loaded = programs.load_programs(["a.script", "b.script"], configured=configured)
    assert asked == ["a.script", "b.script"]
    assert loaded.ok and len(loaded.programs) == 2
    assert [a.codes for a in loaded.analyses] == [[], ["F001"]]
    assert loaded.setup.settings.path is None  # the first file's: no configuration here


def test_load_programs_refuses_what_cannot_run(here: Path) -> None:
    write(here, {"broken.script": WARNS.replace("[action]\n", ""), "bad.scb": b"not bytecode",
                 "sub/scriptc.toml": BROKEN_CONFIG, "sub/a.script": CLEAN})
    loaded = programs.load_programs(["broken.script"])
    assert not loaded.ok and loaded.programs == [None] and loaded.analyses[0].errors
    with pytest.raises(ValueError, match="gave no program"):
        loaded.runnable()
    with pytest.raises(programs.Refused, match=r"bad\.scb"):
        programs.load_programs(["bad.scb"])
    with pytest.raises(ReadError, match="does not exist"):
        programs.load_programs(["missing.script"])
    with pytest.raises(programs.ConfigurationFailed) as failed:
        programs.load_programs(["sub/a.script"])
    assert failed.value.setup.failed


@pytest.mark.parametrize("executor", programs.EXECUTORS)
def test_a_compiled_program_and_its_source_run_alike(here: Path, executor: str) -> None:
    from scriptc.runtime.session import Session

    source = _script(here, "a.script", CLEAN)
    analysis = read_configured(str(source), SourceKind.SCRIPT, setup_for(str(source)))
    (here / "a.scb").write_bytes(emit(analysis.script, "bytecode", analysis.source))
    loaded = programs.load_programs(["a.script", "a.scb"], executor)
    assert loaded.ok and loaded.analyses and len(loaded.programs) == 2
    assert loaded.setup.settings.path is None
    assert loaded.runnable() == loaded.programs
    result = Session(loaded.runnable(), robot="kinematic").run(10_000)
    assert result.outcome == "completed"


def test_the_loader_of_a_session_refuses_with_load_errors(here: Path) -> None:
    write(here, {"good.script": CLEAN, "errors.script": WARNS.replace("[action]\n", ""),
                 "bad.scb": b"not bytecode", "sub/scriptc.toml": BROKEN_CONFIG,
                 "sub/a.script": CLEAN})
    loader = programs.ProgramLoader()
    assert loader(str(here / "good.script")) is not None
    for name, reason in [("missing.script", "does not exist"), ("errors.script", "has errors"),
                         ("bad.scb", "bad.scb"), ("sub/a.script", "configuration of")]:
        with pytest.raises(LoadError, match=reason):
            loader(str(here / name))


def test_the_governor_is_on_by_default_on_the_physical_robot_only() -> None:
    assert programs.governed_by_default("mujoco") is True
    assert programs.governed_by_default("kinematic") is False


# ---------------------------------------------------------------------------------------------
# ops/format


def test_a_format_run_yields_each_files_outcome(here: Path, capsys) -> None:
    write(here, {"tidy.script": TIDY, "messy.script": CLEAN, "broken.script": BROKEN})
    dry = format_ops.FormatRun(["."], dry=True)
    outcomes = {Path(o.path).name: o for o in dry}
    assert {n: o.status for n, o in outcomes.items()} == {
        "broken.script": "refused", "messy.script": "changed", "tidy.script": "unchanged"}
    assert outcomes["messy.script"].new == TIDY and outcomes["messy.script"].old == CLEAN
    assert [d.code for d in outcomes["broken.script"].analysis.diagnostics] == ["P002"]
    assert (here / "messy.script").read_text(encoding="utf-8") == CLEAN
    assert dry.exit_code == 1
    written = format_ops.FormatRun(["."], skip_invalid=True)
    assert [o.status for o in written] == ["refused", "reformatted", "unchanged"]
    assert (here / "messy.script").read_text(encoding="utf-8") == TIDY
    assert (here / "broken.script").read_text(encoding="utf-8") == BROKEN
    assert written.exit_code == 0  # the refused file is skipped
    assert capsys.readouterr() == ("", "")


def test_formatting_stdin_gives_what_goes_to_stdout() -> None:
    (done,) = format_ops.FormatRun(["-"], stdin=CLEAN.encode)
    assert done.status == "reformatted" and done.stdout == TIDY.encode()
    (kept,) = format_ops.FormatRun(["-"], stdin=BROKEN.encode)
    assert kept.status == "refused" and kept.stdout == BROKEN.encode()  # never lost
    (dry,) = format_ops.FormatRun(["-"], stdin=CLEAN.encode, dry=True)
    assert dry.status == "changed" and dry.stdout is None


def test_a_missing_path_and_an_unwritable_file_make_status_2(here: Path, monkeypatch) -> None:
    write(here, {"messy.script": CLEAN})
    missing = format_ops.FormatRun(["nope.script"])
    assert list(missing) == [] and missing.problems and missing.exit_code == 2
    from scriptc.writing import WriteError

    def refuse(path, data):
        raise WriteError(f"cannot write `{path}`")

    monkeypatch.setattr(format_ops, "write_file", refuse)
    run = format_ops.FormatRun(["messy.script"])
    (outcome,) = run
    assert outcome.status == "unwritten" and "cannot write" in outcome.error
    assert run.exit_code == 2
