"""Splitting a script into its bracketed items, before any item is parsed.

The scanner is what makes error recovery per item possible: it finds where each `[ ... ]`
starts and ends (skipping strings and comments), so one broken item never hides the next.
It reports the problems that no parser can recover from (an unterminated string or comment,
a `[` that is never closed, text outside any item) and records comments, which the
formatter keeps. It runs at regex speed and never recurses.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Label
from scriptc.language import STRING_PATTERN
from scriptc.source import Span

# Inside an item, the characters that change what follows.
_ITEM_SPECIAL = re.compile(r'[\[\]"%]')
_STRING = re.compile(STRING_PATTERN)
# A whole item without a comment or a problem inside, in one match: what `_scan_item` finds
# character by special character, at regex speed (possessive: linear when it fails, and the
# item is then scanned the long way, which reports what is wrong).
_PLAIN_ITEM = re.compile(rf'\[(?:[^\[\]"%]++|{STRING_PATTERN})*+\]')
_STRAY = re.compile(r"[^\[%\s][^\[%]*")
_SPACE = re.compile(r"\s*")  # (matches everywhere, maybe nothing)


@dataclass(frozen=True, slots=True)
class RawItem:
    """One bracketed item: `span` covers `[` to `]` inclusive. `closed` is False when the
    `]` is missing (the item then ends where the next item starts); `broken` when the scanner
    already reported a problem inside it, so parsing it again would only repeat that."""

    span: Span
    closed: bool = True
    broken: bool = False


# After this many syntax errors the report stops (the parser says so in a note): one more is
# kept, so that the parser knows there were more. Items and comments are still all found.
MAX_SYNTAX_ERRORS = 100


@dataclass(slots=True)
class Scan:
    """What the scanner found: items, comments, what no parser recovers from."""

    items: list[RawItem] = field(default_factory=list)
    comments: list[Span] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def full(self) -> bool:
        """Whether no more diagnostics are kept: a million stray `[` cost a million
        diagnostics, one by one, where the report shows a hundred."""
        return len(self.diagnostics) > MAX_SYNTAX_ERRORS


def _line_end(text: str, pos: int) -> int:
    m = re.compile(r"[\r\n]").search(text, pos)
    return m.start() if m else len(text)


def _last_non_space(text: str, start: int, end: int) -> int:
    """Offset just after the last non-whitespace character of text[start:end]."""
    while end > start and text[end - 1].isspace():
        end -= 1
    return end


def scan(text: str) -> Scan:
    result = Scan()
    n = len(text)
    blank = _SPACE.match(text, 0)
    assert blank is not None
    pos = blank.end()
    while pos < n:
        ch = text[pos]
        if ch == "%":
            close = text.find("%", pos + 1)
            if close == -1:
                result.diagnostics.append(_unterminated_comment(text, pos))
                return result
            result.comments.append(Span(pos, close + 1))
            pos = close + 1
        elif ch == "[":
            pos = _scan_item(text, pos, result)
            if pos < 0:
                return result
        else:
            m = _STRAY.match(text, pos)
            assert m is not None  # `ch` is neither blank nor `%` nor `[`
            end = _last_non_space(text, pos, m.end())
            if not result.full:
                shown = text[pos:end].splitlines()[0][:40]
                help_ = "items are written in square brackets, such as `[action]`"
                if ch == "]":
                    help_ = "remove the `]`, or add the `[` that should open this item"
                result.diagnostics.append(
                    diagnostic(
                        "P008",
                        f"expected `[` to start an item, found `{shown}`",
                        Span(pos, end),
                        help=help_,
                    )
                )
            pos = m.end()
        blank = _SPACE.match(text, pos)
        assert blank is not None
        pos = blank.end()
    return result


def _unterminated_comment(text: str, pos: int) -> Diagnostic:
    return diagnostic(
        "P004",
        "unterminated comment",
        Span(pos, pos + 1),
        notes=("a comment runs from `%` to the next `%`, so the rest of the file is a comment",),
        help="close the comment with `%`",
    )


def _scan_item(text: str, start: int, result: Scan) -> int:
    """Scan the item opening at `start`; return where scanning continues (-1: stop)."""
    plain = _PLAIN_ITEM.match(text, start)
    if plain is not None:
        result.items.append(RawItem(Span(start, plain.end())))
        return plain.end()
    pos = start + 1
    broken = False  # set when a problem inside the item was reported here
    while True:
        m = _ITEM_SPECIAL.search(text, pos)
        if m is None:
            end = len(text)
            result.diagnostics.append(_unclosed_item(text, start, end))
            result.items.append(RawItem(Span(start, end), closed=False, broken=broken))
            return end
        ch = m.group()
        at = m.start()
        if ch == "]":
            result.items.append(RawItem(Span(start, at + 1), broken=broken))
            return at + 1
        if ch == "[":
            if not result.full:
                result.diagnostics.append(_unclosed_item(text, start, at))
            result.items.append(RawItem(Span(start, at), closed=False, broken=broken))
            return at
        if ch == '"':
            s = _STRING.match(text, at)
            if s is None:
                end = _line_end(text, at)
                result.diagnostics.append(
                    diagnostic(
                        "P003",
                        "unterminated string",
                        Span(at, end),
                        notes=("strings end on the line they start on",),
                        help='close the string with `"` (write `\\"` for a quote inside it)',
                    )
                )
                # The string swallowed the rest of the line, `]` included: the item ends
                # there, and a missing `]` would only repeat this report.
                result.items.append(RawItem(Span(start, end), closed=False, broken=True))
                return end
            else:
                pos = s.end()
        else:  # a comment inside the item
            close = text.find("%", at + 1)
            if close == -1:
                result.diagnostics.append(_unterminated_comment(text, at))
                result.items.append(RawItem(Span(start, at), closed=False, broken=True))
                return -1
            result.comments.append(Span(at, close + 1))
            pos = close + 1


def _unclosed_item(text: str, start: int, stop: int) -> Diagnostic:
    end = _last_non_space(text, start, stop)
    head = text[start:end].splitlines()[0]
    shown = head if len(head) <= 30 else head[:27] + "..."
    return diagnostic(
        "P002",
        f"expected `]` to close `{shown}`",
        Span(end, end),
        labels=(Label(Span(start, start + 1), "this `[` is never closed"),),
        help="add `]` at the end of the item",
    )
