"""Incremental analysis (scriptc.ide.incremental, layout, shift, document): an edit re-parses
only the items it touched, and the result is always what `scriptc lint` reports for the
document's text (`analyze_script`), whatever the edits."""

from __future__ import annotations

import dataclasses
import random
import sys
from pathlib import Path

import pytest
from harness import CASES

from scriptc.analysis.analyze import analyze_script
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.ide.document import Document, canonical
from scriptc.ide.incremental import INITIAL_PAD, MAX_PAD, SLACK, Analyzer, Stats
from scriptc.ide.pads import Layout
from scriptc.ir import nodes
from scriptc.ir.shift import _MAPPERS, _SHIFTERS, map_spans, shift
from scriptc.source import SourceFile, Span
from scriptc.syntax.scan import scan

sys.path.insert(0, str(Path(__file__).parent.parent / "bench"))
from generate import big_script

# The case scripts (but the editor's, with a cursor `$0`), by name: a test's id must be the
# same in every process (a mutation run maps tests to lines in one and runs them in another).
CASE_SCRIPTS = {
    name: text for name, text in (
        (p.relative_to(CASES).as_posix(), p.read_bytes().decode("utf-8", "replace"))
        for p in sorted(CASES.rglob("*.script")))
    if "$0" not in text}
SCRIPTS = list(CASE_SCRIPTS.values())


def real(d: Diagnostic, layout: Layout) -> Diagnostic:
    """A diagnostic of a snapshot in the document's offsets."""
    def f(s: Span) -> Span:
        return Span(layout.to_real(s.start), layout.to_real(s.end))

    fix = d.fix and Fix(d.fix.message, tuple(TextEdit(f(e.span), e.new_text) for e in d.fix.edits),
                        d.fix.safe)
    return Diagnostic(d.code, d.severity, d.message, f(d.span),
                      tuple(Label(f(label.span), label.message) for label in d.labels),
                      d.notes, d.help, fix, d.path)


def assert_same_as_lint(doc: Document) -> None:
    snapshot = doc.snapshot()
    fresh = analyze_script(SourceFile(doc.path, doc.text)).diagnostics
    assert [real(d, snapshot.layout) for d in snapshot.diagnostics] == fresh
    # The scan (partly redone after an edit inside one item) is the scan of the whole text.
    whole = scan(snapshot.text)
    assert (snapshot.items, snapshot.comments, snapshot.result.scan.diagnostics) == (
        whole.items, whole.comments, whole.diagnostics)
    # The analysis text is the document's text with pads of spaces after items.
    pieces, last = [], 0
    for p, n in snapshot.layout.pads:
        assert snapshot.text[p:p + n] == " " * n and snapshot.text[p - 1] == "]"
        pieces.append(snapshot.text[last:p])
        last = p + n
    pieces.append(snapshot.text[last:])
    assert "".join(pieces) == doc.text


# -- the incremental path is the one taken -------------------------------------------------------


@pytest.mark.slow
def test_a_keystroke_reparses_one_item() -> None:
    text = big_script(560)  # about 90 KB
    doc = Document("big", text)
    first = doc.snapshot()
    distinct = len({first.text[i.span.start:i.span.end] for i in first.items})
    assert first.stats.parsed == distinct and first.stats.items == len(first.items)
    for start in [300, len(text) // 2, len(text) - 3000]:
        at = doc.text.index('MV("0.', start) + len('MV("0.')
        doc.replace(at, at, "5")
        stats = doc.snapshot().stats
        assert (stats.parsed, stats.lowered) == (1, 1), stats
        assert stats.shifted_lowerings == 0, "the pad after the item absorbed the keystroke"
        assert stats.reused_parses == stats.items - 1
        doc.replace(at, at + 1, "")
        assert doc.snapshot().stats.parsed == 0  # the old text of the item is still cached
    assert_same_as_lint(doc)


def test_a_structural_edit_moves_items_by_shifting() -> None:
    text = big_script(100)
    doc = Document("big", text)
    doc.snapshot()
    at = doc.text.index("[goal:goal0]")
    doc.replace(at, at, "% a new comment before the goal %\n")  # between items: no pad takes it
    stats = doc.snapshot().stats
    assert stats.parsed == 0 and stats.lowered == 0 and stats.shifted_lowerings > 50
    assert_same_as_lint(doc)


def test_without_slack_the_analysis_text_is_the_text() -> None:
    text = SCRIPTS[0]
    result = Analyzer().analyze(text)
    assert result.source.text == text and result.layout.identity


# -- equal to a fresh analysis ------------------------------------------------------------------


@pytest.mark.parametrize("name", list(CASE_SCRIPTS)[:200])
def test_every_case_file(name: str) -> None:
    text = CASE_SCRIPTS[name]
    analyzer = Analyzer()
    result = analyzer.analyze(text)
    fresh = analyze_script(SourceFile("", text))
    assert result.diagnostics == fresh.diagnostics
    assert result.script == fresh.script
    # Analysing again, from the caches, gives the same.
    again = analyzer.analyze(text)
    assert again.diagnostics == fresh.diagnostics and again.stats.parsed == 0


ALPHABET = list('[]#(){}",%!?:>&@$ \nabcxyzMVLDAO0123456789.') + [
    "blk_inst", "blk_jump", "TRJMP(", "[b#", "OP<", "😀", "é", "\r\n", "\ud83d", "\ude00",
    "% scriptc: ignore[F001] %"]


@pytest.mark.slow
def test_random_edits_equal_a_fresh_analysis() -> None:
    """Random edits, mostly small and inside items (what typing does), some anywhere."""
    rng = random.Random(5)
    steps = 0
    for _ in range(60):
        doc = Document("x", rng.choice(SCRIPTS))
        doc.snapshot()
        for _ in range(rng.randint(1, 30)):
            n = len(doc.text)
            i = rng.randint(0, n)
            j = min(n, i + rng.choice([0, 0, 0, 1, 1, 2, 5, 40]))
            new = "".join(rng.choice(ALPHABET) for _ in range(rng.choice([0, 1, 1, 1, 2, 3])))
            doc.replace(i, j, new)
            if rng.random() < 0.2:  # several edits before one analysis
                k = rng.randint(0, len(doc.text))
                doc.replace(k, k, rng.choice(ALPHABET))
            assert_same_as_lint(doc)
            steps += 1
    assert steps > 500


@pytest.mark.slow
def test_typing_through_a_large_script() -> None:
    """Digits typed into and deleted from numbers all over a valid script: the checks run
    every time, and the pads take every keystroke."""
    import re

    rng = random.Random(11)
    doc = Document("big", big_script(80))
    doc.snapshot()
    digit = re.compile(r"[0-9]")
    for _ in range(80):
        at = digit.search(doc.text, rng.randrange(len(doc.text) - 200)).start()
        if rng.random() < 0.5:
            doc.replace(at, at, str(rng.randint(0, 9)))
        else:
            doc.replace(at, at + 1, "")
        assert_same_as_lint(doc)


STATS_SCRIPT = """[demo]
[alfa:0, kick, "", "", C, U]
[goal:g]
  [action]
    [b##blk_inst: MV("0, 0, 0, 1000, 1000")]
    [b##blk_inst: MV("0, 0, 0, 1000, 1000")]
"""


def test_stats_count_what_each_analysis_did() -> None:
    """Six items, two of them the same text: five parses; the two blocks and the rule message
    are lowered. Again: everything reused. A comment before the goal moves the blocks: their
    lowerings are shifted, the rule message's reused."""
    analyzer = Analyzer()
    first = analyzer.analyze(STATS_SCRIPT)
    assert dataclasses.asdict(first.stats) == {
        "items": 6, "parsed": 5, "reused_parses": 1, "lowered": 3, "reused_lowerings": 0,
        "shifted_lowerings": 0, "scanned": len(STATS_SCRIPT)}
    again = analyzer.analyze(STATS_SCRIPT)
    assert dataclasses.asdict(again.stats) == {
        "items": 6, "parsed": 0, "reused_parses": 6, "lowered": 0, "reused_lowerings": 3,
        "shifted_lowerings": 0, "scanned": len(STATS_SCRIPT)}
    moved = analyzer.analyze(STATS_SCRIPT.replace("[goal:g]", "% a comment %\n[goal:g]"))
    assert dataclasses.asdict(moved.stats) == {
        "items": 6, "parsed": 0, "reused_parses": 6, "lowered": 0, "reused_lowerings": 1,
        "shifted_lowerings": 2, "scanned": len(STATS_SCRIPT) + len("% a comment %\n")}
    assert dataclasses.asdict(Stats()) == dict.fromkeys(dataclasses.asdict(first.stats), 0)


def test_a_keystroke_scans_only_its_item() -> None:
    """The scanner reads the text (then the text with its pads) when a document opens, only
    the item after a keystroke inside it (up to its `]`), and the whole analysis text after
    an edit between items, which keeps the pads as they were."""
    text = ('[demo]\n[goal:g]\n  [action]\n    [b##blk_inst: MV("0, 0, 0, 1000, 1000")]\n'
            '    [b##blk_inst: MV("0, 0, 0, 2000, 1000")]\n')
    doc = Document("x", text)
    opened = doc.snapshot()
    assert opened.stats.scanned == len(text) + len(text) + 5 * INITIAL_PAD
    at = doc.text.index("2000")
    doc.replace(at, at, "1")
    typed = doc.snapshot()
    item = typed.items[-1]
    assert typed.text[item.span.start:item.span.end] == '[b##blk_inst: MV("0, 0, 0, 12000, 1000")]'
    assert typed.stats.scanned == item.span.end - item.span.start
    at = doc.text.index(")]", at) + 1  # right before the `]`
    doc.replace(at, at, " ")
    assert doc.snapshot().stats.scanned == item.span.end - item.span.start + 1
    assert_same_as_lint(doc)
    doc.replace(doc.text.index("[goal"), doc.text.index("[goal"), "\n")
    between = doc.snapshot()
    assert between.stats.scanned == len(between.text)
    assert [n for _p, n in between.layout.pads] == [INITIAL_PAD] * 4 + [INITIAL_PAD - 2]
    assert_same_as_lint(doc)


def pads_by_item(doc: Document) -> list[tuple[int, int]]:
    """The pads of the document's analysis: (the document offset of the item's end, length)."""
    layout = doc.snapshot().layout
    return [(layout.to_real(p), n) for p, n in layout.pads]


def item_ends(text: str) -> list[int]:
    return [i + 1 for i, c in enumerate(text) if c == "]"]


def test_pads_follow_each_kind_of_edit() -> None:
    """Where each pad is and how long, after each kind of edit (scriptc.ide.pads): typing
    inside an item takes from its pad, or gives it SLACK when it runs out (the items after it
    move); a deletion inside an item gives to its pad; typing between items, or right after
    an item's `]`, moves the pads after it and changes none. The analysis never starts
    again, and the scanner reads one item, or the whole analysis text once."""
    text = ('[demo]\n[goal:g]\n  [action]\n    [b##blk_inst: MV("0, 0, 0, 1000, 1000")]\n'
            '    [b##blk_inst: MV("0, 0, 0, 2000, 1000")]% a comment right after it %\n')
    doc = Document("x", text)
    assert pads_by_item(doc) == [(end, INITIAL_PAD) for end in item_ends(text)]
    lengths = [INITIAL_PAD] * 5  # 0: no pad

    def check(scanned: int | None = None) -> None:
        assert pads_by_item(doc) == [
            (end, n) for end, n in zip(item_ends(doc.text), lengths, strict=True) if n]
        snapshot = doc.snapshot()
        whole = len(snapshot.text)
        assert snapshot.stats.scanned == (whole if scanned is None else scanned)
        assert_same_as_lint(doc)

    at = doc.text.index("1000")  # 20 characters inside the fourth item: its pad runs out
    doc.replace(at, at, "1" * 20)
    lengths[3] = SLACK
    check()
    at = doc.text.index("[goal")  # between items
    doc.replace(at, at, "% note %\n")
    check()
    at = doc.text.index("2000")  # a deletion inside the fifth item
    doc.replace(at, at + 3, "")
    lengths[4] += 3
    check(scanned=len('[b##blk_inst: MV("0, 0, 0, 0, 1000")]'))
    doc.replace(1, 5, "dumb")  # a replacement as long as what it replaces
    check(scanned=len("[dumb]"))
    end = item_ends(doc.text)[3]  # typing right after an item's `]` goes after its pad
    doc.replace(end, end, "\n")
    check()
    end = item_ends(doc.text)[1]  # an edit that ends at an item's end stops before its pad
    doc.replace(end - 2, end, "gg]")
    check()
    # Typing as much as the pad holds into the fifth item leaves it none; a deletion then
    # gives it one again (the comment right after the item stays where it is); typing
    # more than that gives it SLACK.
    at = doc.text.index("0, 1000\")]% a")
    doc.replace(at, at, "1" * lengths[4])
    lengths[4] = 0
    check(scanned=len('[b##blk_inst: MV("0, 0, 0, 11111111111111111110, 1000")]'))
    doc.replace(at, at + 1, "")
    lengths[4] = 1
    check(scanned=len('[b##blk_inst: MV("0, 0, 0, 1111111111111111110, 1000")]'))
    doc.replace(at, at, "22")
    lengths[4] = SLACK
    check()
    # Two edits inside one item before one analysis: the first takes from the pad, the
    # second is followed as an edit anywhere (it moves the pads after it).
    at = doc.text.index("0, 0, 0, 1")
    doc.replace(at, at, "1")
    doc.replace(at, at, "2")
    lengths[3] -= 1
    check()


def test_the_cache_keeps_one_version_back() -> None:
    """An item's old text stays cached one analysis longer (an undo parses nothing), then
    goes: memory follows the document."""
    versions = [STATS_SCRIPT.replace("1000, 1000", f"{n}, 1000", 1) for n in (1500, 2000, 3000)]
    analyzer = Analyzer()
    for text in versions:
        analyzer.analyze(text)
    assert analyzer.analyze(versions[1]).stats.parsed == 0  # one back: still cached
    analyzer.analyze(versions[2])
    assert analyzer.analyze(versions[0]).stats.parsed == 1  # two back: parsed again


def test_cached_syntax_errors_hold_no_frames() -> None:
    """A cached syntax error keeps no traceback (its frames would hold the analysis in a
    reference cycle until a full collection); the error raised from the cache is a copy."""
    analyzer = Analyzer()
    text = "[demo]\n[goal:g]\n[action]\n[b##blk_inst: MV(]\n"
    result = analyzer.analyze(text)
    assert result.diagnostics == analyze_script(SourceFile("", text)).diagnostics
    errors = [entry.error for entry in analyzer._current.values() if entry.error is not None]
    assert len(errors) == 1
    assert (errors[0].__traceback__, errors[0].__context__, errors[0].__cause__) == (
        None, None, None)
    again = analyzer.analyze(text)
    assert again.diagnostics == result.diagnostics and again.stats.parsed == 0


def test_set_text_starts_again() -> None:
    doc = Document("x", SCRIPTS[1])
    doc.snapshot()
    doc.set_text(SCRIPTS[2])
    assert_same_as_lint(doc)


def assert_lint_of(result, text: str) -> None:
    fresh = analyze_script(SourceFile("", text)).diagnostics
    assert [real(d, result.layout) for d in result.diagnostics] == fresh
    assert "".join(result.source.text[p:p + n] for p, n in result.layout.pads).strip() == ""


def test_edits_that_cannot_be_followed_start_again() -> None:
    """The language server's recovery: edits that do not lead to the text the client sent (a
    change lost on the way), or that end before they start, are not followed; the analysis
    starts again from the text, with fresh pads."""
    first, second = SCRIPTS[1], SCRIPTS[2]
    assert len(first) != len(second)
    analyzer = Analyzer(slack=True)
    analyzer.analyze(first)
    result = analyzer.analyze(second, edits=[(0, 0, "")])
    assert_lint_of(result, second)
    assert {n for _p, n in result.layout.pads} == {INITIAL_PAD}
    at = first.index("]") + 1
    result = analyzer.analyze(first, edits=[(at + 3, at, "")])
    assert_lint_of(result, first)
    assert {n for _p, n in result.layout.pads} == {INITIAL_PAD}
    # An edit that ends before it starts, sent with a text as long as following it would
    # make (three more characters: those it would repeat).
    inside = first.index("[") + 2
    longer = first + "   "
    result = analyzer.analyze(longer, edits=[(inside + 3, inside, "")])
    assert_lint_of(result, longer)
    assert result.source.text.replace(" ", "") == longer.replace(" ", "")


def test_a_large_deletion_inside_an_item_starts_again() -> None:
    """A deletion inside one item grows the pad after it by what it took out; past MAX_PAD
    the analysis text starts again from the document's (no pad longer than the first)."""
    path = "x" * (MAX_PAD + 300)
    text = (f'[a]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO("{path}, 0, 100")]\n'
            "[b##blk_terminus]\n")
    analyzer = Analyzer(slack=True)
    analyzer.analyze(text)
    at = text.index(path)
    small = text[:at] + text[at + 100:]
    result = analyzer.analyze(small, edits=[(at, at + 100, "")])
    assert_lint_of(result, small)
    assert max(n for _p, n in result.layout.pads) == INITIAL_PAD + 100  # the pad took it
    cut = MAX_PAD - INITIAL_PAD - 100
    large = small[:at] + small[at + cut:]
    result = analyzer.analyze(large, edits=[(at, at + cut, "")])
    assert_lint_of(result, large)
    assert max(n for _p, n in result.layout.pads) == MAX_PAD  # the longest pad kept
    larger = large[:at] + large[at + 1:]
    result = analyzer.analyze(larger, edits=[(at, at + 1, "")])
    assert_lint_of(result, larger)
    assert {n for _p, n in result.layout.pads} == {INITIAL_PAD}


# -- the pieces ---------------------------------------------------------------------------------


def test_layout_converts_both_ways() -> None:
    # Analysis text: "[a]" + 3 pad spaces + "\n[b]" + 2 pad spaces + "\n"
    layout = Layout(((3, 3), (10, 2)))
    assert ([layout.to_real(o) for o in (0, 3, 4, 5, 6, 7, 10, 11, 12, 13)]
            == [0, 3, 3, 3, 3, 4, 7, 7, 7, 8])
    assert layout.to_analysis(3) == 3 and layout.to_analysis(3, after=True) == 6
    assert layout.to_analysis(4) == 7 and layout.to_analysis(7) == 10
    assert layout.to_analysis(7, after=True) == 12 and layout.total == 5
    for r in range(9):
        assert layout.to_real(layout.to_analysis(r)) == r
        assert layout.to_real(layout.to_analysis(r, after=True)) == r


def test_shift_moves_every_span_and_only_spans() -> None:
    script = analyze_script(SourceFile("x", (CASES / "emit" / "features.script").read_text(
        encoding="utf-8"))).script
    moved = shift(script, 17)
    assert moved != script and shift(moved, -17) == script
    first_block = script.goals[0].actions[0].blocks[0]
    assert moved.goals[0].actions[0].blocks[0].span == first_block.span.shift(17)
    assert shift(script, 0) is script


def test_every_node_type_can_be_shifted() -> None:
    import dataclasses

    from scriptc.diagnostics import model

    for module in (nodes, model):
        for value in vars(module).values():
            if (isinstance(value, type) and dataclasses.is_dataclass(value)
                    and value.__module__ == module.__name__):
                assert value in _SHIFTERS, (f"{value.__name__} has no generated shifter "
                                            "(is it slotted?)")
                assert value in _MAPPERS, f"{value.__name__} has no generated mapper"


def test_map_spans_passes_every_span_through_the_remap() -> None:
    """`map_spans` with a shift is `shift`; with any other map, every span of the IR and of the
    diagnostics (labels and fixes too) is the map's image, and nothing else changes."""
    from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity, TextEdit

    script = analyze_script(SourceFile("x", (CASES / "emit" / "features.script").read_text(
        encoding="utf-8"))).script
    assert map_spans(script, lambda s: s.shift(17)) == shift(script, 17)
    doubled = map_spans(script, lambda s: Span(2 * s.start, 2 * s.end))
    block = script.goals[0].actions[0].blocks[0]
    assert doubled.goals[0].actions[0].blocks[0].span == Span(2 * block.span.start,
                                                              2 * block.span.end)
    assert map_spans(doubled, lambda s: Span(s.start // 2, s.end // 2)) == script
    d = Diagnostic("L003", Severity.ERROR, "m", Span(1, 2), labels=(Label(Span(3, 4), "l"),),
                   notes=("n",), fix=Fix("f", (TextEdit(Span(5, 6), "x"),)))
    moved = map_spans(d, lambda s: Span(s.start + 10, s.end + 20))
    assert moved == Diagnostic("L003", Severity.ERROR, "m", Span(11, 22),
                               labels=(Label(Span(13, 24), "l"),), notes=("n",),
                               fix=Fix("f", (TextEdit(Span(15, 26), "x"),)))
    assert map_spans(None, lambda s: s) is None


def test_canonical_joins_surrogate_pairs() -> None:
    assert canonical("a\ud83d\ude00b") == "a😀b"
    assert canonical("a\ud83db") == "a\ud83db"  # a lone half stays
    doc = Document("x", "[a] 😀")
    doc.replace(5, 5, "X")  # after the emoji
    assert doc.text == "[a] 😀X"
    doc = Document("x", "[a] \ud83d")
    doc.replace(5, 5, "\ude00")  # completes the pair
    assert doc.text == "[a] 😀"
    assert_same_as_lint(doc)
