"""Robot backends: what turns the actuators' velocity commands into a pose.

A backend implements `Robot`: `set_velocity(t_ms, v_x, v_y, v_theta, ramp=None)` (body-frame
speeds from `t_ms` on, m/s and rad/s), `advance(t_ms)` (bring the simulation up to `t_ms`) and
`pose()` (world frame: metres and radians, starting at the origin facing +x; `theta` is not
wrapped, so a full turn reads 2π). Times only grow; the session calls `set_velocity` only when
the effective velocity changes, so a backend sees O(events) calls, never one per millisecond.

Without `ramp` the velocity changes at once. With `ramp` (a `motion.Ramp` of the safety
governor, whose target the velocity is, and which starts from the velocity the robot has) each
axis follows its linear ramp on the 1 ms grid: both backends follow the same `Ramp`, so the
governor knows at every millisecond what velocity the robot has.

Backends by name (`--robot NAME`): `mujoco` (the physics of the Teo/Oimi model, `mujoco.py`,
the default of `scriptc run`; docs/robot.md) and `kinematic` (exact integration,
`kinematic.py`). Only `mujoco.py` imports mujoco, and only when that backend is made.
"""

from __future__ import annotations

import importlib
from typing import Protocol

from scriptc.robot.motion import Pose, Ramp, Velocity

__all__ = ["ROBOTS", "Pose", "Ramp", "Robot", "RobotFailure", "UnknownRobot", "Velocity",
           "make_robot"]


class Robot(Protocol):
    name: str

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp: Ramp | None = None) -> None: ...

    def advance(self, t_ms: int) -> None: ...

    def pose(self) -> Pose: ...


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
