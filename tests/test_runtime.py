"""The runtime through its library API and `scriptc run`: what the case files
(tests/cases/runtime/) do not show as well — exact numbers, error messages, registration of
an activity's own functions and rules, the executor interface, bad scenario files."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.analysis.analyze import analyze_bytes, analyze_file
from scriptc.cli.main import cli
from scriptc.frontend.script import lower_script
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.commands import BlockAddress, BlockCommands, Move, compare, format_number
from scriptc.runtime.evaluate import EvalContext, evaluate
from scriptc.runtime.executor import End, Issue, SeekError
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.robots import make_robot
from scriptc.runtime.robots.kinematic import KinematicRobot
from scriptc.runtime.rules import STANDARD_RULES, RuleError, parse_condition_text, parse_params
from scriptc.runtime.scenario import ScenarioError, load_scenario, scenario_from_data
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import UpdateError, World, parse_update
from scriptc.source import SourceFile

ROOT = Path(__file__).parent.parent
EXAMPLE = ROOT / "examples" / "test_act.script"
JUMP = """\
[jump_act]
[goal:g]
  [action]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
    [b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE})
                  TRJMP(near) FLSJMP()]
    [b##blk_inst: MV("-0.1, 0, 0, 0, 1000") LD() AO()]
    [b##blk_terminus]
    [b#near#blk_inst: MV("0.1, 0, 0, 0, 1000") LD() AO()]
    [b##blk_terminus]
"""
CHILD_AT_08 = {"updates": [{"at": 500, "objectid": "Human/kid1", "attributename": "poses",
                            "policy": "R",
                            "jsonmsg": "{\"positionrho\": 0.8, \"positiontheta\": 0}"}]}


def program(text: str, name: str = "t.script", functions=None) -> IRProgram:
    kwargs = {"functions": functions.registry()} if functions is not None else {}
    analysis = analyze_bytes(name, text.encode(), "script", **kwargs)
    assert analysis.ok, [d.message for d in analysis.diagnostics]
    return IRProgram(analysis.script, name)


def run(text: str, world=None, until=None, **kwargs):
    trace = Trace()
    scenario = scenario_from_data(world) if world is not None else None
    result = Session([program(text)], scenario=scenario, trace=trace, **kwargs).run(until)
    return result, trace


def cli_run(*args: str):
    if "--robot" not in args:  # the default is mujoco (tests/test_mujoco*.py); these hold kinematic
        args = (*args, "--robot", "kinematic")
    return CliRunner().invoke(cli, ["run", *args], catch_exceptions=False)


# ---------------------------------------------------------------------------------------------
# The done-when of the issue


def test_listing_4_1_runs_exactly_16000_ms() -> None:
    analysis = analyze_file(EXAMPLE)
    result = Session([IRProgram(analysis.script, str(EXAMPLE))]).run()
    assert (result.outcome, result.time_ms) == ("completed", 16000)
    # The square closes and the two turns cancel exactly.
    assert result.pose == (0.0, 0.0, 0.0)
    assert result.loads[0].goals == {"test_act_goal": "reached"}


@pytest.mark.parametrize("world, branch, x", [(CHILD_AT_08, "goal0/act0/blk4", 0.1),
                                              (None, "goal0/act0/blk2", -0.1)])
def test_jump_on_a_child_closer_than_1_m(world, branch: str, x: float) -> None:
    result, trace = run(JUMP, world)
    (jump,) = trace.of_kind("jump")
    assert jump["target"] == branch
    assert jump["value"] is (world is not None)
    assert jump["bindings"] == ({"?kid": "Human/kid1"} if world else {})
    assert result.pose.x == pytest.approx(x)
    assert result.time_ms == 2000


@pytest.mark.slow
def test_two_runs_write_identical_traces(tmp_path: Path) -> None:
    """Two processes with different hash seeds: the same bytes (rules, aliases, overrides)."""
    import os
    import subprocess
    import sys

    cases = ROOT / "tests" / "cases" / "runtime"
    outputs = []
    for seed in ("1", "2"):
        out = tmp_path / f"{seed}.jsonl"
        env = {**os.environ, "PYTHONHASHSEED": seed}
        done = subprocess.run([sys.executable, "-m", "scriptc", "run", str(cases / "scopes.script"),
                               "--world", str(cases / "scopes.world"), "--trace", str(out)],
                              capture_output=True, env=env, timeout=60, check=False)
        assert done.returncode == 0, done.stderr
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1] and outputs[0].count(b"\n") > 20


# ---------------------------------------------------------------------------------------------
# Time: exact milliseconds, no ticking


def test_track_timing_is_exact_and_block_waits_for_the_longest_track() -> None:
    text = """[timing]
[goal:g]
[action]
[b##blk_inst: MV("1, 0, 0, 7, 13", "0, 1, 0, 0, 0") LD("1, 0, 0, 1, 3, 5") AO("a.wav, 0, 41")]
[b##blk_terminus]
"""
    result, trace = run(text)
    starts = [(e["t"], e["track"], e["index"]) for e in trace.of_kind("cmd_start")]
    stops = [(e["t"], e["track"], e["index"]) for e in trace.of_kind("cmd_stop")]
    assert starts == [(0, "audioout", 0), (3, "led", 0), (7, "move", 0), (20, "move", 1)]
    assert stops == [(8, "led", 0), (20, "move", 0), (20, "move", 1), (41, "audioout", 0)]
    assert result.time_ms == 41
    assert result.pose.x == pytest.approx(0.013)


def test_a_ten_minute_activity_costs_its_events_not_its_milliseconds() -> None:
    text = """[long]
[goal:g]
[action]
[b#a#blk_inst: MV("0.1, 0, 0, 0, 60000") LD("1, 0, 0, 1, 0, 60000") AO()]
[b##blk_jump: CND({VAR @t U F: now()} ! {E: lt(@t, 600000)}) TRJMP(a) FLSJMP()]
[b##blk_terminus]
"""
    result, trace = run(text)
    assert result.time_ms == 600_000
    assert result.pose.x == pytest.approx(60.0)
    assert trace.count < 200  # ten blocks, a handful of events each


# ---------------------------------------------------------------------------------------------
# The kinematic robot


def _integrate(v, seconds, steps=200_000):
    x = y = th = 0.0
    dt = seconds / steps
    vx, vy, w = v
    for _ in range(steps):
        mid = th + w * dt / 2
        x += (vx * math.cos(mid) - vy * math.sin(mid)) * dt
        y += (vx * math.sin(mid) + vy * math.cos(mid)) * dt
        th += w * dt
    return x, y, th


@pytest.mark.parametrize("v", [(0.3, 0.0, 0.0), (0.2, 0.1, 0.5), (0.0, 0.4, -1.3), (0.0, 0.0, 2.0),
                               (0.5, 0.0, 1e-12)])
def test_kinematic_robot_integrates_arcs_in_closed_form(v) -> None:
    robot = KinematicRobot()
    robot.set_velocity(0, *v)
    robot.advance(2000)
    expected = _integrate(v, 2.0, steps=2000)
    assert robot.pose() == pytest.approx(expected, abs=1e-6)


def test_kinematic_robot_splits_nothing_it_does_not_need_to() -> None:
    one, many = KinematicRobot(), KinematicRobot()
    one.set_velocity(0, 0.2, 0.1, 0.5)
    many.set_velocity(0, 0.2, 0.1, 0.5)
    for t in range(1, 3001, 7):
        many.advance(t)
    one.advance(3000)
    many.advance(3000)
    assert one.pose() == pytest.approx(many.pose(), abs=1e-12)


def test_unknown_robot_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown robot `hoverboard`"):
        make_robot("hoverboard")
    result = cli_run(str(EXAMPLE), "--robot", "nope")
    assert result.exit_code == 2 and "unknown robot `nope`" in result.output


# ---------------------------------------------------------------------------------------------
# Values and the map


def test_compare_is_numeric_when_both_sides_are_numbers() -> None:
    assert compare("10", 9) == 1  # numbers, not text ("10" < "9" as text)
    assert compare("10", "9") == 1
    assert compare("abc", "abd") == -1
    assert compare("10", "x") == -1  # text: "1" < "x"
    assert compare(None, 1) is None
    assert compare("1_000", 5) == -1  # not the language's number syntax: text
    assert format_number(2000.0) == "2000" and format_number(0.8) == "0.8"


def test_map_updates_are_checked_against_the_tables() -> None:
    with pytest.raises(UpdateError, match="unknown class `Dog`"):
        parse_update("Dog/rex", "poses", "R", "{}")
    with pytest.raises(UpdateError, match="`Human` has no attribute `mood`"):
        parse_update("Human/k", "mood", "R", "x")
    with pytest.raises(UpdateError, match="takes policy `R` only"):
        parse_update("Camera/c", "isonline", "A", "s_true")
    with pytest.raises(UpdateError, match="unknown key `rho`"):
        parse_update("Human/k", "poses", "R", '{"rho": 1}')
    with pytest.raises(UpdateError, match="must be a number"):
        parse_update("Human/k", "poses", "R", {"positionrho": "near"})
    with pytest.raises(UpdateError, match="not JSON"):
        parse_update("Human/k", "poses", "R", "{positionrho: 1}")
    with pytest.raises(UpdateError, match='"s_true" or "s_false"'):
        parse_update("Obstacle/o", "isfixed", "R", "yes")
    assert parse_update("RobotStatus/teo", "batterytimeleft", "R", "120").value == 120


# Every refusal of a MapUpdate (tables 4.1 and 4.2), as its sender gets it: the message, the
# update's field it is about, and the jsonmsg's key (None: the message is about the whole
# jsonmsg), with `!` before the key when the key itself is wrong, not its value.
REFUSED_UPDATES = [
    (("Script/x", "submove", "R", "1"), "`Script` takes no id, found `Script/x`",
     "objectid", None),
    (("Humna/k", "poses", "R", "{}"),
     "unknown class `Humna` in objectid `Humna/k` (did you mean `Human`?)", "objectid", None),
    (("Dog/rex", "poses", "R", "{}"),
     ("unknown class `Dog` in objectid `Dog/rex` (one of `Camera`, `Sonar`, `Human`, "
     "`Obstacle`, `Object`, `RobotStatus`, `Script`)"), "objectid", None),
    (("Human", "poses", "R", "{}"), "objectid `Human` must be `Human/ID`", "objectid", None),
    (("Human/", "poses", "R", "{}"), "objectid `Human/` must be `Human/ID`", "objectid", None),
    (("Human/a/b", "poses", "R", "{}"), "objectid `Human/a/b`: an id cannot contain `/`",
     "objectid", None),
    (("Human/k", "pose", "R", "{}"), "`Human` has no attribute `pose` (did you mean `poses`?)",
     "attributename", None),
    (("Human/k", "mood", "R", "x"), ("`Human` has no attribute `mood` (one of `poses`, "
     "`tracking`)"), "attributename", None),
    (("Human/k", "poses", "X", "{}"), "policy must be `R` or `A`, found `X`", "policy", None),
    (("Camera/c", "fps", "A", "1"), "`Camera` `fps` takes policy `R` only, found `A`",
     "policy", None),
    (("Human/k", "poses", "R", "[1]"), ("jsonmsg of `poses` must be an object with "
     "`positionrho`, `positiontheta`, `positionchangetime`"), "jsonmsg", None),
    (("Human/k", "poses", "R", "{positionrho: 1}"),
     "jsonmsg of `poses` is not JSON: expected a key in double quotes, found `positionrho`",
     "jsonmsg", None),
    (("Human/k", "poses", "R", '{"positionrh": 1}'), ("jsonmsg of `poses` has an unknown key "
     "`positionrh` (did you mean `positionrho`?)"), "jsonmsg", "!positionrh"),
    (("Human/k", "poses", "R", {"rho": 1}), ("jsonmsg of `poses` has an unknown key `rho` "
     "(one of `positionrho`, `positiontheta`, `positionchangetime`)"), "jsonmsg", "!rho"),
    (("Human/k", "poses", "R", {"positionrho": True}),
     "`positionrho` in the jsonmsg of `poses` must be a number, found true", "jsonmsg",
     "positionrho"),
    (("Human/k", "poses", "R", {"positionrho": "near"}),
     '`positionrho` in the jsonmsg of `poses` must be a number, found "near"', "jsonmsg",
     "positionrho"),
    (("Human/k", "poses", "R", {"positionrho": math.inf}),
     "`positionrho` in the jsonmsg of `poses` must be a finite number, found inf", "jsonmsg",
     "positionrho"),
    (("Human/k", "tracking", "R", {"appearanceon": 1.5}),
     "`appearanceon` in the jsonmsg of `tracking` must be a whole number, found 1.5",
     "jsonmsg", "appearanceon"),
    (("Human/k", "tracking", "R", {"appearanceon": True}),
     "`appearanceon` in the jsonmsg of `tracking` must be a whole number, found true",
     "jsonmsg", "appearanceon"),
    (("Human/k", "tracking", "R", {"appearanceon": "1e3"}),
     '`appearanceon` in the jsonmsg of `tracking` must be a whole number, found "1e3"',
     "jsonmsg", "appearanceon"),
    (("Human/k", "tracking", "R", {"appearanceon": "9" * 400}),
     ("`appearanceon` in the jsonmsg of `tracking` must be a whole number within a double's "
     f'range, found "{"9" * 400}"'), "jsonmsg", "appearanceon"),
    (("Human/k", "tracking", "R", {"appearanceon": math.inf}),
     "`appearanceon` in the jsonmsg of `tracking` must be a whole number, found inf",
     "jsonmsg", "appearanceon"),
    (("Object/o", "category", "R", 5), "jsonmsg of `category` must be a string, found 5",
     "jsonmsg", None),
    (("Obstacle/o", "isfixed", "R", "yes"),
     'jsonmsg of `isfixed` must be "s_true" or "s_false", found "yes"', "jsonmsg", None),
    (("RobotStatus", "touch", "R", {"touchtype": "ab"}),
     '`touchtype` in the jsonmsg of `touch` must be one character, found "ab"', "jsonmsg",
     "touchtype"),
    (("RobotStatus", "touch", "R", {"touchtype": "éé"}),
     '`touchtype` in the jsonmsg of `touch` must be one character, found "éé"', "jsonmsg",
     "touchtype"),
    (("RobotStatus", "touch", "R", {"touchtype": 7}),
     "`touchtype` in the jsonmsg of `touch` must be one character, found 7", "jsonmsg",
     "touchtype"),
    (("Script", "script_vect", "R", {"update": ["a", 1]}),
     '`update` in the jsonmsg of `script_vect` must be a list of strings, found ["a", 1]',
     "jsonmsg", "update"),
    (("Script", "script_vect", "R", {"update": "a"}),
     '`update` in the jsonmsg of `script_vect` must be a list of strings, found "a"',
     "jsonmsg", "update"),
    (("Script", "script_vect", "R", {"restart": "s_true"}),
     "jsonmsg of `script_vect` needs an `update` list", "jsonmsg", None),
    (("RobotStatus", "goalreached", "A", {"timestamp": 1}),
     "jsonmsg of `goalreached` needs a `goalid`", "jsonmsg", None),
    (("RobotStatus", "batterytimeleft", "R", "x"),
     'jsonmsg of `batterytimeleft` must be a whole number, found "x"', "jsonmsg", None),
    (("RobotStatus", "batterytimeleft", "R", 10**400),
     ("jsonmsg of `batterytimeleft` must be a whole number, found a number beyond a double's "
     "range"), "jsonmsg", None),
    (("RobotStatus", "batterytimeleft", "R", object()),
     "jsonmsg of `batterytimeleft` must be a whole number, found 'object'", "jsonmsg", None),
]


@pytest.mark.parametrize("update, message, field, key", REFUSED_UPDATES,
                         ids=[m[:60] for _u, m, _f, _k in REFUSED_UPDATES])
def test_every_refusal_of_a_map_update(update, message: str, field: str, key) -> None:
    with pytest.raises(UpdateError) as info:
        parse_update(*update)
    error = info.value
    assert str(error) == message
    assert error.field == field
    assert (error.key, error.unknown_key) == ((key.lstrip("!"), key[0] == "!") if key
                                             else (None, False))


def test_a_map_update_points_into_its_jsonmsg_text() -> None:
    """A jsonmsg given as text: the span of the wrong key, or of the wrong value, in it."""
    text = '{"positiontheta": 0, "positionrh": 1}'
    with pytest.raises(UpdateError) as info:
        parse_update("Human/k", "poses", "R", text)
    assert text[info.value.span.start:info.value.span.end] == '"positionrh"'
    text = '{"positionrho": "far"}'
    with pytest.raises(UpdateError) as info:
        parse_update("Human/k", "poses", "R", text)
    assert text[info.value.span.start:info.value.span.end] == '"far"'
    with pytest.raises(UpdateError) as info:
        parse_update("Human/k", "poses", "R", '{"positionrho": 1,')
    assert info.value.span == (18, 18) and "the file ends inside an object" in str(info.value)
    with pytest.raises(UpdateError) as info:
        parse_update("Human/k", "poses", "R", {"positionrho": "far"})  # no text to point into
    assert info.value.span is None


@pytest.mark.parametrize("update, value", [
    (("Human/k", "tracking", "R", {"appearanceon": 2.0}), {"appearanceon": 2}),
    (("Human/k", "tracking", "R", {"appearanceon": " 12 "}), {"appearanceon": 12}),
    (("Human/k", "tracking", "A", '{"appearanceon": -3}'), {"appearanceon": -3}),
    (("Human/k", "poses", "R", {"positionrho": 1}), {"positionrho": 1.0}),
    (("Camera/c", "isonline", "R", True), "s_true"),
    (("Camera/c", "isonline", "R", False), "s_false"),
    (("Camera/c", "isonline", "R", "s_false"), "s_false"),
    (("RobotStatus", "audioin", "A", {"words": ["hi", {"n": 1}]}), {"words": ["hi", {"n": 1}]}),
    (("RobotStatus/teo", "touch", "A", {"touchtype": "h", "duration": 5}),
     {"touchtype": "h", "duration": 5}),
    (("Script", "script_vect", "R", {"update": ["a", "b"], "restart": True}),
     {"update": ["a", "b"], "restart": "s_true"}),
    (("RobotStatus", "batterytimeleft", "R", "120"), 120),
    (("Object/o", "category", "R", "ball"), "ball"),
    (("RobotStatus", "goalfailed", "A", {"goalid": "g", "timestamp": 5}),
     {"goalid": "g", "timestamp": 5}),
])
def test_map_updates_take_their_values_in_the_tables_types(update, value) -> None:
    got = parse_update(*update)
    assert got.value == value and type(got.value) is type(value)
    if isinstance(value, dict):
        assert all(type(got.value[k]) is type(v) for k, v in value.items())
    cls, _sep, ident = update[0].partition("/")
    assert (got.cls, got.id) == (cls, "" if cls in ("RobotStatus", "Script") else ident)
    assert got.as_dict() == {"objectid": update[0], "attributename": update[1],
                             "policy": update[2], "value": got.value}
    with pytest.raises(dataclasses.FrozenInstanceError):
        got.policy = "A"  # an update, once read, is what was sent


def test_r_drops_pending_updates_of_the_same_attribute_only() -> None:
    world = World()
    a1 = parse_update("Human/k", "poses", "A", {"positionrho": 3.0})
    other = parse_update("Human/j", "poses", "A", {"positionrho": 2.0})
    a2 = parse_update("Human/k", "tracking", "A", {"appearanceon": 5})
    r = parse_update("Human/k", "poses", "R", {"positionrho": 1.0})
    for u in (a1, other, a2):
        assert world.post(u) == []
    assert world.post(r) == [a1]
    for u in world.take_pending():
        world.apply(u, 7)
    kid = world.entity("Human", "k")
    assert kid.fields["positionrho"] == 1.0 and kid.fields["positionchangetime"] == 7
    assert kid.fields["appearanceon"] == 5 and len(kid.history["poses"]) == 1


def test_histories_are_circular_registers() -> None:
    world = World()
    for i in range(250):
        world.apply(parse_update("Human/k", "poses", "A", {"positionrho": float(i)}), i)
    history = world.entity("Human", "k").history["poses"]
    assert len(history) == 100 and history[0]["positionrho"] == 150.0


# ---------------------------------------------------------------------------------------------
# Conditions: the shared evaluator


def _context(n: int = 0) -> EvalContext:
    world = World()
    for i in range(n):
        world.apply(parse_update(f"Human/h{i}", "poses", "R", {"positionrho": 2.0 + i}), i)
    return EvalContext(world, Bindings(), STANDARD_IMPLEMENTATIONS)


def test_oldest_free_candidate_wins_over_a_thousand_entities() -> None:
    ctx = _context(1000)
    cond = parse_condition_text("{CLASS #Human U ?far (?THIS>&positionrho OP> 500)} ! {TRUE}")
    ctx.begin("t", 0)
    assert evaluate(cond, ctx).bindings == {"?far": "Human/h499"}
    ctx.begin("t", 0)
    cond2 = parse_condition_text("{CLASS #Human U ?far2 (?THIS>&positionrho OP> 500)} ! {TRUE}")
    assert evaluate(cond2, ctx).bindings == {"?far2": "Human/h500"}  # h499 holds ?far
    ctx.begin("t", 0)
    none = parse_condition_text("{CLASS #Human U ?x (?THIS>&positionrho OP> 5000)} ! {TRUE}")
    assert evaluate(none, ctx).value is False


def test_failed_assignment_keeps_the_ones_before_it_and_true_ends_evaluation() -> None:
    ctx = _context(2)
    cond = parse_condition_text("{CLASS #Human U ?a (?THIS>&positionrho OP< 10)} "
                                "{CLASS #Human U ?b (?THIS>&positionrho OP< 0)} ! {TRUE}")
    ctx.begin("t", 0)
    assert evaluate(cond, ctx).value is False
    assert ctx.bindings.lookup("?a").key == "Human/h0" and ctx.bindings.lookup("?b") is None
    ctx.begin("t", 0)
    assert evaluate(parse_condition_text("! {TRUE} {E: eq(1, 2)}"), ctx).value is True
    ctx.begin("t", 0)
    assert evaluate(parse_condition_text("! {E: eq(1, 2)} {TRUE}"), ctx).value is False


def test_a_bound_alias_keeps_its_entity_while_it_passes_and_moves_when_it_does_not() -> None:
    ctx = _context(2)  # h0 at 2 m, h1 at 3 m
    ctx.world.apply(parse_update("Human/h1", "tracking", "R", {"appearanceon": -5}), 3)  # h1 older
    near = parse_condition_text("{CLASS #Human U ?k (?THIS>&positionrho OP< 2.5)} ! {TRUE}")
    ctx.begin("t", 0)
    assert evaluate(near, ctx).bindings == {"?k": "Human/h0"}
    anyone = parse_condition_text("{CLASS #Human U ?k (?THIS>&positionrho OP< 10)} ! {TRUE}")
    ctx.begin("t", 0)
    assert evaluate(anyone, ctx).bindings == {"?k": "Human/h0"}  # stable, although h1 is older
    ctx.world.apply(parse_update("Human/h0", "poses", "R", {"positionrho": 50.0}), 4)
    ctx.begin("t", 0)
    assert evaluate(anyone, ctx).bindings == {"?k": "Human/h1"}


def test_scopes_end_where_they_should() -> None:
    b = Bindings()
    world = World()
    e = [world.create("Human", f"k{i}", 0) for i in range(3)]
    b.bind("?u", e[0], "U", "r1")
    b.bind("?t", e[1], "T", "r1")
    b.bind("?l", e[2], "L", "r1")
    b.set_att("?l", "mood", "calm", "U", "r1")
    b.end_owner("r2")
    assert b.lookup("?l") is e[2]
    b.end_owner("r1")
    assert b.lookup("?l") is None and b.get_att("?l", "mood") is None  # ATT goes with its alias
    assert b.alias_of(e[2]) is None
    b.end_loop()
    assert b.lookup("?t") is None and b.lookup("?u") is e[0]
    b.bind("?u", e[0], "L", "r2")  # asserted again with a shorter scope: stays U
    b.end_owner("r2")
    assert b.lookup("?u") is e[0]
    b.end_script()
    assert b.lookup("?u") is None


# ---------------------------------------------------------------------------------------------
# An activity's own functions and rules (programmatic registration)


def test_user_functions_are_checked_and_run() -> None:
    impls = STANDARD_IMPLEMENTATIONS.extended()
    impls.register("closer", "E", 2, lambda call, a, b: float(a) < float(b), params=("a", "b"))
    impls.register("mood", "F", 0, lambda call: "happy")
    impls.register("boom", "E", 0, lambda call: 1 / 0)
    text = """[mine]
[goal:g]
[action]
[b##blk_inst: MV() LD() AO("Silence, 0, 10")]
[b##blk_jump: CND({VAR @m U F: mood()} ! {E: closer(1, 2)} {E: eq(@m, "happy")})
              TRJMP(yes) FLSJMP()]
[b##blk_jump: CND(! {E: boom()}) TRJMP() FLSJMP()]
[b#yes#blk_jump: CND(! {E: boom()}) TRJMP() FLSJMP()]
[b##blk_terminus]
"""
    # The standard registry does not know them: the checker refuses the script.
    assert not analyze_bytes("m.script", text.encode(), "script").ok
    trace = Trace()
    result = Session([program(text, functions=impls)], functions=impls, trace=trace).run()
    jumps = trace.of_kind("jump")
    assert jumps[0]["value"] is True and jumps[0]["bindings"] == {"@m": "happy"}
    assert jumps[1]["value"] is False
    (error,) = trace.of_kind("error")
    assert error["code"] == "function" and "ZeroDivisionError" in error["message"]
    assert not error["fatal"] and result.outcome == "completed"
    with pytest.raises(ValueError):
        impls.register("bad name", "E", 0, lambda call: True)
    with pytest.raises(ValueError):
        impls.register("k", "X", 0, lambda call: True)


class _NoTruth:
    def __bool__(self) -> bool:
        raise ValueError("no truth value")


def test_a_function_result_that_is_no_value_is_its_failure() -> None:
    """An F function's result is a text, a number or None, a B/E function's anything with a
    truth value: a list from F, or a result whose truth value raises, is the function failing
    (reported, no value / false), not the session stopping."""
    impls = STANDARD_IMPLEMENTATIONS.extended()
    impls.register("listed", "F", 0, lambda call: ["a", "b"])
    impls.register("vague", "E", 0, lambda call: _NoTruth())
    impls.register("count", "F", 0, lambda call: 3.0)
    text = """[odd]
[goal:g]
[action]
[b##blk_jump: CND({VAR @n U F: count()} ! {TRUE}) TRJMP() FLSJMP()]
[b##blk_jump: CND({VAR @v U F: listed()} ! {TRUE}) TRJMP() FLSJMP()]
[b##blk_jump: CND(! {E: vague()}) TRJMP() FLSJMP()]
[b##blk_terminus]
"""
    trace = Trace()
    result = Session([program(text, functions=impls)], functions=impls, trace=trace).run()
    counted, listed, vague = trace.of_kind("jump")
    assert counted["value"] is True and counted["bindings"] == {"@n": "3"}
    assert listed["value"] is False and listed["bindings"] == {}
    assert vague["value"] is False
    first, second = trace.of_kind("error")
    assert first["code"] == second["code"] == "function"
    assert "`listed` returned list, not a text or a number" in first["message"]
    assert "`vague`" in second["message"] and "no truth value" in second["message"]
    assert result.outcome == "completed"


def test_user_rules_change_the_block_hold_motion_and_set_vars() -> None:
    rules = STANDARD_RULES.extended()
    slow = BlockCommands(moves=(Move(0.05, 0, 0, 0, 2000),))

    def swap(ctx):
        block = ctx.block
        if block is not None and block.moves and block.moves[0].v_x == 1.0:
            ctx.replace_block(slow)
            ctx.set_var("@swapped", str(ctx.now))

    rules.register_simple(100, "swapper",
                          "{CLASS #Human L ?h (?THIS>&positionrho OP< 1.0)} ! {TRUE}",
                          on_true=swap, doc="slows the robot down near a child")
    rules.register_simple(101, "broken", "{TRUE}", on_true=lambda ctx: ctx.no_such_thing)
    text = """[ruled]
[alfa:100, swapper, "", "", A, M]
[alfa:101, broken, "", "", A, U]
[omega:100, swapper, "", "", R, L]
[omega:101, broken, "", "", R, M]
[goal:g]
[action]
[b##blk_inst: MV("1.0, 0, 0, 0, 4000") LD() AO()]
[b##blk_jump: CND(! {E: neq(@swapped, "")}) TRJMP() FLSJMP()]
[b##blk_terminus]
"""
    world = {"updates": [{"at": 1000, "objectid": "Human/k", "attributename": "poses",
                          "policy": "R", "jsonmsg": {"positionrho": 0.5}}]}
    result, trace = run(text, world, rules=rules)
    blocks = trace.of_kind("block")
    assert [(b["t"], b["changed"]) for b in blocks] == [(0, False), (1000, True)]
    cancelled = [e for e in trace.of_kind("cmd_stop") if e.get("cancelled")]
    assert [(e["t"], e["track"]) for e in cancelled] == [(1000, "move")]
    # 1 m at 1 m/s, then the slow block from its beginning: 2 s at 0.05 m/s.
    assert result.time_ms == 3000 and result.pose.x == pytest.approx(1.1)
    assert trace.of_kind("jump")[0]["value"] is True
    errors = [e for e in trace.of_kind("error") if e["code"] == "rule"]
    assert errors and "AttributeError" in errors[0]["message"] and not errors[0]["fatal"]


def test_rule_parameters_and_bad_rules() -> None:
    assert parse_params("distance=0.6; class=Object") == {"distance": "0.6", "class": "Object"}
    assert parse_params("script=x; when={TRUE}; a=b") == {"script": "x", "when": "{TRUE}; a=b"}
    with pytest.raises(RuleError, match="key=value"):
        parse_params("distance 0.6")
    with pytest.raises(RuleError, match="condition"):
        parse_condition_text("{CLASS #Human ?k}")
    text = """[bad_rule]
[alfa:1, guard, "distance=close", "", A, U]
[omega:1, guard, "", "", R, L]
[goal:g]
[action]
[b##blk_inst: MV() LD() AO("Silence, 0, 10")]
[b##blk_terminus]
"""
    _result, trace = run(text)
    (error,) = trace.of_kind("error")
    assert "`distance` must be a number" in error["message"]
    assert trace.of_kind("rule")[0]["result"] == "failed"


# ---------------------------------------------------------------------------------------------
# The executor interface, used directly


class Sink:
    def __init__(self):
        self.seen = []

    def visit(self, position):
        self.seen.append(("visit", position.path))

    def jump(self, position, condition, evaluation, target):
        self.seen.append(("jump", position.path, evaluation.value, target and target.path))

    def sensor(self, position, payload):
        self.seen.append(("sensor", position.path, payload))


def test_ir_executor_reads_seeks_and_ends() -> None:
    script, problems = lower_script(SourceFile("e.script", """[e]
[goal:a]
[action]
[b##blk_sens: "hi"]
[b##blk_inst: MV() LD() AO()]
[goal:b]
[action]
[b##blk_jump: CND(! {TRUE}) TRJMP(end) FLSJMP()]
[b##blk_inst: MV("1, 0, 0, 0, 5") LD() AO()]
[b#end#blk_terminus]
"""))
    assert not problems
    executor = IRProgram(script, "e.script").executor()
    ctx = _context()
    sink = Sink()
    executor.start()
    first = executor.read(ctx, sink)
    assert isinstance(first, Issue) and first.position == BlockAddress(0, 0, 1)
    assert sink.seen == [("visit", "goal0/act0/blk0"), ("sensor", "goal0/act0/blk0", ("hi",)),
                         ("visit", "goal0/act0/blk1")]
    end = executor.read(ctx, sink)
    assert isinstance(end, End) and end.how == "terminus" and end.position == BlockAddress(1, 0, 2)
    executor.seek(BlockAddress(1, 0, 1))
    issue = executor.read(ctx, sink)
    assert issue.instruction.moves == (Move(1.0, 0.0, 0.0, 0, 5),)
    assert isinstance(executor.read(ctx, sink), End)
    with pytest.raises(SeekError):
        executor.seek(BlockAddress(3, 0, 0))
    assert executor.goal_ids == ("a", "b") and executor.alfa == ()


def test_idle_activity_is_a_clean_script() -> None:
    """The idle activity, built as IR (the run time reads no script text), prints as a script
    that lints clean and whose lowering is the same program."""
    from scriptc.emit.script import format_script
    from scriptc.runtime.idle import idle_program, idle_script
    from scriptc.runtime.interp import IRProgram

    text = format_script(idle_script())
    analysis = analyze_bytes("idle.script", text.encode(), "script")
    assert analysis.ok and not [d for d in analysis.diagnostics if d.severity.value != "info"]
    assert format_script(analysis.script) == text
    read, built = IRProgram(analysis.script), idle_program()
    assert (read.name, read.goal_ids, read.labels, read.instructions, read.conditions) == \
        (built.name, built.goal_ids, built.labels, built.instructions, built.conditions)
    assert [b.condition_text for _, b in built.blocks if hasattr(b, "condition")] == \
        [b.condition_text for _, b in read.blocks if hasattr(b, "condition")] == ["! {TRUE}"]


def test_a_replacement_idle_activity_and_the_stalled_outcome() -> None:
    idle = program("[my_idle]\n[goal:g]\n[action]\n"
                   "[b#a#blk_inst: MV() LD() AO(\"Silence, 0, 700\")]\n"
                   "[b##blk_jump: CND(! {TRUE}) TRJMP(a) FLSJMP()]\n")
    trace = Trace()
    result = Session([], idle=idle, stop_when_done=False, trace=trace).run(2000)
    assert result.outcome == "until"
    assert [e["script"] for e in trace.of_kind("script_load")] == ["my_idle"]
    assert len(trace.of_kind("block")) == 3  # 0, 700, 1400
    freeze = {"operator": [{"at": 0, "command": "safety_lock", "held": True},
                           {"at": 100, "command": "interrupt"}]}
    result, _ = run("[f]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO(\"Silence, 0, 500\")]\n"
                    "[b##blk_terminus]\n", freeze)
    assert (result.outcome, result.time_ms) == ("stalled", 100)


FROZEN_SCRIPT = ("[f]\n[goal:g]\n[action]\n[b##blk_inst: MV(\"0.1, 0, 0, 0, 500\") LD() "
                 "AO(\"Silence, 0, 500\")]\n[b##blk_terminus]\n")
FROZEN = {"operator": [{"at": 0, "command": "safety_lock", "held": True},
                       {"at": 100, "command": "interrupt"}]}


def test_a_frozen_run_stalls_at_once_whatever_the_time_limit() -> None:
    """Frozen by the operator with no operator event left, a run can never change again: it
    ends `stalled` at the freeze, with a time limit as without one (it used to run on to the
    limit, the hour `scriptc run` gives by default)."""
    for until in (None, 3_600_000):
        result, trace = run(FROZEN_SCRIPT, FROZEN, until)
        assert (result.outcome, result.time_ms) == ("stalled", 100)
        assert trace.events[-1]["event"] == "session_end"
        assert (trace.events[-1]["outcome"], trace.events[-1]["t"]) == ("stalled", 100)
        assert result.pose.x == pytest.approx(0.01)
    # Wheels that still turn (the operator drives without an end) are not stalled: the robot
    # goes on to the limit. Without a limit nothing else can happen: stalled.
    driving = {"operator": [*FROZEN["operator"], {"at": 200, "command": "drive", "v_x": 0.2}]}
    result, _ = run(FROZEN_SCRIPT, driving, 1200)
    assert (result.outcome, result.time_ms) == ("until", 1200)
    assert result.pose.x == pytest.approx(0.01 + 0.2)
    assert run(FROZEN_SCRIPT, driving)[0].outcome == "stalled"
    # Something still scheduled (the operator resumes later) is not stalled either.
    resumed = {"operator": [*FROZEN["operator"], {"at": 5000, "command": "interrupt"}]}
    result, _ = run(FROZEN_SCRIPT, resumed, 3_600_000)
    assert (result.outcome, result.time_ms) == ("completed", 5400)


@pytest.mark.parametrize("robot", ["kinematic", "mujoco"])
def test_cli_reports_a_frozen_run_as_stalled(tmp_path: Path, robot: str) -> None:
    script, world = tmp_path / "f.script", tmp_path / "freeze.json"
    script.write_text(FROZEN_SCRIPT, encoding="utf-8")
    world.write_text(json.dumps(FROZEN), encoding="utf-8")
    trace = tmp_path / "t.jsonl"
    result = cli_run(str(script), "--world", str(world), "--robot", robot, "--json",
                     "--trace", str(trace))
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert (data["outcome"], data["time_ms"]) == ("stalled", 100) and "note" not in data
    end = json.loads(trace.read_text(encoding="utf-8").splitlines()[-1])
    assert (end["event"], end["outcome"], end["time_ms"]) == ("session_end", "stalled", 100)
    text = cli_run(str(script), "--world", str(world), "--robot", robot)
    assert text.exit_code == 0
    assert text.stdout.startswith("stalled at 100 ms (0.100 s simulated): nothing more could "
                                  "happen")
    assert "f: loaded at 0 ms (queue), still running" in text.stdout


# ---------------------------------------------------------------------------------------------
# Scenario files


def test_scenario_errors_name_the_file_and_the_place(tmp_path: Path) -> None:
    """Every problem at once, sorted by position, each with its line and column, where it is
    in the document, and for an unknown key the known one it is close to."""
    path = tmp_path / "w.json"
    path.write_text(json.dumps({
        "updates": [
            {"at": 5, "objectid": "Human/k", "attributename": "poses", "policy": "X",
             "jsonmsg": "{}"},
            {"at": 5, "objectid": "Human/k", "attributename": "poses", "policy": "R",
             "jsonmsg": "{}", "extra": 1},
        ],
        "operator": [{"at": 1, "command": "safety_lock", "v_x": 1, "on": True}],
        "updatez": [],
    }, indent=1), encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    assert info.value.lines() == [
        f"scenario {path}:7:14: updates[0].policy: must be one of `R`, `A`, found `\"X\"`",
        (f"scenario {path}:16:4: updates[1]: unknown key `extra` (the keys here are `at`, "
         "`attributename`, `jsonmsg`, `objectid`, `policy`)"),
        f"scenario {path}:20:3: operator[0]: the key `held` is missing",
        f"scenario {path}:23:4: operator[0]: `v_x` is not a key of a `safety_lock` event",
        f"scenario {path}:24:4: operator[0]: `on` is not a key of a `safety_lock` event",
        f"scenario {path}:27:2: unknown key `updatez` (did you mean `updates`?)",
    ]
    assert str(path) in str(info.value)
    path.write_text('{"updates": [{"at": 5, "objectid": "Human/k", "attributename": "poze", '
                    '"policy": "R", "jsonmsg": "x"}]}', encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    assert info.value.lines() == [
        (f"scenario {path}:1:64: updates[0] (at 5 ms): `Human` has no attribute `poze` "
         "(did you mean `poses`?)")]
    path.write_text('{"updates": [}', encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    assert info.value.lines() == [f"scenario {path}:1:14: expected a value, found `}}`"]
    with pytest.raises(ScenarioError, match="does not exist"):
        load_scenario(str(tmp_path / "missing.json"))
    path.write_bytes(b'{"description": "ok",\n "x\xff": 1}')
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    assert info.value.lines() == [(f"scenario {path}:2:4: the file is not UTF-8 text: byte 0xff "
                                   "is not valid UTF-8 (byte 25 of the file)")]
    # A byte order mark is dropped (and counted in the file's bytes, not in the columns).
    path.write_bytes(b'\xef\xbb\xbf{"description": "ok",\n "x\xff": 1}')
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    assert info.value.lines() == [(f"scenario {path}:2:4: the file is not UTF-8 text: byte 0xff "
                                   "is not valid UTF-8 (byte 28 of the file)")]
    path.write_bytes(b'\xef\xbb\xbf{"description": "ok"}')
    assert load_scenario(str(path)).updates == []


def test_a_jsonmsg_text_is_pointed_into(tmp_path: Path) -> None:
    """A problem inside a jsonmsg given as text is at its place in the file, escapes and all;
    given as a JSON value, at the key or value of the record."""
    path = tmp_path / "w.json"
    update = '{"at": 0, "objectid": "Human/k", "attributename": "poses", "policy": "R", '
    path.write_text('{"updates": [\n' + update + '"jsonmsg": "{\\"positionrho\\": NaN}"},\n'
                    + update + '"jsonmsg": "{\\"positionrhoo\\": 1}"},\n'
                    + update + '"jsonmsg": {"positiontheta": "left"}},\n'
                    + update + '"jsonmsg": {"positionrhoo": 1}}]}', encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    lines = path.read_text(encoding="utf-8").splitlines()
    assert [(p, m.split(": ", 1)[1])
            for p, m in zip(info.value.positions, info.value.problems, strict=True)] \
        == [((2, lines[1].index("NaN") + 1),
             ("jsonmsg of `poses` is not JSON: `NaN` is not a JSON number: JSON numbers are "
              "finite")),
            ((3, lines[2].index('\\"positionrhoo') + 1),
             ("jsonmsg of `poses` has an unknown key `positionrhoo` (did you mean "
              "`positionrho`?)")),
            ((4, lines[3].index('"left"') + 1),
             "`positiontheta` in the jsonmsg of `poses` must be a number, found \"left\""),
            ((5, lines[4].index('"positionrhoo"') + 1),
             ("jsonmsg of `poses` has an unknown key `positionrhoo` (did you mean "
              "`positionrho`?)"))]


@pytest.mark.parametrize("world, problem", [
    ('{"updates": [{"at": 0, "objectid": "Human/k", "attributename": "poses", "policy": "R", '
     '"jsonmsg": {"positionrho": ' + "1" * 5000 + '}}]}', "(5000 digits) is too large"),
    ('{"operator": [{"at": 0, "command": "drive", "v_x": NaN}]}', "`NaN` is not a JSON number"),
    ('{"operator": [{"at": 0, "command": "drive", "v_x": 1e308}]}',
     "operator[0].v_x: must be at most 100, found `1e308`"),
    ('{"entities": [{"objectid": "Human/k", "x": 1e400, "y": 0}]}', "`1e400` is too large"),
    ('{"entities": [{"objectid": "Human/k", "x": ' + "9" * 400 + ', "y": 0}]}',
     "(400 digits) is too large"),
    ('{"entities": [{"objectid": "Human/k", "x": 1e7, "y": 0}]}',
     "entities[0].x: must be at most 1000000, found `1e7`"),
    ('{"sensing": {"rate_hz": 5e-324}}', "sensing.rate_hz: must be at least 0.001"),
    (('{"updates": [{"at": 1e300, "objectid": "Human/k", "attributename": "poses", '
      '"policy": "R", "jsonmsg": {}}]}'), "updates[0].at: must be at most 2147483647"),
    ('{"description": ' + "[" * 100_000 + "]" * 100_000 + "}",
     "nested more than 32 levels deep"),
    ('{"updates": [{"at": 0, "objectid": "Human/k", "attributename": "poses", '
     '"policy": "R", "jsonmsg": "' + "[" * 100 + "]" * 100 + '"}]}',
     "jsonmsg of `poses` is not JSON: arrays and objects nested more than 32 levels deep"),
])
def test_numbers_and_depths_a_scenario_refuses(tmp_path: Path, world: str, problem: str) -> None:
    """Hostile numbers and nesting are refused where they are written, with a position: each
    was an internal error (or NaN in `--json`) before one number policy read every file."""
    path = tmp_path / "w.json"
    path.write_text(world, encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(str(path))
    (line,) = info.value.lines()
    assert problem in line and line.startswith(f"scenario {path}:1:"), line


def test_scenario_schema_accepts_the_case_worlds() -> None:
    import jsonschema

    from scriptc.resources import schema_path

    for name in ("scenario.schema.json", "trace.schema.json"):
        schema = json.loads(schema_path(name).read_text(encoding="utf-8"))
        jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(
        json.loads(schema_path("scenario.schema.json").read_text(encoding="utf-8")))
    worlds = sorted((ROOT / "tests" / "cases" / "runtime").glob("*.world"))
    assert worlds
    for world in worlds:
        assert not list(validator.iter_errors(json.loads(world.read_text(encoding="utf-8")))), world


# ---------------------------------------------------------------------------------------------
# scriptc run


def test_cli_json_summary(tmp_path: Path) -> None:
    result = cli_run(str(EXAMPLE), "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["outcome"] == "completed" and data["time_ms"] == 16000
    assert data["pose"] == {"x": 0.0, "y": 0.0, "theta": 0.0}
    assert data["scripts"][0]["goals"] == {"test_act_goal": "reached"}
    until = json.loads(cli_run(str(EXAMPLE), "--json", "--until", "1500").stdout)
    assert until["outcome"] == "until" and until["time_ms"] == 1500
    assert until["pose"]["x"] == pytest.approx(5.0)  # 10 m/s for the 500 ms from 1000 ms


def test_cli_text_summary_and_queue_of_json_and_script(tmp_path: Path) -> None:
    trace = tmp_path / "t.jsonl"
    result = cli_run(str(EXAMPLE), str(ROOT / "tests" / "data" / "test_act.json"),
                     "--trace", str(trace))
    assert result.exit_code == 0
    assert result.stdout.startswith("completed at 32000 ms (32.000 s simulated)")
    assert "pose: x = 0.0000 m, y = 0.0000 m, theta = 0.0000 rad" in result.stdout
    assert f"trace: {trace}" in result.stdout
    lines = trace.read_text(encoding="utf-8").splitlines()
    assert json.loads(lines[-1])["event"] == "session_end"


def test_cli_refuses_scripts_with_errors(tmp_path: Path) -> None:
    bad = tmp_path / "bad.script"
    bad.write_text("[bad]\n[goal:g]\n[action]\n"
                   "[b##blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n", encoding="utf-8")
    result = cli_run(str(EXAMPLE), str(bad))
    assert result.exit_code == 1
    assert "error[L003]" in result.stderr and not result.stdout


def test_cli_bad_world_and_missing_file_exit_2(tmp_path: Path) -> None:
    world = tmp_path / "w.json"
    world.write_text('{"updates": [{"at": -1}]}', encoding="utf-8")
    result = cli_run(str(EXAMPLE), "--world", str(world))
    assert result.exit_code == 2
    assert f"error: scenario {world}:1:21: updates[0].at: must be at least 0, found `-1`\n" \
        in result.stderr
    assert cli_run(str(tmp_path / "nope.script")).exit_code == 2


def test_cli_bytecode_is_verified_then_run_by_the_vm(tmp_path: Path) -> None:
    """A `.scb` file is decoded and verified (refused, exit 1, when malformed), then runs on the
    VM: the Listing 4.1 bytecode runs for 16,000 ms like the script, to the same summary."""
    bad = tmp_path / "bad.scb"
    bad.write_bytes(b"SCB\x00")
    result = cli_run(str(bad))
    assert result.exit_code == 1 and "malformed bytecode" in result.stderr
    scb = tmp_path / "t.scb"
    compiled = CliRunner().invoke(cli, ["compile", str(EXAMPLE), "--emit", "bytecode", "-o",
                                        str(scb)])
    assert compiled.exit_code == 0
    ran = json.loads(cli_run(str(scb), "--json").stdout)
    assert ran["outcome"] == "completed" and ran["time_ms"] == 16_000
    for executor in ("vm", "ir"):
        script = json.loads(cli_run(str(EXAMPLE), "--json", "--executor", executor).stdout)
        assert (script["outcome"], script["time_ms"], script["pose"]) == \
            (ran["outcome"], ran["time_ms"], ran["pose"])


def test_cli_refuses_a_loop_that_never_lets_time_pass(tmp_path: Path) -> None:
    """The checker sees the cycle (F002), so the run never starts; the run-time guard behind it
    is held by the `no_progress` case, run unchecked."""
    loop = tmp_path / "z.script"
    loop.write_text("[z]\n[goal:g]\n[action]\n[b#a#blk_inst: MV() LD() AO()]\n"
                    "[b##blk_jump: CND(! {TRUE}) TRJMP(a) FLSJMP()]\n", encoding="utf-8")
    result = cli_run(str(loop), "--json")
    assert result.exit_code == 1
    assert "F002" in result.stderr


@pytest.mark.parametrize("op", ["OP<", "OP>", "OP="])
@pytest.mark.parametrize("right", ["1.0", '"1.0"', '"abc"', "-3", '"s_true"', "1e999"])
def test_compiled_tests_mean_what_compare_op_does(op: str, right: str) -> None:
    """A test compiled from the IR (the fast comparison of a field with a number among them)
    holds exactly when `compare_op` says the field's value and the right side compare so."""
    from scriptc.runtime.commands import compare_op
    from scriptc.runtime.evaluate import check_of, read_of

    cond = parse_condition_text(f"{{CLASS #Object U ?o (?THIS>&category {op} {right})}} ! {{TRUE}}")
    (test,) = cond.assignments[0].tests
    check = check_of(test)
    ctx = _context()
    expected_right = read_of(test.value).get(None, ctx)
    for i, value in enumerate([0.5, 1, 1.0, 2, -3, -3.0, "1.0", "0.9", "-3", "abc", "abd",
                               "s_true", True, False, None, float("inf"), float("nan")]):
        entity = ctx.world.create("Object", f"o{i}", 0)
        if value is not None:
            entity.fields["category"] = value
        assert check(entity, ctx) == compare_op(op, value, expected_right), (op, right, value)


def test_the_runtime_never_reads_the_wall_clock() -> None:
    import re

    runtime = ROOT / "src" / "scriptc" / "runtime"
    clock = re.compile(r"\b(import time|from time|datetime|perf_counter|monotonic|time\.time)\b")
    offenders = [p.name for p in runtime.rglob("*.py")
                 if clock.search(p.read_text(encoding="utf-8"))]
    assert not offenders


@pytest.mark.slow
def test_scriptc_run_stays_light(tmp_path: Path) -> None:
    """A run without a scenario imports neither jsonschema nor rich (not a terminal), pygls or
    mujoco."""
    import subprocess
    import sys

    (tmp_path / "a.script").write_text(
        "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n[b##blk_terminus]\n",
        encoding="utf-8")
    probe = ("import sys\nfrom scriptc.cli.main import main\n"
             "sys.argv = ['scriptc', 'run', 'a.script', '--robot', 'kinematic']\n"
             "try:\n    main()\nexcept SystemExit:\n    pass\n"
             "print(sorted({m.split('.')[0] for m in sys.modules}))")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          cwd=tmp_path, timeout=60, check=False)
    assert "completed at 0 ms" in done.stdout
    import ast

    loaded = set(ast.literal_eval(done.stdout.strip().splitlines()[-1]))  # the list printed
    assert not loaded & {"jsonschema", "rich", "pygls", "mujoco"}, loaded


def test_an_idle_activity_that_ends_at_once_does_not_hang() -> None:
    idle = program("[quick_idle]\n[goal:g]\n[action]\n[b##blk_terminus]\n")
    trace = Trace(enabled=False)
    result = Session([], idle=idle, stop_when_done=False, trace=trace,
                     max_loops_per_instant=50).run(1000)
    assert result.outcome == "error" and trace.errors[0]["code"] == "no-progress"
