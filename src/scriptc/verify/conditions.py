"""How a jump's condition can come out, as the exploration sees it (docs/verify.md, "What is
exact and what is the world's").

A condition is read part by part, as the evaluator (`runtime/evaluate.py`) runs it: its
assignments left to right, then its evaluations up to a `{TRUE}`. Each part is one of:

- **constant**: true or false whatever happens (`{TRUE}`, a comparison of two constants, a
  CLASS test on the Activity's `startingtime`, a field the class never has);
- **timed**: decided by the robot's own clock, the running Activity's `elapsedtime`, compared
  with a number (in a CLASS `#Activity` assignment's tests or an E comparison of its alias):
  true exactly at a set of instants (`TimeSet`);
- **free**: the world's (an entity of the map: a Human, an Object, an Obstacle, their fields,
  a VAR or an ATT holding what was read from them, `goalreached`, which a sensor may record),
  or what verify does not model (a repository's own functions): either outcome is possible.

The script's variables are the robot's when what they hold is known: a VAR the script only
ever gives constant texts (`F: str("calm")`, `F: str(2)`, or another such VAR) is *tracked*:
a run's state holds its value (or that it is unset) with its scope, an assignment sets it, and
a comparison that reads it is decided (`branches_of`). Any other VAR (the time, `F: now()`;
what was read from the world) is the world's.

The whole condition is true when every part is (the evaluator stops at the first that fails),
so it can be true at the instants every timed part allows (unless a part is constant false or
a free part can never hold), and false at the instants some part can fail. A condition with no
free part is decided by the time alone: `Outcomes.world` is False and the two sets partition
time. This over-approximates what a world can do (each free part is taken as free on its own);
what verify claims exists is confirmed by replaying a concrete world (`verify/witness.py`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from scriptc.ir import nodes as ir
from scriptc.ir.walk import ConditionVisitor
from scriptc.runtime.bindings import SCOPE_RANK
from scriptc.runtime.commands import Value, as_number, compare, to_text
from scriptc.source import Span
from scriptc.verify.timeset import TimeSet

if TYPE_CHECKING:
    from scriptc.runtime.functions import Implementations

__all__ = ["ALWAYS", "NEVER", "Outcomes", "Part", "outcomes_of"]

# The standard comparisons, which verify computes itself when their operands are known.
_COMPARISONS = {
    "eq": lambda c: c == 0,
    "neq": lambda c: c != 0,
    "lt": lambda c: c < 0,
    "gt": lambda c: c > 0,
    "le": lambda c: c <= 0,
    "ge": lambda c: c >= 0,
}
_OPS = {"OP=": "eq", "OP<": "lt", "OP>": "gt"}
# Comparisons with the operands swapped (`c OP elapsed` is `elapsed OP' c`).
_SWAPPED = {"eq": "eq", "neq": "neq", "lt": "gt", "gt": "lt", "le": "ge", "ge": "le"}

ALWAYS = TimeSet.all()
NEVER = TimeSet.empty()


class _Top:
    """A value verify does not know: the world's, or what a function returns."""

    __repr__ = lambda self: "TOP"  # noqa: E731  # (a one-line repr for debugging)


class _Elapsed:
    """The running Activity's `elapsedtime`: the instant minus the script's start."""

    __repr__ = lambda self: "ELAPSED"  # noqa: E731


TOP = _Top()
ELAPSED = _Elapsed()


@dataclass(frozen=True, slots=True)
class Const:
    """A value known before the run: a number, a text, or missing (None)."""

    value: Value


Abstract = Const | _Top | _Elapsed


@dataclass(frozen=True, slots=True)
class Part:
    """One part of a condition and how it can come out: `true_at` and `false_at` are the
    instants (session times) at which it can be true and false; `world` is True when it is
    the world's (either outcome), `what` says what it is, for explanations."""

    true_at: TimeSet
    false_at: TimeSet
    world: bool
    what: str
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class Outcomes:
    """How a whole condition can come out: at which instants it can be true and false, and
    whether the world decides it (some part is free). `parts` are its parts up to a `{TRUE}`."""

    true_at: TimeSet
    false_at: TimeSet
    world: bool
    parts: tuple[Part, ...]


# A run's tracked variables: (name, value or None when unset, the rank of its scope in
# runtime.bindings.SCOPE_RANK, UNSET when unset), sorted by name.
Valuation = tuple[tuple[str, str | None, int], ...]
UNSET = -1


@dataclass(frozen=True, slots=True)
class Branch:
    """One way a condition can come out from a valuation of the tracked variables: the
    `outcome`, the instants it can (`at`), the valuation after it (the assignments made up
    to where the condition was decided), and whether the world decides it."""

    outcome: bool
    at: TimeSet
    valuation: Valuation
    world: bool


def runs_standard(name: str, functions: Implementations | None,
                  standard: Implementations) -> bool:
    """Whether the run's `name` (`functions`; None: the standard ones) is the standard
    implementation (a repository may not redefine one, but verify does not rely on that)."""
    ours = standard.get(name)
    theirs = ours if functions is None else functions.get(name)
    return ours is not None and theirs is ours


def _constant(value: bool, what: str, span: Span | None = None) -> Part:
    return Part(ALWAYS if value else NEVER, NEVER if value else ALWAYS, False, what, span)


def _free(what: str, span: Span | None = None) -> Part:
    return Part(ALWAYS, ALWAYS, True, what, span)


def _timed(at: TimeSet, what: str, span: Span | None = None) -> Part:
    return Part(at, ALWAYS - at, False, what, span)


def elapsed_compared(test: str, number: float, start: int = 0) -> TimeSet:
    """The instants `t >= 0` at which `elapsed OP number` holds, `elapsed` being `t - start`
    and `test` one of the standard comparisons (`gt`: elapsed > number). Exact for whole
    milliseconds: `elapsed > 20000.5` from 20001 on."""
    if test == "eq":
        at = TimeSet.point(int(number)) if number == int(number) else NEVER
    elif test == "neq":
        at = ALWAYS - (TimeSet.point(int(number)) if number == int(number) else NEVER)
    elif test in ("gt", "ge"):
        # elapsed > n from floor(n) + 1; elapsed >= n from ceil(n)
        first = math.floor(number) + 1 if test == "gt" else math.ceil(number)
        at = TimeSet.interval(max(first, 0), None) if first >= 0 else ALWAYS
    else:  # lt, le: elapsed < n up to ceil(n) - 1; elapsed <= n up to floor(n)
        last = math.ceil(number) - 1 if test == "lt" else math.floor(number)
        at = TimeSet.interval(0, last) if last >= 0 else NEVER
    return at.shift(start) if start else at


class _Reader(ConditionVisitor):
    """The parts of one condition (see the module's docstring)."""

    def __init__(self, functions: Implementations | None, standard: Implementations,
                 activity: str, exact_activity: bool,
                 values: dict[str, tuple[str | None, int]] | None = None) -> None:
        self.functions = functions
        self.standard = standard
        self.activity = activity  # the running script's name: its Activity's `activityid`
        self.exact_activity = exact_activity
        self.aliases: dict[str, str] = {}  # alias -> class, bound in this condition
        # The tracked variables' values as the condition runs (None: nothing is tracked).
        self.values = values

    # -- values ---------------------------------------------------------------------------------

    def visit_number(self, value: ir.NumberValue, this: str | None) -> Abstract:
        v = value.number.value
        return Const(v if v is not None and math.isfinite(v) else None)

    def visit_string(self, value: ir.StringValue, this: str | None) -> Abstract:
        return Const(value.text.value)

    def visit_alias(self, value: ir.AliasRef, this: str | None) -> Abstract:
        return TOP

    def visit_field(self, value: ir.FieldRef, this: str | None) -> Abstract:
        alias = value.alias.name.text
        cls = this if alias == "?THIS" else self.aliases.get(alias)
        if cls == "Activity" and self.exact_activity:
            return self._activity_field(value.field.text)
        return TOP

    def visit_att(self, value: ir.AttRef, this: str | None) -> Abstract:
        return TOP

    def visit_var(self, value: ir.VarRef, this: str | None) -> Abstract:
        values = self.values
        if values is not None and value.name.text in values:
            return Const(values[value.name.text][0])
        return TOP

    def _activity_field(self, name: str) -> Abstract:
        if name == "elapsedtime":
            return ELAPSED
        if name == "startingtime":
            return Const(0.0)
        if name in ("activityid", "id"):
            return Const(self.activity)
        return Const(None)  # a field an Activity never has: missing

    # -- comparisons ----------------------------------------------------------------------------

    def _compare(self, test: str, a: Abstract, b: Abstract, what: str, span: Span) -> Part:
        if isinstance(a, Const) and isinstance(b, Const):
            c = compare(a.value, b.value)
            return _constant(c is not None and _COMPARISONS[test](c), what, span)
        if isinstance(b, _Elapsed) and isinstance(a, Const):
            a, b, test = b, a, _SWAPPED[test]
        if isinstance(a, _Elapsed) and isinstance(b, Const):
            number = as_number(b.value)
            if b.value is None:
                return _constant(False, what, span)  # no comparison with a missing value holds
            if number is not None:
                return _timed(elapsed_compared(test, number), what, span)
        return _free(what, span)

    def _standard(self, name: str) -> bool:
        """Whether `name` is a standard comparison that runs the standard implementation."""
        return name in _COMPARISONS and self._runs_standard(name)

    # -- parts ----------------------------------------------------------------------------------

    def visit_class_assignment(self, a: ir.ClassAssignment) -> Part:
        cls = a.class_name.text
        alias = a.alias.name.text
        what = f"an entity of class `{cls}` that passes its tests"
        if cls != "Activity":
            self.aliases[alias] = cls
            if _contradictory(a.tests):
                return _constant(False, f"no `{cls}` can pass these tests", a.span)
            return _free(f"whether the world holds {what}", a.span)
        self.aliases[alias] = cls
        if not self.exact_activity:
            return _free("which Activity the alias names (several aliases name one)", a.span)
        parts = [self.visit(t, cls) for t in a.tests]
        return _conjunction(parts, f"the running activity passes its tests ({alias})", a.span)

    def visit_field_test(self, t: ir.FieldTest, this: str) -> Part:
        what = f"`?THIS>&{t.field.text} {t.op.text} ...`"
        left = self._activity_field(t.field.text)
        right = self.visit(t.value, this)
        return self._compare(_OPS[t.op.text], left, right, what, t.span)

    def visit_call_test(self, t: ir.CallTest, this: str) -> Part:
        return _free(f"what `{t.call.name.text}` says of the activity", t.span)

    def visit_var_assignment(self, a: ir.VarAssignment) -> Part:
        name = a.call.name.text
        values, var = self.values, a.var.name.text
        if values is not None and var in values:
            # A tracked variable: only `str` of a constant or of another tracked one.
            given = self.visit(a.call.args[0], None)
            assert isinstance(given, Const) and name == "str"
            text = to_text(given.value)
            if text is None:
                return _constant(False, f"`{var}` gets no value", a.span)
            # The longer scope is kept, as runtime.bindings.Bindings.set_var does.
            rank = max(SCOPE_RANK.get(a.scope.text, SCOPE_RANK["U"]), values[var][1])
            values[var] = (text, rank)
            return _constant(True, f"`{var}` takes the text `{text}`", a.span)
        if name == "now" and self._runs_standard("now"):
            return _constant(True, f"`{a.var.name.text}` takes the time", a.span)
        if name == "str" and self._runs_standard("str") and a.call.args:
            value = self.visit(a.call.args[0], None)
            if isinstance(value, Const):
                return _constant(value.value is not None, f"`{a.var.name.text}` takes a text",
                                 a.span)
            if isinstance(value, _Elapsed):
                return _constant(True, f"`{a.var.name.text}` takes the elapsed time", a.span)
        return _free(f"whether `{name}` gives `{a.var.name.text}` a value", a.span)

    def visit_att_assignment(self, a: ir.AttAssignment) -> Part:
        return _free(f"whether `{a.alias.name.text}` is bound and `{a.call.name.text}` gives "
                     "a value", a.span)

    def visit_call_evaluation(self, e: ir.CallEvaluation) -> Part:
        call = e.call
        name = call.name.text
        if self._standard(name) and len(call.args) == 2:
            a, b = (self.visit(v, None) for v in call.args)
            return self._compare(name, a, b, f"`{name}(...)`", e.span)
        if name == "goalreached":
            return _free("`goalreached` (a sensor may record a goal as reached)", e.span)
        return _free(f"what `{name}` says", e.span)

    def _runs_standard(self, name: str) -> bool:
        return runs_standard(name, self.functions, self.standard)


def _conjunction(parts: list[Part], what: str, span: Span) -> Part:
    """The parts all hold (a CLASS assignment's tests, or a whole condition)."""
    true_at, false_at, world = ALWAYS, NEVER, False
    for p in parts:
        true_at = true_at & p.true_at
        false_at = false_at | p.false_at
        world = world or p.world
    return Part(true_at, false_at, world, what, span)


def _contradictory(tests: tuple[ir.Test, ...]) -> bool:
    """Whether no entity can pass every test: comparisons of one field with numbers that no
    number satisfies together (`< 1` and `> 2`, `B: near(1)` and `positionrho OP> 3`), or
    equalities with two different values. Anything else an entity of the world can pass."""
    low: dict[str, tuple[float, bool]] = {}  # field -> (bound, strict)
    high: dict[str, tuple[float, bool]] = {}
    equal: dict[str, Value] = {}
    for test in tests:
        if isinstance(test, ir.CallTest):
            call = test.call
            if call.name.text == "near" and len(call.args) == 1 \
                    and isinstance(call.args[0], ir.NumberValue):
                limit = call.args[0].number.value
                if limit is not None and math.isfinite(limit):
                    _bound(high, "positionrho", limit, True, upper=True)
            continue
        value, field, op = test.value, test.field.text, test.op.text
        if isinstance(value, ir.NumberValue):
            number = value.number.value
            if number is None or not math.isfinite(number):
                continue
            if op == "OP<":
                _bound(high, field, number, True, upper=True)
            elif op == "OP>":
                _bound(low, field, number, True, upper=False)
            else:
                if field in equal and compare(equal[field], number) != 0:
                    return True
                equal[field] = number
                _bound(low, field, number, False, upper=False)
                _bound(high, field, number, False, upper=True)
        elif isinstance(value, ir.StringValue) and op == "OP=":
            text = value.text.value
            if field in equal and compare(equal[field], text) != 0:
                return True
            equal[field] = text
    for field, (lo, lo_strict) in low.items():
        if field in high:
            hi, hi_strict = high[field]
            if lo > hi or (lo == hi and (lo_strict or hi_strict)):
                return True
    return False


def _bound(table: dict[str, tuple[float, bool]], field: str, value: float, strict: bool, *,
           upper: bool) -> None:
    """Tighten the bound of `field` (an upper bound when `upper`, else a lower one)."""
    old = table.get(field)
    if old is None or (value < old[0] if upper else value > old[0]):
        table[field] = (value, strict)
    elif value == old[0]:
        table[field] = (value, strict or old[1])


def outcomes_of(condition: ir.Condition, *, activity: str, exact_activity: bool = True,
                functions: Implementations | None = None) -> Outcomes:
    """How `condition`, read by the block reader of the script `activity`, can come out (see
    the module's docstring). `exact_activity` is False when the script names the Activity by
    several aliases (one alias per entity may then refuse the second: verify leaves it to
    the world); `functions` are the implementations a run uses (None: the standard ones)."""
    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    if condition.is_constant_true:
        part = _constant(True, "`{TRUE}`", condition.span)
        return Outcomes(ALWAYS, NEVER, False, (part,))
    reader = _Reader(functions, STANDARD_IMPLEMENTATIONS, activity, exact_activity)
    parts: list[Part] = [reader.visit(a) for a in condition.assignments]
    for evaluation in condition.evaluations:
        if isinstance(evaluation, ir.TrueEvaluation):
            break
        parts.append(reader.visit(evaluation))
    whole = _conjunction(parts, "the condition", condition.span)
    return Outcomes(whole.true_at, whole.false_at, whole.world, tuple(parts))


def branches_of(condition: ir.Condition, valuation: Valuation, *, activity: str,
                exact_activity: bool = True, functions: Implementations | None = None
                ) -> list[Branch]:
    """How `condition` can come out when the tracked variables hold `valuation` (see the
    module's docstring): true when every part can be, with every assignment made; false
    where some part fails with those before it true, with the assignments before it made.
    Branches that lead to the same valuation with the same outcome are one."""
    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    if condition.is_constant_true:
        return [Branch(True, ALWAYS, valuation, False)]
    values = {name: (value, rank) for name, value, rank in valuation}
    reader = _Reader(functions, STANDARD_IMPLEMENTATIONS, activity, exact_activity, values)
    parts: list[Part] = []
    after: list[Valuation] = []  # the valuation once each part has run
    for node in (*condition.assignments, *condition.evaluations):
        if isinstance(node, ir.TrueEvaluation):
            break
        parts.append(reader.visit(node))
        after.append(tuple(sorted((name, v, r) for name, (v, r) in values.items())))
    out: dict[tuple[bool, Valuation], Branch] = {}

    def add(outcome: bool, at: TimeSet, result: Valuation, world: bool) -> None:
        if not at:
            return
        key = (outcome, result)
        had = out.get(key)
        out[key] = Branch(outcome, at, result, world) if had is None else Branch(
            outcome, had.at | at, result, had.world or world)

    held = ALWAYS  # the instants every part so far can hold at
    world = False
    for k, part in enumerate(parts):
        before = valuation if k == 0 else after[k - 1]
        add(False, held & part.false_at, before, world or part.world)
        held = held & part.true_at
        world = world or part.world
    add(True, held, after[-1] if after else valuation, world)
    return list(out.values())


def tracked_variables(conditions: list[ir.Condition], elsewhere: list[ir.Condition],
                      functions: Implementations | None = None) -> frozenset[str]:
    """The variables verify tracks (see the module's docstring): those the `conditions` (the
    script's jumps) give only constant texts, or the values of other tracked variables, with
    the standard `str`, and that no condition of `elsewhere` (the rules') assigns."""
    from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS

    str_is_standard = runs_standard("str", functions, STANDARD_IMPLEMENTATIONS)
    sources: dict[str, list[ir.Value | None]] = {}  # var -> what each assignment gives it
    for condition in conditions:
        for a in condition.assignments:
            if isinstance(a, ir.VarAssignment):
                given = (a.call.args[0] if a.call.name.text == "str" and str_is_standard
                         and len(a.call.args) == 1 else None)
                sources.setdefault(a.var.name.text, []).append(given)
    for condition in elsewhere:
        for a in condition.assignments:
            if isinstance(a, ir.VarAssignment):
                sources.setdefault(a.var.name.text, []).append(None)
    tracked = set(sources)
    changed = True
    while changed:  # a variable given another's value is tracked only if that one is
        changed = False
        for var in list(tracked):
            for given in sources[var]:
                ok = isinstance(given, (ir.NumberValue, ir.StringValue)) or (
                    isinstance(given, ir.VarRef) and given.name.text in tracked)
                if not ok:
                    tracked.discard(var)
                    changed = True
                    break
    return frozenset(tracked)
