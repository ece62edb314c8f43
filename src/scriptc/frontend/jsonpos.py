"""A JSON parser that remembers where every key and value is (for `scriptc check FILE.json`).

The standard `json` module returns values without positions, recurses (a file of 20,000 nested
arrays raises RecursionError) and accepts `NaN` and `Infinity`. This parser is iterative (an
explicit stack, so nesting depth is bounded by memory only), follows RFC 8259 strictly and
returns a small tree of `JsonNode`s whose spans are character offsets into the text, the same
offsets `scriptc.source.Span` uses everywhere. Errors raise `JsonError` with the span of the
offending text, its line and column, and a message that says what was expected.

Choices beyond RFC 8259, each for a reason:
- duplicate keys are an error (RFC 8259 leaves their meaning open; JSON loaders commonly keep
  one of the two silently, so the other would be a mistake nobody sees);
- `NaN`, `Infinity` and `-Infinity` are errors with a message of their own (Python writes them);
- a `\\u` escape of half a surrogate pair is an error (the text could not be written as UTF-8);
- a leading byte order mark is skipped (some Windows editors write one; it is an encoding mark,
  not part of the document);
- numbers follow scriptc's number policy (`scriptc.numbers`): a number too large for a double
  (`1e999`, an integer of thousands of digits) is an error at its text, like `NaN`;
- a reader may bound the nesting depth (`max_depth`), for values that go on to code that
  recurses.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import TypeAlias

from scriptc.gcpause import gc_paused
from scriptc.numbers import NumberError, json_number
from scriptc.source import SourceFile, Span

__all__ = ["JsonError", "JsonNode", "JsonScalar", "Member", "parse_json",
           "string_offsets"]

# The Python value of a JSON scalar (a string, a number, `true`/`false`, `null`).
JsonScalar: TypeAlias = str | int | float | bool | None


class Member:
    """One `"key": value` pair of an object; `key_span` covers the key with its quotes."""

    __slots__ = ("key", "key_end", "key_start", "value")

    def __init__(self, key: str, key_start: int, key_end: int, value: JsonNode) -> None:
        self.key = key
        self.key_start = key_start
        self.key_end = key_end
        self.value = value

    @property
    def key_span(self) -> Span:
        return Span(self.key_start, self.key_end)

    def __repr__(self) -> str:
        return f"Member({self.key!r}, {self.value!r})"


class JsonNode:
    """A JSON value and where it is.

    `kind` is one of "object", "array", "string", "number", "boolean", "null". `value` is the
    Python value of a scalar (str, int, float, bool or None; None for containers). `raw` is the
    number's text as written (`1000`, `1e3`), empty for other kinds. `span` covers the whole
    value, quotes and brackets included. Objects keep their members in document order.
    """

    # A plain slotted class holding offsets rather than a dataclass holding a Span: a large
    # file makes hundreds of thousands of nodes, and allocation is most of the parse time.
    __slots__ = ("end", "items", "kind", "members", "raw", "start", "value")

    def __init__(self, kind: str, start: int, end: int, value: JsonScalar = None,
                 raw: str = "") -> None:
        self.kind = kind
        self.start = start
        self.end = end
        self.value = value
        self.raw = raw
        self.items: list[JsonNode] = [] if kind == "array" else _NO_ITEMS
        self.members: list[Member] = [] if kind == "object" else _NO_MEMBERS

    def __repr__(self) -> str:
        return f"JsonNode({self.kind}, {self.start}-{self.end})"

    @property
    def span(self) -> Span:
        return Span(self.start, self.end)

    @property
    def content_span(self) -> Span:
        """A string's span without its quotes (the whole span for other kinds)."""
        if self.kind == "string":
            return Span(self.start + 1, self.end - 1)
        return Span(self.start, self.end)

    def get(self, key: str) -> JsonNode | None:
        for m in self.members:
            if m.key == key:
                return m.value
        return None

    def member(self, key: str) -> Member | None:
        for m in self.members:
            if m.key == key:
                return m
        return None

    def child(self, step: str | int) -> JsonNode | None:
        """The value at one step of a path: a key of an object or an index of an array."""
        if self.kind == "object" and isinstance(step, str):
            return self.get(step)
        if self.kind == "array" and isinstance(step, int) and 0 <= step < len(self.items):
            return self.items[step]
        return None

    def locate(self, steps: Iterable[str | int]) -> tuple[JsonNode, Member | None]:
        """The node at a path of keys and indices (as jsonschema reports one), and the member
        that holds it when the last step is a key; where the path leaves the document, the
        last node it reached."""
        node, member = self, None
        for step in steps:
            child = node.child(step)
            if child is None:
                break
            member = node.member(step) if isinstance(step, str) else None
            node = child
        return node, member

    def to_python(self, max_depth: int | None = None) -> object:
        """The plain Python value (dict, list, str, int, float, bool, None), built without
        recursion so a deeply nested document converts as well as it parsed. With
        `max_depth`, containers nested deeper than that are left empty: a shallow copy for
        code that recurses (jsonschema, `repr`) and looks no deeper anyway."""
        if self.kind not in ("object", "array"):
            return self.value
        root: _Container = {} if self.kind == "object" else []
        stack: list[tuple[JsonNode, _Container, int]] = [(self, root, 0)]
        while stack:
            node, out, depth = stack.pop()
            if max_depth is not None and depth >= max_depth:
                continue
            if isinstance(out, dict):  # (the node is an object)
                for m in node.members:
                    out[m.key] = _shell(m.value, stack, depth + 1)
            else:
                for item in node.items:
                    out.append(_shell(item, stack, depth + 1))
        return root


# Shared by the nodes that are not arrays, or not objects; never appended to.
_NO_ITEMS: list[JsonNode] = []
_NO_MEMBERS: list[Member] = []

# A container of `JsonNode.to_python`, filled as its stack is worked off.
_Container: TypeAlias = dict[str, object] | list[object]


def _shell(node: JsonNode, stack: list[tuple[JsonNode, _Container, int]],
           depth: int) -> object:
    out: _Container
    if node.kind == "object":
        out = {}
    elif node.kind == "array":
        out = []
    else:
        return node.value
    stack.append((node, out, depth))
    return out


class JsonError(ValueError):
    """Text that is not JSON. `span` is the offending text (empty at the end of the file),
    `line` and `column` (1-based, code points) its start, `labels` secondary spans with a
    message each (where an unclosed bracket opened, where a duplicate key first appeared)."""

    def __init__(self, message: str, span: Span, text: str,
                 labels: tuple[tuple[Span, str], ...] = ()) -> None:
        position = SourceFile("", text).position(span.start)
        self.message = message
        self.span = span
        self.line = position.line
        self.column = position.column
        self.labels = labels
        super().__init__(f"line {self.line}, column {self.column}: {message}")


_WS = re.compile(r"[ \t\n\r]*")
_STRING_RUN = re.compile(r'[^"\\\x00-\x1f]*')
_NUMBER = re.compile(r"-?(?:0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?")
_NUMBERISH = re.compile(r"[-+0-9.eE]+")
_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ESCAPES = {'"': '"', "\\": "\\", "/": "/", "b": "\b", "f": "\f", "n": "\n", "r": "\r", "t": "\t"}
_CLOSER = {"object": "}", "array": "]"}


def _shown(ch: str) -> str:
    if ch == "":
        return "the end of the file"
    if ch == "`":
        return "a backtick"
    if ch.isprintable() and not ch.isspace():
        return f"`{ch}`"
    return f"U+{ord(ch):04X}"


def _parse_string(text: str, start: int) -> tuple[str, int]:
    """The string literal opening at `start` (a `"`): its value and the offset after it."""
    pos = start + 1
    n = len(text)
    parts: list[str] = []
    while True:
        run = _STRING_RUN.match(text, pos)
        assert run is not None  # (a run of no characters at the least)
        end = run.end()
        if end > pos:
            parts.append(text[pos:end])
        pos = end
        if pos >= n:
            raise JsonError("unterminated string", Span(start, n), text,
                            ((Span(start, start + 1), "the string starts here"),))
        ch = text[pos]
        if ch == '"':
            return "".join(parts), pos + 1
        if ch != "\\":
            what = "line break" if ch in "\n\r" else f"control character U+{ord(ch):04X}"
            escape = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}.get(ch, f"\\u{ord(ch):04x}")
            raise JsonError(f"a {what} inside a string: write it as `{escape}`",
                            Span(pos, pos + 1), text)
        esc = text[pos + 1 : pos + 2]
        if esc in _ESCAPES:
            parts.append(_ESCAPES[esc])
            pos += 2
            continue
        if esc == "u":
            code, pos = _parse_unicode_escape(text, pos)
            parts.append(code)
            continue
        shown = f"\\{esc}" if esc and esc.isprintable() else "\\"
        raise JsonError(
            f"invalid escape `{shown}` in a string: JSON knows `\\\"`, `\\\\`, `\\/`, `\\b`, "
            "`\\f`, `\\n`, `\\r`, `\\t` and `\\uXXXX`",
            Span(pos, min(pos + 2, n)), text)


def _hex4(text: str, pos: int) -> int | None:
    digits = text[pos : pos + 4]
    if len(digits) == 4 and all(c in "0123456789abcdefABCDEF" for c in digits):
        return int(digits, 16)
    return None


def _parse_unicode_escape(text: str, pos: int) -> tuple[str, int]:
    """The `\\uXXXX` escape at `pos` (a surrogate pair takes two escapes)."""
    code = _hex4(text, pos + 2)
    if code is None:
        raise JsonError("`\\u` must be followed by four hexadecimal digits",
                        Span(pos, min(pos + 6, len(text))), text)
    if 0xDC00 <= code <= 0xDFFF:
        raise JsonError(f"the escape `\\u{code:04x}` is the second half of a surrogate pair "
                        "without its first half", Span(pos, pos + 6), text)
    if 0xD800 <= code <= 0xDBFF:
        low = _hex4(text, pos + 8) if text[pos + 6 : pos + 8] == "\\u" else None
        if low is None or not 0xDC00 <= low <= 0xDFFF:
            raise JsonError(f"the escape `\\u{code:04x}` is the first half of a surrogate pair "
                            "without its second half", Span(pos, pos + 6), text)
        return chr(0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00)), pos + 12
    return chr(code), pos + 6


def string_offsets(text: str, node: JsonNode) -> list[int]:
    """For the string `node` of `text`: the source offset of each character of its value, and
    one more entry for the offset of the closing quote. Lets a caller that parses the string's
    value (a `toparse` condition) report positions in the JSON file even across escapes."""
    offsets: list[int] = []
    pos = node.start + 1
    end = node.end - 1
    while pos < end:
        if text[pos] != "\\":
            offsets.append(pos)
            pos += 1
        elif text[pos + 1] != "u":
            offsets.append(pos)
            pos += 2
        else:
            _, after = _parse_unicode_escape(text, pos)
            offsets.append(pos)
            pos = after
    offsets.append(end)
    return offsets


def _number(text: str, raw: str, start: int, is_integer: bool) -> int | float:
    """The value of the number `raw` at `start`, under scriptc's number policy
    (`scriptc.numbers`: finite, within a double's range, however many digits it is written
    with)."""
    try:
        return json_number(raw, is_integer)
    except NumberError as error:
        raise JsonError(error.message, Span(start, start + len(raw)), text) from None


def _scalar(text: str, pos: int) -> tuple[JsonNode, int]:
    """The scalar value starting at `pos` (not `{` or `[`)."""
    n = len(text)
    ch = text[pos] if pos < n else ""
    if ch == '"':
        string, end = _parse_string(text, pos)
        return JsonNode("string", pos, end, string), end
    if ch and (ch == "-" or ch.isdigit() or ch in "+."):
        if text.startswith("-Infinity", pos):
            raise JsonError("`-Infinity` is not a JSON number: JSON numbers are finite",
                            Span(pos, pos + 9), text)
        m = _NUMBER.match(text, pos)
        loose = _NUMBERISH.match(text, pos)
        loose_end = loose.end() if loose else pos + 1
        if m is None or m.end() != loose_end:
            bad = text[pos:loose_end]
            hint = ""
            unsigned = bad.lstrip("-")
            if unsigned.startswith("0") and len(unsigned) > 1 and unsigned[1:2].isdigit():
                hint = ": JSON numbers have no leading zeros"
            elif bad.startswith("+"):
                hint = ": JSON numbers have no `+` sign"
            elif bad.startswith((".", "-.")) or bad.endswith("."):
                hint = ": write a digit on both sides of the decimal point"
            raise JsonError(f"invalid number `{bad}`{hint}", Span(pos, loose_end), text)
        raw = m.group()
        end = m.end()
        number = _number(text, raw, pos, not (m.group(1) or m.group(2)))
        return JsonNode("number", pos, end, number, raw), end
    w = _WORD.match(text, pos)
    if w is not None:
        word = w.group()
        span = Span(pos, w.end())
        if word in _LITERALS:
            kind, literal = _LITERALS[word]
            return JsonNode(kind, pos, span.end, literal), span.end
        if word in ("NaN", "Infinity"):
            raise JsonError(f"`{word}` is not a JSON number: JSON numbers are finite", span, text)
        if word in ("True", "False", "None"):
            proper = {"True": "true", "False": "false", "None": "null"}[word]
            raise JsonError(f"`{word}` is not JSON: write `{proper}`", span, text)
        raise JsonError(f"expected a value, found `{word}`", span, text)
    if ch == "'":
        raise JsonError("JSON strings use double quotes, not single quotes",
                        Span(pos, pos + 1), text)
    if ch == "/" and text[pos + 1 : pos + 2] in ("/", "*"):
        raise JsonError("JSON has no comments", Span(pos, pos + 2), text)
    if ch == "":
        raise JsonError("expected a value, found the end of the file", Span(n, n), text)
    raise JsonError(f"expected a value, found {_shown(ch)}", Span(pos, pos + 1), text)


def _skip(text: str, pos: int) -> int:
    blank = _WS.match(text, pos)
    assert blank is not None  # (no blank at the least)
    return blank.end()


def _unclosed(node: JsonNode) -> tuple[tuple[Span, str], ...]:
    what = "object" if node.kind == "object" else "array"
    return ((Span(node.start, node.start + 1), f"this {what} is never closed"),)


# One token, whitespace before it skipped: the fast path of `parse_json`. Groups: 1 `{` or `[`,
# 2 `}` or `]`, 3 `,`, 4 a string without escapes (its content), 5 a number (6 its fraction,
# 7 its exponent), 8 `true`/`false`/`null`. Anything else goes to the careful path, which also
# writes every error message.
_TOKEN = re.compile(
    r'[ \t\n\r]*(?:([{\[])|([}\]])|(,)|"([^"\\\x00-\x1f]*)"'
    r"|(-?(?:0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?)(?![-+0-9.eE])"
    r"|(true|false|null)(?![A-Za-z0-9_]))"
)
_COLON = re.compile(r"[ \t\n\r]*:")
_LITERALS: dict[str, tuple[str, bool | None]] = {
    "true": ("boolean", True), "false": ("boolean", False), "null": ("null", None)}
# The key of the value being parsed, per open container (an array's: none, never read).
_NO_KEY = ("", -1, -1)
_VALUE, _AFTER, _KEY = 0, 1, 2


def parse_json(text: str, max_depth: int | None = None) -> JsonNode:
    """Parse `text` (one JSON value, whitespace around it allowed). Raises `JsonError`.
    With `max_depth`, arrays and objects nested deeper than that are an error at the bracket
    that opens one level too many (for readers whose values go on to code that recurses)."""
    # The tree has no reference cycles: pausing the cyclic collector while it grows skips
    # rescans that nearly doubled the time of a large file (see scriptc.gcpause).
    with gc_paused():
        return _parse(text, max_depth)


def _parse(text: str, max_depth: int | None) -> JsonNode:
    n = len(text)
    pos = 1 if text.startswith("\ufeff") else 0
    # Open containers, innermost last; for each, the keys seen so far (objects: for duplicate
    # reports) and the key whose value is being parsed.
    stack: list[JsonNode] = []
    keys_stack: list[dict[str, int]] = []
    pending: list[tuple[str, int, int]] = []
    mode = _VALUE
    done: JsonNode  # the value just completed (each way to the end of the loop sets it)
    comma = -1  # where the last comma was (for the trailing-comma message)
    token = _TOKEN.match
    colon = _COLON.match

    while True:
        m = token(text, pos)
        handled = False
        if m is not None:
            g = m.lastindex
            if mode == _VALUE:
                handled = True
                if g == 4:
                    end = m.end()
                    done = JsonNode("string", m.start(4) - 1, end, m.group(4))
                    pos = end
                elif g == 5:
                    raw = m.group(5)
                    if len(raw) < 16 and not (m.group(6) or m.group(7)):
                        value: JsonScalar = int(raw)  # the common case, within any policy
                    else:
                        value = _number(text, raw, m.start(5), not (m.group(6) or m.group(7)))
                    done = JsonNode("number", m.start(5), m.end(), value, raw)
                    pos = m.end()
                elif g == 8:
                    kind, value = _LITERALS[m.group(8)]
                    done = JsonNode(kind, m.start(8), m.end(), value)
                    pos = m.end()
                elif g == 1:
                    if max_depth is not None and len(stack) >= max_depth:
                        raise JsonError(f"arrays and objects nested more than {max_depth} "
                                        "levels deep", Span(m.start(1), m.end()), text)
                    opener = m.group(1)
                    kind = "object" if opener == "{" else "array"
                    node = JsonNode(kind, m.start(1), m.end())
                    pos = m.end()
                    m2 = token(text, pos)
                    if m2 is not None and m2.lastindex == 2 and m2.group(2) == _CLOSER[kind]:
                        node.end = m2.end()
                        pos = m2.end()
                        done = node
                    else:
                        stack.append(node)
                        keys_stack.append({})
                        pending.append(_NO_KEY)
                        mode = _KEY if kind == "object" else _VALUE
                        continue
                else:
                    handled = False
            elif mode == _AFTER:
                container = stack[-1]
                if g == 3:
                    comma = m.end() - 1
                    pos = m.end()
                    mode = _KEY if container.kind == "object" else _VALUE
                    continue
                if g == 2 and m.group(2) == _CLOSER[container.kind]:
                    container.end = m.end()
                    pos = m.end()
                    stack.pop()
                    keys_stack.pop()
                    pending.pop()
                    done = container
                    handled = True
            elif g == 4:  # mode == _KEY
                c = colon(text, m.end())
                if c is not None:
                    key = m.group(4)
                    key_start = m.start(4) - 1
                    seen = keys_stack[-1]
                    if key in seen:
                        _duplicate(text, key, Span(key_start, m.end()), seen[key])
                    seen[key] = key_start
                    pending[-1] = (key, key_start, m.end())
                    pos = c.end()
                    mode = _VALUE
                    continue

        if not handled:
            # The careful path: strings with escapes, and every error.
            pos = _skip(text, pos)
            ch = text[pos] if pos < n else ""
            _no_comment(text, pos)
            if mode == _VALUE:
                if ch and ch in "}]" and stack and ch == _CLOSER[stack[-1].kind]:
                    raise JsonError(f"a comma before `{ch}`: JSON allows no trailing comma",
                                    Span(comma, comma + 1), text,
                                    ((Span(pos, pos + 1), f"`{ch}` follows the comma"),))
                if ch == "" and stack:
                    raise JsonError("the file ends where a value was expected", Span(n, n), text,
                                    _unclosed(stack[-1]))
                done, pos = _scalar(text, pos)
            elif mode == _KEY:
                container = stack[-1]
                if ch == '"':
                    key_start = pos
                    key, pos = _parse_string(text, pos)
                    key_end = pos
                    seen = keys_stack[-1]
                    if key in seen:
                        _duplicate(text, key, Span(key_start, key_end), seen[key])
                    seen[key] = key_start
                    pos = _skip(text, pos)
                    if text[pos : pos + 1] != ":":
                        found = _shown(text[pos : pos + 1])
                        raise JsonError(f"expected `:` after the key `{key}`, found {found}",
                                        Span(pos, min(pos + 1, n)), text,
                                        _unclosed(container) if pos >= n else ())
                    pending[-1] = (key, key_start, key_end)
                    pos += 1
                    mode = _VALUE
                    continue
                if ch == "}":
                    raise JsonError("a comma before `}`: JSON allows no trailing comma",
                                    Span(comma, comma + 1), text,
                                    ((Span(pos, pos + 1), "`}` follows the comma"),))
                if ch == "":
                    raise JsonError("the file ends inside an object", Span(n, n), text,
                                    _unclosed(container))
                if ch == "'":
                    raise JsonError("JSON keys are strings in double quotes, not single quotes",
                                    Span(pos, pos + 1), text)
                w = _WORD.match(text, pos)
                found = f"`{w.group()}`" if w else _shown(ch)
                span = Span(pos, w.end()) if w else Span(pos, pos + 1)
                raise JsonError(f"expected a key in double quotes, found {found}", span, text)
            else:  # _AFTER: the fast path takes `,` and the right closer, so this is an error
                container = stack[-1]
                closer = _CLOSER[container.kind]
                what = "object member" if container.kind == "object" else "array element"
                if ch == "":
                    raise JsonError(f"the file ends inside an {container.kind}", Span(n, n),
                                    text, _unclosed(container))
                raise JsonError(f"expected `,` or `{closer}` after an {what}, found {_shown(ch)}",
                                Span(pos, pos + 1), text,
                                _unclosed(container) if ch in "}]" else ())

        # A value is complete: hand it to its container, or it is the document.
        if not stack:
            break
        parent = stack[-1]
        if parent.kind == "array":
            parent.items.append(done)
        else:
            key, key_start, key_end = pending[-1]
            parent.members.append(Member(key, key_start, key_end, done))
        mode = _AFTER

    pos = _skip(text, pos)
    _no_comment(text, pos)
    if pos < n:
        raise JsonError(f"unexpected {_shown(text[pos])} after the end of the JSON value",
                        Span(pos, pos + 1), text)
    return done


def _no_comment(text: str, pos: int) -> None:
    if text.startswith(("//", "/*"), pos):
        raise JsonError("JSON has no comments", Span(pos, pos + 2), text)


def _duplicate(text: str, key: str, key_span: Span, first_start: int) -> None:
    first_end = _parse_string(text, first_start)[1]
    first = Span(first_start, first_end)
    first_pos = SourceFile("", text).position(first_start)
    raise JsonError(
        f"duplicate key `{key}` (first at line {first_pos.line}, column {first_pos.column})",
        key_span, text, ((first, "first defined here"),))
