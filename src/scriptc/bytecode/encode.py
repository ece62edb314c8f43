"""Program -> the bytes of a `.scb` file (layout in `container.py`, docs/bytecode.md).

Encoding does not judge the program (that is `verify`): it writes what it is given, and
raises ValueError only for what the format cannot hold (a number past 32 bits, say).
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Iterable

from scriptc.bytecode import container as L
from scriptc.bytecode.program import Num, Program

__all__ = ["encode"]

_U32 = struct.Struct("<I")
_U16 = struct.Struct("<H")
_NUM = struct.Struct("<BdI")
_TEXT = struct.Struct("<BI")


def _opt(index: int | None) -> int:
    return L.NONE if index is None else index


def _constants(program: Program) -> bytes:
    out = [_U32.pack(len(program.constants))]
    append = out.append
    for c in program.constants:
        if isinstance(c, str):
            data = c.encode("utf-8")
            append(_TEXT.pack(L.TEXT_TAG, len(data)))
            append(data)
        elif isinstance(c, Num):
            data = c.text.encode("utf-8")
            append(_NUM.pack(L.NUMBER_TAG, c.value, len(data)))
            append(data)
        else:
            raise ValueError(f"not a constant: {c!r}")
    return b"".join(out)


def _script(program: Program) -> bytes:
    out = [L.SCRIPT_HEAD.struct.pack(program.name, _opt(program.source), len(program.alfa),
                                     len(program.omega))]
    pack = L.MESSAGE.struct.pack
    for m in (*program.alfa, *program.omega):
        out.append(pack(m.rulecode, m.id, m.intopic, m.outtopic, ord(m.action), ord(m.mutex),
                        m.span[0], m.span[1]))
    return b"".join(out)


def _blocks(program: Program) -> bytes:
    out = [L.BLOCK_COUNTS.struct.pack(len(program.goals), len(program.actions),
                                      len(program.blocks))]
    goal = L.GOAL.struct.pack
    out.extend(goal(g.id, g.actions, g.span[0], g.span[1]) for g in program.goals)
    action = L.ACTION.struct.pack
    out.extend(action(a.blocks, a.span[0], a.span[1]) for a in program.actions)
    block = L.BLOCK.struct.pack
    out.extend(block(ord(b.kind), _opt(b.label), b.code, b.span[0], b.span[1])
               for b in program.blocks)
    return b"".join(out)


def _deltas(values: Iterable[int]) -> list[int]:
    out: list[int] = []
    previous = 0
    for v in values:
        out.append(v - previous)
        previous = v
    return out


def _column(values: list[int], signed: bool) -> tuple[int, bytes]:
    """The narrowest width that holds every value, and the column packed at it."""
    low = min(values, default=0)
    high = max(values, default=0)
    for width, (unsigned_code, signed_code) in L.COLUMN_TYPES.items():
        bits = 8 * width
        if signed and -(1 << (bits - 1)) <= low and high < (1 << (bits - 1)):
            return width, struct.pack(f"<{len(values)}{signed_code}", *values)
        if not signed and low >= 0 and high < (1 << bits):
            return width, struct.pack(f"<{len(values)}{unsigned_code}", *values)
    raise ValueError("a span value does not fit in 32 bits")


def _spans(program: Program) -> bytes:
    spans = program.spans
    line_width, lines = _column(_deltas(program.lines), False)
    code_width, codes = _column(_deltas([s[0] for s in spans]), False)
    start_width, starts = _column(_deltas([s[1] for s in spans]), True)
    length_width, lengths = _column([s[2] - s[1] for s in spans], False)
    head = L.SPANS_HEAD.struct.pack(len(program.lines), len(spans), line_width, code_width,
                                    start_width, length_width)
    return b"".join((head, lines, codes, starts, lengths))


def encode(program: Program) -> bytes:
    """The bytes of the `.scb` file holding `program`."""
    try:
        sections = [
            (1, _constants(program)),
            (2, _script(program)),
            (3, _blocks(program)),
            (4, bytes(program.code)),
            (5, _spans(program)),
        ]
    except (struct.error, OverflowError, TypeError) as exc:
        raise ValueError(f"the program does not fit the format: {exc}") from None
    table_size = 2 + L.SECTION_ENTRY.size * len(sections)
    offset = L.HEADER.size + table_size
    table = [_U16.pack(len(sections))]
    for sid, data in sections:
        table.append(L.SECTION_ENTRY.struct.pack(sid, offset, len(data)))
        offset += len(data)
    body = b"".join(table + [data for _, data in sections])
    header = L.HEADER.struct.pack(L.MAGIC, L.FORMAT_VERSION, 0, len(body), zlib.crc32(body))
    return header + body
