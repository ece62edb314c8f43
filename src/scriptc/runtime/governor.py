"""The safety governor: a `Robot` wrapper between the actuators and the backend that keeps
every velocity and the LEDs within the robot profile (docs/robot.md, "The governor"). A script
is never refused for being too fast: it is slowed, ramped, held.

- Speed: the planar speed |(v_x, v_y)| is scaled down to `max_linear_speed` (the direction is
  kept), |v_theta| is clamped to `max_angular_speed`. Durations are untouched, so the timing of
  the script (and of the run) is what it was: a clamped move goes less far, not longer.
- People: with simulated sensing, when a Human is closer than `min_human_distance` plus the
  distance the robot needs to brake toward them, and the command would bring the robot closer,
  translation is held (turning allowed) until the command or the distance changes.
- Acceleration: the velocity the robot is given changes per axis of the body frame at most at
  `max_linear_acceleration` (v_x, v_y) and `max_angular_acceleration` (v_theta), as ROS 2
  nav2's velocity smoother does: a step of the command becomes a linear ramp (`motion.Ramp`,
  on the 1 ms grid; the backend steps it). v_x and v_y ramp together over the time the larger
  change needs (nav2's `scale_velocities`), so the planar speed stays within its limit during
  the ramp. When the actuators issue a block (`plan_block`), its move track is known ahead:
  the motions whose ramps fit in the block are ramped centred on their changes (starting half
  a ramp before), so the robot covers exactly the script's distance; the others, and every
  change the plan could not know (the operator, a freeze, a hold, a person: `drop_plan`), are
  ramped late, from the change, at the limit (`motion.Shaper`). A late move from rest to rest
  keeps its distance per axis: the ramp down after the command's stop gives back what the ramp
  up lost. The hold brakes at the limit too.
- LEDs: at most `max_led_flash_rate` onsets (dark to lit) in any one-second window, as K002
  counts them. An onset beyond it is not shown: the LEDs stay dark until the window allows
  one, then show what the script asks at that moment (the session wakes the governor then).
  A colour change while lit is not a flash; going dark is always allowed.

A command is applied at the end of the instant it was given in (`end_instant`; or when time
moves on), so commands that cancel out within one millisecond (a move's stop and the next
move's start) are not ramps. Every clamp is written in the trace as a `governor` event with the
`reasons` (`speed`, `angular-speed`, `human-distance`, `acceleration`, `angular-acceleration`,
`led-flash`), the `commanded` and the `applied` value, and for a late ramp its `target` and
`ramp_ms`; for a held onset, `until`. Each is counted in `clamps`. A centred ramp is not a
clamp: it changes nothing of where the robot goes (docs/robot.md, "In the trace").
"""

from __future__ import annotations

import copy
import math
from collections import deque
from collections.abc import Callable, Iterable
from typing import TypeGuard

from scriptc.robot.motion import ZERO, Shaper, limit_speed, rates_of, track_steps
from scriptc.robot.profile import DEFAULT_PROFILE, Profile
from scriptc.runtime.clock import PRIO_UPDATE
from scriptc.runtime.commands import Move
from scriptc.runtime.robots import Pose, Ramp, Rgb, Robot
from scriptc.runtime.trace import Event, Trace

# The governor's wake-up (a held LED onset's window frees) runs after every other event of its
# millisecond, so it sees the LEDs the tracks set at that millisecond.
PRIO_WAKE = PRIO_UPDATE + 1
WINDOW_MS = 1000  # the flash limit's window, as K002's (check/safety.py)

Vector = tuple[float, float, float]

# Where the nearest person is at a millisecond, seen from the robot's pose: (distance m,
# bearing rad in the body frame), None when nobody is there (runtime/sensing.py).
Nearest = Callable[[int, Pose], tuple[float, float] | None]


def _velocity(v: Vector) -> dict[str, float]:
    return {"v_x": v[0], "v_y": v[1], "v_theta": v[2]}


def _lit(rgb: Rgb | None) -> TypeGuard[Rgb]:
    """Black with `turnas` 1 is dark, as K002 counts it."""
    return rgb is not None and any(c > 0 for c in rgb)


class Governor:
    def __init__(self, robot: Robot, profile: Profile = DEFAULT_PROFILE,
                 trace: Trace | None = None) -> None:
        self.robot = robot
        self.profile = profile
        self.trace = trace
        self.name = getattr(robot, "name", type(robot).__name__)
        p = profile
        self.rates = rates_of(p)
        self.commanded = ZERO  # the last command (script or operator)
        # What the wheels get: the velocity the limits allow, ramped late or centred on the
        # changes of a block's plan (scriptc/robot/motion.py).
        self.shaper = Shaper(self.rates)
        self.clamps = 0
        self.reasons: dict[str, int] = {}  # clamps by reason, in the order first met
        self._pending: int | None = None  # the instant whose command is still to be applied
        self._last_command = ZERO  # the command applied last
        self.nearest: Nearest | None = None
        # The LEDs: what the script asks, what is shown, the onsets shown in the last window,
        # and while an onset is held, when the window allows one. `wake(t)` (set by the
        # session) asks to be called back with `wake_led` at t.
        self.led_asked: Rgb | None = None
        self.led_shown: Rgb | None = None
        self.held_until: int | None = None
        self._onsets: deque[int] = deque()
        self._max_onsets = math.floor(p.max_led_flash_rate)  # K002: count > rate is too many
        self._show: Callable[[Rgb | None], None] | None = getattr(robot, "set_led", None)
        self.wake: Callable[[int], None] | None = None
        # The speaker: audio commands carry no volume, so the robot plays every track at one
        # level, and the governor sets it to the profile's maximum.
        set_volume = getattr(robot, "set_volume", None)
        if set_volume is not None:
            set_volume(p.max_volume)

    def __getattr__(self, name: str) -> object:
        """The backend's own attributes (`set_audio`, `time_ms`, ...), as the backend has them."""
        return getattr(self.robot, name)

    # -- velocity -----------------------------------------------------------------------------

    @property
    def target(self) -> tuple[float, float, float]:
        """The velocity the robot is at or ramping to."""
        return self.shaper.target

    @property
    def ramp(self) -> Ramp | None:
        """The ramp the robot follows (`motion.Ramp`), None when it is on its target."""
        return self.shaper.ramp

    def velocity_at(self, t_ms: int) -> tuple[float, float, float]:
        """The velocity the robot has at `t_ms` (from the last applied command on)."""
        return self.shaper.velocity(t_ms)

    def limit(self, v_x: float, v_y: float, v_theta: float,
              t_ms: int = 0) -> tuple[tuple[float, float, float], list[str]]:
        """The velocity the profile allows for a command at `t_ms`, and why it differs."""
        p = self.profile
        (v_x, v_y, v_theta), reasons = limit_speed((v_x, v_y, v_theta), p)
        if self.nearest is not None and (v_x or v_y):
            near = self.nearest(t_ms, self.robot.pose())
            if near is not None:
                distance, bearing = near
                c, s = math.cos(bearing), math.sin(bearing)
                if v_x * c + v_y * s > 0 and \
                        distance - self._braking(t_ms, c, s) < p.min_human_distance:
                    v_x = v_y = 0.0
                    reasons.append("human-distance")
        return (v_x, v_y, v_theta), reasons

    def _braking(self, t_ms: int, c: float, s: float) -> float:
        """How far toward the bearing (c, s) the robot goes if it brakes now at the limit (in a
        straight line, over max(|v_x|, |v_y|) / a: half its velocity times that)."""
        a = self.profile.max_linear_acceleration
        if not 0.0 < a < math.inf:
            return 0.0
        vx, vy, _ = self.velocity_at(t_ms)
        return max(0.0, (vx * c + vy * s) * max(abs(vx), abs(vy)) / (2.0 * a))

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float) -> None:
        """A command from `t_ms` on; applied at the end of that instant."""
        self._due(t_ms)
        self.commanded = (float(v_x), float(v_y), float(v_theta))

    def recheck(self, t_ms: int) -> None:
        """Sensing saw the people move: the limits are applied again at the end of the
        instant to the same command."""
        self._due(t_ms)

    def _due(self, t_ms: int) -> None:
        if self._pending is not None and t_ms > self._pending:
            self.flush()
        self._pending = t_ms

    def flush(self) -> None:
        """Apply the command of the pending instant, if any."""
        t = self._pending
        if t is None:
            return
        self._pending = None
        self._play(t)
        self.robot.advance(t)
        command = self.commanded
        target, reasons = self.limit(*command, t)
        new = command != self._last_command
        self._last_command = command
        shaper = self.shaper
        expected = shaper.expected_at(t)
        if expected is not None and (target != expected or self._anticipation_held(t)):
            shaper.drop()  # not what the plan expects: the changes are ramped late from now
        applied = shaper.velocity(t)
        ramped = shaper.late(t, target)
        if ramped:
            self.robot.set_velocity(t, *shaper.target, ramp=shaper.ramp)
            if ramped.get(0, 0) > 1:
                reasons.append("acceleration")
            if ramped.get(1, 0) > 1:
                reasons.append("angular-acceleration")
        if reasons and (ramped or new):
            fields: Event = {"reasons": reasons, "commanded": _velocity(command),
                             "applied": _velocity(applied)}
            ramp_ms = max(ramped.values(), default=0)
            if ramp_ms > 1:
                fields["target"] = _velocity(shaper.target)
                fields["ramp_ms"] = ramp_ms
            self._log(t, fields)

    # -- the plan of a block: ramps centred on the changes known ahead -------------------------

    def plan_block(self, t_ms: int, moves: Iterable[Move], length: int) -> None:
        """The actuators issue a block at `t_ms` that lasts `length` ms: its move track
        (`Move`s) is known ahead, so the motions whose ramps fit in the block are ramped centred
        on their changes (docs/robot.md, "Acceleration"), the others late, command by command."""
        self._due(t_ms)
        steps = track_steps(((m.v_x, m.v_y, m.v_theta), m.wait_t, m.duration) for m in moves)
        profile = self.profile
        self.shaper.plan(t_ms, length, [(t, limit_speed(v, profile)[0]) for t, v in steps],
                         limit_speed(self._last_command, profile)[0])

    def drop_plan(self, t_ms: int) -> None:
        """Something the plan could not know changes the wheels at `t_ms` (the operator, a
        freeze, a rule's hold, the block dropped): no more centred ramps; the end of the
        instant applies the command, late, from the velocity the robot has."""
        self._due(t_ms)
        self._play(t_ms)
        self.shaper.drop()

    def _play(self, t_ms: int) -> None:
        """Start the centred ramps of the plan due by `t_ms`, each at its millisecond (the
        robot brought there first); one that would bring the robot toward a person closer than
        the limits allow drops the plan instead."""
        shaper = self.shaper
        while (planned := shaper.due(t_ms)) is not None:
            self.robot.advance(planned.at)
            if planned.group == 0 and self.nearest is not None:
                v_x, v_y = planned.values  # group 0: the plane
                if "human-distance" in self.limit(v_x, v_y, shaper.target[2], planned.at)[1]:
                    shaper.drop()
                    return
            shaper.start(planned)
            self.robot.set_velocity(planned.at, *shaper.target, ramp=shaper.ramp)

    def _anticipation_held(self, t_ms: int) -> bool:
        """Whether the robot ramps ahead of a change (a centred ramp) toward a velocity the
        people around it no longer allow."""
        if self.nearest is None or self.shaper.anticipating[0] is None:
            return False
        return "human-distance" in self.limit(*self.shaper.target, t_ms)[1]

    def _log(self, t_ms: int, fields: Event) -> None:
        self.clamps += 1
        for reason in fields["reasons"]:
            self.reasons[reason] = self.reasons.get(reason, 0) + 1
        if self.trace is not None:
            self.trace.emit(t_ms, "governor", **fields)

    def advance(self, t_ms: int) -> None:
        if self._pending is not None and t_ms > self._pending:
            self.flush()
        self._play(t_ms)
        self.robot.advance(t_ms)

    def pose(self) -> Pose:
        return self.robot.pose()

    def ghost(self) -> Governor:
        """A copy that moves on its own (`Robot.ghost`): its own backend ghost and plan, the
        same limits and people, no trace and no LEDs shown; the robot where it will be at a
        later millisecond, the plan's centred ramps played there, without moving this one."""
        twin = Governor.__new__(Governor)  # not copy.copy: `__getattr__` forwards to `robot`
        twin.__dict__.update(self.__dict__)
        twin.robot = self.robot.ghost()
        twin.shaper = copy.deepcopy(self.shaper)
        twin.trace = None
        twin.reasons = dict(self.reasons)
        twin._onsets = deque(self._onsets)
        twin._show = None
        return twin

    def end_instant(self, t_ms: int, led: Rgb | None) -> None:
        """The end of the instant `t_ms` (the session calls it after each): apply the pending
        command, show the LEDs the script asks for as far as the flash limit allows."""
        self.flush()
        self.show_led(t_ms, led)

    def come_to_rest(self, t_ms: int) -> int:
        """The session is over at `t_ms`: the robot brakes at the limit (from a command still
        running, the session's end is a zero command) and the backend is stepped until it is at
        rest. Returns the millisecond it is at rest."""
        self.flush()
        self._play(t_ms)
        self.shaper.drop()  # a run cut at `until` cuts the block's plan too
        if self.target != ZERO:
            self._pending = t_ms
            self.commanded = ZERO
            self.flush()
        rest = max(t_ms, self.ramp.end if self.ramp is not None else t_ms)
        self.robot.advance(rest)
        return rest

    # -- LEDs ---------------------------------------------------------------------------------

    def show_led(self, t_ms: int, rgb: Rgb | None) -> None:
        """The script asks for `rgb` (None: off) from `t_ms` on."""
        asked_before = self.led_asked
        self.led_asked = rgb
        if self.held_until is not None and t_ms >= self.held_until:
            self.held_until = None
        if not _lit(rgb) or _lit(self.led_shown):
            self._display(rgb)  # going dark, or a change while lit: never a flash
            return
        if self.held_until is not None:  # an onset is held: stay dark
            if not _lit(asked_before):  # a new onset, held as well
                self._hold(t_ms, rgb, self.held_until)
            return
        free = self._window_free(t_ms)
        if free is None or free > t_ms:
            self._hold(t_ms, rgb, free)
        else:
            self._onsets.append(t_ms)
            self._display(rgb)

    def wake_led(self, t_ms: int, rgb: Rgb | None) -> None:
        """The window of a held onset frees at `t_ms`: show what the script asks now."""
        if self.held_until is None or t_ms < self.held_until:
            return
        self.show_led(t_ms, rgb)

    def _window_free(self, t_ms: int) -> int | None:
        """When an onset is allowed (from `t_ms` on), None: never (a rate below 1 Hz)."""
        onsets = self._onsets
        while onsets and onsets[0] <= t_ms - WINDOW_MS:
            onsets.popleft()
        if self._max_onsets < 1:
            return None
        if len(onsets) < self._max_onsets:
            return t_ms
        return onsets[len(onsets) - self._max_onsets] + WINDOW_MS

    def _hold(self, t_ms: int, rgb: Rgb, until: int | None) -> None:
        self._display(None)
        if until is not None and self.held_until is None and self.wake is not None:
            self.wake(until)
        self.held_until = until
        self._log(t_ms, {"reasons": ["led-flash"], "commanded": {"led": list(rgb)},
                         "applied": {"led": None}, "until": until})

    def _display(self, rgb: Rgb | None) -> None:
        if rgb != self.led_shown:
            self.led_shown = rgb
            if self._show is not None:
                self._show(rgb)
