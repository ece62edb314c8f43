"""Laws that hold for every input (hypothesis)."""

from __future__ import annotations

import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import conditions, scripts

from scriptc.analysis.analyze import analyze_script
from scriptc.diagnostics.model import Severity
from scriptc.source import SourceFile

# Property tests over generated input: the slow tier (CONTRIBUTING.md).
pytestmark = pytest.mark.slow

FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# Text made of the language's own pieces, glued at random: nearer to real mistakes than
# uniformly random characters.
PIECES = st.sampled_from(
    ["[", "]", "(", ")", "{", "}", '"', "%", ",", ":", "#", "!", "?THIS", ">&", ">$", "OP<",
     "b#x#", "blk_inst", "blk_jump", "MV", "LD", "AO", "CND", "TRJMP", "FLSJMP", "CLASS",
     "#Human", "?kid", "@v", "$a", "E:", "B:", "F:", "TRUE", "goal:", "action", "alfa:", "\\",
     "0", "1.5", "-2", "1e999", "nan", " ", "\n", "\r\n", "\t", "é", "😀", "\x00"]
)
JUNK = st.one_of(st.text(max_size=300), st.lists(PIECES, max_size=80).map("".join))


@FAST
@given(JUNK)
def test_front_end_never_raises(text: str) -> None:
    analysis = analyze_script(SourceFile("fuzz.script", text))
    for d in analysis.diagnostics:
        assert 0 <= d.span.start <= d.span.end <= len(text)
        assert d.message and d.code


@FAST
@given(scripts())
def test_generated_scripts_parse(text: str) -> None:
    analysis = analyze_script(SourceFile("gen.script", text))
    syntax = [d for d in analysis.diagnostics if d.code[0] in "PS"]
    assert not syntax, (text, syntax)


@FAST
@given(scripts(), st.data())
def test_mutations_never_raise(text: str, data) -> None:
    """Deleting or inserting a piece anywhere in a valid script never crashes anything."""
    at = data.draw(st.integers(0, len(text)))
    length = data.draw(st.integers(0, 5))
    piece = data.draw(PIECES)
    mutated = text[:at] + piece + text[at + length :]
    analyze_script(SourceFile("mut.script", mutated))


@FAST
@given(scripts())
def test_compile_decompile_compile_is_identity(text: str) -> None:
    from scriptc.emit.json import emit_json
    from scriptc.emit.script import format_script
    from scriptc.frontend.thesis_json import script_from_json

    analysis = analyze_script(SourceFile("gen.script", text))
    if not analysis.ok:
        return
    first = emit_json(analysis.script)
    script, problems = script_from_json(SourceFile("gen.json", first))
    errors = [p for p in problems if p.severity is Severity.ERROR]
    assert script is not None and not errors, problems
    again = analyze_script(SourceFile("dec.script", format_script(script)))
    assert again.ok, again.diagnostics
    second = emit_json(again.script)
    assert json.loads(first) == json.loads(second)
    assert first == second


@FAST
@given(conditions())
def test_condition_text_round_trips(text: str) -> None:
    """The canonical `toparse` text of a condition parses to the same canonical text."""
    from scriptc.emit.condition import condition_text
    from scriptc.frontend.script import parse_condition

    cond, problems = parse_condition(text)
    assert cond is not None, problems
    canonical = condition_text(cond)
    again, _ = parse_condition(canonical)
    assert condition_text(again) == canonical
