"""The governor's centred ramps and K003 (scriptc/robot/motion.py, check/ramps.py; docs/robot.md
"Acceleration"): a ramp centred on a change covers exactly the step's distance on the 1 ms
grid; a block's motions whose ramps fit are centred, the others late; and the law of K003: for
random blocks within the profile, the governed run ends where the ideal robot does wherever
K003 says nothing, and differs by what K003 says where it warns."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from scriptc.analysis.analyze import analyze_bytes
from scriptc.robot.motion import (
    REST,
    Kinematics,
    Ramp,
    Shaper,
    centred_bound,
    centred_ms,
    limit_ms,
    limit_speed,
    rates_of,
    run_block,
    track_steps,
)
from scriptc.robot.profile import DEFAULT_PROFILE, Profile
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace

RATES = rates_of(DEFAULT_PROFILE)
TOLERANCE_M, TOLERANCE_RAD = 0.01, math.radians(1.0)
SLOW = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def steps_of(*moves, profile: Profile = DEFAULT_PROFILE):
    return [(t, limit_speed(v, profile)[0]) for t, v in track_steps(moves)]


# ---------------------------------------------------------------------------------------------
# A centred ramp on the grid


@pytest.mark.slow
@given(st.floats(-1.6, 1.6), st.floats(-1.6, 1.6), st.sampled_from([0.3, 1.0, 2.0, 3.0]),
       st.integers(0, 5000))
def test_a_centred_ramp_covers_the_distance_of_the_step(v0: float, v1: float, rate: float,
                                                       edge: int) -> None:
    """m ms (odd, the limit's or one more) from (m - 1) / 2 before the change: the sum of its
    milliseconds is the step's, and no millisecond changes faster than the limit."""
    assume(v0 != v1)
    m = centred_ms(limit_ms([v0], [v1], [rate]))
    assert m % 2 == 1
    start = edge - (m - 1) // 2
    ramp = Ramp((start, start, start), (0.0, 0.0, v0), (0.0, 0.0, v1), (0, 0, m))
    lo, hi = start - 3, start + m + 3
    step = sum(v0 if t <= edge else v1 for t in range(lo + 1, hi + 1))  # ms ending at t
    assert ramp.sums(lo, hi)[2] == pytest.approx(step, rel=1e-9, abs=1e-12)
    assert abs(ramp.step[2]) * 1000 <= rate * (1 + 1e-9)


def test_ramp_sums_agree_with_the_milliseconds() -> None:
    ramp = Ramp((10, 10, 40), (0.0, 0.3, 1.0), (0.25, -0.05, -0.5), (350, 350, 7))
    for a, b in ((0, 500), (5, 45), (41, 46), (300, 361), (359, 420)):
        assert ramp.sums(a, b) == pytest.approx(
            tuple(sum(ramp.velocity(t)[i] for t in range(a + 1, b + 1)) for i in range(3)))
    assert ramp.breaks(0, 500) == [10, 40, 47, 360, 500] and ramp.end == 360


# ---------------------------------------------------------------------------------------------
# Plans


def test_a_motion_with_room_in_its_block_is_centred() -> None:
    shaper = Shaper(RATES)
    motions = shaper.plan(1000, 2400, steps_of(((0, 0, 0.8), 200, 1000),
                                               ((0, 0, -0.8), 0, 1000)), (0.0, 0.0, 0.0))
    (motion,) = motions
    assert motion.centred and motion.group == 1 and motion.late_because is None
    # 0.8 rad/s at 3 rad/s²: 267 ms; the reversal 534, one more to be odd: 535
    assert [(p.at, p.steps, p.due) for p in shaper.planned] == [
        (1200 - 133, 267, 1200), (2200 - 267, 535, 2200), (3200 - 133, 267, 3200)]


@pytest.mark.parametrize("moves, length, why", [
    ((((0, 0, 0.8), 0, 1000), ((0, 0, -0.8), 0, 1000)), 2000, "start"),  # at the block's start
    ((((0, 0, 0.8), 200, 1000), ((0, 0, -0.8), 0, 1000)), 2200, "end"),  # stops as it ends
    ((((0.5, 0, 0), 300, 200),), 1000, "overlap"),  # shorter than its ramps
])
def test_a_motion_whose_ramps_do_not_fit_is_late(moves, length: int, why: str) -> None:
    shaper = Shaper(RATES)
    (motion,) = shaper.plan(0, length, steps_of(*moves), (0.0, 0.0, 0.0))
    assert not motion.centred and motion.late_because == why and not shaper.planned


def test_a_block_entered_moving_or_braking_is_not_centred() -> None:
    shaper = Shaper(RATES)
    shaper.late(0, (0.2, 0.0, 0.0))  # 200 ms ramp up
    (motion,) = shaper.plan(1000, 2000, steps_of(((-0.2, 0, 0), 0, 1000)), (0.2, 0.0, 0.0))
    assert motion.late_because == "entered"
    shaper = Shaper(RATES)
    shaper.late(0, (0.2, 0.0, 0.0))
    shaper.late(1000, (0.0, 0.0, 0.0))  # braking until 1200
    (motion,) = shaper.plan(1000, 2000, steps_of(((0.2, 0, 0), 150, 500)), (0.0, 0.0, 0.0))
    assert motion.late_because == "start"  # its ramp would start at 1050, still braking
    (motion,) = shaper.plan(1000, 2000, steps_of(((0.2, 0, 0), 300, 500)), (0.0, 0.0, 0.0))
    assert motion.centred  # from 1200 on: at rest


def test_the_example_of_the_issue_ends_where_it_started_once_it_has_room() -> None:
    """Imitation's "turn left and back" (issue 12): late, it ends 0.214 rad to the left; with
    200 ms before and after, its ramps are centred and it ends where it started."""
    late = run_block(REST, steps_of(((0, 0, 0.8), 0, 1000), ((0, 0, -0.8), 0, 1000)), 2000,
                     RATES)
    assert late.error[2] == pytest.approx(0.2136, abs=1e-4)
    room = run_block(REST, steps_of(((0, 0, 0.8), 200, 1000), ((0, 0, -0.8), 0, 1000)), 2400,
                     RATES)
    assert room.error == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)


# ---------------------------------------------------------------------------------------------
# The law of K003


def moves_text(moves, length: int) -> str:
    mv = ", ".join(f'"{vx}, {vy}, {w}, {wait}, {dur}"' for vx, vy, w, wait, dur in moves)
    return ("[k]\n[goal:g]\n[action]\n"
            f'[b##blk_inst: MV({mv}) LD("0, 0, 1, 1, 0, {length}") AO()]\n[b##blk_terminus]\n')


@st.composite
def moves_within_the_profile(draw, turning: bool = True):
    """A move track within the default profile's speeds (0.5 m/s, 1.5 rad/s)."""
    moves = []
    for _ in range(draw(st.integers(1, 3))):
        speed = draw(st.sampled_from([0, 0.05, 0.1, 0.2, 0.3, 0.49]))
        angle = draw(st.sampled_from([0, 0.5, 1.5, 3.14, -1.2]))
        w = draw(st.sampled_from([0, 0.3, -0.8, 1.5])) if turning else 0
        moves.append((round(speed * math.cos(angle), 3), round(speed * math.sin(angle), 3), w,
                      draw(st.sampled_from([0, 0, 50, 150, 300, 600])),
                      draw(st.sampled_from([0, 100, 250, 700, 1500]))))
    return moves


def governed_and_ideal(text: str):
    analysis = analyze_bytes("k.script", text.encode("utf-8"), "script")
    assert not [d for d in analysis.diagnostics if d.code == "K001"]
    poses = []
    for profile in (DEFAULT_PROFILE, None):
        session = Session([IRProgram(analysis.script, "k.script")], trace=Trace(False),
                          profile=profile)
        poses.append(session.run().pose)
    (g, i) = poses
    return analysis, (g.x - i.x, g.y - i.y, g.theta - i.theta)


def said(message: str) -> tuple[float, float]:
    """The position (m) and heading (rad) K003's message gives (0 for what it leaves out)."""
    cm = re.search(r"(\d+\.\d) cm", message)
    m = re.search(r"(\d+\.\d\d) m ", message)
    rad = re.search(r"\((\d+\.\d{3}) rad\)", message)
    position = float(cm.group(1)) / 100 if cm else float(m.group(1)) if m else 0.0
    return position, float(rad.group(1)) if rad else 0.0


@pytest.mark.slow
@SLOW
@given(moves_within_the_profile(), st.sampled_from([0, 0, 100, 200, 600]))
def test_k003_says_where_the_governed_robot_ends(moves, tail: int) -> None:
    length = sum(wait + dur for *_, wait, dur in moves) + tail
    assume(length > 0)
    analysis, error = governed_and_ideal(moves_text(moves, length))
    position, heading = math.hypot(error[0], error[1]), abs(error[2])
    # (what the check integrates by quadrature may round across a tolerance)
    assume(abs(position - TOLERANCE_M) > 1e-6 and abs(heading - TOLERANCE_RAD) > 1e-6)
    warned = [d for d in analysis.diagnostics if d.code == "K003"]
    if position < TOLERANCE_M and heading < TOLERANCE_RAD:
        assert not warned, (moves, error)
    else:
        (k003,) = warned
        p, h = said(k003.message)
        if position >= TOLERANCE_M:
            assert p == pytest.approx(position, abs=0.0006 if position < 1 else 0.006)
        if heading >= TOLERANCE_RAD:
            assert h == pytest.approx(heading, abs=0.0006)


@pytest.mark.slow
@SLOW
@given(moves_within_the_profile(turning=False), moves_within_the_profile(turning=False),
       st.sampled_from([0, 0, 300]))
def test_two_blocks_without_k003_end_where_the_ideal_robot_does(first, second, tail) -> None:
    """Moves on into the next block, a change at its start from the velocity the first leaves,
    the next block's ramps spoilt by the braking of the first: where K003 says nothing, the
    run ends within its tolerance of each block's pose (in a straight line: the blocks' errors
    add up)."""
    lengths = [sum(wait + dur for *_, wait, dur in moves) for moves in (first, second)]
    assume(all(lengths))
    blocks = ["[b##blk_inst: MV("
              + ", ".join(f'"{vx}, {vy}, {w}, {wt}, {d}"' for vx, vy, w, wt, d in moves)
              + ") LD() AO()]"
              for moves in (first, second)]
    text = ("[k]\n[goal:g]\n[action]\n" + "\n".join(blocks) +
            f'\n[b##blk_inst: MV() LD("0, 0, 1, 1, 0, {tail + 1}") AO()]\n[b##blk_terminus]\n')
    analysis, error = governed_and_ideal(text)
    if not [d for d in analysis.diagnostics if d.code == "K003"]:
        assert math.hypot(error[0], error[1]) < 2 * TOLERANCE_M + 1e-6, (first, second, error)
        assert error[2] == pytest.approx(0.0, abs=1e-9)


def test_k003_follows_the_repositorys_profile() -> None:
    text = moves_text([(0, 0, 0.8, 0, 1000), (0, 0, -0.8, 0, 1000)], 2000)
    for profile, expected in ((DEFAULT_PROFILE, 1), (Profile(max_angular_acceleration=100.0,
                                                             source="scriptc.toml"), 0)):
        analysis = analyze_bytes("k.script", text.encode("utf-8"), "script", profile=profile)
        assert len([d for d in analysis.diagnostics if d.code == "K003"]) == expected
    slow = Profile(max_angular_acceleration=1.0, source="scriptc.toml")
    analysis = analyze_bytes("k.script", text.encode("utf-8"), "script", profile=slow)
    (k003,) = analysis.diagnostics
    run = Session([IRProgram(analysis.script, "k.script")], profile=slow).run()
    assert said(k003.message)[1] == pytest.approx(run.pose.theta, abs=5e-4)  # 0.760 rad
    assert any("(from scriptc.toml)" in n for n in k003.notes)
    # 0.8 rad/s at 1 rad/s²: a centred ramp of 801 ms, 400 of them before the change
    assert "start it at least 400 ms into the block" in k003.help


def test_a_turn_while_moving_is_checked_in_the_world_frame() -> None:
    """An arc from the block's start to its end: each axis, ramped late, keeps its distance,
    but the turn's ramp (500 ms) and the plane's (300 ms) do not lag alike: the arc is drawn
    turned, 6 cm away. The same arc with room for its ramps ends within a millimetre."""
    late = run_block(REST, steps_of(((0.3, 0, 1.5), 0, 2000)), 2000, RATES)
    assert math.hypot(late.error[0], late.error[1]) == pytest.approx(0.0588, abs=2e-4)
    assert late.error[2] == pytest.approx(0.0, abs=1e-12)
    room = run_block(REST, steps_of(((0.3, 0, 1.0), 300, 2000)), 2600, RATES)
    assert math.hypot(room.error[0], room.error[1]) < 1e-3


def test_the_kinematics_follow_a_ramp_per_millisecond_or_by_quadrature() -> None:
    """The runtime integrates each millisecond of a ramp that turns while it moves; the check
    integrates the stretch by quadrature instead (`exact=False`): the same pose within a
    micrometre, the same heading."""
    shaper = Shaper(RATES)
    shaper.late(0, (0.4, 0.1, 1.2))
    ramp = shaper.ramp
    poses = []
    for exact in (True, False):
        robot = Kinematics(exact=exact)
        robot.set_velocity(0, 0.4, 0.1, 1.2, ramp=ramp)
        robot.advance(1500)
        poses.append(robot.pose())
    exact, fast = poses
    assert 0 < math.hypot(exact.x - fast.x, exact.y - fast.y) < 1e-6
    assert exact.theta == pytest.approx(fast.theta, abs=1e-12)
    assert math.hypot(exact.x, exact.y) > 0.3  # a real path


@st.composite
def moves_with_room(draw):
    """A move track whose motions all have room for centred ramps: each move waits and lasts
    at least 600 ms (ramps within the profile's speeds take at most 501 and 1001 ms)."""
    moves = []
    for _ in range(draw(st.integers(1, 3))):
        speed = draw(st.sampled_from([0, 0.1, 0.3, 0.49]))
        angle = draw(st.sampled_from([0, 0.7, -2.0]))
        moves.append(((round(speed * math.cos(angle), 3), round(speed * math.sin(angle), 3),
                       draw(st.sampled_from([0, 0.4, -1.0, 1.5]))),
                      draw(st.integers(6, 12)) * 100, draw(st.integers(6, 20)) * 100))
    return moves


@SLOW
@given(moves_with_room())
def test_the_bound_of_centred_ramps_holds(moves) -> None:
    """What K003 uses to skip a block (`centred_bound`): the robot ends within the bound of the
    script's position, facing its heading."""
    steps = steps_of(*moves)
    length = sum(wait + dur for _, wait, dur in moves) + 600
    found = centred_bound(steps, length, RATES)
    run = run_block(REST, steps, length, RATES)
    if found is None:
        assert not all(m.centred for m in run.motions)
        return
    motions, bound = found
    assert all(m.centred for m in motions) and run.exit == REST
    assert math.hypot(run.error[0], run.error[1]) <= bound + 1e-6
    assert run.error[2] == pytest.approx(0.0, abs=1e-12)


@st.composite
def flows(draw) -> str:
    """A script of instruction blocks that take time and that take none, sensor blocks, jumps
    (constant or not, to any block or on) and termini."""
    n = draw(st.integers(1, 8))
    lines = ["[flow]", "[goal:g]", "[action]"]
    for k in range(n):
        kind = draw(st.sampled_from("iizsjjt"))
        label = f"b{k}"
        if kind == "i":
            lines.append(f'[b#{label}#blk_inst: MV() LD("1, 0, 0, 1, 0, 100") AO()]')
        elif kind == "z":
            lines.append(f"[b#{label}#blk_inst: MV() LD() AO()]")
        elif kind == "s":
            lines.append(f"[b#{label}#blk_sens]")
        elif kind == "t":
            lines.append(f"[b#{label}#blk_terminus]")
        else:
            true, false = (draw(st.sampled_from(["", *(f"b{m}" for m in range(n))]))
                           for _ in range(2))
            condition = draw(st.sampled_from(["{TRUE}", "! {E: gt(@x, 1)}"]))
            lines.append(f"[b#{label}#blk_jump: CND({condition}) TRJMP({true}) "
                         f"FLSJMP({false})]")
    return "\n".join(lines) + "\n"


@given(flows())
def test_the_next_blocks_that_take_time_are_those_the_search_finds(text: str) -> None:
    """`ramps.NextTimed.after` answers the common cases without a search: what it finds is
    what `flow.next_timed` finds from the block's successors, for every block."""
    from scriptc.check.context import Context
    from scriptc.check.flow import next_timed, successors
    from scriptc.check.ramps import NextTimed
    from scriptc.frontend.script import lower_script
    from scriptc.source import SourceFile

    source = SourceFile("flow.script", text)
    script, _ = lower_script(source)
    assert script is not None
    ctx = Context(script, source)
    flow = NextTimed(ctx)
    succ = successors(ctx)[0]
    timed = [d != 0 for d in ctx.durations]
    for i in range(len(ctx.blocks)):
        assert flow.after(i) == next_timed(ctx.blocks, succ, timed, succ[i], 256), i
