"""The bytecode VM (`scriptc.runtime.vm`): the executor interface over verified bytecode, its
traps, and its searches compiled and interpreted. That it agrees with the reference
interpreter is held by the runtime cases (tests/harness/runtime.py: every case through both) and
tests/test_vm_differential.py (generated scripts and scenarios)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scriptc import bytecode
from scriptc.analysis.analyze import analyze_bytes
from scriptc.ops.build import emit
from scriptc.runtime.bindings import READER, Bindings
from scriptc.runtime.commands import BlockAddress
from scriptc.runtime.evaluate import EvalContext, evaluate
from scriptc.runtime.executor import End, Issue, SeekError
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.rules import parse_condition_text
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.vm import VMProgram, program_from_bytecode
from scriptc.runtime.world import World, parse_update

ROOT = Path(__file__).resolve().parent.parent


def vm_program(text: str, compile_searches: bool = True) -> VMProgram:
    analysis = analyze_bytes("t.script", text.encode("utf-8"), "script")
    assert analysis.ok, [d.message for d in analysis.diagnostics]
    return VMProgram(bytecode.load(emit(analysis.script, "bytecode", analysis.source)),
                     "t.script", compile_searches)


class Sink:
    def __init__(self) -> None:
        self.events: list = []

    def visit(self, position):
        self.events.append(("visit", position.path))

    def jump(self, position, condition, evaluation, target):
        self.events.append(("jump", position.path, condition, evaluation.value,
                            target.path if target else None))

    def sensor(self, position, payload):
        self.events.append(("sensor", position.path, payload))


def context(n: int = 0) -> EvalContext:
    world = World()
    for i in range(n):
        world.apply(parse_update(f"Human/h{i}", "poses", "R", {"positionrho": 2.0 + i}), i)
    return EvalContext(world, Bindings(), STANDARD_IMPLEMENTATIONS)


SCRIPT = """[t]
[alfa:16, greeter, "\\\\in", "\\\\out", A, U]
[omega:16, greeter, "", "", R, L]
[goal:first]
  [action]
    [b#a#blk_inst: MV("0.1, 0, 0, 0, 500") LD("0, 0, 1, 1, 0, 500") AO("Silence, 0, 500")]
    [b##blk_sens: "hello", "world"]
    [b##blk_jump: CND({VAR @v T F: str("x")} ! {E: eq(@v, "x")}) TRJMP(c) FLSJMP()]
[goal:second]
  [action]
    [b#c#blk_inst: MV() LD() AO("songs/a.wav, 0, 100")]
    [b##blk_terminus]
"""


def test_the_executor_interface() -> None:
    program = program_from_bytecode(bytecode.verify(vm_program(SCRIPT).bytecode), "t.scb")
    assert (program.name, program.path, program.goal_ids) == ("t", "t.scb", ("first", "second"))
    assert [(m.kind, m.rulecode, m.id, m.intopic, m.action, m.mutex) for m in program.alfa] == \
        [("alfa", 16, "greeter", "\\in", "A", "U")]
    ex = program.executor()
    ex.start()
    sink, ctx = Sink(), context()
    first = ex.read(ctx, sink)
    assert isinstance(first, Issue) and first.label == "a"
    assert first.position == BlockAddress(0, 0, 0)
    assert first.instruction.moves[0].v_x == 0.1 and first.instruction.moves[0].duration == 500
    assert first.instruction.leds[0].turnas == 1
    assert first.instruction.audios[0].track_path == "Silence"
    second = ex.read(ctx, sink)
    assert isinstance(second, Issue) and second.position == BlockAddress(1, 0, 0)
    assert ex.read(ctx, sink) == End(BlockAddress(1, 0, 1), "terminus")
    assert sink.events == [
        ("visit", "goal0/act0/blk0"), ("visit", "goal0/act0/blk1"),
        ("sensor", "goal0/act0/blk1", ("hello", "world")), ("visit", "goal0/act0/blk2"),
        ("jump", "goal0/act0/blk2", '{VAR @v T F: str("x")} ! {E: eq(@v, "x")}', True,
         "goal1/act0/blk0"),
        ("visit", "goal1/act0/blk0"), ("visit", "goal1/act0/blk1")]
    ex.seek(BlockAddress(0, 0, 2))
    sink.events.clear()
    assert isinstance(ex.read(ctx, sink), Issue)
    assert sink.events[0] == ("visit", "goal0/act0/blk2")
    with pytest.raises(SeekError):
        ex.seek(BlockAddress(5, 0, 0))


def test_running_past_the_last_block() -> None:
    program = vm_program("[p]\n[goal:g]\n[action]\n[b##blk_inst: MV() LD() AO()]\n")
    ex = program.executor()
    ex.start()
    sink, ctx = Sink(), context()
    assert isinstance(ex.read(ctx, sink), Issue)
    assert ex.read(ctx, sink) == End(BlockAddress(0, 0, 0), "past_end")
    assert ex.read(ctx, sink) == End(BlockAddress(0, 0, 0), "past_end")


def test_a_trap_is_a_fatal_error_in_the_trace_not_an_exception(monkeypatch) -> None:
    program = vm_program("[trap]\n[goal:g]\n[action]\n"
                         "[b##blk_jump: CND(! {E: eq(@v, 1)}) TRJMP() FLSJMP()]\n"
                         "[b##blk_inst: MV() LD() AO()]\n")

    def broken(self, name):
        raise ZeroDivisionError("the map is broken")

    monkeypatch.setattr(EvalContext, "var", broken)
    trace = Trace()
    result = Session([program], trace=trace).run(1000)
    assert result.outcome == "error"
    errors = [json.loads(line) for line in trace.text().splitlines() if '"error"' in line]
    assert errors and errors[0]["code"] == "read" and errors[0]["fatal"] is True
    assert "goal0/act0/blk0 (line 4, column 21)" in errors[0]["message"]
    assert "ZeroDivisionError: the map is broken" in errors[0]["message"]


@pytest.mark.parametrize("compile_searches", [True, False])
def test_a_thousand_entities_oldest_free_first(compile_searches: bool) -> None:
    text = ("[k]\n[goal:g]\n[action]\n"
            "[b##blk_jump: CND({CLASS #Human U ?far (?THIS>&positionrho OP> 500)} ! {TRUE}) "
            "TRJMP() FLSJMP()]\n"
            "[b##blk_jump: CND({CLASS #Human U ?far2 (?THIS>&positionrho OP> 500)} ! {TRUE}) "
            "TRJMP() FLSJMP()]\n"
            "[b##blk_jump: CND({CLASS #Human U ?x (?THIS>&positionrho OP> 5000)} ! {TRUE}) "
            "TRJMP() FLSJMP()]\n"
            "[b##blk_inst: MV() LD() AO()]\n")
    ex = vm_program(text, compile_searches).executor()
    ex.start()
    ctx, sink = context(1000), Sink()
    found = []
    sink.jump = lambda position, condition, evaluation, target: found.append(
        (evaluation.value, evaluation.bindings))
    ex.read(ctx, sink)
    assert found == [(True, {"?far": "Human/h499"}), (True, {"?far2": "Human/h500"}),
                     (False, {})]


@pytest.mark.parametrize("op", ["OP<", "OP>", "OP="])
@pytest.mark.parametrize("right", ["1.0", '"1.0"', '"abc"', "-3", '"s_true"', "@v",
                                   "?THIS>&positionrho"])
def test_compiled_and_interpreted_searches_mean_what_the_ir_does(op: str, right: str) -> None:
    condition = f"{{CLASS #Object U ?o (?THIS>&category {op} {right})}} ! {{TRUE}}"
    text = f"[s]\n[goal:g]\n[action]\n[b##blk_jump: CND({condition}) TRJMP() FLSJMP()]\n"
    outcomes = []
    for how in ("ir", "compiled", "interpreted"):
        results = []
        for value in ["1", "1.0", "abc", "-5", "s_true", 2.0, None]:
            world = World()
            fields = {} if value is None else {"category": value}
            world.apply(parse_update("Object/o1", "poses", "R", {"positionrho": 1.0}), 0)
            entity = world.candidates("Object")[0]
            entity.fields.update(fields)
            ctx = EvalContext(world, Bindings(), STANDARD_IMPLEMENTATIONS)
            if how == "ir":
                ctx.begin(READER, 0)
                results.append(evaluate(parse_condition_text(condition), ctx).value)
            else:
                ex = vm_program(text, how == "compiled").executor()
                ex.start()
                sink = Sink()
                ex.read(ctx, sink)
                results.append(sink.events[1][3])
        outcomes.append(results)
    assert outcomes[0] == outcomes[1] == outcomes[2]


def test_cli_runs_scripts_on_the_vm_and_the_ir_alike(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from scriptc.cli.main import cli

    world = ROOT / "tests" / "cases" / "runtime" / "jump_on_child.near.world"
    script = ROOT / "tests" / "cases" / "runtime" / "jump_on_child.script"
    traces = []
    for executor in ("vm", "ir"):
        out = tmp_path / f"{executor}.jsonl"
        result = CliRunner().invoke(cli, ["run", str(script), "--world", str(world),
                                          "--robot", "kinematic", "--trace", str(out),
                                          "--executor", executor], catch_exceptions=False)
        assert result.exit_code == 0, result.output
        traces.append(out.read_text(encoding="utf-8"))
    assert traces[0] == traces[1] and '"jump"' in traces[0]


def test_the_vm_never_imports_the_ir_or_a_parser() -> None:
    source = (ROOT / "src" / "scriptc" / "runtime" / "vm.py").read_text(encoding="utf-8")
    imports = [line for line in source.splitlines() if line.startswith(("from ", "import "))]
    assert not [line for line in imports
                if "scriptc.ir" in line or "syntax" in line or "interp" in line
                or "driver" in line or "emit" in line], imports


def test_ir_program_and_vm_agree_on_listing_4_1() -> None:
    example = ROOT / "examples" / "test_act.script"
    analysis = analyze_bytes("test_act.script", example.read_bytes(), "script")
    traces = []
    for program in (IRProgram(analysis.script, "x"),
                    program_from_bytecode(bytecode.load(emit(analysis.script, "bytecode",
                                                             analysis.source)), "x")):
        trace = Trace()
        result = Session([program], trace=trace).run()
        traces.append((result.time_ms, trace.text()))
    assert traces[0] == traces[1] and traces[0][0] == 16_000


FUZZ_WORLD = {"updates": [
    {"at": t, "objectid": f"Human/kid{k}", "attributename": "poses", "policy": "R",
     "jsonmsg": {"positionrho": 0.3 + k + (t // 500) % 3, "positiontheta": 0.0}}
    for t in range(0, 6000, 500) for k in range(3)]}


def _mutants(draw_sample):
    """Programs that verify but that codegen never writes: operands of a compiled program
    replaced by other values of their kind (a function, alias, field or class name swapped for
    another text, a GOTO to another block, another scope, comparison or number)."""
    import struct as _struct

    from hypothesis import strategies as st

    from scriptc.bytecode.code import instructions

    @st.composite
    def mutant(draw):
        program = draw_sample(draw)
        texts = [i for i, c in enumerate(program.constants) if isinstance(c, str)]
        numbers = [i for i, c in enumerate(program.constants) if not isinstance(c, str)]
        listing = list(instructions(program.code))
        code = bytearray(program.code)
        for _ in range(draw(st.integers(1, 4))):
            ins = draw(st.sampled_from(listing))
            where = ins.offset + 1
            choices = []
            for operand in ins.opcode.operands:
                choices.append((where, operand.kind.name))
                where += operand.kind.size
            if not choices:
                continue
            at, kind = draw(st.sampled_from(choices))
            if kind in ("name", "text") and texts:
                code[at:at + 4] = _struct.pack("<I", draw(st.sampled_from(texts)))
            elif kind == "num" and numbers:
                code[at:at + 4] = _struct.pack("<I", draw(st.sampled_from(numbers)))
            elif kind == "const":
                constant = draw(st.integers(0, len(program.constants) - 1))
                code[at:at + 4] = _struct.pack("<I", constant)
            elif kind == "block":
                code[at:at + 4] = _struct.pack("<I", draw(st.integers(0, len(program.blocks) - 1)))
            elif kind == "scope":
                code[at] = ord(draw(st.sampled_from("ULT")))
            elif kind == "cmp":
                code[at] = ord(draw(st.sampled_from("=<>")))
            elif kind in ("u32", "u8", "bit"):
                code[at] = draw(st.integers(0, 1))
        from dataclasses import replace

        return replace(program, code=bytes(code))

    return mutant()


FUZZ_WORLD = {"updates": [
    {"at": t, "objectid": f"Human/kid{k}", "attributename": "poses", "policy": "R",
     "jsonmsg": {"positionrho": 0.3 + k + (t // 500) % 3, "positiontheta": 0.0}}
    for t in range(0, 6000, 500) for k in range(3)]}


@pytest.mark.slow
def test_the_vm_never_crashes_on_a_verified_program() -> None:
    """Compiled programs with operands swapped for other valid values (which codegen would
    never write: calls to functions of the wrong kind or arity, unknown classes, aliases
    used unbound, jumps anywhere) that still verify run on the VM: whatever they do, the
    session ends with an outcome, never an exception."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from scriptc.runtime.scenario import scenario_from_data

    samples = []
    for path in (ROOT / "examples" / "test_act.script",
                 ROOT / "tests" / "cases" / "bytecode" / "conditions.script",
                 ROOT / "tests" / "cases" / "runtime" / "scopes.script"):
        analysis = analyze_bytes(path.name, path.read_bytes(), "script")
        samples.append(bytecode.load(emit(analysis.script, "bytecode", analysis.source)).program)
    scenario = scenario_from_data(FUZZ_WORLD)
    ran = []

    @settings(max_examples=120, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow])
    @given(_mutants(lambda draw: draw(st.sampled_from(samples))))
    def run(program) -> None:
        try:
            verified = bytecode.verify(program)
        except bytecode.InvalidError:
            return
        result = Session([program_from_bytecode(verified, "fuzz.scb")], scenario=scenario,
                         trace=Trace()).run(6000)
        assert result.outcome in ("completed", "until", "stalled", "error")
        ran.append(result.outcome)
        for error in result.errors:  # traps name where they happened
            if error["code"] == "read" and "blocks without reaching" not in error["message"]:
                assert error["message"].startswith("goal"), error  # a trap

    run()
    assert len(ran) >= 30, f"only {len(ran)} mutants verified"


def test_a_var_and_an_att_hold_texts_whatever_value_the_stack_gives() -> None:
    """SET_VAR and SET_ATT pop any value (`v`): a verified program may assign a number
    constant, which codegen never writes. VARs and ATTs hold texts (docs/rules.md), and the
    trace's bindings are texts (schemas/trace.schema.json): the number is stored as its text."""
    from scriptc.bytecode.code import Assembler, JumpTarget
    from scriptc.bytecode.program import ActionRecord, BlockRecord, GoalRecord, Num, Program
    from scriptc.source import Span

    asm = Assembler()
    fail = JumpTarget()
    asm.emit("COND", fail, 0)
    asm.emit("PUSH_CONST", 1)
    asm.emit("SET_VAR", ord("U"), 2)
    asm.emit("PUSH_CONST", 1)
    asm.emit("SET_ATT", ord("U"), 3, 4)
    asm.emit("NEXT_BLOCK")
    asm.place(fail)
    asm.emit("NEXT_BLOCK")
    program = Program(name=0, source=None, constants=("x", Num(2.0, "2.0"), "@n", "?k", "mood"),
                      alfa=(), omega=(), goals=(GoalRecord(0, 1, Span(0, 0)),),
                      actions=(ActionRecord(1, Span(0, 0)),),
                      blocks=(BlockRecord("J", None, 0, Span(0, 0)),),
                      code=bytes(asm.code))
    executor = program_from_bytecode(bytecode.verify(program)).executor()
    executor.start()
    sink, ctx = Sink(), context(1)
    ctx.bindings.bind("?k", ctx.world.entity("Human", "h0"), "U", READER)
    assert executor.read(ctx, sink) == End(BlockAddress(0, 0, 0), "past_end")
    assert sink.events[-1][3] is True  # the true exit
    assert ctx.bindings.get_var("@n") == "2" and ctx.bindings.get_att("?k", "mood") == "2"
    assert ctx.bindings.snapshot() == {"?k": "Human/h0", "@n": "2", "?k>$mood": "2"}


def test_the_vm_runs_verified_programs_only() -> None:
    """A runtime gets programs only through verification: the VM refuses a bytecode Program
    that did not go through `bytecode.verify`, and only the verifier makes a `Verified`."""
    program = vm_program(SCRIPT).bytecode
    with pytest.raises(TypeError, match="verified"):
        VMProgram(program, "t.scb")
    with pytest.raises(TypeError, match=r"bytecode\.verify"):
        bytecode.Verified(program, [])
    verified = bytecode.verify(program)
    assert verified.program is program
    # The verifier hands over the instructions it decoded, block by block, in code order.
    assert verified.instructions[0][0].offset == 0
    assert len(verified.instructions) == len(program.blocks)
    assert all(ins.end == ins.offset + ins.opcode.size
               for block in verified.instructions for ins in block)


def test_run_verifies_codegen_s_program_without_bytes(monkeypatch) -> None:
    """`scriptc run` of a script: codegen's program is verified in memory and run, never
    encoded to bytes and decoded back."""
    import importlib

    from scriptc.ops.programs import checked_program

    analysis = analyze_bytes("t.script", SCRIPT.encode("utf-8"), "script")

    def never(*args, **kwargs):
        raise AssertionError("the program went through bytes")

    # What `load` decodes with, and what `emit_bytecode` encodes with.
    monkeypatch.setattr(importlib.import_module("scriptc.bytecode.verify"), "decode", never)
    monkeypatch.setattr(importlib.import_module("scriptc.emit.codegen"), "encode", never)
    program = checked_program(analysis, "t.script")
    assert isinstance(program, VMProgram) and program.name == "t"
    trace = Trace()
    assert Session([program], trace=trace).run(5000).outcome == "completed"
    assert '"jump"' in trace.text()
