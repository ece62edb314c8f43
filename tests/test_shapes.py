"""The item parser with its shape cache (syntax/shapes.py) builds lark's own trees and raises
lark's own errors: for every case file of the suite, for generated scripts and conditions, and
for junk made of the language's pieces; the first, second and later items of a shape (table
parse, recorded template, compiled template) alike."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lark.exceptions import UnexpectedInput
from strategies import conditions, scripts
from test_properties import PIECES

from scriptc.syntax import shapes
from scriptc.syntax.parser import _build, script_lark
from scriptc.syntax.scan import scan
from scriptc.syntax.shapes import ShapeParser

CASES = Path(__file__).parent / "cases"


@pytest.fixture(autouse=True)
def hot_soon(monkeypatch: pytest.MonkeyPatch) -> None:
    """Shapes get their own regex from their second item built by a template (in use, from
    the 256th): the rounds of `agree` go through every way an item is read."""
    monkeypatch.setattr(shapes, "HOT", 2)
FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def outcome(parse, text: str, start: str):
    """The tree, or the error's class, position and expected set."""
    try:
        return parse(text, start=start)
    except UnexpectedInput as error:
        return (type(error).__name__, getattr(error, "pos_in_stream", None),
                sorted(getattr(error, "expected", None) or getattr(error, "allowed", None) or ()))


def items_of(text: str) -> list[str]:
    return [text[r.span.start:r.span.end] for r in scan(text).items]


def agree(parser: ShapeParser, lark, texts: list[str], start: str = "item") -> None:
    # three rounds: the first item of a shape is table-parsed, the second compiles its
    # template, the third on are built by the compiled template
    for _ in range(3):
        for text in texts:
            assert outcome(parser.parse, text, start) == outcome(lark.parse, text, start), text


def all_case_items() -> list[str]:
    texts = []
    for path in sorted(CASES.rglob("*.script")):
        texts += items_of(path.read_text(encoding="utf-8", errors="replace"))
    return texts


@pytest.mark.slow
def test_the_trees_of_every_case_file_are_larks() -> None:
    texts = all_case_items()
    assert len(texts) > 500
    agree(ShapeParser(script_lark(), "item"), script_lark(), texts)


@pytest.mark.slow
def test_the_trees_are_larks_in_any_order() -> None:
    texts = all_case_items()
    agree(ShapeParser(script_lark(), "item"), script_lark(), texts[::-1])


@pytest.mark.slow
@FAST
@given(scripts())
def test_generated_scripts(text: str) -> None:
    agree(ShapeParser(script_lark(), "item"), script_lark(), items_of(text))


@FAST
@given(st.lists(PIECES, max_size=40).map("".join))
def test_junk_items_fail_as_lark_does(text: str) -> None:
    agree(ShapeParser(script_lark(), "item"), script_lark(), ["[" + text + "]", text])


@pytest.mark.slow
@FAST
@given(st.lists(conditions(), min_size=1, max_size=4))
def test_conditions(texts: list[str]) -> None:
    lark = _build("condition.lark", ["condition"])
    agree(ShapeParser(lark, "condition"), lark, texts, "condition")


def test_same_shape_other_comment_places() -> None:
    """A comment is a token of the shape: items that differ only in where it stands are
    different shapes (a template counts the comment's match)."""
    texts = ['[b#a#blk_inst: MV("1,0,0,0,100") % one % LD()]',
             '[b#a#blk_inst: MV("1,0,0,0,100") LD() % one %]',
             '[b#a#blk_inst: % one % MV("1,0,0,0,100") LD()]']
    agree(ShapeParser(script_lark(), "item"), script_lark(), texts)


def test_a_frequent_shape_does_not_take_keywords_for_names() -> None:
    """`[x]` is a name item; `[alfa]` and `[goal]` are other shapes (keywords where a name
    could stand): the regex of the frequent shape `[NAME]` matches them, its check refuses."""
    texts = [f"[x{i}]" for i in range(5)] + ["[alfa]", "[goal]", "[b]", "[alfax]", "[x]"]
    agree(ShapeParser(script_lark(), "item"), script_lark(), texts * 2)


def test_keywords_that_are_names_elsewhere() -> None:
    """`goal` and `b` are keywords where the parser accepts them and names elsewhere."""
    texts = ["[goal:goal]", "[b#goal#blk_terminus]", "[b#b#blk_terminus]", "[goal:b]",
             "[b#blk_inst#blk_inst:]", "[goalx]", ("[b#x#blk_jump: CND(! {TRUE}) TRJMP(goal) "
             "FLSJMP(b)]")]
    agree(ShapeParser(script_lark(), "item"), script_lark(), texts)


def test_the_trie_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(shapes, "MAX_NODES", 60)
    parser = ShapeParser(script_lark(), "item")
    texts = [f'[b#l{i}#blk_inst: {"MV() " * i}]' for i in range(1, 12)]
    agree(parser, script_lark(), texts)
    assert parser._nodes <= 60


def test_a_start_symbol_of_its_own_goes_to_lark() -> None:
    parser = ShapeParser(script_lark(), "item")
    assert parser.parse("[x]", start="item") == script_lark().parse("[x]", start="item")
    assert parser.terminals == script_lark().terminals  # describe() reads lark's terminals


def test_a_very_long_item_is_parsed_and_not_recorded(monkeypatch: pytest.MonkeyPatch) -> None:
    """An item longer than MAX_SHAPE_TOKENS (say 20,000 tracks) would fill the trie and
    throw the frequent shapes away: it is parsed (as lark does) and not recorded."""
    monkeypatch.setattr(shapes, "MAX_SHAPE_TOKENS", 50)
    parser = ShapeParser(script_lark(), "item")
    agree(parser, script_lark(), ["[b#a#blk_inst: MV()]"])
    nodes = parser._nodes
    agree(parser, script_lark(), ["[b#a#blk_inst: " + "MV() " * 20 + "]"])
    assert parser._nodes == nodes
