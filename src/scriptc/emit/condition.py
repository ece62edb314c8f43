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
    AttAssignment,
    AttRef,
    Call,
    CallEvaluation,
    CallTest,
    ClassAssignment,
    Condition,
    FieldRef,
    FieldTest,
    Name,
    NumberValue,
    StringValue,
    TrueEvaluation,
    VarAssignment,
    VarRef,
)
from scriptc.language import quote

__all__ = ["condition_text", "value_text", "call_text"]


def _sigil(sigil: str, name: Name) -> str:
    text = name.text
    return text if text.startswith(sigil) else sigil + text


def _bare(sigil: str, name: Name) -> str:
    text = name.text
    return text[len(sigil):] if text.startswith(sigil) else text


def _alias(alias: AliasRef) -> str:
    return _sigil("?", alias.name)


def value_text(value) -> str:
    """One argument or compared value."""
    if isinstance(value, NumberValue):
        return value.number.text
    if isinstance(value, StringValue):
        return quote(value.text.value)
    if isinstance(value, FieldRef):
        return f"{_alias(value.alias)}>&{_bare('&', value.field)}"
    if isinstance(value, AttRef):
        return f"{_alias(value.alias)}>${_bare('$', value.att)}"
    if isinstance(value, VarRef):
        return _sigil("@", value.name)
    if isinstance(value, AliasRef):
        return _alias(value)
    raise TypeError(f"not a condition value: {value!r}")


def call_text(call: Call) -> str:
    """`KIND: name(arg, arg)`."""
    args = ", ".join(value_text(a) for a in call.args)
    return f"{call.kind}: {call.name.text}({args})"


def _test_text(test) -> str:
    if isinstance(test, FieldTest):
        return f"?THIS>&{_bare('&', test.field)} {test.op.text} {value_text(test.value)}"
    if isinstance(test, CallTest):
        return call_text(test.call)
    raise TypeError(f"not a CLASS test: {test!r}")


def _assignment_text(assignment) -> str:
    if isinstance(assignment, ClassAssignment):
        tests = ", ".join(_test_text(t) for t in assignment.tests)
        return (
            f"{{CLASS {_sigil('#', assignment.class_name)} {assignment.scope.text} "
            f"{_alias(assignment.alias)} ({tests})}}"
        )
    if isinstance(assignment, VarAssignment):
        return (
            f"{{VAR {_sigil('@', assignment.var.name)} {assignment.scope.text} "
            f"{call_text(assignment.call)}}}"
        )
    if isinstance(assignment, AttAssignment):
        return (
            f"{{ATT {_alias(assignment.alias)} {_sigil('$', assignment.att)} "
            f"{assignment.scope.text} {call_text(assignment.call)}}}"
        )
    raise TypeError(f"not an assignment: {assignment!r}")


def _evaluation_text(evaluation) -> str:
    if isinstance(evaluation, CallEvaluation):
        return f"{{{call_text(evaluation.call)}}}"
    if isinstance(evaluation, TrueEvaluation):
        return "{TRUE}"
    raise TypeError(f"not an evaluation: {evaluation!r}")


def condition_text(cond: Condition) -> str:
    """The canonical text of `cond` (the `toparse` of the thesis JSON)."""
    if cond.bare_true:
        return "{TRUE}"
    parts = [_assignment_text(a) for a in cond.assignments]
    parts.append("!")
    parts.extend(_evaluation_text(e) for e in cond.evaluations)
    return " ".join(parts)
