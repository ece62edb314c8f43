"""Plain run-time values: what an executor hands the session and what the map stores.

Shared by every executor (the IR interpreter, the bytecode VM): commands are floats and whole
milliseconds, not IR nodes, so the actuators, rules and traces never see where a script came
from. Also the one answer to "is this a number" and "how do two values compare" at run time
(docs/rules.md: numeric when both sides are numbers, else text).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, overload

from scriptc.ir.fields import NUMBER_RE

# ---------------------------------------------------------------------------------------------
# Positions and commands


class BlockAddress(NamedTuple):
    """A block's address in its script: goal, action and block indices, all from 0."""

    goal: int
    action: int
    block: int

    @property
    def path(self) -> str:
        """The thesis JSON path, `goal0/act0/blk4`."""
        return f"goal{self.goal}/act{self.action}/blk{self.block}"


@dataclass(frozen=True, slots=True)
class Move:
    """Body-frame speeds (m/s, m/s, rad/s) and times (ms)."""

    v_x: float
    v_y: float
    v_theta: float
    wait_t: int
    duration: int

    def as_dict(self) -> dict[str, float]:
        return {"v_x": self.v_x, "v_y": self.v_y, "v_theta": self.v_theta,
                "wait_t": self.wait_t, "duration": self.duration}


@dataclass(frozen=True, slots=True)
class Led:
    """Colour channels in [0, 1]; `turnas` 1 lights the LEDs, 0 keeps them off."""

    r: float
    g: float
    b: float
    turnas: int
    wait_t: int
    duration: int

    def as_dict(self) -> dict[str, float]:
        return {"r": self.r, "g": self.g, "b": self.b, "turnas": self.turnas,
                "wait_t": self.wait_t, "duration": self.duration}


SILENCE = "Silence"


@dataclass(frozen=True, slots=True)
class Audio:
    """A track to play (`Silence` plays nothing but still takes its time)."""

    track_path: str
    wait_t: int
    duration: int

    def as_dict(self) -> dict[str, str | int]:
        return {"track_path": self.track_path, "wait_t": self.wait_t, "duration": self.duration}


Command = Move | Led | Audio

TRACKS = ("move", "led", "audioout")


@dataclass(frozen=True, slots=True)
class BlockCommands:
    """The commands of an instruction block as the actuators receive them: three tracks of
    timed commands."""

    moves: tuple[Move, ...] = ()
    leds: tuple[Led, ...] = ()
    audios: tuple[Audio, ...] = ()

    def track(self, index: int) -> tuple[Command, ...]:
        return (self.moves, self.leds, self.audios)[index]

    @property
    def length(self) -> int:
        """Milliseconds from issue to consumption when nothing interferes: the longest track,
        each track being the sum of its commands' `wait_t + duration` (docs/runtime.md)."""
        return max(sum(c.wait_t + c.duration for c in track)
                   for track in (self.moves, self.leds, self.audios))


@dataclass(frozen=True, slots=True)
class RuleMessage:
    """One alfa or omega message (thesis 4.4): which rule (`rulecode`, `id`), what to do with
    it (`action` A R D B C) and the mutex command (`mutex` L M U)."""

    kind: str  # "alfa" or "omega"
    rulecode: int
    id: str
    intopic: str
    outtopic: str
    action: str
    mutex: str


# ---------------------------------------------------------------------------------------------
# Values in conditions: text, numbers, or None for "missing" (a field never set, an unbound
# alias). A missing value never satisfies a test or a comparison.

Value = str | float | int | None


def as_number(value: Value) -> float | None:
    """The value as a number, or None when it is not one (or not finite)."""
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (int, float)):
        return float(value) if math.isfinite(value) else None
    text = value.strip()
    if NUMBER_RE.fullmatch(text) is None:
        return None
    number = float(text)
    return number if math.isfinite(number) else None


def format_number(number: float | int) -> str:
    """A number as text: whole numbers without a fraction (`2000`, not `2000.0`), others as
    the shortest text that reads back the same (`0.8`)."""
    if isinstance(number, int):
        return str(number)
    if number.is_integer() and abs(number) < 1e16:
        return str(int(number))
    return repr(number)


@overload
def to_text(value: None) -> None: ...
@overload
def to_text(value: str | float | int) -> str: ...
def to_text(value: Value) -> str | None:
    """The value as text (None stays None): numbers through `format_number`."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "s_true" if value else "s_false"
    return format_number(value)


def compare(a: Value, b: Value) -> int | None:
    """-1, 0 or 1 as `a` is below, equal to or above `b`: numerically when both are numbers
    (texts that read as numbers count), else as text by code points. None when either value
    is missing, so that no comparison with a missing value holds."""
    if a is None or b is None:
        return None
    x, y = as_number(a), as_number(b)
    if x is None or y is None:
        sa, sb = to_text(a), to_text(b)
        return (sa > sb) - (sa < sb)
    return (x > y) - (x < y)


def compare_op(op: str, a: Value, b: Value) -> bool:
    """A comparison of the rule grammar (`OP=`, `OP<`, `OP>`), false on a missing value."""
    c = compare(a, b)
    if c is None:
        return False
    if op == "OP=":
        return c == 0
    if op == "OP<":
        return c < 0
    if op == "OP>":
        return c > 0
    raise ValueError(f"unknown operator {op!r}")
