"""The scanner's one-match reading of a plain item (`syntax/scan.py`, `_PLAIN_ITEM`) finds what
the character-by-character scan finds: the same items, comments and diagnostics."""

from __future__ import annotations

import re

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from scriptc.syntax import scan as scanner

FAST = settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])

PIECES = st.sampled_from(["[", "]", '"', '\\"', "\\\\", "\\", "%", "% c %", "a", " ", "\n", "\r",
                          "MV(", '"0, 0, 1, 0, 10"', ")", "é"])


def _scanned(text: str) -> tuple:
    result = scanner.scan(text)
    return ([(r.span, r.closed, r.broken) for r in result.items], result.comments,
            [(d.code, d.message, d.span) for d in result.diagnostics])


def _scanned_the_long_way(text: str, monkeypatch: pytest.MonkeyPatch) -> tuple:
    with monkeypatch.context() as m:
        m.setattr(scanner, "_PLAIN_ITEM", re.compile(r"(?!)"))
        return _scanned(text)


@FAST
@given(st.lists(PIECES, max_size=40).map("".join))
@example('[b#x#blk_inst: MV("[a]", "%") LD() AO()]\n[b##blk_terminus]')
@example('[a "unterminated ]\n[b]')
@example("[a % comment ] % b]")
@example("[a [b]")
def test_one_match_finds_what_the_long_way_finds(text: str) -> None:
    with pytest.MonkeyPatch.context() as monkeypatch:
        assert _scanned(text) == _scanned_the_long_way(text, monkeypatch)


def test_a_plain_item_is_one_match_and_a_failing_one_costs_no_backtracking() -> None:
    item = '[b#x#blk_inst: MV("0, 0, 1, 0, 10") LD("[", "]") AO("%")]'
    assert scanner._PLAIN_ITEM.match(item).end() == len(item)
    assert scanner._PLAIN_ITEM.match("[a % c % b]") is None  # a comment: the long way
    # An item never closed, a megabyte long, fails at once (possessive repeats).
    assert scanner._PLAIN_ITEM.match("[" + "a b " * 250_000) is None
    assert _scanned("[" + "a b " * 250_000)[2][0][0] == "P002"
