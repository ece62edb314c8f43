"""The bytecode VM: an executor (`executor.py`) that runs a verified `.scb` program
(docs/bytecode.md, "Running a program"). It is the executor `scriptc run` uses; the reference
interpreter over the IR (`interp.py`) is the executable spec it must agree with, trace for
trace (tests/harness/runtime.py runs every case through both; tests/test_vm_differential.py
runs generated scripts and scenarios through both).

It knows nothing of the IR and never parses: its input is a `scriptc.bytecode.Verified`
program, which only the verifier makes (`bytecode.verify` of codegen's program in memory, or
`bytecode.load` of a file's bytes), and its only partners are the runtime's shared modules: the
session through the `ReadSink`, the map through `EvalContext`'s primitives, and the parts of
conditions of `evaluate.py` (what reading a value, calling a function and comparing mean).

How it runs (the registers of docs/bytecode.md):

- **Loading** turns each block's instructions, as the verifier decoded them, into steps. The
  operands are read by their kinds in the opcode table (one decoder for all opcodes: texts and
  names to str, constants to their values, letters to str, jump offsets to indices in the
  block's steps); each opcode then says what its step does: a value push becomes the `Read` of
  `evaluate.py` for that value, a call or a comparison the same `invoke` and `compare_op` the
  IR's conditions use. The commands of an instruction block and the payload of a sensor block
  are constants: they are gathered at load, and reading such a block starts at its `ISSUE` or
  `SENSE`. The verifier has already proved what the loop below relies on: operands in range,
  jumps inside the block, a stack that never underflows and holds truth values where they are
  popped, searches well formed, exits with an empty stack.
- **The block reader** has two registers, the block and `pc` (an index in the block's steps).
  `read` arrives at a block (the session's `visit`), runs its steps until one transfers
  control (`GOTO`, `NEXT_BLOCK`, `END`) or stops reading (`ISSUE`: the pending block's
  commands are returned as an `Issue`; the next `read` resumes after it, at `NEXT_BLOCK`).
- **Conditions** run on a value stack with the failure handler `COND` sets. A failing
  instruction empties the stack and continues at the handler. An exit reached before the
  handler is the true exit, at or after it the false one: the jump is reported to the sink
  with the condition's canonical text (`COND`'s text operand), the `Evaluation` the context
  gathered, and the target block.
- **Searches** (`FIND` ... `NEXT_CANDIDATE` tests `BIND`) run as one call to
  `EvalContext.assign_class`, which the docs allow ("a VM may also run a whole search with one
  call"): the tests between `NEXT_CANDIDATE` and `BIND` are its `passes` predicate. The tests
  run once per candidate (1,000 entities per jump must cost under a millisecond), so at load
  each search's tests are turned into the checks `evaluate.py` builds for the IR's tests (a
  symbolic run of the stack: the pushes' `Read`s become the arguments of `comparison` and
  `call`; each `JUMP_IF_FALSE` back to `NEXT_CANDIDATE` closes one test).
  `VMProgram(..., compile_searches=False)` runs them step by step instead, with the candidate
  as `?THIS` (tests hold the two equal).
- **Traps.** A verified program cannot make the VM misbehave, but a run can still go wrong
  in a way the script is to blame for at run time. Function failures are the context's
  (reported, the call counts as false / missing: docs/bytecode.md). Anything else that goes
  wrong while an instruction runs becomes a `VMTrap` (a RuntimeError carrying the block's path
  and the source position from the code span table), which the session reports in the trace
  as a fatal `read` error: never an exception out of the session.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, overload

from scriptc.bytecode.code import Instruction
from scriptc.bytecode.opcodes import BY_CODE, BY_NAME, KINDS
from scriptc.bytecode.program import MessageRecord, Num
from scriptc.bytecode.verify import Verified
from scriptc.runtime.bindings import READER
from scriptc.runtime.commands import (
    Audio,
    BlockAddress,
    BlockCommands,
    Led,
    Move,
    RuleMessage,
    Value,
    compare_op,
)
from scriptc.runtime.evaluate import (
    Check,
    EvalContext,
    Read,
    alias_id,
    attribute,
    call,
    comparison,
    constant,
    field_of,
    invoke,
    test_of,
    this_field,
    this_id,
    variable,
)
from scriptc.runtime.executor import End, ExecutorBase, Issue, ReadLimit, ReadResult, ReadSink
from scriptc.runtime.world import Entity

__all__ = ["VMExecutor", "VMProgram", "VMTrap", "program_from_bytecode"]

MAX_BLOCKS_PER_READ = 100_000


class VMTrap(RuntimeError):
    """Something went wrong while an instruction ran (the script's fault at run time): the
    session reports it as a fatal `read` error in the trace."""


# ---------------------------------------------------------------------------------------------
# Operands, read by their kinds (bytecode/opcodes.py, "Operand kinds")


class _Operands:
    """What reading the operands of one block needs: the constants, and where each of the
    block's instructions starts (a jump operand becomes the index of its target step)."""

    __slots__ = ("constants", "index")

    def __init__(self, constants: Sequence[object], index: dict[int, int]) -> None:
        self.constants = constants
        self.index = index

    def constant(self, value: int) -> object:
        """A number's value or a text (a `const`, `num`, `text` or `name` operand)."""
        c = self.constants[value]
        return c.value if isinstance(c, Num) else c

    def step(self, offset: int) -> int:
        return self.index[offset]


def _plain(operands: _Operands, value: int) -> int:
    return value


# The run-time value of an operand, by its kind: every kind of the table has one.
_KIND_VALUE: dict[str, Callable[[_Operands, int], object]] = {
    "u8": _plain, "u32": _plain, "bit": _plain, "block": _plain,
    "const": _Operands.constant, "num": _Operands.constant, "text": _Operands.constant,
    "name": _Operands.constant,
    "scope": lambda operands, value: chr(value),
    "cmp": lambda operands, value: "OP" + chr(value),  # the comparison as the language writes it
    "jump": _Operands.step,
}
if set(_KIND_VALUE) != set(KINDS):
    raise AssertionError(f"operand kinds without a run-time value: "
                         f"{set(KINDS) ^ set(_KIND_VALUE)}")


# ---------------------------------------------------------------------------------------------
# Steps: what each instruction does, `(code, arguments...)`

# A step is a plain tuple, indexed in the block reader's loop (the fastest form in Python);
# what follows its code depends on the code (`_STEPS` says what, per opcode, and the verifier
# has proved the operands), so its items are typed by that table, not one by one.
_Step = tuple[Any, ...]

(_PUSH, _CALL, _BRANCH, _COMPARE, _FIND, _ASSIGN, _BOUND, _COND, _EXIT, _ISSUE, _SENSE, _END,
 _NEXT_CANDIDATE, _BIND, _COMMAND, _PAYLOAD) = range(16)


def _push(read: Read) -> _Step:
    return (_PUSH, read.get, read)


# Per mnemonic, the step of an instruction from its operands' values (in table order). Move,
# Led and Audio take their fields in the order of MOVE's, LED's and AUDIO's operands.
_STEPS: dict[str, Callable[..., _Step]] = {
    "MOVE": lambda *values: (_COMMAND, 0, Move(*values)),
    "LED": lambda *values: (_COMMAND, 1, Led(*values)),
    "AUDIO": lambda *values: (_COMMAND, 2, Audio(*values)),
    "ISSUE": lambda: (_ISSUE, BlockCommands()),
    "PAYLOAD": lambda text: (_PAYLOAD, text),
    "SENSE": lambda: (_SENSE, ()),
    "END": lambda: (_END,),
    "GOTO": lambda target: (_EXIT, target),
    "NEXT_BLOCK": lambda: (_EXIT, None),
    "COND": lambda fail, text: (_COND, fail, text),
    "JUMP_IF_FALSE": lambda target: (_BRANCH, target),
    "FIND": lambda cls, alias, scope, bind: (_FIND, cls, alias, scope, bind),
    "NEXT_CANDIDATE": lambda: (_NEXT_CANDIDATE,),
    "BIND": lambda: (_BIND,),
    "SET_VAR": lambda scope, var: (
        _ASSIGN, lambda ctx, value: ctx.assign_var(var, value, scope)),
    "SET_ATT": lambda scope, alias, att: (
        _ASSIGN, lambda ctx, value: ctx.assign_att(alias, att, value, scope)),
    "BOUND": lambda alias: (_BOUND, alias),
    "PUSH_CONST": lambda value: _push(constant(value)),
    "PUSH_VAR": lambda name: _push(variable(name)),
    "PUSH_ALIAS": lambda alias: _push(alias_id(alias)),
    "PUSH_FIELD": lambda alias, name: _push(field_of(alias, name)),
    "PUSH_ATT": lambda alias, name: _push(attribute(alias, name)),
    "PUSH_THIS": lambda: _push(this_id()),
    "PUSH_THIS_FIELD": lambda name: _push(this_field(name)),
    "COMPARE": lambda op: (_COMPARE, op),
    "CALL_B": lambda name, argc: (_CALL, name, "B", argc),
    "CALL_F": lambda name, argc: (_CALL, name, "F", argc),
    "CALL_E": lambda name, argc: (_CALL, name, "E", argc),
}
if set(_STEPS) != set(BY_NAME):
    raise AssertionError(f"opcodes without a step: {set(BY_NAME) ^ set(_STEPS)}")

# Per opcode number: the value readers of its operands, and its step.
_DECODE: dict[int, tuple[tuple[Callable[[_Operands, int], object], ...],
                         Callable[..., _Step]]] = {
    op.code: (tuple(_KIND_VALUE[o.kind.name] for o in op.operands), _STEPS[op.name])
    for op in BY_CODE.values()
}


class _Block:
    __slots__ = ("condition", "entry", "kind", "label", "offsets", "searches", "steps")

    def __init__(self, kind: str, label: str) -> None:
        self.kind = kind
        self.label = label
        self.steps: list[_Step] = []
        self.offsets: list[int] = []  # code offset of each instruction (for spans)
        self.entry = 0  # the step reading starts at
        self.searches: dict[int, tuple[Check, ...]] = {}  # FIND index -> compiled tests
        self.condition = ""


def _steps(listing: Sequence[Instruction], operands: _Operands) -> list[_Step]:
    """The steps of a block's instructions: each operand read by its kind, then the opcode's
    step built from the values."""
    steps = []
    for ins in listing:
        readers, step = _DECODE[ins.opcode.code]
        # The verifier decoded each instruction's operands by the same table: one per reader.
        steps.append(step(*[read(operands, raw)
                            for read, raw in zip(readers, ins.operands, strict=True)]))
    return steps


def _gather(block: _Block) -> None:
    """Fold the constant steps at the start of an instruction or sensor block (its commands,
    its payload) into the ISSUE or SENSE that takes them, and start reading there."""
    steps = block.steps
    k = 0
    tracks: tuple[list[Move], list[Led], list[Audio]] = ([], [], [])
    payload: list[str] = []
    while k < len(steps) and steps[k][0] in (_COMMAND, _PAYLOAD):
        if steps[k][0] == _COMMAND:
            tracks[steps[k][1]].append(steps[k][2])
        else:
            payload.append(steps[k][1])
        k += 1
    if k < len(steps) and steps[k][0] == _ISSUE and not payload:
        steps[k] = (_ISSUE, BlockCommands(tuple(tracks[0]), tuple(tracks[1]), tuple(tracks[2])))
        block.entry = k
    elif k < len(steps) and steps[k][0] == _SENSE and not any(tracks):
        steps[k] = (_SENSE, tuple(payload))
        block.entry = k


def _compile_tests(steps: list[_Step], start: int, bind: int) -> tuple[Check, ...] | None:
    """The tests of a search (steps `start` .. `bind`, after its NEXT_CANDIDATE) as the checks
    evaluate.py builds, in order; None when they are not pushes, comparisons and calls, each
    test closed by a JUMP_IF_FALSE with nothing left under it (what the verifier allows in a
    search), so they run step by step."""
    stack: list[Read] = []
    checks: list[Check] = []
    for k in range(start, bind):
        step = steps[k]
        code = step[0]
        if code == _PUSH:
            stack.append(step[2])
        elif code == _COMPARE and len(stack) >= 2:
            right = stack.pop()
            stack.append(comparison(step[1], stack.pop(), right))
        elif code == _CALL and len(stack) >= step[3]:
            at = len(stack) - step[3]
            args = stack[at:]
            del stack[at:]
            stack.append(call(step[1], step[2], args))
        elif code == _BRANCH and len(stack) == 1:
            checks.append(test_of(stack.pop()))
        else:
            return None
    return tuple(checks) if not stack else None


class VMProgram:
    """A verified bytecode program, ready to be loaded any number of times (the runtime
    `Loadable` interface)."""

    def __init__(self, verified: Verified, path: str = "", compile_searches: bool = True
                 ) -> None:
        if not isinstance(verified, Verified):
            raise TypeError("the VM runs verified programs only (bytecode.verify or load)")
        bytecode = verified.program
        self.bytecode = bytecode
        self.path = path
        self.name = bytecode.activity
        self.compile_searches = compile_searches
        text = bytecode.text
        self.alfa = tuple(self._message("alfa", m) for m in bytecode.alfa)
        self.omega = tuple(self._message("omega", m) for m in bytecode.omega)
        self.goal_ids = tuple(text(g.id) for g in bytecode.goals)
        self.positions = [BlockAddress(*a) for a in bytecode.addresses()]
        self.index: dict[tuple[int, int, int], int] = {
            p: i for i, p in enumerate(self.positions)}
        self.blocks = [self._block(i, listing) for i, listing in enumerate(verified.instructions)]

    def _message(self, kind: str, m: MessageRecord) -> RuleMessage:
        text = self.bytecode.text
        return RuleMessage(kind, m.rulecode, text(m.id), text(m.intopic), text(m.outtopic),
                           m.action, m.mutex)

    def _block(self, i: int, listing: Sequence[Instruction]) -> _Block:
        record = self.bytecode.blocks[i]
        block = _Block(record.kind, self.bytecode.text(record.label))
        block.offsets = [ins.offset for ins in listing]
        operands = _Operands(self.bytecode.constants,
                             {offset: k for k, offset in enumerate(block.offsets)})
        block.steps = steps = _steps(listing, operands)
        if block.kind == "J":
            block.condition = steps[0][2]  # COND starts every jump block
            if self.compile_searches:
                for k, step in enumerate(steps):
                    if step[0] == _FIND:
                        checks = _compile_tests(steps, k + 2, step[4])
                        if checks is not None:
                            block.searches[k] = checks
        else:
            _gather(block)
        return block

    def executor(self) -> VMExecutor:
        return VMExecutor(self)

    def mnemonic(self, block: int, pc: int) -> str:
        """The mnemonic of the instruction of step `pc` of a block."""
        return BY_CODE[self.bytecode.code[self.blocks[block].offsets[pc]]].name

    def where(self, block: int, pc: int) -> str:
        """`goal0/act0/blk1, line 11:33` for an instruction (for traps)."""
        path = self.positions[block].path
        offsets = self.blocks[block].offsets
        if not 0 <= pc < len(offsets):
            return path
        span = self.bytecode.span_at(offsets[pc])
        if span is None:
            return path
        position = self.bytecode.position(span.start)
        if position is None:
            return f"{path} (source offset {span.start})"
        return f"{path} (line {position[0]}, column {position[1]})"


def program_from_bytecode(program: Verified, path: str = "") -> VMProgram:
    """The runtime program of a verified bytecode program (`scriptc.bytecode.verify`)."""
    return VMProgram(program, path)


# ---------------------------------------------------------------------------------------------
# The executor


class VMExecutor(ExecutorBase[VMProgram]):
    """Block reading over verified bytecode (the `Executor` interface)."""

    def __init__(self, program: VMProgram) -> None:
        super().__init__(program)
        self._block = 0  # the block register
        self._pc: int | None = None  # None: arrive at the block; else resume at this step

    def start(self) -> None:
        self._block = 0
        self._pc = None
        self.position = None

    def seek(self, position: BlockAddress) -> None:
        self._block = self._index_of(position)
        self._pc = None

    def read(self, ctx: EvalContext, sink: ReadSink,
             max_blocks: int = MAX_BLOCKS_PER_READ) -> ReadResult:
        program = self.program
        blocks = program.blocks
        positions = program.positions
        n = len(blocks)
        i = self._block
        if self._pc is not None:
            # Resume after an ISSUE: the rest of that block (its NEXT_BLOCK).
            pc, self._pc = self._pc, None
            result = self._run(i, pc, ctx, sink)
            if not isinstance(result, int):
                return result
            i = result
        for _ in range(max_blocks):
            if i >= n:
                self._block = n
                return End(self.position, "past_end")
            position = positions[i]
            self.position = position
            sink.visit(position)
            result = self._run(i, blocks[i].entry, ctx, sink)
            if isinstance(result, int):
                i = result
                continue
            return result
        self._block = i
        raise ReadLimit(f"`{self.name}` read {max_blocks} blocks without reaching an "
                        "instruction block or its end (a jump cycle lets no time pass)")

    @overload
    def _run(self, i: int, pc: int, ctx: EvalContext, sink: ReadSink,
             this: None = None) -> int | ReadResult: ...

    @overload
    def _run(self, i: int, pc: int, ctx: EvalContext, sink: ReadSink,
             this: Entity) -> bool: ...

    def _run(self, i: int, pc: int, ctx: EvalContext, sink: ReadSink,
             this: Entity | None = None) -> int | ReadResult | bool:
        """Run block i's steps from `pc` until control leaves the block: the next block's
        index, an Issue or an End. With a candidate (`this`), run a search's tests from after
        its NEXT_CANDIDATE instead: True when they reach the BIND, False when one sends the
        candidate back to NEXT_CANDIDATE."""
        block = self.program.blocks[i]
        steps = block.steps
        stack: list[Value] = []
        fail = -1  # the failure handler, once COND has set it
        try:
            while True:
                step = steps[pc]
                code = step[0]
                if code == _PUSH:
                    stack.append(step[1](this, ctx))
                elif code == _CALL:
                    argc = step[3]
                    if argc:
                        args = stack[-argc:]
                        del stack[-argc:]
                    else:
                        args = []
                    stack.append(invoke(ctx, step[1], step[2], args, this))
                elif code == _BRANCH:
                    if not stack.pop():
                        if step[1] < pc:
                            return False  # back to NEXT_CANDIDATE: the candidate is rejected
                        pc = step[1]
                        continue
                elif code == _COMPARE:
                    right = stack.pop()
                    stack.append(compare_op(step[1], stack.pop(), right))
                elif code == _FIND:
                    if not self._search(i, pc, step, ctx, sink):
                        stack.clear()
                        pc = fail
                        continue
                    pc = step[4]  # the BIND: the search is over
                elif code == _ASSIGN:
                    if not step[1](ctx, stack.pop()):
                        stack.clear()
                        pc = fail
                        continue
                elif code == _BOUND:
                    if ctx.lookup(step[1]) is None:
                        stack.clear()
                        pc = fail
                        continue
                elif code == _COND:
                    ctx.begin(READER, ctx.now)
                    stack.clear()
                    fail = step[1]
                elif code == _EXIT:
                    j = i + 1 if step[1] is None else step[1]
                    if fail >= 0:  # a jump's exit: true before the handler, false after
                        positions = self.program.positions
                        sink.jump(positions[i], block.condition, ctx.result(pc < fail),
                                  positions[j] if j < len(positions) else None)
                    return j
                elif code == _ISSUE:
                    self._block, self._pc = i, pc + 1
                    return Issue(self.program.positions[i], step[1], block.label)
                elif code == _SENSE:
                    sink.sensor(self.program.positions[i], step[1])
                elif code == _END:
                    self._block = len(self.program.blocks)
                    return End(self.program.positions[i], "terminus")
                elif code == _BIND and this is not None:
                    return True
                else:
                    # NEXT_CANDIDATE and BIND run within a search (FIND runs it whole), the
                    # commands and payloads of a block before its ISSUE or SENSE (gathered at
                    # load): the verifier keeps them there.
                    raise VMTrap(f"{self.program.where(i, pc)}: "
                                 f"{self.program.mnemonic(i, pc)} cannot run here")
                pc += 1
        except (ReadLimit, VMTrap):
            raise
        except Exception as exc:  # a trap, never a crash of the session
            raise VMTrap(f"{self.program.where(i, pc)}: "
                         f"{type(exc).__name__}: {exc}") from exc

    def _search(self, i: int, at: int, step: _Step, ctx: EvalContext, sink: ReadSink) -> bool:
        """The search the FIND step `at` of block i starts, as one `assign_class` call (its
        tests, run step by step, read with the same sink: they never reach an exit)."""
        _code, cls, alias, scope, _bind = step
        checks = self.program.blocks[i].searches.get(at)
        if checks is None:
            start = at + 2  # after the NEXT_CANDIDATE

            def tests(entity: Entity, ctx: EvalContext) -> bool:
                return self._run(i, start, ctx, sink, entity)

            checks = (tests,)
        return ctx.assign_class(alias, cls, scope, checks)
