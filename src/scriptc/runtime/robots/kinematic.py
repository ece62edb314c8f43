"""The kinematic robot: an ideal holonomic base that does exactly what it is told.

Between two velocity changes the body-frame velocity (v_x, v_y, ω) is constant, so the pose
follows a closed form (an arc, or a line when ω = 0), integrated exactly over each interval,
not in Euler steps. With θ0 the heading at the start of an interval of T seconds and
θm = θ0 + ωT/2 the heading at its middle:

    x += k (v_x cos θm - v_y sin θm)
    y += k (v_x sin θm + v_y cos θm)        k = 2 sin(ωT/2) / ω   (k = T when ω = 0)
    θ += ωT

which is the integral of the body velocity rotated by θ(t) = θ0 + ωt, written so that it
stays accurate as ω goes to 0.
"""

from __future__ import annotations

import math

from scriptc.runtime.robots import Pose


class KinematicRobot:
    name = "kinematic"

    def __init__(self, x: float = 0.0, y: float = 0.0, theta: float = 0.0) -> None:
        self._x, self._y, self._theta = x, y, theta
        self._t = 0
        self._v = (0.0, 0.0, 0.0)

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float) -> None:
        self.advance(t_ms)
        self._v = (float(v_x), float(v_y), float(v_theta))

    def advance(self, t_ms: int) -> None:
        if t_ms <= self._t:
            return
        vx, vy, w = self._v
        if vx or vy or w:
            T = (t_ms - self._t) / 1000.0
            half = w * T / 2.0
            k = T if w == 0.0 else 2.0 * math.sin(half) / w
            mid = self._theta + half
            c, s = math.cos(mid), math.sin(mid)
            self._x += k * (vx * c - vy * s)
            self._y += k * (vx * s + vy * c)
            self._theta += w * T
        self._t = t_ms

    def pose(self) -> Pose:
        return Pose(self._x, self._y, self._theta)

    @property
    def velocity(self) -> tuple[float, float, float]:
        return self._v
