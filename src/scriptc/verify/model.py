"""A script as the exploration reads it: its blocks in execution order, each with what reading
it does, taken from the runtime's own program (`runtime/interp.py`'s `IRProgram`: the same
block list, the same label table and jump targets as the block reader, the same commands and
block lengths as the actuators) and, for each jump, how its condition can come out
(`conditions.py`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from scriptc.ir import nodes as ir
from scriptc.runtime.commands import BlockAddress
from scriptc.verify.conditions import Outcomes, outcomes_of

if TYPE_CHECKING:
    from scriptc.runtime.functions import Implementations
    from scriptc.runtime.interp import IRProgram
    from scriptc.source import Span

INSTRUCTION, JUMP, TERMINUS, SENSOR = "instruction", "jump", "terminus", "sensor"


@dataclass(frozen=True, slots=True)
class Step:
    """One block: its index in execution order, where it is, its kind, the goal it belongs to
    (an index), its label ("" when none) and its span; for an instruction block its `length`
    (ms from issue to consumption: `BlockCommands.length`); `next` the block that follows in
    order (the block count: past the last block); for a jump where each outcome goes and how
    the condition can come out."""

    index: int
    address: BlockAddress
    kind: str
    goal: int
    label: str
    span: Span
    length: int = 0
    next: int = 0
    on_true: int = 0
    on_false: int = 0
    outcomes: Outcomes | None = None
    condition: str = ""  # a jump's condition, canonical text (as the trace shows it)


class Model:
    """The steps of one script (see the module's docstring). `name` is the activity's,
    `goal_ids` its goals', `end` the index that stands for past the last block."""

    def __init__(self, program: IRProgram, functions: Implementations | None = None) -> None:
        self.program = program
        self.name = program.name
        self.goal_ids = program.goal_ids
        script = program.script
        self.goal_spans = tuple(g.span for g in script.goals)
        blocks = program.blocks
        self.end = len(blocks)
        # One alias for the Activity everywhere: its CLASS tests are the robot's clock. With
        # several, one alias per entity can refuse the second: the world's, for verify.
        activity_aliases = {a.alias.name.text for _, block in blocks
                            if isinstance(block, ir.JumpBlock)
                            for a in block.condition.assignments
                            if isinstance(a, ir.ClassAssignment)
                            and a.class_name.text == "Activity"}
        exact = len(activity_aliases) <= 1
        steps: list[Step] = []
        for i, (address, block) in enumerate(blocks):
            where = BlockAddress(*address)
            label = block.label.text if block.label is not None else ""
            if isinstance(block, ir.InstructionBlock):
                steps.append(Step(i, where, INSTRUCTION, address[0], label, block.span,
                                  length=program.instructions[i].length, next=i + 1))
            elif isinstance(block, ir.JumpBlock):
                outcomes = outcomes_of(block.condition, activity=self.name,
                                       exact_activity=exact, functions=functions)
                steps.append(Step(i, where, JUMP, address[0], label, block.span, next=i + 1,
                                  on_true=program.target(block.true_target, i),
                                  on_false=program.target(block.false_target, i),
                                  outcomes=outcomes, condition=program.conditions[i]))
            else:
                kind = TERMINUS if isinstance(block, ir.TerminusBlock) else SENSOR
                steps.append(Step(i, where, kind, address[0], label, block.span, next=i + 1))
        self.steps = tuple(steps)

    def goal_of(self, index: int) -> int:
        return self.steps[index].goal
