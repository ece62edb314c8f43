"""scriptc's pytest plugin (src/scriptc/pytest_plugin.py, docs/testing.md "With pytest"), driven
by pytest's own `pytester`: test files collected as items when a repository opts in, with the
verdicts and messages of `scriptc test` (its CLI's output is the reference), a test file with a
problem as a collection error, `-k`, and the items under pytest-xdist. The plugin is the one
installed with scriptc (its `pytest11` entry point), not registered by these tests."""

from __future__ import annotations

import gc
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.cli.main import cli
from scriptc.ops.test import run_one
from scriptc.testing.read import read_test

pytest_plugins = ("pytester",)

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

PASSES = """\
description = "A child who comes close is greeted with a song"
scripts = ["../greeting.script"]
world = "../greeting.world.json"
until = 60000

[[expect]]
name = "says hello"
event = "block"
where = { label = "hello" }
within = [2000, 4000]
count = "1"

[[expect]]
outcome = "completed"
"""

FAILS = """\
description = "The greeting kept waiting"
scripts = ["../greeting.script"]
world = "../greeting.world.json"
until = 60000

[[expect]]
name = "says hello at once"
event = "block"
where = { label = "hello" }
within = [0, 1000]

[[expect]]
name = "still there at 30 s"
at = 30000
block = "wait"

[[expect]]
outcome = "completed"
"""

# An unknown key (T002, with the key it is close to) and a script that does not exist (T004).
BROKEN = """\
scripts = ["../nowhere.script"]

[[expect]]
evnet = "block"
"""

# A script with an error (a jump to a label that does not exist): a test of it cannot run.
BROKEN_SCRIPT = """\
[greeting]
[goal:g]
  [action]
    [b##blk_jump: CND({TRUE}) TRJMP(nowhere) FLSJMP()]
"""
ERRS = """\
scripts = ["../broken.script"]
"""

# pytest-asyncio (under pytest-lsp, of the test extra) warns in every session without it.
QUIET = "[pytest]\nasyncio_default_fixture_loop_scope = function\n"
INI = QUIET + "scriptc_tests = true\n"


@pytest.fixture(scope="module", autouse=True)
def _quick_inline_runs() -> Iterator[None]:
    """What running a test imports, imported in this process first (pytester's inline runs
    unload the modules a run imported, and each run would import them again), and this
    process's objects frozen (each inline run collects garbage several times, which costs a
    second over a suite's heap). Hypothesis's plugin imports hypothesis as a session ends
    (a second or two each time, were it unloaded)."""
    import importlib

    from scriptc.diagnostics.render import render

    importlib.import_module("hypothesis")
    from scriptc.testing.report import failures

    test = read_test(str(EXAMPLES / "tests" / "greeting.test.toml")).test
    assert test is not None
    render("text", [(test.source, failures(test, run_one(test)))])
    gc.collect()
    gc.freeze()
    yield
    gc.unfreeze()


@pytest.fixture
def project(pytester: pytest.Pytester) -> pytest.Pytester:
    """An activity repository: the greeting example and its world, tests under t/."""
    for name in ("greeting.script", "greeting.world.json"):
        (pytester.path / name).write_text((EXAMPLES / name).read_text(encoding="utf-8"),
                                          encoding="utf-8")
    (pytester.path / "t").mkdir()
    (pytester.path / "t" / "passes.test.toml").write_text(PASSES, encoding="utf-8")
    (pytester.path / "t" / "fails.test.toml").write_text(FAILS, encoding="utf-8")
    pytester.makeini(QUIET)
    return pytester


def scriptc_test(*args: str) -> str:
    """What `scriptc test ARGS` prints (in the working folder, pytester's)."""
    result = CliRunner().invoke(cli, ["test", "-j", "1", *args])
    assert result.exit_code in (0, 1, 2), result.output
    return result.output


def reports(run: pytest.HookRecorder, when: str = "call") -> dict[str, pytest.TestReport]:
    return {r.nodeid: r for r in run.getreports("pytest_runtest_logreport") if r.when == when}


def test_the_entry_point_is_pytest11_named_scriptc() -> None:
    from importlib.metadata import entry_points

    (plugin,) = [e for e in entry_points(group="pytest11") if e.name == "scriptc"]
    assert plugin.value == "scriptc.pytest_plugin"


def test_loading_the_plugin_imports_nothing_of_scriptc_but_the_suffix() -> None:
    """Every pytest of an environment with scriptc loads the plugin: it must cost nothing."""
    code = ("import sys, scriptc.pytest_plugin; "
            "print(sorted(m for m in sys.modules if m.startswith('scriptc')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "['scriptc', 'scriptc.pytest_plugin', 'scriptc.testing']"


def test_off_unless_the_repository_asks(project: pytest.Pytester) -> None:
    """Without `scriptc_tests`, test files are not collected, not even a broken one."""
    (project.path / "t" / "broken.test.toml").write_text(BROKEN, encoding="utf-8")
    result = project.runpytest()
    result.assert_outcomes()
    assert result.ret == pytest.ExitCode.NO_TESTS_COLLECTED
    project.makeini(QUIET + "scriptc_tests = false\n")
    assert project.runpytest().ret == pytest.ExitCode.NO_TESTS_COLLECTED


def test_verdicts_and_messages_are_scriptc_tests(project: pytest.Pytester) -> None:
    project.makeini(INI)
    run = project.inline_run()
    run.assertoutcome(passed=1, failed=1)
    found = reports(run)
    assert found["t/passes.test.toml::passes"].passed
    failed = found["t/fails.test.toml::fails"]
    assert failed.failed
    # The failure is exactly the T006 diagnostics `scriptc test` prints for that test.
    cli_output = scriptc_test("t/fails.test.toml")
    text = failed.longreprtext
    assert text.startswith("error[T006]: `says hello at once`: expected at least 1 `block`")
    assert text.count("error[T006]") == cli_output.count("error[T006]") == 2
    assert text.strip() in cli_output
    assert "help: replay the run: scriptc run greeting.script --world greeting.world.json" \
        in text


def test_the_short_summary_names_the_first_failed_expectation(project: pytest.Pytester) -> None:
    project.makeini(INI)
    result = project.runpytest("-rf")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["FAILED t/fails.test.toml::fails - *says hello at once*"])


def test_a_test_file_with_problems_is_a_collection_error(project: pytest.Pytester) -> None:
    """Its text is the diagnostics `scriptc test` prints, and nothing runs (not even the
    tests that check), as `scriptc test` runs nothing."""
    project.makeini(INI)
    (project.path / "t" / "broken.test.toml").write_text(BROKEN, encoding="utf-8")
    run = project.inline_run()
    (error,) = [r for r in run.getreports("pytest_collectreport") if r.failed]
    assert error.nodeid == "t/broken.test.toml"
    text = error.longreprtext
    assert "error[T002]" in text and "did you mean `event`?" in text
    assert "error[T004]" in text
    assert text.strip() in scriptc_test("t/broken.test.toml")
    assert reports(run) == {}
    result = project.runpytest()
    assert result.ret == pytest.ExitCode.INTERRUPTED
    result.stdout.fnmatch_lines(["*ERROR collecting t/broken.test.toml*",
                                 "*Interrupted: 1 error during collection*"])


def test_a_test_that_cannot_run_fails_with_the_scripts_diagnostics(
        project: pytest.Pytester) -> None:
    project.makeini(INI)
    (project.path / "broken.script").write_text(BROKEN_SCRIPT, encoding="utf-8")
    (project.path / "t" / "errs.test.toml").write_text(ERRS, encoding="utf-8")
    run = project.inline_run("t/errs.test.toml")
    failed = reports(run)["t/errs.test.toml::errs"]
    assert failed.failed
    text = failed.longreprtext
    cli_output = scriptc_test("t/errs.test.toml")
    first = text.splitlines()[0]
    assert first.startswith("ERROR t/errs.test.toml: `broken.script` has errors")
    assert first in cli_output.splitlines()
    assert "--> broken.script:" in text
    assert text.split("\n", 2)[2].strip() in cli_output


def test_k_selects_by_name_folder_and_description(project: pytest.Pytester) -> None:
    project.makeini(INI)
    for expression, passed, failed in [("passes", 1, 0), ("not fails", 1, 0),
                                       ("kept", 0, 1),  # fails.test.toml's description
                                       ("song and not kept", 1, 0), ("t", 1, 1),
                                       ("nothing", 0, 0)]:
        run = project.inline_run("-k", expression)
        run.assertoutcome(passed=passed, failed=failed)


def test_a_file_named_is_collected_without_the_option(project: pytest.Pytester) -> None:
    run = project.inline_run("t/passes.test.toml")
    run.assertoutcome(passed=1)
    assert project.runpytest("t").ret == pytest.ExitCode.NO_TESTS_COLLECTED


def test_the_configurations_exclude_leaves_files_out(project: pytest.Pytester) -> None:
    project.makeini(INI)
    (project.path / "scriptc.toml").write_text('exclude = ["drafts/"]\n', encoding="utf-8")
    (project.path / "drafts").mkdir()
    (project.path / "drafts" / "broken.test.toml").write_text(BROKEN, encoding="utf-8")
    run = project.inline_run()
    run.assertoutcome(passed=1, failed=1)
    assert [r for r in run.getreports("pytest_collectreport") if r.failed] == []
    assert "drafts" not in scriptc_test()


def test_p_no_scriptc_removes_the_plugin(project: pytest.Pytester) -> None:
    project.makeini(INI)
    result = project.runpytest("-p", "no:scriptc")
    assert result.ret == pytest.ExitCode.NO_TESTS_COLLECTED


def test_junit_has_the_simulated_time_and_the_replay(project: pytest.Pytester) -> None:
    project.makeini(INI)
    project.runpytest("--junitxml=report.xml")
    cases = {c.get("name"): c for c in ET.parse(project.path / "report.xml").iter("testcase")}
    assert set(cases) == {"passes", "fails"}
    properties = {p.get("name"): p.get("value") for p in cases["passes"].iter("property")}
    assert properties == {"simulated_ms": "6000", "replay": "scriptc run greeting.script "
                          "--world greeting.world.json --robot kinematic --no-governor "
                          "--until 60000"}
    (failure,) = cases["fails"].iter("failure")
    assert "error[T006]: `says hello at once`" in failure.text


@pytest.mark.slow
def test_items_run_under_xdist(project: pytest.Pytester) -> None:
    """Worker processes collect and run the items as pytest's own process does."""
    project.makeini(INI)
    result = project.runpytest_subprocess("-n", "2", "-p", "no:cacheprovider")
    result.assert_outcomes(passed=1, failed=1)
    output = result.stdout.str()
    assert "error[T006]: `says hello at once`" in output
    assert "error[T006]: `still there at 30 s`" in output


@pytest.mark.slow
def test_scriptc_runs_under_pytest_as_python_compiles_it(pytester: pytest.Pytester) -> None:
    """pytest would rewrite the asserts of every module of scriptc (the distribution of a
    plugin): the plugin unmarks it, so a session's scriptc is the one that ships."""
    pytester.makeini(QUIET)
    pytester.makepyfile(test_compiled="""
        import scriptc.testing.read as read
        import scriptc.runtime.session as session

        def test_not_rewritten():
            assert "@py_builtins" not in vars(read) and "@pytest_ar" not in vars(session)
        """)
    pytester.makepyfile(test_rewritten="""
        def test_the_check_sees_rewriting():
            assert "@py_builtins" in globals()
        """)
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=2)


def test_the_examples_tests_pass_as_pytest_items(pytester: pytest.Pytester) -> None:
    """The examples' own tests (examples/tests/), collected and run by the plugin from the
    repository's configuration, as `scriptc test examples/` runs them."""
    tests = sorted(p.name.removesuffix(".test.toml")
                   for p in (EXAMPLES / "tests").rglob("*.test.toml"))
    assert tests
    run = pytester.inline_run(str(EXAMPLES / "tests"), "-o", "scriptc_tests=true",
                              "-p", "no:cacheprovider")
    run.assertoutcome(passed=len(tests))
    assert sorted(r.nodeid.rsplit("::", 1)[1] for r in reports(run).values()) == tests
