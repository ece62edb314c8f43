"""The readable listing of a verified program (`scriptc dis`), like CPython's `dis`.

One line per rule message, goal, action, block and instruction. The left column is the source
position (`line:col`, or `@offset` when the program carries no line table), shown where the
span changes; then the code offset, `>>` on jump targets, the mnemonic and the operands
rendered by their kinds (constants by value, blocks by path and label, jumps by offset) through
each opcode's listing template. Depends on the format only.
"""

from __future__ import annotations

import json
import re

from scriptc.bytecode.code import instructions
from scriptc.bytecode.container import FORMAT_VERSION
from scriptc.bytecode.opcodes import BLOCK_KINDS, Opcode
from scriptc.bytecode.program import Program
from scriptc.language import NAME_PATTERN, SIGILS

__all__ = ["disassemble", "render_operands"]

# A name shown bare: a name of the language, perhaps after its sigil (`&` marks a field).
_PLAIN_NAME = re.compile(f"[{re.escape(''.join(SIGILS.values()))}&]?{NAME_PATTERN}\\Z")
_POSITION_WIDTH = 9


def _quote(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)


def _name(text: str) -> str:
    return text if _PLAIN_NAME.match(text) else _quote(text)


def _block_ref(program: Program, index: int) -> str:
    label = program.blocks[index].label
    path = program.block_path(index)
    return f"{path} ({_name(program.text(label))})" if label is not None else path


def _operand(program: Program, kind: str, value: int) -> str:
    if kind == "num":
        return program.text(value)
    if kind == "text":
        return _quote(program.text(value))
    if kind == "name":
        return _name(program.text(value))
    if kind == "const":
        c = program.constants[value]
        return _quote(c) if isinstance(c, str) else c.text
    if kind in ("scope", "cmp"):
        return chr(value)
    if kind == "block":
        return _block_ref(program, value)
    if kind == "jump":
        return f"-> {value}"
    return str(value)


def render_operands(program: Program, op: Opcode, operands: tuple[int, ...]) -> str:
    """The operands of one instruction as the listing shows them."""
    if not op.operands:
        return ""
    # the operands were unpacked by the opcode's own struct: one value per operand
    rendered = {o.name: _operand(program, o.kind.name, v)
                for o, v in zip(op.operands, operands, strict=True)}
    if op.listing:
        return op.listing.format(**rendered)
    return " ".join(rendered.values())


class _Positions:
    def __init__(self, program: Program) -> None:
        self.program = program

    def __call__(self, offset: int) -> str:
        position = self.program.position(offset)
        if position is None:
            return f"@{offset}"
        return f"{position[0]}:{position[1]}"


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _line(position: str, text: str) -> str:
    return f"{position:>{_POSITION_WIDTH}}  {text}".rstrip()


def disassemble(program: Program) -> str:
    """The listing of `program` (which must have passed `verify`)."""
    where = _Positions(program)
    out: list[str] = [
        f"; scriptc bytecode, format version {FORMAT_VERSION}",
        f"; activity {_name(program.activity)}"
        + (f", compiled from {_quote(program.text(program.source))}"
           if program.source is not None else ""),
        f"; {_count(len(program.constants), 'constant')}, {_count(len(program.goals), 'goal')}, "
        f"{_count(len(program.actions), 'action')}, {_count(len(program.blocks), 'block')}, "
        f"{_count(len(program.code), 'byte')} of code, "
        f"{_count(len(program.spans), 'code span')}"
        + ("" if program.lines else ", no line table"),
    ]
    if program.alfa or program.omega:
        out.append("")
    for which, messages in (("alfa", program.alfa), ("omega", program.omega)):
        for i, m in enumerate(messages):
            out.append(_line(where(m.span[0]),
                             f"{which} {i}  {_name(program.text(m.id))}  rulecode {m.rulecode}"
                             f"  in {_quote(program.text(m.intopic))}"
                             f"  out {_quote(program.text(m.outtopic))}"
                             f"  action {m.action}  mutex {m.mutex}"))
    spans = {s.code: s.start for s in program.spans}
    index = 0
    action_index = 0
    for g, goal in enumerate(program.goals):
        out.append("")
        out.append(_line(where(goal.span[0]), f"goal{g}  {_name(program.text(goal.id))}"))
        for a in range(goal.actions):
            action = program.actions[action_index]
            action_index += 1
            out.append(_line(where(action.span[0]), f"goal{g}/act{a}"))
            for _ in range(action.blocks):
                block = program.blocks[index]
                shown = where(block.span[0])
                out.append(_line(shown, f"{_block_ref(program, index)}  "
                                        f"{BLOCK_KINDS[block.kind]}"))
                listing = list(instructions(program.code, block.code, program.block_end(index)))
                targets = {ins.operands[i] for ins in listing
                           for i, o in enumerate(ins.opcode.operands) if o.kind.name == "jump"}
                for ins in listing:
                    # The position where the span changes, unless it reads the same.
                    start = spans.get(ins.offset)
                    position = ""
                    if start is not None and where(start) != shown:
                        position = shown = where(start)
                    marker = ">>" if ins.offset in targets else "  "
                    text = f"{marker} {ins.offset:>6}  {ins.opcode.name:<16}" + \
                        render_operands(program, ins.opcode, ins.operands)
                    out.append(_line(position, "  " + text))
                index += 1
    return "\n".join(out) + "\n"
