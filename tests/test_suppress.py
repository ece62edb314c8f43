"""Suppression comments (`% scriptc: ignore[...] %`): what they cover and what they cannot
silence. The case files `tests/cases/config/suppress_*.script` (and `checks/fixes_keep_crlf`)
hold most of the behaviour, the C003 fix's text included; these tests hold what a case file
cannot show (the explain examples, where suppressed diagnostics go)."""

from __future__ import annotations

import pytest
from test_check_explanations import example_script

from scriptc.analysis.analyze import analyze_bytes, analyze_script
from scriptc.analysis.suppress import find_suppressions
from scriptc.source import SourceFile

HEAD = "[act]\n[goal:g]\n[action]\n"
UNREACHABLE = (HEAD + "[b##blk_jump: CND(! {TRUE}) TRJMP(end) FLSJMP()]\n"
               "[b##blk_inst: MV() LD() AO()]{comment}\n"
               "[b#end#blk_terminus]\n")


def lint(text: str):
    return analyze_script(SourceFile("t.script", text))


def codes(text: str) -> list[str]:
    return [d.code for d in lint(text).diagnostics]


@pytest.mark.parametrize("code", ["C003", "C004", "C006"])
def test_explanation_examples_trigger_their_code(code: str) -> None:
    from scriptc.diagnostics.codes import explanation

    assert code in codes(example_script(explanation(code)))


def test_suppressed_diagnostics_are_kept_aside() -> None:
    analysis = lint(UNREACHABLE.replace("{comment}", " % scriptc: ignore[F001] %"))
    assert analysis.diagnostics == []
    assert [d.code for d in analysis.suppressed] == ["F001"]
    assert analysis.ok


@pytest.mark.parametrize("comment, left", [
    (" % scriptc: ignore[F001] %", []),
    ("% scriptc: ignore[unreachable-block] %", []),
    (" % scriptc:ignore[ f001 ] %", []),
    (" % scriptc: ignore[F001, M004] % % another comment %", ["C003"]),  # M004: unused
    ("\n% scriptc: ignore[F001] %", ["F001", "C003"]),  # precedes the terminus, not this
])
def test_forms_that_suppress(comment: str, left: list[str]) -> None:
    assert codes(UNREACHABLE.replace("{comment}", comment)) == left


def test_a_comment_inside_a_multiline_item_covers_all_of_it() -> None:
    text = (HEAD + "[b##blk_jump: CND(! {TRUE}) TRJMP(end) FLSJMP()]\n"
            "[b##blk_inst:\n  MV()\n  % scriptc: ignore[F001, A001] %\n  LD()\n"
            '  AO("/abs.wav, 0, 1")]\n[b#end#blk_terminus]\n')
    assert codes(text) == []


def test_errors_are_never_suppressed() -> None:
    text = HEAD + ("[b##blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]"
                   " % scriptc: ignore[L003] %\n"
                   "% scriptc: ignore-file[unknown-label] %\n[b##blk_terminus]\n")
    analysis = lint(text)
    assert [d.code for d in analysis.diagnostics] == ["L003", "C004", "C004"]
    assert not analysis.ok and analysis.suppressed == []


def test_json_has_no_suppressions() -> None:
    # Thesis JSON has no comments: a "scriptc:" in a string is just text.
    from scriptc.analysis.analyze import analyze_json

    text = '{"activityname": "scriptc: ignore[F001]"}'
    assert "C006" not in [d.code for d in analyze_json(SourceFile("t.json", text)).diagnostics]


def test_a_file_without_the_marker_is_not_scanned(monkeypatch) -> None:
    def boom(*args):
        raise AssertionError("scanned")

    monkeypatch.setattr("scriptc.syntax.scan.scan", boom)
    assert find_suppressions(SourceFile("t", "[a] % scripts: ignore %")) == ([], [])


def test_unused_is_not_reported_when_the_checks_did_not_run() -> None:
    text = HEAD + "[b##blk_inst: MV() LD() AO()] % scriptc: ignore[F001] %\n[b##blk_bogus]\n"
    assert codes(text) == ["P001"]


def test_ignore_file_can_silence_the_suppression_warnings() -> None:
    text = HEAD + "% scriptc: ignore-file[C003] %\n[b##blk_terminus] % scriptc: ignore[F001] %\n"
    analysis = lint(text)
    assert analysis.diagnostics == [] and [d.code for d in analysis.suppressed] == ["C003"]


def test_bytes_with_a_bom_and_crlf() -> None:
    data = b"\xef\xbb\xbf" + UNREACHABLE.replace("{comment}", " % scriptc: ignore[F001] %").replace(
        "\n", "\r\n").encode()
    assert analyze_bytes("t.script", data).diagnostics == []
