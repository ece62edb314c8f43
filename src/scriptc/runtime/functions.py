"""Run-time implementations of the rule grammar's B/F/E functions, and the registration API
for an activity's own functions. Shared by every executor.

`ir/builtins.py` holds the *signatures* the checker knows; this module holds the Python that
runs. An `Implementations` table maps a name to a `FunctionImpl` (name, kind, arity, callable,
doc) and can hand the checker the matching `FunctionRegistry` (`registry()`), so a script is
checked against exactly the functions that will run it.

A function is called as `fn(call, *args)`: `call` is a `CallContext` (the map, the time, the
candidate entity for a B function, the bindings, and `goal_reached`), `args` the evaluated
arguments: texts, numbers, or None for a missing value (an unbound alias, a field never set).
B and E functions return a truth value, F functions a text (a number is turned into text; None
makes the VAR/ATT assignment fail). A repository declares its functions in its configuration
(`[[functions]]`, read by `runtime/configured.py`); code registers them directly:

    impls = STANDARD_IMPLEMENTATIONS.extended()
    impls.register("closer", "E", 2, lambda call, a, b: ..., doc="...")
    Session(functions=impls, ...)
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from scriptc.ir.builtins import STANDARD_FUNCTIONS, Function, FunctionRegistry, Param
from scriptc.language import FUNCTION_KINDS, name_problem
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.commands import Value, as_number, compare, to_text
from scriptc.runtime.world import Entity, World

if TYPE_CHECKING:
    from scriptc.runtime.goals import Goals

# A function's Python, `fn(call, *args)`: the standard ones below, or an activity's own (any
# callable its configuration names). Its arguments are `Value`s; what it returns is checked
# by `Implementations.call` (a truth value, or a text, a number or None), so it is typed at
# this boundary as foreign code is.
FunctionBody = Callable[..., Any]

# What a call gives: a B/E function's truth value, an F function's text (None: no value).
CallResult = bool | str | None


class CallContext:
    """What a function sees besides its arguments."""

    __slots__ = ("bindings", "goals", "now", "this", "world")

    def __init__(self, world: World, now: int, this: Entity | None, bindings: Bindings,
                 goals: Goals | None) -> None:
        self.world = world
        self.now = now
        self.this = this  # the candidate entity of a CLASS assignment (B functions)
        self.bindings = bindings
        self.goals = goals  # the session's goal records (runtime/goals.py; may be None)

    def goal_reached(self, goalid: str) -> bool:
        """True when the map records `goalid` as reached by the running script since it was
        loaded (docs/runtime.md "Goals")."""
        if self.goals is None:
            return any(r.get("goalid") == goalid for r in self.world.goal_records("goalreached"))
        return self.goals.reached(goalid)


@dataclass(frozen=True, slots=True)
class FunctionImpl:
    """A B/F/E function's implementation with its name, kind and arity."""

    name: str
    kind: str
    arity: int
    fn: FunctionBody
    doc: str = ""
    params: tuple[str, ...] = ()
    origin: str = "standard"

    def signature(self) -> Function:
        """The signature the checker validates calls against."""
        names = self.params or tuple(f"arg{i + 1}" for i in range(self.arity))
        return Function(self.name, self.kind, tuple(Param(n, "") for n in names), self.doc,
                        self.origin)


class FunctionError(Exception):
    """A function failed at run time (unknown, wrong arity, or it raised): the call counts as
    false (B, E) or as a failed assignment (F), and the session reports it in the trace."""


class Implementations:
    """Function implementations by name (names are unique across kinds)."""

    def __init__(self, impls: Iterable[FunctionImpl] = ()) -> None:
        self._by_name: dict[str, FunctionImpl] = {}
        for impl in impls:
            self._by_name[impl.name] = impl

    def register(self, name: str, kind: str, arity: int, fn: FunctionBody, doc: str = "",
                 params: tuple[str, ...] = (), origin: str = "user") -> FunctionImpl:
        """Add (or replace) a function. `fn(call, *args)`; see the module's docstring."""
        if kind not in FUNCTION_KINDS:
            raise ValueError(f"a function's kind is one of {', '.join(FUNCTION_KINDS)}, "
                             f"not {kind!r}")
        problem = name_problem(name) if isinstance(name, str) else "a name is a string"
        if problem is not None:
            raise ValueError(f"{name!r} is not a function name: {problem}")
        if params and len(params) != arity:
            raise ValueError(f"{name}: {len(params)} parameter names for arity {arity}")
        impl = FunctionImpl(name, kind, arity, fn, doc, tuple(params), origin)
        self._by_name[name] = impl
        return impl

    def get(self, name: str) -> FunctionImpl | None:
        return self._by_name.get(name)

    def __iter__(self) -> Iterator[FunctionImpl]:
        return iter(self._by_name.values())

    def extended(self, impls: Iterable[FunctionImpl] = ()) -> Implementations:
        """A copy with more functions (the standard table is never changed in place)."""
        return Implementations([*self._by_name.values(), *impls])

    def registry(self) -> FunctionRegistry:
        """The signatures, for `check_script(..., functions=...)`."""
        return FunctionRegistry(impl.signature() for impl in self._by_name.values())

    def call(self, name: str, kind: str, args: list[Value], call: CallContext) -> CallResult:
        """Run a function; raises FunctionError when it cannot (see the class), or when what it
        gives is no value of its kind: an F function's result is a text, a number (as text)
        or None, a B or E function's anything with a truth value."""
        impl = self._by_name.get(name)
        if impl is None:
            raise FunctionError(f"no function `{name}` is registered")
        if impl.kind != kind:
            raise FunctionError(f"`{name}` is a {impl.kind} function, called as {kind}")
        if len(args) != impl.arity:
            raise FunctionError(f"`{name}` takes {impl.arity} argument(s), given {len(args)}")
        try:
            result = impl.fn(call, *args)
            if kind != "F":
                return bool(result)  # a truth value that raises is the function's failure
        except Exception as exc:  # a user's function must not stop the robot
            raise FunctionError(f"`{name}` raised {type(exc).__name__}: {exc}") from exc
        if result is None or isinstance(result, str):
            return result
        if isinstance(result, (int, float)):
            return to_text(result)
        raise FunctionError(f"`{name}` returned {type(result).__name__}, not a text or a "
                            "number")


# ---------------------------------------------------------------------------------------------
# The standard functions (signatures in ir/builtins.py, STANDARD_FUNCTIONS)


def _cmp(test: Callable[[int], bool]) -> Callable[..., bool]:
    def fn(call: CallContext, a: Value, b: Value) -> bool:
        c = compare(a, b)
        return c is not None and test(c)

    return fn


def _near(call: CallContext, distance: Value) -> bool:
    if call.this is None:
        return False
    rho, limit = as_number(call.this.fields.get("positionrho")), as_number(distance)
    return rho is not None and limit is not None and rho < limit


def _goalreached(call: CallContext, goalid: Value) -> bool:
    return goalid is not None and call.goal_reached(to_text(goalid) or "")


def _str(call: CallContext, value: Value) -> str | None:
    return to_text(value)


def _now(call: CallContext) -> str:
    return str(call.now)


_STANDARD_CALLABLES: dict[str, FunctionBody] = {
    "eq": _cmp(lambda c: c == 0),
    "neq": _cmp(lambda c: c != 0),
    "lt": _cmp(lambda c: c < 0),
    "gt": _cmp(lambda c: c > 0),
    "le": _cmp(lambda c: c <= 0),
    "ge": _cmp(lambda c: c >= 0),
    "goalreached": _goalreached,
    "near": _near,
    "str": _str,
    "now": _now,
}

STANDARD_IMPLEMENTATIONS = Implementations(
    FunctionImpl(f.name, f.kind, f.arity, _STANDARD_CALLABLES[f.name], f.doc,
                 tuple(p.name for p in f.params))
    for f in STANDARD_FUNCTIONS
)
