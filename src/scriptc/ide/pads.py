"""Slack: spaces the analysis keeps after edited items, so that typing moves nothing else.

When a keystroke changes the length of one item, every item after it starts at another
offset, and their lowered IR would have to be moved (`scriptc.ir.shift`): on a 90 KB script
that is most of the cost of a keystroke near the top. So the analyser works on its own copy
of the text, the *analysis text*, which is the document's text with runs of spaces (*pads*)
right after the `]` of items that were edited. Typing into such an item takes its length from
the pad after it (deleting gives it back), and nothing after the pad moves: only the edited
item is parsed and lowered again, and everything else is reused as it was.

Spaces between items mean nothing to the language, and a pad sits after a closed item's `]`
and before the line break, so the analysis text has the same items, comments, lines and
indentation as the document: the analysis is the document's, with offsets that differ by the
pads. `Layout` converts between the two.

Every position in a `Snapshot` (its text, spans, diagnostics) is an analysis offset; the
language server converts them to the document's offsets (`to_real`) before it turns them
into lines and columns, and converts the offsets of requests the other way (`to_analysis`).
A snapshot of a text analysed once (`Snapshot.of_text`) has no pads: both are the same.
"""

from __future__ import annotations

import bisect
from itertools import accumulate

__all__ = ["IDENTITY", "Layout"]


class Layout:
    """The pads of an analysis text, as (analysis offset, length) pairs in order."""

    __slots__ = ("_before", "_real_starts", "_starts", "pads")

    def __init__(self, pads: tuple[tuple[int, int], ...] = ()) -> None:
        self.pads = pads
        self._starts = [p for p, _ in pads]
        # _before[k] = total length of the first k pads
        self._before = [0, *accumulate(n for _, n in pads)]
        self._real_starts = [p - self._before[k] for k, (p, _) in enumerate(pads)]

    @property
    def identity(self) -> bool:
        return not self.pads

    @property
    def total(self) -> int:
        return self._before[-1]

    def to_real(self, offset: int) -> int:
        """The document offset of an analysis offset (an offset inside a pad is the end of
        the item before it)."""
        if not self.pads:
            return offset
        k = bisect.bisect_right(self._starts, offset)
        if k and offset < self._starts[k - 1] + self.pads[k - 1][1]:
            return self._real_starts[k - 1]
        return offset - self._before[k]

    def to_analysis(self, offset: int, *, after: bool = False) -> int:
        """The analysis offset of a document offset. At the end of an edited item, where a
        pad follows, the offset is before the pad (the cursor is on the item), or after it
        with `after=True` (the start of text typed after the item goes after its pad)."""
        if not self.pads:
            return offset
        if after:
            k = bisect.bisect_right(self._real_starts, offset)
        else:
            k = bisect.bisect_left(self._real_starts, offset)
        return offset + self._before[k]

    def __repr__(self) -> str:
        return f"Layout({self.pads!r})"


IDENTITY = Layout()
