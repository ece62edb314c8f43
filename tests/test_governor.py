"""The safety governor (runtime/governor.py) over the kinematic robot: clamps keep the
direction and the timing, and every clamp is in the trace."""

from __future__ import annotations

import math

import pytest

from scriptc.profile import DEFAULT_PROFILE, Profile
from scriptc.runtime.governor import Governor
from scriptc.runtime.robots.kinematic import KinematicRobot
from scriptc.runtime.trace import Trace


def governed(profile: Profile = DEFAULT_PROFILE):
    trace = Trace()
    return Governor(KinematicRobot(), profile, trace), trace


def test_a_fast_move_is_slowed_keeping_its_direction() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 3.0, 4.0, 0.0)  # 5 m/s toward (0.6, 0.8)
    gov.set_velocity(1000, 0, 0, 0)
    p = gov.pose()
    assert p.x == pytest.approx(0.3) and p.y == pytest.approx(0.4)
    [event] = trace.of_kind("governor")
    assert event["t"] == 0 and event["reasons"] == ["speed"]
    assert event["commanded"] == {"v_x": 3.0, "v_y": 4.0, "v_theta": 0.0}
    assert math.hypot(event["applied"]["v_x"], event["applied"]["v_y"]) == pytest.approx(0.5)


def test_turning_is_clamped_with_its_sign() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0, 0, -50)
    gov.advance(1000)
    assert gov.pose().theta == pytest.approx(-DEFAULT_PROFILE.max_angular_speed)
    assert trace.of_kind("governor")[0]["reasons"] == ["angular-speed"]


def test_slow_commands_pass_untouched_and_unlogged() -> None:
    gov, trace = governed()
    gov.set_velocity(0, 0.2, -0.1, 0.4)
    assert gov.applied == (0.2, -0.1, 0.4) and gov.clamps == 0 and not trace.events


def test_humans_closer_than_the_minimum_stop_translation_toward_them() -> None:
    gov, trace = governed()
    gov.nearest = lambda t, pose: (0.3, 0.0)  # a child 30 cm straight ahead
    gov.set_velocity(0, 0.2, 0, 0.5)
    assert gov.applied == (0.0, 0.0, 0.5)
    assert trace.of_kind("governor")[0]["reasons"] == ["human-distance"]
    gov.set_velocity(10, -0.2, 0, 0)  # backing away is allowed
    assert gov.applied == (-0.2, 0.0, 0.0)
    gov.nearest = lambda t, pose: (1.0, 0.0)
    gov.set_velocity(20, 0.2, 0, 0)
    assert gov.applied == (0.2, 0.0, 0.0)


def test_the_session_uses_the_governor_only_with_a_profile() -> None:
    from scriptc.driver import analyze_bytes
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.session import Session

    text = '[m]\n[goal:g]\n[action]\n[b##blk_inst: MV("2, 0, 0, 0, 1000") LD() AO()]\n' \
           '[b##blk_terminus]\n'
    analysis = analyze_bytes("m.script", text.encode(), "script")
    plain = Session([IRProgram(analysis.script, "m.script")]).run()
    assert plain.pose.x == pytest.approx(2.0)
    governed_run = Session([IRProgram(analysis.script, "m.script")],
                           profile=DEFAULT_PROFILE).run()
    assert governed_run.pose.x == pytest.approx(0.5) and governed_run.time_ms == 1000


def test_governor_events_follow_the_trace_schema() -> None:
    """Every clamp is a `governor` event of schemas/trace.schema.json."""
    import json

    import jsonschema

    from scriptc.resources import schema_path

    trace = Trace()
    governor = Governor(KinematicRobot(), DEFAULT_PROFILE, trace)
    governor.set_velocity(0, 10.0, 0.0, 50.0)
    governor.advance(1000)
    events = trace.of_kind("governor")
    assert events and events[0]["reasons"] == ["speed", "angular-speed"]
    schema = json.loads(schema_path("trace.schema.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schema)
    for event in events:
        validator.validate(event)
