"""A `.scb` program in memory: the constant pool, the script's tables, the code and the spans,
exactly as the file holds them (indices stay indices, the code stays bytes).

`decode` builds a Program from bytes without judging it; `verify` judges it; `encode` writes it.
Codegen (`scriptc.emit.codegen`) builds one from the IR. Nothing here knows the IR.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import NamedTuple

from scriptc.bytecode.opcodes import BLOCK_KINDS
from scriptc.source import Span

__all__ = ["ActionRecord", "BlockRecord", "CodeSpan", "Constant", "GoalRecord", "MessageRecord",
           "Num", "Program"]


@dataclass(frozen=True, slots=True)
class Num:
    """A number constant: the value a VM computes with, and the text the script wrote (which
    the thesis JSON keeps for speeds and colours, and the listing shows)."""

    value: float
    text: str


# A constant is a text (str) or a number (Num).
Constant = str | Num


@dataclass(frozen=True, slots=True)
class MessageRecord:
    """An alfa or omega rule message; `id`, `intopic`, `outtopic` are text constants."""

    rulecode: int
    id: int
    intopic: int
    outtopic: int
    action: str  # one letter of ARDBC
    mutex: str  # one letter of LMU
    span: Span


@dataclass(frozen=True, slots=True)
class GoalRecord:
    """A goal: its id (a text constant), how many action records follow as its own."""

    id: int  # text constant
    actions: int  # how many consecutive action records are this goal's
    span: Span


@dataclass(frozen=True, slots=True)
class ActionRecord:
    """An action: how many block records follow as its own."""

    blocks: int  # how many consecutive block records are this action's
    span: Span


@dataclass(frozen=True, slots=True)
class BlockRecord:
    """A block: its kind, its label and the offset of its first instruction."""

    kind: str  # a letter of BLOCK_KINDS
    label: int | None  # text constant
    code: int  # offset of the block's first instruction
    span: Span

    @property
    def kind_name(self) -> str:
        return BLOCK_KINDS.get(self.kind, "?")


class CodeSpan(NamedTuple):
    """From code offset `code` on, instructions come from the source span [start, end)."""

    code: int
    start: int
    end: int


class _Lookups:
    """What a `Program` derives from its tables, each built on first use (None until then)."""

    __slots__ = ("addresses", "index", "span_codes", "starts")

    def __init__(self) -> None:
        self.addresses: list[tuple[int, int, int]] | None = None  # `Program.addresses`
        self.index: dict[tuple[int, int, int], int] | None = None  # address -> block index
        self.starts: list[int] | None = None  # each block's code offset
        self.span_codes: list[int] | None = None  # each span's code offset


@dataclass(frozen=True, slots=True)
class Program:
    """A program as the `.scb` file holds it: constants, messages, records, code."""

    name: int  # text constant: the activity name
    source: int | None  # text constant: the source file's name
    constants: tuple[Constant, ...]
    alfa: tuple[MessageRecord, ...]
    omega: tuple[MessageRecord, ...]
    goals: tuple[GoalRecord, ...]
    actions: tuple[ActionRecord, ...]
    blocks: tuple[BlockRecord, ...]
    code: bytes
    # Offsets (code points) where each line of the source starts: line/column of any span
    # without the source. Empty when the program was compiled without its source text.
    lines: tuple[int, ...] = ()
    spans: tuple[CodeSpan, ...] = ()
    # Lookups derived from the tables, built on first use (not an init field: `replace`
    # gives the new program a fresh one).
    _cache: _Lookups = field(default_factory=_Lookups, init=False, compare=False, repr=False,
                             hash=False)

    # -- reading the tables (on a verified program) -------------------------------------------

    def text(self, index: int | None) -> str:
        """The text constant at `index` (empty for None)."""
        if index is None:
            return ""
        value = self.constants[index]
        return value if isinstance(value, str) else value.text

    @property
    def activity(self) -> str:
        return self.text(self.name)

    def addresses(self) -> list[tuple[int, int, int]]:
        """The (goal, action, block) address of each block record, in order."""
        cached = self._cache.addresses
        if cached is not None:
            return cached
        out: list[tuple[int, int, int]] = []
        action = 0
        for g, goal in enumerate(self.goals):
            for a in range(goal.actions):
                n = self.actions[action].blocks if action < len(self.actions) else 0
                out.extend((g, a, b) for b in range(n))
                action += 1
        self._cache.addresses = out
        return out

    def block_index(self, goal: int, action: int, block: int) -> int | None:
        """The index of the block at an address (for a switch "at goal/action/block")."""
        index = self._cache.index
        if index is None:
            index = {address: i for i, address in enumerate(self.addresses())}
            self._cache.index = index
        return index.get((goal, action, block))

    def block_path(self, index: int) -> str:
        """`goal0/act0/blk4`: the thesis JSON path of a block."""
        g, a, b = self.addresses()[index]
        return f"goal{g}/act{a}/blk{b}"

    def block_end(self, index: int) -> int:
        """The code offset where block `index`'s code ends."""
        if index + 1 < len(self.blocks):
            return self.blocks[index + 1].code
        return len(self.code)

    def block_at(self, offset: int) -> int:
        """The index of the block whose code holds `offset`."""
        starts = self._cache.starts
        if starts is None:
            starts = [b.code for b in self.blocks]
            self._cache.starts = starts
        return bisect.bisect_right(starts, offset) - 1

    def span_at(self, offset: int) -> Span | None:
        """The source span of the instruction at code offset `offset` (None if unknown)."""
        codes = self._cache.span_codes
        if codes is None:
            codes = [s.code for s in self.spans]
            self._cache.span_codes = codes
        i = bisect.bisect_right(codes, offset) - 1
        if i < 0:
            return None
        return Span(self.spans[i].start, self.spans[i].end)

    def position(self, offset: int) -> tuple[int, int] | None:
        """1-based line and column (code points) of a source offset, from the line table
        (None when the program carries no line table)."""
        if not self.lines:
            return None
        line = bisect.bisect_right(self.lines, offset) - 1
        line = max(line, 0)
        return line + 1, offset - self.lines[line] + 1
