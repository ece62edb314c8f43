"""The conditions' visitor: the one dispatch on the kind of a node of the rule grammar's IR.

A condition (`scriptc.ir.nodes`, docs/rules.md) is assignments (CLASS, VAR, ATT) and then
evaluations (an E call, TRUE); a CLASS assignment has tests (a field compared, a B call); calls
and tests hold values (a number, a string, an alias, a field or an attribute of an alias, a
variable). Code that does something for each kind of node (print it, compile it, check it,
index it) subclasses `ConditionVisitor` with one method per kind it meets, named after the
kind (`visit_class_assignment`, `visit_field_test`, `visit_number`...: `KINDS`); `visit(node,
*args)` calls the method of the node's class with the further arguments, by one dictionary
lookup rather than a chain of `isinstance`, and a node whose kind the subclass has no method
for raises TypeError naming both.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

from scriptc.ir import nodes as ir

__all__ = ["KINDS", "ConditionVisitor"]

# The kinds of node a condition holds, and the name of the visitor's method for each.
KINDS: dict[type, str] = {
    ir.ClassAssignment: "visit_class_assignment",
    ir.VarAssignment: "visit_var_assignment",
    ir.AttAssignment: "visit_att_assignment",
    ir.CallEvaluation: "visit_call_evaluation",
    ir.TrueEvaluation: "visit_true_evaluation",
    ir.FieldTest: "visit_field_test",
    ir.CallTest: "visit_call_test",
    ir.NumberValue: "visit_number",
    ir.StringValue: "visit_string",
    ir.AliasRef: "visit_alias",
    ir.FieldRef: "visit_field",
    ir.AttRef: "visit_att",
    ir.VarRef: "visit_var",
}


class ConditionVisitor:
    """The base of code that acts on each kind of a condition's nodes (see the module's
    docstring). `methods` is made once per subclass: the class's function for each kind of
    node, which a loop that runs very often may call itself (`methods[type(node)](self,
    node)`: one call where `visit` makes two)."""

    methods: ClassVar[dict[type, Callable[..., Any]]] = {}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.methods = {kind: getattr(cls, name) for kind, name in KINDS.items()
                       if hasattr(cls, name)}

    def visit(self, node: Any, *args: Any) -> Any:
        """What the method for `node`'s kind returns, called with `args`."""
        try:
            method = self.methods[type(node)]
        except KeyError:
            raise TypeError(f"{type(self).__name__} cannot visit {type(node).__name__} "
                            f"(no {KINDS.get(type(node), 'method for it')}): {node!r}") from None
        return method(self, node, *args)
