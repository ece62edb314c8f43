"""Laws of the formatter for every input (hypothesis): idempotence, meaning, comments kept,
agreement with the canonical printer, and no exception and no lost byte on broken input.

Inputs are generated scripts (`strategies.scripts()`) with comments injected at random item
boundaries and between the tokens inside items, and with their blanks shuffled (spaces, tabs,
line breaks of every kind, none next to punctuation).
"""

from __future__ import annotations

import random
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scripts
from test_properties import JUNK, PIECES

from scriptc.analysis.analyze import analyze_script
from scriptc.diagnostics.edits import apply_edits
from scriptc.emit.json import emit_json
from scriptc.emit.script import format_script
from scriptc.formatter import format_range, format_text
from scriptc.source import SourceFile
from scriptc.syntax.parser import parse_items
from scriptc.syntax.scan import scan

# Property tests over generated input: the slow tier (CONTRIBUTING.md).
pytestmark = pytest.mark.slow

FAST = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# A generated script in pieces: strings and comments (never touched), blanks, other characters.
_PIECE = re.compile(r'"(?:\\.|[^"\\\n])*"|%[^%]*%|\s+|.', re.DOTALL)
# Next to these, a comment may be inserted and blanks may be removed without joining tokens.
_PUNCT = set("[](){},:!")
COMMENT_CHARS = list("ab z09[](){}\"\\#?!,:") + ["\n", "\r\n", "\t", "é"]
BLANKS = [" ", "  ", "\t", "\n", "\n\n\n", "\r\n", " \n    ", "\n\t"]


def decorate(text: str, rnd) -> str:
    """Comments injected at random token boundaries (inside items too), blanks shuffled.
    A seeded `random.Random`: a hypothesis draw per character would make generating the
    input ten times slower than formatting it."""
    pieces = _PIECE.findall(text)
    out: list[str] = []
    for i, piece in enumerate(pieces):
        prev = pieces[i - 1] if i else ""
        nxt = pieces[i + 1] if i + 1 < len(pieces) else ""
        at_boundary = (not out or prev.isspace() or piece.isspace() or prev in _PUNCT
                       or piece in _PUNCT)
        if at_boundary and rnd.random() < 0.08:
            comment = "%" + "".join(rnd.choices(COMMENT_CHARS, k=rnd.randrange(8))) + "%"
            out.append(rnd.choice(["", *BLANKS]) + comment + rnd.choice(["", *BLANKS]))
        written = piece
        if piece.isspace():
            choice = rnd.randrange(4)
            if choice == 0 and (prev in _PUNCT or nxt in _PUNCT):
                continue
            if choice == 1:
                written = rnd.choice(BLANKS)
        out.append(written)
    if rnd.random() < 0.5:
        out.append(rnd.choice(BLANKS) + "% the end %")
    return "".join(out)


@st.composite
def decorated(draw, max_blocks: int = 10) -> str:
    """A generated script with comments injected and blanks shuffled."""
    text = draw(scripts(max_blocks=max_blocks))
    return decorate(text, random.Random(draw(st.integers(0, 2**32 - 1))))


def compiled(text: str) -> tuple[str | None, list[str]]:
    analysis = analyze_script(SourceFile("x.script", text))
    return (emit_json(analysis.script) if analysis.ok else None), sorted(
        d.code for d in analysis.diagnostics
    )


def comments(text: str) -> list[str]:
    return [text[c.start : c.end] for c in scan(text).comments]


@FAST
@given(decorated())
def test_formatting_is_idempotent_and_keeps_meaning_and_comments(text: str) -> None:
    result = format_text(text)
    assert result.text is not None, (text, result.diagnostics)
    out = result.text
    assert format_text(out).text == out
    assert compiled(out) == compiled(text)
    assert comments(out) == comments(text)
    assert out.endswith(("\n", "\r")) or out == ""
    assert not re.search(r"[ \t]+(\r\n|\r|\n)", _outside_comments(out)), "trailing blanks"


def _outside_comments(text: str) -> str:
    return re.sub(r"%[^%]*%", "%%", text)


@FAST
@given(scripts())
def test_canonical_printer_output_is_already_formatted(text: str) -> None:
    """emit/script.py and the formatter share one layout: the printer's text of any script
    is a fixpoint of the formatter, long items included."""
    analysis = analyze_script(SourceFile("gen.script", text))
    if analysis.script is None:
        return
    canonical = format_script(analysis.script)
    assert format_text(canonical).text == canonical


@FAST
@given(decorated(max_blocks=6), st.data())
def test_range_formatting_agrees_with_whole_formatting(text: str, data) -> None:
    whole = format_text(text).text
    assert apply_edits(text, format_range(text, 0, len(text))) == whole
    a = data.draw(st.integers(0, len(text)))
    b = data.draw(st.integers(a, len(text)))
    partial = apply_edits(text, format_range(text, a, b))
    # Formatting a part, then the whole, is formatting the whole; the part kept its meaning.
    # (Line endings aside: a file whose only line breaks are inside the items formatted has
    # none left to tell its style, so it gets `\n`.)
    assert _lf(format_text(partial).text) == _lf(whole)
    assert compiled(partial) == compiled(text)
    assert comments(partial) == comments(text)


def _lf(text: str) -> str:
    return re.sub(r"\r\n?", "\n", text)


def _syntax(text: str) -> list[tuple[str, str]]:
    return [(d.code, d.message) for d in parse_items(text).diagnostics]


def _check_broken(text: str) -> None:
    result = format_text(text)
    if result.text is None:
        assert result.diagnostics
    else:
        assert format_text(result.text).text == result.text
    a, b = 0, len(text)
    once = apply_edits(text, format_range(text, a, b))
    # What does not parse is left as it is: the same syntax errors, the same comments.
    assert _syntax(once) == _syntax(text)
    assert comments(once) == comments(text)
    assert apply_edits(once, format_range(once, 0, len(once))) == once


@FAST
@given(JUNK)
def test_junk_never_raises_nor_loses_text(text: str) -> None:
    _check_broken(text)


@FAST
@given(decorated(max_blocks=6), st.data())
def test_mutated_scripts_never_raise_nor_lose_text(text: str, data) -> None:
    at = data.draw(st.integers(0, len(text)))
    length = data.draw(st.integers(0, 5))
    mutated = text[:at] + data.draw(PIECES) + text[at + length :]
    _check_broken(mutated)
