"""The two ways a `.scb` file is refused, kept apart as WebAssembly keeps them:

- *malformed* (`MalformedError`, raised by `decode`): the bytes are not a program at all: the
  magic number, the format version, the length, the checksum, a truncated or overlong section,
  text that is not UTF-8. Its offset is a byte offset in the file.
- *invalid* (`InvalidError`, raised by `verify`): a well-formed program that must not run: an
  unknown opcode, a jump out of its block, a constant index out of range, a stack that would
  underflow, tables that contradict each other. Its offset is a code offset when the fault is
  in the code, else None.

A *trap* (the script's fault at run time) and a *crash* (a bug of ours) are the runtime's.
"""

from __future__ import annotations

__all__ = ["BytecodeError", "InvalidError", "MalformedError"]


class BytecodeError(Exception):
    """A refused program: a message and where the fault is."""

    kind = "bytecode"
    where = "byte"

    def __init__(self, message: str, offset: int | None = None) -> None:
        super().__init__(message, offset)
        self.message = message
        self.offset = offset

    def __str__(self) -> str:
        if self.offset is None:
            return f"{self.kind}: {self.message}"
        return f"{self.kind}: {self.message} (at {self.where} {self.offset})"


class MalformedError(BytecodeError):
    """The bytes are not a well-formed `.scb` file (offset: byte in the file)."""

    kind = "malformed bytecode"
    where = "byte"


class InvalidError(BytecodeError):
    """A well-formed program that fails verification (offset: code offset, or None)."""

    kind = "invalid bytecode"
    where = "code offset"
