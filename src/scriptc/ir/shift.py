"""Moving lowered IR and diagnostics by a number of characters, for incremental analysis.

When an edit changes the length of the text, every item after it keeps its text but starts
at another offset. Lowering such an item again costs about 80 us; moving the IR it lowered
to before by `delta` costs a third of that. `shift(value, delta)` rebuilds a value of the
IR (`scriptc.ir.nodes`) or of the diagnostic model (`scriptc.diagnostics.model`) with every
`Span` moved; strings, numbers, booleans, enums and None are kept as they are.

The rebuilding functions are generated once per dataclass from its fields (a span field
becomes `Span(s + delta, e + delta)`, a tuple field a list comprehension, any other field a
recursive call), so a node type added to the IR later is handled without a change here. A
value of a type that is neither one of these dataclasses nor a leaf raises TypeError: the
caller then lowers the item afresh rather than keep a span it could not move.
"""

from __future__ import annotations

import dataclasses
import enum

from scriptc.diagnostics import model as _model
from scriptc.ir import nodes as _nodes
from scriptc.source import Span

__all__ = ["shift", "shift_span"]

_tuple_new = tuple.__new__
_LEAVES = (str, int, float, bool, enum.Enum)
_SHIFTERS: dict[type, object] = {}


def shift_span(span: Span, delta: int) -> Span:
    return _tuple_new(Span, (span[0] + delta, span[1] + delta))


def _shift_any(value, delta: int):
    shifter = _SHIFTERS.get(type(value))
    if shifter is not None:
        return shifter(value, delta)
    if value is None:
        return None
    t = type(value)
    if t is Span:
        return _tuple_new(Span, (value[0] + delta, value[1] + delta))
    if t is tuple:
        return tuple([_shift_any(v, delta) for v in value])
    if isinstance(value, _LEAVES):
        return value
    raise TypeError(f"cannot shift a {t.__name__}")


# One namespace for the generated functions, so that each can call the others by name.
_ENV: dict[str, object] = {"new": object.__new__, "S": Span, "tnew": _tuple_new, "any_": _shift_any}


def _compile(cls: type, known: set[str]) -> None:
    """Generate the function rebuilding one frozen, slotted dataclass with its spans moved.
    Fields are set through their slot descriptors: frozen dataclasses refuse `setattr`, and
    going through `__init__` would cost a call to `object.__setattr__` per field. A field
    whose annotation names one node class calls that class's function directly; unions go
    through `_shift_any`, which dispatches on the type."""
    name = cls.__name__
    _ENV[f"C_{name}"] = cls
    lines = [f"def shift_{name}(o, d):", f"    n = new(C_{name})"]
    for f in dataclasses.fields(cls):
        annotation = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
        setter = f"set_{name}_{f.name}"
        _ENV[setter] = cls.__dict__[f.name].__set__
        get = f"o.{f.name}"
        element = annotation[len("tuple["):-len(", ...]")] if annotation.startswith("tuple[") else ""
        optional = annotation[:-len(" | None")] if annotation.endswith(" | None") else ""
        if annotation == "Span":
            value = f"tnew(S, ({get}[0] + d, {get}[1] + d))"
        elif annotation in ("str", "bool", "int", "str | None"):
            value = get
        elif annotation in known:
            value = f"shift_{annotation}({get}, d)"
        elif optional in known:
            lines.append(f"    v = {get}")
            value = f"None if v is None else shift_{optional}(v, d)"
        elif element in known:
            value = f"tuple([shift_{element}(x, d) for x in {get}])"
        elif element in ("str", "Span"):
            value = get if element == "str" else f"tuple([any_(x, d) for x in {get}])"
        elif annotation.startswith("tuple["):
            value = f"tuple([any_(x, d) for x in {get}])"
        else:
            value = f"any_({get}, d)"
        lines.append(f"    {setter}(n, {value})")
    lines.append("    return n")
    exec("\n".join(lines), _ENV)  # noqa: S102 - code generated from dataclass fields only
    _SHIFTERS[cls] = _ENV[f"shift_{name}"]


def _register(*modules) -> None:
    classes = [value for module in modules for value in vars(module).values()
               if isinstance(value, type) and dataclasses.is_dataclass(value)
               and value.__module__ == module.__name__ and "__slots__" in value.__dict__]
    known = {cls.__name__ for cls in classes}
    for cls in classes:
        _compile(cls, known)


_register(_nodes, _model)


def shift(value, delta: int):
    """`value` with every span moved by `delta` characters (the value itself when 0)."""
    if delta == 0:
        return value
    return _shift_any(value, delta)
