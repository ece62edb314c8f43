"""The one fix applier and its overlap rule, and the one minimal edit (diagnostics/edits.py)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from scriptc.diagnostics.edits import apply_edits, apply_fixes, clash, compatible, minimal_edit
from scriptc.diagnostics.model import Fix, TextEdit
from scriptc.source import Span

TEXT = "abcdefgh"


def edit(start: int, end: int, new: str) -> TextEdit:
    return TextEdit(Span(start, end), new)


def fix(*edits: tuple[int, int, str]) -> Fix:
    return Fix("f", tuple(edit(*e) for e in edits))


@pytest.mark.parametrize(("a", "b", "expected"), [
    ((0, 2), (1, 3), True),     # share a character
    ((1, 3), (0, 2), True),
    ((0, 2), (2, 4), False),    # one ends where the other starts
    ((2, 4), (0, 2), False),
    ((2, 2), (2, 2), True),     # two insertions at one place
    ((2, 2), (2, 5), True),     # an insertion at the start of a replacement
    ((2, 5), (2, 2), True),
    ((5, 5), (2, 5), False),    # an insertion at the end of a replacement
    ((2, 5), (5, 5), False),
    ((3, 3), (2, 5), True),     # an insertion strictly inside
    ((2, 5), (3, 3), True),
    ((1, 1), (2, 5), False),
    ((2, 5), (6, 6), False),
    ((0, 8), (3, 4), True),     # one inside the other
])
def test_the_overlap_rule(a: tuple[int, int], b: tuple[int, int], expected: bool) -> None:
    assert clash(Span(*a), Span(*b)) is expected


def test_overlapping_fixes_wait_for_the_next_round() -> None:
    assert apply_fixes(TEXT, [fix((0, 2, "X")), fix((1, 3, "Y"))]) == ("Xcdefgh", 1)
    assert apply_fixes(TEXT, [fix((2, 2, "X")), fix((2, 2, "Y"))]) == ("abXcdefgh", 1)
    assert apply_fixes(TEXT, [fix((1, 4, "")), fix((2, 2, "Y"))]) == ("aefgh", 1)
    assert apply_fixes(TEXT, [fix((0, 1, "A")), fix((1, 2, "B"))]) == ("ABcdefgh", 2)
    # A fix whose own edits clash is never applied; the others still are.
    assert apply_fixes(TEXT, [fix((0, 2, "X"), (1, 3, "Y")), fix((7, 8, "H"))]) == (
        "abcdefgH", 1)
    assert apply_fixes(TEXT, [fix((6, 8, ""), (0, 0, ">"))]) == (">abcdef", 1)
    # The edits of one fix are one change: insertions at one place go in the fix's order.
    assert apply_fixes(TEXT, [fix((2, 2, "X"), (2, 2, "Y"))]) == ("abXYcdefgh", 1)
    assert apply_fixes(TEXT, [fix((2, 4, "-"), (2, 2, "+")), fix((4, 4, "!"))]) == (
        "ab+-!efgh", 2)
    assert apply_fixes(TEXT, [fix((1, 5, "X"), (3, 3, "Y"))]) == (TEXT, 0)
    assert apply_fixes(TEXT, []) == (TEXT, 0)


def test_compatible_keeps_the_order_and_skips_the_clashing() -> None:
    first, second, third = fix((0, 1, "A")), fix((0, 2, "B")), fix((4, 4, "C"))
    assert compatible([first, second, third]) == [first, third]
    assert compatible([second, first, third]) == [second, third]


def test_edits_of_one_change_keep_the_order_of_insertions_at_one_place() -> None:
    assert apply_edits(TEXT, [edit(2, 2, "X"), edit(2, 2, "Y")]) == "abXYcdefgh"
    assert apply_edits(TEXT, [edit(2, 2, "Y"), edit(2, 2, "X")]) == "abYXcdefgh"
    # An insertion goes before a replacement starting at its offset, wherever it is listed.
    assert apply_edits(TEXT, [edit(2, 4, "-"), edit(2, 2, "+")]) == "ab+-efgh"
    assert apply_edits(TEXT, [edit(6, 8, "!"), edit(0, 1, "A"), edit(4, 4, "_")]) == "Abcd_ef!"
    assert apply_edits(TEXT, [edit(0, 8, "")]) == ""
    assert apply_edits(TEXT, []) == TEXT


@pytest.mark.parametrize("edits", [
    [edit(0, 3, "X"), edit(2, 4, "Y")],
    [edit(1, 5, "X"), edit(3, 3, "Y")],
    [edit(3, 9, "X")],
    [edit(3, 2, "X")],
])
def test_edits_that_overlap_or_leave_the_text_are_refused(edits: list[TextEdit]) -> None:
    with pytest.raises(ValueError):
        apply_edits(TEXT, edits)


@pytest.mark.parametrize(("old", "new", "at", "expected"), [
    ("abc", "abc", 0, None),
    ("abc", "aXc", 0, edit(1, 2, "X")),
    ("abc", "abXc", 10, edit(12, 12, "X")),
    ("aaa", "aa", 0, edit(2, 3, "")),          # the common ends never overlap
    ("", "new", 4, edit(4, 4, "new")),
    ("old", "", 0, edit(0, 3, "")),
    ("xay", "xby", 0, edit(1, 2, "b")),
])
def test_minimal_edit(old: str, new: str, at: int, expected: TextEdit | None) -> None:
    assert minimal_edit(old, new, at) == expected


@given(st.text("ab\n", max_size=12), st.text("ab\n", max_size=12), st.text("ab", max_size=3))
def test_the_minimal_edit_turns_old_into_new_and_keeps_the_common_ends(
        old: str, new: str, before: str) -> None:
    result = minimal_edit(old, new, len(before))
    if old == new:
        assert result is None
        return
    assert result is not None
    assert apply_edits(before + old, [result]) == before + new
    start, end = result.span.start - len(before), result.span.end - len(before)
    replaced, inserted = old[start:end], result.new_text
    # Nothing common is left at either end of what the edit replaces.
    assert not (replaced and inserted and replaced[0] == inserted[0])
    assert not (replaced and inserted and replaced[-1] == inserted[-1])
    assert old[:start] == new[:start]


spans = st.tuples(st.integers(0, 8), st.integers(0, 8)).map(lambda p: Span(min(p), max(p)))


@pytest.mark.slow
@given(st.lists(st.tuples(spans, st.text("XY", max_size=2)), max_size=6))
def test_fixes_that_can_go_together_apply_as_one_change_in_any_order(
        pairs: list[tuple[Span, str]]) -> None:
    fixes = [Fix("f", (TextEdit(s, t),)) for s, t in pairs]
    taken = compatible(fixes)
    text, applied = apply_fixes(TEXT, fixes)
    assert applied == len(taken)
    # No two taken edits clash, so their order cannot matter.
    edits = [e for f in taken for e in f.edits]
    assert all(not clash(a.span, b.span) for i, a in enumerate(edits) for b in edits[i + 1:])
    assert apply_edits(TEXT, list(reversed(edits))) == text
    # A fix left out clashes with one taken before it.
    taken_ids = {id(f) for f in taken}
    for i, f in enumerate(fixes):
        if id(f) not in taken_ids:
            earlier = [e for t in fixes[:i] if id(t) in taken_ids for e in t.edits]
            assert any(clash(f.edits[0].span, e.span) for e in earlier)
