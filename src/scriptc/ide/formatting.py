"""Formatting through the formatter's API (`scriptc.formatter`), as minimal text edits.

`scriptc.formatter.format_text(text)` returns the formatted text (None when the text cannot be
formatted, e.g. it has syntax errors, with the reason in its diagnostics); the edit sent
back replaces only the part between the common prefix and the common suffix of the two
texts, so an editor keeps the cursor and the undo history tidy. `format_range` returns the
formatter's own edits for a range.
"""

from __future__ import annotations

from scriptc.diagnostics.model import TextEdit
from scriptc.source import Span

__all__ = ["format_document", "format_range", "available"]


def available() -> bool:
    """True when the formatter is installed in this tree (it is developed alongside)."""
    import importlib.util

    return importlib.util.find_spec("scriptc.formatter") is not None


def minimal_edit(old: str, new: str) -> list[TextEdit]:
    if old == new:
        return []
    start = 0
    limit = min(len(old), len(new))
    while start < limit and old[start] == new[start]:
        start += 1
    end_old, end_new = len(old), len(new)
    while end_old > start and end_new > start and old[end_old - 1] == new[end_new - 1]:
        end_old -= 1
        end_new -= 1
    return [TextEdit(Span(start, end_old), new[start:end_new])]


def format_document(text: str) -> list[TextEdit] | None:
    """The edits formatting the whole text; None when it cannot be formatted."""
    from scriptc.formatter import format_text

    result = format_text(text)
    if result.text is None:
        return None
    return minimal_edit(text, result.text)


def format_range(text: str, start: int, end: int) -> list[TextEdit]:
    from scriptc.formatter import format_range as fmt_range

    return [TextEdit(Span(s, e), new) for s, e, new in fmt_range(text, start, end)]
