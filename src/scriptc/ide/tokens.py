"""Semantic tokens: what each word of the script is, for highlighting.

Each item is read by a small lexer of its own (regexes, no lark), so that an item being typed
is highlighted too; what a name is comes from where it stands, as the grammar places it: the
word after `[` names the item kind, `b#NAME#` declares a label and `TRJMP(NAME)` uses one,
`{CLASS #C U ?a (...)}` names a class, a scope and binds an alias, a name before `(` in a
condition is a function, a name after `>&` a field. Tokens of an item depend only on its text
(and on whether it is the first item, which names the activity), so they are cached by item
text: a keystroke re-lexes one item.

Types and modifiers are the protocol's standard names (`label` is LSP 3.18's).
"""

from __future__ import annotations

import re
from functools import lru_cache

from scriptc.ide.answers import SemanticToken
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.builtins import STANDARD
from scriptc.language import (
    ASSIGNMENTS,
    FUNCTION_KINDS,
    ITEM_KEYWORDS,
    JUMP_WORDS,
    NAME_PATTERN,
    NUMBER_PATTERN,
    OPEN_COMMENT_PATTERN,
    OPEN_STRING_PATTERN,
    OPERATOR_PATTERN,
    THIS,
    TRACKS,
    TRUE,
    not_in_name,
    sigiled,
)
from scriptc.source import Span

__all__ = ["MODIFIERS", "TYPES", "semantic_tokens"]

TYPES = ("namespace", "label", "keyword", "string", "number", "comment", "class", "property",
         "variable", "function", "operator", "modifier", "enumMember", "event")
MODIFIERS = ("declaration", "readonly", "defaultLibrary")

# The tokens of an item as an editor sees it, perhaps while it is typed (a string or a comment
# not closed yet), from the language's patterns (`scriptc.language`).
_TOKEN = re.compile("|".join(f"(?P<{group}>{pattern})" for group, pattern in (
    ("comment", OPEN_COMMENT_PATTERN),
    ("string", OPEN_STRING_PATTERN),
    ("op", OPERATOR_PATTERN),
    ("cls", sigiled("CLASS_REF")),
    ("this", not_in_name(re.escape(THIS))),
    ("alias", sigiled("ALIAS")),
    ("var", sigiled("VAR_REF")),
    ("att", sigiled("ATT_REF")),
    ("number", NUMBER_PATTERN),
    ("name", NAME_PATTERN),
    ("punct", r">&|>|[\[\]():,{}!#]"),
    ("space", r"\s+"),
    ("other", "."),
)), re.DOTALL)
_ITEM_KEYWORDS = frozenset(ITEM_KEYWORDS)
_BODY_KEYWORDS = frozenset((*TRACKS, *JUMP_WORDS))
_CONDITION_KEYWORDS = frozenset((*ASSIGNMENTS, TRUE))

# (relative start, length, type, modifiers)
_Raw = tuple[int, int, str, tuple[str, ...]]


_BLOCK_HEAD = re.compile(rf"\[(\s*)(b)(\s*)#(\s*)({NAME_PATTERN})?(\s*)#(\s*)({NAME_PATTERN})?")


@lru_cache(maxsize=65536)
def item_tokens(text: str, first: bool) -> tuple[_Raw, ...]:
    """The tokens of one item's text, with offsets relative to the item."""
    out: list[_Raw] = []

    def add(t, type_: str, *modifiers: str) -> None:
        out.append((t[1], t[2] - t[1], type_, modifiers))

    head = _BLOCK_HEAD.match(text)
    if head is not None:
        # `[b#LABEL#KIND`: the `#`s would otherwise read as class references.
        out.append((head.start(2), 1, "keyword", ()))
        if head.group(5):
            out.append((head.start(5), len(head.group(5)), "label", ("declaration",)))
        if head.group(8):
            out.append((head.start(8), len(head.group(8)), "keyword", ()))
        _block_body(text, head.end(), add)
        return tuple(out)
    lexed = [(m.lastgroup, m.start(), m.end(), m.group()) for m in _TOKEN.finditer(text)]
    words = [t for t in lexed if t[0] not in ("comment", "space")]
    word = words[1] if len(words) > 1 and words[0][3] == "[" else None
    kind = None
    if word is not None and word[0] == "name":
        if word[3] in _ITEM_KEYWORDS:
            kind = word[3]
        elif first:
            kind = "activity"
    message_field = 0
    for t in lexed:
        group, value = t[0], t[3]
        if group == "comment":
            add(t, "comment")
        elif group == "string":
            add(t, "string")
        elif t is word and kind in _ITEM_KEYWORDS:
            add(t, "keyword")
        elif (t is word and kind == "activity") or (kind == "goal" and group == "name"):
            add(t, "namespace", "declaration")
        elif kind in ("alfa", "omega"):
            if value == ",":
                message_field += 1
            elif group == "number" and message_field == 0:
                add(t, "number")
            elif group == "name" and message_field == 1:
                add(t, "event")
            elif group == "name" and message_field >= 4:
                add(t, "enumMember")
    return tuple(out)


def _block_body(text: str, start: int, add) -> None:
    lexed = [(m.lastgroup, m.start(), m.end(), m.group()) for m in _TOKEN.finditer(text, start)]
    lexed = [t for t in lexed if t[0] != "space"]
    in_condition = False
    depth = 0  # parentheses open inside CND(...)
    jump_target = False
    previous = None  # the previous token that is not a comment
    for i, t in enumerate(lexed):
        group, value = t[0], t[3]
        if group == "comment":
            add(t, "comment")
            continue
        if group == "string":
            add(t, "string")
        elif in_condition:
            depth, in_condition = _condition_token(t, lexed, i, previous, depth, add)
        elif group == "name" and value in _BODY_KEYWORDS:
            add(t, "keyword")
            if value == "CND":
                in_condition, depth = True, 0
            jump_target = value in ("TRJMP", "FLSJMP")
        elif jump_target and group == "name":
            add(t, "label")
        elif value == ")":
            jump_target = False
        previous = t


def _condition_token(t, lexed, i, previous, depth, add):
    """One token inside `CND(...)`; returns the parenthesis depth and whether the condition
    goes on."""
    group, _s, _e, value = t
    if value == "(":
        return depth + 1, True
    if value == ")":
        return depth - 1, depth > 1  # the `)` of `CND(` ends the condition
    following = next((x for x in lexed[i + 1:] if x[0] != "comment"), None)
    if group == "op":
        add(t, "operator")
    elif group == "cls":
        add(t, "class")
    elif group == "this":
        add(t, "variable", "readonly")
    elif group == "alias":
        declared = previous is not None and previous[0] == "name" and _is_scope_position(lexed, i)
        add(t, "variable", *(("declaration",) if declared else ()))
    elif group == "var":
        add(t, "variable")
    elif group == "att":
        add(t, "property")
    elif group == "number":
        add(t, "number")
    elif group == "name":
        if value in _CONDITION_KEYWORDS or (value in FUNCTION_KINDS and following is not None
                                            and following[3] == ":"):
            add(t, "keyword")
        elif following is not None and following[3] == "(":
            library = STANDARD.get(value) is not None
            add(t, "function", *(("defaultLibrary",) if library else ()))
        elif previous is not None and previous[3] == ">&":
            add(t, "property")
        elif previous is not None and previous[0] in ("cls", "var", "att"):
            add(t, "modifier")  # the scope of an assignment
    return depth, True


def _is_scope_position(lexed, i) -> bool:
    """True when the alias at `lexed[i]` is the one a CLASS assignment binds: `#Class SCOPE
    ?alias`."""
    j = i - 1
    seen: list[str] = []  # the groups of the two tokens before, comments skipped
    while j >= 0 and len(seen) < 2:
        if lexed[j][0] != "comment":
            seen.append(lexed[j][0])
        j -= 1
    return seen == ["name", "cls"]


def semantic_tokens(snapshot: Snapshot, span: Span | None = None) -> list[SemanticToken]:
    """The tokens of the document (or of the items and comments meeting `span`), in order.
    Comments inside items come with their item's tokens; the scanner's list of comments
    gives the others."""
    text = snapshot.text
    lo, hi = (span.start, span.end) if span is not None else (0, len(text))
    out: list[SemanticToken] = []
    comments = snapshot.comments
    c = 0
    last_end = -1
    for n, item in enumerate(snapshot.items):
        start, end = item.span
        # The comments before this item (those inside earlier items were skipped there).
        while c < len(comments) and comments[c].start < start:
            comment = comments[c]
            if comment.start >= last_end and comment.end >= lo and comment.start <= hi:
                out.append(SemanticToken(comment, "comment"))
            c += 1
        last_end = end
        if end < lo or start > hi:
            continue
        for rel, length, type_, modifiers in item_tokens(text[start:end], n == 0):
            s = start + rel
            out.append(SemanticToken(Span(s, s + length), type_, modifiers))
    for comment in comments[c:]:
        if comment.start >= last_end and comment.end >= lo and comment.start <= hi:
            out.append(SemanticToken(comment, "comment"))
    return out
