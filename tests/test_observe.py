"""Observing a run's state at given milliseconds (docs/runtime.md, "Observing a run"), what a
test's `at` reads: observing changes nothing of the run (the robot is looked ahead through a
ghost of itself), and what is observed at t is the state a run stopped at t ends in."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.ops.programs import load_programs
from scriptc.runtime.loop import RunResult
from scriptc.runtime.scenario import load_scenario
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
# Examples that move, light and play, each with its world; the approach is governed by
# default on MuJoCo and ramps its steps.
NAMES = ("approach", "greeting", "reward_dance", "turn_taking")


@cache
def _programs(name: str) -> tuple:
    loaded = load_programs([str(EXAMPLES / f"{name}.script")])
    assert loaded.ok
    return tuple(loaded.programs), loaded.setup.profile


def _run(name: str, until: int, observe=(), *, robot: str = "kinematic",
         governed: bool = False) -> tuple[RunResult, str]:
    programs, profile = _programs(name)
    trace = Trace()
    session = Session(programs, scenario=load_scenario(str(EXAMPLES / f"{name}.world.json")),
                      robot=robot, trace=trace, profile=profile if governed else None)
    result = session.run(until, observe)
    return result, trace.text()


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(NAMES), st.booleans(),
       st.lists(st.integers(0, 30_000), max_size=40))
def test_observing_changes_nothing(name: str, governed: bool, instants: list[int]) -> None:
    """The same trace, byte for byte, and the same end, observed or not: a kinematic robot
    advanced to an observed millisecond would cut its arcs (and a governed ramp) there and
    round differently."""
    plain, plain_trace = _run(name, 30_000, governed=governed)
    observed, observed_trace = _run(name, 30_000, instants, governed=governed)
    assert observed_trace == plain_trace
    assert observed.pose == plain.pose and observed.time_ms == plain.time_ms
    reached = sorted({t for t in instants if t <= plain.time_ms})
    assert [state.t for state in observed.observations] == reached


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(NAMES), st.integers(0, 30_000))
def test_an_observation_is_where_a_run_stopped_there_ends(name: str, t: int) -> None:
    """Without the governor (no braking after the end), the state observed at t is the final
    state of the same run stopped at t by `until`, exactly."""
    observed, _ = _run(name, 30_000, [t])
    stopped, _ = _run(name, t)
    if stopped.outcome != "until":
        assert observed.observations == [] or observed.observations[0].t == stopped.time_ms
        return
    (state,) = observed.observations
    assert state == stopped.final


def test_the_state_says_what_runs_at_the_instant() -> None:
    """The greeting's child comes within 1.5 m at 3 s: the hello block runs, green, with its
    song, turning left; at 5.5 s the goodbye glows dim blue with nothing playing; after the
    end nothing runs and the LEDs are off."""
    result, _ = _run("greeting", 60_000, [3500, 5500, 59_000])
    hello, bye = result.observations
    assert (hello.block, hello.path, hello.script) == ("hello", "goal1/act0/blk0", "greeting")
    assert hello.led == (0.2, 0.8, 0.3) and hello.audio == "songs/hello.wav"
    assert hello.pose.theta == pytest.approx(0.175)
    assert (bye.block, bye.led, bye.audio) == ("bye", (0.1, 0.2, 0.4), None)
    assert result.final is not None and result.final.t == result.time_ms == 6000
    assert (result.final.block, result.final.led, result.final.audio) == (None, None, None)


@pytest.mark.slow
def test_observing_the_mujoco_robot_changes_nothing() -> None:
    """MuJoCo, governed: the ghost steps a copy of the physics (its own `MjData`)."""
    plain, plain_trace = _run("approach", 12_000, robot="mujoco", governed=True)
    observed, observed_trace = _run("approach", 12_000, range(0, 12_000, 333),
                                    robot="mujoco", governed=True)
    assert observed_trace == plain_trace and observed.pose == plain.pose
    moved = [s.pose.x for s in observed.observations]
    assert moved == sorted(moved) and moved[-1] > 0.1  # the approach steps forward
