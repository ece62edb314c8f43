"""What a run's trace says over time, as the report draws it (`scriptc.views.report`): the
robot's path (recorded by `--report`'s `PathRecorder`, or reconstructed from the trace), where
the people, objects and obstacles were, the three tracks as segments (the LEDs as they were lit),
the commanded velocity, the events to mark on a timeline, the blocks the reader visited, and the
summary of the run.

Every function reads the trace's events as `runtime/trace.py` writes them, but a trace is a
file from outside (`scriptc report TRACE`): a field that is missing or of another type is read as
absent, never an exception. Nothing here reads the clock or iterates a set: the same events
give the same data.

**The path from the trace (decided).** A trace has no poses but the last (`session_end`): it
has every change of the velocity the wheels were given (`velocity`, body frame) and, with the
governor, every change it made to it (`governor`: the speed limits, a late ramp's `target`, a
person too close). `reconstruct_path` rebuilds what the governor gave the robot, group of axes
by group (`_changes`): a late ramp where a clamp says so; a change the limits allow in a
millisecond at once; any other change a ramp centred on it (the only other ramp the governor
makes, and the one it does not log); a ramp centred on a change that never came (the operator
froze the block first) from where the next clamp says it had brought the robot. It follows
that with the exact kinematics of `robot/motion.py`. That is the kinematic robot's path (within
a micrometre; every runtime case's trace ends at its `session_end` pose, and the examples'
recorded paths match); MuJoCo's differs by its physics (tens of micrometres on the examples,
3 cm over the ten minutes of bench/bench_mujoco.py); a hold the governor released when a
person moved away is not in the trace (the robot is held until the next command). `path_gap`
says how far the reconstruction ends from the pose the run ended at, and the page says it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from scriptc.robot.motion import (
    GROUPS,
    Kinematics,
    Ramp,
    Velocity,
    centred_ms,
    limit_ms,
    limit_speed,
    rates_of,
)
from scriptc.robot.profile import Profile
from scriptc.runtime.commands import TRACKS
from scriptc.runtime.recorded import Sample, command_intervals
from scriptc.runtime.trace import Event

__all__ = [
    "LANES",
    "TRACKS",
    "Marker",
    "Sample",
    "Segment",
    "Summary",
    "Visit",
    "end_ms",
    "markers",
    "path_gap",
    "profile_of",
    "reconstruct_path",
    "summarize_run",
    "thin_path",
    "track_segments",
    "velocity_steps",
    "visits",
]

# The lanes of the events' timeline, top to bottom.
LANES = ("script", "jumps", "rules", "operator", "governor", "errors")
# A marker's style (the page gives each its colour): plain, a condition that held, one that did
# not, a goal reached, a warning (the governor), an error.
PLAIN, HELD, NOT_HELD, REACHED, WARNING, ERROR = range(6)
# The path is sampled this often; a longer run is sampled less often, to at most MAX_SAMPLES.
EVERY_MS = 20
MAX_SAMPLES = 40_000


def _number(value: object) -> float | None:
    """A finite JSON number (not a boolean), else None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def _ms(value: object) -> int | None:
    """A whole, non-negative number of milliseconds, else None."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        return None
    return value


def _text(value: object) -> str:
    return value if isinstance(value, str) else ""


def _velocity(value: object) -> Velocity | None:
    """`{"v_x", "v_y", "v_theta"}` as a velocity, else None."""
    if not isinstance(value, dict):
        return None
    parts = [_number(value.get(k)) for k in ("v_x", "v_y", "v_theta")]
    if parts[0] is None or parts[1] is None or parts[2] is None:
        return None
    return (parts[0], parts[1], parts[2])


def _t(event: Event) -> int:
    return _ms(event.get("t")) or 0


def end_ms(events: Sequence[Event]) -> int:
    """The last millisecond the run shows: the session's end, or when the robot came to rest
    after it (the governor brakes), or the last event's time."""
    end = 0
    for e in events:
        end = max(end, _t(e))
        if e.get("event") == "session_end":
            end = max(end, _ms(e.get("time_ms")) or 0, _ms(e.get("at_rest_ms")) or 0)
    return end


def profile_of(events: Sequence[Event]) -> Profile | None:
    """The robot profile the governor kept (`session_start`'s `profile`), None without one."""
    for e in events:
        if e.get("event") != "session_start":
            continue
        given = e.get("profile")
        if not isinstance(given, dict):
            return None
        # The limits the trace gives (numbers, by the profile's field names): data from outside.
        values: dict[str, Any] = {k: _number(given.get(k)) for k in Profile().limits()}
        return replace(Profile(), **{k: v for k, v in values.items() if v is not None})
    return None


# -- the robot's path ---------------------------------------------------------------------------


# The reason a clamp gives for a late ramp of each group of axes (`GROUPS`: plane, turn).
_LATE = ("acceleration", "angular-acceleration")


@dataclass(frozen=True, slots=True)
class _Change:
    """A group of axes heads for `values` from `at`: over `steps` ms (a centred ramp), or, when
    `steps` is None, at the limit from the velocity it has then (a late ramp, or a step)."""

    at: int
    group: int
    values: tuple[float, ...]
    steps: int | None


def _changes(events: Sequence[Event], profile: Profile | None) -> list[_Change]:
    """What the governor did with the wheels, group by group, from the trace: every change the
    governor ramped late is a `governor` event (its `target`); a change of a group that the
    limits let it make at once (in a millisecond, from the velocity it has) is not; any other
    change was a ramp centred on it (`Shaper.plan`: `centred_ms` milliseconds, starting half of
    them before the change, from the velocity the plan expected before it)."""
    commands: dict[int, Velocity] = {}
    clamps: dict[int, Event] = {}
    for e in events:
        if e.get("event") == "velocity":
            v = _velocity(e)
            if v is not None:  # the last command of an instant is the one applied
                commands[_t(e)] = v
        elif e.get("event") == "governor" and profile is not None \
                and _velocity(e.get("commanded")) is not None:
            clamps[_t(e)] = e
    out: list[_Change] = []
    if profile is None:  # the wheels do what they are told, at once
        for t in sorted(commands):
            out += [_Change(t, g, commands[t][a[0]:a[-1] + 1], 0) for g, a in enumerate(GROUPS)]
        return out
    rates = rates_of(profile)
    groups = [_Group(len(axes)) for axes in GROUPS]
    for t in sorted({*commands, *clamps}):
        clamp = clamps.get(t)
        target = _velocity(clamp.get("target")) if clamp is not None else None
        reasons = clamp.get("reasons") if clamp is not None else None
        reasons = reasons if isinstance(reasons, list) else []
        if target is None:
            asked = commands.get(t) or _velocity(clamp.get("commanded") if clamp else None)
            if asked is None:
                continue
            target = limit_speed(asked, profile)[0]
            if "human-distance" in reasons:
                target = (0.0, 0.0, target[2])
        for g, axes in enumerate(GROUPS):
            lo, hi = axes[0], axes[-1] + 1
            values, group = target[lo:hi], groups[g]
            now = group.at(t)
            applied = _velocity(clamp.get("applied")) if clamp is not None else None
            if applied is not None and _LATE[g] in reasons \
                    and max(abs(a - b) for a, b in zip(applied[lo:hi], now, strict=True)) > 1e-9:
                # A ramp centred on a change that never came (the operator froze the block
                # first): the trace says only where it had brought the group. It went there at
                # the limit, ending now.
                k = limit_ms(now, applied[lo:hi], rates[lo:hi])
                group.head(max(0, t - k), now, applied[lo:hi], k)
                out.append(_Change(max(0, t - k), g, applied[lo:hi], k))
                now = applied[lo:hi]
            elif values == group.target:
                continue
            n = limit_ms(now, values, rates[lo:hi])
            if _LATE[g] in reasons or n <= 1:
                group.head(t, now, values, n)
                out.append(_Change(t, g, values, None))
            else:
                m = centred_ms(limit_ms(group.target, values, rates[lo:hi]))
                at = max(0, t - (m - 1) // 2)
                group.head(at, group.at(at), values, m)
                out.append(_Change(at, g, values, m))
    out.sort(key=lambda c: c.at)
    return out


class _Group:
    """The velocity of one group of axes over time, as `_changes` rebuilds it: on `target`
    from `t0 + steps`, ramping there from `start` before."""

    def __init__(self, size: int) -> None:
        self.t0, self.steps = 0, 0
        self.start = self.target = (0.0,) * size

    def at(self, t: int) -> tuple[float, ...]:
        k = t - self.t0
        if not self.steps or k >= self.steps:
            return self.target
        if k <= 0:
            return self.start
        return tuple(a + k * (b - a) / self.steps
                     for a, b in zip(self.start, self.target, strict=True))

    def head(self, t: int, now: tuple[float, ...], target: tuple[float, ...], steps: int) -> None:
        self.t0, self.start, self.target = t, now, target
        self.steps = steps if steps > 1 else 0


class _Wheels:
    """The velocity of each axis as the governor gives it (`Shaper._set`): a group's change
    ramps its axes from the velocity they have, the other axes keep their ramps."""

    def __init__(self, robot: Kinematics, profile: Profile | None) -> None:
        self.robot = robot
        self.rates = rates_of(profile) if profile is not None else (math.inf,) * 3
        self.t0s = [0, 0, 0]
        self.starts = [0.0, 0.0, 0.0]
        self.targets = [0.0, 0.0, 0.0]
        self.steps = [0, 0, 0]

    def value(self, i: int, t: int) -> float:
        k, n = t - self.t0s[i], self.steps[i]
        if k <= 0 or not n:
            return self.starts[i] if n else self.targets[i]
        if k >= n:
            return self.targets[i]
        return self.starts[i] + k * (self.targets[i] - self.starts[i]) / n

    def change(self, change: _Change) -> None:
        at = change.at
        self.robot.advance(at)
        now = [self.value(i, at) for i in range(3)]
        for i in range(3):
            if self.steps[i] and at >= self.t0s[i] + self.steps[i]:
                self.t0s[i], self.starts[i], self.steps[i] = at, self.targets[i], 0
        axes = GROUPS[change.group]
        lo, hi = axes[0], axes[-1] + 1
        n = change.steps if change.steps is not None else limit_ms(
            now[lo:hi], change.values, self.rates[lo:hi])
        for i, v in zip(axes, change.values, strict=True):
            self.t0s[i], self.starts[i], self.targets[i] = at, now[i], v
            self.steps[i] = n if n > 1 and now[i] != v else 0
        target = (self.targets[0], self.targets[1], self.targets[2])
        if any(self.steps):
            self.robot.set_velocity(at, *target, ramp=Ramp(self.t0s, self.starts, target,
                                                            self.steps))
        else:
            self.robot.set_velocity(at, *target)


def reconstruct_path(events: Sequence[Event], every_ms: int = EVERY_MS,
                     end: int | None = None) -> list[Sample]:
    """The robot's path from the trace's velocity changes (the module's docstring): a sample
    every `every_ms` from 0 to `end` (`end_ms`; less often past `MAX_SAMPLES`), and at the
    end."""
    # Ramps that turn while they move by quadrature (within a micrometre: `Kinematics`).
    robot = Kinematics(exact=False)
    wheels = _Wheels(robot, profile_of(events))
    changes = _changes(events, profile_of(events))
    end = end_ms(events) if end is None else end
    every = max(every_ms, math.ceil(end / MAX_SAMPLES / every_ms) * every_ms)
    samples: list[Sample] = [(0, 0.0, 0.0, 0.0)]
    i = 0
    for sample_t in [*range(every, end, every), end] if end > 0 else []:
        while i < len(changes) and changes[i].at <= sample_t:
            wheels.change(changes[i])
            i += 1
        robot.advance(sample_t)
        p = robot.pose()
        samples.append((sample_t, p.x, p.y, p.theta))
    return samples


def path_gap(samples: Sequence[Sample], events: Sequence[Event]) -> float | None:
    """How far (m) the path ends from the pose `session_end` gives (None: no such pose)."""
    for e in events:
        if e.get("event") == "session_end" and isinstance(e.get("pose"), dict):
            x, y = _number(e["pose"].get("x")), _number(e["pose"].get("y"))
            if x is None or y is None or not samples:
                return None
            return math.hypot(samples[-1][1] - x, samples[-1][2] - y)
    return None


def thin_path(samples: Sequence[Sample], most: int = MAX_SAMPLES) -> list[Sample]:
    """The samples a page needs: where the robot stands still, the first and last of the
    stretch only; then, if more than `most` are left, every k-th (the last always kept)."""
    kept: list[Sample] = []
    for i, s in enumerate(samples):
        if 0 < i < len(samples) - 1 and s[1:] == samples[i - 1][1:] == samples[i + 1][1:]:
            continue
        kept.append(s)
    if len(kept) > most:
        k = math.ceil(len(kept) / most)
        kept = [s for i, s in enumerate(kept) if i % k == 0 or i == len(kept) - 1]
    return kept


# -- the tracks ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Segment:
    """A command of a track from `start` to `end` (ms). `values`: a move's (v_x, v_y,
    v_theta); the LEDs' (r, g, b) and `lit` (1 lit, 0 off, 2 held dark by the governor's flash
    limit); an audio command's `name` (its track_path)."""

    start: int
    end: int
    values: tuple[float, float, float] = (0.0, 0.0, 0.0)
    lit: int = 0
    name: str = ""


def _held_dark(events: Sequence[Event]) -> list[tuple[int, int | None]]:
    """The LED onsets the governor held dark: (from, until; None: to the command's end)."""
    out = []
    for e in events:
        reasons = e.get("reasons")
        if e.get("event") == "governor" and isinstance(reasons, list) and "led-flash" in reasons:
            out.append((_t(e), _ms(e.get("until"))))
    return out


def track_segments(events: Sequence[Event], end: int | None = None) -> dict[str, list[Segment]]:
    """Each track's commands as segments, in time order; the LEDs as they were lit: an onset
    the governor held dark is dark (`lit` 2) until it let the LEDs show; a command still
    running at the end runs to `end` (`end_ms`)."""
    end = end_ms(events) if end is None else end
    out: dict[str, list[Segment]] = {track: [] for track in TRACKS}
    for track, start, stop, command in command_intervals(events, end):
        if track == "move":
            v = _velocity(command) or (0.0, 0.0, 0.0)
            out[track].append(Segment(start, stop, v))
        elif track == "led":
            rgb = [_number(command.get(k)) for k in ("r", "g", "b")]
            colour = (rgb[0] or 0.0, rgb[1] or 0.0, rgb[2] or 0.0)
            on = command.get("turnas") == 1
            out[track].append(Segment(start, stop, colour, 1 if on else 0))
        else:
            out[track].append(Segment(start, stop, name=_text(command.get("track_path"))))
    holds = _held_dark(events)
    if holds:
        out["led"] = _darken(out["led"], holds)
    return out


def _darken(segments: list[Segment], holds: list[tuple[int, int | None]]) -> list[Segment]:
    """The LED segments with each held stretch (from its onset to `until`, or to the end of
    the command it held) cut out and marked dark (`lit` 2)."""
    for at, given in holds:
        until = given if given is not None else next(
            (s.end for s in segments if s.start <= at < s.end), None)
        if until is None or until <= at:
            continue
        cut: list[Segment] = []
        for s in segments:
            lo, hi = max(s.start, at), min(s.end, until)
            if s.lit != 1 or lo >= hi:
                cut.append(s)
                continue
            if lo > s.start:
                cut.append(Segment(s.start, lo, s.values, 1))
            cut.append(Segment(lo, hi, s.values, 2))
            if hi < s.end:
                cut.append(Segment(hi, s.end, s.values, 1))
        segments = cut
    return segments


def velocity_steps(events: Iterable[Event]) -> list[tuple[int, Velocity]]:
    """The velocity the wheels were given (`velocity` events, body frame), as steps in time
    order; the last of a millisecond wins. Starts at rest at 0."""
    steps: list[tuple[int, Velocity]] = [(0, (0.0, 0.0, 0.0))]
    for e in events:
        if e.get("event") != "velocity":
            continue
        v = _velocity(e)
        if v is None:
            continue
        t = _t(e)
        if steps and steps[-1][0] == t:
            steps[-1] = (t, v)
        else:
            steps.append((t, v))
    return steps


# -- the events ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Marker:
    """An event on the timeline: its millisecond, its lane (`LANES`), its style and what it
    says."""

    t: int
    lane: int
    style: int
    text: str


def _v(value: object) -> str:
    v = _velocity(value)
    return "?" if v is None else f"({v[0]:g}, {v[1]:g}, {v[2]:g})"


def _describe(e: Event) -> tuple[int, int, str] | None:
    """(lane, style, text) of an event the timeline marks, None for the others."""
    kind = e.get("event")
    script = _text(e.get("script"))
    path = _text(e.get("path"))
    if kind == "script_load":
        shown = f" from {path}" if path else ""
        return 0, PLAIN, f"`{script}` loaded ({_text(e.get('reason'))}){shown}"
    if kind == "script_unload":
        return 0, PLAIN, f"`{script}` unloaded ({_text(e.get('reason'))})"
    if kind == "goal":
        record = _text(e.get("record"))
        by = f" by the rule `{_text(e.get('by'))}`" if e.get("by") else ""
        style = REACHED if record == "reached" else WARNING if record == "failed" else PLAIN
        return 0, style, f"goal `{_text(e.get('goalid'))}` {record}{by} ({script})"
    if kind == "override":
        return 0, WARNING, (f"override by `{_text(e.get('by'))}`: `{_text(e.get('script'))}` -> "
                            f"`{_text(e.get('to'))}` at {_text(e.get('at'))}")
    if kind == "terminus":
        return 1, PLAIN, f"terminus at {path} ({script})"
    if kind == "sensor":
        payload = e.get("payload")
        said = ", ".join(p for p in payload if isinstance(p, str)) \
            if isinstance(payload, list) else ""
        return 1, PLAIN, f"sensor at {path}: {said}"
    if kind == "jump":
        value = e.get("value") is True
        target = _text(e.get("target")) or "past the end"
        bindings = e.get("bindings")
        bound = ""
        if isinstance(bindings, dict) and bindings:
            bound = " with " + ", ".join(f"{k} = {_text(v)}" for k, v in bindings.items())
        return 1, HELD if value else NOT_HELD, (
            f"jump at {path}: {_text(e.get('condition'))} is {'true' if value else 'false'}"
            f"{bound} -> {target}")
    if kind == "rule":
        note = f" ({_text(e.get('note'))})" if e.get("note") else ""
        result = _text(e.get("result"))
        return 2, WARNING if result == "failed" else PLAIN, (
            f"{_text(e.get('message'))} of `{script}`: rule `{_text(e.get('id'))}` "
            f"{_text(e.get('action'))}/{_text(e.get('mutex'))} {result}{note}")
    if kind == "rule_fire":
        return 2, HELD, f"rule `{_text(e.get('id'))}` fires"
    if kind == "rule_note":
        return 2, PLAIN, f"rule `{_text(e.get('id'))}`: {_text(e.get('message'))}"
    if kind == "mutex":
        note = f": {_text(e.get('note'))}" if e.get("note") else ""
        return 2, PLAIN, f"map lock {_text(e.get('state'))} by `{_text(e.get('by'))}`{note}"
    if kind == "operator":
        command = _text(e.get("command"))
        words = [f"operator: {command}"]
        if command == "drive":
            words.append(_v(e))
        if isinstance(e.get("held"), bool):
            words.append("held" if e["held"] else "released")
        if isinstance(e.get("on"), bool):
            words.append("on" if e["on"] else "off")
        if e.get("ignored") is True:
            words.append("ignored (no safety lock)")
        return 3, WARNING if e.get("ignored") is True else PLAIN, " ".join(words)
    if kind == "governor":
        reasons = e.get("reasons")
        why = ", ".join(r for r in reasons if isinstance(r, str)) \
            if isinstance(reasons, list) else ""
        commanded, applied = e.get("commanded"), e.get("applied")
        if isinstance(commanded, dict) and "led" in commanded:
            until = _ms(e.get("until"))
            held = f"until {until} ms" if until is not None else "while the command lasts"
            return 4, WARNING, f"governor ({why}): the LEDs held dark {held}"
        text = f"governor ({why}): commanded {_v(commanded)}, applied {_v(applied)}"
        if "target" in e:
            text += f", ramp to {_v(e.get('target'))} in {_ms(e.get('ramp_ms')) or 0} ms"
        return 4, WARNING, text
    if kind == "error":
        fatal = " (fatal)" if e.get("fatal") is True else ""
        return 5, ERROR, f"error {_text(e.get('code'))}{fatal}: {_text(e.get('message'))}"
    return None


def markers(events: Iterable[Event]) -> list[Marker]:
    """The events the timeline marks (`LANES`), in the trace's order."""
    out = []
    for e in events:
        described = _describe(e)
        if described is not None:
            out.append(Marker(_t(e), *described))
    return out


# -- the blocks the reader visited --------------------------------------------------------------

ISSUED, JUMP_TRUE, JUMP_FALSE, TERMINUS, SENSOR, DONE = range(6)


@dataclass(frozen=True, slots=True)
class Visit:
    """The reader at a block of a script (`load`: the index of its `script_load` in the run)
    at `t`: an instruction block issued, a jump (true or false), a terminus, a sensor block,
    or the block consumed (`DONE`)."""

    t: int
    load: int
    path: str
    kind: int


_VISITS = {"block": ISSUED, "terminus": TERMINUS, "sensor": SENSOR, "block_done": DONE}


def visits(events: Iterable[Event]) -> tuple[list[tuple[str, str]], list[Visit]]:
    """The scripts loaded (`(script, path)` of each `script_load`, in order) and the blocks
    visited, each with the load of its script (the latest load of that name)."""
    loads: list[tuple[str, str]] = []
    latest: dict[str, int] = {}
    out: list[Visit] = []
    for e in events:
        kind = e.get("event")
        if kind == "script_load":
            script = _text(e.get("script"))
            latest[script] = len(loads)
            loads.append((script, _text(e.get("path"))))
            continue
        visit = _VISITS.get(kind) if isinstance(kind, str) else None
        if kind == "jump":
            visit = JUMP_TRUE if e.get("value") is True else JUMP_FALSE
        if visit is None:
            continue
        load = latest.get(_text(e.get("script")))
        if load is not None:
            out.append(Visit(_t(e), load, _text(e.get("path")), visit))
    return loads, out


# -- the summary --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Summary:
    """What the top of the report says: how the run ended, when, the goals recorded (script,
    goal, record; the last record of each), the errors (t, code, message, fatal), the
    governor's clamps by reason, the robot, the scenario, the scripts."""

    outcome: str
    time_ms: int
    at_rest_ms: int | None
    robot: str
    governed: bool
    scenario: str
    scripts: tuple[str, ...]
    goals: tuple[tuple[str, str, str], ...]
    errors: tuple[tuple[int, str, str, bool], ...]
    clamps: int
    reasons: tuple[tuple[str, int], ...]
    events: int
    pose: tuple[float, float, float] | None = field(default=None)


def summarize_run(events: Sequence[Event]) -> Summary:
    """The summary of the run the events tell (`Summary`); a trace cut short (no
    `session_end`) has the outcome `unfinished`."""
    outcome, time_ms, at_rest = "unfinished", end_ms(events), None
    robot, scenario, governed = "", "", False
    scripts: list[str] = []
    pose = None
    goals: dict[tuple[str, str], str] = {}
    errors = []
    reasons: dict[str, int] = {}
    clamps = 0
    for e in events:
        kind = e.get("event")
        if kind == "session_start":
            robot, scenario = _text(e.get("robot")), _text(e.get("scenario"))
            governed = isinstance(e.get("profile"), dict)
            listed = e.get("scripts")
            scripts = [s for s in listed if isinstance(s, str)] if isinstance(listed, list) \
                else []
        elif kind == "session_end":
            outcome = _text(e.get("outcome")) or outcome
            time_ms = _ms(e.get("time_ms")) or _t(e)
            at_rest = _ms(e.get("at_rest_ms"))
            given = e.get("pose")
            if isinstance(given, dict):
                parts = [_number(given.get(k)) for k in ("x", "y", "theta")]
                if parts[0] is not None and parts[1] is not None and parts[2] is not None:
                    pose = (parts[0], parts[1], parts[2])
        elif kind == "goal":
            goals[(_text(e.get("script")), _text(e.get("goalid")))] = _text(e.get("record"))
        elif kind == "error":
            errors.append((_t(e), _text(e.get("code")), _text(e.get("message")),
                           e.get("fatal") is True))
        elif kind == "governor":
            clamps += 1
            listed = e.get("reasons")
            for reason in listed if isinstance(listed, list) else ():
                if isinstance(reason, str):
                    reasons[reason] = reasons.get(reason, 0) + 1
    return Summary(outcome, time_ms, at_rest, robot, governed, scenario, tuple(scripts),
                   tuple((s, g, r) for (s, g), r in goals.items()), tuple(errors), clamps,
                   tuple(reasons.items()), len(events), pose)
