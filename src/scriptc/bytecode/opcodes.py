"""THE opcode table of the `.scb` bytecode: each instruction's number, mnemonic, operands,
stack effect, where it may appear and what it does.

Everything else derives from this table: the assembler that codegen drives and the decoder of
instruction streams (`code.py`), the verifier (`verify.py`), the listing (`disasm.py`) and the
opcode section of `docs/bytecode.md` (`docs.py`). An instruction is its opcode byte followed by
its operands, little-endian, at fixed widths given by the operand kinds, so the size of an
instruction depends on its opcode alone. (clox wrote its jump encoding in three places; here a
jump's encoding is the `jump` operand kind, once.)

Numbers are part of the format: an opcode keeps its number forever. A new instruction takes a
free number and bumps the format version (`layout.FORMAT_VERSION`).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

from scriptc.language import OPERATORS, SCOPES

__all__ = [
    "BLOCK_KINDS",
    "BY_CODE",
    "BY_NAME",
    "KINDS",
    "MAX_STACK",
    "OPCODES",
    "SEARCH_NONE",
    "Opcode",
    "Operand",
    "OperandKind",
]


# ---------------------------------------------------------------------------------------------
# Operand kinds: how an operand is stored and what the verifier demands of it.


@dataclass(frozen=True, slots=True)
class OperandKind:
    """How an operand is stored and what the verifier demands of it."""

    name: str
    fmt: str  # struct code: "B" (u8) or "I" (u32)
    doc: str
    # Letters (ASCII codes) an operand of this kind may hold, when it is a letter.
    letters: str = ""
    size: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", struct.calcsize("<" + self.fmt))


KINDS: dict[str, OperandKind] = {
    k.name: k
    for k in (
        OperandKind("u8", "B", "an unsigned byte"),
        OperandKind("u32", "I", "an unsigned 32-bit integer"),
        OperandKind("bit", "B", "a byte holding 0 or 1"),
        OperandKind("const", "I", "index of a constant of either kind (text or number)"),
        OperandKind("num", "I", "index of a number constant"),
        OperandKind("text", "I", "index of a text constant holding data (a path, a payload)"),
        OperandKind("name", "I", "index of a text constant holding a name (alias `?kid`, "
                                 "variable `@v`, attribute `$a`, field, class, function)"),
        OperandKind("scope", "B", "the ASCII code of a scope letter", letters="".join(SCOPES)),
        OperandKind("cmp", "B", "the ASCII code of a comparison: `=`, `<` or `>`",
                    letters="".join(op.removeprefix("OP") for op in OPERATORS)),
        OperandKind("block", "I", "index of a block in the block table"),
        OperandKind("jump", "I", "code offset of an instruction of the same block"),
    )
}


@dataclass(frozen=True, slots=True)
class Operand:
    """One operand of an opcode: its name and its kind."""

    name: str
    kind: OperandKind


# ---------------------------------------------------------------------------------------------
# Opcodes

# The kinds of blocks (their letters in the block table): instruction, jump, terminus, sensor.
BLOCK_KINDS = {"I": "instruction", "J": "jump", "T": "terminus", "S": "sensor"}

# The deepest the condition stack may grow. Conditions push at most one value per argument of
# a call plus one, and an argument count is a byte: 256 leaves no program out that codegen makes.
MAX_STACK = 256

# The search states the verifier tracks (docs/bytecode.md, "Conditions"): no search running,
# a search started by FIND with no candidate yet, a candidate in THIS.
SEARCH_NONE, SEARCH_STARTED, SEARCH_CANDIDATE = "none", "started", "candidate"


def _parse_stack(op: Opcode) -> tuple[tuple[str, ...], str | None, tuple[str, ...]]:
    if not op.stack:
        return (), None, ()
    left, _, right = op.stack.partition("->")
    pops: list[str] = []
    count: str | None = None
    for item in left.split():
        if "*" in item:
            kind, count = item.split("*")
            if count not in {o.name for o in op.operands}:
                raise AssertionError(f"{op.name}: stack count {count!r} is not an operand")
            pops.append(kind)
        else:
            pops.append(item)
    pushes = tuple(right.split())
    for t in (*pops, *pushes):
        if t not in ("v", "b"):
            raise AssertionError(f"{op.name}: unknown stack type {t!r}")
    return tuple(pops), count, pushes


@dataclass(frozen=True, eq=False)  # compared and hashed by identity: one object per opcode
class Opcode:
    """An instruction of the table: number, mnemonic, operands, stack effect, placement."""

    code: int
    name: str
    operands: tuple[Operand, ...]
    # Stack effect, `pops -> pushes`, left to right from deeper to the top. `v` is a value
    # (a number, a text, another field value, or missing), `b` a truth value; `v*argc` is as
    # many values as the operand `argc` says. "" is no effect.
    stack: str
    # The kinds of block whose code may hold the instruction (letters of BLOCK_KINDS).
    blocks: str
    doc: str
    # How the listing shows the operands (`str.format` over the rendered operands by name).
    listing: str = ""
    # Control: a terminator ends its block's code (nothing after it runs in this block).
    terminator: bool = False
    # The search state the instruction needs (None: any), and the one it leaves (None: same).
    search_in: tuple[str, ...] | None = None
    search_out: str | None = None
    # The stack must be empty when the instruction starts.
    empty_stack: bool = False

    # Derived from the fields above (__post_init__): the operand struct, the size of the
    # instruction, and the stack effect parsed (pop types, the operand counting them, pushes).
    struct: struct.Struct = field(init=False, repr=False, compare=False)
    size: int = field(init=False, repr=False, compare=False)
    pops: tuple[str, ...] = field(init=False, repr=False, compare=False)
    pop_count_operand: str | None = field(init=False, repr=False, compare=False)
    pushes: tuple[str, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        layout = struct.Struct("<" + "".join(o.kind.fmt for o in self.operands))
        object.__setattr__(self, "struct", layout)
        object.__setattr__(self, "size", 1 + layout.size)
        pops, count, pushes = _parse_stack(self)
        object.__setattr__(self, "pops", pops)
        object.__setattr__(self, "pop_count_operand", count)
        object.__setattr__(self, "pushes", pushes)


def _ops(*spec: str) -> tuple[Operand, ...]:
    """`"v_x:num"` -> Operand("v_x", KINDS["num"])."""
    out = []
    for item in spec:
        name, kind = item.split(":")
        out.append(Operand(name, KINDS[kind]))
    return tuple(out)


_NO_SEARCH = (SEARCH_NONE,)
_CANDIDATE = (SEARCH_CANDIDATE,)

OPCODES: tuple[Opcode, ...] = (
    # -- instruction blocks: build the pending block, then issue it ---------------------------
    Opcode(0x01, "MOVE", _ops("v_x:num", "v_y:num", "v_theta:num", "wait_t:u32", "duration:u32"),
           "", "I",
           "Append a move command to the move track of the pending block: body-frame speeds "
           "(m/s, m/s, rad/s), then the wait and the duration in ms.",
           "{v_x}, {v_y}, {v_theta}  wait {wait_t} for {duration}"),
    Opcode(0x02, "LED", _ops("r:num", "g:num", "b:num", "turnas:bit", "wait_t:u32",
                             "duration:u32"),
           "", "I",
           "Append an LED command to the led track of the pending block: colour channels in "
           "[0, 1], `turnas` (1 on, 0 off), then the wait and the duration in ms.",
           "{r}, {g}, {b}  turnas {turnas}  wait {wait_t} for {duration}"),
    Opcode(0x03, "AUDIO", _ops("track:text", "wait_t:u32", "duration:u32"), "", "I",
           "Append an audio command to the audioout track of the pending block: the track's "
           "path (`Silence` plays nothing), then the wait and the duration in ms.",
           "{track}  wait {wait_t} for {duration}"),
    Opcode(0x04, "ISSUE", (), "", "I",
           "The pending block is complete: stop reading blocks. The runtime issues it to the "
           "actuators (after the rules, which may change it) and resumes at the next "
           "instruction once the block is consumed. The pending block is then emptied."),
    # -- sensor blocks ---------------------------------------------------------------------------
    Opcode(0x05, "PAYLOAD", _ops("text:text"), "", "S",
           "Append a text to the payload of the pending sensor message.", "{text}"),
    Opcode(0x06, "SENSE", (), "", "S",
           "Send the sensor message with the payload gathered so far, then empty it."),
    # -- block transfers ---------------------------------------------------------------------------
    Opcode(0x07, "END", (), "", "T",
           "Terminus: the script ends.", terminator=True),
    Opcode(0x08, "GOTO", _ops("target:block"), "", "J",
           "Continue with the block `target` (a jump's true or false target).",
           "{target}", terminator=True, search_in=(SEARCH_NONE,), empty_stack=True),
    Opcode(0x09, "NEXT_BLOCK", (), "", "IJS",
           "Continue with the next block in order (a jump with no target, or the end of an "
           "instruction or sensor block); past the last block the script ends.",
           terminator=True, search_in=(SEARCH_NONE,), empty_stack=True),
    # -- conditions: control -----------------------------------------------------------------
    Opcode(0x10, "COND", _ops("fail:jump", "condition:text"), "", "J",
           "Start evaluating a condition: empty the stack, no search, and set the failure "
           "handler to `fail`, where the false exit starts. `condition` is the condition's "
           "canonical text (the `toparse` of the thesis JSON), which a runtime reports with "
           "the jump. Only the first instruction of a "
           "jump block. An instruction that *fails* empties the stack, ends the search and "
           "continues at `fail`.",
           "fail {fail}  {condition}"),
    Opcode(0x11, "JUMP_IF_FALSE", _ops("target:jump"), "b ->", "J",
           "Pop a truth value; if it is false, continue at `target`: forward outside a "
           "search, back to the search's NEXT_CANDIDATE inside one (the candidate is "
           "rejected).",
           "{target}"),
    # -- conditions: assignments -------------------------------------------------------------
    Opcode(0x18, "FIND", _ops("class:name", "alias:name", "scope:scope", "bind:jump"), "",
           "J",
           "Start the search of a CLASS assignment that binds `alias` to an entity of `class` "
           "for `scope`; its tests run between the NEXT_CANDIDATE that always follows and the "
           "BIND at `bind`.",
           "{class} {alias} {scope}  bind {bind}", search_in=(SEARCH_NONE,),
           search_out=SEARCH_STARTED, empty_stack=True),
    Opcode(0x19, "NEXT_CANDIDATE", (), "", "J",
           "Put the next candidate of the running search in THIS: first the entity the alias "
           "already names, if it is of the class; then, the alias released, the entities of "
           "the class free for the alias, oldest first (docs/bytecode.md, \"Searches\"). Fails "
           "when none is left.",
           search_in=(SEARCH_STARTED, SEARCH_CANDIDATE), search_out=SEARCH_CANDIDATE,
           empty_stack=True),
    Opcode(0x1A, "BIND", (), "", "J",
           "The candidate in THIS passed every test: bind the search's alias to it for the "
           "search's scope, and end the search.",
           search_in=_CANDIDATE, search_out=SEARCH_NONE),
    Opcode(0x1B, "SET_VAR", _ops("scope:scope", "var:name"), "v ->", "J",
           "Pop a value and assign it to the variable `var` for `scope`; fails when the value "
           "is missing (the F function gave none).",
           "{scope} {var}", search_in=_NO_SEARCH),
    Opcode(0x1C, "SET_ATT", _ops("scope:scope", "alias:name", "att:name"), "v ->", "J",
           "Pop a value and assign it to the attribute `att` of `alias` for `scope`; fails "
           "when the value is missing or the alias is not bound.",
           "{scope} {alias}>${att}", search_in=_NO_SEARCH),
    Opcode(0x1D, "BOUND", _ops("alias:name"), "", "J",
           "Fails when `alias` is not bound (an ATT assignment checks its alias before "
           "calling its function).",
           "{alias}", search_in=_NO_SEARCH),
    # -- conditions: values -------------------------------------------------------------------
    Opcode(0x20, "PUSH_CONST", _ops("value:const"), "-> v", "J",
           "Push a constant: a number's value or a text.", "{value}"),
    Opcode(0x21, "PUSH_VAR", _ops("var:name"), "-> v", "J",
           "Push the value of the variable `var` (missing if never assigned).", "{var}"),
    Opcode(0x22, "PUSH_ALIAS", _ops("alias:name"), "-> v", "J",
           "Push the id of the entity bound to `alias` (missing if not bound).", "{alias}"),
    Opcode(0x23, "PUSH_FIELD", _ops("alias:name", "field:name"), "-> v", "J",
           "Push the field `field` of the entity bound to `alias` (missing if the alias is "
           "not bound or the field not set).",
           "{alias}>&{field}"),
    Opcode(0x24, "PUSH_ATT", _ops("alias:name", "att:name"), "-> v", "J",
           "Push the attribute `att` of `alias` (missing if never assigned).",
           "{alias}>${att}"),
    Opcode(0x25, "PUSH_THIS", (), "-> v", "J",
           "Push the id of the candidate in THIS (`?THIS`).",
           search_in=_CANDIDATE),
    Opcode(0x26, "PUSH_THIS_FIELD", _ops("field:name"), "-> v", "J",
           "Push the field `field` of the candidate (`?THIS>&field`; missing if not set).",
           "?THIS>&{field}", search_in=_CANDIDATE),
    Opcode(0x28, "COMPARE", _ops("op:cmp"), "v v -> b", "J",
           "Pop the right value, then the left; push whether `left OPop right` holds: as "
           "numbers when both are numbers, else as texts; false when either is missing.",
           "OP{op}"),
    Opcode(0x29, "CALL_B", _ops("function:name", "argc:u8"), "v*argc -> b", "J",
           "Call the B function `function` about the candidate in THIS with `argc` arguments "
           "(popped; the deepest is the first); push its truth value (false if it fails).",
           "{function}/{argc}", search_in=_CANDIDATE),
    Opcode(0x2A, "CALL_F", _ops("function:name", "argc:u8"), "v*argc -> v", "J",
           "Call the F function `function` with `argc` arguments; push the text it returns "
           "(missing if it gives none or fails).",
           "{function}/{argc}", search_in=_NO_SEARCH),
    Opcode(0x2B, "CALL_E", _ops("function:name", "argc:u8"), "v*argc -> b", "J",
           "Call the E function `function` with `argc` arguments; push its truth value "
           "(false if it fails).",
           "{function}/{argc}", search_in=_NO_SEARCH),
)

BY_CODE: dict[int, Opcode] = {op.code: op for op in OPCODES}
BY_NAME: dict[str, Opcode] = {op.name: op for op in OPCODES}

def _check_table() -> None:
    for op in OPCODES:
        if not 0 < op.code < 256:
            raise AssertionError(f"{op.name}: opcode out of range")
        if set(op.blocks) - set(BLOCK_KINDS):
            raise AssertionError(f"{op.name}: unknown block kind")
    if len(BY_CODE) != len(OPCODES) or len(BY_NAME) != len(OPCODES):
        raise AssertionError("opcode numbers and names must be unique")


_check_table()
