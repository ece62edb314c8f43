"""The run-time codes (family X of the registry): the runtime writes no other code, every one
it writes is registered, each explanation's example really reports its code when run, and
lint refuses to select or suppress them (it never reports them)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from scriptc.analysis.analyze import analyze_file
from scriptc.diagnostics.codes import all_codes, explanation, lint_codes, run_time_name
from scriptc.project.setup import setup_for
from scriptc.runtime import status
from scriptc.runtime.configured import implementations_for, rules_for
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import load_scenario
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace

RUNTIME = Path(__file__).parent.parent / "src" / "scriptc" / "runtime"
RUN_TIME = [c for c in all_codes() if c.at_run_time]


def test_the_runtime_writes_exactly_the_registered_run_time_codes() -> None:
    written = {value for name, value in vars(status).items()
               if name.isupper() and isinstance(value, str)}
    assert written == {c.name for c in RUN_TIME}
    assert all(c.code.startswith("X") for c in RUN_TIME)
    assert not any(c.at_run_time for c in lint_codes())


def test_only_the_status_writes_error_events() -> None:
    """Every `error` event goes through `RunStatus` (whose codes the registry checks): no
    other module of the runtime emits one itself."""
    emitting = re.compile(r"""emit\([^)]*["']error["']""")
    offenders = [p.name for p in RUNTIME.rglob("*.py")
                 if p.name != "status.py" and emitting.search(p.read_text(encoding="utf-8"))]
    assert offenders == []


@pytest.mark.parametrize("name", ["no-such-code", "unknown-label", "L003", "X001"])
def test_a_name_that_is_not_a_run_time_code_is_refused(name: str) -> None:
    with pytest.raises(KeyError):
        run_time_name(name)


# -- each explanation's example, run ------------------------------------------------------------

# Robots other than the kinematic one: MuJoCo's physics is what can become unstable.
ROBOT = {"X010": "mujoco"}


def _blocks(text: str, language: str) -> list[str]:
    example = text.split("## Example", 1)[1].split("## How to fix", 1)[0]
    return re.findall(rf"```{language}\n(.*?)```", example, re.DOTALL)


@pytest.mark.parametrize("code", [c.code for c in RUN_TIME])
def test_the_example_of_each_run_time_code_reports_it(code: str, tmp_path: Path) -> None:
    """The example, laid out as a repository (its configuration and Python implementations,
    the script, the scenario), runs through the library as `scriptc run` runs it, without the
    checker (some examples are what the checker rejects), and its trace has an `error` event
    with the code's name, fatal exactly when the code is an error."""
    entry = next(c for c in RUN_TIME if c.code == code)
    text = explanation(code)
    (script,) = _blocks(text, "scriptc")
    path = tmp_path / "example.script"
    path.write_text(script, encoding="utf-8")
    for config in _blocks(text, "toml"):
        (tmp_path / "scriptc.toml").write_text(config, encoding="utf-8")
    modules = []
    for python in _blocks(text, "python"):
        found = re.search(r'implementation = "(\w+):', "".join(_blocks(text, "toml")))
        assert found, f"{code}: a Python example needs its declaration in the toml example"
        modules.append(found.group(1))
        (tmp_path / f"{found.group(1)}.py").write_text(python, encoding="utf-8")
    scenario = None
    for world in _blocks(text, "json"):
        (tmp_path / "world.json").write_text(world, encoding="utf-8")
        scenario = load_scenario(str(tmp_path / "world.json"))
    try:
        setup = setup_for(str(path), cache=False)
        analysis = analyze_file(path, functions=setup.functions)
        assert analysis.script is not None, analysis.diagnostics
        trace = Trace()
        Session([IRProgram(analysis.script, "example.script")], scenario=scenario, trace=trace,
                robot=ROBOT.get(code, "kinematic"), functions=implementations_for(setup.settings),
                rules=rules_for(setup.settings)).run(60_000)
    finally:
        for module in modules:
            sys.modules.pop(module, None)
        if str(tmp_path) in sys.path:
            sys.path.remove(str(tmp_path))
    reported = [e for e in trace.errors if e["code"] == entry.name]
    assert reported, f"{code}'s example reports {[e['code'] for e in trace.errors]}"
    assert all(e["fatal"] == (entry.severity.value == "error") for e in reported)


# -- lint never reports them ----------------------------------------------------------------------


def test_lint_refuses_to_select_or_ignore_run_time_codes(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    script = tmp_path / "a.script"
    script.write_text("[a]\n[goal:g]\n[action]\n[b##blk_terminus]\n", encoding="utf-8")
    runner = CliRunner()
    for option, selector, shown in (("--select", "mutex-misuse", "X001"),
                                    ("--ignore", "X", "X001..X010")):
        result = runner.invoke(cli, ["lint", option, selector, str(script)])
        assert result.exit_code == 2
        assert f"names only run-time codes ({shown}), which lint never reports" in result.output
    # A mistyped code is offered lint's codes only.
    result = runner.invoke(cli, ["lint", "--select", "X0011", str(script)])
    assert result.exit_code == 2 and "X001" not in result.output.split("did you mean", 1)[1]


def test_explain_says_a_run_time_code_is_reported_by_a_run() -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    result = CliRunner().invoke(cli, ["explain", "no-progress"])
    assert result.exit_code == 0
    assert result.output.startswith("X008 (no-progress): ")
    assert "at run time, in the trace: error (the run stops)" in result.output
    result = CliRunner().invoke(cli, ["explain", "X002"])
    assert "at run time, in the trace: warning (the run goes on)" in result.output
