"""Robot backends: what turns the actuators' velocity commands into a pose.

A backend implements `Robot`: `set_velocity(t_ms, v_x, v_y, v_theta, ramp=None)` (body-frame
speeds from `t_ms` on, m/s and rad/s), `advance(t_ms)` (bring the simulation up to `t_ms`) and
`pose()` (world frame: metres and radians, starting at the origin facing +x; `theta` is not
wrapped, so a full turn reads 2π), and `ghost()`, a copy that moves on its own: advanced to a
later millisecond, it says where the robot will be then without moving the robot (a session
observes the state between two instants so: `scriptc test`'s `at`). Times only grow; the
session calls `set_velocity` only when the effective velocity changes, so a backend sees
O(events) calls, never one per millisecond.

Without `ramp` the velocity changes at once. With `ramp` (a `motion.Ramp` of the safety
governor, whose target the velocity is, and which starts from the velocity the robot has) each
axis follows its linear ramp on the 1 ms grid: both backends follow the same `Ramp`, so the
governor knows at every millisecond what velocity the robot has.

Backends by name (`--robot NAME`): `mujoco` (the physics of the Teo/Oimi model, `mujoco.py`,
the default of `scriptc run`; docs/robot.md) and `kinematic` (exact integration,
`kinematic.py`). Only `mujoco.py` imports mujoco, and only when that backend is made.

What the session drives is a `Drive`: a backend, or the safety governor in front of one (which
makes its own ramps, so it takes none). A backend may do more, which the session asks of it by
what it has: show the LEDs and the speaker (`Display`, MuJoCo's model), step its physics in
time (`Stepped`, MuJoCo: brought up to each instant before the instant's events).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Protocol, TypeGuard

from scriptc.robot.motion import Pose, Ramp, Velocity

__all__ = ["ROBOTS", "Display", "Drive", "Pose", "Ramp", "Rgb", "Robot", "RobotFailure",
           "Stepped", "UnknownRobot", "Velocity", "is_display", "is_stepped", "make_robot"]

Rgb = tuple[float, float, float]


class Drive(Protocol):
    """What the session drives: velocities from `t_ms` on, time, and the pose."""

    name: str

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float) -> None: ...

    def advance(self, t_ms: int) -> None: ...

    def pose(self) -> Pose: ...

    def ghost(self) -> Drive: ...


class Robot(Drive, Protocol):
    """A backend (see the module's docstring): it follows a ramp of the governor too."""

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp: Ramp | None = None) -> None: ...

    def ghost(self) -> Robot: ...


class Display(Protocol):
    """A backend that shows the LEDs (None: off) and what the speaker plays (None: silence)."""

    def set_led(self, rgb: Rgb | None) -> None: ...

    def set_audio(self, track: str | None) -> None: ...


class Stepped(Protocol):
    """A backend that steps its physics: `time_ms` is how far it has got."""

    stepped: bool

    @property
    def time_ms(self) -> int: ...


def is_display(robot: object) -> TypeGuard[Display]:
    """Whether a backend (or the governor in front of it) shows the LEDs and the speaker."""
    return hasattr(robot, "set_led")


def is_stepped(robot: object) -> TypeGuard[Stepped]:
    """Whether a backend (or the governor in front of it) steps its physics."""
    return bool(getattr(robot, "stepped", False))


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
    backend: Callable[[], Robot] = getattr(importlib.import_module(module), cls)
    return backend()
