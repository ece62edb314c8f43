"""The IR's nodes (`ir/nodes.py`, `@node`): frozen slotted dataclasses whose `__init__` sets the
slots directly. Every class takes its fields by position and by name, keeps its defaults, is
frozen, compares and hashes by value, and `dataclasses.replace` works."""

from __future__ import annotations

import dataclasses
import inspect

import pytest

from scriptc.ir import nodes

CLASSES = [c for _, c in inspect.getmembers(nodes, inspect.isclass)
           if dataclasses.is_dataclass(c) and c.__module__ == nodes.__name__]


def test_every_node_class_is_made_by_node() -> None:
    assert len(CLASSES) >= 25
    for cls in CLASSES:
        assert cls.__init__.__qualname__ == f"{cls.__qualname__}.__init__"
        params = cls.__dataclass_params__
        assert params.frozen and "__slots__" in cls.__dict__, cls


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_fields_by_position_and_by_name(cls) -> None:
    fields = dataclasses.fields(cls)
    values = [object() for _ in fields]
    by_position = cls(*values)
    by_name = cls(**{f.name: v for f, v in zip(fields, values, strict=True)})
    for f, v in zip(fields, values, strict=True):
        assert getattr(by_position, f.name) is v and getattr(by_name, f.name) is v
    assert by_position == by_name
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(by_position, fields[0].name, None)
    first = fields[0].name
    changed = dataclasses.replace(by_position, **{first: "other"})
    assert getattr(changed, first) == "other" and changed != by_position
    required = [f for f in fields if f.default is dataclasses.MISSING]
    with pytest.raises(TypeError):
        cls(*values, object())  # one too many
    if required:
        with pytest.raises(TypeError):
            cls(*values[:len(required) - 1])  # one too few


@pytest.mark.parametrize("cls", [c for c in CLASSES
                                 if any(f.default is not dataclasses.MISSING
                                        for f in dataclasses.fields(c))],
                         ids=lambda c: c.__name__)
def test_defaults(cls) -> None:
    fields = dataclasses.fields(cls)
    required = [f for f in fields if f.default is dataclasses.MISSING]
    made = cls(*[f"v{i}" for i in range(len(required))])
    for f in fields:
        if f.default is not dataclasses.MISSING:
            assert getattr(made, f.name) == f.default


def test_equal_values_hash_alike() -> None:
    span = nodes.Span(1, 2)
    assert hash(nodes.Number("1", span)) == hash(nodes.Number("1", span))
    assert nodes.Number("1", span) != nodes.Name("1", span)
    assert repr(nodes.Number("1", span)) == "Number(text='1', span=Span(start=1, end=2))"


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_methods_mean_what_a_frozen_dataclass_means(cls) -> None:
    """`@node` writes the methods `@dataclass(frozen=True)` would, itself: the same meaning."""
    fields = dataclasses.fields(cls)
    values = [f"v{i}" for i in range(len(fields))]
    made, same = cls(*values), cls(*values)
    assert made == same and hash(made) == hash(same) == hash(tuple(values))
    assert made.__eq__(tuple(values)) is NotImplemented and made != tuple(values)
    for i in range(len(fields)):  # each field takes part in equality
        other = cls(*values[:i], "changed", *values[i + 1:])
        assert other != made and not other == made  # noqa: SIM201  # __eq__ itself
    shown = ", ".join(f"{f.name}={v!r}" for f, v in zip(fields, values, strict=True))
    assert repr(made) == f"{cls.__qualname__}({shown})"
    with pytest.raises(dataclasses.FrozenInstanceError):
        delattr(made, fields[0].name)
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.not_a_field = 1
    for method in ("__init__", "__repr__", "__eq__", "__hash__", "__setattr__", "__delattr__"):
        assert getattr(cls, method).__qualname__ == f"{cls.__qualname__}.{method}"
    assert cls.__doc__  # written for a node without one: never computed from its signature


def test_an_undocumented_node_is_named_by_its_fields() -> None:
    assert nodes.Goal.__doc__ == "Goal(id, actions, span)"
