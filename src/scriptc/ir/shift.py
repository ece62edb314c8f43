"""Moving the spans of IR values and diagnostics: the one way to make a copy of a lowered value
that stands somewhere else in its text.

- `shift(value, delta)` moves every span by `delta` characters. The language server moves the
  IR an item lowered to before when an edit moves the item (`scriptc.ide.incremental`: a third
  of the cost of lowering it again); the thesis-JSON reader moves a condition parsed once to
  where each copy of its text stands.
- `map_spans(value, remap)` passes every span through `remap`: the thesis-JSON reader maps the
  spans of a condition parsed from a JSON string's value back to the characters of the JSON
  text (escapes make the value shorter than its text).

A value is one of the IR (`scriptc.ir.nodes`) or of the diagnostic model
(`scriptc.diagnostics.model`), or a tuple of them; strings, numbers, booleans, enums and None
are kept as they are. The rebuilding functions are generated once per dataclass from its
fields (a span field becomes its moved span, a tuple field a list comprehension, any other
field a recursive call), so a node type added to the IR later is handled without a change
here. A value of a type that is neither one of these dataclasses nor a leaf raises TypeError:
the caller then lowers the item afresh rather than keep a span it could not move.
"""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Callable
from types import ModuleType
from typing import Any, TypeAlias, TypeVar

from scriptc.diagnostics import model as _model
from scriptc.ir import nodes as _nodes
from scriptc.source import Span

__all__ = ["map_spans", "shift"]

# A function of one family: (a value, the family's argument: a delta or a remap) -> the value
# with its spans moved, of the same type. `exec` builds them from dataclass fields, so they are
# typed at this boundary; `shift` and `map_spans` say what comes out.
_Move: TypeAlias = Callable[[Any, Any], Any]
_Value = TypeVar("_Value")

_tuple_new = tuple.__new__
_LEAVES = (str, int, float, bool, enum.Enum)
# The generated functions of each dataclass, by family: "shift" takes a delta, "map" a remap.
_SHIFTERS: dict[type, _Move] = {}
_MAPPERS: dict[type, _Move] = {}
_FAMILIES = {"shift": _SHIFTERS, "map": _MAPPERS}
# A moved span, in each family: `x` is the span, `d` the delta or the remap.
_MOVED = {"shift": "tnew(S, ({x}[0] + d, {x}[1] + d))", "map": "d({x})"}


def _dispatcher(movers: dict[type, _Move], move_span: _Move) -> _Move:
    """The function that moves the spans of any value of one family: a dataclass through its
    generated function, a span through `move_span`, a tuple element by element."""

    def move_any(value: object, d: object) -> object:
        mover = movers.get(type(value))
        if mover is not None:
            return mover(value, d)
        if value is None:
            return None
        t = type(value)
        if t is Span:
            return move_span(value, d)
        if t is tuple and isinstance(value, tuple):  # (a plain tuple: not a named one)
            return tuple([move_any(v, d) for v in value])
        if isinstance(value, _LEAVES):
            return value
        raise TypeError(f"cannot move the spans of a {t.__name__}")

    return move_any


_shift_any = _dispatcher(_SHIFTERS, lambda span, d: _tuple_new(Span, (span[0] + d, span[1] + d)))
_map_any = _dispatcher(_MAPPERS, lambda span, remap: remap(span))

# One namespace for the generated functions, so that each can call the others by name.
_ENV: dict[str, object] = {"new": object.__new__, "S": Span, "tnew": _tuple_new,
                           "shift_any": _shift_any, "map_any": _map_any}


def _compile(cls: type, known: set[str], family: str) -> None:
    """Generate the function rebuilding one frozen, slotted dataclass with its spans moved.
    Fields are set through their slot descriptors: frozen dataclasses refuse `setattr`, and
    going through `__init__` would cost a call to `object.__setattr__` per field. A field
    whose annotation names one node class calls that class's function directly; unions go
    through the family's dispatcher, which dispatches on the type."""
    name = cls.__name__
    _ENV[f"C_{name}"] = cls
    lines = [f"def {family}_{name}(o, d):", f"    n = new(C_{name})"]
    for f in dataclasses.fields(cls):
        annotation = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
        setter = f"set_{name}_{f.name}"
        _ENV[setter] = cls.__dict__[f.name].__set__
        get = f"o.{f.name}"
        element = (annotation[len("tuple["):-len(", ...]")] if annotation.startswith("tuple[")
                   else "")
        optional = annotation[:-len(" | None")] if annotation.endswith(" | None") else ""
        if annotation == "Span":
            value = _MOVED[family].format(x=get)
        elif annotation in ("str", "bool", "int", "str | None"):
            value = get
        elif annotation in known:
            value = f"{family}_{annotation}({get}, d)"
        elif optional in known:
            lines.append(f"    v = {get}")
            value = f"None if v is None else {family}_{optional}(v, d)"
        elif element in known:
            value = f"tuple([{family}_{element}(x, d) for x in {get}])"
        elif element == "str":
            value = get
        elif annotation.startswith("tuple["):
            value = f"tuple([{family}_any(x, d) for x in {get}])"
        else:
            value = f"{family}_any({get}, d)"
        lines.append(f"    {setter}(n, {value})")
    lines.append("    return n")
    exec("\n".join(lines), _ENV)  # (code generated from the dataclass's fields only)
    move = _ENV[f"{family}_{name}"]
    assert callable(move)
    _FAMILIES[family][cls] = move


def _register(*modules: ModuleType) -> None:
    classes = [value for module in modules for value in vars(module).values()
               if isinstance(value, type) and dataclasses.is_dataclass(value)
               and value.__module__ == module.__name__ and "__slots__" in value.__dict__]
    known = {cls.__name__ for cls in classes}
    for cls in classes:
        for family in _FAMILIES:
            _compile(cls, known, family)


_register(_nodes, _model)


def shift(value: _Value, delta: int) -> _Value:
    """`value` with every span moved by `delta` characters (the value itself when 0)."""
    if delta == 0:
        return value
    moved: _Value = _shift_any(value, delta)
    return moved


def map_spans(value: _Value, remap: Callable[[Span], Span]) -> _Value:
    """`value` with every span replaced by `remap(span)`."""
    mapped: _Value = _map_any(value, remap)
    return mapped
