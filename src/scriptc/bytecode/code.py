"""Instructions as bytes and back, derived from the opcode table: `Assembler` writes an
instruction stream (codegen drives it), `read_instruction`/`instructions` read one back (the
verifier and the listing). No other module knows how an instruction is laid out.
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from typing import NamedTuple

from scriptc.bytecode.errors import InvalidError
from scriptc.bytecode.opcodes import BY_CODE, BY_NAME, Opcode

__all__ = ["Assembler", "Instruction", "JumpTarget", "instructions", "read_instruction"]


class Instruction(NamedTuple):
    """One instruction of a code section: where it starts, its opcode, its operands as stored
    (integers, in table order), and where the next one starts."""

    offset: int
    opcode: Opcode
    operands: tuple[int, ...]
    end: int


def read_instruction(code: bytes, offset: int, end: int | None = None) -> Instruction:
    """The instruction at `offset`; InvalidError for an unknown opcode or one whose operands
    run past `end` (by default the end of the code)."""
    if end is None:
        end = len(code)
    op = BY_CODE.get(code[offset])
    if op is None:
        raise InvalidError(f"unknown opcode 0x{code[offset]:02x}", offset)
    if offset + op.size > end:
        raise InvalidError(f"{op.name} needs {op.size} bytes but its block ends after "
                           f"{end - offset}", offset)
    return Instruction(offset, op, op.struct.unpack_from(code, offset + 1), offset + op.size)


def instructions(code: bytes, start: int = 0, end: int | None = None) -> Iterator[Instruction]:
    """The instructions of `code[start:end]` in order."""
    if end is None:
        end = len(code)
    offset = start
    while offset < end:
        ins = read_instruction(code, offset, end)
        yield ins
        offset = ins.end


class JumpTarget:
    """A code offset not known yet (a forward jump's target); `Assembler.place` fixes it. (The
    script's labels are names of blocks; this is the assembler's own.)"""

    __slots__ = ("offset", "uses")

    def __init__(self) -> None:
        self.offset: int | None = None
        self.uses: list[int] = []  # byte offsets of u32 operands waiting for it


class Assembler:
    """Builds an instruction stream: `emit("MOVE", ...)` with operands in table order; jump
    operands may be JumpTargets, patched when the target is placed. `mark(span)` records the
    source span of the instructions that follow (an entry only when the span changes)."""

    def __init__(self) -> None:
        self.code = bytearray()
        self.spans: list[tuple[int, int, int]] = []
        self._span: tuple[int, int] | None = None

    @property
    def offset(self) -> int:
        return len(self.code)

    def mark(self, start: int, end: int) -> None:
        if self._span != (start, end):
            self._span = (start, end)
            here = len(self.code)
            if self.spans and self.spans[-1][0] == here:
                # Nothing was emitted under the previous span: it gives way.
                self.spans.pop()
                if self.spans and self.spans[-1][1:] == (start, end):
                    return
            self.spans.append((here, start, end))

    def place(self, target: JumpTarget) -> None:
        target.offset = len(self.code)
        for at in target.uses:
            self.code[at:at + 4] = target.offset.to_bytes(4, "little")

    def since(self, offset: int) -> bytes:
        """The bytes emitted from `offset` on (to `replay` later)."""
        return bytes(self.code[offset:])

    def replay(self, encoded: bytes) -> None:
        """Append instructions encoded before by this assembler (`since`), which hold no
        jump: their bytes do not depend on where they go."""
        self.code += encoded

    def emit(self, name: str, *operands: int | JumpTarget) -> int:
        """Append one instruction; returns its offset."""
        packer, code, jumps = _EMIT[name]
        at = len(self.code)
        if jumps:
            values = list(operands)
            for index, where in jumps:
                value = values[index]
                if isinstance(value, JumpTarget):
                    if value.offset is None:
                        value.uses.append(at + where)
                        values[index] = 0
                    else:
                        values[index] = value.offset
            operands = tuple(values)
        try:
            self.code += packer.pack(code, *operands)
        except struct.error as exc:
            raise ValueError(f"{name}: {exc}") from None
        return at


# Per mnemonic: the struct of the whole instruction (opcode byte first), the opcode, the jump
# operands (position, byte offset in the instruction).
_EMIT: dict[str, tuple[struct.Struct, int, tuple[tuple[int, int], ...]]] = {}
for _op in BY_NAME.values():
    _jumps = []
    _where = 1
    for _i, _o in enumerate(_op.operands):
        if _o.kind.name == "jump":
            _jumps.append((_i, _where))
        _where += _o.kind.size
    _EMIT[_op.name] = (struct.Struct("<B" + _op.struct.format[1:]), _op.code, tuple(_jumps))
