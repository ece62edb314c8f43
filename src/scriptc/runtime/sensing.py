"""Simulated sensing: people, objects and obstacles placed in the world by the scenario file
(`entities`: a position in metres in the world frame, an optional straight-line velocity), and
the sensor that reports them to the map as the thesis's perception did (thesis 4.5): a
MapUpdate `poses` of `positionrho` (m) and `positiontheta` (rad, in the robot's frame,
counter-clockwise from its front, in (-π, π]) for each entity, relative to where the physics
put the robot, at the sensor rate (`sensing.rate_hz`, default 10 Hz, readings from 0 ms; an
entity is reported from the first reading at or after its `from`). So conditions react to
what the physics does: "drive toward the child until closer than 0.5 m" stops where the robot
really is.

The session schedules one sensing event per period; each advances the robot to that
millisecond, reads its pose and posts the updates (policy `R`: a reading replaces the older
one not yet processed). Periods are whole milliseconds (1000 / rate, rounded down, at least 1).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from scriptc.runtime.robots import Pose
from scriptc.runtime.world import Record


@dataclass(frozen=True, slots=True)
class PlacedEntity:
    """A person, object or obstacle placed in the simulated world."""

    objectid: str
    x: float
    y: float
    v_x: float = 0.0
    v_y: float = 0.0
    start: int = 0  # ms: when it appears
    stop: int | None = None  # ms: when it stops moving

    @classmethod
    def from_data(cls, item: Record) -> PlacedEntity:
        """An entity of a scenario's `entities` (checked by the scenario's schema)."""
        return cls(item["objectid"], float(item["x"]), float(item["y"]),
                   float(item.get("v_x", 0.0)), float(item.get("v_y", 0.0)),
                   int(item.get("from", 0)), item.get("until"))

    @property
    def cls(self) -> str:
        return self.objectid.partition("/")[0]

    def position(self, t_ms: int) -> tuple[float, float]:
        """World position at `t_ms` (it moves from `start` to `stop`)."""
        end = t_ms if self.stop is None else min(t_ms, self.stop)
        dt = max(0, end - self.start) / 1000.0
        return self.x + self.v_x * dt, self.y + self.v_y * dt


def relative(pose: Pose, x: float, y: float) -> tuple[float, float]:
    """(rho, theta) of the world point (x, y) seen from the robot: distance and bearing in
    the body frame, the bearing wrapped to (-π, π]."""
    dx, dy = x - pose.x, y - pose.y
    rho = math.hypot(dx, dy)
    theta = math.atan2(dy, dx) - pose.theta
    theta = math.atan2(math.sin(theta), math.cos(theta))
    return rho, theta


class Sensing:
    """The simulated sensor over a scenario's placed entities."""

    def __init__(self, entities: Iterable[PlacedEntity], rate_hz: float = 10.0,
                 max_range: float | None = None) -> None:
        self.entities = list(entities)
        self.period = max(1, int(1000 // rate_hz))
        self.max_range = max_range
        self.readings = 0

    def read(self, t_ms: int, pose: Pose) -> list[tuple[str, float, float]]:
        """(objectid, rho, theta) of every entity present and in range at `t_ms`."""
        out = []
        for entity in self.entities:
            if t_ms < entity.start:
                continue
            rho, theta = relative(pose, *entity.position(t_ms))
            if self.max_range is not None and rho > self.max_range:
                continue
            out.append((entity.objectid, rho, theta))
        self.readings += 1
        return out

    def nearest_human(self, t_ms: int, pose: Pose) -> tuple[float, float] | None:
        """(distance, bearing) of the nearest Human present (for the governor)."""
        best: tuple[float, float] | None = None
        for entity in self.entities:
            if entity.cls != "Human" or t_ms < entity.start:
                continue
            rho, theta = relative(pose, *entity.position(t_ms))
            if best is None or rho < best[0]:
                best = (rho, theta)
        return best
