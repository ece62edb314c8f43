"""The safety governor: a `Robot` wrapper between the actuators and the backend that keeps
every velocity within the robot profile (docs/robot.md). A script is never refused for being
too fast: it is slowed.

- Speed: the planar speed |(v_x, v_y)| is scaled down to `max_linear_speed` (the direction is
  kept), |v_theta| is clamped to `max_angular_speed`. Durations are untouched, so the timing of
  the script (and of the run) is what it was: a clamped move goes less far, not longer.
- People: with simulated sensing, when a Human is closer than `min_human_distance` and the
  command would bring the robot closer, the wheels are held (translation zeroed, turning
  allowed) until the command or the distance changes.

Every clamp is written in the trace as a `governor` event with the commanded and the applied
velocity and the reason (`speed`, `angular-speed`, `human-distance`), and counted in
`clamps`.
"""

from __future__ import annotations

import math

from scriptc.profile import DEFAULT_PROFILE, Profile
from scriptc.runtime.robots import Pose


class Governor:
    def __init__(self, robot, profile: Profile = DEFAULT_PROFILE, trace=None) -> None:
        self.robot = robot
        self.profile = profile
        self.trace = trace
        self.name = getattr(robot, "name", type(robot).__name__)
        self.commanded = (0.0, 0.0, 0.0)
        self.applied = (0.0, 0.0, 0.0)
        self.clamps = 0
        # callback(t_ms, pose) -> (distance m, bearing rad in the body frame) | None
        self.nearest = None

    def __getattr__(self, name: str):
        return getattr(self.robot, name)

    def limit(self, v_x: float, v_y: float, v_theta: float,
              t_ms: int = 0) -> tuple[tuple[float, float, float], list[str]]:
        """The velocity the profile allows for a command, and why it differs."""
        p = self.profile
        reasons = []
        speed = math.hypot(v_x, v_y)
        if speed > p.max_linear_speed:
            k = p.max_linear_speed / speed
            v_x, v_y = v_x * k, v_y * k
            reasons.append("speed")
        if abs(v_theta) > p.max_angular_speed:
            v_theta = math.copysign(p.max_angular_speed, v_theta)
            reasons.append("angular-speed")
        if self.nearest is not None and (v_x or v_y):
            near = self.nearest(t_ms, self.robot.pose())
            if near is not None:
                distance, bearing = near
                toward = v_x * math.cos(bearing) + v_y * math.sin(bearing)
                if distance < p.min_human_distance and toward > 0:
                    v_x = v_y = 0.0
                    reasons.append("human-distance")
        return (v_x, v_y, v_theta), reasons

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float) -> None:
        self.commanded = (float(v_x), float(v_y), float(v_theta))
        self.robot.advance(t_ms)
        self._apply(t_ms)

    def _apply(self, t_ms: int) -> None:
        v, reasons = self.limit(*self.commanded, t_ms)
        if reasons and self.trace is not None:
            self.clamps += 1
            c = self.commanded
            self.trace.emit(t_ms, "governor", reasons=reasons,
                            commanded={"v_x": c[0], "v_y": c[1], "v_theta": c[2]},
                            applied={"v_x": v[0], "v_y": v[1], "v_theta": v[2]})
        if v != self.applied:
            self.applied = v
            self.robot.set_velocity(t_ms, *v)

    def recheck(self, t_ms: int) -> None:
        """Sensing saw the people move: apply the limits again to the same command."""
        v, _ = self.limit(*self.commanded, t_ms)
        if v != self.applied:
            self._apply(t_ms)

    def advance(self, t_ms: int) -> None:
        self.robot.advance(t_ms)

    def pose(self) -> Pose:
        return self.robot.pose()
