"""The generated parts of docs/bytecode.md: the record layouts (from `container.py`), the operand
kinds and the opcode table (from `opcodes.py`).

The prose of docs/bytecode.md is written by hand; each generated part sits between a pair of
markers, `<!-- generated: NAME -->` and `<!-- end: NAME -->`, and `python -m scriptc.generate`
rewrites what is between them from `GENERATED` (tests/test_generated.py fails when the file is
stale).
"""

from __future__ import annotations

from scriptc.bytecode import container as L
from scriptc.bytecode.opcodes import (
    BLOCK_KINDS,
    KINDS,
    MAX_STACK,
    OPCODES,
    SEARCH_CANDIDATE,
    SEARCH_NONE,
    SEARCH_STARTED,
    Opcode,
)

__all__ = ["GENERATED", "render_kinds", "render_layout", "render_opcodes"]


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _record(record: L.Record) -> str:
    lines = [f"**{record.name}** ({record.size} bytes). {record.doc}", "",
             "| Offset | Size | Type | Field | Meaning |", "|---:|---:|---|---|---|"]
    for offset, size, type_, name, doc in record.rows():
        lines.append(f"| {offset} | {size} | {type_} | `{name}` | {_cell(doc)} |")
    return "\n".join(lines)


def render_layout() -> str:
    """The fixed-size records of the file."""
    parts = [_record(r) for r in L.RECORDS]
    sections = ["| Id | Section |", "|---:|---|"]
    sections += [f"| {i} | {name} |" for i, name in L.SECTIONS.items()]
    return "\n\n".join([*parts[:2], "Section ids, in file order:\n\n" + "\n".join(sections),
                        *parts[2:]])


def render_kinds() -> str:
    """The operand kinds."""
    lines = ["| Kind | Bytes | Holds | The verifier requires |", "|---|---:|---|---|"]
    requires = {
        "u8": "", "u32": "", "bit": "0 or 1",
        "const": "an index below the number of constants",
        "num": "the index of a number constant",
        "text": "the index of a text constant",
        "name": "the index of a text constant",
        "block": "an index below the number of blocks",
        "jump": "the offset of an instruction of the same block (see Verification)",
    }
    for kind in KINDS.values():
        need = requires.get(kind.name) or (
            "one of " + ", ".join(f"`{c}`" for c in kind.letters) if kind.letters else "")
        lines.append(f"| `{kind.name}` | {kind.size} | {_cell(kind.doc)} | {_cell(need)} |")
    return "\n".join(lines)


def _operands(op: Opcode) -> str:
    if not op.operands:
        return ""
    return ", ".join(f"`{o.name}`:{o.kind.name}" for o in op.operands)


_SEARCH_WORDS = {SEARCH_NONE: "no search", SEARCH_STARTED: "a search started",
                 SEARCH_CANDIDATE: "a candidate"}


def _search(op: Opcode) -> str:
    parts = []
    if op.search_in is not None:
        parts.append("needs " + " or ".join(_SEARCH_WORDS[s] for s in op.search_in))
    if op.search_out is not None:
        parts.append("leaves " + _SEARCH_WORDS[op.search_out])
    if op.empty_stack:
        parts.append("empty stack")
    if op.terminator:
        parts.append("ends the block")
    return "; ".join(parts)


def render_opcodes() -> str:
    """The opcode table."""
    lines = [
        (f"Stack effects read `pops -> pushes`, deepest first; `v` is a value, `b` a truth "
         f"value, `v*argc` as many values as the operand `argc`. The stack never holds more "
         f"than {MAX_STACK} values. *In* lists the block kinds whose code may hold the "
         f"instruction ({', '.join(f'`{k}` {v}' for k, v in BLOCK_KINDS.items())})."),
        "",
        "| Code | Mnemonic | Size | Operands | Stack | In | Control, search | Meaning |",
        "|---|---|---:|---|---|---|---|---|",
    ]
    for op in OPCODES:
        lines.append(
            f"| `0x{op.code:02x}` | `{op.name}` | {op.size} | {_operands(op)} | "
            f"{'`' + op.stack + '`' if op.stack else ''} | {op.blocks} | {_search(op)} | "
            f"{_cell(op.doc)} |"
        )
    return "\n".join(lines)


GENERATED = {"layout": render_layout, "kinds": render_kinds, "opcodes": render_opcodes}
