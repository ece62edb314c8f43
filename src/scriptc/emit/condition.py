"""The canonical text of a rule-grammar condition: what a jump block's `toparse` holds in the
thesis JSON and what `CND(...)` holds in the canonical script syntax.

The layout is the thesis's own (docs/json.md, thesis 4.3/4.4): one space between the elements of a
condition, braces hugging their contents, `, ` between arguments and between the tests of a
CLASS assignment. Numbers keep the text they were written with; strings are re-escaped with the
two escapes of the language (`\\\\` and `\\"`). Examples:

    ! {TRUE}
    {TRUE}
    {CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)} ! {E: gt(?kid>&permanencetime, 2000)}
    {VAR @v U F: now()} !

Sigils are added here, so an IR whose names carry them (`#Human`, `@v`, `$mood`, `&rho`) or
not (`Human`, `v`) prints the same.
"""

from __future__ import annotations

from scriptc.ir.nodes import (
    AliasRef,
    Assignment,
    AttAssignment,
    AttRef,
    Call,
    CallEvaluation,
    CallTest,
    ClassAssignment,
    Condition,
    Evaluation,
    FieldRef,
    FieldTest,
    Name,
    NumberValue,
    StringValue,
    Test,
    TrueEvaluation,
    Value,
    VarAssignment,
    VarRef,
)
from scriptc.ir.walk import ConditionVisitor
from scriptc.language import quote

__all__ = ["call_text", "condition_text", "value_text"]


def _sigil(sigil: str, name: Name) -> str:
    text = name.text
    return text if text.startswith(sigil) else sigil + text


def _bare(sigil: str, name: Name) -> str:
    text = name.text
    return text[len(sigil):] if text.startswith(sigil) else text


def _alias(alias: AliasRef) -> str:
    return _sigil("?", alias.name)


class _Text(ConditionVisitor):
    """The text of each kind of node."""

    def visit_number(self, value: NumberValue) -> str:
        return value.number.text

    def visit_string(self, value: StringValue) -> str:
        return quote(value.text.value)

    def visit_field(self, value: FieldRef) -> str:
        return f"{_alias(value.alias)}>&{_bare('&', value.field)}"

    def visit_att(self, value: AttRef) -> str:
        return f"{_alias(value.alias)}>${_bare('$', value.att)}"

    def visit_var(self, value: VarRef) -> str:
        return _sigil("@", value.name)

    def visit_alias(self, value: AliasRef) -> str:
        return _alias(value)

    def visit_field_test(self, test: FieldTest) -> str:
        value = self.methods[type(test.value)](self, test.value)  # (`visit`, one call less)
        return f"?THIS>&{_bare('&', test.field)} {test.op.text} {value}"

    def visit_call_test(self, test: CallTest) -> str:
        return call_text(test.call)

    def visit_class_assignment(self, assignment: ClassAssignment) -> str:
        methods = self.methods  # (`visit`, one call less: the JSON back end prints every jump)
        tests = ", ".join([methods[type(t)](self, t) for t in assignment.tests])
        return (f"{{CLASS {_sigil('#', assignment.class_name)} {assignment.scope.text} "
                f"{_alias(assignment.alias)} ({tests})}}")

    def visit_var_assignment(self, assignment: VarAssignment) -> str:
        return (f"{{VAR {_sigil('@', assignment.var.name)} {assignment.scope.text} "
                f"{call_text(assignment.call)}}}")

    def visit_att_assignment(self, assignment: AttAssignment) -> str:
        return (f"{{ATT {_alias(assignment.alias)} {_sigil('$', assignment.att)} "
                f"{assignment.scope.text} {call_text(assignment.call)}}}")

    def visit_call_evaluation(self, evaluation: CallEvaluation) -> str:
        return f"{{{call_text(evaluation.call)}}}"

    def visit_true_evaluation(self, evaluation: TrueEvaluation) -> str:
        return "{TRUE}"


_TEXT = _Text()
_visit = _TEXT.visit
_text_of = _Text.methods  # for the loops below, which the JSON emitter runs for every jump


def value_text(value: Value | Test | Assignment | Evaluation) -> str:
    """One argument or compared value (or any other node of a condition)."""
    text: str = _visit(value)
    return text


def call_text(call: Call) -> str:
    """`KIND: name(arg, arg)`."""
    args = ", ".join([_text_of[type(a)](_TEXT, a) for a in call.args])
    return f"{call.kind}: {call.name.text}({args})"


def condition_text(cond: Condition) -> str:
    """The canonical text of `cond` (the `toparse` of the thesis JSON)."""
    if cond.bare_true:
        return "{TRUE}"
    parts = [_text_of[type(a)](_TEXT, a) for a in cond.assignments]
    parts.append("!")
    parts.extend([_text_of[type(e)](_TEXT, e) for e in cond.evaluations])
    return " ".join(parts)
