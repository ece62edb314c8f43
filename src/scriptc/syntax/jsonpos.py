"""A JSON parser that remembers where every key and value is (for `scriptc check FILE.json`).

The standard `json` module returns values without positions, recurses (a file of 20,000 nested
arrays raises RecursionError) and accepts `NaN` and `Infinity`. This parser is iterative (an
explicit stack, so nesting depth is bounded by memory only), follows RFC 8259 strictly and
returns a small tree of `JsonNode`s whose spans are character offsets into the text, the same
offsets `scriptc.source.Span` uses everywhere. Errors raise `JsonError` with the span of the
offending text, its line and column, and a message that says what was expected.

Choices beyond RFC 8259, each for a reason:
- duplicate keys are an error (RFC 8259 leaves their meaning open; the robot's loader would
  keep one of them silently, so the other is a mistake nobody would see);
- `NaN`, `Infinity` and `-Infinity` are errors with a message of their own (Python writes them);
- a `\\u` escape of half a surrogate pair is an error (the text could not be written as UTF-8);
- a leading byte order mark is skipped (Windows editors write one; the robot's loader, nlohmann
  json, skips it too).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from scriptc.source import SourceFile, Span

__all__ = ["JsonNode", "Member", "JsonError", "parse_json", "string_offsets"]


_EMPTY: list = []  # shared by scalars; never appended to


@dataclass(slots=True, eq=False)
class Member:
    """One `"key": value` pair of an object; `key_span` covers the key with its quotes."""

    key: str
    key_span: Span
    value: JsonNode


class JsonNode:
    """A JSON value and where it is.

    `kind` is one of "object", "array", "string", "number", "boolean", "null". `value` is the
    Python value of a scalar (str, int, float, bool or None; None for containers). `raw` is the
    number's text as written (`1000`, `1e3`), empty for other kinds. `span` covers the whole
    value, quotes and brackets included. Objects keep their members in document order.
    """

    # A plain slotted class rather than a dataclass: a large file makes hundreds of thousands
    # of nodes, and only containers need the two lists.
    __slots__ = ("kind", "span", "value", "raw", "items", "members")

    def __init__(self, kind: str, span: Span, value: object = None, raw: str = "") -> None:
        self.kind = kind
        self.span = span
        self.value = value
        self.raw = raw
        self.items: list[JsonNode] = [] if kind == "array" else _EMPTY
        self.members: list[Member] = [] if kind == "object" else _EMPTY

    def __repr__(self) -> str:
        return f"JsonNode({self.kind}, {self.span.start}-{self.span.end})"

    @property
    def content_span(self) -> Span:
        """A string's span without its quotes (the whole span for other kinds)."""
        if self.kind == "string":
            return Span(self.span.start + 1, self.span.end - 1)
        return self.span

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

    def to_python(self) -> object:
        """The plain Python value (dict, list, str, int, float, bool, None), built without
        recursion so a deeply nested document converts as well as it parsed."""
        if self.kind not in ("object", "array"):
            return self.value
        root: object = {} if self.kind == "object" else []
        stack: list[tuple[JsonNode, object]] = [(self, root)]
        while stack:
            node, out = stack.pop()
            if node.kind == "object":
                for m in node.members:
                    out[m.key] = _shell(m.value, stack)  # type: ignore[index]
            else:
                for item in node.items:
                    out.append(_shell(item, stack))  # type: ignore[union-attr]
        return root


def _shell(node: JsonNode, stack: list) -> object:
    if node.kind == "object":
        out: object = {}
    elif node.kind == "array":
        out = []
    else:
        return node.value
    stack.append((node, out))
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
        end = run.end()  # type: ignore[union-attr]
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
    pos = node.span.start + 1
    end = node.span.end - 1
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


def _scalar(text: str, pos: int) -> tuple[JsonNode, int]:
    """The scalar value starting at `pos` (not `{` or `[`)."""
    n = len(text)
    ch = text[pos] if pos < n else ""
    if ch == '"':
        value, end = _parse_string(text, pos)
        return JsonNode("string", Span(pos, end), value), end
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
            if bad.lstrip("-").startswith("0") and len(bad.lstrip("-")) > 1 and bad.lstrip("-")[1:2].isdigit():
                hint = ": JSON numbers have no leading zeros"
            elif bad.startswith("+"):
                hint = ": JSON numbers have no `+` sign"
            elif bad.startswith(".") or bad.startswith("-.") or bad.endswith("."):
                hint = ": write a digit on both sides of the decimal point"
            raise JsonError(f"invalid number `{bad}`{hint}", Span(pos, loose_end), text)
        raw = m.group()
        end = m.end()
        value: object = float(raw) if m.group(1) or m.group(2) else int(raw)
        return JsonNode("number", Span(pos, end), value, raw), end
    w = _WORD.match(text, pos)
    if w is not None:
        word = w.group()
        span = Span(pos, w.end())
        if word == "true":
            return JsonNode("boolean", span, True), span.end
        if word == "false":
            return JsonNode("boolean", span, False), span.end
        if word == "null":
            return JsonNode("null", span, None), span.end
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
    return _WS.match(text, pos).end()  # type: ignore[union-attr]


def _unclosed(node: JsonNode, text: str) -> tuple[tuple[Span, str], ...]:
    what = "object" if node.kind == "object" else "array"
    return ((Span(node.span.start, node.span.start + 1), f"this {what} is never closed"),)


def parse_json(text: str) -> JsonNode:
    """Parse `text` (one JSON value, whitespace around it allowed). Raises `JsonError`."""
    n = len(text)
    pos = 1 if text.startswith("\ufeff") else 0
    # Open containers, innermost last. For an object, `keys` maps each key to its span (for
    # duplicate reports) and `key`/`key_span` hold the key whose value is being parsed.
    stack: list[JsonNode] = []
    keys_stack: list[dict[str, Span]] = []
    pending: list[tuple[str, Span] | None] = []
    root: JsonNode | None = None
    mode = "value"  # "value", "after" (a value ended), "key" (expect a key)
    done: JsonNode | None = None

    ws_match = _WS.match
    while True:
        if pos < n and text[pos] in " \t\n\r":
            pos = ws_match(text, pos).end()  # type: ignore[union-attr]
        ch = text[pos] if pos < n else ""
        if mode == "value":
            if ch == "{" or ch == "[":
                kind = "object" if ch == "{" else "array"
                node = JsonNode(kind, Span(pos, pos + 1))
                pos = _skip(text, pos + 1)
                if text[pos : pos + 1] == _CLOSER[kind]:
                    node.span = Span(node.span.start, pos + 1)
                    pos += 1
                    done = node
                else:
                    stack.append(node)
                    keys_stack.append({})
                    pending.append(None)
                    mode = "key" if kind == "object" else "value"
                    continue
            else:
                if ch and ch in "}]" and stack:
                    container = stack[-1]
                    if ch == _CLOSER[container.kind]:
                        raise JsonError(f"a trailing comma before `{ch}`: JSON allows none",
                                        Span(pos, pos + 1), text)
                if ch == "" and stack:
                    raise JsonError("the file ends where a value was expected", Span(n, n), text,
                                    _unclosed(stack[-1], text))
                done, pos = _scalar(text, pos)
        elif mode == "key":
            container = stack[-1]
            if ch == '"':
                key_start = pos
                key, pos = _parse_string(text, pos)
                key_span = Span(key_start, pos)
                seen = keys_stack[-1]
                if key in seen:
                    first = seen[key]
                    first_pos = SourceFile("", text).position(first.start)
                    raise JsonError(
                        f"duplicate key `{key}` (first at line {first_pos.line}, "
                        f"column {first_pos.column})",
                        key_span, text, ((first, "first defined here"),))
                seen[key] = key_span
                pos = _skip(text, pos)
                if text[pos : pos + 1] != ":":
                    found = _shown(text[pos : pos + 1])
                    raise JsonError(f"expected `:` after the key `{key}`, found {found}",
                                    Span(pos, min(pos + 1, n)), text,
                                    _unclosed(container, text) if pos >= n else ())
                pending[-1] = (key, key_span)
                pos += 1
                mode = "value"
                continue
            if ch == "}":
                raise JsonError("a trailing comma before `}`: JSON allows none",
                                Span(pos, pos + 1), text)
            if ch == "":
                raise JsonError("the file ends inside an object", Span(n, n), text,
                                _unclosed(container, text))
            if ch == "'":
                raise JsonError("JSON keys are strings in double quotes, not single quotes",
                                Span(pos, pos + 1), text)
            w = _WORD.match(text, pos)
            found = f"`{w.group()}`" if w else _shown(ch)
            span = Span(pos, w.end()) if w else Span(pos, pos + 1)
            raise JsonError(f"expected a key in double quotes, found {found}", span, text)
        else:  # mode == "after": a value inside a container has ended
            container = stack[-1]
            closer = _CLOSER[container.kind]
            if ch == ",":
                pos += 1
                mode = "key" if container.kind == "object" else "value"
                continue
            if ch == closer:
                container.span = Span(container.span.start, pos + 1)
                pos += 1
                stack.pop()
                keys_stack.pop()
                pending.pop()
                done = container
            else:
                what = "object member" if container.kind == "object" else "array element"
                if ch == "":
                    raise JsonError(f"the file ends inside an {'object' if closer == '}' else 'array'}",
                                    Span(n, n), text, _unclosed(container, text))
                raise JsonError(f"expected `,` or `{closer}` after an {what}, found {_shown(ch)}",
                                Span(pos, pos + 1), text, _unclosed(container, text)
                                if ch and ch in "}]" else ())

        # A value is complete: hand it to its container, or it is the document.
        assert done is not None
        if not stack:
            root = done
            break
        parent = stack[-1]
        if parent.kind == "array":
            parent.items.append(done)
        else:
            key, key_span = pending[-1]  # type: ignore[misc]
            parent.members.append(Member(key, key_span, done))
            pending[-1] = None
        done = None
        mode = "after"

    pos = _skip(text, pos)
    if pos < n:
        raise JsonError(f"unexpected {_shown(text[pos])} after the end of the JSON value",
                        Span(pos, pos + 1), text)
    return root
