"""The formatter (`scriptc.formatter`): case files, the API the language server calls, refusals,
line endings and range formatting.

Case files (the `fmt` aspect of tests/harness/, run by tests/test_cases.py):
`tests/cases/fmt/NAME.script` is the input, `NAME.fmt.script` beside it the exact expected
output; each is also checked to be a fixed point of the formatter and to compile to the same
JSON (or the same diagnostic codes) before and after.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from harness import CASES
from harness.aspects import fmt_inputs

from scriptc.diagnostics.edits import apply_edits
from scriptc.formatter import LINE_WIDTH, FormatResult, format_range, format_text

FMT = CASES / "fmt"
INPUTS = fmt_inputs()


def test_canonical_case_is_unchanged() -> None:
    text = (FMT / "canonical.script").read_text(encoding="utf-8")
    assert format_text(text).text == text


# ---------------------------------------------------------------------------------------------
# The API


def test_result_of_a_clean_script() -> None:
    result = format_text("[a]\n[goal:g]\n[action]\n[b##blk_terminus]\n")
    assert isinstance(result, FormatResult)
    assert result.text == "[a]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n"
    assert result.diagnostics == [] and not result.refused


@pytest.mark.parametrize("text,code", [
    ('[a]\n[goal:g]\n[action]\n[b##blk_inst MV() LD() AO()]\n', "P001"),
    ("[a]\n[goal:g\n[action]\n", "P002"),
    ('[a]\n[goal:g]\n[action]\n[b##blk_sens: "open]\n', "P003"),
    ("[a] % never closed\n[goal:g]\n", "P004"),
    ("[a]\nstray words\n[goal:g]\n", "P008"),
    ("[a]\n[b##blk_jump: CND(! {E: gt(1 < 2)}) TRJMP() FLSJMP()]\n", "P002"),
])
def test_syntax_errors_refuse(text: str, code: str) -> None:
    result = format_text(text)
    assert result.refused and result.text is None
    assert code in [d.code for d in result.diagnostics]


def test_semantic_errors_do_not_refuse() -> None:
    """Only syntax errors stop the formatter: a jump to a missing label is still laid out."""
    text = "[a]\n[goal:g]\n[action]\n[b##blk_jump: CND(!{TRUE}) TRJMP(nowhere) FLSJMP()]\n"
    assert format_text(text).text == (
        "[a]\n[goal:g]\n  [action]\n    [b##blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n"
    )


@pytest.mark.parametrize("text,expected", [
    ("", ""),
    ("   \n\n", ""),
    ("%c%", "%c%\n"),
    ("[a]", "[a]\n"),
    ("\n\n[a]\n\n\n", "[a]\n"),
])
def test_edges(text: str, expected: str) -> None:
    assert format_text(text).text == expected


def test_crlf_stays_crlf() -> None:
    source = (FMT / "comments.script").read_bytes().decode("utf-8")
    expected = (FMT / "comments.fmt.script").read_bytes().decode("utf-8")
    crlf = source.replace("\n", "\r\n")
    assert format_text(crlf).text == expected.replace("\n", "\r\n")


def test_lone_cr_line_endings_are_kept() -> None:
    assert format_text("[a]\r[goal:g]\r[action]\r[b##blk_terminus]").text == (
        "[a]\r[goal:g]\r  [action]\r    [b##blk_terminus]\r"
    )


def test_mixed_line_endings_take_the_first() -> None:
    assert format_text("[a]\r\n[goal:g]\n[action]\n").text == "[a]\r\n[goal:g]\r\n  [action]\r\n"


def test_wrapped_lines_fit_when_they_can() -> None:
    """What the formatter writes of long items: every line fits the width, but a line that
    holds one string alone (a command or payload longer than the width, which cannot be cut)."""
    text = (FMT / "wrap_instruction.script").read_text(encoding="utf-8")
    assert max(map(len, text.splitlines())) > LINE_WIDTH
    out = format_text(text).text
    assert out is not None and out.count("\n") > text.count("\n")
    for line in out.splitlines():
        if len(line) > LINE_WIDTH:
            assert line.count('"') <= 2, line


def test_strings_and_numbers_keep_their_text() -> None:
    text = ('[a]\n[alfa:007, r, "a  b\\\\", "", A, U]\n[goal:g]\n[action]\n'
            '[b##blk_jump: CND(! {E: eq(1.50, "x\\"y")}) TRJMP() FLSJMP()]\n')
    out = format_text(text).text
    assert '[alfa:007, r, "a  b\\\\", "", A, U]' in out
    assert 'eq(1.50, "x\\"y")' in out


def test_command_with_backslash_before_the_quote_is_left_alone() -> None:
    """Trimming `"...2 \\ "` would make the backslash escape the closing quote."""
    text = '[a]\n[goal:g]\n[action]\n[b##blk_inst: MV("0,0,0,0, 2\\ ") LD() AO("p,0, 1\\ ")]\n'
    out = format_text(text).text
    assert 'MV("0,0,0,0, 2\\ ")' in out and 'AO("p,0, 1\\ ")' in out


# ---------------------------------------------------------------------------------------------
# format_range


MESSY = "[a]\n[goal:g]\n[action]\n[b##blk_inst:MV() LD() AO()]\n[b##blk_terminus]\n"


def test_range_of_everything_is_format_text() -> None:
    for path in INPUTS:
        text = path.read_text(encoding="utf-8")
        assert apply_edits(text, format_range(text, 0, len(text))) == format_text(text).text, path


def test_range_reformats_only_the_items_it_touches() -> None:
    at = MESSY.index("[b##blk_inst")
    edits = format_range(MESSY, at + 3, at + 5)
    assert apply_edits(MESSY, edits) == MESSY.replace("[b##blk_inst:MV()", "    [b##blk_inst: MV()")
    for (start, end), _new in ((e.span, e.new_text) for e in edits):
        assert MESSY.index("[action]") + len("[action]") <= start
        assert end <= MESSY.index("]\n[b##blk_t")


def test_empty_range_takes_the_item_at_the_cursor() -> None:
    at = MESSY.index("[action]") + 2
    assert (apply_edits(MESSY, format_range(MESSY, at, at))
            == MESSY.replace("[action]", "  [action]"))


def test_range_of_a_formatted_text_has_no_edits() -> None:
    text = format_text(MESSY).text
    assert format_range(text, 0, len(text)) == []


def test_range_works_beside_a_syntax_error_and_never_touches_it() -> None:
    text = "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV( LD() AO()]\n[b##blk_terminus]\n"
    whole = apply_edits(text, format_range(text, 0, len(text)))
    assert whole == ("[a]\n[goal:g]\n  [action]\n[b##blk_inst: MV( LD() AO()]\n"
                     "    [b##blk_terminus]\n")
    broken = text.index("MV(")
    assert format_range(text, broken, broken + 1) == []


def test_range_clamps_offsets() -> None:
    assert apply_edits(MESSY, format_range(MESSY, -5, 10**6)) == format_text(MESSY).text


def test_examples_in_docs_are_formatted() -> None:
    """The scriptc examples of docs/editors.md are in the layout they describe."""
    import re

    doc = (Path(__file__).parent.parent / "docs" / "editors.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```scriptc\n(.*?)```", doc, re.DOTALL)
    assert len(blocks) >= 2
    for block in blocks:
        assert format_text(block).text == block


def test_a_formatter_bug_raises_instead_of_changing_meaning(monkeypatch) -> None:
    """The self-check: with spacing broken on purpose (`U F:` glued into `UF:`), the output
    would mean something else, so format_text raises rather than return it."""
    import scriptc.emit.printer as layout
    import scriptc.formatter as fmt

    monkeypatch.setattr(layout, "_space", lambda *args: "")
    text = "[a]\n[goal:g]\n[action]\n[b##blk_jump: CND({VAR @v U F: now()} !) TRJMP() FLSJMP()]\n"
    with pytest.raises(fmt.FormatterError):
        format_text(text)
