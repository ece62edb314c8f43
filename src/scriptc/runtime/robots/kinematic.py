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

A ramp of the safety governor (`set_velocity(..., rates=...)`, `robots.Ramp`) is integrated on
the 1 ms grid, like the MuJoCo robot's: the velocity is constant within each millisecond of the
ramp and each millisecond is an exact arc. When the heading does not change during the ramp
(no turning, or turning without translation) the milliseconds are summed in closed form;
otherwise the ramp costs one arc per millisecond of it (a second at most with the default
profile; the governed 10-minute activity of bench/bench_mujoco.py runs in about 0.25 s).
"""

from __future__ import annotations

import math

from scriptc.runtime.robots import Pose, Ramp


class KinematicRobot:
    name = "kinematic"

    def __init__(self, x: float = 0.0, y: float = 0.0, theta: float = 0.0) -> None:
        self._x, self._y, self._theta = x, y, theta
        self._t = 0
        self._v = (0.0, 0.0, 0.0)
        self._ramp: Ramp | None = None

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     rates: tuple[float, float, float] | None = None) -> None:
        self.advance(t_ms)
        now = self.velocity
        self._v = (float(v_x), float(v_y), float(v_theta))
        self._ramp = Ramp.between(t_ms, now, self._v, rates)

    def advance(self, t_ms: int) -> None:
        if t_ms <= self._t:
            return
        ramp = self._ramp
        if ramp is not None:
            k1, k2 = self._t - ramp.t0 + 1, min(t_ms, ramp.end) - ramp.t0
            (vx0, vy0, w0), (vx1, vy1, w1) = ramp.start, ramp.target
            if (w0 == 0.0 and w1 == 0.0) or not (vx0 or vy0 or vx1 or vy1):
                sx, sy, sw = ramp.totals(k1, k2)
                self._arc(0.001, sx, sy, sw)  # the heading is constant: one closed form
            else:
                for k in range(k1, k2 + 1):
                    self._arc(0.001, *ramp.at(k))
            self._t = ramp.t0 + k2
            if self._t >= ramp.end:
                self._ramp = None
        if t_ms > self._t:
            self._arc((t_ms - self._t) / 1000.0, *self._v)
            self._t = t_ms

    def _arc(self, T: float, vx: float, vy: float, w: float) -> None:
        """T seconds at the constant body velocity (vx, vy, w), in closed form."""
        if vx or vy or w:
            half = w * T / 2.0
            k = T if w == 0.0 else 2.0 * math.sin(half) / w
            mid = self._theta + half
            c, s = math.cos(mid), math.sin(mid)
            self._x += k * (vx * c - vy * s)
            self._y += k * (vx * s + vy * c)
            self._theta += w * T

    def pose(self) -> Pose:
        return Pose(self._x, self._y, self._theta)

    @property
    def velocity(self) -> tuple[float, float, float]:
        """The velocity the robot has now (within a ramp: the one reached at this ms)."""
        return self._ramp.velocity(self._t) if self._ramp is not None else self._v
