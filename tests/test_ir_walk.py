"""The conditions' visitor (scriptc/ir/walk.py): one method per kind of node, dispatched on the
node's class, and every visitor of the code knows every kind it can meet, so a kind added to
the IR fails here rather than deep in a pass."""

from __future__ import annotations

import typing

import pytest

from scriptc.ir import nodes as ir
from scriptc.ir.walk import KINDS, ConditionVisitor
from scriptc.source import Span

NOWHERE = Span(0, 0)
ASSIGNMENTS = set(typing.get_args(ir.Assignment))
EVALUATIONS = set(typing.get_args(ir.Evaluation))
TESTS = set(typing.get_args(ir.Test))
VALUES = set(typing.get_args(ir.Value))


def test_kinds_are_the_nodes_of_a_condition() -> None:
    assert set(KINDS) == ASSIGNMENTS | EVALUATIONS | TESTS | VALUES
    assert len(set(KINDS.values())) == len(KINDS)
    assert all(name.startswith("visit_") for name in KINDS.values())


class Names(ConditionVisitor):
    def visit_number(self, value, prefix: str) -> str:
        return prefix + value.number.text

    def visit_alias(self, value, prefix: str) -> str:
        return prefix + value.name.text


class LoudNames(Names):
    def visit_alias(self, value, prefix: str) -> str:
        return super().visit_alias(value, prefix).upper()


def test_visit_calls_the_method_of_the_node_s_class_with_the_arguments() -> None:
    number = ir.NumberValue(ir.Number("1.5", NOWHERE))
    alias = ir.AliasRef(ir.Name("?kid", NOWHERE), NOWHERE)
    assert Names().visit(number, "n:") == "n:1.5"
    assert Names().visit(alias, "a:") == "a:?kid"
    assert LoudNames().visit(alias, "a:") == "A:?KID"  # each subclass has its own table
    assert Names.methods[ir.AliasRef] is Names.visit_alias
    assert LoudNames.methods[ir.AliasRef] is LoudNames.visit_alias


def test_a_kind_without_a_method_is_a_type_error_naming_both() -> None:
    var = ir.VarRef(ir.Name("@v", NOWHERE), NOWHERE)
    with pytest.raises(TypeError, match=r"Names cannot visit VarRef \(no visit_var\)"):
        Names().visit(var, "")
    with pytest.raises(TypeError, match="cannot visit Name"):
        Names().visit(ir.Name("x", NOWHERE), "")


def _visitors():
    from scriptc.check.conditions import _ConditionChecker
    from scriptc.emit.codegen import _Codegen
    from scriptc.emit.condition import _Text
    from scriptc.ide.index import _ItemWalker
    from scriptc.runtime.evaluate import _Compiler

    everything = ASSIGNMENTS | EVALUATIONS | TESTS | VALUES
    return [
        (_Text, everything),
        (_ConditionChecker, everything),
        (_ItemWalker, everything),
        # These two run the evaluations themselves: `{TRUE}` ends a condition.
        (_Codegen, ASSIGNMENTS | TESTS | VALUES),
        (_Compiler, ASSIGNMENTS | TESTS | VALUES),
    ]


@pytest.mark.parametrize("visitor, kinds", _visitors(), ids=lambda v: getattr(v, "__name__", ""))
def test_every_visitor_knows_every_kind_it_meets(visitor, kinds) -> None:
    missing = sorted(k.__name__ for k in kinds - set(visitor.methods))
    assert not missing, f"{visitor.__name__} has no method for {missing}"
