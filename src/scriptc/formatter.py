"""The formatter: one canonical layout for script syntax, comments kept where they were.

`format_text(text)` returns the whole text in the canonical layout, or refuses (text None) with
the syntax errors that made it refuse: a file that does not parse is never rewritten, so no
byte of it can be lost. `format_range(text, start, end)` returns text edits that reformat only
the items overlapping a range (for an editor's "format selection"); it works in a file with
syntax errors elsewhere, and leaves alone every part of the file that holds one.

The layout of each item (its spacing, where a long item wraps, its indentation) is the
shared canonical layout, `scriptc.emit.printer`, which the IR printer (`scriptc.emit.script`:
`scriptc decompile`, the Python API) uses too, so what they print is already formatted. The
formatter works on the text's tokens, not on the IR, so it keeps what the IR forgets: comments,
blank lines (at most one in a row), the file's line endings and the exact text of every number,
name and string; it normalizes only the blanks inside command strings (`"0,0,1,1,0,100"`
becomes `"0, 0, 1, 1, 0, 100"`). docs/editors.md ("Formatting") lists every decision.

How it stays safe: the layout is a function of the tokens alone (so formatting twice changes
nothing); each item it changes is parsed again and compared with the original parse, and the
whole output is scanned again and compared item for item and comment for comment; a mismatch
is a bug in the formatter and raises `FormatterError` rather than returning changed meaning.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from scriptc.diagnostics.edits import minimal_edit
from scriptc.diagnostics.model import Diagnostic, TextEdit
from scriptc.emit.printer import (
    ACTION_INDENT,
    BLOCK_INDENT,
    INSTRUCTION,
    LINE_WIDTH,
    LayoutError,
    Tok,
    command_text,
    lay_out,
    tokens,
)
from scriptc.source import Span

# The parse trees come from `scriptc.syntax` (lark's Tree and Token, named by its one door to
# lark): a tree has `data` and `children`, a token is a `str` with a `type`.
from scriptc.syntax.larkshim import Child, ParseTree, Token, Tree
from scriptc.syntax.parser import ParsedItem, parse_items
from scriptc.syntax.scan import scan

__all__ = ["LINE_WIDTH", "FormatResult", "FormatterError", "format_range", "format_text"]

_BREAK = re.compile(r"\r\n|\r|\n")

class FormatterError(RuntimeError):
    """The formatter produced text that does not parse to the same items and comments: a bug
    in scriptc (the input is never rewritten when this is raised)."""


@dataclass(frozen=True, slots=True)
class FormatResult:
    """What `format_text` returns: the formatted text, or None when the formatter refused
    because of the syntax errors in `diagnostics`."""

    text: str | None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def refused(self) -> bool:
        return self.text is None


# ---------------------------------------------------------------------------------------------
# Public API


def format_text(text: str) -> FormatResult:
    """The canonical layout of a whole script, or a refusal with the syntax errors (text None).

    Never raises on any input, except `FormatterError` for a bug of the formatter itself."""
    parsed = parse_items(text)
    if parsed.diagnostics:
        return FormatResult(None, list(parsed.diagnostics))
    layout = _Layout(text, parsed.items, parsed.comments, [])
    out = "".join(region.new for region in layout.regions)
    _verify_whole(text, out, parsed.items, parsed.comments)
    return FormatResult(out, [])


def format_range(text: str, start: int, end: int) -> list[TextEdit]:
    """Edits (offsets into `text`, in order, never overlapping) that reformat the items
    overlapping `[start, end)`: an item is taken when its text or a comment before it overlaps
    the range (an empty range takes the item it touches). The line breaks and comments before
    a taken item are laid out with it.

    Items that do not parse, and the text between items that holds a syntax error, are never
    edited; the other items are, so a selection can be formatted while another part of the
    file is still broken. Applying every edit of the range `[0, len(text))` to a file without
    syntax errors gives `format_text(text).text`."""
    n = len(text)
    start = max(0, min(start, n))
    end = max(start, min(end, n))
    parsed = parse_items(text)
    layout = _Layout(text, parsed.items, parsed.comments, parsed.diagnostics)
    edits: list[TextEdit] = []
    for region in layout.regions:
        if not region.clean or not region.touches(start, end):
            continue
        edit = minimal_edit(text[region.start : region.end], region.new, region.start)
        if edit is not None:
            edits.append(edit)
    return edits


# ---------------------------------------------------------------------------------------------
# Regions: the file cut into consecutive pieces, one per item (the line breaks and comments
# before it, the item, the comments after it on its line) and one for the end of the file.


@dataclass(slots=True)
class _Region:
    """A stretch of the file laid out as one: its old extent and its new text."""

    start: int
    end: int
    new: str
    clean: bool
    # Spans that select this region in `format_range`: the item and the comments before it.
    spans: list[Span]

    def touches(self, start: int, end: int) -> bool:
        for span in self.spans:
            if start == end:
                if span.start <= start <= span.end:
                    return True
            elif span.start < end and start < span.end:
                return True
        return False


def _breaks(text: str) -> int:
    return len(_BREAK.findall(text))


def _blank_free(text: str, start: int, end: int, comments: Sequence[Span]) -> bool:
    """True when text[start:end] holds only whitespace besides the given comments."""
    pos = start
    for c in comments:
        if text[pos : c.start].strip():
            return False
        pos = c.end
    return not text[pos:end].strip()


class _Layout:
    """The regions of a text, each with its formatted text (for a clean region)."""

    def __init__(self, text: str, parsed_items: list[ParsedItem], comments: list[Span],
                 diagnostics: list[Diagnostic]) -> None:
        self.text = text
        # Every bracketed item the scanner found, with its parse (None: it did not parse, and
        # it is kept as it is, in a region of its own, so the items around it still format).
        by_start = {p.span.start: p for p in parsed_items}
        if diagnostics:
            items: list[tuple[Span, ParsedItem | None]] = [
                (raw.span, by_start.get(raw.span.start)) for raw in scan(text).items
            ]
        else:
            items = [(p.span, p) for p in parsed_items]
        self.nl = _line_ending(text, comments)
        self.regions: list[_Region] = []
        problems = sorted((d.span for d in diagnostics), key=lambda s: s.start)

        # The comments between items: before[k] are those before item k (after item k - 1);
        # the comments inside an item are among its tokens (`_render_item`).
        before: list[list[Span]] = [[] for _ in range(len(items) + 1)]
        k = 0
        for c in comments:
            while k < len(items) and c.start >= items[k][0].end:
                k += 1
            if k == len(items) or c.start < items[k][0].start:
                before[k].append(c)

        boundary = 0
        previous_indent = ""
        first = True
        for k, (span, item) in enumerate(items):
            leading = before[k]
            following = before[k + 1]
            # Comments on the item's own line after it stay there.
            trailing: list[Span] = []
            pos = span.end
            for c in following:
                gap = text[pos : c.start]
                if gap.strip() or _breaks(gap):
                    break
                trailing.append(c)
                pos = c.end
            region_end = trailing[-1].end if trailing else span.end
            clean = (
                item is not None
                and text[span.end - 1 : span.end] == "]"
                and _blank_free(text, boundary, span.start, leading)
                and not _overlaps(problems, boundary, region_end)
            )
            if item is None or not clean:
                # Kept as it is. The region ends at the item's last character: the blanks
                # and comments after it belong to the next region, which counts the line
                # breaks in them.
                end = span.start + len(text[span.start : span.end].rstrip())
                self.regions.append(_Region(boundary, end, "", False, []))
                boundary = end
                first = False
                continue
            before[k + 1] = following[len(trailing) :]
            indent = _indent(item.tree)
            new = self._region_text(first, boundary, leading, span, item, trailing, indent)
            self.regions.append(_Region(boundary, region_end, new, True, [span, *leading]))
            boundary = region_end
            previous_indent = indent
            first = False

        # The end of the file: comments after the last item (at the last item's level: they
        # belong to the innermost section still open) and the final line break.
        leading = before[len(items)]
        end = len(text)
        clean = _blank_free(text, boundary, end, leading) and not _overlaps(problems, boundary, end)
        new = ""
        if clean:
            new = self._end_text(not items, boundary, leading, previous_indent)
        spans = list(leading)
        if items:
            spans.append(items[-1][0])
        self.regions.append(_Region(boundary, end, new, clean, spans))

    # -- the text of a region ------------------------------------------------------------

    def _comment_lines(self, first: bool, pos: int, comments: list[Span], indent: str
                       ) -> tuple[str, int, bool]:
        """The comments before an item, one line per line they were on (several comments on
        one line stay together), at most one blank line between lines. Returns the text,
        where the source continues and whether the last line of comments was on the item's
        line (returned open: the item follows after a space)."""
        text = self.text
        lines: list[tuple[int, list[str]]] = []
        for c in comments:
            breaks = _breaks(text[pos : c.start])
            if lines and breaks == 0:
                lines[-1][1].append(text[c.start : c.end])
            else:
                lines.append((breaks, [text[c.start : c.end]]))
            pos = c.end
        out = []
        for i, (breaks, group) in enumerate(lines):
            if not (first and i == 0):
                out.append(self.nl * min(max(breaks, 1), 2))
            out.append(indent + " ".join(group))
        return "".join(out), pos, bool(lines)

    def _region_text(self, first: bool, boundary: int, leading: list[Span], span: Span,
                     item: ParsedItem, trailing: list[Span], indent: str) -> str:
        text = self.text
        head, pos, has_comments = self._comment_lines(first, boundary, leading, indent)
        breaks = _breaks(text[pos : span.start])
        if has_comments and breaks == 0:
            head += " "  # a comment before the item on the item's own line stays there
        else:
            if not (first and not has_comments):
                head += self.nl * min(max(breaks, 1), 2)
            head += indent
        column = len(head) - max(head.rfind("\n"), head.rfind("\r")) - 1
        body = _render_item(text, item, column, self.nl)
        tail = "".join(" " + text[c.start : c.end] for c in trailing)
        return head + body + tail

    def _end_text(self, empty: bool, boundary: int, leading: list[Span], indent: str) -> str:
        if empty and not leading:
            return ""  # a file with nothing in it stays empty
        body, _pos, _ = self._comment_lines(empty, boundary, leading, indent)
        return body + self.nl


def _line_ending(text: str, comments: list[Span]) -> str:
    """The file's line ending: `\r\n` if the file has one anywhere, else `\n` if it has one,
    else a lone `\r` if it has one, else `\n`. Deciding by presence, not by position or
    count, keeps the style stable through formatting even in a file that mixes endings: every
    break the formatter writes is of the chosen kind and the output ends with one, while the
    breaks it keeps (inside comments, in text it cannot format) are never of a kind ranked
    above it. So formatting twice changes nothing."""
    if "\r\n" in text:
        return "\r\n"
    if "\n" in text:
        return "\n"
    return "\r" if "\r" in text else "\n"


def _overlaps(problems: list[Span], start: int, end: int) -> bool:
    """Whether a diagnostic's span meets [start, end] (ends included: a zero-width
    diagnostic at an item's edge belongs to it)."""
    return any(p.start <= end and p.end >= start for p in problems)


def _kind(tree: ParseTree) -> str:
    return str(tree.data).rsplit("__", 1)[-1]


def _indent(tree: ParseTree) -> str:
    kind = _kind(tree)
    if kind == "block":
        return BLOCK_INDENT
    if kind == "name_item" and str(tree.children[0]) == "action":
        return ACTION_INDENT
    return ""


# ---------------------------------------------------------------------------------------------
# One item: its tokens as written (command strings normalized), laid out by the shared layout.


def _normalize_command(track: str, literal: str) -> str:
    """A command string with the canonical `, ` between its fields, or as it is when that
    could change what it means. Fields are split and trimmed exactly as lowering does
    (`scriptc.frontend.script`), and the audio path is kept byte for byte, so the compiled values
    are the same; strings with a backslash in a number field are left alone (trimming next
    to a backslash would change which character it escapes)."""
    raw = literal[1:-1]
    parts = raw.split(",")
    if track in ("MV", "LD"):
        if len(parts) != (5 if track == "MV" else 6) or "\\" in raw:
            return literal
        fields = [p.strip() for p in parts]
        if not all(fields):
            return literal
        return command_text(fields)
    if track != "AO" or len(parts) < 3 or "\\" in parts[-1] or "\\" in parts[-2]:
        return literal
    wait_t, duration = parts[-2].strip(), parts[-1].strip()
    if not wait_t or not duration:
        return literal
    # The path: from the first field's first non-blank character to the last path field's
    # last one, as lowering reads it.
    pos = 0
    bounds = []
    for part in parts[:-2]:
        lead = len(part) - len(part.lstrip())
        at = pos + lead
        bounds.append((at, at + len(part.strip())))
        pos += len(part) + 1
    path = raw[bounds[0][0] : bounds[-1][1]]
    if not path:
        return literal
    return command_text((path, wait_t, duration))


def _normalize_commands(toks: list[Tok]) -> None:
    """Canonical spacing inside the command strings of MV(...), LD(...), AO(...)."""
    track = None
    depth = 0
    last: Tok | None = None  # the previous token that is not a comment
    for tok in toks:
        if tok.kind != "comment":
            before, last = last, tok
        if tok.is_("("):
            if depth == 0 and before is not None and before.kind == "name":
                track = before.text
            depth += 1
        elif tok.is_(")"):
            depth -= 1
            if depth == 0:
                track = None
        elif tok.kind == "str" and depth == 1 and track is not None:
            tok.text = _normalize_command(track, tok.text)


def _body_kind(tree: ParseTree) -> str:
    if _kind(tree) != "block":
        return ""
    body = tree.children[1]
    return _kind(body) if isinstance(body, Tree) else ""


def _render_item(text: str, item: ParsedItem, column: int, nl: str) -> str:
    """The canonical text of one item that starts at `column`; checked by parsing it again."""
    try:
        toks = tokens(text[item.span.start : item.span.end])
    except LayoutError as exc:
        raise FormatterError(str(exc)) from None
    body = _body_kind(item.tree)
    if body == INSTRUCTION:
        _normalize_commands(toks)
    out = lay_out(toks, body, column, nl)
    if out != text[item.span.start : item.span.end]:  # an unchanged item needs no check
        _verify_item(item, out)
    return out


# ---------------------------------------------------------------------------------------------
# Checks: the formatted text must mean what the original meant.


def _same_tree(a: ParseTree, b: ParseTree) -> bool:
    """Trees equal in structure and token text; command strings compared after the
    formatter's own normalization (which `_normalize_command` documents)."""
    stack: list[tuple[Child, Child, str | None]] = [(a, b, None)]
    while stack:
        x, y, track = stack.pop()
        if x is None or y is None:
            if x is not y:
                return False
        elif isinstance(x, Token):
            if not isinstance(y, Token) or x.type != y.type:
                return False
            sx, sy = str(x), str(y)
            if track is not None and x.type.endswith("STRING"):
                sx, sy = _normalize_command(track, sx), _normalize_command(track, sy)
            if sx != sy:
                return False
        else:
            if isinstance(y, Token) or x.data != y.data or len(x.children) != len(y.children):
                return False
            inner = str(x.children[0]) if _kind(x) == "track" and x.children else None
            stack.extend((p, q, inner) for p, q in zip(x.children, y.children, strict=True))
    return True


def _verify_item(item: ParsedItem, out: str) -> None:
    again = parse_items(out)
    if again.diagnostics or len(again.items) != 1:
        raise FormatterError(f"the formatted item does not parse: {out!r}")
    if not _same_tree(item.tree, again.items[0].tree):
        raise FormatterError(f"the formatted item means something else: {out!r}")


def _verify_whole(text: str, out: str, items: list[ParsedItem], comments: list[Span]) -> None:
    again = scan(out)
    if again.diagnostics or len(again.items) != len(items):
        raise FormatterError("the formatted text does not hold the same items")
    before = [text[c.start : c.end] for c in comments]
    after = [out[c.start : c.end] for c in again.comments]
    if before != after:
        raise FormatterError("the formatted text does not hold the same comments")
