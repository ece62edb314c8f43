"""Lowering reads a well-formed command string in one match (`frontend/script.py`, `_WELL_FORMED`)
and any other by splitting it field by field: both ways give the same IR and diagnostics."""

from __future__ import annotations

import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scriptc.frontend import script as lower
from scriptc.frontend.script import lower_script
from scriptc.source import SourceFile

FAST = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])

BLANKS = st.sampled_from(["", " ", "  ", "\t", "\n", "\u00a0", "\u2003"])
NUMBERS = st.sampled_from(["0", "1", "-2", "+3", "0.5", ".5", "5.", "1e3", "2E-2", "1000",
                           "nan", "inf", "x", "", "1.2.3", "٣", "1_0", "0x1"])
PATHS = st.sampled_from(["songs/a.wav", "a, b.wav", "my song.wav", "", " ", "x,y,z", "é.wav"])


@st.composite
def fields(draw, count: int, path: bool) -> str:
    n = draw(st.sampled_from([count, count, count, count - 1, count + 1, 1]))
    values = [draw(NUMBERS) for _ in range(n)]
    if path and values:
        values[0] = draw(PATHS)
    return ",".join(draw(BLANKS) + v + draw(BLANKS) for v in values)


@st.composite
def blocks(draw) -> str:
    mv = draw(fields(5, False))
    ld = draw(fields(6, False))
    ao = draw(fields(3, True))
    return (f'[a]\n[goal:g]\n[action]\n[b#x#blk_inst: MV("{mv}") LD("{ld}") AO("{ao}")]\n'
            "[b##blk_terminus]\n")


def lowered(text: str):
    script, diagnostics = lower_script(SourceFile("t.script", text))
    return script, [(d.code, d.message, d.span) for d in diagnostics]


def field_by_field(text: str, monkeypatch: pytest.MonkeyPatch):
    never = re.compile(r"(?!)")
    with monkeypatch.context() as m:
        m.setattr(lower, "_WELL_FORMED", {"MV": never, "LD": never, "AO": never})
        m.setattr(lower, "_SPLIT", {track: {} for track in lower._SPLIT})  # nothing known
        return lowered(text)


@pytest.mark.slow
@FAST
@given(blocks())
def test_one_match_reads_as_field_by_field(text: str) -> None:
    with pytest.MonkeyPatch.context() as monkeypatch:
        assert lowered(text) == field_by_field(text, monkeypatch)


@pytest.mark.parametrize("mv", ["1,0,0,0,100", " 1 , 0 ,0, 0 ,100 ", "\u00a01,0,0,0,100",
                                "1e3,0,0,0,100", "1,0,0,0", "1,0,0,0,100,1", "a,0,0,0,100"])
def test_examples(mv: str, monkeypatch: pytest.MonkeyPatch) -> None:
    text = f'[a]\n[goal:g]\n[action]\n[b#x#blk_inst: MV("{mv}") LD() AO("s, 0, 10")]\n'
    assert lowered(text) == field_by_field(text, monkeypatch)


def test_a_command_string_met_again_is_read_the_same_at_its_own_place() -> None:
    """Each distinct command string is split once (`_SPLIT`); where it is met again, its
    numbers get their own spans, and a string with an error is reported each time."""
    inst = '[b#x{}#blk_inst: MV("0, 0.1, 0, 0, 500") LD("1, x, 0, 1, 0, 500") AO("s.wav, 0, 9")]\n'
    text = "[a]\n[goal:g]\n[action]\n" + inst.format(1) + "  " + inst.format(2)
    script, diagnostics = lowered(text)
    first, second = script.goals[0].actions[0].blocks
    shift = text.index(inst.format(2)) - text.index(inst.format(1))

    def numbers(block):
        m, a = block.moves[0], block.audios[0]
        return [m.v_x, m.v_y, m.v_theta, m.wait_t, m.duration, a.wait_t, a.duration]

    assert [n.text for n in numbers(second)] == ["0", "0.1", "0", "0", "500", "0", "9"]
    for a, b in zip(numbers(first), numbers(second), strict=True):
        assert b.text == a.text and b.span == (a.span.start + shift, a.span.end + shift)
        assert text[b.span.start:b.span.end] == b.text
    assert [code for code, _, _ in diagnostics] == ["V002", "V002"]
    assert diagnostics[1][2].start - diagnostics[0][2].start == shift
    assert lowered(text) == (script, diagnostics)


@pytest.mark.parametrize("ao", ["songs/a.wav, ,0,0", "a,,0,0", " ,x,0,0", "a, ,b,0,0",
                                "a b.wav ,0, 0", "x,y,z,1,2"])
def test_audio_paths(ao: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The path is the text from its first part's first character to its last part's last,
    blanks of a blank last part included (found by the property above)."""
    text = f'[a]\n[goal:g]\n[action]\n[b#x#blk_inst: MV() LD() AO("{ao}")]\n'
    assert lowered(text) == field_by_field(text, monkeypatch)


@pytest.mark.parametrize("inside", ['% a ) here %', '% ( %', 'E: eq("(", ")")'])
def test_the_condition_of_a_jump_ends_at_its_own_parenthesis(inside: str) -> None:
    """A `)` inside a comment or a string of `CND(...)` does not end the condition (a comment
    cut the condition text short, `! {TRUE} % a`, an unterminated comment)."""
    condition = f"! {{{inside}}}" if inside.startswith("E:") else f"! {{TRUE}} {inside}"
    text = (f"[a]\n[goal:g]\n[action]\n[b#j#blk_jump: CND({condition}) TRJMP() FLSJMP()]\n"
            "[b##blk_terminus]\n")
    script, diagnostics = lower_script(SourceFile("a.script", text))
    assert diagnostics == []
    jump = script.goals[0].actions[0].blocks[0]
    assert jump.condition_text == condition


def _closing_paren_by_regex(text: str, at: int, end: int) -> int:
    """The `)` closing a parenthesis opened before `at`, by the regex of parentheses, strings
    and comments (the general way `_closing_paren` takes when a string or comment is there)."""
    depth = 1
    for m in lower._PARENS.finditer(text, at, end):
        depth += {"(": 1, ")": -1}.get(m.group(), 0)
        if depth == 0:
            return m.start()
    return -1


@FAST
@given(st.text(st.sampled_from('()ab "%\\'), max_size=40), st.integers(0, 5), st.integers(0, 5))
def test_the_closing_parenthesis_is_found_alike_with_or_without_strings(
        text: str, at: int, cut: int) -> None:
    """A jump's condition ends at the `)` closing `CND(`: counted at once where no string or
    comment can hold a parenthesis, else by the regex; both find the same one."""
    at, end = min(at, len(text)), max(min(at, len(text)), len(text) - cut)
    assert lower._closing_paren(text, at, end) == _closing_paren_by_regex(text, at, end)
