"""Is a well-formed program safe to run? `verify(program)` returns it `Verified` or raises
InvalidError; `load(data)` decodes and verifies. A runtime takes only a `Verified` program,
which only `verify` makes: whether a program comes from a `.scb` file (`load`) or straight from
codegen in memory (`verify(codegen(...))`, what `scriptc run` does with a script), it runs only
once the checks below have passed.

What a verified program guarantees a VM (docs/bytecode.md, "Verification"):

- every constant, block and text index is in range and of the right kind; every number is
  finite; every letter (scope, comparison, rule action, mutex, block kind) is one the format
  knows;
- the goal, action and block tables agree with each other and with the code: blocks cover the
  code in order, back to back, and each block's code is made of whole instructions of known
  opcodes that its kind allows, in the shape its kind requires;
- in a jump block, every path from COND ends at GOTO or NEXT_BLOCK with an empty stack and no
  search running; the stack never underflows, never exceeds MAX_STACK, and holds the types each
  instruction pops; ?THIS and B functions are used only while a candidate is in THIS; jumps stay
  in their block and land on instructions; the only backward jumps return to the
  NEXT_CANDIDATE of the running search, so every condition terminates;
- the span and line tables are ordered and point at instructions.

The checks are linear in the size of the program.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from scriptc.bytecode.code import Instruction
from scriptc.bytecode.decode import decode
from scriptc.bytecode.errors import InvalidError
from scriptc.bytecode.opcodes import (
    BLOCK_KINDS,
    BY_CODE,
    BY_NAME,
    KINDS,
    MAX_STACK,
    SEARCH_CANDIDATE,
    SEARCH_NONE,
    SEARCH_STARTED,
    Opcode,
)
from scriptc.bytecode.program import Num, Program
from scriptc.gcpause import gc_paused
from scriptc.language import MUTEXES, RULE_ACTIONS

__all__ = ["Verified", "load", "verify"]

_TEXT, _NUMBER = 1, 2
_ACTIONS = "".join(RULE_ACTIONS)
_MUTEXES = "".join(MUTEXES)

_COND = BY_NAME["COND"]
_FIND = BY_NAME["FIND"]
_NEXT_CANDIDATE = BY_NAME["NEXT_CANDIDATE"]
_BIND = BY_NAME["BIND"]
_JUMP_IF_FALSE = BY_NAME["JUMP_IF_FALSE"]
_ISSUE = BY_NAME["ISSUE"]
_SENSE = BY_NAME["SENSE"]
_NEXT_BLOCK = BY_NAME["NEXT_BLOCK"]
_END = BY_NAME["END"]

_LETTERS = {name: frozenset(ord(c) for c in kind.letters)
            for name, kind in KINDS.items() if kind.letters}


_VERIFIER = object()  # the key only `verify` holds: see Verified


class Verified:
    """A program that passed `verify` (the guarantees of the module's docstring), with the
    instructions of each block as the verifier decoded them, in code order: what a runtime
    takes, so that it never decodes the code again. Only `verify` makes one."""

    __slots__ = ("instructions", "program")

    def __init__(self, program: Program, instructions: list[list[Instruction]],
                 key: object = None) -> None:
        if key is not _VERIFIER:
            raise TypeError("a Verified program comes from bytecode.verify (or load)")
        self.program = program
        self.instructions = instructions


def load(data: bytes) -> Verified:
    """Decode and verify: a program safe to run, or MalformedError / InvalidError."""
    # Decoding a large program builds many small acyclic objects: the cyclic collector's
    # scans would only add time (scriptc/gcpause.py).
    with gc_paused():
        return verify(decode(data))


def verify(program: Program) -> Verified:
    """The program, verified; InvalidError when it must not run (see the module's
    docstring)."""
    kinds = _constants(program)
    _tables(program, kinds)
    starts, instructions = _code(program, kinds)
    _spans(program, starts)
    return Verified(program, instructions, _VERIFIER)


# ---------------------------------------------------------------------------------------------
# Constants and tables


def _constants(program: Program) -> bytearray:
    kinds = bytearray(len(program.constants))
    for i, c in enumerate(program.constants):
        if isinstance(c, str):
            kinds[i] = _TEXT
        elif isinstance(c, Num):
            if not math.isfinite(c.value):
                raise InvalidError(f"constant {i} is not a finite number")
            try:
                written = float(c.text)
            except ValueError:
                raise InvalidError(f"constant {i}: the text {c.text!r} of a number constant "
                                   "is not a number") from None
            if written != c.value:
                raise InvalidError(f"constant {i}: the number {c.value!r} does not match its "
                                   f"text {c.text!r}")
            kinds[i] = _NUMBER
        else:
            raise InvalidError(f"constant {i} is neither a text nor a number")
    return kinds


def _text(kinds: bytearray, index: int | None, what: str, optional: bool = False) -> None:
    if index is None and optional:
        return
    if index is None or not 0 <= index < len(kinds):
        raise InvalidError(f"{what}: constant index {index} out of range "
                           f"({len(kinds)} constants)")
    if kinds[index] != _TEXT:
        raise InvalidError(f"{what}: constant {index} is a number, not a text")


def _span(span: tuple[int, int], what: str) -> None:
    if span[0] > span[1]:
        raise InvalidError(f"{what}: its source span ends ({span[1]}) before it starts "
                           f"({span[0]})")


def _tables(program: Program, kinds: bytearray) -> None:
    _text(kinds, program.name, "the activity name")
    _text(kinds, program.source, "the source name", optional=True)
    for which, messages in (("alfa", program.alfa), ("omega", program.omega)):
        for i, m in enumerate(messages):
            what = f"{which} message {i}"
            if not 0 <= m.rulecode <= 0xFFFF_FFFF:
                raise InvalidError(f"{what}: rulecode {m.rulecode} is not a u32")
            for index in (m.id, m.intopic, m.outtopic):
                _text(kinds, index, what)
            if m.action not in _ACTIONS or len(m.action) != 1:
                raise InvalidError(f"{what}: unknown rule action {m.action!r} (expected one "
                                   f"of {', '.join(_ACTIONS)})")
            if m.mutex not in _MUTEXES or len(m.mutex) != 1:
                raise InvalidError(f"{what}: unknown mutex command {m.mutex!r} (expected one "
                                   f"of {', '.join(_MUTEXES)})")
            _span(m.span, what)
    for g, goal in enumerate(program.goals):
        _text(kinds, goal.id, f"goal {g}")
        _span(goal.span, f"goal {g}")
    owned = sum(goal.actions for goal in program.goals)
    if owned != len(program.actions):
        raise InvalidError(f"the goals own {owned} actions, but the table holds "
                           f"{len(program.actions)}")
    for a, action in enumerate(program.actions):
        _span(action.span, f"action {a}")
    owned = sum(action.blocks for action in program.actions)
    if owned != len(program.blocks):
        raise InvalidError(f"the actions own {owned} blocks, but the table holds "
                           f"{len(program.blocks)}")
    previous = -1
    n_code = len(program.code)
    for i, block in enumerate(program.blocks):
        what = f"block {i}"
        if block.kind not in BLOCK_KINDS or len(block.kind) != 1:
            raise InvalidError(f"{what}: unknown block kind {block.kind!r}")
        _text(kinds, block.label, f"{what}'s label", optional=True)
        _span(block.span, what)
        if i == 0 and block.code != 0:
            raise InvalidError(f"the first block's code starts at {block.code}, not 0")
        if block.code <= previous:
            raise InvalidError(f"{what}'s code starts at {block.code}, not after block "
                               f"{i - 1}'s ({previous}): blocks are in code order and not empty")
        if block.code >= n_code:
            raise InvalidError(f"{what}'s code starts at {block.code}, past the end of the "
                               f"code ({n_code} bytes)")
        previous = block.code
    if not program.blocks and n_code:
        raise InvalidError(f"{n_code} bytes of code belong to no block")


def _spans(program: Program, starts: set[int]) -> None:
    previous = -1
    for i, line in enumerate(program.lines):
        if (i == 0 and line != 0) or line <= previous:
            raise InvalidError(f"the line table is not increasing from 0 (line {i + 1} "
                               f"starts at {line})")
        previous = line
    spans = program.spans
    if spans and spans[0].code != 0:
        raise InvalidError(f"the first code span starts at code offset {spans[0].code}, not 0")
    previous = -1
    for i, (code, start, end) in enumerate(spans):
        if (code <= previous or code not in starts
                or not 0 <= start <= end):
            if start < 0:
                raise InvalidError(f"code span {i} starts at a negative source offset "
                                   f"({start})")
            if code <= previous:
                raise InvalidError(f"code span {i} is out of order (code offset {code})")
            if code not in starts:
                raise InvalidError(f"code span {i} points at code offset {code}, which is "
                                   "not the start of an instruction")
            _span((start, end), f"code span {i}")
        previous = code


# ---------------------------------------------------------------------------------------------
# Code


# Operand checks, by kind (plain integers need none).
_C_CONST, _C_NUM, _C_TEXT, _C_BLOCK, _C_JUMP, _C_BIT, _C_LETTER = range(7)
_CHECK_OF_KIND = {"const": _C_CONST, "num": _C_NUM, "text": _C_TEXT, "name": _C_TEXT,
                  "block": _C_BLOCK, "jump": _C_JUMP, "bit": _C_BIT, "scope": _C_LETTER,
                  "cmp": _C_LETTER}
# Per opcode byte: (opcode, size, unpack_from, checks, block kinds); checks are
# (operand position, check, letters allowed, operand kind name). `unpack_from` is struct's,
# whose values are untyped (the operands: integers).
_Check = tuple[int, int, frozenset[int], str]
_Decoder = tuple[Opcode, int, Callable[[bytes, int], tuple[Any, ...]], tuple[_Check, ...], str]
_DECODE: list[_Decoder | None] = [None] * 256
for _op in BY_CODE.values():
    _DECODE[_op.code] = (
        _op, _op.size, _op.struct.unpack_from,
        tuple((i, _CHECK_OF_KIND[o.kind.name], _LETTERS.get(o.kind.name, frozenset()),
               o.kind.name)
              for i, o in enumerate(_op.operands) if o.kind.name in _CHECK_OF_KIND),
        _op.blocks,
    )


def _code(program: Program, kinds: bytearray) -> tuple[set[int], list[list[Instruction]]]:
    """Check every block's code; return the set of instruction offsets and each block's
    instructions."""
    code = program.code
    blocks = program.blocks
    n_blocks = len(blocks)
    n_constants = len(kinds)
    starts: set[int] = set()
    add = starts.add
    decode_table = _DECODE
    new = tuple.__new__  # Instruction(...) without the named tuple's Python-level __new__
    listings: list[list[Instruction]] = []
    for index, block in enumerate(blocks):
        start = block.code
        end = blocks[index + 1].code if index + 1 < n_blocks else len(code)
        kind = block.kind
        listing: list[Instruction] = []
        offset = start
        while offset < end:
            entry = decode_table[code[offset]]
            if entry is None:
                raise _fault(program, index, f"unknown opcode 0x{code[offset]:02x}", offset)
            op, size, unpack_from, checks, allowed = entry
            following = offset + size
            if following > end:
                raise _fault(program, index, f"{op.name} needs {size} bytes, the block "
                                             f"ends after {end - offset}", offset)
            if kind not in allowed:
                raise _fault(program, index, f"{op.name} cannot appear in "
                                             f"{_a(BLOCK_KINDS.get(kind, kind))} block", offset)
            operands = unpack_from(code, offset + 1)
            for position, check, letters, kind_name in checks:
                value = operands[position]
                if check <= _C_TEXT:
                    if value >= n_constants:
                        raise _fault(program, index, f"{op.name}: constant index {value} out "
                                                     f"of range ({n_constants} constants)",
                                     offset)
                    if check == _C_NUM:
                        if kinds[value] != _NUMBER:
                            raise _fault(program, index, f"{op.name}: constant {value} is a "
                                                         "text, not a number", offset)
                    elif check == _C_TEXT and kinds[value] != _TEXT:
                        raise _fault(program, index, f"{op.name}: constant {value} is a "
                                                     "number, not a text", offset)
                elif check == _C_BLOCK:
                    if value >= n_blocks:
                        raise _fault(program, index, f"{op.name}: block {value} out of range "
                                                     f"({n_blocks} blocks)", offset)
                elif check == _C_JUMP:
                    if not start <= value < end:
                        raise _fault(program, index, f"{op.name}: jump to code offset "
                                                     f"{value}, outside its block "
                                                     f"({start}..{end - 1})", offset)
                elif check == _C_BIT:
                    if value > 1:
                        raise _fault(program, index, f"{op.name}: {value} is not 0 or 1",
                                     offset)
                elif value not in letters:
                    raise _fault(program, index, f"{op.name}: {_show_byte(value)} is not a "
                                                 f"{kind_name} letter "
                                                 f"({KINDS[kind_name].letters})", offset)
            listing.append(new(Instruction, (offset, op, operands, following)))
            add(offset)
            offset = following
        # `listing` holds one instruction at least: `_tables` made every block's code
        # non-empty (each block starts after the one before, and before the code's end).
        if kind == "J":
            _flow(program, index, listing)
        else:
            _shape(program, index, kind, listing)
        listings.append(listing)
    return starts, listings


def _a(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


def _show_byte(value: int) -> str:
    return repr(chr(value)) if 32 <= value < 127 else f"0x{value:02x}"


def _fault(program: Program, index: int, message: str, offset: int) -> InvalidError:
    """A refusal in block `index`, named by its path (the tables agree by now: `_tables`)."""
    return InvalidError(f"{program.block_path(index)}: {message}", offset)


# The straight-line shapes of the other kinds: what comes before the last two instructions
# (any number of it), then the last two.
_SHAPES = {
    "I": (frozenset(("MOVE", "LED", "AUDIO")), (_ISSUE, _NEXT_BLOCK)),
    "S": (frozenset(("PAYLOAD",)), (_SENSE, _NEXT_BLOCK)),
    "T": (frozenset(), (_END,)),
}


def _shape(program: Program, index: int, kind: str, listing: list[Instruction]) -> None:
    body, tail = _SHAPES[kind]
    n = len(tail)
    if len(listing) < n or tuple(ins[1] for ins in listing[-n:]) != tail:
        expected = " ".join(op.name for op in tail)
        raise _fault(program, index, f"{_a(BLOCK_KINDS[kind])} block must end with {expected}",
                     listing[-1][0])
    for offset, op, _operands, _end in listing[:-n]:
        if op.name not in body:
            raise _fault(program, index, f"{op.name} cannot come before {tail[0].name} in "
                                         f"{_a(BLOCK_KINDS[kind])} block", offset)


def _search_name(search: int, candidate: bool) -> str:
    if search < 0:
        return SEARCH_NONE
    return SEARCH_CANDIDATE if candidate else SEARCH_STARTED


_SEARCH_FAULTS = {
    SEARCH_NONE: "no search is running",
    SEARCH_STARTED: "the search has no candidate yet",
    SEARCH_CANDIDATE: "a search is still running",
}


# Per opcode: what the flow analysis needs (see _flow): pops, the position of the operand
# that counts them (-1: none), pushes, search_in, search_out, empty_stack, terminator.
_FlowFacts = tuple[tuple[str, ...], int, tuple[str, ...], tuple[str, ...] | None, str | None,
                   bool, bool]
_FLOW: dict[Opcode, _FlowFacts] = {}
# A state of the flow analysis: (stack types, search FIND offset or -1, candidate in THIS).
_FlowState = tuple[tuple[str, ...], int, bool]
for _op in BY_CODE.values():
    _count = _op.pop_count_operand
    _FLOW[_op] = (
        _op.pops,
        [o.name for o in _op.operands].index(_count) if _count is not None else -1,
        _op.pushes,
        _op.search_in,
        _op.search_out,
        _op.empty_stack,
        _op.terminator,
    )


def _flow(program: Program, index: int, listing: list[Instruction]) -> None:
    """Abstract interpretation of a jump block's condition: at each instruction, the types
    on the stack and the running search (the offset of its FIND, -1 for none, and whether a
    candidate is in THIS). Paths that meet must agree, except that NEXT_CANDIDATE forgets
    whether a candidate was there."""
    first_offset, first_op = listing[0][0], listing[0][1]
    if first_op is not _COND:
        raise _fault(program, index, "a jump block must start with COND", first_offset)
    at = {ins[0]: ins for ins in listing}
    # A state: (stack types, search FIND offset or -1, candidate in THIS).
    empty: _FlowState = ((), -1, False)
    states: dict[int, _FlowState] = {first_offset: empty}
    work: list[int] = [first_offset]
    find_size = _FIND.size
    block_end = listing[-1][3]

    def enter(target: int, state: _FlowState, source_offset: int, source_name: str) -> None:
        ins = at.get(target)
        if ins is None:
            raise _fault(program, index, f"{source_name}: code offset {target} is not the "
                                         "start of an instruction", source_offset)
        if ins[1] is _NEXT_CANDIDATE:
            state = (state[0], state[1], False)
        old = states.get(target)
        if old is None:
            states[target] = state
            work.append(target)
        elif old != state:
            raise _fault(program, index, f"paths meet at code offset {target} with different "
                                         f"stacks or searches ({_show(old)} and "
                                         f"{_show(state)})", source_offset)

    while work:
        offset, op, operands, following = at[work.pop()]
        stack, search, candidate = states[offset]
        pops, count_position, pushes, search_in, search_out, empty_stack, terminator = _FLOW[op]
        if op is _COND and offset != first_offset:
            raise _fault(program, index, "COND may only start a jump block", offset)
        if search_in is not None:
            now = _search_name(search, candidate)
            if now not in search_in:
                needs = " or ".join(_SEARCH_NEEDS[s] for s in search_in)
                raise _fault(program, index, f"{op.name} needs {needs}, but "
                                             f"{_SEARCH_FAULTS[now]}", offset)
        if empty_stack and stack:
            raise _fault(program, index, f"{op.name} needs an empty stack, it holds "
                                         f"{len(stack)} values", offset)
        if count_position >= 0:
            pops = pops * operands[count_position]
        if pops:
            n = len(pops)
            if len(stack) < n:
                raise _fault(program, index, f"stack underflow: {op.name} pops {n} values, "
                                             f"the stack holds {len(stack)}", offset)
            got = stack[len(stack) - n:]
            if got != pops:
                raise _fault(program, index, f"{op.name} pops {_types(pops)}, the stack holds "
                                             f"{_types(got)}", offset)
            stack = stack[:len(stack) - n]
        if pushes:
            stack = stack + pushes
            if len(stack) > MAX_STACK:
                raise _fault(program, index, f"stack overflow: more than {MAX_STACK} values",
                             offset)
        if op is _FIND:
            nxt = at.get(following)
            if nxt is None or nxt[1] is not _NEXT_CANDIDATE:
                raise _fault(program, index, "FIND must be followed by NEXT_CANDIDATE", offset)
            bind = at.get(operands[3])
            if bind is None or bind[1] is not _BIND or bind[0] <= offset:
                raise _fault(program, index, f"FIND names code offset {operands[3]} as its "
                                             "BIND, which is not a BIND after it", offset)
            search, candidate = offset, False
        elif op is _NEXT_CANDIDATE:
            if search + find_size != offset:
                raise _fault(program, index, "NEXT_CANDIDATE must follow the FIND of the "
                                             "running search", offset)
            candidate = True
        elif op is _BIND and at[search][2][3] != offset:
            raise _fault(program, index, f"BIND ends the search of the FIND at {search}, "
                                         "which names another BIND", offset)
        if search_out == SEARCH_NONE:  # BIND: the search is over
            search, candidate = -1, False
        state = (stack, search, candidate)
        if op is _COND:
            target = operands[0]
            if target <= offset:
                raise _fault(program, index, "COND's handler must come after it", offset)
            enter(target, empty, offset, op.name)
        elif op is _JUMP_IF_FALSE:
            target = operands[0]
            if search >= 0:
                if target != search + find_size:
                    raise _fault(program, index, "inside a search, a jump may only return to "
                                                 "the search's NEXT_CANDIDATE", offset)
            elif target <= offset:
                raise _fault(program, index, "a backward jump may only return to the "
                                             "NEXT_CANDIDATE of the running search", offset)
            enter(target, state, offset, op.name)
        if not terminator:
            if following >= block_end:
                raise _fault(program, index, f"{op.name} is the last instruction: execution "
                                             "would run past the end of the block", offset)
            enter(following, state, offset, op.name)


_SEARCH_NEEDS = {
    SEARCH_NONE: "no search running",
    SEARCH_STARTED: "a search started by FIND",
    SEARCH_CANDIDATE: "a candidate in THIS",
}


def _types(types: tuple[str, ...]) -> str:
    return "[" + " ".join(types) + "]"


def _show(state: _FlowState) -> str:
    stack, search, candidate = state
    return f"stack {_types(stack)}, search {_search_name(search, candidate)}"
