"""The reference interpreter: an executor (see `executor.py`) that reads a script's blocks
straight from the IR. It is the executable spec of the block reader, kept simple on purpose:
a flat list of blocks in execution order (goal by goal, action by action, block by block), a
label table, and one loop.

- an instruction block is returned as plain values (`BlockCommands`) and reading stops;
- a jump evaluates its condition with the shared evaluator (`evaluate.py`) and goes to its
  true or false target; an empty target is the next block in order (docs/language.md); a label
  carried by several blocks names the first of them (as the checker reads it, L001);
- a sensor block is reported and reading goes on;
- a terminus ends the script; so does running past the last block.

Everything else (time, actuators, rules, goal records) is the session's: a bytecode VM is
another executor beside this one, and shares all of it.
"""

from __future__ import annotations

import math

from scriptc.ir import nodes as ir
from scriptc.runtime.bindings import READER
from scriptc.runtime.commands import Audio, BlockAddress, BlockCommands, Led, Move, RuleMessage
from scriptc.runtime.evaluate import EvalContext, evaluate
from scriptc.runtime.executor import End, ExecutorBase, Issue, ReadLimit, ReadResult, ReadSink

MAX_BLOCKS_PER_READ = 100_000


class JumpTargetError(RuntimeError):
    """A jump names a label no block carries (only in scripts that were not checked: L003)."""


def _float(number: ir.Number) -> float:
    value = number.value
    return value if value is not None and math.isfinite(value) else 0.0


def _ms(number: ir.Number) -> int:
    """A time in whole milliseconds. Checked scripts hold whole numbers >= 0 (V006); an
    unchecked script's other values are rounded and clamped at 0."""
    value = number.value
    if value is None or not math.isfinite(value) or value < 0:
        return 0
    return round(value)


def instruction_of(block: ir.InstructionBlock) -> BlockCommands:
    """An instruction block's commands as plain run-time values."""
    return BlockCommands(
        tuple(Move(_float(m.v_x), _float(m.v_y), _float(m.v_theta), _ms(m.wait_t), _ms(m.duration))
              for m in block.moves),
        tuple(Led(_float(c.r), _float(c.g), _float(c.b), 1 if _float(c.turnas) == 1 else 0,
                  _ms(c.wait_t), _ms(c.duration)) for c in block.leds),
        tuple(Audio(a.track_path.value, _ms(a.wait_t), _ms(a.duration)) for a in block.audios),
    )


def message_of(message: ir.RuleMessage) -> RuleMessage:
    value = message.rulecode.value
    code = int(value) if value is not None and math.isfinite(value) and value >= 0 else 0
    return RuleMessage(message.kind, code, message.id.text, message.intopic.value,
                       message.outtopic.value, message.action.text, message.mutex.text)


class IRProgram:
    """A checked (or at least lowered) script, ready to be loaded any number of times."""

    def __init__(self, script: ir.Script, path: str = "") -> None:
        from scriptc.emit.condition import condition_text

        self.script = script
        self.name = script.name.text
        self.path = path
        self.blocks = script.blocks()
        self.alfa = tuple(message_of(m) for m in script.alfa)
        self.omega = tuple(message_of(m) for m in script.omega)
        self.goal_ids = tuple(g.id.text for g in script.goals)
        self.labels: dict[str, int] = {}
        self.index: dict[tuple[int, int, int], int] = {}
        self.instructions: dict[int, BlockCommands] = {}
        self.conditions: dict[int, str] = {}
        for i, (address, block) in enumerate(self.blocks):
            self.index[address] = i
            if block.label is not None and block.label.text:
                self.labels.setdefault(block.label.text, i)
            if isinstance(block, ir.InstructionBlock):
                self.instructions[i] = instruction_of(block)
            elif isinstance(block, ir.JumpBlock):
                self.conditions[i] = condition_text(block.condition)

    def executor(self) -> IRExecutor:
        return IRExecutor(self)

    def target(self, name: ir.Name | None, i: int) -> int:
        """Where the jump at block `i` goes to the block labelled `name`: its index (the
        first block carrying the label), or `i + 1` for an empty target (the block count
        when that is past the last block). The one reading of a jump's target: the block
        reader here and `scriptc verify` follow it."""
        if name is None or not name.text:
            return i + 1
        j = self.labels.get(name.text)
        if j is None:
            raise JumpTargetError(f"the jump at {BlockAddress(*self.blocks[i][0]).path} "
                                  f"names label `{name.text}`, which no block carries")
        return j


class IRExecutor(ExecutorBase[IRProgram]):
    """Block reading over the IR (the `Executor` interface)."""

    def __init__(self, program: IRProgram) -> None:
        super().__init__(program)
        self._next = 0

    def start(self) -> None:
        self._next = 0
        self.position = None

    def seek(self, position: BlockAddress) -> None:
        self._next = self._index_of(position)

    def read(self, ctx: EvalContext, sink: ReadSink,
             max_blocks: int = MAX_BLOCKS_PER_READ) -> ReadResult:
        blocks = self.program.blocks
        n = len(blocks)
        i = self._next
        for _ in range(max_blocks):
            if i >= n:
                self._next = n
                return End(self.position, "past_end")
            address, block = blocks[i]
            position = BlockAddress(*address)
            self.position = position
            sink.visit(position)
            if isinstance(block, ir.InstructionBlock):
                self._next = i + 1
                label = block.label.text if block.label is not None else ""
                return Issue(position, self.program.instructions[i], label)
            if isinstance(block, ir.JumpBlock):
                ctx.begin(READER, ctx.now)
                evaluation = evaluate(block.condition, ctx)
                target = block.true_target if evaluation.value else block.false_target
                j = self.program.target(target, i)
                sink.jump(position, self.program.conditions[i], evaluation,
                          BlockAddress(*blocks[j][0]) if j < n else None)
                i = j
            elif isinstance(block, ir.TerminusBlock):
                self._next = n
                return End(position, "terminus")
            else:  # SensorBlock
                sink.sensor(position, tuple(t.value for t in block.payload))
                i += 1
        self._next = i
        raise ReadLimit(f"`{self.name}` read {max_blocks} blocks without reaching an "
                        "instruction block or its end (a jump cycle lets no time pass)")
