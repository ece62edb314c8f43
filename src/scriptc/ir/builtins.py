"""What the rule grammar can name: the map's classes and their fields (thesis 4.1, tables 4.1
and 4.2) and the registry of B/F/E functions (docs/rules.md).

The checker validates conditions against a `FunctionRegistry`; `STANDARD_FUNCTIONS` is the set
the toolchain ships. Activity repositories extend it from their configuration. Only the
signatures live here; the run-time implementations belong to the interpreter.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Field:
    """A field of a map class: its name, its type and what it holds."""

    name: str
    type: str  # "text", "number" or "bool" (the map's "s_true"/"s_false")
    doc: str


_ENTITY_FIELDS = (
    Field("id", "text", "the entity's unique id, fixed at creation"),
    Field("positionrho", "number", "distance from the robot in metres"),
    Field("positiontheta", "number", "bearing from the robot's heading in radians"),
    Field("positionchangetime", "number", "map time (ms) of the last position change"),
    Field("permanencetime", "number", "how long (ms) the entity has been tracked"),
    Field("appearanceon", "number", "map time (ms) the entity first appeared"),
)

CLASSES: Mapping[str, tuple[Field, ...]] = {
    "Human": _ENTITY_FIELDS,
    "Obstacle": _ENTITY_FIELDS + (Field("isfixed", "bool", "whether the obstacle never moves"),),
    "Object": _ENTITY_FIELDS
    + (
        Field("istarget", "bool", "whether the object is the activity's target"),
        Field("category", "text", "the object's category"),
    ),
    "Activity": (
        Field("activityid", "text", "the tracked activity's name"),
        Field("startingtime", "number", "map time (ms) the activity started"),
        Field("elapsedtime", "number", "ms since the activity started"),
    ),
}

def field_of(class_name: str, field: str) -> Field | None:
    for f in CLASSES.get(class_name, ()):
        if f.name == field:
            return f
    return None


@dataclass(frozen=True, slots=True)
class Param:
    """A parameter of a function's signature: its name and what it means."""

    name: str
    doc: str


@dataclass(frozen=True, slots=True)
class Function:
    """A function's signature. `kind` is "B" (boolean about the candidate entity of a CLASS
    assignment), "F" (returns a string) or "E" (boolean, right of the `!`)."""

    name: str
    kind: str
    params: tuple[Param, ...]
    doc: str
    origin: str = "standard"

    @property
    def arity(self) -> int:
        return len(self.params)

    @property
    def signature(self) -> str:
        return f"{self.kind}: {self.name}({', '.join(p.name for p in self.params)})"


def _cmp(name: str, verb: str) -> Function:
    return Function(
        name,
        "E",
        (Param("a", "left value"), Param("b", "right value")),
        f"True when `a` {verb} `b`; numeric when both sides are numbers, else text.",
    )


STANDARD_FUNCTIONS: tuple[Function, ...] = (
    _cmp("eq", "equals"),
    _cmp("neq", "differs from"),
    _cmp("lt", "is less than"),
    _cmp("gt", "is greater than"),
    _cmp("le", "is at most"),
    _cmp("ge", "is at least"),
    Function(
        "goalreached",
        "E",
        (Param("goalid", "a goal id of the running script"),),
        "True when the map records the goal as reached.",
    ),
    Function(
        "near",
        "B",
        (Param("distance", "metres"),),
        "True when the candidate entity's `positionrho` is below `distance`.",
    ),
    Function("str", "F", (Param("value", "any value"),), "The value as text."),
    Function("now", "F", (), "The map's time in ms, as text."),
)


class FunctionRegistry:
    """Function signatures by name. Names are unique across kinds."""

    def __init__(self, functions: Iterable[Function] = STANDARD_FUNCTIONS) -> None:
        self._by_name: dict[str, Function] = {}
        for f in functions:
            self._by_name[f.name] = f

    def get(self, name: str) -> Function | None:
        return self._by_name.get(name)

    def names(self, kind: str | None = None) -> list[str]:
        return sorted(n for n, f in self._by_name.items() if kind is None or f.kind == kind)

    def __iter__(self) -> Iterator[Function]:
        return iter(self._by_name.values())

    def extended(self, functions: Iterable[Function]) -> FunctionRegistry:
        return FunctionRegistry([*self._by_name.values(), *functions])


STANDARD = FunctionRegistry()
