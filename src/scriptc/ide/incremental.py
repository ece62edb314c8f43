"""Incremental analysis: a keystroke re-parses only the bracketed items it touched.

The front end already works item by item (`scriptc.syntax.parser.parse_items` scans the text
into `[...]` items and parses each one alone), which is what makes this cheap. Per analysis:

1. **Follow the edits** on the analysis text (the document's text with pads of spaces after
   edited items, `scriptc.ide.pads`): typing inside an item takes its length from the pad
   after the item, so no other item moves.
2. **Scan**: after an edit inside one item, only that item is scanned again and spliced into
   the previous scan (the scanner carries no state between items); otherwise the whole text
   (regex speed: 3 ms for 90 KB).
3. **Parse** each item through a cache keyed by the item's text: an item whose text did not
   change gets its old lark tree (or its old syntax error) back, wherever it now stands, and
   only new or changed items reach lark. Trees hold offsets relative to their item, so they
   do not care where the item moved. The items the previous analysis dropped are kept one
   analysis longer, so an undo parses nothing.
4. **Lower** each item through a cache keyed by the tree and the item's span: an item at the
   same place reuses its IR and diagnostics as they are; an item that moved (a structural
   edit, or a pad that ran out) gets its old IR moved by the difference
   (`scriptc.ir.shift`, a third of the cost of lowering again); only new items are lowered.
   The assembly of the hierarchy and the structure checks (S codes) run over all items: they
   are cheap and depend on the order of items.
5. **Check** the whole script with the passes of `scriptc.check`, then apply suppression
   comments, as the driver does (linear: 6 ms for 90 KB, most of what a keystroke costs).

On a 90 KB script a keystroke costs about 12-15 ms of CPU, wherever it is (bench/bench_lsp.py
gives the figures over stdio).

The result is by construction what `scriptc.analysis.analyze.analyze_script` gives for the
same text (an `IncrementalAnalysis` is an `Analysis`):
the same `parse_items` (given the spliced scan and a parser that answers from the cache of
item texts) and the same `Lowerer.script` run, with the two per-item methods of the lowerer
(`block`, `rule_message`) answered from the cache, then the same `scriptc.analysis.analyze.finish`.
`tests/test_ide_incremental.py` checks the equality with `analyze_script` (and of the spliced
scan with a whole scan) over random edits.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

from scriptc.analysis.analyze import Analysis, finish
from scriptc.diagnostics.model import Diagnostic
from scriptc.frontend import script as _lower
from scriptc.gcpause import gc_paused
from scriptc.ide.pads import IDENTITY, Layout
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.ir.shift import shift
from scriptc.source import SourceFile, Span
from scriptc.syntax import parser as _parser
from scriptc.syntax import scan as _scan
from scriptc.syntax.larkshim import UnexpectedInput
from scriptc.syntax.scan import RawItem, Scan

__all__ = ["Analyzer", "IncrementalAnalysis", "Stats"]


@dataclass
class Stats:
    """What the last analysis did: items parsed by lark, parses reused from the cache, items
    lowered, lowerings reused as they were and lowerings moved by a shift; and how many
    characters the scanner read (one item's after a keystroke inside it, else the text)."""

    items: int = 0
    parsed: int = 0
    reused_parses: int = 0
    lowered: int = 0
    reused_lowerings: int = 0
    shifted_lowerings: int = 0
    scanned: int = 0


class IncrementalAnalysis(Analysis):
    """One analysis of a document: an `Analysis` (source, script, diagnostics, suppressed),
    plus the scan that editor features read (item boundaries, comments) and what the analysis
    reused (`stats`). Offsets are those of `source.text`,
    the analysis text; `layout` converts them to offsets of `real`, the document's text (see
    scriptc.ide.pads)."""

    __slots__ = ("layout", "real", "scan", "stats")

    def __init__(self, source: SourceFile, scan: Scan, script: Script | None,
                 diagnostics: list[Diagnostic], suppressed: list[Diagnostic], stats: Stats,
                 layout: Layout, real: str) -> None:
        super().__init__(source, script, diagnostics, suppressed)
        self.scan = scan
        self.stats = stats
        self.layout = layout
        self.real = real


class _Entry:
    """The cache of one item text: its tree (or the syntax error lark raised for it) and the
    lowerings of that tree by item span."""

    __slots__ = ("error", "lowered", "next_lowered", "tree")

    def __init__(self, tree, error) -> None:
        self.tree = tree
        self.error = error
        self.lowered: dict[Span, tuple[object, tuple[Diagnostic, ...]]] = {}
        self.next_lowered: dict[Span, tuple[object, tuple[Diagnostic, ...]]] = {}


class _CachingParser:
    """Stands for the lark parser inside `parse_items`: `parse` answers from the cache of
    item texts and asks lark only for texts it has not seen. Everything else (the terminals
    `describe` reads to word an error) is lark's."""

    def __init__(self, analyzer: Analyzer) -> None:
        self._analyzer = analyzer
        self._lark = _parser.script_parser()

    def __getattr__(self, name: str):
        return getattr(self._lark, name)

    def parse(self, text: str, start: str | None = None):
        a = self._analyzer
        entry = a._current.get(text)
        if entry is None:
            entry = a._previous.pop(text, None) or a._spare.pop(text, None)
            if entry is None:
                a._stats.parsed += 1
                try:
                    entry = _Entry(self._lark.parse(text, start=start), None)
                except UnexpectedInput as error:
                    entry = _Entry(None, _bare(error))
            else:
                a._stats.reused_parses += 1
            a._current[text] = entry
        else:
            a._stats.reused_parses += 1
        if entry.error is not None:
            # A copy, so that the cached error never holds a traceback: its frames (this
            # one's `entry` among their locals, the caller's list of items) would make a
            # reference cycle, kept until the next full collection, which the server runs
            # only when idle.
            raise _fresh(entry.error)
        a._by_tree[id(entry.tree)] = entry
        return entry.tree


def _bare(error: BaseException) -> BaseException:
    """`error` without its traceback and the exceptions it was raised while handling."""
    error.__traceback__ = error.__context__ = error.__cause__ = None
    return error


def _fresh(error: BaseException) -> BaseException:
    """A new exception equal to `error` (its class, arguments and attributes), made without
    calling its `__init__` (lark's take arguments that `copy.copy` cannot give back)."""
    clone = type(error).__new__(type(error), *error.args)
    clone.__dict__.update(error.__dict__)  # BaseException.__new__ gave it the same args
    return clone


class _CachingLowerer(_lower.Lowerer):
    """The lowerer, with the two per-item steps answered from the cache."""

    analyzer: Analyzer

    def block(self, tree, span):
        return self._cached(tree, span, super().block)

    def rule_message(self, tree, span):
        return self._cached(tree, span, super().rule_message)

    def _cached(self, tree, span: Span, lower):
        a = self.analyzer
        # Every tree the lowerer is handed is an item's, from `_CachingParser.parse` (which
        # records it), and every IR value can be shifted (tests/test_ide_incremental.py holds
        # each node type to it).
        entry = a._by_tree[id(tree)]
        hit = entry.next_lowered.get(span) or entry.lowered.get(span)
        if hit is not None:
            a._stats.reused_lowerings += 1
        else:
            length = span.end - span.start
            for old_span, old in entry.lowered.items():
                if old_span.end - old_span.start == length:
                    delta = span.start - old_span.start
                    hit = (shift(old[0], delta), shift(old[1], delta))
                    a._stats.shifted_lowerings += 1
                    break
        if hit is None:
            mark = len(self.diagnostics)
            value = lower(tree, span)
            hit = (value, tuple(self.diagnostics[mark:]))
            del self.diagnostics[mark:]
            a._stats.lowered += 1
        entry.next_lowered[span] = hit
        self.diagnostics.extend(hit[1])
        return hit[0]


# The pads (see scriptc.ide.pads): every closed item gets INITIAL_PAD spaces when the
# analysis text is made from the document's text, and an item whose pad runs out gets SLACK
# (a line's worth of typing before the items after it move again). A pad longer than MAX_PAD
# (after a large deletion) makes the analyser start again from the document's text.
INITIAL_PAD = 16
SLACK = 64
MAX_PAD = 4096


# After an edit inside one item that moved nothing else: the item's index in the last scan,
# the item, and its end now.
_Rescan = tuple[int, RawItem, int]


def _layout(pads: dict[int, int]) -> Layout:
    return Layout(tuple(sorted(pads.items()))) if pads else IDENTITY


class Analyzer:
    """The analysis of one document as it changes. `analyze(text, edits=...)` gives the same
    result as `scriptc.analysis.analyze.analyze_script` for that text (in the offsets of the
    analysis text: see `scriptc.ide.pads`), reusing what it can of the previous call. Not
    thread-safe: one analyzer per document, used from one thread."""

    def __init__(self, functions: FunctionRegistry = STANDARD, *, slack: bool = False,
                 profile=None) -> None:
        self.functions = functions
        self.profile = profile  # the robot profile of the safety checks (None: the defaults)
        self.slack = slack  # keep pads after items (for documents being edited)
        self._current: dict[str, _Entry] = {}
        self._previous: dict[str, _Entry] = {}
        # The items the last analysis dropped: an undo brings them back.
        self._spare: dict[str, _Entry] = {}
        self._by_tree: dict[int, _Entry] = {}
        self._stats = Stats()  # of the analysis under way, or the last one
        self._real: str | None = None  # the document's text at the last analysis
        self._text = ""  # the analysis text
        self._pads: dict[int, int] = {}  # analysis offset -> length
        self._scanned = Scan([], [], [])  # the last scan (analysis offsets)

    # -- the analysis text --------------------------------------------------------------------

    def _scan(self, text: str) -> Scan:
        self._stats.scanned += len(text)
        return _scan.scan(text)


    def _follow(self, text: str, edits) -> tuple[bool, _Rescan | None]:
        """Apply the document's edits (`(start, end, new_text)` in document offsets, each on
        the text the previous one left) to the analysis text, keeping the pads. False when
        the edits cannot be followed (the analysis text then starts again from `text`);
        when they can, and were one edit inside one item that moved nothing else, what
        `_scan_edited_item` needs."""
        if self._real is None or edits is None:
            return False, None
        analysis = self._text
        pads = dict(self._pads)
        rescan = None
        for n, (start, end, new) in enumerate(edits):
            layout = _layout(pads)
            a = layout.to_analysis(start, after=True)
            b = layout.to_analysis(end, after=end == start) if end != start else a
            if b < a:
                return False, None
            # An edit over a pad (its start and end are never inside one) is refused by the
            # length check at the end: the pad it took out is still counted.
            delta = len(new) - (b - a)
            found = self._item_around(a, b) if n == 0 else None
            if found is not None:
                index, item = found
                x_end = item.span.end
                had = pads.pop(x_end, 0)
                keep = had - delta
                if keep < 0:
                    keep = SLACK
                if keep > MAX_PAD:
                    return False, None
                analysis = (analysis[:a] + new + analysis[b:x_end] + " " * keep
                            + analysis[x_end + had:])
                moved = delta + keep - had
                pads = {(p + moved if p > x_end else p): length for p, length in pads.items()}
                if keep:
                    pads[x_end + delta] = keep
                if moved == 0 and len(edits) == 1:
                    rescan = (index, item, x_end + delta)
            else:
                analysis = analysis[:a] + new + analysis[b:]
                pads = {(p + delta if p >= b else p): length for p, length in pads.items()}
        if len(analysis) - sum(pads.values()) != len(text):
            return False, None
        self._text, self._pads = analysis, pads
        return True, rescan

    def _item_around(self, a: int, b: int) -> tuple[int, RawItem] | None:
        """The closed item of the last scan holding `[a, b]` strictly inside its brackets,
        with its index."""
        items = self._scanned.items
        lo = bisect.bisect_left(items, a, key=lambda item: item.span.start)
        if lo == 0:
            return None
        item = items[lo - 1]  # the last item that starts before `a`
        if item.closed and not item.broken and b <= item.span.end - 1:
            return lo - 1, item
        return None

    def _scan_edited_item(self, rescan: _Rescan) -> Scan | None:
        """The scan of the analysis text after an edit inside one item that moved nothing
        else: the old scan with that item scanned again, when the item is still one closed
        item with nothing to report (otherwise None: scan everything). The scanner carries
        no state from one item to the next, so this is what scanning the whole text gives."""
        old = self._scanned
        index, item, end = rescan
        start = item.span.start
        part = self._scan(self._text[start:end])
        if (part.diagnostics or len(part.items) != 1 or not part.items[0].closed
                or part.items[0].broken or part.items[0].span != Span(0, end - start)):
            return None
        items = old.items[:index] + [RawItem(Span(start, end))] + old.items[index + 1:]
        comments = [c for c in old.comments if not start <= c.start < item.span.end]
        inside = [Span(c.start + start, c.end + start) for c in part.comments]
        if inside:
            at = bisect.bisect_left([c.start for c in comments], start)
            comments[at:at] = inside
        return Scan(items, comments, list(old.diagnostics))

    def _pads_hold(self, scanned: Scan) -> bool:
        """Every pad still sits right after the `]` of a closed item."""
        ends = {item.span.end for item in scanned.items if item.closed}
        return all(p in ends for p in self._pads)

    # -- analysis -------------------------------------------------------------------------------

    def _restart(self, text: str) -> Scan:
        """Make the analysis text from the document's text: with a pad after every closed
        item when `slack` is on. Returns the scan of the new analysis text."""
        scanned = self._scan(text)
        if not self.slack or not scanned.items:
            self._text, self._pads = text, {}
            return scanned
        pieces = []
        pads = {}
        last = 0
        added = 0
        pad = " " * INITIAL_PAD
        for item in scanned.items:
            if item.closed:
                end = item.span.end
                pieces.append(text[last:end])
                pieces.append(pad)
                pads[end + added] = INITIAL_PAD
                added += INITIAL_PAD
                last = end
        pieces.append(text[last:])
        self._text, self._pads = "".join(pieces), pads
        return self._scan(self._text)

    def analyze(self, text: str, path: str = "", edits=None) -> IncrementalAnalysis:
        """Analyse the document's `text`; `edits` are the changes since the last call (None:
        unknown, or a new document), which let the analysis keep its pads."""
        self._stats = Stats()
        followed, rescan = self._follow(text, edits)
        if followed:
            scanned = ((rescan and self._scan_edited_item(rescan))
                       or self._scan(self._text))
            if not self._pads_hold(scanned):
                scanned = self._restart(text)
        else:
            scanned = self._restart(text)
        self._real = text
        self._scanned = scanned
        return self._analyze(self._text, scanned, path, _layout(self._pads), text)

    def _analyze(self, text: str, scanned: Scan, path: str, layout: Layout,
                 real: str) -> IncrementalAnalysis:
        source = SourceFile(path, text)
        stats = self._stats
        # Entries not used by this analysis are kept for the next one only (an undo, a
        # keystroke typed and deleted), then dropped: memory follows the document.
        self._previous, self._current = self._current, {}

        with gc_paused():
            parsed = _parser.parse_items(text, scanned=scanned, parser=_CachingParser(self))
            lowerer = _CachingLowerer(text)
            lowerer.analyzer = self
            script = lowerer.script(source, parsed)
            for entry in self._current.values():
                entry.lowered, entry.next_lowered = entry.next_lowered, {}
            self._spare, self._previous = self._previous, {}
            self._by_tree = {}  # the trees' ids are looked up during the lowering only
            stats.items = len(scanned.items)
            diagnostics, suppressed = finish(source, script, lowerer.diagnostics,
                                             functions=self.functions, profile=self.profile)
        return IncrementalAnalysis(source, scanned, script, diagnostics, suppressed,
                                   stats, layout, real)

