"""One analysed version of a document: what every editor feature reads.

A `Snapshot` holds the text, the scan (items and comments), the script
(None when the text holds no item) and the diagnostics, exactly as `scriptc lint` would
report them, and builds its `index` (what is where) on first use.

Its offsets are those of its `text`, the analysis text, which may hold pads of spaces after
edited items (scriptc.ide.pads); `layout` converts them to offsets of the document's text
(`real_source`). Features work in the snapshot's offsets only.
"""

from __future__ import annotations

import bisect
from functools import cached_property

from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.ide.incremental import IncrementalAnalysis, Stats
from scriptc.ide.pads import Layout
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.source import SourceFile, Span
from scriptc.syntax.scan import RawItem


class Snapshot:
    def __init__(self, result: IncrementalAnalysis, version: int | None = None,
                 functions: FunctionRegistry = STANDARD, policy=None) -> None:
        self.result = result
        self.version = version
        self.functions = functions
        self.policy = policy  # what is reported of the diagnostics (see Document)

    @classmethod
    def of_text(cls, text: str, path: str = "", functions: FunctionRegistry = STANDARD
                ) -> Snapshot:
        """A snapshot of a text analysed on its own (tests, one-off requests)."""
        from scriptc.ide.incremental import Analyzer

        return cls(Analyzer(functions).analyze(text, path), None, functions)

    # -- what the analysis found ------------------------------------------------------------

    @property
    def source(self) -> SourceFile:
        return self.result.source

    @property
    def text(self) -> str:
        return self.result.source.text

    @property
    def layout(self) -> Layout:
        return self.result.layout

    @cached_property
    def real_source(self) -> SourceFile:
        """The document's text (the analysis text without its pads)."""
        if self.result.real == self.text:
            return self.result.source
        return SourceFile(self.result.source.path, self.result.real)

    @property
    def script(self) -> Script | None:
        return self.result.script

    @cached_property
    def diagnostics(self) -> list[Diagnostic]:
        """What is reported: the analysis's diagnostics, after the policy if there is one."""
        if self.policy is None:
            return self.result.diagnostics
        return list(self.policy(self.result.diagnostics))

    @property
    def stats(self) -> Stats:
        return self.result.stats

    @property
    def items(self) -> list[RawItem]:
        """Every bracketed item the scanner found, parsed or not, in order."""
        return self.result.scan.items

    @property
    def comments(self) -> list[Span]:
        return self.result.scan.comments

    @cached_property
    def has_syntax_errors(self) -> bool:
        """True when some item could not be read (its names are then unknown)."""
        return has_errors([d for d in self.diagnostics if d.code[0] in "PS"])

    @cached_property
    def _item_starts(self) -> list[int]:
        return [item.span.start for item in self.items]

    def item_at(self, offset: int) -> RawItem | None:
        """The item whose span holds `offset` (its end included: the cursor just after `]`
        is still on the item)."""
        i = bisect.bisect_right(self._item_starts, offset) - 1
        if i >= 0 and offset <= self.items[i].span.end:
            return self.items[i]
        return None

    def in_comment(self, offset: int) -> Span | None:
        """The comment holding `offset` strictly inside it, if any."""
        comments = self.comments
        lo, hi = 0, len(comments)
        while lo < hi:
            mid = (lo + hi) // 2
            if comments[mid].end <= offset:
                lo = mid + 1
            else:
                hi = mid
        if lo < len(comments) and comments[lo].start < offset < comments[lo].end:
            return comments[lo]
        return None

    @cached_property
    def index(self):
        from scriptc.ide.index import ScriptIndex

        return ScriptIndex(self)
