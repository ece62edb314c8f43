"""A test file (`*.test.toml`, docs/testing.md) as data: what to run and what the run must do.

A `TestFile` holds the scripts of the session (paths usable from the working folder), its
world (a `Scenario`, from a file or the inline `[world]` table), the robot, the governor, the
time limit and the expectations, each one of four kinds:

- `EventExpectation`: how many trace events of a kind, with fields of given values, fall in a
  window of time (`event`, `where`, `within`, `count`);
- `StateExpectation`: the robot's state at an instant or at the end (`at` with any of `pose`,
  `led`, `audio`, `block`);
- `SessionExpectation`: how the session ended and when (`outcome`, `time`);
- `DistanceExpectation`: a distance kept to a person, object or obstacle, or to every entity
  of a class (`distance`, `within`).

Every expectation knows where it is written (`span`: its `[[expect]]` table) and its name, so
a failure points at it. Everything here is plain data that a worker process receives whole.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from scriptc.runtime.scenario import Scenario
from scriptc.source import SourceFile, Span

# Where a run stops when the test does not say (ms of simulated time): ten minutes.
DEFAULT_UNTIL = 600_000
# The robot a test runs on when it does not say: the kinematic robot, exact and fast.
DEFAULT_ROBOT = "kinematic"
# How far a pose may be from the one expected when the test does not say (m, and rad).
DEFAULT_TOLERANCE = 0.01
# How far each channel of the colour lit may be from the one expected.
LED_TOLERANCE = 0.01
# The outcomes an `outcome` expectation may name (`interrupted` is no run's end in a test).
OUTCOMES = ("completed", "until", "stalled", "error")
# `at = "end"`: the state when the session is over (the robot at rest).
END = "end"
_START = Span(0, 0)


@dataclass(frozen=True, slots=True)
class Count:
    """How many events an `EventExpectation` wants: `op` is "==", ">=" or "<="."""

    op: str
    n: int

    def holds(self, found: int) -> bool:
        if self.op == "==":
            return found == self.n
        return found >= self.n if self.op == ">=" else found <= self.n

    def words(self, what: str, whats: str) -> str:
        """`at least 1 block event`, `exactly 2 ...`, `no ...` (`what`/`whats`: one, many)."""
        if self.n == 0 and self.op != ">=":
            return f"no {what}"
        noun = what if self.n == 1 else whats
        phrase = {"==": "exactly", ">=": "at least", "<=": "at most"}[self.op]
        return f"{phrase} {self.n} {noun}"


@dataclass(frozen=True, slots=True)
class Window:
    """[start, end] ms, both included; `end` None: to the end of the run."""

    start: int = 0
    end: int | None = None

    def holds(self, t: int) -> bool:
        return self.start <= t and (self.end is None or t <= self.end)

    @property
    def whole(self) -> bool:
        return self.start == 0 and self.end is None

    def words(self) -> str:
        if self.whole:
            return "during the run"
        if self.end is None:
            return f"from {self.start} ms on"
        return f"between {self.start} and {self.end} ms"


@dataclass(frozen=True, slots=True)
class EventExpectation:
    """An `[[expect]]` on the trace's events: which, where, how many times."""

    index: int  # 0-based, in the file's order
    name: str
    span: Span  # the `[[expect]]` table
    event: str
    where: dict[str, Any]
    within: Window
    count: Count

    def words(self) -> str:
        """What is expected: `at least 1 `block` event with label = "hello" between ..."""
        kind = f"`{self.event}` event"
        condition = f" with {where_words(self.where)}" if self.where else ""
        return f"{self.count.words(kind, kind + 's')}{condition} {self.within.words()}"


@dataclass(frozen=True, slots=True)
class PoseExpectation:
    """Any subset of x, y (m) and theta (rad), each within `tolerance`."""

    x: float | None
    y: float | None
    theta: float | None
    tolerance: float

    def axes(self) -> list[tuple[str, float]]:
        return [(axis, value) for axis, value in (("x", self.x), ("y", self.y),
                                                   ("theta", self.theta)) if value is not None]


@dataclass(frozen=True, slots=True)
class StateExpectation:
    """An `[[expect]]` on the state at a time (or at the end)."""

    index: int
    name: str
    span: Span
    at: int | None  # None: at the end
    pose: PoseExpectation | None
    led: tuple[float, float, float] | None  # the colour lit (None: not checked)
    led_off: bool  # `led = "off"`
    audio: str | None  # the track playing, "" for `"none"` (None: not checked)
    block: str | None  # the label of the block running, "" for `"none"` (None: not checked)

    def when(self) -> str:
        return "at the end" if self.at is None else f"at {self.at} ms"


@dataclass(frozen=True, slots=True)
class SessionExpectation:
    """An `[[expect]]` on how the session ends and how long it lasts."""

    index: int
    name: str
    span: Span
    outcome: str | None
    time_min: int | None
    time_max: int | None


@dataclass(frozen=True, slots=True)
class DistanceExpectation:
    """An `[[expect]]` on the robot's distance to an entity."""

    index: int
    name: str
    span: Span
    to: str  # `Class/ID`, or `Class/*`
    min: float
    within: Window

    def matches(self, objectid: str) -> bool:
        if self.to.endswith("/*"):
            return objectid.startswith(self.to[:-1])
        return objectid == self.to


Expectation = EventExpectation | StateExpectation | SessionExpectation | DistanceExpectation


@dataclass(frozen=True, slots=True)
class TestFile:
    """A test file read and checked (`scriptc.testing.read`). `path` is the file as named,
    `source` its text (named as shown), `scripts` the session's files as paths from the
    working folder, `world` the scenario (None: none), `world_arg` what `scriptc run --world`
    takes to replay it (the world file, or the test file itself for a `[world]` table),
    `governor` None when the test leaves it to the robot's default (decided by the caller,
    as `scriptc run` does)."""

    __test__ = False  # not a pytest class, despite its name

    path: str
    source: SourceFile
    description: str
    scripts: tuple[str, ...]
    world: Scenario | None
    world_arg: str | None
    robot: str = DEFAULT_ROBOT
    governor: bool | None = None
    until: int = DEFAULT_UNTIL
    expectations: tuple[Expectation, ...] = field(default=())
    # The span to point at for what concerns the test as a whole (its `scripts` key).
    head: Span = _START
    # `snapshot = true`: the span of its key (the trace must equal the snapshot file beside
    # the test: `scriptc.testing.snapshot`); None without it.
    snapshot: Span | None = None

    @property
    def instants(self) -> list[int]:
        """The milliseconds whose state an expectation reads (`at`), for the session to
        observe."""
        return sorted({e.at for e in self.expectations
                       if isinstance(e, StateExpectation) and e.at is not None})


def where_words(where: dict[str, Any]) -> str:
    """`label = "hello", command = {"track": "led"}`: the fields as the test writes them."""
    return ", ".join(f"{key} = {shown_value(value)}" for key, value in where.items())


def shown_value(value: Any) -> str:
    """A value of the trace or of a test in a message: JSON, compact."""
    return json.dumps(value, ensure_ascii=False, separators=(", ", ": "), default=str)
