"""Robot backends: what turns the actuators' velocity commands into a pose.

A backend implements `Robot`: `set_velocity(t_ms, v_x, v_y, v_theta, rates=None)` (body-frame
speeds from `t_ms` on, m/s and rad/s), `advance(t_ms)` (bring the simulation up to `t_ms`) and
`pose()` (world frame: metres and radians, starting at the origin facing +x; `theta` is not
wrapped, so a full turn reads 2π). Times only grow; the session calls `set_velocity` only when
the effective velocity changes, so a backend sees O(events) calls, never one per millisecond.

Without `rates` the velocity changes at once. With `rates` (the safety governor's accelerations
per axis: m/s², m/s², rad/s²) each axis goes from the velocity the robot has at `t_ms` to its
target in a linear ramp on the 1 ms grid, as `Ramp` defines it: both backends follow the same
`Ramp`, so the governor knows at every millisecond what velocity the robot has.

Backends by name (`--robot NAME`): `mujoco` (the physics of the Teo/Oimi model, `mujoco.py`,
the default of `scriptc run`; docs/robot.md) and `kinematic` (exact integration,
`kinematic.py`). Only `mujoco.py` imports mujoco, and only when that backend is made.
"""

from __future__ import annotations

import importlib
import math
from typing import NamedTuple, Protocol


class Pose(NamedTuple):
    x: float
    y: float
    theta: float

    def as_dict(self) -> dict:
        return {"x": self.x, "y": self.y, "theta": self.theta}


class Robot(Protocol):
    name: str

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     rates: tuple[float, float, float] | None = None) -> None: ...

    def advance(self, t_ms: int) -> None: ...

    def pose(self) -> Pose: ...


Velocity = tuple[float, float, float]


class Ramp:
    """A rate-limited change of velocity on the 1 ms grid (docs/robot.md, "Acceleration").

    From `start` at `t0` the velocity goes linearly to `target`, no axis faster than its rate
    (per second): v_theta over `ceil(|Δ| / rate)` whole milliseconds, v_x and v_y together
    over the whole milliseconds the larger of their two changes needs (so the planar velocity
    moves on a straight line and its speed never exceeds the larger of the two ends: the
    governor's speed limit holds during the ramp too). During the k-th millisecond after `t0`
    (k = 1, 2, ...) an axis has `start + k * step`, reaching its target exactly at its
    `steps`-th; it keeps it after. Velocities are constant within a millisecond (the value
    reached at its end: MuJoCo's integrator actuators with `actearly`), so a ramp from rest to
    v at a has velocity a*t at every whole t of the ramp when v/a is whole milliseconds, and a
    ramp down gives back what the ramp up lost: a move from rest to rest goes v*T per axis,
    exactly. `velocity(t)` is the velocity reached at the whole millisecond t."""

    __slots__ = ("t0", "start", "target", "step", "steps", "end")

    GROUPS = ((0, 1), (2,))  # axes that ramp together: the plane, the turn

    def __init__(self, t0: int, start: Velocity, target: Velocity,
                 rates: tuple[float, float, float]) -> None:
        self.t0 = t0
        self.start = start
        self.target = target
        need = []
        for v0, v1, rate in zip(start, target, rates):
            d = abs(v1 - v0)
            if d == 0.0:
                need.append(0)
            elif not 0.0 < rate < math.inf:
                need.append(1)  # no limit on this axis: the change takes one millisecond
            else:
                # 1e-9: a change of exactly k ms at the rate is k steps, not k + 1
                need.append(max(1, math.ceil(d / (rate / 1000.0) - 1e-9)))
        steps = [0, 0, 0]
        step = [0.0, 0.0, 0.0]
        for group in self.GROUPS:
            n = max(need[i] for i in group)
            for i in group:
                if need[i]:
                    steps[i] = n
                    step[i] = (target[i] - start[i]) / n
        self.step = tuple(step)
        self.steps = tuple(steps)
        self.end = t0 + max(steps)  # the millisecond every axis is on its target

    @classmethod
    def between(cls, t0: int, start: Velocity, target: Velocity,
                rates: tuple[float, float, float] | None) -> Ramp | None:
        """The ramp, or None when the change takes at most one millisecond (no ramp: within
        the step, a change at once and a ramp are the same thing on the grid)."""
        if rates is None:
            return None
        ramp = cls(t0, start, target, rates)
        return ramp if ramp.end - t0 > 1 else None

    def at(self, k: int) -> Velocity:
        """The velocity during the k-th millisecond of the ramp (reached at its end)."""
        if k <= 0:
            return self.start
        return tuple(v1 if k >= n else v0 + k * s  # type: ignore[return-value]
                     for v0, v1, s, n in zip(self.start, self.target, self.step, self.steps))

    def velocity(self, t_ms: int) -> Velocity:
        return self.at(t_ms - self.t0)

    def totals(self, k1: int, k2: int) -> Velocity:
        """Per axis, the sum of the velocities of the milliseconds k1..k2 of the ramp (times
        1 ms: the distance covered, in the body frame, when the heading does not change)."""
        out = []
        for v0, v1, s, n in zip(self.start, self.target, self.step, self.steps):
            a, b = k1, min(k2, n - 1)
            total = 0.0
            if b >= a:
                total += (b - a + 1) * (v0 + s * (a + b) / 2.0)
            a = max(k1, n)
            if k2 >= a:
                total += (k2 - a + 1) * v1
            out.append(total)
        return tuple(out)  # type: ignore[return-value]


# name -> "module:class"
ROBOTS: dict[str, str] = {
    "kinematic": "scriptc.runtime.robots.kinematic:KinematicRobot",
    "mujoco": "scriptc.runtime.robots.mujoco:MujocoRobot",
}


class UnknownRobot(ValueError):
    pass


class RobotFailure(RuntimeError):
    """The backend cannot go on (the physics became unstable): the session reports it as the
    fatal run-time error `robot-unstable`."""


def make_robot(name: str) -> Robot:
    """A fresh backend by name (see `ROBOTS`)."""
    target = ROBOTS.get(name)
    if target is None:
        raise UnknownRobot(f"unknown robot `{name}` (known: {', '.join(sorted(ROBOTS))})")
    module, _, cls = target.partition(":")
    return getattr(importlib.import_module(module), cls)()
