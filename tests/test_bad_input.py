"""Hostile input: each gets diagnostics in bounded time, never an exception, a RecursionError
or a hang (the CLI's own handling of bytes and paths is in test_cli.py)."""

from __future__ import annotations

import pytest

from scriptc.analysis.analyze import analyze_script
from scriptc.frontend.script import parse_condition
from scriptc.source import SourceFile

HEAD = "[act]\n[goal:g]\n[action]\n"


def codes(text: str) -> list[str]:
    return [d.code for d in analyze_script(SourceFile("bad.script", text)).diagnostics]


def test_twenty_thousand_nested_parentheses() -> None:
    text = HEAD + "[b##blk_jump: CND(" + "(" * 20000 + ")" * 20000 + ") TRJMP() FLSJMP()]\n"
    assert codes(text) == ["P001"]


def test_twenty_thousand_nested_braces_in_a_condition() -> None:
    cond, problems = parse_condition("{" * 20000 + "}" * 20000)
    assert cond is None and [p.code for p in problems] == ["P001"]


def test_twenty_thousand_open_brackets_are_capped() -> None:
    found = codes("[" * 20000)
    assert 0 < len(found) <= 100 and set(found) == {"P002"}


@pytest.mark.slow
def test_the_scanner_keeps_no_more_diagnostics_than_are_shown() -> None:
    """A million stray `[` made a million diagnostics, one by one, to show a hundred (more
    than 20 s for a 1 MB line: the fuzz campaign's slow class); every item is still found."""
    from scriptc.syntax.scan import MAX_SYNTAX_ERRORS, scan

    scanned = scan("[" * 20000 + "x ]" * 5)
    assert len(scanned.diagnostics) == MAX_SYNTAX_ERRORS + 1
    assert len(scanned.items) == 20000


def _cpu_seconds(text: str) -> tuple[float, list[str]]:
    import time

    start = time.process_time()
    found = codes(text)
    return time.process_time() - start, found


def test_a_megabyte_of_blanks_in_an_audio_path_is_linear() -> None:
    """The audio command's pattern retried the blanks from each of them: quadratic, a 1 MB
    path of spaces never finished compiling (the fuzz campaign's `compile: hang`). Now about
    0.1 s for 200,000 blanks; quadratic took minutes."""
    text = (HEAD + '[b##blk_inst: MV() LD() AO("so' + " " * 200_000 + 'ng.wav, 0, 10")]\n'
            "[b##blk_terminus]\n")
    took, found = _cpu_seconds(text)
    assert found == [] and took < 5, took


def test_a_megabyte_of_blanks_before_a_syntax_error_is_linear() -> None:
    """Naming the open parenthesis of a syntax error (`MV(`) searched for the word before it
    with a regex anchored at the end, from each blank: quadratic (`fmt: hang`)."""
    text = HEAD + "[b##blk_jump:" + " " * 200_000 + "CND(! {E: eq(1, }) TRJMP() FLSJMP()]\n"
    took, found = _cpu_seconds(text)
    assert found == ["P001"] and took < 5, took


def test_syntax_errors_stop_at_a_hundred_parsed_item_by_item_or_first() -> None:
    """Items that do not parse are reported up to `MAX_SYNTAX_ERRORS`; when the scan alone
    found more, the last says so in a note. Lowering parses each item as it lowers it
    (`each_item`) and reports what parsing them all first reports (`parse_items`), in the
    same order."""
    from scriptc.frontend.script import Lowerer, lower_script
    from scriptc.syntax.parser import parse_items
    from scriptc.syntax.scan import MAX_SYNTAX_ERRORS

    note = f"scriptc stopped after {MAX_SYNTAX_ERRORS} syntax errors; fix these first"
    for text, noted in ((HEAD + "[b##blk_inst: MV(1)]\n" * 150 + "[b##blk_terminus]\n", False),
                        (HEAD + "[" * 300, True)):
        _, streamed = lower_script(SourceFile("s.script", text))
        parsed = parse_items(text)
        lowerer = Lowerer(text)
        lowerer.script(SourceFile("s.script", text), parsed)
        assert streamed == lowerer.diagnostics == parsed.diagnostics
        assert len(streamed) == MAX_SYNTAX_ERRORS
        assert [note in d.notes for d in streamed] == [False] * (MAX_SYNTAX_ERRORS - 1) + [noted]
    # the syntax errors come first, then lowering's, wherever they are in the file
    text = HEAD + '[b##blk_inst: MV("x, 0, 0, 0, 0") LD() AO()]\n' + "[b##blk_inst: MV(1)]\n" * 3
    assert [d.code for d in lower_script(SourceFile("s.script", text))[1]] == ["P002"] * 3 + [
        "V002"]


def test_unclosed_everything() -> None:
    found = codes('[act\n[goal:g\n[action\n[b##blk_inst: MV("1, 0')
    assert found == ["P002", "P002", "P002", "P003"]


@pytest.mark.parametrize("number", ["1e999", "-1e999", "1" * 400])
def test_huge_numbers(number: str) -> None:
    text = HEAD + f'[b##blk_inst: MV("{number}, 0, 0, 0, 100") LD() AO()]\n[b##blk_terminus]\n'
    assert "V003" in codes(text)


@pytest.mark.parametrize("word", ["nan", "NaN", "inf", "-Infinity"])
def test_non_finite_words(word: str) -> None:
    text = HEAD + f'[b##blk_inst: MV("{word}, 0, 0, 0, 100") LD() AO()]\n[b##blk_terminus]\n'
    assert codes(text) == ["V003"]


def test_huge_time_is_refused() -> None:
    text = (HEAD + '[b##blk_inst: MV("0, 0, 0, 0, 99999999999999999999") LD() AO()]\n'
            "[b##blk_terminus]\n")
    assert "V006" in codes(text)


@pytest.mark.slow
def test_many_megabytes_of_one_line() -> None:
    """A 4 MB comment and a megabyte of items, all on one line (the items cost ~0.1 ms each,
    which bench/bench_compile.py measures; the test holds correctness, not speed)."""
    text = (HEAD + "% " + "x" * 4_000_000 + " %" + "[b##blk_inst: MV() LD() AO()]" * 30_000
            + "[b##blk_terminus]")
    assert len(text) > 4_000_000
    assert codes(text) == []


def test_many_megabytes_of_junk_is_one_error() -> None:
    assert codes("x" * 5_000_000) == ["P008"]


def test_control_characters_and_nul() -> None:
    found = codes(HEAD + "[b##blk_terminus]\x00\x01\n")
    assert found == ["P008"]


def test_crlf_and_lone_cr_line_endings() -> None:
    text = ("[act]\r\n[goal:g]\r[action]\r\n[b##blk_jump: CND(! {TRUE}) TRJMP(x) FLSJMP()]\r\n"
            "[b#x#blk_terminus]")
    analysis = analyze_script(SourceFile("crlf.script", text))
    assert analysis.ok


def test_completion_in_a_megabyte_word_is_linear() -> None:
    """Completion read the word before the cursor with a regex anchored at the end, which
    retried the rest of a run of name characters from each of them: quadratic (the fuzz
    campaign's `editor: hang`, a 1 MB word then a bracket took minutes)."""
    import time

    from scriptc.ide.completion import complete
    from scriptc.ide.snapshot import Snapshot

    text = HEAD + "[b##blk_jump: CND(" + "x" * 200_000 + ")" + "abc"
    snapshot = Snapshot.of_text(text)
    start = time.process_time()
    items = complete(snapshot, len(text))
    took = time.process_time() - start
    assert [i.label for i in items] == ["TRJMP"] and took < 5, took
