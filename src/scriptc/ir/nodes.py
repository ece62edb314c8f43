"""The typed IR of a script and of the rule grammar's conditions.

Every node is frozen and slotted and carries the `Span` of the text it came from (offsets in
the script, or in the JSON file for `scriptc check`). Numbers keep the text the user wrote,
because the thesis JSON emits speeds and colours as that text (docs/json.md).

Names keep their sigil where the language writes one as part of a reference: an alias is
`?kid` (or `?THIS`), a variable `@count`, an attribute `$mood`; a class is `Human` (the `#`
is left out, since the registry knows classes by name) and a field `positionrho`.

A script is a tree: Script > Goal > Action > Block. Blocks are addressed by their position
(goal, action, block indices, all from 0), which is also the JSON path `goalG/actA/blkB`.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, FrozenInstanceError, dataclass, fields, is_dataclass
from operator import attrgetter
from types import FunctionType
from typing import TYPE_CHECKING, TypeAlias, TypeVar, cast, dataclass_transform

from scriptc.source import Span

if TYPE_CHECKING:
    from collections.abc import Callable

_Node = TypeVar("_Node")


@dataclass(frozen=True)
class _Frozen:
    """Its parameters are what `@node` classes report as theirs (`__dataclass_params__`)."""


_FROZEN = _Frozen.__dataclass_params__  # type: ignore[attr-defined]  # set by dataclass
del _Frozen


@dataclass_transform(frozen_default=True)
def node(cls: type[_Node]) -> type[_Node]:
    """A frozen, slotted dataclass, built faster than `@dataclass(frozen=True, slots=True)`.

    `dataclass` is asked only for the fields and the slots (`dataclasses.fields` and `replace`
    work); the methods a frozen dataclass has are made here with the same meaning: `__init__`
    (positional or by name, defaults), `__repr__`, `__eq__` and `__hash__` by the fields'
    values in order, and `__setattr__` and `__delattr__` raising `FrozenInstanceError`. Making
    the classes is on every command's import path, and `dataclass` compiles six functions for
    each (a fifth of a cold `scriptc lint`): here only `__init__` is compiled, the others are
    closures over the field names. `__init__` calls each slot's own setter: the dataclass one
    goes through `object.__setattr__` for every field, a third of the cost of lowering a large
    script. Fields may have plain defaults (no factories, no `__post_init__`)."""
    undocumented = cls.__doc__ is None
    if undocumented:  # else dataclass would compute the class's signature: slow, at import
        cls.__doc__ = cls.__name__
    cls = dataclass(slots=True, init=False, repr=False, eq=False)(cls)
    assert is_dataclass(cls)
    names: list[str] = []
    params: list[str] = []
    namespace: dict[str, object] = {}
    for i, f in enumerate(fields(cls)):
        if f.default_factory is not MISSING:
            raise TypeError(f"{cls.__name__}.{f.name}: only plain fields and defaults")
        names.append(f.name)
        namespace[f"set_{i}"] = cls.__dict__[f.name].__set__
        if f.default is MISSING:
            params.append(f.name)
        else:
            namespace[f"default_{i}"] = f.default
            params.append(f"{f.name}=default_{i}")
    code = "\n".join([f"def __init__(self, {', '.join(params)}):",
                      *[f"    set_{i}(self, {n})" for i, n in enumerate(names)]])
    exec(code, namespace)  # (code generated from the class's field names only)
    methods = {"__init__": namespace["__init__"], **_methods(tuple(names))}
    for name, function in methods.items():
        assert isinstance(function, FunctionType)
        function.__qualname__ = f"{cls.__qualname__}.{name}"
        setattr(cls, name, function)
    if undocumented:  # what dataclass writes: the name and the fields
        cls.__doc__ = f"{cls.__name__}({', '.join(names)})"
    cls.__dataclass_params__ = _FROZEN  # type: ignore[attr-defined]  # what dataclass would say
    return cls


def _methods(names: tuple[str, ...]) -> dict[str, object]:
    """A node class's methods but `__init__`, over its field names."""
    values: Callable[[object], tuple[object, ...]]
    if len(names) == 1:
        get_one = attrgetter(names[0])

        def values(node: object) -> tuple[object, ...]:
            return (get_one(node),)
    else:  # a tuple of the values, made in C
        values = cast("Callable[[object], tuple[object, ...]]", attrgetter(*names))

    def __repr__(self: object) -> str:
        shown = ", ".join(f"{name}={value!r}"
                          for name, value in zip(names, values(self), strict=True))
        return f"{type(self).__qualname__}({shown})"

    def __eq__(self: object, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return bool(values(self) == values(other))

    def __hash__(self: object) -> int:
        return hash(values(self))

    def __setattr__(self: object, name: str, value: object) -> None:
        raise FrozenInstanceError(f"cannot assign to field {name!r}")

    def __delattr__(self: object, name: str) -> None:
        raise FrozenInstanceError(f"cannot delete field {name!r}")

    return {"__repr__": __repr__, "__eq__": __eq__, "__hash__": __hash__,
            "__setattr__": __setattr__, "__delattr__": __delattr__}


# ---------------------------------------------------------------------------------------------
# Leaves


@node
class Name:
    """An identifier as written (activity name, goal id, label, rule id, class, field...)."""

    text: str
    span: Span


@node
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


@node
class Text:
    """A string's value (escapes resolved) and the span of the whole literal."""

    value: str
    span: Span


# ---------------------------------------------------------------------------------------------
# Conditions (the rule grammar, docs/rules.md)


@node
class NumberValue:
    number: Number

    @property
    def span(self) -> Span:
        return self.number.span


@node
class StringValue:
    text: Text

    @property
    def span(self) -> Span:
        return self.text.span


@node
class AliasRef:
    """`?kid`, or `?THIS` when `name.text == "?THIS"` (see `is_this`)."""

    name: Name
    span: Span

    @property
    def is_this(self) -> bool:
        return self.name.text == "?THIS"


@node
class FieldRef:
    """`?kid>&positionrho`: a fixed or updatable field of the aliased entity."""

    alias: AliasRef
    field: Name
    span: Span


@node
class AttRef:
    """`?kid>$mood`: an attribute bound to the alias by an ATT assignment."""

    alias: AliasRef
    att: Name
    span: Span


@node
class VarRef:
    """`@count`: a VAR's value."""

    name: Name
    span: Span


Value: TypeAlias = NumberValue | StringValue | AliasRef | FieldRef | AttRef | VarRef


@node
class Call:
    """`B: near(1.5)`, `F: now()`, `E: gt(a, b)`: kind is "B", "F" or "E"."""

    kind: str
    name: Name
    args: tuple[Value, ...]
    span: Span


@node
class FieldTest:
    """`?THIS>&positionrho OP< 1.5`; `op` is "OP=", "OP<" or "OP>"."""

    field: Name
    op: Name
    value: Value
    span: Span


@node
class CallTest:
    """`B: near(1.5)` as a test of a CLASS assignment."""

    call: Call
    span: Span


Test: TypeAlias = FieldTest | CallTest


@node
class ClassAssignment:
    """`{CLASS #Human U ?kid (tests)}`."""

    class_name: Name
    scope: Name
    alias: AliasRef
    tests: tuple[Test, ...]
    span: Span


@node
class VarAssignment:
    """`{VAR @count U F: now()}`."""

    var: VarRef
    scope: Name
    call: Call
    span: Span


@node
class AttAssignment:
    """`{ATT ?kid $mood U F: str("calm")}`."""

    alias: AliasRef
    att: Name
    scope: Name
    call: Call
    span: Span


Assignment: TypeAlias = ClassAssignment | VarAssignment | AttAssignment


@node
class CallEvaluation:
    """`{E: gt(?kid>&permanencetime, 2000)}`."""

    call: Call
    span: Span


@node
class TrueEvaluation:
    """`{TRUE}` after the `!`: the condition is true once it is reached."""

    span: Span


Evaluation: TypeAlias = CallEvaluation | TrueEvaluation


@node
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
        if not self.evaluations:
            return True  # "!" alone: an empty conjunction is true
        return isinstance(self.evaluations[0], TrueEvaluation)


# ---------------------------------------------------------------------------------------------
# Script


@node
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


@node
class MoveCommand:
    v_x: Number
    v_y: Number
    v_theta: Number
    wait_t: Number
    duration: Number
    span: Span

    @property
    def texts(self) -> tuple[str, ...]:
        """The command as written, but for where: its track, then each field's text. Two
        commands alike (scripts repeat theirs) read and emit alike."""
        return ("MV", self.v_x.text, self.v_y.text, self.v_theta.text, self.wait_t.text,
                self.duration.text)


@node
class LedCommand:
    r: Number
    g: Number
    b: Number
    turnas: Number
    wait_t: Number
    duration: Number
    span: Span

    @property
    def texts(self) -> tuple[str, ...]:
        """As `MoveCommand.texts`."""
        return ("LD", self.r.text, self.g.text, self.b.text, self.turnas.text, self.wait_t.text,
                self.duration.text)


@node
class AudioCommand:
    track_path: Text  # trimmed path; its span covers the path inside the string
    wait_t: Number
    duration: Number
    span: Span

    @property
    def texts(self) -> tuple[str, ...]:
        """As `MoveCommand.texts` (the path's value: escapes resolved)."""
        return ("AO", self.track_path.value, self.wait_t.text, self.duration.text)


Command: TypeAlias = MoveCommand | LedCommand | AudioCommand


@node
class InstructionBlock:
    label: Name | None
    moves: tuple[MoveCommand, ...]
    leds: tuple[LedCommand, ...]
    audios: tuple[AudioCommand, ...]
    span: Span


@node
class JumpBlock:
    """`TRJMP()`/`FLSJMP()` with no label continue with the next block (docs/language.md)."""

    label: Name | None
    condition: Condition
    true_target: Name | None
    false_target: Name | None
    span: Span
    # The condition's text as written (for `toparse` the canonical text is emitted instead).
    condition_text: str = ""


@node
class TerminusBlock:
    label: Name | None
    span: Span


@node
class SensorBlock:
    """`blk_sens` (or `blk_sensor`): a stub for sensor messages with optional payload strings."""

    label: Name | None
    payload: tuple[Text, ...]
    span: Span


Block: TypeAlias = InstructionBlock | JumpBlock | TerminusBlock | SensorBlock


@node
class Action:
    blocks: tuple[Block, ...]
    span: Span  # the `[action]` item


@node
class Goal:
    id: Name
    actions: tuple[Action, ...]
    span: Span  # the `[goal:ID]` item


@node
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
