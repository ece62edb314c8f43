"""Source text and positions: the first stage of every pipeline.

A `Span` is a pair of character offsets into one `SourceFile`'s text (code points, end
exclusive). Lines and columns are computed only when something is shown to a person or an
editor: `SourceFile.position(offset)` gives 1-based line and column in code points. The
language server's positions (columns in UTF-8, UTF-16 or UTF-32 units) are
`scriptc.server.convert`'s alone.

`SourceKind` says what a source is written in: script syntax, thesis JSON or bytecode.
"""

from __future__ import annotations

import bisect
import os
import re
from dataclasses import dataclass
from enum import StrEnum
from functools import cached_property
from typing import NamedTuple

_LINE_BREAK = re.compile(r"\r\n|\r|\n")


class SourceKind(StrEnum):
    """What a source is written in. The values are the words the cache keys and messages use
    (a `StrEnum`: each member is equal to its value)."""

    SCRIPT = "script"  # the script syntax (docs/language.md)
    JSON = "json"  # the thesis JSON (docs/json.md)
    BYTECODE = "scb"  # a compiled program (docs/bytecode.md)

    @classmethod
    def of_path(cls, path: str) -> SourceKind:
        """The kind a file's suffix names (`.json`, `.scb`); script syntax for any other."""
        suffix = os.path.splitext(path)[1].lower()
        return {".json": cls.JSON, ".scb": cls.BYTECODE}.get(suffix, cls.SCRIPT)


class Span(NamedTuple):
    """Half-open range of character offsets `[start, end)` in a source text.

    A named tuple rather than a dataclass: lowering creates hundreds of thousands of spans
    for a large script, and a tuple is three times cheaper to build."""

    start: int
    end: int

    def cover(self, other: Span) -> Span:
        return Span(min(self.start, other.start), max(self.end, other.end))

    def shift(self, delta: int) -> Span:
        return Span(self.start + delta, self.end + delta)

    @property
    def length(self) -> int:
        return self.end - self.start


@dataclass(frozen=True, slots=True)
class Position:
    """A 1-based line and a 1-based column counted in code points."""

    line: int
    column: int


class SourceFile:
    """The text of one file and the name it is shown under."""

    __slots__ = ("__dict__", "path", "text")

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.text = text

    def __repr__(self) -> str:
        return f"SourceFile({self.path!r}, {len(self.text)} chars)"

    @cached_property
    def line_starts(self) -> list[int]:
        """Offsets at which each line starts. `\\n`, `\\r\\n` and a lone `\\r` end lines."""
        starts = [0]
        text = self.text
        i = text.find("\n")
        if "\r" not in text:
            while i != -1:
                starts.append(i + 1)
                i = text.find("\n", i + 1)
            return starts
        starts.extend(m.end() for m in _LINE_BREAK.finditer(text))
        return starts

    def line_of(self, offset: int) -> int:
        """0-based line index containing `offset`."""
        return bisect.bisect_right(self.line_starts, offset) - 1

    def position(self, offset: int) -> Position:
        offset = max(0, min(offset, len(self.text)))
        line = self.line_of(offset)
        return Position(line + 1, offset - self.line_starts[line] + 1)

    def offset(self, line: int, column: int) -> int:
        """Offset of a 1-based line and column (clamped to the text)."""
        starts = self.line_starts
        line = max(1, min(line, len(starts)))
        start = starts[line - 1]
        return min(start + max(column, 1) - 1, self.line_end(line - 1))

    def line_end(self, line_index: int) -> int:
        """Offset of the end of a 0-based line, before its line break."""
        starts = self.line_starts
        end = starts[line_index + 1] if line_index + 1 < len(starts) else len(self.text)
        while end > starts[line_index] and self.text[end - 1] in "\r\n":
            end -= 1
        return end

    def line_text(self, line_index: int) -> str:
        return self.text[self.line_starts[line_index] : self.line_end(line_index)]
