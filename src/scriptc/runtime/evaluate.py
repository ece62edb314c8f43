"""Evaluating rule-grammar conditions against the map (docs/rules.md, thesis 4.3).

Two layers:

- `EvalContext`: the primitives any evaluator needs, whatever form the condition has
  (the IR here, bytecode in a VM): the three assignments (`assign_class` with the tests as a
  predicate: stable bindings, one alias per entity, oldest candidate first; `assign_var`;
  `assign_att`), reading aliases, fields, VARs and ATTs, calling B/F/E functions through the
  implementations table (`call`), comparing values (`compare`: numeric when both sides are
  numbers, else text), and the bindings one evaluation made (`result`, for the trace). A
  bytecode VM calls these and nothing else.
- `evaluate(condition, ctx)`: the condition as IR, evaluated with those primitives. The block
  reader of `interp.py` uses it for jumps; the rule chain uses it for every rule's condition
  (rules are shared, whatever executor reads the script).

Meaning, in order:
1. `{TRUE}` alone is true.
2. Assignments run left to right. The first that cannot be made makes the condition false;
   the ones made before it stay bound. A CLASS assignment keeps the entity its alias already
   names while that entity still passes every test (a stable identity); otherwise the alias
   is released and the candidates of the class are tried oldest first, skipping entities
   that hold another alias: the first that passes every test is bound, with the
   assignment's scope. A VAR or ATT assignment fails when its F function gives nothing (or
   fails), an ATT also when its alias is not bound.
3. Evaluations run left to right: `{TRUE}` makes the condition true at once; an E function
   that is false makes it false. Past the last one (or with none) the condition is true.
A missing value (an unbound alias, a field never set, an unset VAR) satisfies no test.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from dataclasses import dataclass, field

from scriptc.ir import nodes as ir
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.functions import CallContext, FunctionError, Implementations
from scriptc.runtime.commands import Value, compare_op
from scriptc.runtime.world import Entity, World


@dataclass(slots=True)
class Evaluation:
    """The value of one condition and the bindings it made or kept, as text
    (`?kid` -> `Human/kid1`, `@v` -> `1200`, `?kid>$mood` -> `calm`)."""

    value: bool
    bindings: dict[str, str] = field(default_factory=dict)


class EvalContext:
    """The shared primitives of condition evaluation (see the module's docstring).

    `owner` is who evaluates (a rule id, or `bindings.READER` for the block reader): `L`
    bindings belong to it. `on_error(message)` is called when a function fails at run time.
    """

    __slots__ = ("world", "bindings", "functions", "goals", "now", "owner", "made",
                 "on_error")

    def __init__(self, world: World, bindings: Bindings, functions: Implementations,
                 goals=None, on_error=None) -> None:
        self.world = world
        self.bindings = bindings
        self.functions = functions
        self.goals = goals  # the session's goal records, for goalreached (may be None)
        self.now = 0
        self.owner = ""
        self.made: dict[str, str] = {}
        self.on_error = on_error

    def begin(self, owner: str, now: int) -> None:
        """Start one condition's evaluation."""
        self.owner = owner
        self.now = now
        self.made = {}

    # -- entities and aliases -----------------------------------------------------------------

    def candidates(self, cls: str) -> tuple[Entity, ...]:
        """The entities of a class, oldest first (`World.candidates`)."""
        return self.world.candidates(cls)

    def is_free_for(self, entity: Entity, alias: str) -> bool:
        """True when the entity holds no alias, or holds `alias` itself."""
        holder = self.bindings.holder.get(id(entity))
        return holder is None or holder == alias

    def lookup(self, alias: str) -> Entity | None:
        return self.bindings.lookup(alias)

    def bind(self, alias: str, entity: Entity, scope: str) -> None:
        self.bindings.bind(alias, entity, scope, self.owner)
        self.made[alias] = entity.key

    def unbind(self, alias: str) -> None:
        self.bindings.unbind(alias)

    def field(self, entity: Entity | None, name: str) -> Value:
        return None if entity is None else entity.fields.get(name)

    def assign_class(self, alias: str, cls: str, scope: str,
                     passes: Callable[[Entity], bool]) -> bool:
        """A CLASS assignment, whatever form its tests have (`passes(entity)` runs them with
        the entity as `?THIS`): keep the entity the alias names while it passes (a stable
        identity), else release the alias and bind the oldest free candidate that passes.
        False when none does. The one place these rules live: evaluators call it."""
        current = self.bindings.lookup(alias)
        if current is not None:
            if current.cls == cls and passes(current):
                self.bind(alias, current, scope)
                return True
            self.bindings.unbind(alias)
        holder = self.bindings.holder
        for entity in self.world.candidates(cls):
            # An entity holding another alias is not a candidate (one alias per entity).
            held = holder.get(id(entity))
            if held is not None and held != alias:
                continue
            if passes(entity):
                self.bind(alias, entity, scope)
                return True
        return False

    def assign_var(self, name: str, value: str | None, scope: str) -> bool:
        """A VAR assignment with its F function's result (None: the assignment fails)."""
        if value is None:
            return False
        self.set_var(name, value, scope)
        return True

    def assign_att(self, alias: str, name: str, value: str | None, scope: str) -> bool:
        """An ATT assignment: fails when the alias is not bound or there is no value."""
        if value is None or self.bindings.lookup(alias) is None:
            return False
        self.set_att(alias, name, value, scope)
        return True

    # -- VAR and ATT ------------------------------------------------------------------------

    def var(self, name: str) -> Value:
        return self.bindings.get_var(name)

    def set_var(self, name: str, value: str, scope: str) -> None:
        self.bindings.set_var(name, value, scope, self.owner)
        self.made[name] = value

    def att(self, alias: str, name: str) -> Value:
        return self.bindings.get_att(alias, name)

    def set_att(self, alias: str, name: str, value: str, scope: str) -> None:
        self.bindings.set_att(alias, name, value, scope, self.owner)
        self.made[f"{alias}>${name}"] = value

    # -- functions and comparisons ------------------------------------------------------------

    def call(self, name: str, kind: str, args: list[Value], this: Entity | None = None):
        """A B/E function's truth value, or an F function's text (None: no value). A function
        that fails is reported through `on_error` and counts as false / no value."""
        try:
            return self.functions.call(name, kind, args,
                                       CallContext(self.world, self.now, this, self.bindings,
                                                   self.goals))
        except FunctionError as exc:
            if self.on_error is not None:
                self.on_error(str(exc))
            return None if kind == "F" else False

    @staticmethod
    def compare(op: str, a: Value, b: Value) -> bool:
        return compare_op(op, a, b)

    def result(self, value: bool) -> Evaluation:
        return Evaluation(value, self.made)


# ---------------------------------------------------------------------------------------------
# The IR evaluator


def _bare(text: str, sigil: str) -> str:
    return text[1:] if text.startswith(sigil) else text


def value_of(value: ir.Value, ctx: EvalContext, this: Entity | None) -> Value:
    """An argument or the right side of a test."""
    if isinstance(value, ir.NumberValue):
        return value.number.value
    if isinstance(value, ir.StringValue):
        return value.text.value
    if isinstance(value, ir.FieldRef):
        entity = this if value.alias.is_this else ctx.lookup(value.alias.name.text)
        return ctx.field(entity, _bare(value.field.text, "&"))
    if isinstance(value, ir.AliasRef):
        entity = this if value.is_this else ctx.lookup(value.name.text)
        return None if entity is None else entity.id
    if isinstance(value, ir.VarRef):
        return ctx.var(value.name.text)
    if isinstance(value, ir.AttRef):
        return ctx.att(value.alias.name.text, _bare(value.att.text, "$"))
    raise TypeError(f"not a value: {value!r}")


def _call(call: ir.Call, ctx: EvalContext, this: Entity | None):
    args = [value_of(a, ctx, this) for a in call.args]
    return ctx.call(call.name.text, call.kind, args, this)


_FAST_OPS = {"OP<": operator.lt, "OP>": operator.gt, "OP=": operator.eq}

# Compiled tests of CLASS assignments, by the identity of the IR tuple (kept alive here, so an
# id is never reused while its entry exists). A test runs once per candidate entity, so this
# is the evaluator's inner loop: 1,000 entities must cost well under a millisecond.
_COMPILED: dict[int, tuple[tuple, tuple]] = {}


def _compile_test(test: ir.Test):
    """A test as `check(entity, ctx) -> bool`, with the same meaning as spelled out in
    `passes_slow`: a number constant on the right is read once, and a numeric field is
    compared without going through `compare_op`."""
    if isinstance(test, ir.CallTest):
        call = test.call
        return lambda entity, ctx: bool(_call(call, ctx, entity))
    name = _bare(test.field.text, "&")
    op = test.op.text
    value = test.value
    constant = value.number.value if isinstance(value, ir.NumberValue) else None
    if constant is not None and math.isfinite(constant) and op in _FAST_OPS:
        fast = _FAST_OPS[op]

        def check(entity: Entity, ctx: EvalContext) -> bool:
            v = entity.fields.get(name)
            kind = type(v)
            if kind is float or kind is int:
                return fast(v, constant)
            return v is not None and compare_op(op, v, constant)

        return check

    def check_general(entity: Entity, ctx: EvalContext) -> bool:
        v = entity.fields.get(name)
        return v is not None and compare_op(op, v, value_of(value, ctx, entity))

    return check_general


def compiled_tests(tests: tuple[ir.Test, ...]) -> tuple:
    entry = _COMPILED.get(id(tests))
    if entry is None or entry[0] is not tests:
        entry = _COMPILED[id(tests)] = (tests, tuple(_compile_test(t) for t in tests))
    return entry[1]


def passes(tests: tuple[ir.Test, ...], entity: Entity, ctx: EvalContext) -> bool:
    """True when `entity` (as `?THIS`) passes every test of a CLASS assignment."""
    for check in compiled_tests(tests):
        if not check(entity, ctx):
            return False
    return True


def passes_slow(tests: tuple[ir.Test, ...], entity: Entity, ctx: EvalContext) -> bool:
    """`passes`, written plainly (the meaning; tests hold the two equal)."""
    for test in tests:
        if isinstance(test, ir.FieldTest):
            left = entity.fields.get(_bare(test.field.text, "&"))
            right = value_of(test.value, ctx, entity)
            if left is None or not compare_op(test.op.text, left, right):
                return False
        elif not _call(test.call, ctx, entity):
            return False
    return True


def _assign_class(asg: ir.ClassAssignment, ctx: EvalContext) -> bool:
    checks = compiled_tests(asg.tests)
    if len(checks) == 1:
        check = checks[0]

        def passes_all(entity: Entity) -> bool:
            return check(entity, ctx)
    else:
        def passes_all(entity: Entity) -> bool:
            for check in checks:
                if not check(entity, ctx):
                    return False
            return True

    return ctx.assign_class(asg.alias.name.text, _bare(asg.class_name.text, "#"),
                            asg.scope.text, passes_all)


def _assign(asg: ir.Assignment, ctx: EvalContext) -> bool:
    if isinstance(asg, ir.ClassAssignment):
        return _assign_class(asg, ctx)
    if isinstance(asg, ir.VarAssignment):
        return ctx.assign_var(asg.var.name.text, _call(asg.call, ctx, None), asg.scope.text)
    if isinstance(asg, ir.AttAssignment):
        alias = asg.alias.name.text
        if ctx.lookup(alias) is None:
            return False  # the F function is not called for an unbound alias
        return ctx.assign_att(alias, _bare(asg.att.text, "$"), _call(asg.call, ctx, None),
                              asg.scope.text)
    raise TypeError(f"not an assignment: {asg!r}")


def evaluate(condition: ir.Condition, ctx: EvalContext) -> Evaluation:
    """The value of a condition (see the module's docstring). Call `ctx.begin(owner, now)`
    first."""
    if condition.bare_true:
        return ctx.result(True)
    for asg in condition.assignments:
        if not _assign(asg, ctx):
            return ctx.result(False)
    for ev in condition.evaluations:
        if isinstance(ev, ir.TrueEvaluation):
            return ctx.result(True)
        if not _call(ev.call, ctx, None):
            return ctx.result(False)
    return ctx.result(True)
