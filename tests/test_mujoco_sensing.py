"""Simulated sensing (runtime/sensing.py) and the scenario's placed entities."""

from __future__ import annotations

import math

import pytest

from scriptc.runtime.robots import Pose
from scriptc.runtime.scenario import ScenarioError, scenario_from_data
from scriptc.runtime.sensing import PlacedEntity, Sensing, relative


def test_relative_positions_are_in_the_body_frame() -> None:
    assert relative(Pose(0, 0, 0), 2, 0) == (2.0, 0.0)
    rho, theta = relative(Pose(1, 1, math.pi / 2), 1, 3)
    assert rho == pytest.approx(2) and theta == pytest.approx(0)
    rho, theta = relative(Pose(0, 0, 4 * math.pi), -1, 0)  # unwrapped heading, wrapped bearing
    assert rho == pytest.approx(1) and abs(theta) == pytest.approx(math.pi)


def test_entities_move_in_a_straight_line_between_from_and_until() -> None:
    e = PlacedEntity("Human/kid", 1.0, 0.0, v_x=0.5, start=1000, stop=3000)
    assert e.position(0) == (1.0, 0.0) and e.position(2000) == (1.5, 0.0)
    assert e.position(9000) == (2.0, 0.0)


def test_readings_respect_from_range_and_rate() -> None:
    near = PlacedEntity("Human/a", 1.0, 0.0)
    far = PlacedEntity("Object/b", 10.0, 0.0)
    late = PlacedEntity("Obstacle/c", 0.0, 2.0, start=500)
    sensing = Sensing([near, far, late], rate_hz=4, max_range=5.0)
    assert sensing.period == 250
    assert [r[0] for r in sensing.read(0, Pose(0, 0, 0))] == ["Human/a"]
    assert [r[0] for r in sensing.read(500, Pose(0, 0, 0))] == ["Human/a", "Obstacle/c"]
    assert sensing.nearest_human(0, Pose(0.5, 0, 0)) == (0.5, 0.0)


def test_the_scenario_schema_checks_entities() -> None:
    scenario = scenario_from_data({"entities": [{"objectid": "Human/kid", "x": 1, "y": 2,
                                                 "v_y": -0.1, "from": 100}],
                                   "sensing": {"rate_hz": 20, "range": 4}})
    assert scenario.entities == [PlacedEntity("Human/kid", 1.0, 2.0, 0.0, -0.1, 100)]
    assert scenario.sensing_rate_hz == 20 and scenario.sensing_range == 4
    with pytest.raises(ScenarioError) as info:
        scenario_from_data({"entities": [{"objectid": "Robot/x", "x": 1, "y": 2, "z": 0}],
                            "sensing": {"rate_hz": 0}})
    text = "; ".join(info.value.problems)
    assert "entities[0].objectid" in text and "entities[0]" in text and "rate_hz" in text
