"""The bytecode: round trips, one test per kind of refusal (each says whether it expects a
malformed or an invalid program), codegen's shapes and the generated docs. The golden listings
are case files (the `listing` aspect of tests/harness/)."""

from __future__ import annotations

import dataclasses
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import pytest
from harness import CASES

from scriptc.analysis.analyze import analyze_file, analyze_script
from scriptc.bytecode import (
    FORMAT_VERSION,
    InvalidError,
    MalformedError,
    Verified,
    decode,
    disassemble,
    encode,
    load,
    verify,
)
from scriptc.bytecode.code import Assembler, JumpTarget, instructions
from scriptc.bytecode.opcodes import BY_NAME, MAX_STACK, OPCODES
from scriptc.bytecode.program import ActionRecord, BlockRecord, CodeSpan, GoalRecord, Num, Program
from scriptc.emit.codegen import CodegenError, codegen
from scriptc.language import MUTEXES, RULE_ACTIONS
from scriptc.ops.build import emit
from scriptc.source import SourceFile, Span

ROOT = Path(__file__).parent.parent
BYTECODE_CASES = CASES / "bytecode"
EXAMPLE = ROOT / "examples" / "test_act.script"


def compiled(path: Path) -> Program:
    analysis = analyze_file(path)
    assert analysis.ok, analysis.diagnostics
    return codegen(analysis.script, analysis.source)


def compile_text(text: str, name: str = "t.script") -> Program:
    source = SourceFile(name, text)
    analysis = analyze_script(source)
    assert analysis.ok, analysis.diagnostics
    return codegen(analysis.script, source)


def reseal(data: bytes | bytearray) -> bytes:
    """The header's length and CRC made right for a changed body (to reach past them)."""
    body = bytes(data[16:])
    return bytes(data[:8]) + struct.pack("<II", len(body), zlib.crc32(body)) + body


def code_offset(program: Program, name: str, nth: int = 0) -> int:
    found = [ins.offset for ins in instructions(program.code) if ins.opcode.name == name]
    return found[nth]


def patched(program: Program, offset: int, data: bytes) -> Program:
    code = bytearray(program.code)
    code[offset:offset + len(data)] = data
    return dataclasses.replace(program, code=bytes(code))


_CONSTANTS = ("x", Num(1.0, "1"))


def one_block(build, kind: str = "J", constants=_CONSTANTS) -> Program:
    """A program of one block whose code `build(asm)` writes."""
    asm = Assembler()
    build(asm)
    return Program(name=0, source=None, constants=tuple(constants), alfa=(), omega=(),
                   goals=(GoalRecord(0, 1, Span(0, 0)),), actions=(ActionRecord(1, Span(0, 0)),),
                   blocks=(BlockRecord(kind, None, 0, Span(0, 0)),), code=bytes(asm.code))


def guarded(body) -> Program:
    """A program of one jump block: COND, whose handler is a NEXT_BLOCK at the end, and
    between them the code `body(asm)` writes (which falls into the handler)."""
    def build(asm: Assembler) -> None:
        fail = JumpTarget()
        asm.emit("COND", fail, 0)
        body(asm)
        asm.place(fail)
        asm.emit("NEXT_BLOCK")

    return one_block(build)


def invalid(program: Program, match: str) -> None:
    with pytest.raises(InvalidError, match=match):
        verify(program)
    # The same refusal through the file: decoding is fine, verifying is not.
    with pytest.raises(InvalidError, match=match):
        load(encode(program))


# ---------------------------------------------------------------------------------------------
# Round trips and golden listings

CASE_SCRIPTS = sorted(BYTECODE_CASES.glob("*.script"))
ALL_SCRIPTS = [EXAMPLE, *CASE_SCRIPTS, *sorted((CASES / "emit").glob("*.script"))]


@pytest.mark.parametrize("path", ALL_SCRIPTS, ids=lambda p: p.name)
def test_round_trip(path: Path) -> None:
    program = compiled(path)
    verify(program)
    data = encode(program)
    assert decode(data) == program
    assert encode(load(data).program) == data


def test_docs_example_is_the_golden_listing() -> None:
    docs = (ROOT / "docs" / "bytecode.md").read_text(encoding="utf-8")
    golden = (BYTECODE_CASES / "conditions.dis").read_text(encoding="utf-8")
    example = docs.split("`conditions.dis`):\n\n```\n", 1)[1].split("```", 1)[0]
    assert example and example in golden


def test_header_and_sections() -> None:
    data = encode(compiled(EXAMPLE))
    magic, version, flags, length, crc = struct.unpack_from("<4sHHII", data)
    assert (magic, version, flags) == (b"SCB\0", FORMAT_VERSION, 0)
    assert length == len(data) - 16 and crc == zlib.crc32(data[16:])
    (count,) = struct.unpack_from("<H", data, 16)
    entries = [struct.unpack_from("<HII", data, 18 + 10 * i) for i in range(count)]
    assert [e[0] for e in entries] == [1, 2, 3, 4, 5]
    assert entries[0][1] == 18 + 10 * count
    assert entries[-1][1] + entries[-1][2] == len(data)


def test_positions_without_the_source() -> None:
    analysis = analyze_file(EXAMPLE)
    bare = codegen(analysis.script)
    full = codegen(analysis.script, analysis.source)
    assert bare.code == full.code and bare.blocks == full.blocks and bare.spans == full.spans
    assert bare.lines == () and bare.source is None
    first = analysis.source.position(analysis.script.goals[0].actions[0].blocks[0].span.start)
    assert full.position(full.blocks[0].span.start) == (first.line, first.column)
    assert bare.position(0) is None
    assert "@" in disassemble(load(encode(bare)).program).splitlines()[4]
    # The back end of `compile --emit bytecode`: with the source, the file carries lines.
    assert decode(emit(analysis.script, "bytecode", analysis.source)) == full
    assert decode(emit(analysis.script, "bytecode")) == bare


def test_program_lookups() -> None:
    program = load(encode(compiled(BYTECODE_CASES / "conditions.script"))).program
    assert program.activity == "greet"
    assert program.block_path(4) == "goal1/act0/blk0"
    assert program.block_index(1, 0, 0) == 4 and program.block_index(5, 0, 0) is None
    jump = program.blocks[1]
    assert program.block_at(jump.code + 3) == 1
    span = program.span_at(jump.code)
    assert span is not None and program.position(span.start) == (11, 11)


# ---------------------------------------------------------------------------------------------
# Codegen


def test_condition_shapes() -> None:
    program = compile_text(
        "[a]\n[goal:g]\n[action]\n"
        "[b#x#blk_jump: CND({VAR @v U F: now()} ! {TRUE} {E: gt(1, 2)}) TRJMP() FLSJMP(z)]\n"
        "[b#y#blk_jump: CND({TRUE}) TRJMP(z) FLSJMP()]\n"
        "[b#z#blk_terminus]\n")
    names = [ins.opcode.name for ins in instructions(program.code, 0, program.block_end(0))]
    # TRUE is the true exit: the E evaluation after it is not compiled.
    assert names == ["COND", "CALL_F", "SET_VAR", "NEXT_BLOCK", "GOTO"]
    names = [ins.opcode.name for ins in instructions(program.code, program.blocks[1].code,
                                                     program.block_end(1))]
    assert names == ["COND", "GOTO", "NEXT_BLOCK"]


def test_constants_are_shared_and_numbers_keep_their_text() -> None:
    program = compile_text('[a]\n[goal:g]\n[action]\n[b##blk_inst: MV("+0.50, 0, .5, 0, 1000", '
                           '"0, 0, 0, 0, 10") LD() AO()]\n[b##blk_terminus]\n')
    numbers = [c for c in program.constants if isinstance(c, Num)]
    assert numbers == [Num(0.5, "+0.50"), Num(0.0, "0"), Num(0.5, ".5")]
    move = next(instructions(program.code))
    assert move.operands[3:] == (0, 1000)


def test_codegen_refuses_what_the_checks_refuse() -> None:
    source = SourceFile("t.script", "[a]\n[goal:g]\n[action]\n"
                                    "[b##blk_jump: CND(! {E: gt(?THIS, 1)}) TRJMP() FLSJMP()]\n")
    analysis = analyze_script(source)
    assert not analysis.ok
    with pytest.raises(CodegenError, match="THIS"):
        codegen(analysis.script, source)
    source = SourceFile("t.script", "[a]\n[goal:g]\n[action]\n"
                                    "[b##blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n")
    with pytest.raises(CodegenError, match="nowhere"):
        codegen(analyze_script(source).script, source)


def test_assembler_patches_forward_labels_and_compacts_spans() -> None:
    asm = Assembler()
    label = JumpTarget()
    asm.mark(0, 1)
    asm.mark(5, 6)  # replaces the entry above: nothing was emitted under it
    asm.emit("COND", label, 0)
    asm.mark(5, 6)
    asm.emit("NEXT_BLOCK")
    asm.place(label)
    asm.emit("NEXT_BLOCK")
    assert asm.spans == [(0, 5, 6)]
    assert int.from_bytes(asm.code[1:5], "little") == 10


# ---------------------------------------------------------------------------------------------
# Refused: malformed (decode)


@pytest.fixture(scope="module")
def good() -> bytes:
    return encode(compiled(BYTECODE_CASES / "conditions.script"))


def test_bad_magic(good: bytes) -> None:
    with pytest.raises(MalformedError, match="bad magic number") as info:
        decode(b"SCX\0" + good[4:])
    assert info.value.offset == 0
    with pytest.raises(MalformedError, match="looks like text"):
        decode(EXAMPLE.read_bytes())
    for short in (b"SCX", b"\x7fELF"):
        with pytest.raises(MalformedError, match="bad magic number"):
            decode(short)
    with pytest.raises(MalformedError, match="empty"):
        decode(b"")
    with pytest.raises(MalformedError, match="truncated"):
        decode(b"SC")


def test_wrong_version(good: bytes) -> None:
    data = good[:4] + struct.pack("<H", FORMAT_VERSION + 1) + good[6:]
    with pytest.raises(MalformedError, match=rf"unsupported format version {FORMAT_VERSION + 1} "
                                             r".*compile the script again"):
        decode(data)


def test_flags_are_reserved(good: bytes) -> None:
    with pytest.raises(MalformedError, match="unknown flags"):
        decode(good[:6] + b"\x01\x00" + good[8:])


def test_bad_checksum(good: bytes) -> None:
    data = bytearray(good)
    data[len(data) // 2] ^= 0x10
    with pytest.raises(MalformedError, match="checksum mismatch"):
        decode(bytes(data))


@pytest.mark.parametrize("keep", [0, 3, 15, 16, 17, 40, -1])
def test_truncated(good: bytes, keep: int) -> None:
    with pytest.raises(MalformedError, match=r"truncated|empty"):
        decode(good[:keep])


def test_bytes_after_the_end(good: bytes) -> None:
    with pytest.raises(MalformedError, match="after the end"):
        decode(good + b"\0")


def test_sections_must_fill_the_file(good: bytes) -> None:
    count_too_big = bytearray(good)
    count_too_big[16:18] = struct.pack("<H", 6)
    with pytest.raises(MalformedError, match="section table has 6 entries"):
        decode(reseal(count_too_big))
    # An extra byte inside the constants section: its records no longer fill it.
    data = bytearray(good)
    entry = 18
    sid, offset, length = struct.unpack_from("<HII", data, entry)
    data[entry:entry + 10] = struct.pack("<HII", sid, offset, length + 1)
    for i in range(1, 5):
        at = entry + 10 * i
        s, o, n = struct.unpack_from("<HII", data, at)
        data[at:at + 10] = struct.pack("<HII", s, o + 1, n)
    data[offset + length:offset + length] = b"\0"
    with pytest.raises(MalformedError, match="after its last record"):
        decode(reseal(data))


def test_absurd_counts_are_refused_before_allocating(good: bytes) -> None:
    data = bytearray(good)
    _sid, offset, _length = struct.unpack_from("<HII", data, 18)
    data[offset:offset + 4] = struct.pack("<I", 0xFFFF_FFFF)
    with pytest.raises(MalformedError, match="announces 4294967295 constants"):
        decode(reseal(data))


def test_text_must_be_utf8() -> None:
    program = one_block(lambda asm: asm.emit("END"), "T", constants=("ab",))
    data = bytearray(encode(program))
    at = bytes(data).index(b"ab")
    data[at] = 0xFF
    with pytest.raises(MalformedError, match="not UTF-8"):
        decode(reseal(data))


# ---------------------------------------------------------------------------------------------
# Refused: invalid (verify)


@pytest.fixture(scope="module")
def program() -> Program:
    return compiled(BYTECODE_CASES / "conditions.script")


def test_out_of_range_jump(program: Program) -> None:
    at = code_offset(program, "JUMP_IF_FALSE")
    invalid(patched(program, at + 1, struct.pack("<I", 999_999)), "outside its block")
    # Into the middle of an instruction of the same block.
    at = code_offset(program, "JUMP_IF_FALSE", 2)
    target = code_offset(program, "PUSH_ATT") + 1
    invalid(patched(program, at + 1, struct.pack("<I", target)),
            f"JUMP_IF_FALSE: code offset {target} is not the start of an instruction")


def test_backward_jump_only_to_the_search(program: Program) -> None:
    at = code_offset(program, "JUMP_IF_FALSE", 2)  # after the E call: forward to the exit
    cond = code_offset(program, "COND", 0)
    invalid(patched(program, at + 1, struct.pack("<I", cond)), "backward jump")


def test_bad_constant_index(program: Program) -> None:
    at = code_offset(program, "PUSH_CONST")
    invalid(patched(program, at + 1, struct.pack("<I", 70_000)),
            rf"constant index 70000 out of range \({len(program.constants)} constants\)")
    move = code_offset(program, "MOVE")
    text = program.constants.index("Silence")
    invalid(patched(program, move + 1, struct.pack("<I", text)),
            f"MOVE: constant {text} is a text, not a number")
    n = len(program.constants)
    invalid(dataclasses.replace(program, name=n),
            rf"the activity name: constant index {n} out of range \({n} constants\)")
    audio = code_offset(program, "AUDIO")
    number = _number_at(program)
    invalid(patched(program, audio + 1, struct.pack("<I", number)),
            f"AUDIO: constant {number} is a number, not a text")


def test_unknown_opcode(program: Program) -> None:
    invalid(patched(program, code_offset(program, "COMPARE"), b"\xee"), "unknown opcode 0xee")


def test_bad_block_operand(program: Program) -> None:
    at = code_offset(program, "GOTO")
    invalid(patched(program, at + 1, struct.pack("<I", 99)),
            rf"GOTO: block 99 out of range \({len(program.blocks)} blocks\)")


def test_bad_letters(program: Program) -> None:
    at = code_offset(program, "FIND")
    invalid(patched(program, at + 9, b"X"), r"'X' is not a scope letter \([A-Z]+\) ")
    # A letter is shown as itself when it is printable ASCII, else as its byte.
    invalid(patched(program, at + 9, b" "), "FIND: ' ' is not a scope letter")
    invalid(patched(program, at + 9, b"~"), "FIND: '~' is not a scope letter")
    invalid(patched(program, at + 9, b"\x7f"), "FIND: 0x7f is not a scope letter")
    invalid(patched(program, at + 9, b"\x1f"), "FIND: 0x1f is not a scope letter")
    at = code_offset(program, "COMPARE")
    invalid(patched(program, at + 1, b"!"), "not a cmp letter")
    message = dataclasses.replace(program.alfa[0], mutex="Q")
    invalid(dataclasses.replace(program, alfa=(message,)), "unknown mutex command")


def test_stack_underflow() -> None:
    def build(asm: Assembler) -> None:
        asm.emit("COMPARE", ord("="))

    invalid(guarded(build), "stack underflow: COMPARE pops 2 values, the stack holds 0 ")


def test_stack_overflow() -> None:
    def build(asm: Assembler) -> None:
        for _ in range(MAX_STACK + 1):
            asm.emit("PUSH_CONST", 0)
        asm.emit("CALL_E", 0, 255)

    invalid(guarded(build), f"stack overflow: more than {MAX_STACK} values ")


def test_a_full_stack_is_not_an_overflow() -> None:
    """MAX_STACK values at once are allowed: one more is the overflow."""
    def build(asm: Assembler) -> None:
        after_first, after_second = JumpTarget(), JumpTarget()
        for _ in range(MAX_STACK):
            asm.emit("PUSH_CONST", 0)
        asm.emit("COMPARE", ord("="))
        asm.emit("JUMP_IF_FALSE", after_first)
        asm.place(after_first)
        asm.emit("CALL_E", 0, MAX_STACK - 2)
        asm.emit("JUMP_IF_FALSE", after_second)
        asm.place(after_second)

    verify(guarded(build))


def test_stack_types_are_shown_in_order() -> None:
    def build(asm: Assembler) -> None:
        asm.emit("PUSH_CONST", 0)
        asm.emit("PUSH_CONST", 0)
        asm.emit("COMPARE", ord("="))
        asm.emit("PUSH_CONST", 0)
        asm.emit("COMPARE", ord("="))

    invalid(guarded(build), r"COMPARE pops \[v v\], the stack holds \[b v\]")


def test_stack_types() -> None:
    def build(asm: Assembler) -> None:
        fail = JumpTarget()
        asm.emit("COND", fail, 0)
        asm.emit("PUSH_CONST", 0)
        asm.emit("JUMP_IF_FALSE", fail)
        asm.place(fail)
        asm.emit("NEXT_BLOCK")

    invalid(one_block(build), r"JUMP_IF_FALSE pops \[b\], the stack holds \[v\]")


def test_values_left_at_an_exit() -> None:
    def build(asm: Assembler) -> None:
        asm.emit("PUSH_CONST", 0)
        asm.emit("NEXT_BLOCK")

    invalid(guarded(build), "NEXT_BLOCK needs an empty stack, it holds 1 values")


def test_this_needs_a_candidate() -> None:
    def build(asm: Assembler) -> None:
        asm.emit("PUSH_THIS")

    invalid(guarded(build), "PUSH_THIS needs a candidate in THIS, but no search is running")

    def next_candidate_alone(asm: Assembler) -> None:
        asm.emit("NEXT_CANDIDATE")

    invalid(guarded(next_candidate_alone), "NEXT_CANDIDATE needs a search started by FIND or "
                                           "a candidate in THIS, but no search is running")


def test_search_must_end_before_an_exit() -> None:
    def build(asm: Assembler) -> None:
        bind = JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), bind)
        asm.emit("NEXT_CANDIDATE")
        asm.emit("NEXT_BLOCK")
        asm.place(bind)
        asm.emit("BIND")

    invalid(guarded(build), "NEXT_BLOCK needs no search running, but a search is still "
                            "running")


def test_find_needs_next_candidate_and_its_bind() -> None:
    def build(asm: Assembler) -> None:
        bind = JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), bind)
        asm.place(bind)
        asm.emit("BIND")

    invalid(guarded(build), "FIND must be followed by NEXT_CANDIDATE")

    def wrong_bind(asm: Assembler) -> None:
        fail = JumpTarget()
        asm.emit("COND", fail, 0)
        asm.emit("FIND", 0, 0, ord("U"), fail)
        asm.emit("NEXT_CANDIDATE")
        asm.emit("BIND")
        asm.place(fail)
        asm.emit("NEXT_BLOCK")

    # The handler after the BIND: COND (9 bytes), FIND (14), NEXT_CANDIDATE and BIND (1 each).
    invalid(one_block(wrong_bind), "FIND names code offset 25 as its BIND, which is not a "
                                     "BIND after it")


def test_searches_hold_tests_only() -> None:
    def forward(asm: Assembler) -> None:
        bind = JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), bind)
        asm.emit("NEXT_CANDIDATE")
        asm.emit("PUSH_THIS")
        asm.emit("PUSH_CONST", 0)
        asm.emit("COMPARE", ord("="))
        asm.emit("JUMP_IF_FALSE", bind)
        asm.place(bind)
        asm.emit("BIND")

    invalid(guarded(forward), "inside a search, a jump may only return")

    def assigns(asm: Assembler) -> None:
        bind = JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), bind)
        asm.emit("NEXT_CANDIDATE")
        asm.emit("PUSH_CONST", 0)
        asm.emit("SET_VAR", ord("U"), 0)
        asm.place(bind)
        asm.emit("BIND")

    invalid(guarded(assigns), "SET_VAR needs no search running")


def test_paths_must_agree() -> None:
    def build(asm: Assembler) -> None:
        join = JumpTarget()
        asm.emit("PUSH_CONST", 0)
        asm.emit("PUSH_CONST", 0)
        asm.emit("COMPARE", ord("="))
        asm.emit("JUMP_IF_FALSE", join)
        asm.emit("PUSH_CONST", 0)
        asm.place(join)
        asm.emit("SET_VAR", ord("U"), 0)

    # Each path's state is shown: the values on the stack, whether a search runs.
    invalid(guarded(build), r"paths meet at code offset 31 with different stacks or searches "
                            r"\(stack \[\], search none and stack \[v\], search none\)")


def test_a_jump_to_itself_is_backward() -> None:
    def build(asm: Assembler) -> None:
        here = JumpTarget()
        asm.emit("CALL_E", 0, 0)
        asm.place(here)
        asm.emit("JUMP_IF_FALSE", here)

    invalid(guarded(build), "blk0: a backward jump may only return to the "
                            "NEXT_CANDIDATE of the running search")


def test_falling_through_into_the_last_instruction() -> None:
    """The last instruction may be reached by falling through the one before it (here COND,
    whose handler is the same instruction)."""
    verify(guarded(lambda asm: None))


def test_running_off_the_block() -> None:
    def build(asm: Assembler) -> None:
        fail = JumpTarget()
        asm.emit("COND", fail, 0)
        asm.emit("NEXT_BLOCK")
        asm.place(fail)
        asm.emit("PUSH_CONST", 0)

    invalid(one_block(build), "run past the end")


def test_block_shapes() -> None:
    invalid(one_block(lambda asm: asm.emit("NEXT_BLOCK"), "I"),
            "an instruction block must end with ISSUE NEXT_BLOCK")
    invalid(one_block(lambda asm: asm.emit("COND", 5, 0), "I"),
            "cannot appear in an instruction block")
    invalid(one_block(lambda asm: asm.emit("NEXT_BLOCK")), "must start with COND")
    invalid(one_block(lambda asm: asm.emit("ISSUE")), "ISSUE cannot appear in a jump block")
    # A block of the wrong shape is refused at its last instruction.
    offsets: list[int] = []
    wrong_end = one_block(lambda asm: offsets.extend((asm.emit("ISSUE"), asm.emit("ISSUE"))),
                          "I")
    with pytest.raises(InvalidError, match="an instruction block must end with ISSUE "
                                           "NEXT_BLOCK") as info:
        verify(wrong_end)
    assert info.value.offset == offsets[1] > 0
    invalid(one_block(lambda asm: (asm.emit("SENSE"), asm.emit("PAYLOAD", 0),
                                   asm.emit("NEXT_BLOCK")), "S"), "must end with SENSE")


def test_inconsistent_tables(program: Program) -> None:
    goals = (dataclasses.replace(program.goals[0], actions=5), *program.goals[1:])
    owned = 5 + sum(goal.actions for goal in program.goals[1:])
    invalid(dataclasses.replace(program, goals=goals),
            f"the goals own {owned} actions, but the table holds {len(program.actions)}$")
    blocks = list(program.blocks)
    blocks[2] = dataclasses.replace(blocks[2], code=blocks[1].code)
    invalid(dataclasses.replace(program, blocks=tuple(blocks)),
            rf"block 2's code starts at {blocks[1].code}, not after block 1's "
            rf"\({blocks[1].code}\): blocks are in code order and not empty$")
    blocks = list(program.blocks)
    blocks[0] = dataclasses.replace(blocks[0], kind="Z")
    invalid(dataclasses.replace(program, blocks=tuple(blocks)), "unknown block kind")
    spans = list(program.spans)
    spans[1] = CodeSpan(spans[1].code + 1, spans[1].start, spans[1].end)
    invalid(dataclasses.replace(program, spans=tuple(spans)),
            f"code span 1 points at code offset {spans[1].code}, which is not the start of an "
            "instruction")
    invalid(dataclasses.replace(program, lines=(0, 5, 5)), "line table")


def test_number_constants_must_be_finite_and_match_their_text() -> None:
    def end(asm: Assembler) -> None:
        asm.emit("END")

    invalid(one_block(end, "T", constants=("a", Num(2.0, "1"))),
            "constant 1: the number 2.0 does not match its text '1'")
    invalid(one_block(end, "T", constants=("a", Num(float("inf"), "inf"))),
            "constant 1 is not a finite number")


def _first(program: Program, table: str, at: int = 0, **changes) -> Program:
    """`program` with the record `at` of `table` changed."""
    records = list(getattr(program, table))
    records[at] = (records[at]._replace(**changes) if isinstance(records[at], tuple)
                   else dataclasses.replace(records[at], **changes))
    return dataclasses.replace(program, **{table: tuple(records)})


def _number_at(program: Program) -> int:
    return next(i for i, c in enumerate(program.constants) if isinstance(c, Num))


# Each refusal of the tables and constants (docs/bytecode.md, "Verification"), made from the
# golden program by one change: (the change, what the error says, whether the file format can
# hold the change, so that `load` must refuse it too).
TABLE_REFUSALS = {
    "number written as no number": (
        lambda p: dataclasses.replace(p, constants=(*p.constants, Num(1.0, "one"))),
        r"constant \d+: the text 'one' of a number constant is not a number$", True),
    "constant of no kind": (
        lambda p: dataclasses.replace(p, constants=(*p.constants, 3)),
        r"constant \d+ is neither a text nor a number", False),
    "name that is a number": (
        lambda p: dataclasses.replace(p, name=_number_at(p)), "is a number, not a text", True),
    "no activity name": (
        lambda p: dataclasses.replace(p, name=None),
        "the activity name: constant index None out of range", False),
    "source name that is a number": (
        lambda p: dataclasses.replace(p, source=_number_at(p)),
        "the source name: constant .* is a number, not a text", True),
    "goal id one past the constants": (
        lambda p: _first(p, "goals", id=len(p.constants)),
        "goal 0: constant index .* out of range", True),
    "span ending before its start": (
        lambda p: _first(p, "goals", span=Span(5, 2)),
        r"goal 0: its source span ends \(2\) before it starts \(5\)", True),
    "action span ending before its start": (
        lambda p: _first(p, "actions", 1, span=Span(9, 4)),
        r"action 1: its source span ends \(4\) before it starts \(9\)", True),
    "block span ending before its start": (
        lambda p: _first(p, "blocks", 2, span=Span(30, 20)),
        r"block 2: its source span ends \(20\) before it starts \(30\)", True),
    "message id that is a number": (
        lambda p: _first(p, "alfa", id=_number_at(p)),
        "alfa message 0: constant .* is a number, not a text", True),
    "message outtopic one past the constants": (
        lambda p: _first(p, "omega", outtopic=len(p.constants)),
        "omega message 0: constant index .* out of range", True),
    "message span ending before its start": (
        lambda p: _first(p, "omega", span=Span(8, 3)),
        r"omega message 0: its source span ends \(3\) before it starts \(8\)", True),
    "rulecode past u32": (
        lambda p: _first(p, "alfa", rulecode=2**32), "rulecode 4294967296 is not a u32", False),
    "negative rulecode": (
        lambda p: _first(p, "alfa", rulecode=-1), "rulecode -1 is not a u32", False),
    "unknown rule action": (
        lambda p: _first(p, "alfa", action="Z"),
        rf"unknown rule action 'Z' \(expected one of {', '.join(RULE_ACTIONS)}\)$", True),
    "empty rule action": (
        lambda p: _first(p, "alfa", action=""), "unknown rule action ''", False),
    "two rule actions": (
        lambda p: _first(p, "alfa", action="AR"), "unknown rule action 'AR'", False),
    "empty mutex letter": (
        lambda p: _first(p, "omega", mutex=""), "omega message 0: unknown mutex command ''",
        False),
    "two mutex letters": (
        lambda p: _first(p, "omega", mutex="LM"),
        rf"unknown mutex command 'LM' \(expected one of {', '.join(MUTEXES)}\)$", False),
    "actions owning more blocks": (
        lambda p: _first(p, "actions", blocks=p.actions[0].blocks + 1),
        r"the actions own (\d+) blocks, but the table holds (?!\1)\d+$", True),
    "first block after 0": (
        lambda p: _first(p, "blocks", code=1), "the first block's code starts at 1, not 0",
        True),
    "last block past the code": (
        lambda p: _first(p, "blocks", len(p.blocks) - 1, code=len(p.code)),
        r"block \d+'s code starts at (\d+), past the end of the code \(\1 bytes\)$", True),
    "code without blocks": (
        lambda p: dataclasses.replace(p, goals=(), actions=(), blocks=(), spans=()),
        "bytes of code belong to no block", True),
    "label that is a number": (
        lambda p: _first(p, "blocks", label=_number_at(p)), "block 0's label: constant", True),
    "line table from 1": (
        lambda p: dataclasses.replace(p, lines=(1, 5)), r"line 1 starts at 1\)", True),
    "first code span after 0": (
        lambda p: _first(p, "spans", code=1),
        "the first code span starts at code offset 1, not 0", True),
    "code span before the text": (
        lambda p: _first(p, "spans", 1, start=-1),
        r"code span 1 starts at a negative source offset \(-1\)$", False),
    "code span from 0 ending before it": (
        lambda p: _first(p, "spans", 1, start=0, end=-1),
        r"code span 1: its source span ends \(-1\) before it starts \(0\)$", False),
    "code spans out of order": (
        lambda p: _first(p, "spans", 2, code=p.spans[1].code),
        r"code span 2 is out of order \(code offset \d+\)$",
        True),
    "code span ending before its start": (
        lambda p: _first(p, "spans", 1, start=10, end=5),
        r"code span 1: its source span ends \(5\) before it starts \(10\)", False),
}


@pytest.mark.parametrize("change, match, in_a_file", TABLE_REFUSALS.values(),
                         ids=list(TABLE_REFUSALS))
def test_every_refusal_of_the_tables(program: Program, change, match: str,
                                     in_a_file: bool) -> None:
    verify(program)
    if in_a_file:
        invalid(change(program), match)
    else:
        with pytest.raises(InvalidError, match=match):
            verify(change(program))


def test_operands_one_past_their_table(program: Program) -> None:
    """An index equal to its table's length is out of range, as any beyond it."""
    at = code_offset(program, "PUSH_CONST")
    n = len(program.constants)
    invalid(patched(program, at + 1, struct.pack("<I", n)),
            f"constant index {n} out of range")
    at = code_offset(program, "GOTO")
    n = len(program.blocks)
    invalid(patched(program, at + 1, struct.pack("<I", n)), f"block {n} out of range")
    # A jump to the end of its block is outside it (the next block starts there).
    at = code_offset(program, "JUMP_IF_FALSE")
    block = program.block_at(at)
    end = program.block_end(block)
    invalid(patched(program, at + 1, struct.pack("<I", end)),
            rf"jump to code offset {end}, outside its block \(\d+\.\.{end - 1}\)")
    at = code_offset(program, "LED")
    turnas = at + 1 + 3 * 4  # after r, g and b (text constants' indexes)
    assert program.code[turnas] == 1
    invalid(patched(program, turnas, b"\x02"), "LED: 2 is not 0 or 1")


def test_every_refusal_of_the_code() -> None:
    cond = BY_NAME["COND"]
    truncated = Program(name=0, source=None, constants=_CONSTANTS, alfa=(), omega=(),
                        goals=(GoalRecord(0, 1, Span(0, 0)),),
                        actions=(ActionRecord(1, Span(0, 0)),),
                        blocks=(BlockRecord("J", None, 0, Span(0, 0)),),
                        code=bytes([cond.code, 0]))
    invalid(truncated, f"COND needs {cond.size} bytes, the block ends after 2")
    push = BY_NAME["PUSH_CONST"]
    after_cond = dataclasses.replace(
        truncated, code=bytes([cond.code, cond.size, 0, 0, 0, 0, 0, 0, 0, push.code, 0]))
    assert cond.size == 9
    invalid(after_cond, f"PUSH_CONST needs {push.size} bytes, the block ends after 2 ")

    def two_conds(asm: Assembler) -> None:
        fail = JumpTarget()
        asm.emit("COND", fail, 0)
        asm.emit("COND", fail, 0)
        asm.place(fail)
        asm.emit("NEXT_BLOCK")

    invalid(one_block(two_conds), "COND may only start a jump block")
    invalid(one_block(lambda asm: (asm.emit("COND", 0, 0), asm.emit("NEXT_BLOCK"))),
            "COND's handler must come after it")

    def second_next_candidate(asm: Assembler) -> None:
        bind = JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), bind)
        asm.emit("NEXT_CANDIDATE")
        asm.emit("NEXT_CANDIDATE")
        asm.place(bind)
        asm.emit("BIND")

    invalid(guarded(second_next_candidate),
            "NEXT_CANDIDATE must follow the FIND of the running search")

    def other_bind(asm: Assembler) -> None:
        first, second = JumpTarget(), JumpTarget()
        asm.emit("FIND", 0, 0, ord("U"), second)
        asm.emit("NEXT_CANDIDATE")
        asm.place(first)
        asm.emit("BIND")
        asm.place(second)
        asm.emit("BIND")

    invalid(guarded(other_bind), "BIND ends the search of the FIND at 9, which names "
                                 "another BIND")
    invalid(one_block(lambda asm: (asm.emit("NEXT_BLOCK"), asm.emit("ISSUE"),
                                   asm.emit("NEXT_BLOCK")), "I"),
            "NEXT_BLOCK cannot come before ISSUE in an instruction block")


def test_only_verify_makes_a_verified_program(program: Program) -> None:
    with pytest.raises(TypeError, match=r"comes from bytecode\.verify"):
        Verified(program, [])
    assert verify(program).program is program


def test_error_messages_say_where() -> None:
    program = compiled(BYTECODE_CASES / "conditions.script")
    at = code_offset(program, "COMPARE")
    with pytest.raises(InvalidError) as info:
        verify(patched(program, at, b"\xee"))
    assert info.value.offset == at
    assert str(info.value) == (f"invalid bytecode: goal0/act0/blk1: unknown opcode 0xee "
                               f"(at code offset {at})")


# ---------------------------------------------------------------------------------------------
# The table and the docs


def test_every_opcode_is_documented_and_sized() -> None:
    for op in OPCODES:
        assert op.doc and op.size == 1 + sum(o.kind.size for o in op.operands)
        for name in (o.name for o in op.operands):
            assert op.listing == "" or "{" + name + "}" in op.listing, (op.name, name)
    assert BY_NAME["MOVE"].size == 21


def test_bytecode_does_not_import_the_ir() -> None:
    probe = ("import sys, scriptc.bytecode, scriptc.bytecode.docs\n"
             "bad = [m for m in sys.modules if m.startswith(('scriptc.ir', 'scriptc.syntax', "
             "'scriptc.emit', 'lark'))]\n"
             "assert not bad, bad\n")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=60, check=False)
    assert done.returncode == 0, done.stderr
