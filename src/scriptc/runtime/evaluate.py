"""Evaluating rule-grammar conditions against the map (docs/rules.md, thesis 4.3): the one
semantics of conditions, whatever executor reads the script.

Three layers:

- `EvalContext`: the primitives any evaluator needs, whatever form the condition has
  (the IR here, bytecode in the VM): the three assignments (`assign_class` with the tests as
  checks: stable bindings, one alias per entity, oldest candidate first; `assign_var`;
  `assign_att`), reading aliases, fields, VARs and ATTs, calling B/F/E functions through the
  implementations table (`call`), and the bindings one evaluation made (`result`, for the
  trace).
- The parts of a condition, as closures over (`?THIS`, ctx): what reading a value means (a
  `Read`: `constant`, `variable`, `alias_id`, `field_of`, `attribute`, `this_id`,
  `this_field`), what a call means (`invoke`, `call`) and what a comparison means (`compare_op`
  of runtime/commands.py, and `comparison`, with the one fast path of `?THIS>&f OP number` as
  its `test`: a test of a CLASS assignment, run once per candidate).
  The VM (vm.py) builds its steps and its searches' checks from these, so the two executors
  cannot mean different things.
- `evaluate(condition, ctx)`: the condition as IR, compiled once to those parts
  (`compile_condition`). The block reader of `interp.py` uses it for jumps; the rule chain
  uses it for every rule's condition (rules are shared, whatever executor reads the script).

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
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

from scriptc.ir import nodes as ir
from scriptc.ir.walk import ConditionVisitor
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.commands import Value, compare_op, to_text
from scriptc.runtime.functions import CallContext, CallResult, FunctionError, Implementations
from scriptc.runtime.world import Entity, World

if TYPE_CHECKING:
    from scriptc.runtime.goals import Goals


class EvaluationError(RuntimeError):
    """A condition this map cannot evaluate: a CLASS assignment over a class the map does not
    hold. Only a program run although it was not checked has one (lint reports it as R001,
    code generation refuses it, a rule's condition is refused when the rule is made); an
    executor reading blocks stops the run with it (a `read` error), as with any fault of the
    program."""


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

    __slots__ = ("bindings", "functions", "goals", "made", "now", "on_error", "owner", "world")

    def __init__(self, world: World, bindings: Bindings, functions: Implementations,
                 goals: Goals | None = None,
                 on_error: Callable[[str], None] | None = None) -> None:
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

    def assign_class(self, alias: str, cls: str, scope: str, tests: Sequence[Check]) -> bool:
        """A CLASS assignment, whatever form its tests have (`test(entity, ctx)` runs one with
        the entity as `?THIS`): keep the entity the alias names while it passes every test (a
        stable identity), else release the alias and bind the oldest free candidate that
        passes them all. False when none does. The one place these rules live: evaluators
        call it."""
        current = self.bindings.lookup(alias)
        if current is not None:
            if current.cls == cls and all(test(current, self) for test in tests):
                self.bind(alias, current, scope)
                return True
            self.bindings.unbind(alias)
        if cls not in self.world.classes:
            raise EvaluationError(f"the map has no class `{cls}`")
        holder = self.bindings.holder
        candidates = self.world.candidates(cls)
        # Each candidate runs the tests (1,000 entities must cost well under a millisecond):
        # one test, the common case, is called directly. An entity holding another alias is
        # not a candidate (one alias per entity).
        if len(tests) == 1:
            (test,) = tests
            for entity in candidates:
                held = holder.get(id(entity))
                if (held is None or held == alias) and test(entity, self):
                    self.bind(alias, entity, scope)
                    return True
            return False
        for entity in candidates:
            held = holder.get(id(entity))
            if held is not None and held != alias:
                continue
            for test in tests:
                if not test(entity, self):
                    break
            else:
                self.bind(alias, entity, scope)
                return True
        return False

    def assign_var(self, name: str, value: Value, scope: str) -> bool:
        """A VAR assignment with its F function's result (None: the assignment fails). A VAR
        holds a text: another value (a number a bytecode program pushed) is stored as its
        text (`to_text`)."""
        if value is None:
            return False
        self.set_var(name, to_text(value), scope)
        return True

    def assign_att(self, alias: str, name: str, value: Value, scope: str) -> bool:
        """An ATT assignment: fails when the alias is not bound or there is no value; the value
        is stored as text, as a VAR's is."""
        if value is None or self.bindings.lookup(alias) is None:
            return False
        self.set_att(alias, name, to_text(value), scope)
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

    def call(self, name: str, kind: str, args: list[Value], this: Entity | None = None
             ) -> CallResult:
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

    def result(self, value: bool) -> Evaluation:
        return Evaluation(value, self.made)


# ---------------------------------------------------------------------------------------------
# The parts of a condition, as closures: THE meaning of reading a value, calling a function
# and comparing two values. Both executors build their conditions from these (the IR below,
# `compile_condition`; the VM from its instructions, vm.py), so a comparison or a call means
# one thing whatever form the script has.
#
# A part runs as `get(this, ctx)`: `this` is the candidate of a CLASS assignment's tests
# (`?THIS`), None elsewhere. A test (`Check`) runs only on a candidate, and only its truth
# counts.

Getter = Callable[["Entity | None", EvalContext], Value]
Check = Callable[[Entity, EvalContext], object]


class Read(NamedTuple):
    """A value of a condition: `get(this, ctx)` reads it. `this_field` names the field when it
    reads a field of `?THIS`, `constant` holds the number when it is a finite number constant:
    what the fast comparison (`comparison`) needs to know. `test`, when there is one, is the
    same value as a test of a candidate, in a faster form (`test_of`)."""

    get: Getter
    this_field: str | None = None
    constant: float | None = None
    test: Check | None = None


def test_of(read: Read) -> Check:
    """A value as a test of a CLASS assignment: its `test` when it has one, else `get`."""
    return read.get if read.test is None else read.test


def constant(value: Value) -> Read:
    """A constant: a number's value or a text."""
    number = value if type(value) is float and math.isfinite(value) else None
    return Read(lambda this, ctx: value, constant=number)


def variable(name: str) -> Read:
    """A VAR's value (missing if never assigned)."""
    return Read(lambda this, ctx: ctx.var(name))


def alias_id(alias: str) -> Read:
    """The id of the entity bound to `alias` (missing if not bound)."""

    def get(this: Entity | None, ctx: EvalContext) -> Value:
        entity = ctx.lookup(alias)
        return None if entity is None else entity.id

    return Read(get)


def this_id() -> Read:
    """The id of the candidate (`?THIS`)."""
    return Read(lambda this, ctx: None if this is None else this.id)


def field_of(alias: str, name: str) -> Read:
    """A field of the entity bound to `alias` (missing if unbound or not set)."""
    return Read(lambda this, ctx: ctx.field(ctx.lookup(alias), name))


def this_field(name: str) -> Read:
    """A field of the candidate (`?THIS>&name`; missing if not set)."""
    return Read(lambda this, ctx: None if this is None else this.fields.get(name),
                this_field=name)


def attribute(alias: str, name: str) -> Read:
    """An attribute of `alias` (missing if never assigned)."""
    return Read(lambda this, ctx: ctx.att(alias, name))


def invoke(ctx: EvalContext, name: str, kind: str, args: list[Value],
           this: Entity | None) -> Value:
    """A call of a function of `kind` with argument values: an F function's text (None: no
    value), a B or E function's truth value. A function that fails counts as false or no
    value (`EvalContext.call` reports it)."""
    result = ctx.call(name, kind, args, this)
    return result if kind == "F" else bool(result)


def call(name: str, kind: str, args: Sequence[Read]) -> Read:
    """A call (`invoke`) whose arguments are read left to right."""
    getters = tuple(a.get for a in args)
    if not getters:
        return Read(lambda this, ctx: invoke(ctx, name, kind, [], this))
    if len(getters) == 1:
        (only,) = getters
        return Read(lambda this, ctx: invoke(ctx, name, kind, [only(this, ctx)], this))
    return Read(lambda this, ctx: invoke(ctx, name, kind, [g(this, ctx) for g in getters],
                                         this))


_FAST_OPS: dict[str, Callable[[float, float], bool]] = {
    "OP<": operator.lt, "OP>": operator.gt, "OP=": operator.eq}


def comparison(op: str, left: Read, right: Read) -> Read:
    """Whether `left OPop right` holds (`compare_op`: as numbers when both are numbers, else as
    texts; false when either is missing). `?THIS>&field OP number`, the common test, runs once
    per candidate entity (1,000 entities must cost well under a millisecond): as a test
    (`test_of`), a finite numeric field is compared with the number directly, which is what
    `compare_op` does for two numbers (an infinity or NaN is no number to it: it compares their
    texts)."""
    lget, rget = left.get, right.get
    read = Read(lambda this, ctx: compare_op(op, lget(this, ctx), rget(this, ctx)))
    if left.this_field is not None and right.constant is not None and op in _FAST_OPS:
        fast, name, number = _FAST_OPS[op], left.this_field, right.constant

        def check(this: Entity, ctx: EvalContext) -> bool:
            v = this.fields.get(name)
            if type(v) is float:
                if v - v == 0:  # finite: compared as numbers
                    return fast(v, number)
            elif type(v) is int:
                return fast(v, number)
            return v is not None and compare_op(op, v, number)

        return read._replace(test=check)
    return read


# ---------------------------------------------------------------------------------------------
# Conditions in the IR, compiled to those parts


def _bare(text: str, sigil: str) -> str:
    return text[1:] if text.startswith(sigil) else text


Step = Callable[[EvalContext], bool]


class _Compiler(ConditionVisitor):
    """Each kind of node as its part: a value as a `Read`, a test as a `Check`, an assignment
    as a `Step`."""

    def visit_number(self, value: ir.NumberValue) -> Read:
        return constant(value.number.value)

    def visit_string(self, value: ir.StringValue) -> Read:
        return constant(value.text.value)

    def visit_field(self, value: ir.FieldRef) -> Read:
        name = _bare(value.field.text, "&")
        return this_field(name) if value.alias.is_this else field_of(value.alias.name.text, name)

    def visit_alias(self, value: ir.AliasRef) -> Read:
        return this_id() if value.is_this else alias_id(value.name.text)

    def visit_var(self, value: ir.VarRef) -> Read:
        return variable(value.name.text)

    def visit_att(self, value: ir.AttRef) -> Read:
        return attribute(value.alias.name.text, _bare(value.att.text, "$"))

    def visit_call_test(self, test: ir.CallTest) -> Check:
        return _call_of(test.call).get

    def visit_field_test(self, test: ir.FieldTest) -> Check:
        return test_of(comparison(test.op.text, this_field(_bare(test.field.text, "&")),
                                  read_of(test.value)))

    def visit_class_assignment(self, asg: ir.ClassAssignment) -> Step:
        checks = tuple(check_of(t) for t in asg.tests)
        alias, cls, scope = asg.alias.name.text, _bare(asg.class_name.text, "#"), asg.scope.text
        return lambda ctx: ctx.assign_class(alias, cls, scope, checks)

    def visit_var_assignment(self, asg: ir.VarAssignment) -> Step:
        get, scope, name = _call_of(asg.call).get, asg.scope.text, asg.var.name.text
        return lambda ctx: ctx.assign_var(name, get(None, ctx), scope)

    def visit_att_assignment(self, asg: ir.AttAssignment) -> Step:
        get, scope = _call_of(asg.call).get, asg.scope.text
        alias, att = asg.alias.name.text, _bare(asg.att.text, "$")
        # The F function is not called for an unbound alias.
        return lambda ctx: (ctx.lookup(alias) is not None
                            and ctx.assign_att(alias, att, get(None, ctx), scope))


_compile = _Compiler().visit


def read_of(value: ir.Value) -> Read:
    """An argument or the right side of a test."""
    read: Read = _compile(value)
    return read


def _call_of(node: ir.Call) -> Read:
    return call(node.name.text, node.kind, [read_of(a) for a in node.args])


def check_of(test: ir.Test) -> Check:
    """A test of a CLASS assignment as a check over (`?THIS`, ctx)."""
    check: Check = _compile(test)
    return check


def compile_condition(condition: ir.Condition) -> Step:
    """The condition as one function of the context: its value (see the module's docstring;
    the bindings it made are the context's)."""
    if condition.bare_true:
        return lambda ctx: True
    steps: list[Step] = [_compile(a) for a in condition.assignments]
    for ev in condition.evaluations:
        if isinstance(ev, ir.TrueEvaluation):
            break  # true at once: what follows is never evaluated
        steps.append(_evaluation(_call_of(ev.call).get))
    if len(steps) == 1:
        return steps[0]

    def run(ctx: EvalContext) -> bool:
        for step in steps:  # noqa: SIM110 - a loop: `all` over a generator costs more per pass
            if not step(ctx):
                return False
        return True

    return run


def _evaluation(get: Getter) -> Step:
    """An E function's call as a step of a condition: its truth value (a bool already, from
    `invoke`, for an E function; the condition's value is a truth value whatever it gives)."""
    return lambda ctx: bool(get(None, ctx))


# Compiled conditions by the identity of the IR node (kept alive here, so an id is never
# reused while its entry exists): the rule chain evaluates the same conditions again and again.
_COMPILED: dict[int, tuple[ir.Condition, Step]] = {}
_MAX_COMPILED = 10_000


def compiled(condition: ir.Condition) -> Step:
    """`compile_condition`, once per condition."""
    entry = _COMPILED.get(id(condition))
    if entry is None or entry[0] is not condition:
        if len(_COMPILED) >= _MAX_COMPILED:
            _COMPILED.clear()
        entry = _COMPILED[id(condition)] = (condition, compile_condition(condition))
    return entry[1]


def evaluate(condition: ir.Condition, ctx: EvalContext) -> Evaluation:
    """The value of a condition (see the module's docstring). Call `ctx.begin(owner, now)`
    first."""
    entry = _COMPILED.get(id(condition))  # `compiled`, inline: rules evaluate at every pass
    run = entry[1] if entry is not None and entry[0] is condition else compiled(condition)
    return Evaluation(run(ctx), ctx.made)
