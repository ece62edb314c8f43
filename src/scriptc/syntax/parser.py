"""Parsing with the lark grammars of grammar/: per item for scripts, whole for conditions.

`parse_items(text)` scans the text into items (scan.py), parses each one with the `item` start
symbol of grammar/script.lark, and returns the trees with their offsets plus diagnostics. An
item that does not parse is reported once, in words ("expected `)` to close `MV(`"), and
skipped; the others are still parsed. `each_item` does the same one item at a time, for
lowering that takes each tree as it comes. `parse_condition_tree(text)` parses a condition
alone (grammar/condition.lark), for the `toparse` strings of thesis JSON.

Token offsets in the returned trees are relative to the item's text; `ParsedItem.base` is the
item's offset in the file. Nothing here raises on bad input.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Collection, Iterable, Iterator
from dataclasses import dataclass, replace
from functools import cache
from typing import Protocol

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.language import (
    NAME_CHARS,
    OPEN_COMMENT_PATTERN,
    OPEN_STRING_PATTERN,
    OPERATORS,
)
from scriptc.resources import grammar_path
from scriptc.source import Span
from scriptc.syntax.larkshim import (
    Lark,
    ParseTree,
    TerminalDef,
    UnexpectedCharacters,
    UnexpectedEOF,
    UnexpectedInput,
    UnexpectedToken,
    characters_offset,
    terminal_literal,
)
from scriptc.syntax.lexer import ContextualFastLexer
from scriptc.syntax.scan import MAX_SYNTAX_ERRORS, Scan, scan
from scriptc.syntax.shapes import ShapeParser


class ItemParser(Protocol):
    """What `parse_items` and `describe` need of a parser: lark's `parse`, and the grammar's
    terminals, which word an error (a `ShapeParser`; the language server's parser answers
    from its cache of item texts, see scriptc.ide.incremental)."""

    @property
    def terminals(self) -> Collection[TerminalDef]: ...

    def parse(self, text: str, start: str | None = None) -> ParseTree: ...


@dataclass(frozen=True, slots=True)
class ParsedItem:
    """One item's parse tree, with where the item is in the file."""

    tree: ParseTree
    base: int  # offset of the item's `[` in the file
    span: Span  # the whole item in the file


@dataclass(slots=True)
class ParsedScript:
    """Every item's tree, the comments and the syntax diagnostics of a file."""

    items: list[ParsedItem]
    comments: list[Span]
    diagnostics: list[Diagnostic]


def _build(name: str, start: list[str]) -> Lark:
    path = grammar_path(name)
    return Lark(
        path.read_text(encoding="utf-8"),
        parser="lalr",
        lexer=ContextualFastLexer,
        start=start,
        maybe_placeholders=True,
        import_paths=[str(path.parent)],
        source_path=str(path),
        cache=True,
    )


@cache
def script_lark() -> Lark:
    """lark's parser of grammar/script.lark (start symbol `item`)."""
    return _build("script.lark", ["item"])


@cache
def script_parser() -> ShapeParser:
    """The parser of items: lark's tables with the shape cache of syntax/shapes.py (the trees
    and errors are lark's)."""
    return ShapeParser(script_lark(), "item")


@cache
def condition_parser() -> ShapeParser:
    return ShapeParser(_build("condition.lark", ["condition"]), "condition")


def parse_items(text: str, *, scanned: Scan | None = None,
                parser: ItemParser | None = None) -> ParsedScript:
    """Scan `text` (or take `scanned`, the scan of this same text) and parse each item with
    `parser` (default: `script_parser()`, the parser of grammar/script.lark's items). The
    language server passes a parser that answers from its cache of item texts
    (scriptc.ide.incremental)."""
    scanned = scanned if scanned is not None else scan(text)
    diagnostics = list(scanned.diagnostics)
    items = list(each_item(text, scanned, parser if parser is not None else script_parser(),
                           diagnostics))
    return ParsedScript(items, scanned.comments, diagnostics)


def each_item(text: str, scanned: Scan, parser: ItemParser,
              diagnostics: list[Diagnostic]) -> Iterator[ParsedItem]:
    """The items of `text` (`scanned`: its scan), each parsed as it is asked for: lowering
    that takes each at once keeps one item's tree at a time (a 1 MB script's trees are some
    400,000 objects). Syntax errors are added to `diagnostics` (the scan's are there first),
    at most `MAX_SYNTAX_ERRORS`: once they are all in, the last says in a note that there
    were more."""
    for raw in scanned.items:
        if len(diagnostics) >= MAX_SYNTAX_ERRORS:
            break
        if raw.broken:
            continue
        start, end = raw.span.start, raw.span.end
        item_text = text[start:end] if raw.closed else text[start:end].rstrip() + "]"
        try:
            tree = parser.parse(item_text, start="item")
        except UnexpectedInput as error:
            if raw.closed:  # an unclosed item was reported already; don't pile on
                diagnostics.append(describe(error, item_text, start, parser))
            continue
        yield ParsedItem(tree, start, raw.span)
    if len(diagnostics) > MAX_SYNTAX_ERRORS:
        # 20,000 stray brackets are one problem to the person reading the report.
        last = diagnostics[MAX_SYNTAX_ERRORS - 1]
        note = f"scriptc stopped after {MAX_SYNTAX_ERRORS} syntax errors; fix these first"
        del diagnostics[MAX_SYNTAX_ERRORS:]
        diagnostics[-1] = replace(last, notes=(*last.notes, note))


def parse_condition_tree(text: str, base: int = 0) -> tuple[ParseTree | None, list[Diagnostic]]:
    parser = condition_parser()
    try:
        return parser.parse(text, start="condition"), []
    except UnexpectedInput as error:
        return None, [describe(error, text, base, parser)]


# ---------------------------------------------------------------------------------------------
# Error messages for people

# How terminals are named in messages, by their name in the grammar (namespace stripped).
_COMPARISONS = ", ".join(f"`{op}`" for op in list(OPERATORS)[:-1]) + f" or `{list(OPERATORS)[-1]}`"
_TERMINAL_WORDS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "ALIAS": "an alias such as `?kid`",
    "THIS": "`?THIS`",
    "CLASS_REF": "a class such as `#Human`",
    "VAR_REF": "a variable such as `@count`",
    "ATT_REF": "an attribute such as `$mood`",
    "OPERATOR": f"a comparison ({_COMPARISONS})",
    "FIELD_ACCESS": "`>&`",
    "ATT_ACCESS": "`>$`",
    "$END": "the end of the text",
}
_OPENERS = {"(": ")", "{": "}", "[": "]"}
_CLOSERS = {v: k for k, v in _OPENERS.items()}
# What the search for the delimiter still open skips: strings and comments, closed or not.
_SKIP = re.compile(rf"{OPEN_STRING_PATTERN}|{OPEN_COMMENT_PATTERN}|[()\[\]{{}}]")


def _bare(name: str) -> str:
    return name.rsplit("__", 1)[-1]


def _words(parser: ItemParser, names: Iterable[str]) -> list[str]:
    terminals = {t.name: t for t in parser.terminals}
    words: set[str] = set()
    for name in names:
        t = terminals.get(name)
        literal = terminal_literal(t) if t is not None else None
        if literal is not None:
            words.add(f"`{literal}`")
        else:
            words.add(_TERMINAL_WORDS.get(_bare(name), f"`{_bare(name).lower()}`"))
    return sorted(words, key=lambda w: (not w.startswith("`"), w))


def _join(words: list[str]) -> str:
    if len(words) > 7:
        words = words[:6] + ["..."]
    if len(words) == 1:
        return words[0]
    return ", ".join(words[:-1]) + " or " + words[-1]


def _open_delimiter(text: str, upto: int) -> tuple[int, str] | None:
    """The innermost delimiter still open at `upto`: its offset and what it opens, e.g.
    `MV(` (the word before a parenthesis is part of how people name it)."""
    stack: list[int] = []
    for m in _SKIP.finditer(text, 0, upto):
        tok = m.group()
        if tok in _OPENERS:
            stack.append(m.start())
        elif tok in _CLOSERS and stack and text[stack[-1]] == _CLOSERS[tok]:
            stack.pop()
    if not stack:
        return None
    at = stack[-1]
    if text[at] != "(":
        return at, text[at]
    # The word before the parenthesis, blanks apart, read backwards: a regex anchored at the
    # end (`[A-Za-z_]*\s*$`) retried the blanks from each of them, quadratic in a megabyte
    # of spaces.
    end = at
    while end > 0 and text[end - 1].isspace():
        end -= 1
    start = end
    while start > 0 and text[start - 1] in NAME_CHARS:
        start -= 1
    return at, text[start:end] + "("


def describe(error: UnexpectedInput, text: str, base: int, parser: ItemParser) -> Diagnostic:
    """One diagnostic for a lark error in `text` (which starts at `base` in the file)."""
    terminals = {t.name for t in parser.terminals} | {"$END"}
    if isinstance(error, UnexpectedToken):
        # lark's expected set also names non-terminals (the parser's gotos): keep terminals.
        expected = {n for n in error.expected if n in terminals}
        token = error.token
        if token.type == "$END":
            at, found, shown = len(text), "", "the end of the text"
        else:
            at = token.start_pos if token.start_pos is not None else 0
            found = str(token)
            shown = f"`{found}`"
        return _expected(parser, expected, text, base, at, found, shown,
                         found_type=_bare(token.type))
    if isinstance(error, UnexpectedCharacters):
        at = characters_offset(error)
        ch = text[at] if at < len(text) else ""
        expected = {n for n in error.allowed or () if n in terminals}
        if ch in "<>=" and any(_bare(n) == "OPERATOR" for n in expected):
            span = Span(base + at, base + at + 1)
            return diagnostic(
                "P001",
                f"expected a comparison ({_COMPARISONS}), found `{ch}`",
                span,
                help=f"comparisons are written `OP{ch}` in the rule grammar",
                fix=Fix(f"write `OP{ch}`", (TextEdit(span, f"OP{ch}"),)),
            )
        if expected:
            return _expected(parser, expected, text, base, at, ch, f"`{ch}`", code="P005")
        return diagnostic("P005", f"unexpected character `{ch}`", Span(base + at, base + at + 1))
    if isinstance(error, UnexpectedEOF):
        end = base + len(text)
        return diagnostic("P001", "unexpected end of the text", Span(end, end))
    return diagnostic("P001", "syntax error", Span(base, base + len(text)))


# Tokens that can be an element of a list: met where `,` or a closer was expected, they mean
# a forgotten comma more often than a forgotten closer (`gt(1 2)`).
_ELEMENTS = {"NUMBER", "STRING", "ALIAS", "THIS", "VAR_REF", "NAME"}


def _expected(parser: ItemParser, expected: set[str], text: str, base: int, at: int, found: str,
              shown: str, code: str = "P001", found_type: str = "") -> Diagnostic:
    span = Span(base + at, base + at + len(found))
    if not _words(parser, expected):
        # The parser's state names no terminal it would take (`{ATT ?kid>$mood ...`: a field
        # access where the attribute's alias ends): nothing to list, only what was found.
        return diagnostic(code, f"unexpected {shown}", span)
    bare = {_bare(n) for n in expected}
    if "COMMA" in bare and found_type in _ELEMENTS:
        closers_expected = [w for w in _words(parser, expected) if w != "`,`"]
        return diagnostic(
            code,
            f"expected `,` or {_join(closers_expected)}, found {shown}",
            span,
            help="separate the elements of a list with `,`",
            fix=Fix("insert `,`", (TextEdit(Span(span.start, span.start), ", "),), safe=False),
        )
    closers = {"RPAR": ")", "RBRACE": "}", "RSQB": "]"}
    opened = _open_delimiter(text, at)
    if opened is not None:
        at_open, what = opened
        closer = _OPENERS[text[at_open]]
        if any(closers.get(b) == closer for b in bare):
            others = [w for w in _words(parser, expected) if w != f"`{closer}`"]
            goes_on = f", or {_join(others)} if the list goes on" if others else ""
            return diagnostic(
                "P002",
                f"expected `{closer}` to close `{what}`, found {shown}",
                span,
                labels=(Label(Span(base + at_open, base + at_open + 1), f"`{what}` opened here"),),
                help=f"add `{closer}`{goes_on}",
            )
    words = _words(parser, expected)
    help_: str | None = None
    fix: Fix | None = None
    if "BANG" in bare and found == ")":
        help_ = "a condition is `ASSIGNMENTS ! EVALUATIONS`; the smallest is `! {TRUE}`"
    if found:
        keywords = [w.strip("`") for w in words if w.startswith("`")]
        close = difflib.get_close_matches(found, keywords, n=1, cutoff=0.6)
        if close:
            help_ = f"did you mean `{close[0]}`?"
            fix = Fix(f"replace with `{close[0]}`", (TextEdit(span, close[0]),), safe=False)
    return diagnostic(code, f"expected {_join(words)}, found {shown}", span, help=help_, fix=fix)
