"""Where each key and value of a TOML document is, so that a configuration problem can point at
its line: `tomllib` parses without positions.

`locate(text)` scans a document that `tomllib` has already accepted and records, for every
key path (`("lint", "select")`, `("functions", 0, "kind")`, array items by index), the span of
the key and the span of its value. It follows the TOML 1.0 rules that decide a path: table
headers (`[a.b]`), arrays of tables (`[[functions]]`, counted, with later headers under the
last element), dotted keys (`lint.select = ...`, also inside inline tables), quoted keys with
escapes, inline tables and arrays nested to any depth, and strings of the four kinds (so a `#`
or `]` inside a string is not mistaken for syntax). It never raises: on text it cannot follow
it keeps what it found so far.
"""

from __future__ import annotations

import re
from typing import Any

from scriptc.source import Span

KeyPath = tuple[str | int, ...]
# A value of a TOML document as `tomllib` parses it (a table, an array, a string, a number, a
# boolean or a date): untyped until the configuration's schema and checks have looked at it.
TOMLValue = Any
TOMLTable = dict[str, TOMLValue]

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
_WS = re.compile(r"[ \t]*")
# A scalar that is not a string: numbers, booleans, dates and times (a date and a time may be
# separated by one space).
_SCALAR = re.compile(r"[^\s,\]\}#]+(?: [0-9]{2}:[^\s,\]\}#]*)?")
_ESCAPE = re.compile(r"\\(u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8}|.)")
_SIMPLE_ESCAPES = {"b": "\b", "t": "\t", "n": "\n", "f": "\f", "r": "\r", '"': '"',
                   "\\": "\\", "e": "\x1b"}


class _Stop(Exception):
    """The scanner met text it cannot follow (never for a document tomllib accepted)."""


class KeySpans:
    """The spans of the keys and values of one document, by key path."""

    def __init__(self) -> None:
        self.keys: dict[KeyPath, Span] = {}
        self.values: dict[KeyPath, Span] = {}

    def key(self, path: KeyPath) -> Span | None:
        return self.keys.get(tuple(path))

    def value(self, path: KeyPath) -> Span | None:
        return self.values.get(tuple(path))

    def find(self, path: KeyPath, *, prefer: str = "value") -> Span:
        """The span to show for `path`: its value (or key, with `prefer="key"`), else the
        other, else that of the nearest enclosing path that was found, else the start."""
        path = tuple(path)
        first, second = (self.values, self.keys) if prefer == "value" else \
            (self.keys, self.values)
        while True:
            span = first.get(path) or second.get(path)
            if span is not None:
                return span
            if not path:
                return Span(0, 0)
            path = path[:-1]


def _unescape(body: str) -> str:
    def one(m: re.Match[str]) -> str:
        e = m.group(1)
        if e[0] in "uU":
            return chr(int(e[1:], 16))
        return _SIMPLE_ESCAPES.get(e, e)

    return _ESCAPE.sub(one, body)


class _Scanner:
    def __init__(self, text: str) -> None:
        self.text = text
        self.pos = 0
        self.out = KeySpans()
        # Arrays of tables: resolved path -> how many elements have been opened.
        self.counts: dict[KeyPath, int] = {}

    # -- lexical helpers ----------------------------------------------------------------------

    def ws(self) -> None:
        blanks = _WS.match(self.text, self.pos)
        assert blanks is not None  # `[ \t]*` matches at any position
        self.pos = blanks.end()

    def ws_comments_newlines(self) -> None:
        text, n = self.text, len(self.text)
        while self.pos < n:
            ch = text[self.pos]
            if ch in " \t\r\n":
                self.pos += 1
            elif ch == "#":
                end = text.find("\n", self.pos)
                self.pos = n if end == -1 else end
            else:
                return

    def peek(self, s: str) -> bool:
        return self.text.startswith(s, self.pos)

    def expect(self, s: str) -> None:
        if not self.peek(s):
            raise _Stop
        self.pos += len(s)

    def string(self) -> tuple[str, Span]:
        """A string of any kind at `pos`: its value (escapes resolved in basic strings) and
        the span of the whole literal."""
        text, start = self.text, self.pos
        for quote, escapes in (('"""', True), ("'''", False)):
            if text.startswith(quote, start):
                i = start + 3
                while True:
                    j = text.find(quote, i)
                    if j == -1:
                        raise _Stop
                    if escapes:
                        backslashes = 0
                        k = j - 1
                        while k >= start + 3 and text[k] == "\\":
                            backslashes += 1
                            k -= 1
                        if backslashes % 2:
                            i = j + 1
                            continue
                    # Up to two quotes may end the content just before the closing three.
                    end = j + 3
                    while end < len(text) and text[end] == quote[0] and end - j < 5:
                        end += 1
                    self.pos = end
                    body = text[start + 3:end - 3]
                    return (_unescape(body) if escapes else body), Span(start, end)
        quote = text[start]
        if quote == "'":
            j = text.find("'", start + 1)
            if j == -1:
                raise _Stop
            self.pos = j + 1
            return text[start + 1:j], Span(start, j + 1)
        if quote != '"':
            raise _Stop
        i = start + 1
        while i < len(text):
            ch = text[i]
            if ch == "\\":
                i += 2
            elif ch == '"':
                self.pos = i + 1
                return _unescape(text[start + 1:i]), Span(start, i + 1)
            elif ch == "\n":
                break
            else:
                i += 1
        raise _Stop

    def key(self) -> list[tuple[str, Span]]:
        """A dotted key: its parts with their spans."""
        parts = []
        while True:
            self.ws()
            if self.peek('"') or self.peek("'"):
                value, span = self.string()
            else:
                m = _BARE_KEY.match(self.text, self.pos)
                if m is None:
                    raise _Stop
                value, span = m.group(), Span(m.start(), m.end())
                self.pos = m.end()
            parts.append((value, span))
            self.ws()
            if not self.peek("."):
                return parts
            self.pos += 1

    # -- structure ----------------------------------------------------------------------------

    def resolve(self, parts: list[tuple[str, Span]], *, new_element: bool = False) -> KeyPath:
        """The path of a table header, recording the span of each of its names. A name that
        is an array of tables stands for its last element; with `new_element` the header opens
        a new element of the array it names."""
        path: KeyPath = ()
        for i, (name, span) in enumerate(parts):
            path += (name,)
            self.out.keys.setdefault(path, span)
            if i == len(parts) - 1 and new_element:
                count = self.counts.get(path, 0)
                self.counts[path] = count + 1
                path += (count,)
                self.out.keys.setdefault(path, span)
            elif path in self.counts:
                path += (self.counts[path] - 1,)
        return path

    def record_key_parts(self, base: KeyPath, parts: list[tuple[str, Span]]) -> KeyPath:
        path = base
        for name, span in parts:
            path += (name,)
            self.out.keys.setdefault(path, span)
        return path

    def document(self) -> KeySpans:
        table: KeyPath = ()
        n = len(self.text)
        while True:
            self.ws_comments_newlines()
            if self.pos >= n:
                return self.out
            start = self.pos
            if self.peek("[["):
                self.pos += 2
                parts = self.key()
                self.expect("]]")
                table = self.resolve(parts, new_element=True)
                self.out.values.setdefault(table, Span(start, self.pos))
            elif self.peek("["):
                self.pos += 1
                parts = self.key()
                self.expect("]")
                table = self.resolve(parts)
                self.out.values.setdefault(table, Span(start, self.pos))
            else:
                self.keyval(table)
            self.ws()
            if self.peek("#"):
                self.ws_comments_newlines()

    def keyval(self, base: KeyPath) -> None:
        parts = self.key()
        path = self.record_key_parts(base, parts)
        self.ws()
        self.expect("=")
        self.ws()
        self.value(path)

    def value(self, path: KeyPath) -> None:
        start = self.pos
        if self.peek('"') or self.peek("'"):
            self.string()
        elif self.peek("["):
            self.pos += 1
            index = 0
            while True:
                self.ws_comments_newlines()
                if self.peek("]"):
                    self.pos += 1
                    break
                self.value(path + (index,))
                index += 1
                self.ws_comments_newlines()
                if self.peek(","):
                    self.pos += 1
                elif not self.peek("]"):
                    raise _Stop
        elif self.peek("{"):
            self.pos += 1
            while True:
                self.ws_comments_newlines()
                if self.peek("}"):
                    self.pos += 1
                    break
                self.keyval(path)
                self.ws_comments_newlines()
                if self.peek(","):
                    self.pos += 1
                elif not self.peek("}"):
                    raise _Stop
        else:
            m = _SCALAR.match(self.text, self.pos)
            if m is None:
                raise _Stop
            self.pos = m.end()
        self.out.values[path] = Span(start, self.pos)


def locate(text: str) -> KeySpans:
    """The positions of every key and value of a TOML document (see the module's docstring)."""
    scanner = _Scanner(text)
    try:
        return scanner.document()
    except (_Stop, IndexError):
        return scanner.out


def string_offsets(text: str, span: Span) -> list[int]:
    """For the string literal at `span` of a TOML document (any of the four kinds): the offset
    of each character of its value, and one more entry, the offset of its closing quote. A
    reader that parses a string's value (a `jsonmsg` given as text) points into the document
    with it, across escapes: `\\uXXXX` and `\\UXXXXXXXX` stand for one character, a
    line-ending backslash of a multi-line basic string for none, and the line break right after
    the opening quotes of a multi-line string is not part of the value."""
    quotes = 3 if text.startswith(('"""', "'''"), span.start) else 1
    basic = text.startswith('"', span.start)
    pos, end = span.start + quotes, max(span.start + quotes, span.end - quotes)
    if quotes == 3:
        pos += 2 if text.startswith("\r\n", pos) else 1 if text.startswith("\n", pos) else 0
    offsets: list[int] = []
    while pos < end:
        if not basic or text[pos] != "\\" or pos + 1 >= end:
            offsets.append(pos)
            pos += 1
            continue
        escaped = text[pos + 1]
        if quotes == 3 and escaped in " \t\r\n":
            # A line-ending backslash: it and the blanks and line breaks after it are nothing.
            pos += 1
            while pos < end and text[pos] in " \t\r\n":
                pos += 1
            continue
        offsets.append(pos)
        pos += {"u": 6, "U": 10}.get(escaped, 2)
    offsets.append(end)
    return offsets
