"""The `.scb` bytecode: the contract between the compiler and any VM (docs/bytecode.md).

- `opcodes.py`: THE opcode table; `container.py`: the byte layout of the file's records.
- `program.py`: a Program in memory; `code.py`: instructions as bytes (assembler and reader).
- `encode.py` (Program -> bytes), `decode.py` (bytes -> Program, or MalformedError),
  `verify.py` (Program -> `Verified`, or InvalidError; `load` = decode + verify: a runtime
  takes only a `Verified` program), `disasm.py` (the listing), `docs.py` (the generated parts
  of docs/bytecode.md).

This package depends on the format only: it does not import the IR. Codegen
(`scriptc.emit.codegen`) is the bridge from the IR.
"""

from scriptc.bytecode.container import FORMAT_VERSION, MAGIC
from scriptc.bytecode.decode import decode
from scriptc.bytecode.disasm import disassemble
from scriptc.bytecode.encode import encode
from scriptc.bytecode.errors import BytecodeError, InvalidError, MalformedError
from scriptc.bytecode.program import Program
from scriptc.bytecode.verify import Verified, load, verify

__all__ = [
    "FORMAT_VERSION",
    "MAGIC",
    "BytecodeError",
    "InvalidError",
    "MalformedError",
    "Program",
    "Verified",
    "decode",
    "disassemble",
    "encode",
    "load",
    "verify",
]
