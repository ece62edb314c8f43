"""The canonical layout of the script syntax: the one place that knows how an item is spaced,
where a long item breaks and how deep each item is indented.

Two printers use it. The formatter (`scriptc.formatter`) reads the tokens of the text a person
wrote, keeps its comments, blank lines and number text, and lays each item out here; the IR
printer (`scriptc.emit.script`, behind `scriptc decompile` and the Python API's `script_text`)
builds the tokens of each item from the IR and lays it out here too. So a decompiled or
generated script is already formatted: `scriptc fmt --check` has nothing to say about it.

The layout of an item is a function of its tokens, its kind of block body and the column it
starts at (docs/editors.md, "Formatting", lists every decision):

- spacing: `[alfa:0, kick_starter, "", "", C, U]`, `[b#l#blk_inst: MV("...") LD() AO()]`,
  and inside conditions the `toparse` spacing of the thesis JSON (`scriptc.emit.condition`);
- an item wider than `LINE_WIDTH` columns is wrapped: instruction blocks one track per line,
  then one command per line; jump blocks `TRJMP` on a line of its own, then one condition part
  per line; sensor blocks one payload string per line; pieces aligned, never indented by a
  fixed step;
- goals start at column 0, `[action]` two spaces in, blocks four.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from scriptc.language import (
    ATT_ACCESS,
    COMMENT_PATTERN,
    FIELD_ACCESS,
    NAME_PATTERN,
    NUMBER_PATTERN,
    OPERATOR_PATTERN,
    STRING_PATTERN,
    sigiled,
)

__all__ = [
    "ACTION_INDENT",
    "BLOCK_INDENT",
    "GOAL_INDENT",
    "INSTRUCTION",
    "JUMP",
    "LINE_WIDTH",
    "SENSOR",
    "LayoutError",
    "Tok",
    "command_text",
    "lay_out",
    "piece",
    "tokens",
]

# Items wider than this (in code points, indentation included) are wrapped.
LINE_WIDTH = 100

GOAL_INDENT = ""
ACTION_INDENT = "  "
BLOCK_INDENT = "    "

# The kinds of block body whose items may wrap (the grammar's rule names).
INSTRUCTION = "inst_body"
JUMP = "jump_body"
SENSOR = "sensor_body"

_BREAK = re.compile(r"\r\n|\r|\n")

# The tokens of an item, from the language's patterns (`scriptc.language`, read from the
# grammar); `#` is a token of its own, so `#Human` is `#` `Human` (the formatter never puts a
# space after `#`, so the text is the same).
_TOKEN = re.compile("|".join(f"(?P<{group}>{pattern})" for group, pattern in (
    ("ws", r"\s+"),
    ("str", STRING_PATTERN),
    ("comment", COMMENT_PATTERN),
    ("op", OPERATOR_PATTERN),
    ("access", f"{re.escape(FIELD_ACCESS)}|{re.escape(ATT_ACCESS)}"),
    ("alias", sigiled("ALIAS")),
    ("var", sigiled("VAR_REF")),
    ("att", sigiled("ATT_REF")),
    ("num", NUMBER_PATTERN),
    ("name", NAME_PATTERN),
    ("punct", r"[\[\](){},:#!]"),
)))
_OPENERS = frozenset("([{")
_CLOSERS = frozenset(")]}")


class LayoutError(ValueError):
    """An item's text holds a character that starts no token."""


@dataclass(slots=True)
class Tok:
    """A token of an item: its kind (a group name of `_TOKEN`, `this` for `?THIS`, or `raw`
    for a piece that is none of them, which is laid out like a name) and its text."""

    kind: str
    text: str

    def is_(self, punct: str) -> bool:
        return self.kind == "punct" and self.text == punct


def tokens(item_text: str) -> list[Tok]:
    """The tokens of an item's text, blanks dropped. Raises LayoutError at a character that
    starts no token."""
    toks: list[Tok] = []
    pos = 0
    n = len(item_text)
    while pos < n:
        m = _TOKEN.match(item_text, pos)
        if m is None:
            raise LayoutError(f"cannot read the item {item_text[:60]!r} at {pos}")
        kind = m.lastgroup
        assert kind is not None  # every alternative of `_TOKEN` is a named group
        if kind != "ws":
            value = m.group()
            if kind == "alias" and value == "?THIS":
                kind = "this"
            toks.append(Tok(kind, value))
        pos = m.end()
    return toks


def _space(prev: Tok, tok: Tok, before_prev: Tok | None, prev_position: int) -> str:
    """The space between two tokens of an item (neither a comment): the canonical printer's
    spacing (`[alfa:0, x, ...]`, `[b#l#blk_inst: MV("...") LD() AO()]`, the `toparse` text of
    conditions)."""
    if tok.kind == "punct" and (tok.text in _CLOSERS or tok.text in ",:"):
        return ""
    if prev.kind == "punct":
        if prev.text in _OPENERS:
            return ""
        if prev.text == ",":
            return " "
        if prev.text == ":":
            # `[alfa:16`, `[goal:g]` (the third token of the item) but `blk_inst: MV`, `E: gt`
            return "" if prev_position == 2 else " "
        if prev.text == "#":
            return ""
    if tok.is_("#"):
        # `{CLASS #Human`, but `[b#label#blk_inst`
        if prev.kind == "name" and prev.text == "CLASS" and before_prev is not None \
                and before_prev.is_("{"):
            return " "
        return ""
    if prev.kind == "access" or tok.kind == "access":
        return ""  # `?kid>&positionrho`, `?kid>$mood`
    if tok.is_("("):
        # `MV(`, `CND(`, `gt(` hug their parenthesis; a CLASS assignment's tests do not:
        # `{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)}`
        return " " if prev.kind == "alias" else ""
    return " "


def _separators(toks: list[Tok]) -> list[str]:
    """seps[i] is what is written before toks[i]."""
    seps = [""] * len(toks)
    last: Tok | None = None  # the previous token that is not a comment
    before_last: Tok | None = None
    position = -1  # the position of `last` among the tokens that are not comments
    for i, tok in enumerate(toks):
        prev = toks[i - 1] if i else None
        if prev is None:
            pass
        elif tok.kind == "comment":
            seps[i] = "" if prev.kind == "punct" and prev.text in _OPENERS else " "
        elif prev.kind == "comment":
            seps[i] = "" if tok.kind == "punct" and (tok.text in _CLOSERS or tok.text in ",:") \
                else " "
        else:
            seps[i] = _space(prev, tok, before_last, position)
        if tok.kind != "comment":
            before_last, last = last, tok
            position += 1
    return seps


# Break points: token index -> (level, anchor). A break replaces the space before the token
# with a line break and spaces up to the anchor's column; the anchor is ("start", j) (where
# token j starts) or ("end", j) (where it ends). Level 1 breaks are taken together when the
# item does not fit on one line; level 2 breaks only on a line that still does not fit.
_Breaks = dict[int, tuple[int, tuple[str, int]]]


def _code_indices(toks: list[Tok]) -> list[int]:
    return [i for i, t in enumerate(toks) if t.kind != "comment"]


def _break_points(body: str, toks: list[Tok]) -> _Breaks:
    code = _code_indices(toks)
    breaks: _Breaks = {}
    # The body starts after `[ b # [label] # kind`: find the `:` after the kind word.
    colon = next((j for j, i in enumerate(code) if toks[i].is_(":")), None)
    if colon is None:
        return breaks
    rest = code[colon + 1 :]
    if body == INSTRUCTION:
        first_track: int | None = None
        depth = 0
        open_paren = -1
        for j, i in enumerate(rest):
            tok = toks[i]
            if depth == 0 and tok.kind == "name":
                if first_track is None:
                    first_track = i
                else:
                    breaks[i] = (1, ("start", first_track))
            elif tok.is_("("):
                depth += 1
                open_paren = i
            elif tok.is_(")"):
                depth -= 1
            elif tok.is_(",") and depth == 1 and j + 1 < len(rest):
                breaks[rest[j + 1]] = (2, ("end", open_paren))
    elif body == JUMP:
        cnd = rest[0] if rest else None
        depth = 0
        braces = 0
        open_paren = -1
        first_part = True
        after_bang = False
        for i in rest:
            tok = toks[i]
            if tok.is_("("):
                depth += 1
                if depth == 1:
                    open_paren = i
                    first_part = True
                continue
            if tok.is_(")"):
                depth -= 1
                continue
            if depth == 0 and tok.kind == "name" and tok.text == "TRJMP" and cnd is not None:
                breaks[i] = (1, ("start", cnd))
            if depth == 1 and braces == 0 and (tok.is_("{") or tok.is_("!")):
                if not first_part and not (tok.is_("{") and after_bang):
                    breaks[i] = (2, ("end", open_paren))
                first_part = False
                after_bang = tok.is_("!")
            elif depth == 1 and braces == 0:
                after_bang = False
            if tok.is_("{"):
                braces += 1
            elif tok.is_("}"):
                braces -= 1
                after_bang = False
    elif body == SENSOR:
        first = rest[0] if rest else None
        for j, i in enumerate(rest):
            if toks[i].is_(",") and j + 1 < len(rest) and first is not None:
                breaks[rest[j + 1]] = (1, ("start", first))
    return breaks


def _render(toks: list[Tok], seps: list[str], breaks: _Breaks, taken: set[int], column: int,
            nl: str) -> tuple[str, list[tuple[int, int, int]]]:
    """The item's text with the `taken` breaks, and its lines as (first token, last token,
    widest physical line) for deciding where else to break."""
    starts: list[int] = [0] * len(toks)
    ends: list[int] = [0] * len(toks)
    out: list[str] = []
    lines: list[tuple[int, int, int]] = []
    line_first = 0
    widest = column
    col = column
    for i, tok in enumerate(toks):
        if i in taken:
            lines.append((line_first, i - 1, widest))
            kind, j = breaks[i][1]
            indent = starts[j] if kind == "start" else ends[j]
            out.append(nl + " " * indent)
            col = widest = indent
            line_first = i
        else:
            out.append(seps[i])
            col += len(seps[i])
        starts[i] = col
        piece = tok.text
        out.append(piece)
        if "\n" in piece or "\r" in piece:  # a comment of several lines
            physical = _BREAK.split(piece)
            widest = max(widest, col + len(physical[0]), *(len(p) for p in physical[1:-1]))
            col = len(physical[-1])
        else:
            col += len(piece)
        ends[i] = col
        widest = max(widest, col)
    lines.append((line_first, len(toks) - 1, widest))
    return "".join(out), lines


def piece(text: str) -> Tok:
    """One token of an item, as a printer makes it: its kind is the token pattern the whole
    text matches, `raw` when none does (a name that is not an identifier, say: it is kept as
    one piece rather than split, and the analysis reports it)."""
    m = _TOKEN.fullmatch(text)
    if m is None or m.lastgroup == "ws":
        return Tok("raw", text)
    kind = m.lastgroup
    assert kind is not None  # every alternative of `_TOKEN` is a named group
    return Tok("this" if kind == "alias" and text == "?THIS" else kind, text)


def command_text(fields: Iterable[str]) -> str:
    """A command string in its canonical form: the fields (already as they are written
    inside the string) separated by `, `."""
    return '"' + ", ".join(fields) + '"'


def lay_out(toks: list[Tok], body: str, column: int, nl: str = "\n") -> str:
    """The canonical text of one item made of `toks`, starting at `column`; `body` is the
    kind of its block body (`INSTRUCTION`, `JUMP`, `SENSOR`, or "" for any other item), which
    says where it may break; `nl` is the line break a wrapped item uses."""
    seps = _separators(toks)
    breaks = _break_points(body, toks)
    out, lines = _render(toks, seps, breaks, set(), column, nl)
    if lines[0][2] > LINE_WIDTH and breaks:
        taken = {i for i, (level, _) in breaks.items() if level == 1}
        out, lines = _render(toks, seps, breaks, taken, column, nl)
        more = {
            i
            for first, last, widest in lines
            if widest > LINE_WIDTH
            for i, (level, _) in breaks.items()
            if level == 2 and first < i <= last
        }
        if more:
            out, _ = _render(toks, seps, breaks, taken | more, column, nl)
    return out
