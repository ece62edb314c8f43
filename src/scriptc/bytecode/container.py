"""The byte layout of a `.scb` file: the header, the section table and the fixed-size records
of each section, declared once as data.

`encode.py` and `decode.py` pack and unpack with the structs derived here, and `docs.py`
renders these declarations as the tables of docs/bytecode.md ("Every byte"). All integers are
little-endian; there is no padding.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from scriptc.language import MUTEXES, RULE_ACTIONS

__all__ = [
    "ACTION",
    "BLOCK",
    "BLOCK_COUNTS",
    "COLUMN_TYPES",
    "FORMAT_VERSION",
    "GOAL",
    "HEADER",
    "MAGIC",
    "MESSAGE",
    "NONE",
    "NUMBER_TAG",
    "RECORDS",
    "SCRIPT_HEAD",
    "SECTIONS",
    "SECTION_ENTRY",
    "SECTION_NAMES",
    "SPANS_HEAD",
    "TEXT_TAG",
    "Record",
]

MAGIC = b"SCB\x00"
# Bumped whenever a byte of the format changes meaning (a new opcode included). A reader
# refuses every version but its own: the remedy is always to compile the script again.
FORMAT_VERSION = 2
# The u32 written where an optional index (a label, the source name) is absent.
NONE = 0xFFFF_FFFF

# Constant tags.
TEXT_TAG = 1
NUMBER_TAG = 2

_TYPES = {"B": "u8", "H": "u16", "I": "u32", "d": "f64", "4s": "4 bytes"}


@dataclass(frozen=True)
class Record:
    """A fixed-size record: its fields in order, each `(name, struct code, meaning)`."""

    name: str
    fields: tuple[tuple[str, str, str], ...]
    doc: str

    @property
    def struct(self) -> struct.Struct:
        return struct.Struct("<" + "".join(f for _, f, _ in self.fields))

    @property
    def size(self) -> int:
        return self.struct.size

    def rows(self) -> list[tuple[int, int, str, str, str]]:
        """(offset, size, type, name, meaning) of each field, for the documentation."""
        out = []
        offset = 0
        for name, fmt, doc in self.fields:
            size = struct.calcsize("<" + fmt)
            out.append((offset, size, _TYPES[fmt], name, doc))
            offset += size
        return out


HEADER = Record("header", (
    ("magic", "4s", '`SCB\\0` (53 43 42 00)'),
    ("version", "H", f"format version: {FORMAT_VERSION}"),
    ("flags", "H", "0 (every flag is reserved: a set bit is refused)"),
    ("length", "I", "number of bytes after the header (the file is 16 + length bytes)"),
    ("crc32", "I", "CRC-32 (zlib.crc32, the one of zip and PNG) of those bytes"),
), "The first 16 bytes of the file.")

SECTION_ENTRY = Record("section entry", (
    ("id", "H", "section id (table below)"),
    ("offset", "I", "offset of the section from the start of the file"),
    ("length", "I", "length of the section in bytes"),
), "After the header: a u16 count (always 5), then one entry per section. The sections follow "
   "the table in id order, back to back, and the last one ends the file.")

# Section ids and names, in the order they appear.
SECTIONS: dict[int, str] = {1: "constants", 2: "script", 3: "blocks", 4: "code", 5: "spans"}
SECTION_NAMES = {name: i for i, name in SECTIONS.items()}

SCRIPT_HEAD = Record("script head", (
    ("name", "I", "the activity name (text constant)"),
    ("source", "I", "the source file's name (text constant), or FFFFFFFF"),
    ("alfa", "I", "number of alfa messages"),
    ("omega", "I", "number of omega messages"),
), "The start of the script section; then `alfa + omega` message records, alfa first.")

MESSAGE = Record("message", (
    ("rulecode", "I", "what the rule does"),
    ("id", "I", "the rule's id (text constant)"),
    ("intopic", "I", "input topic (text constant)"),
    ("outtopic", "I", "output topic (text constant)"),
    ("action", "B", f"ASCII code of the action letter: {' '.join(RULE_ACTIONS)}"),
    ("mutex", "B", f"ASCII code of the mutex letter: {' '.join(MUTEXES)}"),
    ("start", "I", "source span: first character (offset in code points)"),
    ("end", "I", "source span: end (exclusive)"),
), "One alfa or omega rule message (thesis table 3.1).")

BLOCK_COUNTS = Record("block counts", (
    ("goals", "I", "number of goal records"),
    ("actions", "I", "number of action records (all goals)"),
    ("blocks", "I", "number of block records (all actions)"),
), "The start of the blocks section; then the goal, action and block records.")

GOAL = Record("goal", (
    ("id", "I", "the goal id (text constant)"),
    ("actions", "I", "how many of the next action records are this goal's"),
    ("start", "I", "source span of the `[goal:ID]` item"),
    ("end", "I", "end of that span (exclusive)"),
), "Goals in order; goal g owns the action records after those of goals 0..g-1.")

ACTION = Record("action", (
    ("blocks", "I", "how many of the next block records are this action's"),
    ("start", "I", "source span of the `[action]` item"),
    ("end", "I", "end of that span (exclusive)"),
), "Actions in order, likewise owning consecutive blocks.")

BLOCK = Record("block", (
    ("kind", "B", "ASCII letter: `I` instruction, `J` jump, `T` terminus, `S` sensor"),
    ("label", "I", "the block's label (text constant), or FFFFFFFF"),
    ("code", "I", "offset of the block's first instruction in the code section"),
    ("start", "I", "source span of the block"),
    ("end", "I", "end of that span (exclusive)"),
), "Blocks in execution order (the order of the source). A block's code runs from its `code` "
   "offset to the next block's (the last one to the end of the code section).")

SPANS_HEAD = Record("spans head", (
    ("lines", "I", "number of entries of the line table (0: compiled without the source)"),
    ("spans", "I", "number of entries of the code span table"),
    ("line_width", "B", "bytes per line-table delta: 1, 2 or 4 (unsigned)"),
    ("code_width", "B", "bytes per code-offset delta: 1, 2 or 4 (unsigned)"),
    ("start_width", "B", "bytes per span-start delta: 1, 2 or 4 (signed)"),
    ("length_width", "B", "bytes per span length: 1, 2 or 4 (unsigned)"),
), "The start of the spans section; then four columns of little-endian integers, each as "
   "wide as the head says (the encoder picks the narrowest that holds every value): `lines` "
   "line-table deltas, then `spans` code-offset deltas, `spans` span-start deltas and `spans` "
   "span lengths. A delta is the difference from the previous entry's value (the first "
   "entry's from 0).")

# The integer types a spans column may use, by width: (unsigned, signed) struct codes.
COLUMN_TYPES = {1: ("B", "b"), 2: ("H", "h"), 4: ("I", "i")}

RECORDS: tuple[Record, ...] = (HEADER, SECTION_ENTRY, SCRIPT_HEAD, MESSAGE, BLOCK_COUNTS, GOAL,
                               ACTION, BLOCK, SPANS_HEAD)
