"""The canonical `toparse` text of a condition (`scriptc.emit.condition`)."""

from __future__ import annotations

import pytest

from scriptc.emit.condition import condition_text
from scriptc.frontend.script import parse_condition
from scriptc.ir import nodes as ir
from scriptc.language import quote
from scriptc.source import Span

S = Span(0, 0)


def canonical(text: str) -> str:
    condition, diagnostics = parse_condition(text, 0)
    assert condition is not None and not diagnostics, diagnostics
    return condition_text(condition)


@pytest.mark.parametrize("text, expected", [
    ("! {TRUE}", "! {TRUE}"),
    ("!{TRUE}", "! {TRUE}"),
    ("{TRUE}", "{TRUE}"),
    ("{ TRUE }", "{TRUE}"),
    ("!", "!"),
    ("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)} ! {E: gt(?kid>&permanencetime, 2000)}",
     "{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)} ! {E: gt(?kid>&permanencetime, 2000)}"),
    (("{CLASS   #Human U ?kid(?THIS>&positionrho   OP<1.5 ,B:near( 2 ))}"
      "!{E:gt(?kid>&permanencetime,2000)}"),
     ("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5, B: near(2))} "
      "! {E: gt(?kid>&permanencetime, 2000)}")),
    ("{CLASS #Obstacle T ?o ()} !", "{CLASS #Obstacle T ?o ()} !"),
    ("{VAR @v U F: now()} !", "{VAR @v U F: now()} !"),
    ('{ATT ?kid $mood U F: str("calm")} ! {TRUE}', '{ATT ?kid $mood U F: str("calm")} ! {TRUE}'),
    ('! {E: eq(?kid>$mood, @v)} {E: neq("a\\"b", "c\\\\d")}',
     '! {E: eq(?kid>$mood, @v)} {E: neq("a\\"b", "c\\\\d")}'),
    ("! {E: lt(-0.50, +3)} {E: goalreached(?THIS)}",
     "! {E: lt(-0.50, +3)} {E: goalreached(?THIS)}"),
])
def test_canonical_text(text: str, expected: str) -> None:
    assert canonical(text) == expected
    assert canonical(expected) == expected  # canonical text is a fixed point


def test_sigils_are_added_whether_or_not_the_ir_has_them() -> None:
    def name(t: str) -> ir.Name:
        return ir.Name(t, S)

    kid = ir.AliasRef(name("kid"), S)  # no `?`
    call = ir.Call("F", name("now"), (), S)
    with_sigils = ir.Condition(
        (ir.ClassAssignment(name("#Human"), name("U"), ir.AliasRef(name("?kid"), S), (), S),
         ir.VarAssignment(ir.VarRef(name("@v"), S), name("L"), call, S),
         ir.AttAssignment(ir.AliasRef(name("?kid"), S), name("$m"), name("T"), call, S)),
        (ir.CallEvaluation(ir.Call("E", name("eq"), (
            ir.AttRef(ir.AliasRef(name("?kid"), S), name("$m"), S),
            ir.FieldRef(ir.AliasRef(name("?kid"), S), name("id"), S)), S), S),), S)
    without = ir.Condition(
        (ir.ClassAssignment(name("Human"), name("U"), kid, (), S),
         ir.VarAssignment(ir.VarRef(name("v"), S), name("L"), call, S),
         ir.AttAssignment(kid, name("m"), name("T"), call, S)),
        (ir.CallEvaluation(ir.Call("E", name("eq"), (
            ir.AttRef(kid, name("m"), S), ir.FieldRef(kid, name("id"), S)), S), S),), S)
    expected = ("{CLASS #Human U ?kid ()} {VAR @v L F: now()} {ATT ?kid $m T F: now()} ! "
                "{E: eq(?kid>$m, ?kid>&id)}")
    assert condition_text(with_sigils) == expected
    assert condition_text(without) == expected


def test_quote() -> None:
    assert quote('a"b\\c') == '"a\\"b\\\\c"'
    assert quote("più") == '"più"'
