"""Formatting through the formatter's API (`scriptc.formatter`), as minimal text edits.

`scriptc.formatter.format_text(text)` returns the formatted text (None when the text cannot be
formatted, e.g. it has syntax errors, with the reason in its diagnostics); the edit sent
back replaces only the part between the common prefix and the common suffix of the two texts
(`diagnostics.edits.minimal_edit`), so an editor keeps the cursor and the undo history tidy.
`format_range` returns the formatter's own edits for a range.
"""

from __future__ import annotations

from scriptc.diagnostics.edits import minimal_edit
from scriptc.diagnostics.model import TextEdit

__all__ = ["format_document", "format_range"]


def format_document(text: str) -> list[TextEdit] | None:
    """The edits formatting the whole text; None when it cannot be formatted."""
    from scriptc.formatter import format_text

    result = format_text(text)
    if result.text is None:
        return None
    edit = minimal_edit(text, result.text)
    return [] if edit is None else [edit]


def format_range(text: str, start: int, end: int) -> list[TextEdit]:
    from scriptc.formatter import format_range as fmt_range

    return fmt_range(text, start, end)
