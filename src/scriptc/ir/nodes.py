"""The typed IR of a script and of the rule grammar's conditions.

Every node is frozen and slotted and carries the `Span` of the text it came from (offsets in
the script, or in the JSON file for `scriptc check`). Numbers keep the text the user wrote,
because the thesis JSON emits speeds and colours as that text (JSON.md).

Names keep their sigil where the language writes one as part of a reference: an alias is
`?kid` (or `?THIS`), a variable `@count`, an attribute `$mood`; a class is `Human` (the `#`
is left out, since the registry knows classes by name) and a field `positionrho`.

A script is a tree: Script > Goal > Action > Block. Blocks are addressed by their position
(goal, action, block indices, all from 0), which is also the JSON path `goalG/actA/blkB`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Union

from scriptc.source import Span


# ---------------------------------------------------------------------------------------------
# Leaves


@dataclass(frozen=True, slots=True)
class Name:
    """An identifier as written (activity name, goal id, label, rule id, class, field...)."""

    text: str
    span: Span


@dataclass(frozen=True, slots=True)
class Number:
    """A number as written. `value` is None when the text is not a number at all (the
    diagnostic was reported where the text was read); the text is what the JSON emits."""

    text: str
    span: Span

    @property
    def value(self) -> float | None:
        try:
            return float(self.text)
        except ValueError:
            return None

    @property
    def is_integer_text(self) -> bool:
        """True when the text is a whole number written without fraction or exponent."""
        t = self.text.lstrip("+-")
        return t.isascii() and t.isdigit()

    @property
    def is_finite(self) -> bool:
        v = self.value
        return v is not None and math.isfinite(v)


@dataclass(frozen=True, slots=True)
class Text:
    """A string's value (escapes resolved) and the span of the whole literal."""

    value: str
    span: Span


# ---------------------------------------------------------------------------------------------
# Conditions (the rule grammar, LANGUAGE.md section 2)


@dataclass(frozen=True, slots=True)
class NumberValue:
    number: Number

    @property
    def span(self) -> Span:
        return self.number.span


@dataclass(frozen=True, slots=True)
class StringValue:
    text: Text

    @property
    def span(self) -> Span:
        return self.text.span


@dataclass(frozen=True, slots=True)
class AliasRef:
    """`?kid`, or `?THIS` when `name.text == "?THIS"` (see `is_this`)."""

    name: Name
    span: Span

    @property
    def is_this(self) -> bool:
        return self.name.text == "?THIS"


@dataclass(frozen=True, slots=True)
class FieldRef:
    """`?kid>&positionrho`: a fixed or updatable field of the aliased entity."""

    alias: AliasRef
    field: Name
    span: Span


@dataclass(frozen=True, slots=True)
class AttRef:
    """`?kid>$mood`: an attribute bound to the alias by an ATT assignment."""

    alias: AliasRef
    att: Name
    span: Span


@dataclass(frozen=True, slots=True)
class VarRef:
    """`@count`: a VAR's value."""

    name: Name
    span: Span


Value = Union[NumberValue, StringValue, AliasRef, FieldRef, AttRef, VarRef]


@dataclass(frozen=True, slots=True)
class Call:
    """`B: near(1.5)`, `F: now()`, `E: gt(a, b)`: kind is "B", "F" or "E"."""

    kind: str
    name: Name
    args: tuple[Value, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class FieldTest:
    """`?THIS>&positionrho OP< 1.5`; `op` is "OP=", "OP<" or "OP>"."""

    field: Name
    op: Name
    value: Value
    span: Span


@dataclass(frozen=True, slots=True)
class CallTest:
    """`B: near(1.5)` as a test of a CLASS assignment."""

    call: Call
    span: Span


Test = Union[FieldTest, CallTest]


@dataclass(frozen=True, slots=True)
class ClassAssignment:
    """`{CLASS #Human U ?kid (tests)}`."""

    class_name: Name
    scope: Name
    alias: AliasRef
    tests: tuple[Test, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class VarAssignment:
    """`{VAR @count U F: now()}`."""

    var: VarRef
    scope: Name
    call: Call
    span: Span


@dataclass(frozen=True, slots=True)
class AttAssignment:
    """`{ATT ?kid $mood U F: str("calm")}`."""

    alias: AliasRef
    att: Name
    scope: Name
    call: Call
    span: Span


Assignment = Union[ClassAssignment, VarAssignment, AttAssignment]


@dataclass(frozen=True, slots=True)
class CallEvaluation:
    """`{E: gt(?kid>&permanencetime, 2000)}`."""

    call: Call
    span: Span


@dataclass(frozen=True, slots=True)
class TrueEvaluation:
    """`{TRUE}` after the `!`: the condition is true once it is reached."""

    span: Span


Evaluation = Union[CallEvaluation, TrueEvaluation]


@dataclass(frozen=True, slots=True)
class Condition:
    """A whole condition. `bare_true` is the form `{TRUE}` (no `!`); otherwise the condition
    is `assignments ! evaluations` (either list may be empty)."""

    assignments: tuple[Assignment, ...]
    evaluations: tuple[Evaluation, ...]
    span: Span
    bare_true: bool = False

    @property
    def is_constant_true(self) -> bool:
        """True when the condition cannot be false: `{TRUE}`, or no assignments and a TRUE
        evaluation reached before any E function (thesis 4.3: TRUE ends the evaluation)."""
        if self.bare_true:
            return True
        if self.assignments:
            return False
        for ev in self.evaluations:
            if isinstance(ev, TrueEvaluation):
                return True
            return False
        return True  # "!" alone: an empty conjunction is true


# ---------------------------------------------------------------------------------------------
# Script


@dataclass(frozen=True, slots=True)
class RuleMessage:
    """One alfa or omega message (`[alfa:16, my_rule, "in", "out", A, M]`)."""

    kind: str  # "alfa" or "omega"
    rulecode: Number
    id: Name
    intopic: Text
    outtopic: Text
    action: Name  # one of A R D B C
    mutex: Name  # one of L M U
    span: Span


@dataclass(frozen=True, slots=True)
class MoveCommand:
    v_x: Number
    v_y: Number
    v_theta: Number
    wait_t: Number
    duration: Number
    span: Span


@dataclass(frozen=True, slots=True)
class LedCommand:
    r: Number
    g: Number
    b: Number
    turnas: Number
    wait_t: Number
    duration: Number
    span: Span


@dataclass(frozen=True, slots=True)
class AudioCommand:
    track_path: Text  # trimmed path; its span covers the path inside the string
    wait_t: Number
    duration: Number
    span: Span


Command = Union[MoveCommand, LedCommand, AudioCommand]


@dataclass(frozen=True, slots=True)
class InstructionBlock:
    label: Name | None
    moves: tuple[MoveCommand, ...]
    leds: tuple[LedCommand, ...]
    audios: tuple[AudioCommand, ...]
    span: Span

    @property
    def duration_ms(self) -> int | None:
        """How long the block runs: its three tracks start together and each runs its
        commands one after the other, `wait_t` then `duration` (RUNTIME.md), so the block
        lasts as long as its longest track. None when a time is not a whole number."""
        longest = 0
        for track in (self.moves, self.leds, self.audios):
            total = 0
            for command in track:
                wait, duration = command.wait_t.text, command.duration.text
                if not (wait.isdigit() and duration.isdigit() and wait.isascii()
                        and duration.isascii()):  # the common case first, then signs
                    if not (command.wait_t.is_integer_text
                            and command.duration.is_integer_text):
                        return None
                total += int(wait) + int(duration)
            if total > longest:
                longest = total
        return longest


@dataclass(frozen=True, slots=True)
class JumpBlock:
    """`TRJMP()`/`FLSJMP()` with no label continue with the next block (LANGUAGE.md)."""

    label: Name | None
    condition: Condition
    true_target: Name | None
    false_target: Name | None
    span: Span
    # The condition's text as written (for `toparse` the canonical text is emitted instead).
    condition_text: str = ""


@dataclass(frozen=True, slots=True)
class TerminusBlock:
    label: Name | None
    span: Span


@dataclass(frozen=True, slots=True)
class SensorBlock:
    """`blk_sens` (or `blk_sensor`): a stub for sensor messages with optional payload strings."""

    label: Name | None
    payload: tuple[Text, ...]
    span: Span


Block = Union[InstructionBlock, JumpBlock, TerminusBlock, SensorBlock]


@dataclass(frozen=True, slots=True)
class Action:
    blocks: tuple[Block, ...]
    span: Span  # the `[action]` item


@dataclass(frozen=True, slots=True)
class Goal:
    id: Name
    actions: tuple[Action, ...]
    span: Span  # the `[goal:ID]` item


@dataclass(frozen=True, slots=True)
class Script:
    name: Name
    alfa: tuple[RuleMessage, ...]
    omega: tuple[RuleMessage, ...]
    goals: tuple[Goal, ...]
    span: Span

    def blocks(self) -> list[tuple[tuple[int, int, int], Block]]:
        """Every block with its (goal, action, block) address, in execution order."""
        out = []
        for g, goal in enumerate(self.goals):
            for a, action in enumerate(goal.actions):
                for b, block in enumerate(action.blocks):
                    out.append(((g, a, b), block))
        return out


def block_path(address: tuple[int, int, int]) -> str:
    """The thesis JSON path of a block address: `goal0/act0/blk4`."""
    g, a, b = address
    return f"goal{g}/act{a}/blk{b}"
