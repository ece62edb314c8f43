"""The bytes of a `.scb` file -> Program, or MalformedError.

Decoding checks that the bytes are a well-formed file: the header (magic, version, flags,
length, CRC-32), the section table (every section present once, in order, back to back), and
that every section holds exactly its records. It does not judge what the records say (indices,
jumps, opcodes): that is `verify`. Every count is checked against the bytes left before
anything is allocated for it, so no input makes decoding slow or hungry.
"""

from __future__ import annotations

import struct
import zlib
from itertools import accumulate
from operator import add
from typing import Any

from scriptc.bytecode import container as L
from scriptc.bytecode.errors import MalformedError
from scriptc.bytecode.program import (
    ActionRecord,
    BlockRecord,
    CodeSpan,
    Constant,
    GoalRecord,
    MessageRecord,
    Num,
    Program,
)
from scriptc.source import Span

__all__ = ["decode"]

# A record as `struct` unpacks it: the values of its fields (ints and floats, as the record's
# format says; struct's results are untyped).
Row = tuple[Any, ...]

_U32 = struct.Struct("<I")
_U16 = struct.Struct("<H")
_F64 = struct.Struct("<d")


class _Reader:
    """Reads one section; every read checks the bytes left in it."""

    __slots__ = ("data", "end", "name", "pos")

    def __init__(self, data: bytes, start: int, end: int, name: str) -> None:
        self.data, self.pos, self.end, self.name = data, start, end, name

    def need(self, n: int, what: str) -> None:
        if n > self.end - self.pos:
            raise MalformedError(f"the {self.name} section is truncated: {what} needs {n} "
                                 f"bytes, {self.end - self.pos} are left", self.pos)

    def u8(self, what: str) -> int:
        self.need(1, what)
        self.pos += 1
        return self.data[self.pos - 1]

    def u32(self, what: str) -> int:
        self.need(4, what)
        self.pos += 4
        value: int = _U32.unpack_from(self.data, self.pos - 4)[0]
        return value

    def count(self, what: str, record_size: int) -> int:
        """A u32 count of records of `record_size` bytes that must fit in what is left."""
        at = self.pos
        n = self.u32(f"the number of {what}")
        if n * record_size > self.end - self.pos:
            raise MalformedError(f"the {self.name} section announces {n} {what}, more than "
                                 f"its {self.end - self.pos} remaining bytes can hold", at)
        return n

    def records(self, record: L.Record, n: int, what: str) -> list[Row]:
        size = record.size * n
        self.need(size, what)
        out = list(record.struct.iter_unpack(self.data[self.pos:self.pos + size]))
        self.pos += size
        return out

    def text(self, n: int, what: str) -> str:
        self.need(n, what)
        raw = self.data[self.pos:self.pos + n]
        try:
            value = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise MalformedError(f"{what} is not UTF-8 text", self.pos + exc.start) from None
        self.pos += n
        return value

    def done(self) -> None:
        if self.pos != self.end:
            raise MalformedError(f"the {self.name} section has {self.end - self.pos} bytes "
                                 "after its last record", self.pos)


def _not_bytecode(data: bytes) -> MalformedError:
    head = data[:64]
    hint = ""
    if head and all(b >= 0x20 or b in b"\t\r\n" for b in head):
        hint = (": it looks like text (a script? compile it with "
                "`scriptc compile --emit bytecode`)")
    return MalformedError(f"not a scriptc bytecode file (bad magic number){hint}", 0)


def _header(data: bytes) -> None:
    if not data:
        raise MalformedError("the file is empty: not a scriptc bytecode file", 0)
    if len(data) < L.HEADER.size:
        if not L.MAGIC.startswith(data[:4]):
            raise _not_bytecode(data)
        raise MalformedError(f"the file is truncated: {len(data)} bytes, shorter than the "
                             f"{L.HEADER.size}-byte header", len(data))
    magic, version, flags, length, crc = L.HEADER.struct.unpack_from(data, 0)
    if magic != L.MAGIC:
        raise _not_bytecode(data)
    if version != L.FORMAT_VERSION:
        raise MalformedError(f"unsupported format version {version} (this scriptc reads "
                             f"version {L.FORMAT_VERSION}): compile the script again", 4)
    if flags != 0:
        raise MalformedError(f"unknown flags 0x{flags:04x} in the header", 6)
    actual = len(data) - L.HEADER.size
    if actual < length:
        raise MalformedError(f"the file is truncated: the header announces {length} bytes "
                             f"after it, there are {actual}", len(data))
    if actual > length:
        raise MalformedError(f"{actual - length} unexpected bytes after the end of the "
                             "program", L.HEADER.size + length)
    if zlib.crc32(memoryview(data)[L.HEADER.size:]) != crc:
        raise MalformedError("checksum mismatch: the file is corrupted", 12)


def _sections(data: bytes) -> dict[int, tuple[int, int]]:
    pos = L.HEADER.size
    if len(data) < pos + 2:
        raise MalformedError("the file is truncated before the section table", len(data))
    (count,) = _U16.unpack_from(data, pos)
    if count != len(L.SECTIONS):
        raise MalformedError(f"the section table has {count} entries, not "
                             f"{len(L.SECTIONS)}", pos)
    pos += 2
    entry = L.SECTION_ENTRY
    if len(data) < pos + entry.size * count:
        raise MalformedError("the file is truncated inside the section table", len(data))
    expected_offset = pos + entry.size * count
    out: dict[int, tuple[int, int]] = {}
    for expected_id, name in L.SECTIONS.items():
        sid, offset, length = entry.struct.unpack_from(data, pos)
        if sid != expected_id:
            raise MalformedError(f"section entry {expected_id - 1} has id {sid}, expected "
                                 f"{expected_id} ({name})", pos)
        if offset != expected_offset:
            raise MalformedError(f"the {name} section starts at {offset}, expected "
                                 f"{expected_offset} (sections are back to back)", pos + 2)
        if offset + length > len(data):
            raise MalformedError(f"the {name} section runs past the end of the file", pos + 6)
        out[sid] = (offset, offset + length)
        expected_offset = offset + length
        pos += entry.size
    if expected_offset != len(data):
        raise MalformedError(f"{len(data) - expected_offset} bytes after the last section",
                             expected_offset)
    return out


def _constants(r: _Reader) -> tuple[Constant, ...]:
    n = r.count("constants", 5)  # the smallest constant: tag and an empty text
    out: list[Constant] = []
    append = out.append
    for i in range(n):
        at = r.pos
        tag = r.u8(f"constant {i}")
        if tag == L.TEXT_TAG:
            append(r.text(r.u32(f"constant {i}"), f"constant {i}"))
        elif tag == L.NUMBER_TAG:
            r.need(8, f"constant {i}")
            value = _F64.unpack_from(r.data, r.pos)[0]
            r.pos += 8
            text = r.text(r.u32(f"constant {i}"), f"constant {i}")
            append(Num(value, text))
        else:
            raise MalformedError(f"constant {i} has an unknown tag {tag}", at)
    r.done()
    return tuple(out)


def _opt(index: int) -> int | None:
    return None if index == L.NONE else index


Messages = tuple[MessageRecord, ...]  # a script's alfa or omega list


def _script(r: _Reader) -> tuple[int, int | None, Messages, Messages]:
    name, source, n_alfa, n_omega = r.records(L.SCRIPT_HEAD, 1, "the script head")[0]
    if (n_alfa + n_omega) * L.MESSAGE.size != r.end - r.pos:
        raise MalformedError(f"the script section announces {n_alfa} alfa and {n_omega} "
                             f"omega messages, but holds {r.end - r.pos} bytes of messages",
                             r.pos)
    rows = r.records(L.MESSAGE, n_alfa + n_omega, "the messages")
    messages = [MessageRecord(code, id_, inp, out, chr(action), chr(mutex), Span(s, e))
                for code, id_, inp, out, action, mutex, s, e in rows]
    r.done()
    return name, _opt(source), tuple(messages[:n_alfa]), tuple(messages[n_alfa:])


def _blocks(r: _Reader) -> tuple[tuple[GoalRecord, ...], tuple[ActionRecord, ...],
                                 tuple[BlockRecord, ...]]:
    n_goals, n_actions, n_blocks = r.records(L.BLOCK_COUNTS, 1, "the block counts")[0]
    size = n_goals * L.GOAL.size + n_actions * L.ACTION.size + n_blocks * L.BLOCK.size
    if size != r.end - r.pos:
        raise MalformedError(f"the blocks section announces {n_goals} goals, {n_actions} "
                             f"actions and {n_blocks} blocks ({size} bytes), but holds "
                             f"{r.end - r.pos} bytes of records", r.pos)
    goals = tuple(GoalRecord(i, n, Span(s, e))
                  for i, n, s, e in r.records(L.GOAL, n_goals, "goals"))
    actions = tuple(ActionRecord(n, Span(s, e))
                    for n, s, e in r.records(L.ACTION, n_actions, "actions"))
    blocks = tuple(BlockRecord(chr(kind), _opt(label), code, Span(s, e))
                   for kind, label, code, s, e in r.records(L.BLOCK, n_blocks, "blocks"))
    r.done()
    return goals, actions, blocks


def _spans(r: _Reader) -> tuple[tuple[int, ...], tuple[CodeSpan, ...]]:
    head_at = r.pos
    n_lines, n_spans, *widths = r.records(L.SPANS_HEAD, 1, "the spans head")[0]
    for width in widths:
        if width not in L.COLUMN_TYPES:
            raise MalformedError(f"a spans column is {width} bytes wide (1, 2 or 4 expected)",
                                 head_at + 8)
    line_width, code_width, start_width, length_width = widths
    size = n_lines * line_width + n_spans * (code_width + start_width + length_width)
    if size != r.end - r.pos:
        raise MalformedError(f"the spans section announces {n_lines} lines and {n_spans} "
                             f"spans ({size} bytes), but holds {r.end - r.pos} bytes of "
                             "columns", r.pos)

    def column(n: int, width: int, signed: bool) -> tuple[int, ...]:
        values = struct.unpack_from(f"<{n}{L.COLUMN_TYPES[width][signed]}", r.data, r.pos)
        r.pos += n * width
        return values

    lines = tuple(accumulate(column(n_lines, line_width, False)))
    codes = accumulate(column(n_spans, code_width, False))
    starts = list(accumulate(column(n_spans, start_width, True)))
    lengths = column(n_spans, length_width, False)
    spans = tuple(map(CodeSpan, codes, starts, map(add, starts, lengths)))
    r.done()
    return lines, spans


def decode(data: bytes) -> Program:
    """The program in `data`; MalformedError when the bytes are not a well-formed file."""
    data = bytes(data)
    _header(data)
    sections = _sections(data)

    def reader(name: str) -> _Reader:
        start, end = sections[L.SECTION_NAMES[name]]
        return _Reader(data, start, end, name)

    constants = _constants(reader("constants"))
    name, source, alfa, omega = _script(reader("script"))
    goals, actions, blocks = _blocks(reader("blocks"))
    code_start, code_end = sections[L.SECTION_NAMES["code"]]
    lines, spans = _spans(reader("spans"))
    return Program(
        name=name, source=source, constants=constants, alfa=alfa, omega=omega, goals=goals,
        actions=actions, blocks=blocks, code=data[code_start:code_end], lines=lines,
        spans=spans,
    )
