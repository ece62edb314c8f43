"""A repository's own functions and rules, declared in scriptc.toml with Python
implementations, are checked, imported and run (issue 3: "user functions declared in the
activity repository's configuration with a Python implementation", "user rules declared in
configuration")."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from scriptc.analysis.analyze import analyze_file
from scriptc.project.setup import setup_for
from scriptc.runtime.configured import ConfiguredError, implementations_for, rules_for
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace

CONFIG = """
[[functions]]
name = "farther"
kind = "E"
params = ["a", "b"]
implementation = "activity_functions:farther"

[[rules]]
name = "cheer"
rulecode = 40
implementation = "activity_rules:Cheer"

[[rules]]
name = "wave"
implementation = "activity_rules:Wave"
"""
FUNCTIONS = """
def farther(call, a, b):
    return float(a) > float(b)
"""
RULES = """
from scriptc.runtime.rules import Rule

class Cheer(Rule):
    def on_true(self, ctx):
        ctx.note("cheer", by="rulecode")

class Wave(Rule):
    def on_true(self, ctx):
        ctx.note("wave", by="id")
"""
SCRIPT = """[party]
[alfa:40, cheer, "", "", A, M]
[alfa:99, wave, "", "", A, U]
[omega:40, cheer, "", "", R, L]
[omega:99, wave, "", "", R, M]
[goal:g]
  [action]
    [b#start#blk_inst: MV() LD() AO("Silence, 0, 100")]
    [b##blk_jump: CND(! {E: farther(3, 2)}) TRJMP(yes) FLSJMP()]
    [b##blk_terminus]
    [b#yes#blk_inst: MV("0.1, 0, 0, 0, 1000") LD() AO()]
    [b##blk_terminus]
"""


@pytest.fixture()
def repo(tmp_path: Path):
    (tmp_path / "scriptc.toml").write_text(CONFIG, encoding="utf-8")
    (tmp_path / "activity_functions.py").write_text(FUNCTIONS, encoding="utf-8")
    (tmp_path / "activity_rules.py").write_text(RULES, encoding="utf-8")
    (tmp_path / "party.script").write_text(SCRIPT, encoding="utf-8")
    yield tmp_path
    for name in ("activity_functions", "activity_rules"):
        sys.modules.pop(name, None)
    if str(tmp_path) in sys.path:
        sys.path.remove(str(tmp_path))


def test_declared_functions_and_rules_run(repo: Path) -> None:
    setup = setup_for(str(repo / "party.script"))
    settings = setup.settings
    assert not setup.problems
    analysis = analyze_file(repo / "party.script", functions=setup.functions)
    assert analysis.ok, [d.message for d in analysis.diagnostics]
    trace = Trace()
    session = Session([IRProgram(analysis.script, "party.script")], trace=trace,
                      functions=implementations_for(settings), rules=rules_for(settings))
    result = session.run()
    events = trace.events
    jumps = [e for e in events if e["event"] == "jump"]
    assert jumps and jumps[0]["value"] is True  # farther(3, 2), run from the repository's module
    notes = {e["message"]: e for e in events if e["event"] == "rule_note"}
    assert notes["cheer"]["rulecode"] == 40  # found by its rulecode
    assert notes["wave"]["id"] == "wave"  # no rulecode declared: found by its id
    assert abs(result.pose.x - 0.1) < 1e-9


def test_an_implementation_that_cannot_be_imported_is_named(repo: Path) -> None:
    (repo / "scriptc.toml").write_text(
        CONFIG.replace("activity_rules:Wave", "activity_rules:Missing"), encoding="utf-8")
    settings = setup_for(str(repo / "party.script"), cache=False).settings
    with pytest.raises(ConfiguredError, match=r"rule `wave`.*Missing"):
        rules_for(settings)


def test_scriptc_run_uses_the_repository(repo: Path) -> None:
    """`scriptc run` checks with the declared functions and runs them and the rules."""
    import json

    from click.testing import CliRunner

    from scriptc.cli.main import cli

    trace = repo / "run.jsonl"
    result = CliRunner().invoke(cli, ["run", str(repo / "party.script"), "--robot", "kinematic",
                                      "--json", "--trace", str(trace)])
    assert result.exit_code == 0, result.output
    assert abs(json.loads(result.stdout)["pose"]["x"] - 0.1) < 1e-9
    events = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    assert {e["message"] for e in events if e["event"] == "rule_note"} == {"cheer", "wave"}


def test_scriptc_run_names_an_implementation_it_cannot_import(repo: Path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    (repo / "scriptc.toml").write_text(
        CONFIG.replace("activity_functions:farther", "nowhere:farther"), encoding="utf-8")
    result = CliRunner().invoke(cli, ["run", str(repo / "party.script"), "--robot", "kinematic"])
    assert result.exit_code == 2
    assert "function `farther`" in result.output and "nowhere" in result.output
