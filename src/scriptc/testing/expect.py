"""Each expectation of a test judged over its run (docs/testing.md): a `Verdict` that says
whether it holds, what was expected and what the run did instead.

Everything is read from what the run gave, never simulated again: the trace's events (the
`event` expectations count them; a `distance` is the one the robot perceives, from the
`update` events of `poses` applied to the map, each holding until the next), the states the
session observed at the instants the test names (`at`: `runtime.loop.Observation`, taken by
the session itself after everything at that millisecond) and at the end, and how the session
ended (`session_end`).

What the run did instead, for a failure: the events of the kind that come nearest to what was
expected (those that match but fall outside the window first, then those in the window with
the fewest fields that differ, nearest in time), the matching events when there are too many,
the whole state at the instant, or the closest approach to the entity.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from scriptc.runtime.loop import Observation
from scriptc.runtime.trace import Event
from scriptc.testing.model import (
    LED_TOLERANCE,
    DistanceExpectation,
    EventExpectation,
    Expectation,
    SessionExpectation,
    StateExpectation,
    shown_value,
)

__all__ = ["NEAREST", "Run", "Verdict", "judge", "matches", "shown_event", "state_words"]

# How many events a failure shows (the nearest ones, or the first of too many).
NEAREST = 3
# The longest an event is shown in a note (its fields as JSON, cut beyond this).
_SHOWN_EVENT = 160


@dataclass(frozen=True, slots=True)
class Run:
    """What a run gave that expectations read: the trace's events, the states observed by
    instant, the state at the end, and how and when the session ended."""

    events: Sequence[Event]
    observations: dict[int, Observation]
    final: Observation | None
    outcome: str
    time_ms: int


@dataclass(frozen=True, slots=True)
class Verdict:
    """One expectation judged: `passed`, and for people what was `expected`, what was
    `found` instead and `notes` (the nearest events, the state at the instant). `index` is
    the expectation's (None for the implicit one: a run must not stop on a run-time error
    unless the test expects an outcome; and for the snapshot). `code` is the diagnostic's
    when it fails: T006 for an expectation, T007 for the snapshot
    (`scriptc.testing.snapshot`)."""

    index: int | None
    name: str
    passed: bool
    expected: str
    found: str
    notes: tuple[str, ...] = ()
    code: str = "T006"

    def as_dict(self) -> dict[str, Any]:
        return {"index": self.index, "name": self.name, "code": self.code,
                "passed": self.passed, "expected": self.expected, "found": self.found,
                "notes": list(self.notes)}


def judge(expectations: Iterable[Expectation], run: Run) -> list[Verdict]:
    """The verdict of each expectation, in order; then, when no expectation names an outcome,
    the implicit one: the run did not stop on a fatal run-time error."""
    out: list[Verdict] = []
    outcome_named = False
    for e in expectations:
        if isinstance(e, EventExpectation):
            out.append(_event(e, run))
        elif isinstance(e, StateExpectation):
            out.append(_state(e, run))
        elif isinstance(e, SessionExpectation):
            outcome_named = outcome_named or e.outcome is not None
            out.append(_session(e, run))
        else:
            out.append(_distance(e, run))
    if not outcome_named and run.outcome == "error":
        errors = [e for e in run.events if e["event"] == "error" and e.get("fatal")]
        out.append(Verdict(None, "the run", False, "the run not to stop on a run-time error",
                           f"it stopped at {run.time_ms} ms", tuple(
                               f"at {e['t']} ms: {e['code']}: {e['message']}" for e in errors)))
    return out


# -- events ------------------------------------------------------------------------------------


def matches(expected: Any, actual: Any) -> bool:
    """Whether a value of the trace is what a test's `where` says: equal, a table matching a
    subset of the event's table (at any depth), arrays item by item; a number equals the same
    number written as an integer or not, but `true` is not 1."""
    if isinstance(expected, dict):
        return isinstance(actual, dict) and all(
            key in actual and matches(value, actual[key]) for key, value in expected.items())
    if isinstance(expected, list):
        return isinstance(actual, list) and len(actual) == len(expected) and all(
            matches(e, a) for e, a in zip(expected, actual, strict=True))
    if isinstance(expected, bool) or isinstance(actual, bool):
        return isinstance(expected, bool) and isinstance(actual, bool) and expected == actual
    return bool(expected == actual)


def _fields(event: Event) -> dict[str, Any]:
    return {k: v for k, v in event.items() if k not in ("t", "event")}


def shown_event(event: Event) -> str:
    """`at 5000 ms: {"label": "bye", ...}`: an event in a note."""
    text = shown_value(_fields(event))
    if len(text) > _SHOWN_EVENT:
        text = text[:_SHOWN_EVENT - 3] + "..."
    return f"at {event['t']} ms: {text}"


def _differing(where: dict[str, Any], event: Event) -> list[str]:
    return [key for key, value in where.items() if key not in event
            or not matches(value, event[key])]


def _event(e: EventExpectation, run: Run) -> Verdict:
    kind = [event for event in run.events if event["event"] == e.event]
    matching = [event for event in kind if matches(e.where, _fields(event))]
    inside = [event for event in matching if e.within.holds(event["t"])]
    found = len(inside)
    expected = e.words()
    if e.count.holds(found):
        return Verdict(e.index, e.name, True, expected, str(found))
    if found > e.count.n:  # too many: the first of them
        notes = [shown_event(event) for event in inside[:NEAREST]]
        if found > NEAREST:
            notes.append(f"and {found - NEAREST} more")
        return Verdict(e.index, e.name, False, expected, str(found),
                       (f"the matching events {e.within.words()}:", *notes))
    if not kind:
        return Verdict(e.index, e.name, False, expected, str(found),
                       (f"the run has no `{e.event}` event",))

    def distance(event: Event) -> int:
        t: int = event["t"]
        if e.within.holds(t):
            return 0
        return e.within.start - t if t < e.within.start else t - (e.within.end or t)

    # Nearest first: matching outside the window (by time), then in the window with the
    # fewest fields that differ; ties by time.
    candidates = [event for event in kind if event not in inside]
    candidates.sort(key=lambda event: (len(_differing(e.where, event)), distance(event),
                                       event["t"]))
    notes = [f"the nearest `{e.event}` events:"]
    for event in candidates[:NEAREST]:
        differ = _differing(e.where, event)
        why = f" ({', '.join(f'`{k}` differs' for k in differ)})" if differ else \
            " (outside the window)"
        notes.append(shown_event(event) + why)
    return Verdict(e.index, e.name, False, expected, str(found), tuple(notes))


# -- the state at an instant --------------------------------------------------------------------


def _rgb(rgb: tuple[float, float, float] | None) -> str:
    return "off" if rgb is None else f"[{', '.join(_number(c) for c in rgb)}]"


def _number(value: float) -> str:
    return f"{value:.6g}" if value == value else str(value)


def _named(value: str | None) -> str:
    return "none" if value is None else f"`{value}`"


def state_words(state: Observation) -> str:
    """The whole state at an instant, for a note."""
    pose = state.pose
    block = "none" if state.block is None else (
        f"`{state.block}` ({state.path} of `{state.script}`)" if state.block
        else f"{state.path} of `{state.script}` (no label)")
    return (f"pose x {_number(pose.x)}, y {_number(pose.y)}, theta {_number(pose.theta)}; "
            f"led {_rgb(state.led)}; audio {_named(state.audio)}; block {block}")


def _lit(rgb: tuple[float, float, float] | None) -> bool:
    return rgb is not None and any(c > 0 for c in rgb)


def _state(e: StateExpectation, run: Run) -> Verdict:
    checks: list[str] = []
    if e.pose is not None:
        checks.append("pose " + ", ".join(f"{axis} {_number(value)}"
                                          for axis, value in e.pose.axes())
                      + f" (within {_number(e.pose.tolerance)})")
    if e.led is not None or e.led_off:
        checks.append(f"led {_rgb(e.led)}")
    if e.audio is not None:
        checks.append(f"audio {_named(e.audio or None)}")
    if e.block is not None:
        checks.append(f"block {_named(e.block or None)}")
    expected = f"{e.when()}: {', '.join(checks)}"
    state = run.final if e.at is None else run.observations.get(e.at)
    if state is None:
        return Verdict(e.index, e.name, False, expected,
                       f"the run ended at {run.time_ms} ms (`{run.outcome}`)",
                       ("the state is known up to the end of the run",))
    wrong: list[str] = []
    if e.pose is not None:
        actual = state.pose._asdict()
        off = [f"{axis} {_number(actual[axis])}" for axis, value in e.pose.axes()
               if not abs(actual[axis] - value) <= e.pose.tolerance]
        if off:
            wrong.append("pose " + ", ".join(off))
    if (e.led_off and _lit(state.led)) or (e.led is not None and not (
            _lit(state.led) and state.led is not None
            and all(abs(a - b) <= LED_TOLERANCE for a, b in zip(state.led, e.led, strict=True)))):
        wrong.append(f"led {_rgb(state.led)}")
    if e.audio is not None and (state.audio or "") != e.audio:
        wrong.append(f"audio {_named(state.audio)}")
    if e.block is not None and (state.block if state.block is not None else "") != e.block:
        wrong.append(f"block {_named(state.block) if state.block != '' else state.path}")
    if not wrong:
        return Verdict(e.index, e.name, True, expected, "as expected")
    return Verdict(e.index, e.name, False, expected, ", ".join(wrong),
                   (f"the state {e.when()}: {state_words(state)}",))


# -- the session as a whole ---------------------------------------------------------------------


def _session(e: SessionExpectation, run: Run) -> Verdict:
    parts = []
    if e.outcome is not None:
        parts.append(f"the outcome `{e.outcome}`")
    if e.time_min is not None and e.time_max is not None:
        parts.append(f"the end between {e.time_min} and {e.time_max} ms")
    elif e.time_min is not None:
        parts.append(f"the end at {e.time_min} ms or later")
    elif e.time_max is not None:
        parts.append(f"the end by {e.time_max} ms")
    expected = " and ".join(parts)
    found = f"`{run.outcome}` at {run.time_ms} ms"
    passed = (e.outcome is None or run.outcome == e.outcome) and \
        (e.time_min is None or run.time_ms >= e.time_min) and \
        (e.time_max is None or run.time_ms <= e.time_max)
    if passed:
        return Verdict(e.index, e.name, True, expected, found)
    errors = [f"at {event['t']} ms: {event['code']}: {event['message']}"
              for event in run.events if event["event"] == "error"]
    unloads = [shown_event(event) for event in run.events if event["event"] == "script_unload"]
    notes = (("the run-time errors:", *errors) if errors else
             ("the scripts ended:", *unloads[-NEAREST:]) if unloads else
             ("no script ended",))
    return Verdict(e.index, e.name, False, expected, found, notes)


# -- a distance kept ----------------------------------------------------------------------------


def _distance(e: DistanceExpectation, run: Run) -> Verdict:
    """The distance to each entity the expectation names is the `positionrho` of the last
    `poses` update applied to it, from that update on: the value before the window holds at
    its start."""
    expected = f"`{e.to}` never closer than {_number(e.min)} m {e.within.words()}"
    before: dict[str, Event] = {}
    seen: list[tuple[float, Event]] = []
    for event in run.events:
        if event["event"] != "update" or event.get("status") != "applied" or \
                event.get("attributename") != "poses" or not e.matches(event["objectid"]):
            continue
        value = event.get("value")
        rho = value.get("positionrho") if isinstance(value, dict) else None
        if not isinstance(rho, (int, float)) or isinstance(rho, bool):
            continue
        t = event["t"]
        if t < e.within.start:
            before[event["objectid"]] = event
        elif e.within.end is None or t <= e.within.end:
            seen.append((float(rho), event))
            if t == e.within.start:  # the value before held until the window, not in it
                before.pop(event["objectid"], None)
    seen += [(float(event["value"]["positionrho"]), event) for event in before.values()]
    if not seen:
        return Verdict(e.index, e.name, True, expected, f"the run never placed `{e.to}`")
    seen.sort(key=lambda pair: (pair[0], pair[1]["t"]))
    closest, event = seen[0]
    where = f"{_number(closest)} m from `{event['objectid']}` at {event['t']} ms"
    if closest >= e.min:
        return Verdict(e.index, e.name, True, expected, f"the closest: {where}")
    too_close = [(rho, ev) for rho, ev in seen if rho < e.min]
    too_close.sort(key=lambda pair: pair[1]["t"])
    notes = [f"closer than {_number(e.min)} m:"]
    notes += [f"at {ev['t']} ms: {_number(rho)} m from `{ev['objectid']}`"
              for rho, ev in too_close[:NEAREST]]
    if len(too_close) > NEAREST:
        notes.append(f"and {len(too_close) - NEAREST} more updates")
    return Verdict(e.index, e.name, False, expected, where, tuple(notes))

