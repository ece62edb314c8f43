"""The safety governor (runtime/governor.py, docs/robot.md "The governor"): speed clamps keep the
direction and the timing; accelerations are ramps per axis on the 1 ms grid that keep the
distance of a move from rest to rest; the LEDs never flash more than the profile allows; every
clamp is in the trace, and a script within all limits gets none."""

from __future__ import annotations

import json
import math

import pytest

from scriptc import bytecode
from scriptc.analysis.analyze import analyze_bytes
from scriptc.ops.build import emit
from scriptc.resources import schema_path
from scriptc.robot.motion import Shaper
from scriptc.robot.profile import DEFAULT_PROFILE, Profile
from scriptc.runtime.governor import Governor
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.robots import make_robot
from scriptc.runtime.robots.kinematic import KinematicRobot
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.vm import program_from_bytecode

A = DEFAULT_PROFILE.max_linear_acceleration  # 1 m/s²
ALPHA = DEFAULT_PROFILE.max_angular_acceleration  # 3 rad/s²
STILL = {"v_x": 0.0, "v_y": 0.0, "v_theta": 0.0}


def governed(profile: Profile = DEFAULT_PROFILE):
    trace = Trace()
    return Governor(KinematicRobot(), profile, trace), trace


# The run-time governor is what holds scripts the static checks did not hold to the robot's
# profile (checked under another configuration, built with the API, loaded as bytecode): the
# scripts here are checked against a profile that lets the LEDs flash.
LOOSE = Profile(max_led_flash_rate=1000.0)


def analysis_of(text: str):
    analysis = analyze_bytes("t.script", text.encode("utf-8"), "script", profile=LOOSE)
    assert analysis.ok, [d.message for d in analysis.diagnostics]
    return analysis


def run(text: str, robot: str = "kinematic", profile=DEFAULT_PROFILE, until=None, vm=False):
    analysis = analysis_of(text)
    program = IRProgram(analysis.script, "t.script")
    if vm:
        program = program_from_bytecode(
            bytecode.load(emit(analysis.script, "bytecode", analysis.source)), "t.script")
    trace = Trace()
    session = Session([program], robot=robot, trace=trace, profile=profile)
    return session.run(until), trace, session


def moves(*commands: str, leds: str = "", audio: str = "") -> str:
    mv = ", ".join(f'"{c}"' for c in commands)
    return (f"[m]\n[goal:g]\n[action]\n[b##blk_inst: MV({mv}) LD({leds}) AO({audio})]\n"
            "[b##blk_terminus]\n")


# ---------------------------------------------------------------------------------------------
# Speed, distance to people


def test_a_fast_move_is_slowed_keeping_its_direction() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 3.0, 4.0, 0.0)  # 5 m/s toward (0.6, 0.8)
    gov.flush()
    assert gov.velocity_at(100) == pytest.approx((0.075, 0.1, 0.0))  # the direction, ramping
    gov.set_velocity(1000, 0, 0, 0)
    assert gov.come_to_rest(1000) == 1400  # v_y brakes from 0.4 m/s at 1 m/s²
    p = gov.pose()
    assert p.x == pytest.approx(0.3) and p.y == pytest.approx(0.4)
    start, stop = trace.of_kind("governor")
    assert start["t"] == 0 and start["reasons"] == ["speed", "acceleration"]
    assert start["commanded"] == {"v_x": 3.0, "v_y": 4.0, "v_theta": 0.0}
    assert start["applied"] == STILL and start["ramp_ms"] == 400
    assert math.hypot(start["target"]["v_x"], start["target"]["v_y"]) == pytest.approx(0.5)
    assert start["target"]["v_x"] / start["target"]["v_y"] == pytest.approx(0.75)

    assert stop["t"] == 1000 and stop["reasons"] == ["acceleration"]


def test_turning_is_clamped_with_its_sign() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0, 0, -50)
    gov.set_velocity(1000, 0, 0, 0)
    gov.come_to_rest(1000)
    assert gov.pose().theta == pytest.approx(-DEFAULT_PROFILE.max_angular_speed)
    first = trace.of_kind("governor")[0]
    assert first["reasons"] == ["angular-speed", "angular-acceleration"]
    assert first["target"]["v_theta"] == -DEFAULT_PROFILE.max_angular_speed


def test_changes_within_one_millisecond_at_the_limits_pass_unlogged() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0.001, -0.001, 0.003)  # a * 1 ms, alpha * 1 ms: no ramp
    gov.flush()
    assert gov.target == (0.001, -0.001, 0.003) and gov.ramp is None
    assert gov.clamps == 0 and not trace.events
    gov.set_velocity(10, 0.2, -0.1, 0.4)  # within the speeds, not within one millisecond
    gov.flush()
    (event,) = trace.of_kind("governor")
    assert event["reasons"] == ["acceleration", "angular-acceleration"]
    assert event["ramp_ms"] == 199 and event["target"] == {"v_x": 0.2, "v_y": -0.1,
                                                           "v_theta": 0.4}


def test_commands_that_cancel_out_within_an_instant_are_not_ramps() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0.25, 0, 0)
    gov.set_velocity(500, 0, 0, 0)  # a move's stop and the next move's start, same ms
    gov.set_velocity(500, 0.25, 0, 0)
    gov.set_velocity(1000, 0, 0, 0)
    gov.flush()
    assert [e["t"] for e in trace.of_kind("governor")] == [0, 1000]


def test_humans_closer_than_the_minimum_stop_translation_toward_them() -> None:
    gov, trace = governed()
    gov.nearest = lambda t, pose: (0.3, 0.0)  # a child 30 cm straight ahead
    gov.set_velocity(0, 0.2, 0, 0.5)
    gov.flush()
    assert gov.target == (0.0, 0.0, 0.5)
    assert trace.of_kind("governor")[0]["reasons"] == ["human-distance",
                                                        "angular-acceleration"]
    gov.set_velocity(10, -0.2, 0, 0)  # backing away is allowed
    gov.flush()
    assert gov.target == (-0.2, 0.0, 0.0)
    gov.nearest = lambda t, pose: (1.0, 0.0)
    gov.set_velocity(20, 0.2, 0, 0)
    gov.flush()
    assert gov.target == (0.2, 0.0, 0.0)


def test_the_hold_brakes_at_the_limit_and_anticipates_the_braking_distance() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0.3, 0, 0)
    gov.advance(1000)  # at 0.3 m/s: braking takes 0.3² / 2 = 4.5 cm
    gov.nearest = lambda t, pose: (0.46, 0.0)
    gov.recheck(1000)
    gov.flush()
    assert gov.target == (0.3, 0.0, 0.0)  # 0.46 - 0.045 is beyond 0.4 m
    gov.nearest = lambda t, pose: (0.44, 0.0)
    gov.recheck(1100)
    gov.flush()
    hold = trace.of_kind("governor")[-1]
    assert hold["reasons"] == ["human-distance", "acceleration"] and hold["ramp_ms"] == 300
    assert hold["applied"]["v_x"] == pytest.approx(0.3) and hold["target"] == STILL
    x = gov.pose().x
    gov.nearest = lambda t, pose: (0.44 - (pose.x - x), 0.0)  # the child stands still
    gov.recheck(1200)  # braking: still held (distance minus braking distance is constant)
    gov.flush()
    assert gov.target == (0.0, 0.0, 0.0) and len(trace.of_kind("governor")) == 2
    gov.advance(1400)
    assert gov.pose().x - x == pytest.approx(0.045, abs=2e-4)  # stops 0.395 m from the child


def test_the_session_uses_the_governor_only_with_a_profile() -> None:
    text = moves("2, 0, 0, 0, 1000")
    analysis = analysis_of(text)
    plain = Session([IRProgram(analysis.script, "m.script")]).run()
    assert plain.pose.x == pytest.approx(2.0)
    governed_run = Session([IRProgram(analysis.script, "m.script")],
                           profile=DEFAULT_PROFILE).run()
    assert governed_run.pose.x == pytest.approx(0.5) and governed_run.time_ms == 1000


# ---------------------------------------------------------------------------------------------
# Acceleration: ramps


def test_a_ramp_is_linear_at_the_limit_on_the_millisecond_grid() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0.5, 0, 1.5)
    gov.flush()
    for t in (1, 50, 100, 250, 499):
        v_x, v_y, w = gov.velocity_at(t)
        assert v_x == pytest.approx(A * t / 1000) and v_y == 0.0
        assert w == pytest.approx(min(ALPHA * t / 1000, 1.5))
    assert gov.velocity_at(500) == (0.5, 0.0, 1.5) == gov.velocity_at(9000)
    gov.advance(200)
    assert gov.robot.velocity == pytest.approx((0.2, 0.0, 0.6))
    gov.set_velocity(200, 0, 0, 0)  # stopped mid-ramp: brakes from where it is
    gov.flush()
    stop = trace.of_kind("governor")[-1]
    assert stop["applied"]["v_x"] == pytest.approx(0.2) and stop["ramp_ms"] == 200
    assert gov.come_to_rest(200) == 400


def late_ramp(t0: int, start, target, rates):
    """The ramp the governor starts at `t0` from `start` to `target`, at the limit."""
    shaper = Shaper(rates)
    shaper.target = start
    shaper.late(t0, target)
    return shaper.ramp


def test_ramp_milliseconds_are_whole_and_end_on_the_target() -> None:
    ramp = late_ramp(100, (0.0, 0.3, 0.0), (0.25, -0.05, 0.0105), (1.0, 1.0, 3.0))
    # the plane: the larger change (0.35 m/s at 1 m/s²) sets 350 ms for v_x and v_y together,
    # a straight line of velocities; the turn: 3.5 ms at 3 rad/s² take 4 whole ms
    assert ramp.steps == (350, 350, 4) and ramp.end == 450
    assert ramp.velocity(101)[1] == pytest.approx(0.3 - A / 1000)  # at the limit
    assert ramp.velocity(275)[:2] == pytest.approx((0.125, 0.125))
    assert ramp.velocity(103)[2] == pytest.approx(0.0105 * 3 / 4)
    assert ramp.velocity(104)[2] == 0.0105
    assert ramp.velocity(450) == ramp.target == ramp.velocity(9999)
    sums = ramp.sums(100, 500)
    assert sums == pytest.approx(tuple(sum(ramp.at(k)[i] for k in range(1, 401))
                                       for i in range(3)))
    # a change of at most a * 1 ms is no ramp: at once (on the grid the two are the same)
    shaper = Shaper((1.0, 1.0, 3.0))
    assert shaper.late(0, (0.001, 0.0, 0.003)) == {0: 1, 1: 1} and shaper.ramp is None


def test_the_planar_speed_stays_within_its_limit_during_ramps() -> None:
    """v_x and v_y ramp together: between two velocities within the limit, every velocity of
    the ramp is within it (independent axes would reach 0.54 m/s here)."""
    start, target = (0.355, 0.352, 0.0), (0.4999, -0.001, 0.0)
    ramp = late_ramp(0, start, target, (A, A, ALPHA))
    assert max(math.hypot(*ramp.at(k)[:2]) for k in range(ramp.end + 1)) <= 0.5


@pytest.mark.parametrize("robot", ["kinematic", "mujoco"])
def test_a_move_from_rest_keeps_its_distance(robot: str) -> None:
    result, trace, _ = run(moves("0.3, -0.1, 0, 0, 1500"), robot)
    assert result.time_ms == 1500
    assert result.pose.x == pytest.approx(0.45, abs=1e-6)
    assert result.pose.y == pytest.approx(-0.15, abs=1e-6)
    assert trace.of_kind("session_end")[0]["at_rest_ms"] == 1800
    # a move shorter than its ramp never reaches its speed: a * T² instead of v * T
    result, _, _ = run(moves("0.5, 0, 0, 0, 200"), robot)
    assert result.pose.x == pytest.approx(A * 0.2 ** 2, abs=1e-6)


def test_the_kinematic_robot_agrees_with_mujoco_on_ramps() -> None:
    text = moves("0.4, 0.1, 1.0, 0, 1500", "-0.2, 0.3, -0.8, 0, 700", "0, 0, 1.5, 100, 300")
    poses = {}
    for robot in ("kinematic", "mujoco"):
        result, trace, _ = run(text, robot)
        poses[robot] = result.pose
        assert {r for e in trace.of_kind("governor") for r in e["reasons"]} == \
            {"acceleration", "angular-acceleration"}
    k, m = poses["kinematic"], poses["mujoco"]
    assert math.hypot(k.x - m.x, k.y - m.y) < 1e-3 and abs(k.theta - m.theta) < 1e-3
    assert math.hypot(k.x, k.y) > 0.3 and k.theta > 1.0  # a real path


def test_a_session_that_ends_at_until_brakes_to_rest() -> None:
    result, trace, _ = run(moves("0.25, 0, 0, 0, 5000"), until=1000)
    assert result.outcome == "until" and result.time_ms == 1000
    last = trace.of_kind("governor")[-1]
    assert last["t"] == 1000 and last["commanded"] == STILL and last["ramp_ms"] == 250
    assert trace.of_kind("session_end")[0]["at_rest_ms"] == 1250
    assert result.pose.x == pytest.approx(0.25, abs=1e-9)  # 1 s of 0.25 m/s, from rest to rest


# ---------------------------------------------------------------------------------------------
# LEDs

# A blink through two instruction blocks: ON ms lit, OFF ms dark.
BLINK = """[blink]
[goal:g]
  [action]
    [b#on#blk_inst: MV() LD("1, 0, 0, 1, 0, {on}") AO()]
    [b##blk_inst: MV("0, 0, 0, 0, {off}") LD() AO()]
    [b##blk_jump: CND(! {{TRUE}}) TRJMP(on) FLSJMP()]
    [b##blk_terminus]
"""


def shown_onsets(events: list[dict]) -> list[int]:
    """When the LEDs came on, from the trace: what the led track's commands ask at the end of
    each millisecond, dark during every `led-flash` hold (from its `t` to its `until`)."""
    asked: dict[int, bool] = {}
    lit = False
    holds = []
    for e in events:
        if e["event"] == "cmd_start" and e["track"] == "led":
            c = e["command"]
            lit = c["turnas"] == 1 and any(c[k] > 0 for k in "rgb")
        elif e["event"] == "cmd_stop" and e["track"] == "led":
            lit = False
        elif e["event"] == "governor" and "led-flash" in e["reasons"]:
            holds.append((e["t"], e["until"]))
        asked[e["t"]] = lit
    end = max(asked)
    onsets, before, state = [], False, False
    for t in range(end + 1):
        state = asked.get(t, state)
        shown = state and not any(a <= t < b for a, b in holds)
        if shown and not before:
            onsets.append(t)
        before = shown
    return onsets


def most_in_a_second(onsets: list[int]) -> int:
    return max((sum(1 for o in onsets if t <= o < t + 1000) for t in onsets), default=0)


def test_a_ten_hertz_blink_flashes_at_most_three_times_a_second() -> None:
    text = BLINK.format(on=50, off=50)
    _, plain, _ = run(text, profile=None, until=3000)
    assert most_in_a_second(shown_onsets(plain.events)) == 10  # what the script asks
    _, trace, session = run(text, until=3000)
    onsets = shown_onsets(trace.events)
    assert onsets == [0, 100, 200, 1000, 1100, 1200, 2000, 2100, 2200, 3000]
    assert most_in_a_second(onsets) <= 3
    holds = [e for e in trace.of_kind("governor") if e["reasons"] == ["led-flash"]]
    assert holds[0]["t"] == 300 and holds[0]["until"] == 1000
    assert holds[0]["commanded"] == {"led": [1.0, 0.0, 0.0]} and holds[0]["applied"] == {
        "led": None}
    assert len(holds) == 21  # 300..900, 1300..1900, 2300..2900: each held onset is logged
    assert session.governor.led_shown == (1.0, 0.0, 0.0)  # 3000: allowed again
    # the timing of the script is untouched: the same blocks at the same times
    assert [e["t"] for e in trace.of_kind("block")] == [e["t"] for e in plain.of_kind("block")]


def test_a_held_onset_is_shown_when_the_window_frees() -> None:
    text = BLINK.format(on=200, off=100)  # 3.3 Hz: the fourth onset of a second is held
    robot = make_robot("mujoco")
    dark = robot.led_rgba()
    _, trace, _session = run(text, robot, until=999)
    (hold,) = [e for e in trace.of_kind("governor") if "led-flash" in e["reasons"]]
    assert (hold["t"], hold["until"]) == (900, 1000)
    assert robot.led_rgba() == dark  # 999: the script asks red, the LEDs are dark
    robot = make_robot("mujoco")
    _, trace, _ = run(text, robot, until=1000)
    assert robot.led_rgba() == (1.0, 0.0, 0.0, 1.0)  # woken at 1000, in the middle of a command
    _, trace, _ = run(text, until=4000)
    onsets = shown_onsets(trace.events)
    assert onsets[:6] == [0, 300, 600, 1000, 1300, 1600]
    assert most_in_a_second(onsets) == 3


def test_a_colour_change_while_lit_is_not_a_flash() -> None:
    leds = ", ".join(f'"{i % 2}, {(i + 1) % 2}, 0, 1, 0, 50"' for i in range(40))
    result, trace, _ = run(moves(leds=leds))
    assert result.time_ms == 2000 and not trace.of_kind("governor")


def test_a_script_within_all_limits_gets_no_governor_event() -> None:
    # creeping at a * 1 ms and alpha * 1 ms, LEDs blinking at 2 Hz, a sound
    text = moves("0.001, 0, 0.003, 0, 2000",
                 leds=", ".join(['"0, 1, 0, 1, 0, 250", "0, 0, 1, 1, 250, 250"'] * 4),
                 audio='"songs/hello.wav, 0, 1500"')
    for robot in ("kinematic", "mujoco"):
        result, trace, session = run(text, robot)
        assert result.outcome == "completed" and result.time_ms == 3000
        assert not trace.of_kind("governor") and session.governor.clamps == 0
        assert trace.of_kind("session_end")[0]["at_rest_ms"] == 3000


def test_the_interpreter_and_the_vm_write_the_same_governed_trace() -> None:
    text = BLINK.replace('MV()', 'MV("0.4, 0, 1, 0, 120")').format(on=50, off=60)
    texts = [run(text, until=2500, vm=vm)[1].text() for vm in (False, True)]
    assert texts[0] == texts[1] and '"led-flash"' in texts[0] and '"acceleration"' in texts[0]


def test_governor_events_follow_the_trace_schema() -> None:
    """Every clamp is a `governor` event of schemas/trace.schema.json, and the end says when
    the robot came to rest."""
    import jsonschema

    text = BLINK.replace('MV()', 'MV("10, 0, 50, 0, 120")').format(on=50, off=60)
    _, trace, _ = run(text, until=2500)
    reasons = {r for e in trace.of_kind("governor") for r in e["reasons"]}
    assert reasons == {"speed", "angular-speed", "acceleration", "angular-acceleration",
                       "led-flash"}
    gov, other = governed()
    gov.nearest = lambda t, pose: (0.1, 0.0)
    gov.set_velocity(0, 0.2, 0, 0)
    gov.flush()
    schema = json.loads(schema_path("trace.schema.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schema)
    for event in trace.events + other.events:
        validator.validate(event)
    assert "at_rest_ms" in trace.events[-1] and other.events[0]["reasons"] == ["human-distance"]


def test_the_cli_governs_the_kinematic_robot_on_request(tmp_path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    script = tmp_path / "m.script"
    script.write_text(moves("0.25, 0, 0, 0, 2000"), encoding="utf-8")
    out = tmp_path / "t.jsonl"
    for flag, expected in (("--governor", 2250), ("--no-governor", None)):
        result = CliRunner().invoke(cli, ["run", str(script), "--robot", "kinematic", flag,
                                          "--trace", str(out)], catch_exceptions=False)
        assert result.exit_code == 0, result.output
        events = [json.loads(line) for line in out.read_text(encoding="utf-8").splitlines()]
        assert events[-1]["time_ms"] == 2000 and events[-1].get("at_rest_ms") == expected
        assert events[-1]["pose"]["x"] == pytest.approx(0.5)
        assert bool([e for e in events if e["event"] == "governor"]) == (expected is not None)


# ---------------------------------------------------------------------------------------------
# The profile in the trace, the speaker's level


def test_a_governed_trace_starts_with_the_profile_it_keeps() -> None:
    profile = Profile(max_linear_speed=0.3, max_volume=0.5)
    _, trace, _ = run(moves("0.1, 0, 0, 0, 100"), profile=profile)
    start = trace.events[0]
    assert start["event"] == "session_start"
    assert start["profile"]["max_linear_speed"] == 0.3
    assert start["profile"] == profile.limits() and "source" not in start["profile"]
    _, ungoverned, _ = run(moves("0.1, 0, 0, 0, 100"), profile=None)
    assert "profile" not in ungoverned.events[0]


def test_the_speaker_plays_at_the_profiles_volume() -> None:
    """Audio commands carry no volume: the robot plays every track at one level, which the
    governor sets to the profile's maximum."""
    _, _, session = run(moves("0, 0, 0, 0, 100", audio='"songs/a.wav, 0, 100"'),
                        robot="mujoco", profile=Profile(max_volume=0.4))
    assert session.robot.volume == 0.4
    robot = make_robot("mujoco")
    assert robot.volume == 1.0  # without a governor: full volume


# ---------------------------------------------------------------------------------------------
# Ramps centred on the changes a block knows ahead (docs/robot.md, "Acceleration")


def test_a_block_with_room_is_ramped_around_its_changes_and_ends_where_the_script_does() -> None:
    """A turn left and back that waits 200 ms and leaves 200 ms after it: the ramps start half
    a ramp before each change, nothing is logged, and the robot faces where it started."""
    text = moves("0, 0, 0.8, 200, 1000", "0, 0, -0.8, 0, 1000", leds='"0, 0, 1, 1, 0, 2400"')
    for robot in ("kinematic", "mujoco"):
        result, trace, session = run(text, robot)
        assert result.pose.theta == pytest.approx(0.0, abs=1e-9)
        assert not trace.of_kind("governor") and session.governor.clamps == 0
        assert trace.of_kind("session_end")[0]["at_rest_ms"] == 2400
    gov, _ = governed()
    from scriptc.runtime.commands import Move

    gov.plan_block(0, [Move(0, 0, 0.8, 200, 1000), Move(0, 0, -0.8, 0, 1000)], 2400)
    gov.advance(400)
    # 0.8 rad/s at 3 rad/s²: 267 ms from 67 to 334, half-way at the change (200)
    assert gov.velocity_at(67)[2] == 0.0 and gov.velocity_at(68)[2] == pytest.approx(0.8 / 267)
    assert gov.velocity_at(200)[2] == pytest.approx(0.8 * 133 / 267)
    assert gov.velocity_at(334)[2] == 0.8


def test_a_hold_before_a_planned_ramp_keeps_the_robot_still() -> None:
    """The operator freezes the block during the wait before a move, after its centred ramp has
    begun: the plan is dropped, the robot ramps back at once, and the move, when the block
    resumes, is ramped late (and logged)."""
    from scriptc.runtime.scenario import scenario_from_data

    text = moves("0.25, 0, 0, 1000, 1000", leds='"0, 0, 1, 1, 0, 3000"')
    scenario = scenario_from_data({"operator": [
        {"at": 0, "command": "safety_lock", "held": True},
        {"at": 900, "command": "interrupt", "on": True},
        {"at": 3000, "command": "interrupt", "on": False}]})
    analysis = analysis_of(text)
    trace = Trace()
    session = Session([IRProgram(analysis.script, "t.script")], scenario=scenario, trace=trace,
                      profile=DEFAULT_PROFILE)
    result = session.run()
    back, start, stop = trace.of_kind("governor")
    # the centred ramp (251 ms) began at 875: 25 ms later it is at 0.025 m/s, and comes back
    assert back["t"] == 900 and back["applied"]["v_x"] == pytest.approx(0.25 * 25 / 251)
    assert back["target"] == STILL and back["ramp_ms"] == 25
    assert (start["t"], stop["t"]) == (3100, 4100) and start["ramp_ms"] == 250
    assert result.time_ms == 5100  # the block's clock stopped for 2.1 s
    # 0.25 m from rest to rest, and the 50 ms it moved before the freeze: 0.6 mm
    assert 0.2505 < result.pose.x < 0.2507


def test_a_child_in_the_way_of_a_planned_ramp_holds_it() -> None:
    gov, trace = governed()
    from scriptc.runtime.commands import Move

    gov.nearest = lambda t, pose: (0.3, 0.0)  # a child 30 cm straight ahead
    gov.plan_block(0, [Move(0.25, 0, 0, 1000, 1000)], 3000)
    gov.advance(950)  # the centred ramp would have started at 875
    assert gov.velocity_at(950) == (0.0, 0.0, 0.0) and gov.pose().x == 0.0
    gov.set_velocity(1000, 0.25, 0, 0)
    gov.flush()
    assert gov.target == (0.0, 0.0, 0.0)
    assert trace.of_kind("governor")[-1]["reasons"] == ["human-distance"]


def test_a_run_cut_while_a_centred_ramp_anticipates_its_change_brakes() -> None:
    text = moves("0.25, 0, 0, 1000, 1000", leds='"0, 0, 1, 1, 0, 3000"')
    _result, trace, _ = run(text, until=950)  # the ramp began at 875 toward 0.25 m/s
    (stop,) = trace.of_kind("governor")
    assert stop["t"] == 950 and stop["commanded"] == STILL and stop["ramp_ms"] == 75
    assert trace.of_kind("session_end")[0]["at_rest_ms"] == 1025


def test_a_child_who_comes_while_a_centred_ramp_anticipates_its_change_stops_it() -> None:
    """The ramp toward a move that starts at 1000 ms begins at 875 with nobody around; a
    reading at 950 sees a child 30 cm ahead: the plan is dropped and the robot ramps back at
    once, before the command it was anticipating."""
    gov, trace = governed()
    from scriptc.runtime.commands import Move

    gov.plan_block(0, [Move(0.25, 0, 0, 1000, 1000)], 3000)
    gov.advance(950)
    assert gov.velocity_at(950)[0] == pytest.approx(0.25 * 75 / 251)
    gov.nearest = lambda t, pose: (0.3, 0.0)
    gov.recheck(950)
    gov.flush()
    assert gov.target == (0.0, 0.0, 0.0)
    (event,) = trace.of_kind("governor")
    assert event["t"] == 950 and event["reasons"] == ["acceleration"]
