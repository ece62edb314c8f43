"""The bytecode VM: an executor (`executor.py`) that runs a verified `.scb` program
(docs/bytecode.md, "Running a program"). It is the executor `scriptc run` uses; the reference
interpreter over the IR (`interp.py`) is the executable spec it must agree with, trace for
trace (tests/test_runtime_cases.py runs every case through both; tests/test_vm_differential.py
runs generated scripts and scenarios through both).

It knows nothing of the IR and never parses: its input is a `scriptc.bytecode.Program` that
`scriptc.bytecode.load` (decode + verify) returned, and its only partners are the runtime's
shared modules: the session through the `ReadSink`, the map through `EvalContext`'s primitives.

How it runs (the registers of docs/bytecode.md):

- **Loading** decodes each block's code once into a list of instructions whose operands are
  resolved (names and texts to str, numbers to their values, jump offsets to indices in the
  block's list). The verifier has already proved what the loop below relies on: operands in
  range, jumps inside the block, a stack that never underflows and holds truth values where
  they are popped, searches well formed, exits with an empty stack.
- **The block reader** has two registers, the block and `pc` (an index in the block's list).
  `read` arrives at a block (the session's `visit`), runs its instructions until one transfers
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
  each search's tests are translated once into closures over the entity (a symbolic run of
  the stack: value pushes become getters, `COMPARE` and `CALL_B` become checks, each
  `JUMP_IF_FALSE` back to `NEXT_CANDIDATE` closes one test). `VMProgram(...,
  compile_searches=False)` interprets them instruction by instruction instead (the plain
  meaning; tests hold the two equal).
- **Traps.** A verified program cannot make the VM misbehave, but a run can still go wrong
  in a way the script is to blame for at run time. Function failures are the context's
  (reported, the call counts as false / missing: docs/bytecode.md). Anything else that goes
  wrong while an instruction runs becomes a `VMTrap` (a RuntimeError carrying the block's path
  and the source position from the code span table), which the session reports in the trace
  as a fatal `read` error: never an exception out of the session.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable

from scriptc.bytecode.code import instructions
from scriptc.bytecode.opcodes import BY_NAME
from scriptc.bytecode.program import Num
from scriptc.bytecode.program import Program as Bytecode
from scriptc.runtime.bindings import READER
from scriptc.runtime.evaluate import EvalContext
from scriptc.runtime.executor import End, ExecutorBase, Issue, ReadLimit, ReadResult, ReadSink
from scriptc.runtime.commands import Audio, Instruction, Led, Move, Position, RuleMessage, compare_op
from scriptc.runtime.world import Entity

__all__ = ["VMProgram", "VMExecutor", "VMTrap", "program_from_bytecode"]

MAX_BLOCKS_PER_READ = 100_000

# Opcode numbers (the table's), as plain ints for the dispatch.
_OP = {name: op.code for name, op in BY_NAME.items()}
MOVE, LED, AUDIO, ISSUE = _OP["MOVE"], _OP["LED"], _OP["AUDIO"], _OP["ISSUE"]
PAYLOAD, SENSE, END, GOTO, NEXT_BLOCK = (_OP["PAYLOAD"], _OP["SENSE"], _OP["END"], _OP["GOTO"],
                                        _OP["NEXT_BLOCK"])
COND, JUMP_IF_FALSE = _OP["COND"], _OP["JUMP_IF_FALSE"]
FIND, NEXT_CANDIDATE, BIND = _OP["FIND"], _OP["NEXT_CANDIDATE"], _OP["BIND"]
SET_VAR, SET_ATT, BOUND = _OP["SET_VAR"], _OP["SET_ATT"], _OP["BOUND"]
PUSH_CONST, PUSH_VAR, PUSH_ALIAS, PUSH_FIELD, PUSH_ATT, PUSH_THIS, PUSH_THIS_FIELD = (
    _OP["PUSH_CONST"], _OP["PUSH_VAR"], _OP["PUSH_ALIAS"], _OP["PUSH_FIELD"], _OP["PUSH_ATT"],
    _OP["PUSH_THIS"], _OP["PUSH_THIS_FIELD"])
COMPARE, CALL_B, CALL_F, CALL_E = _OP["COMPARE"], _OP["CALL_B"], _OP["CALL_F"], _OP["CALL_E"]

_EXITS = (GOTO, NEXT_BLOCK)
_FAST_OPS = {"OP<": operator.lt, "OP>": operator.gt, "OP=": operator.eq}


class VMTrap(RuntimeError):
    """Something went wrong while an instruction ran (the script's fault at run time): the
    session reports it as a fatal `read` error in the trace."""


# A decoded instruction: (opcode number, operands resolved...). Jump operands are indices in
# the block's instruction list; block operands stay block indices.
Op = tuple


class _Block:
    __slots__ = ("kind", "label", "ops", "offsets", "searches", "condition")

    def __init__(self, kind: str, label: str) -> None:
        self.kind = kind
        self.label = label
        self.ops: list[Op] = []
        self.offsets: list[int] = []  # code offset of each instruction (for spans)
        self.searches: dict[int, tuple] = {}  # FIND index -> compiled tests
        self.condition = ""


def _cmp(op: int) -> str:
    return "OP" + chr(op)


class VMProgram:
    """A verified bytecode program, ready to be loaded any number of times (the runtime
    `Program` interface)."""

    def __init__(self, bytecode: Bytecode, path: str = "", compile_searches: bool = True) -> None:
        self.bytecode = bytecode
        self.path = path
        self.name = bytecode.activity
        self.compile_searches = compile_searches
        text = bytecode.text
        self.alfa = tuple(self._message("alfa", m) for m in bytecode.alfa)
        self.omega = tuple(self._message("omega", m) for m in bytecode.omega)
        self.goal_ids = tuple(text(g.id) for g in bytecode.goals)
        self.positions = [Position(*a) for a in bytecode.addresses()]
        self.index = {tuple(p): i for i, p in enumerate(self.positions)}
        self.blocks = [self._decode(i) for i in range(len(bytecode.blocks))]

    def _message(self, kind: str, m) -> RuleMessage:
        text = self.bytecode.text
        return RuleMessage(kind, m.rulecode, text(m.id), text(m.intopic), text(m.outtopic),
                           m.action, m.mutex)

    def _constant(self, index: int):
        value = self.bytecode.constants[index]
        return value.value if isinstance(value, Num) else value

    def _decode(self, i: int) -> _Block:
        bc = self.bytecode
        record = bc.blocks[i]
        block = _Block(record.kind, bc.text(record.label))
        listing = list(instructions(bc.code, record.code, bc.block_end(i)))
        where = {ins.offset: k for k, ins in enumerate(listing)}
        text, const = bc.text, self._constant
        for ins in listing:
            op, o = ins.opcode.code, ins.operands
            if op == MOVE:
                decoded = (op, const(o[0]), const(o[1]), const(o[2]), o[3], o[4])
            elif op == LED:
                decoded = (op, const(o[0]), const(o[1]), const(o[2]), o[3], o[4], o[5])
            elif op == AUDIO:
                decoded = (op, text(o[0]), o[1], o[2])
            elif op == PAYLOAD:
                decoded = (op, text(o[0]))
            elif op == GOTO:
                decoded = (op, o[0])
            elif op == COND:
                block.condition = text(o[1])
                decoded = (op, where[o[0]], text(o[1]))
            elif op == JUMP_IF_FALSE:
                decoded = (op, where[o[0]])
            elif op == FIND:
                decoded = (op, text(o[0]), text(o[1]), chr(o[2]), where[o[3]])
            elif op == SET_VAR:
                decoded = (op, chr(o[0]), text(o[1]))
            elif op == SET_ATT:
                decoded = (op, chr(o[0]), text(o[1]), text(o[2]))
            elif op == PUSH_CONST:
                decoded = (op, const(o[0]))
            elif op == COMPARE:
                decoded = (op, _cmp(o[0]))
            elif op in (CALL_B, CALL_F, CALL_E):
                decoded = (op, text(o[0]), o[1])
            else:  # names only, or no operand
                decoded = (op, *(text(x) for x in o))
            block.ops.append(decoded)
            block.offsets.append(ins.offset)
        if self.compile_searches:
            for k, decoded in enumerate(block.ops):
                if decoded[0] == FIND:
                    block.searches[k] = _compile_search(block.ops, k + 2, decoded[4])
        return block

    def executor(self) -> VMExecutor:
        return VMExecutor(self)

    def where(self, block: int, pc: int) -> str:
        """`goal0/act0/blk1, line 11:33` for an instruction (for traps)."""
        path = self.positions[block].path
        ops = self.blocks[block].offsets
        if not 0 <= pc < len(ops):
            return path
        span = self.bytecode.span_at(ops[pc])
        if span is None:
            return path
        position = self.bytecode.position(span.start)
        if position is None:
            return f"{path} (source offset {span.start})"
        return f"{path} (line {position[0]}, column {position[1]})"


def program_from_bytecode(program: Bytecode, path: str = "") -> VMProgram:
    """The runtime `Program` of a verified bytecode program (`scriptc.bytecode.load`)."""
    return VMProgram(program, path)


# ---------------------------------------------------------------------------------------------
# Searches, translated to closures


Getter = Callable[[Entity, EvalContext], object]
Check = Callable[[Entity, EvalContext], bool]


def _getter(op: Op) -> tuple[Getter, object]:
    """A value push as a getter over (THIS, ctx); the second item is the constant, if any."""
    code = op[0]
    if code == PUSH_CONST:
        value = op[1]
        return (lambda e, ctx: value), value
    if code == PUSH_VAR:
        name = op[1]
        return (lambda e, ctx: ctx.var(name)), None
    if code == PUSH_ALIAS:
        alias = op[1]

        def alias_id(e, ctx):
            entity = ctx.lookup(alias)
            return None if entity is None else entity.id

        return alias_id, None
    if code == PUSH_FIELD:
        alias, name = op[1], op[2]
        return (lambda e, ctx: ctx.field(ctx.lookup(alias), name)), None
    if code == PUSH_ATT:
        alias, name = op[1], op[2]
        return (lambda e, ctx: ctx.att(alias, name)), None
    if code == PUSH_THIS:
        return (lambda e, ctx: e.id), None
    if code == PUSH_THIS_FIELD:
        name = op[1]
        return (lambda e, ctx: e.fields.get(name)), None
    raise VMTrap(f"instruction {code:#x} inside a search")


def _compare_check(op: str, left: Op, right: Op, lget: Getter, rget: Getter,
                   constant) -> Check:
    if (left[0] == PUSH_THIS_FIELD and right[0] == PUSH_CONST and isinstance(constant, float)
            and math.isfinite(constant) and op in _FAST_OPS):
        # `?THIS>&f OP number`, the common test: a numeric field is compared directly (the
        # meaning of compare_op for two numbers), anything else through compare_op.
        fast, name = _FAST_OPS[op], left[1]

        def check(e, ctx):
            v = e.fields.get(name)
            kind = type(v)
            if kind is float or kind is int:
                return fast(v, constant)
            return v is not None and compare_op(op, v, constant)

        return check
    return lambda e, ctx: compare_op(op, lget(e, ctx), rget(e, ctx))


def _call_check(name: str, args: list[Getter]) -> Check:
    if not args:
        return lambda e, ctx: bool(ctx.call(name, "B", [], e))
    if len(args) == 1:
        (a,) = args
        return lambda e, ctx: bool(ctx.call(name, "B", [a(e, ctx)], e))
    return lambda e, ctx: bool(ctx.call(name, "B", [g(e, ctx) for g in args], e))


def _compile_search(ops: list[Op], start: int, bind: int) -> tuple[Check, ...]:
    """The tests of a search (instructions `start` .. `bind`, after its NEXT_CANDIDATE) as
    checks over (THIS, ctx), in order. The verifier allows only value pushes, COMPARE, CALL_B
    and JUMP_IF_FALSE back to NEXT_CANDIDATE there, and the stack is empty at each jump back."""
    stack: list = []  # (op, getter, constant) for values; ("b", check) for truth values
    checks: list[Check] = []
    for k in range(start, bind):
        op = ops[k]
        code = op[0]
        if code == COMPARE:
            right, left = stack.pop(), stack.pop()
            stack.append(("b", _compare_check(op[1], left[0], right[0], left[1], right[1],
                                              right[2])))
        elif code == CALL_B:
            argc = op[2]
            args = [g for _, g, _ in stack[len(stack) - argc:]]
            del stack[len(stack) - argc:]
            stack.append(("b", _call_check(op[1], args)))
        elif code == JUMP_IF_FALSE:
            checks.append(stack.pop()[1])
        else:
            getter, constant = _getter(op)
            stack.append((op, getter, constant))
    return tuple(checks)


# ---------------------------------------------------------------------------------------------
# The executor


class _Fail(Exception):
    """An instruction failed (docs/bytecode.md, "Failure"): continue at the handler."""


class VMExecutor(ExecutorBase):
    """Block reading over verified bytecode (the `Executor` interface)."""

    def __init__(self, program: VMProgram) -> None:
        super().__init__(program)
        self._block = 0  # the block register
        self._pc: int | None = None  # None: arrive at the block; else resume at this index

    def start(self) -> None:
        self._block = 0
        self._pc = None
        self.position = None

    def seek(self, position: Position) -> None:
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
            i = self._transfer(i, pc, ctx, sink)
            if isinstance(i, End):
                return i
        for _ in range(max_blocks):
            if i >= n:
                self._block = n
                return End(self.position, "past_end")
            position = positions[i]
            self.position = position
            sink.visit(position)
            result = self._run(i, ctx, sink)
            if isinstance(result, int):
                i = result
                continue
            return result
        self._block = i
        raise ReadLimit(f"`{self.name}` read {max_blocks} blocks without reaching an "
                        "instruction block or its end (a jump cycle lets no time pass)")

    def _transfer(self, i: int, pc: int, ctx: EvalContext, sink: ReadSink):
        """Run block i from pc (after an ISSUE) to its end: the next block's index."""
        ops = self.program.blocks[i].ops
        code = ops[pc][0]
        if code == NEXT_BLOCK:
            return i + 1
        return self._run(i, ctx, sink, pc)

    def _run(self, i: int, ctx: EvalContext, sink: ReadSink, pc: int = 0):
        """Run block i's code from pc until control leaves it: the next block's index, an
        Issue or an End."""
        block = self.program.blocks[i]
        try:
            if block.kind == "J":
                return self._jump(i, block, ctx, sink)
            return self._straight(i, block, sink, pc)
        except (ReadLimit, VMTrap):
            raise
        except Exception as exc:  # noqa: BLE001 - a trap, never a crash of the session
            raise VMTrap(f"{self.program.where(i, self._trap_pc)}: "
                         f"{type(exc).__name__}: {exc}") from exc

    _trap_pc = 0

    def _straight(self, i: int, block: _Block, sink: ReadSink, pc: int):
        """Instruction, sensor and terminus blocks: no control flow but their ends."""
        ops = block.ops
        moves: list[Move] = []
        leds: list[Led] = []
        audios: list[Audio] = []
        payload: list[str] = []
        while True:
            self._trap_pc = pc
            op = ops[pc]
            code = op[0]
            if code == MOVE:
                moves.append(Move(op[1], op[2], op[3], op[4], op[5]))
            elif code == LED:
                leds.append(Led(op[1], op[2], op[3], op[4], op[5], op[6]))
            elif code == AUDIO:
                audios.append(Audio(op[1], op[2], op[3]))
            elif code == ISSUE:
                self._block, self._pc = i, pc + 1
                return Issue(self.program.positions[i],
                             Instruction(tuple(moves), tuple(leds), tuple(audios)), block.label)
            elif code == PAYLOAD:
                payload.append(op[1])
            elif code == SENSE:
                sink.sensor(self.program.positions[i], tuple(payload))
                payload = []
            elif code == NEXT_BLOCK:
                return i + 1
            elif code == GOTO:
                return op[1]
            elif code == END:
                self._block = len(self.program.blocks)
                return End(self.program.positions[i], "terminus")
            else:
                raise VMTrap(f"opcode {code:#x} in a block of kind {block.kind}")
            pc += 1

    def _jump(self, i: int, block: _Block, ctx: EvalContext, sink: ReadSink):
        """A jump block: the condition on the stack machine, then the exit taken."""
        ops = block.ops
        stack: list = []
        fail = len(ops)
        pc = 0
        while True:
            self._trap_pc = pc
            op = ops[pc]
            code = op[0]
            pc += 1
            try:
                if code == PUSH_CONST:
                    stack.append(op[1])
                elif code == PUSH_FIELD:
                    stack.append(ctx.field(ctx.lookup(op[1]), op[2]))
                elif code == PUSH_VAR:
                    stack.append(ctx.var(op[1]))
                elif code == PUSH_ATT:
                    stack.append(ctx.att(op[1], op[2]))
                elif code == PUSH_ALIAS:
                    entity = ctx.lookup(op[1])
                    stack.append(None if entity is None else entity.id)
                elif code == CALL_E or code == CALL_F:
                    argc = op[2]
                    if argc:
                        args = stack[-argc:]
                        del stack[-argc:]
                    else:
                        args = []
                    result = ctx.call(op[1], "E" if code == CALL_E else "F", args, None)
                    stack.append(bool(result) if code == CALL_E else result)
                elif code == JUMP_IF_FALSE:
                    if not stack.pop():
                        pc = op[1]
                elif code == COMPARE:
                    right = stack.pop()
                    stack.append(compare_op(op[1], stack.pop(), right))
                elif code == FIND:
                    if op[1] not in ctx.world.classes:
                        # Codegen writes only the classes of the map; a program that names
                        # another is at fault when it runs.
                        raise VMTrap(f"{self.program.where(i, pc - 1)}: FIND: the map has "
                                     f"no class `{op[1]}`")
                    if not self._search(block, pc - 1, op, ctx):
                        raise _Fail
                    pc = op[4] + 1  # after the BIND
                elif code == SET_VAR:
                    if not ctx.assign_var(op[2], stack.pop(), op[1]):
                        raise _Fail
                elif code == SET_ATT:
                    if not ctx.assign_att(op[2], op[3], stack.pop(), op[1]):
                        raise _Fail
                elif code == BOUND:
                    if ctx.lookup(op[1]) is None:
                        raise _Fail
                elif code == COND:
                    ctx.begin(READER, ctx.now)
                    stack.clear()
                    fail = op[1]
                elif code == GOTO or code == NEXT_BLOCK:
                    value = pc - 1 < fail
                    j = op[1] if code == GOTO else i + 1
                    positions = self.program.positions
                    sink.jump(positions[i], block.condition, ctx.result(value),
                              positions[j] if j < len(positions) else None)
                    return j
                else:
                    # NEXT_CANDIDATE, BIND, PUSH_THIS, PUSH_THIS_FIELD, CALL_B run inside a
                    # search (FIND runs it whole); the verifier keeps them there.
                    raise VMTrap(f"{self.program.where(i, pc - 1)}: opcode {code:#x} "
                                 "outside a search")
            except _Fail:
                stack.clear()
                pc = fail

    def _search(self, block: _Block, at: int, op: Op, ctx: EvalContext) -> bool:
        """The search FIND starts (at index `at`) as one `assign_class` call."""
        checks = block.searches.get(at)
        if checks is not None:
            if len(checks) == 1:
                (check,) = checks

                def passes(entity: Entity) -> bool:
                    return check(entity, ctx)
            else:
                def passes(entity: Entity) -> bool:
                    for check in checks:
                        if not check(entity, ctx):
                            return False
                    return True
        else:
            ops = block.ops
            start, bind = at + 2, op[4]

            def passes(entity: Entity) -> bool:
                return _run_tests(ops, start, bind, entity, ctx)

        return ctx.assign_class(op[2], op[1], op[3], passes)


def _run_tests(ops: list[Op], start: int, bind: int, this: Entity, ctx: EvalContext) -> bool:
    """A search's tests interpreted instruction by instruction with THIS = `this`: True when
    they reach the BIND, False when a JUMP_IF_FALSE goes back to NEXT_CANDIDATE."""
    stack: list = []
    pc = start
    while pc < bind:
        op = ops[pc]
        code = op[0]
        pc += 1
        if code == PUSH_THIS_FIELD:
            stack.append(this.fields.get(op[1]))
        elif code == PUSH_CONST:
            stack.append(op[1])
        elif code == PUSH_THIS:
            stack.append(this.id)
        elif code == PUSH_FIELD:
            stack.append(ctx.field(ctx.lookup(op[1]), op[2]))
        elif code == PUSH_VAR:
            stack.append(ctx.var(op[1]))
        elif code == PUSH_ATT:
            stack.append(ctx.att(op[1], op[2]))
        elif code == PUSH_ALIAS:
            entity = ctx.lookup(op[1])
            stack.append(None if entity is None else entity.id)
        elif code == COMPARE:
            right = stack.pop()
            stack.append(compare_op(op[1], stack.pop(), right))
        elif code == CALL_B:
            argc = op[2]
            args = stack[len(stack) - argc:]
            del stack[len(stack) - argc:]
            stack.append(bool(ctx.call(op[1], "B", args, this)))
        elif code == JUMP_IF_FALSE:
            if not stack.pop():
                return False  # back to NEXT_CANDIDATE: the candidate is rejected
        else:
            raise VMTrap(f"opcode {code:#x} inside a search")
    return True
