"""Changing a text by edits: the one fix applier with its one overlap rule, and the one
minimal edit between two texts.

Two kinds of edit list meet here, and they obey different rules:

- **The edits of one change** (one fix, the formatter's edits of a range, what an editor sends
  back): their author put them together, so their order means something. `apply_edits` applies
  them as the Language Server Protocol says: no two may overlap, and insertions at one offset
  appear in the order of the list (S008's fix inserts ` LD()` then ` AO()` at one place).
- **Independent fixes** (every safe fix of a file, for `lint --fix` and the editor's "fix
  all"): each was written without the others. `clash` is the one rule that says which cannot
  go together, and `compatible` picks, in order, the fixes that can; the others wait for the
  next round, when the text has been analysed again. A fix whose own edits overlap is never
  taken.

The overlap rule (`clash`): two edits clash when their spans share a character, when one is an
insertion strictly inside the other's span, or when both start at the same offset (two
insertions there, or an insertion at the start of a replacement: which text comes first would
be a guess). An edit that ends where another starts does not clash with it.
"""

from __future__ import annotations

from collections.abc import Iterable

from scriptc.diagnostics.model import Fix, TextEdit
from scriptc.source import Span

__all__ = ["apply_edits", "apply_fixes", "clash", "compatible", "minimal_edit"]


def clash(a: Span, b: Span) -> bool:
    """True when edits of spans `a` and `b`, written independently, cannot both be applied
    (the rule in the module docstring)."""
    if a.start == b.start:
        return True
    if a.start < b.end and b.start < a.end:
        return True
    # An insertion strictly inside the other span.
    return (a.start == a.end and b.start < a.start < b.end) or (
        b.start == b.end and a.start < b.start < a.end)


def compatible(fixes: Iterable[Fix]) -> list[Fix]:
    """The fixes that can be applied together, in order: a fix is taken when its own edits
    do not overlap (as one change) and none clashes with an edit of a fix taken before it."""
    taken_spans: list[Span] = []
    taken: list[Fix] = []
    for fix in fixes:
        spans = [e.span for e in fix.edits]
        if _overlap(spans) is not None:
            continue
        if any(clash(s, t) for s in spans for t in taken_spans):
            continue
        taken_spans.extend(spans)
        taken.append(fix)
    return taken


def apply_edits(text: str, edits: Iterable[TextEdit]) -> str:
    """`text` with the edits of one change applied (offsets are into `text`): edits are taken
    in order of their start, an insertion before a replacement starting at the same offset,
    and insertions at one offset in the order of the list. Raises ValueError when two edits
    overlap (their order would be a guess) or an edit lies outside the text."""
    ordered = sorted(edits, key=_order)  # stable: insertions at one offset keep list order
    overlap = _overlap([e.span for e in ordered])
    if overlap is not None:
        raise ValueError(f"overlapping edits at offset {overlap}")
    pieces: list[str] = []
    at = 0
    for edit in ordered:
        start, end = edit.span
        if end < start or end > len(text):
            raise ValueError(f"edit {start}..{end} outside the text (length {len(text)})")
        pieces.append(text[at:start])
        pieces.append(edit.new_text)
        at = end
    pieces.append(text[at:])
    return "".join(pieces)


def _order(edit: TextEdit) -> tuple[int, int]:
    return edit.span.start, edit.span.end


def _overlap(spans: list[Span]) -> int | None:
    """Where two of the spans of one change overlap (share a character, or an insertion lies
    strictly inside a replacement), or None."""
    at = 0
    for start, end in sorted(spans):
        if start < at:
            return start
        at = end
    return None


def apply_fixes(text: str, fixes: Iterable[Fix]) -> tuple[str, int]:
    """`text` with as many of `fixes` applied as can go together (`compatible`: in order, a fix
    whose edits clash waits for the next round), and how many were applied."""
    taken = compatible(fixes)
    return apply_edits(text, [e for fix in taken for e in fix.edits]), len(taken)


def minimal_edit(old: str, new: str, at: int = 0) -> TextEdit | None:
    """The one edit turning `old` (which starts at offset `at` of its document) into `new`,
    without their common prefix and suffix, so an editor keeps the cursor and the undo
    history tidy; None when they are equal."""
    if old == new:
        return None
    limit = min(len(old), len(new))
    prefix = 0
    while prefix < limit and old[prefix] == new[prefix]:
        prefix += 1
    suffix = 0
    while suffix < limit - prefix and old[-1 - suffix] == new[-1 - suffix]:
        suffix += 1
    return TextEdit(Span(at + prefix, at + len(old) - suffix), new[prefix:len(new) - suffix])

