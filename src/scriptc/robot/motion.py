"""What the robot's base does with velocity commands under the robot profile: the governor's
ramps on the 1 ms grid, the plan of an instruction block's move track (ramps centred on the
changes known ahead), and the exact kinematics of a holonomic base (docs/robot.md,
"Acceleration"). One definition for every user: the run-time governor and both robots
(`runtime/`) and the static check K003 (`check/ramps.py`), which predicts a block's run with
the same code the run uses.

Velocities are body-frame `(v_x, v_y, v_theta)` (m/s, m/s, rad/s); times are whole
milliseconds. The axes ramp in two groups (`GROUPS`): the plane (`v_x` and `v_y` together,
over the time the larger change needs, so the planar velocity moves on a straight line) and
the turn (`v_theta`).

- `Ramp`: per axis, a linear change on the 1 ms grid: during the k-th millisecond of an
  axis's ramp (k = 1 .. steps) it has `start + k * step`, the value reached at the
  millisecond's end, and its target from the last one on. A ramp from rest to v at a has
  velocity a*t at every whole t when v/a is whole milliseconds; a ramp of n ms starting at s
  covers the same distance as a step of the velocity at `s + (n - 1) / 2`.
- `Shaper`: the velocity the governor gives the robot. A change it did not know ahead is
  ramped *late*: from the velocity the robot has, at the limit, from the command on. A block's
  motions that `plan` can centre are ramped *centred*: each change's ramp has an odd number of
  milliseconds m (the limit's, or one more) and starts (m - 1) / 2 before the change, so the
  robot covers exactly the distance of the step.
- `Kinematics`: the exact pose of a base following a velocity or a `Ramp`: a closed-form arc
  per interval of constant velocity, each millisecond of a ramp an exact arc (summed in closed
  form when the heading does not change).
"""

from __future__ import annotations

import copy
import math
from bisect import bisect_right
from collections.abc import Iterable, Sequence
from typing import NamedTuple, Self

from scriptc.robot.profile import Profile

Velocity = tuple[float, float, float]
ZERO: Velocity = (0.0, 0.0, 0.0)
GROUPS = ((0, 1), (2,))  # axes that ramp together: the plane, the turn (each a slice)
GROUP_NAMES = ("plane", "turn")
# Per axis (v_x, v_y, v_theta): ms of a ramp's start or length.
AxisTimes = tuple[int, int, int]
# A change of one group's velocity: (ms, the group's values before, after).
Change = tuple[int, tuple[float, ...], tuple[float, ...]]


class Pose(NamedTuple):
    x: float
    y: float
    theta: float

    def as_dict(self) -> dict[str, float]:
        return {"x": self.x, "y": self.y, "theta": self.theta}


def limit_speed(v: Velocity, profile: Profile) -> tuple[Velocity, list[str]]:
    """The velocity within the profile's speeds, and why it differs: the planar speed scaled
    down to `max_linear_speed` (the direction kept), |v_theta| clamped to
    `max_angular_speed`."""
    v_x, v_y, v_theta = v
    reasons = []
    speed = math.hypot(v_x, v_y)
    if speed > profile.max_linear_speed:
        k = profile.max_linear_speed / speed
        v_x, v_y = v_x * k, v_y * k
        reasons.append("speed")
    if abs(v_theta) > profile.max_angular_speed:
        v_theta = math.copysign(profile.max_angular_speed, v_theta)
        reasons.append("angular-speed")
    return (v_x, v_y, v_theta), reasons


def rates_of(profile: Profile) -> Velocity:
    """The accelerations per axis (m/s², m/s², rad/s²)."""
    return (profile.max_linear_acceleration, profile.max_linear_acceleration,
            profile.max_angular_acceleration)


def limit_ms(start: Iterable[float], target: Iterable[float],
             rates: Iterable[float]) -> int:
    """Whole milliseconds a change of a group of axes takes at the limit: the largest need of
    its axes (0: no change; 1 on an axis without a limit)."""
    n = 0
    for v0, v1, rate in zip(start, target, rates, strict=True):  # the axes of one group
        if v0 == v1:
            continue
        if not 0.0 < rate < math.inf:
            need = 1  # no limit on this axis: the change takes one millisecond
        else:
            # 1e-9: a change of exactly k ms at the rate is k steps, not k + 1
            need = math.ceil(abs(v1 - v0) * 1000.0 / rate - 1e-9)
            need = need if need > 1 else 1
        if need > n:
            n = need
    return n


def centred_ms(n: int) -> int:
    """The milliseconds of a centred ramp: odd, so that it starts a whole number of
    milliseconds, (m - 1) / 2, before its change (the limit's n, or n + 1: slower, never
    faster)."""
    return n if n % 2 else n + 1


class Ramp:
    """Linear changes of velocity on the 1 ms grid, one per axis (module docstring).

    Each axis has its own start and length (the `Shaper` makes them: the axes of a group
    share the duration the larger change needs, `limit_ms`). Axis i has `start[i]` up to
    `t0s[i]`, then `start[i] + k * step[i]` during the k-th millisecond after it, and
    `target[i]` from `t0s[i] + steps[i]` on. `end` is the millisecond every axis is on its
    target; `t0` the earliest start."""

    __slots__ = ("end", "ends", "start", "step", "steps", "t0", "t0s", "target")

    def __init__(self, t0s: Sequence[int], start: Sequence[float], target: Sequence[float],
                 steps: Sequence[int]) -> None:
        self.t0s: AxisTimes = (t0s[0], t0s[1], t0s[2])
        self.start: Velocity = (start[0], start[1], start[2])
        self.target: Velocity = (target[0], target[1], target[2])
        self.steps: AxisTimes = (steps[0], steps[1], steps[2])
        self.step = ((target[0] - start[0]) / steps[0] if steps[0] else 0.0,
                     (target[1] - start[1]) / steps[1] if steps[1] else 0.0,
                     (target[2] - start[2]) / steps[2] if steps[2] else 0.0)
        # each axis is on its target from `ends` on
        self.ends = ends = (t0s[0] + steps[0], t0s[1] + steps[1], t0s[2] + steps[2])
        ramping = [i for i in (0, 1, 2) if steps[i]]
        self.t0 = min([t0s[i] for i in ramping]) if ramping else t0s[0]
        self.end = max([ends[i] for i in ramping]) if ramping else self.t0

    def velocity(self, t_ms: int) -> Velocity:
        """The velocity during the millisecond that ends at `t_ms` (reached at its end)."""
        out: list[float] = []
        for t0, v0, v1, s, n in zip(self.t0s, self.start, self.target, self.step, self.steps,
                                    strict=True):
            k = t_ms - t0
            out.append(v0 if k <= 0 or not n else v1 if k >= n else v0 + k * s)
        return (out[0], out[1], out[2])

    def at(self, k: int) -> Velocity:
        """The velocity during the k-th millisecond after `t0`."""
        return self.velocity(self.t0 + k)

    def ramping(self, i: int, a: int, b: int) -> bool:
        """Whether axis i changes during some millisecond of (a, b]."""
        return bool(self.steps[i]) and a < self.ends[i] and b > self.t0s[i]

    def breaks(self, a: int, b: int) -> list[int]:
        """The milliseconds in (a, b) where some axis starts or ends its ramp, then b: within
        each interval between them every axis is constant or linear."""
        out = {b}
        for t0, t1, n in zip(self.t0s, self.ends, self.steps, strict=True):
            if n:
                if a < t0 < b:
                    out.add(t0)
                if a < t1 < b:
                    out.add(t1)
        return sorted(out)

    def sums(self, a: int, b: int) -> Velocity:
        """Per axis, the sum of the velocities of the milliseconds (a, b] (times 1 ms: the
        distance covered, in the body frame, when the heading does not change)."""
        out: list[float] = []
        for t0, v0, v1, s, n in zip(self.t0s, self.start, self.target, self.step, self.steps,
                                    strict=True):
            total = 0.0
            lo, hi = a + 1, b  # the milliseconds, by the time they end
            if not n:
                total = (hi - lo + 1) * v0 if hi >= lo else 0.0
                out.append(total)
                continue
            before = min(hi, t0)  # still at the start value (k <= 0)
            if before >= lo:
                total += (before - lo + 1) * v0
            k1, k2 = max(lo, t0 + 1) - t0, min(hi, t0 + n - 1) - t0  # ramping, 1 <= k < n
            if k2 >= k1:
                total += (k2 - k1 + 1) * (v0 + s * (k1 + k2) / 2.0)
            after = max(lo, t0 + n)  # on the target
            if hi >= after:
                total += (hi - after + 1) * v1
            out.append(total)
        return (out[0], out[1], out[2])


# -- the plan of a block's move track -----------------------------------------------------------


def track_steps(moves: Iterable[tuple[Velocity, int, int]]) -> list[tuple[int, Velocity]]:
    """The velocity a move track asks for, as steps `(ms from the block's start, velocity
    from then on)`: each command starts after its wait and stops after its duration; a stop
    and a start at the same millisecond leave the last (docs/runtime.md, "Instruction
    blocks"). Steps that change nothing are kept out by `changes`."""
    steps: list[tuple[int, Velocity]] = []
    t = 0
    for velocity, wait, duration in moves:
        t += wait
        steps.append((t, velocity))
        t += duration
        steps.append((t, ZERO))
    netted: list[tuple[int, Velocity]] = []
    for t, v in steps:
        if netted and netted[-1][0] == t:
            netted[-1] = (t, v)
        else:
            netted.append((t, v))
    return netted


class Planned(NamedTuple):
    """A centred ramp of one group: from `at`, `steps` ms to `values`, for the change at
    `due`."""

    at: int
    group: int
    values: tuple[float, ...]
    steps: int
    due: int


class Motion(NamedTuple):
    """A stretch of one group's velocity between two rests in a block (for K003): its changes
    `(ms, before, after)` from the block's start, whether the governor centres it, and why
    not (`late_because`: "start" it starts as the block starts or the robot is still moving,
    "end" it runs to the block's end, "overlap" two of its ramps would overlap, "entered" the
    block starts while it moves)."""

    group: int
    changes: tuple[Change, ...]
    centred: bool
    late_because: str | None


class _GroupState:
    """One group's velocity during planning: a ramp from `v0` at `t0` to `v1` over `n` ms."""

    __slots__ = ("n", "t0", "v0", "v1")

    def __init__(self, t0: int, v0: tuple[float, ...], v1: tuple[float, ...], n: int) -> None:
        self.t0, self.v0, self.v1, self.n = t0, v0, v1, n

    def at(self, t: int) -> tuple[float, ...]:
        k = t - self.t0
        if self.n == 0 or k >= self.n:
            return self.v1
        if k <= 0:
            return self.v0
        return tuple(a + k * (b - a) / self.n for a, b in zip(self.v0, self.v1, strict=True))

    def move(self, t: int, v1: tuple[float, ...], n: int) -> None:
        self.v0, self.v1, self.t0, self.n = self.at(t), v1, t, n


def _at_rest(values: Iterable[float]) -> bool:
    return not any(values)


def _why_late(t0: int, length: int, motion: tuple[Change, ...], spans: list[int],
              state: _GroupState) -> str | None:
    """Why the governor cannot centre a motion of a block issued at `t0` that lasts `length`
    ms, whose centred ramps last `spans`, with the group in `state` before it (None: it can):
    "entered", the block starts while the group moves; "start", its first ramp would start
    before the block or while the group still moves; "overlap", two of its ramps would
    overlap; "end", its last ramp would end after the block."""
    if not _at_rest(motion[0][1]):
        return "entered"
    end: int | None = None
    for (t, _, _), m in zip(motion, spans, strict=True):  # a span per change
        at = t0 + t - (m - 1) // 2
        if end is None:
            if at < t0 or at < state.t0 + state.n or not _at_rest(state.v1):
                return "start"
        elif at < end:
            return "overlap"
        end = at + m
    return "end" if end is not None and end > t0 + length else None


class Shaper:
    """The velocity the governor gives the robot (module docstring): `target` is where it is
    or where it goes, `ramp` how (None: it is on `target`). `late(t, v)` applies a command;
    `plan(...)` centres the motions of a block it can, whose ramps `due(t)` then yields in
    order (the caller starts each with `start`)."""

    def __init__(self, rates: tuple[float, float, float]) -> None:
        self.rates = rates
        self.ramp: Ramp | None = None
        self.target: Velocity = ZERO
        # per group: the change a started centred ramp is heading for (its ms), or None
        self.anticipating: list[int | None] = [None, None]
        self.planned: list[Planned] = []  # centred ramps to start, by `at`
        # the plan's steps (absolute ms, and the velocity the command has from then on)
        self.expected_times: list[int] = []
        self.expected: list[Velocity] = []

    def velocity(self, t_ms: int) -> Velocity:
        return self.ramp.velocity(t_ms) if self.ramp is not None else self.target

    # -- changes ------------------------------------------------------------------------------

    def _set(self, t: int, groups: dict[int, tuple[tuple[float, ...], int]]) -> None:
        """From `t`, each group of `groups` ramps to its values over its ms (0: at once); the
        other axes keep their ramp."""
        now = self.velocity(t)
        old = self.ramp
        t0s, start, target, steps = [t] * 3, list(now), list(self.target), [0] * 3
        for i in range(3):
            if old is not None and old.steps[i] and t < old.t0s[i] + old.steps[i]:
                t0s[i], start[i], target[i], steps[i] = (old.t0s[i], old.start[i],
                                                         old.target[i], old.steps[i])
        for g, (values, n) in groups.items():
            for i, v in zip(GROUPS[g], values, strict=True):  # the group's axes
                t0s[i], start[i], target[i] = t, now[i], v
                steps[i] = n if n > 1 and now[i] != v else 0
        self.target = (target[0], target[1], target[2])
        ramp = Ramp(t0s, start, target, steps)
        self.ramp = ramp if any(steps) else None

    def late(self, t: int, target: Velocity) -> dict[int, int]:
        """A command from `t`: each group not heading for a planned change, whose target
        differs, ramps there at the limit from the velocity it has. Returns the ms of each
        group that ramps (1: at once)."""
        if target == self.target and self.anticipating == [None, None]:
            return {}  # nothing changes
        changed: dict[int, tuple[tuple[float, ...], int]] = {}
        now = None
        for g, axes in enumerate(GROUPS):
            due = self.anticipating[g]
            if due is not None:
                if t < due:
                    continue  # a centred ramp heads for the planned change
                self.anticipating[g] = None
            values = target[axes[0]:axes[-1] + 1]
            if values != self.target[axes[0]:axes[-1] + 1]:
                if now is None:
                    now = self.velocity(t)
                n = limit_ms(now[axes[0]:axes[-1] + 1], values,
                             self.rates[axes[0]:axes[-1] + 1])
                changed[g] = (values, n)
        if changed:
            self._set(t, changed)
        return {g: n for g, (_, n) in changed.items()}

    # -- plans --------------------------------------------------------------------------------

    def plan(self, t0: int, length: int, steps: list[tuple[int, Velocity]],
             before: Velocity) -> list[Motion]:
        """The plan of a block issued at `t0` that lasts `length` ms, whose move track asks
        for `steps` (`track_steps`, within the speed limits) after `before`: the motions it
        can centre get `planned` ramps; the others are ramped late, command by command.
        Returns every motion of the block (for K003)."""
        steps = track_steps_from_zero(steps)
        self.planned = []
        self.anticipating = [None, None]
        self.expected_times = [t0 + t for t, _ in steps]
        self.expected = [v for _, v in steps]
        motions: list[Motion] = []
        for g, axes in enumerate(GROUPS):
            motions.extend(self._plan_group(t0, length, g, axes, steps, before))
        self.planned.sort()
        return motions

    def _plan_group(self, t0: int, length: int, g: int, axes: tuple[int, ...],
                    steps: list[tuple[int, Velocity]], before: Velocity) -> list[Motion]:
        lo, hi = axes[0], axes[-1] + 1
        rates = self.rates[lo:hi]
        changes: list[Change] = []
        value: tuple[float, ...] = before[lo:hi]
        for t, v in steps:
            new = v[lo:hi]
            if new != value:
                changes.append((t, value, new))
                value = new
        if not changes:
            return []
        # The group as the robot has it at the issue: where it goes, and when it gets there.
        state = _GroupState(t0, self.velocity(t0)[lo:hi], self.target[lo:hi], 0)
        ramp = self.ramp
        if ramp is not None:
            ends = [ramp.t0s[i] + ramp.steps[i] for i in axes if ramp.steps[i]]
            if ends and max(ends) > t0:
                state.n = max(ends) - t0  # only when it gets there matters for the plan
        motions = []
        k = 0
        while k < len(changes):
            first = k
            while not _at_rest(changes[k][2]) and k + 1 < len(changes):
                k += 1  # on to the change that brings the group to rest
            motion = tuple(changes[first:k + 1])
            k += 1
            spans = [centred_ms(limit_ms(v0, v1, rates)) for _, v0, v1 in motion]
            why = _why_late(t0, length, motion, spans, state)
            for (t, v0, v1), m in zip(motion, spans, strict=True):  # a span per change
                if why is None:
                    at = t0 + t - (m - 1) // 2
                    self.planned.append(Planned(at, g, v1, m, t0 + t))
                    state.v0, state.v1, state.t0, state.n = v0, v1, at, m
                else:  # each change from the velocity the group has, at the limit
                    state.move(t0 + t, v1, limit_ms(state.at(t0 + t), v1, rates))
            motions.append(Motion(g, motion, why is None, why))
        return motions

    def expected_at(self, t: int) -> Velocity | None:
        """The velocity the plan expects the command to have at `t` (None: no plan)."""
        i = bisect_right(self.expected_times, t)
        return self.expected[i - 1] if i else None

    def drop(self) -> None:
        """The plan no longer holds (a command it did not expect): no more centred ramps, and
        the groups heading for a planned change follow the commands again."""
        self.planned = []
        self.expected_times = []
        self.expected = []
        self.anticipating = [None, None]

    def due(self, t: int) -> Planned | None:
        """The next centred ramp to start at or before `t` (taken from the plan)."""
        if self.planned and self.planned[0].at <= t:
            return self.planned.pop(0)
        return None

    def start(self, planned: Planned) -> None:
        self.anticipating[planned.group] = planned.due
        self._set(planned.at, {planned.group: (planned.values, planned.steps)})


# -- kinematics ---------------------------------------------------------------------------------

# Gauss-Legendre nodes and weights on [0, 1] (from [-1, 1]), 4 points: exact for polynomials of
# degree 7, within a micrometre for a heading that turns at most a radian along the stretch.
_GAUSS = tuple(((x + 1) / 2, w / 2) for x, w in (
    (-0.8611363115940526, 0.3478548451374536), (-0.3399810435848563, 0.6521451548625464),
    (0.3399810435848563, 0.6521451548625464), (0.8611363115940526, 0.3478548451374536)))


class Kinematics:
    """An ideal holonomic base (docs/runtime.md, "Robots"): between two velocity changes the
    body-frame velocity (v_x, v_y, ω) is constant, so the pose follows a closed form (an arc,
    or a line when ω = 0), integrated exactly over each interval, not in Euler steps. With θ0
    the heading at the start of an interval of T seconds and θm = θ0 + ωT/2 the heading at
    its middle:

        x += k (v_x cos θm - v_y sin θm)
        y += k (v_x sin θm + v_y cos θm)        k = 2 sin(ωT/2) / ω   (k = T when ω = 0)
        θ += ωT

    which is the integral of the body velocity rotated by θ(t) = θ0 + ωt, written so that it
    stays accurate as ω goes to 0. A `Ramp` is followed on the 1 ms grid: each millisecond an
    exact arc, summed in closed form where the heading does not change (no turning, or turning
    without translation) and over each stretch where no axis changes."""

    def __init__(self, x: float = 0.0, y: float = 0.0, theta: float = 0.0,
                 exact: bool = True) -> None:
        self._x, self._y, self._theta = x, y, theta
        self._t = 0
        self._v: Velocity = ZERO
        self._ramp: Ramp | None = None
        # Not exact: a stretch of a ramp that turns while it moves by quadrature, within a
        # micrometre, instead of an arc per millisecond (the static prediction, K003).
        self._exact = exact

    def start(self, velocity: Velocity, ramp: Ramp | None = None) -> None:
        """The velocity it has at its start (following `ramp`, whose target it is)."""
        self._v, self._ramp = velocity, ramp

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp: Ramp | None = None) -> None:
        """From `t_ms`, (v_x, v_y, v_theta): at once, or following `ramp` (whose target it
        is)."""
        self.advance(t_ms)
        self._v = (float(v_x), float(v_y), float(v_theta))
        self._ramp = ramp

    def advance(self, t_ms: int) -> None:
        if t_ms <= self._t:
            return
        ramp = self._ramp
        if ramp is not None:
            stop = min(t_ms, ramp.end)
            a = self._t
            t0s, ends, steps = ramp.t0s, ramp.ends, ramp.steps
            for b in ramp.breaks(a, stop) if stop > a else ():
                # which axes change within (a, b] (`Ramp.ramping`)
                rx = steps[0] and a < ends[0] and b > t0s[0]
                ry = steps[1] and a < ends[1] and b > t0s[1]
                rw = steps[2] and a < ends[2] and b > t0s[2]
                end = ramp.velocity(b)
                if not (rx or ry or rw):
                    self._arc((b - a) / 1000.0, *end)
                elif not ((rw or end[2]) and (rx or ry or end[0] or end[1])):
                    sx, sy, sw = ramp.sums(a, b)
                    self._arc(0.001, sx, sy, sw)  # the heading is constant: one closed form
                else:
                    # Every axis is constant or linear here: in the millisecond ending at t a
                    # ramping axis has start + (t - t0) * step (`Ramp.velocity`).
                    (x0, y0, w0), (tx, ty, tw), (sx, sy, sw) = ramp.start, t0s, ramp.step
                    if not rx:
                        x0, tx, sx = end[0], 0, 0.0
                    if not ry:
                        y0, ty, sy = end[1], 0, 0.0
                    if not rw:
                        w0, tw, sw = end[2], 0, 0.0
                    if self._exact or b - a <= 8:
                        for t in range(a + 1, b + 1):
                            self._arc(0.001, x0 + (t - tx) * sx, y0 + (t - ty) * sy,
                                      w0 + (t - tw) * sw)
                    else:
                        self._quadrature(a, b, (x0 - tx * sx, y0 - ty * sy, w0 - tw * sw),
                                         (sx, sy, sw))
                a = b
            self._t = max(self._t, stop)
            if self._t >= ramp.end:
                self._ramp = None
        if t_ms > self._t:
            self._arc((t_ms - self._t) / 1000.0, *self._v)
            self._t = t_ms

    def _quadrature(self, a: int, b: int, base: Velocity, slope: Velocity) -> None:
        """The milliseconds (a, b] of velocities `base + t * slope` (t the millisecond's end),
        as the integral of the body velocity along the heading, by Gauss-Legendre quadrature on
        the continuous velocity through the milliseconds' middles, in stretches of at most
        one radian of heading (the heading itself exactly, as the sum of the milliseconds)."""
        (bx, by, bw), (sx, sy, sw) = base, slope
        theta = self._theta
        most = max(abs(bw + (a + 1) * sw), abs(bw + b * sw))  # the fastest turn, rad/s
        pieces = max(1, math.ceil(most * (b - a) / 1000.0))
        length = (b - a) / pieces
        x = y = 0.0
        half = a + 0.5
        for p in range(pieces):
            lo = p * length
            for node, weight in _GAUSS:
                u = lo + node * length  # ms from a, continuous
                # velocity of the ms containing u; heading: the turn's velocity integrated
                t = half + u
                vx, vy = bx + t * sx, by + t * sy
                heading = theta + (bw * u + sw * (u * u / 2 + half * u)) / 1000.0
                c, s = math.cos(heading), math.sin(heading)
                x += weight * (vx * c - vy * s)
                y += weight * (vx * s + vy * c)
        self._x += x * length / 1000.0
        self._y += y * length / 1000.0
        self._theta += (b - a) * (bw + sw * (a + 1 + b) / 2) / 1000.0

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

    def ghost(self) -> Self:
        """A copy that moves on its own: where the robot will be at a later millisecond,
        without moving it (advancing the robot itself there would cut its arcs in other places,
        and the closed forms would round differently). Its state is immutable values, so a
        shallow copy is a whole one."""
        return copy.copy(self)

    @property
    def velocity(self) -> Velocity:
        """The velocity the robot has now (within a ramp: the one reached at this ms)."""
        return self._ramp.velocity(self._t) if self._ramp is not None else self._v


# -- a block's run, predicted (K003) -----------------------------------------------------------


class Entry(NamedTuple):
    """The robot as a block starts (times from the block's start): the ramp it follows, where
    it goes, and the velocity the previous command asked for (within the speed limits)."""

    ramp: Ramp | None
    target: Velocity
    command: Velocity

    def key(self) -> EntryKey:
        r = self.ramp
        ramp = None if r is None else (r.t0s, r.start, r.target, r.steps)
        return (ramp, self.target, self.command)


REST = Entry(None, ZERO, ZERO)
# `Entry.key`: the entry as plain values (the ramp's start times, start, target and lengths).
EntryKey = tuple[tuple[AxisTimes, Velocity, Velocity, AxisTimes] | None, Velocity, Velocity]


class BlockRun(NamedTuple):
    """What the governor makes of a block entered in some `Entry` (`run_block`): its motions
    (`Shaper.plan`), how the robot leaves it (`exit`, for the next block: the ramp it follows
    at the block's end and the command it had), and how far from the script's pose it ends:
    `error` (dx, dy, dtheta), the governed pose minus the script's, when the robot stops at
    the block's end."""

    motions: list[Motion]
    exit: Entry
    error: Velocity


def _shifted(ramp: Ramp | None, by: int) -> Ramp | None:
    if ramp is None or ramp.end <= by:
        return None
    return Ramp([t - by for t in ramp.t0s], ramp.start, ramp.target, ramp.steps)


def run_block(entry: Entry, steps: list[tuple[int, Velocity]], length: int,
              rates: tuple[float, float, float], exact: bool = True,
              ideal: Pose | None = None) -> BlockRun:
    """The block's run as the governor makes it, from `entry`: `steps` (`track_steps`,
    within the speed limits) from the block's start, `length` ms. The governed robot (the
    same `Shaper` as at run time, `Kinematics` for the pose) stops at the block's end and
    comes to rest; the script's pose is the previous motion coming to rest as the governor
    brakes it (`entry` with a zero command) followed by the block's steps at once (`ideal`,
    that pose from the origin, when the caller has it). Not `exact`: the stretches of ramps
    that turn while they move by quadrature (`Kinematics`)."""
    shaper = Shaper(rates)
    shaper.ramp, shaper.target = entry.ramp, entry.target
    motions = shaper.plan(0, length, steps, entry.command)
    robot = Kinematics(exact=exact)
    robot.start(entry.target, entry.ramp)

    def play(t: int) -> None:
        while (planned := shaper.due(t)) is not None:
            robot.advance(planned.at)
            shaper.start(planned)
            robot.set_velocity(planned.at, *shaper.target, ramp=shaper.ramp)

    def command(t: int, v: Velocity) -> None:
        play(t)
        robot.advance(t)
        if shaper.late(t, v):
            robot.set_velocity(t, *shaper.target, ramp=shaper.ramp)

    last = entry.command
    stop = ZERO
    for t, v in zip(shaper.expected_times, shaper.expected, strict=True):  # made together
        if t >= length:
            stop = v  # at the block's end: the next block's first command, or the stop
            break
        command(t, v)
        last = v
    play(length)
    robot.advance(length)
    exit = Entry(_shifted(shaper.ramp, length), shaper.target, last)
    command(length, stop)  # the robot stops at the block's end, and comes to rest
    robot.advance(max(length, shaper.ramp.end if shaper.ramp is not None else length))
    governed = robot.pose()

    x, y, theta = 0.0, 0.0, 0.0
    if entry.ramp is not None or any(entry.target):
        braking = Shaper(rates)
        braking.ramp, braking.target = entry.ramp, entry.target
        script = Kinematics(exact=exact)
        script.start(entry.target, entry.ramp)
        if braking.late(0, ZERO):
            script.set_velocity(0, *braking.target, ramp=braking.ramp)
        script.advance(braking.ramp.end if braking.ramp is not None else 0)
        x, y, theta = script.pose()
    ix, iy, itheta = ideal if ideal is not None else ideal_pose(steps, length)
    c, s = math.cos(theta), math.sin(theta)
    wanted = (x + c * ix - s * iy, y + s * ix + c * iy, theta + itheta)
    return BlockRun(motions, exit, (governed.x - wanted[0], governed.y - wanted[1],
                                    governed.theta - wanted[2]))


def centred_bound(steps: list[tuple[int, Velocity]], length: int,
                  rates: tuple[float, float, float]) -> tuple[list[Motion], float] | None:
    """For a block entered at rest whose motions the governor all centres (None otherwise): its
    motions, and a bound of how far from the script's position the robot ends (its heading
    is the script's, exactly, and it is at rest by the block's end). Centred ramps keep each
    axis's distance; the position differs only where the plane and the turn ramp together:
    over a ramp of T s, by at most |Δu| T² / 24 times the fastest turn around it for a change
    of the planar velocity u, and |Δω| T² / 24 times the fastest planar speed around it for a
    change of the turn ω (the integrals of the ramp's difference from the step against the
    heading's drift, or of the heading's difference against the speed). `run_block` gives the
    exact figure; this is the cheap check that there is nothing to report."""
    shaper = Shaper(rates)
    motions = shaper.plan(0, length, steps, ZERO)
    if not all(m.centred for m in motions):
        return None
    times = shaper.expected_times
    # the ideal speeds from each step on: planar, turning
    speeds = ([math.hypot(v[0], v[1]) for v in shaper.expected],
              [abs(v[2]) for v in shaper.expected])
    longest = max((p.steps for p in shaper.planned), default=0)

    def fastest(lo: int, hi: int, group: int) -> float:
        """The fastest ideal speed of a group over [lo, hi] (planar or turning)."""
        return max(speeds[group][max(0, bisect_right(times, lo) - 1):bisect_right(times, hi)],
                   default=0.0)

    bound = 0.0
    before = [(0.0, 0.0), (0.0,)]
    for p in shaper.planned:  # in order of `at`; per group, in order of their changes
        old, before[p.group] = before[p.group], p.values
        change = math.hypot(*(b - a for a, b in zip(old, p.values, strict=True)))
        spread = (p.steps / 1000.0) ** 2 / 24.0
        if p.group == 0:
            bound += change * spread * fastest(p.at, p.at + p.steps, 1)
        else:
            bound += change * spread * fastest(p.at - longest, p.at + p.steps + longest, 0)
    return motions, bound


def ideal_pose(steps: list[tuple[int, Velocity]], length: int) -> Pose:
    """Where the block's steps at once take the robot from the origin, facing +x."""
    ideal = Kinematics()
    for t, v in track_steps_from_zero(steps):
        if t >= length:
            break
        ideal.set_velocity(t, *v)
    ideal.advance(length)
    return ideal.pose()


def track_steps_from_zero(steps: list[tuple[int, Velocity]]) -> list[tuple[int, Velocity]]:
    """`steps` from the block's start: a block starts with the wheels still until its first
    command (the previous block's move stopped as it ended)."""
    if not steps or steps[0][0] > 0:
        return [(0, ZERO), *steps]
    return steps
