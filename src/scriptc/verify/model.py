"""A script as the exploration reads it: its blocks in execution order, each with what reading
it does, taken from the runtime's own program (`runtime/interp.py`'s `IRProgram`: the same
block list, the same label table and jump targets as the block reader, the same commands and
block lengths as the actuators) and, for each jump, how its condition can come out
(`conditions.py`); and the rules its alfa messages bring into the chain, as the rule library
the run uses makes them (`runtime/rules.py`):

- `kick_starter` and `safety_stop` change no block and switch no script (the safety stop
  holds the wheels while the block's clock goes on): nothing to model;
- an `override` (the library's rulecode 2) is a `Switch`: when its condition `when` holds at a
  pass of the chain, once, the reader goes to its block (`at`, `goal`), or, for another
  script, this script's run ends;
- any other rule (a repository's own, a rulecode the library does not know, a library entry a
  repository replaced) is assumed to change no block and switch no script: `assumed` says so.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from scriptc.ir import nodes as ir
from scriptc.runtime.bindings import SCOPE_RANK
from scriptc.runtime.commands import BlockAddress, BlockCommands
from scriptc.verify.conditions import (
    UNSET,
    Branch,
    Outcomes,
    Valuation,
    branches_of,
    outcomes_of,
    tracked_variables,
)

if TYPE_CHECKING:
    from scriptc.runtime.functions import Implementations
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.rules import RuleLibrary
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
    # An instruction block's instants, as offsets from its issue: 0 and each change of phase
    # of a track before its end (a command starting or stopping): the actuators' events, at
    # which the run passes the chain of rules whatever the world does.
    instants: tuple[int, ...] = (0,)


@dataclass(frozen=True, slots=True)
class Switch:
    """An override rule of the script's alfa messages: its `bit` in a run's set of fired
    switches, its rule `id`, how its condition `when` can come out, where it goes (`target`,
    a block index; `ENDS`: another script, this script's run ends there) and the span of the
    alfa message that brings it."""

    bit: int
    id: str
    when: Outcomes
    target: int
    span: Span
    condition: ir.Condition  # `when`, as the rule reads it


ENDS = -1  # a switch's target that is another script


class Model:
    """The steps of one script (see the module's docstring). `name` is the activity's,
    `goal_ids` its goals', `end` the index that stands for past the last block, `switches`
    its override rules and `assumed` what verify assumes of its other rules."""

    def __init__(self, program: IRProgram, functions: Implementations | None = None,
                 rules: RuleLibrary | None = None) -> None:
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
                commands = program.instructions[i]
                steps.append(Step(i, where, INSTRUCTION, address[0], label, block.span,
                                  length=commands.length, next=i + 1,
                                  instants=_instants(commands)))
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
        self.switches, self.assumed = _rules(program, rules, exact, functions)
        # The variables verify tracks (conditions.tracked_variables), and the valuations of
        # them runs reach, numbered as met (0: every one unset, as a run starts).
        self.exact = exact
        self.functions = functions
        jumps = [b.condition for _, b in blocks if isinstance(b, ir.JumpBlock)]
        self.tracked = tracked_variables(jumps, [s.condition for s in self.switches],
                                         functions)
        self.valuations: list[Valuation] = [tuple((name, None, UNSET)
                                                  for name in sorted(self.tracked))]
        self._valuation_ids: dict[Valuation, int] = {self.valuations[0]: 0}
        self._branches: dict[tuple[int, int], list[tuple[Branch, int]]] = {}

    def valuation_id(self, valuation: Valuation) -> int:
        """The number of a valuation of the tracked variables (given when first met)."""
        found = self._valuation_ids.get(valuation)
        if found is None:
            found = self._valuation_ids[valuation] = len(self.valuations)
            self.valuations.append(valuation)
        return found

    def branches(self, index: int, valuation: int) -> list[tuple[Branch, int]]:
        """How the jump at block `index` can come out under the valuation numbered
        `valuation`: each branch with the number of the valuation after it."""
        key = (index, valuation)
        found = self._branches.get(key)
        if found is None:
            step = self.steps[index]
            assert step.outcomes is not None
            if not self.tracked:
                outcomes = step.outcomes
                found = [(Branch(True, outcomes.true_at, (), outcomes.world), 0),
                         (Branch(False, outcomes.false_at, (), outcomes.world), 0)]
            else:
                block = self.program.blocks[index][1]
                assert isinstance(block, ir.JumpBlock)
                found = [(b, self.valuation_id(b.valuation)) for b in branches_of(
                    block.condition, self.valuations[valuation], activity=self.name,
                    exact_activity=self.exact, functions=self.functions)]
            self._branches[key] = found
        return found

    def cleared(self, valuation: int) -> int:
        """The valuation once the block reader's step ends (an instruction block issued): the
        variables of scope `L` and `T` are unset (`runtime/bindings.py`)."""
        if not self.tracked:
            return valuation
        kept = tuple((name, value, rank) if rank == SCOPE_RANK["U"] else (name, None, UNSET)
                     for name, value, rank in self.valuations[valuation])
        return self.valuation_id(kept)


def _instants(commands: BlockCommands) -> tuple[int, ...]:
    """The offsets of a block's events before its end (see `Step.instants`): each track's
    commands wait, run, stop, one after the other (`runtime/actuators.py`)."""
    out = {0}
    length = commands.length
    for track in (commands.moves, commands.leds, commands.audios):
        at = 0
        for command in track:
            at += command.wait_t
            out.add(at)
            at += command.duration
            out.add(at)
    return tuple(sorted(t for t in out if t < length)) or (0,)


def _rules(program: IRProgram, library: RuleLibrary | None, exact: bool,
           functions: Implementations | None) -> tuple[tuple[Switch, ...], list[str]]:
    """The switches of the script's alfa messages, and what is assumed of its other rules
    (see the module's docstring). A message that makes no rule (a `when` that does not parse,
    a target the script lacks) makes nothing that changes the flow: the run reports it."""
    from scriptc.runtime import rules as lib

    library = library if library is not None else lib.STANDARD_RULES
    standard = {0: lib.KickStarter, 1: lib.SafetyStop, 2: lib.Override}
    switches: list[Switch] = []
    assumed: list[str] = []
    script = program.script
    spans = {m.id.text: m.span for m in script.alfa}
    for message in program.alfa:
        if message.action not in ("A", "B", "C"):
            continue  # removed, or held back (D): not in the chain
        entry = library.get(message.rulecode, message.id)
        factory = entry.factory if entry is not None else None
        if factory is not None and factory is standard.get(message.rulecode) \
                and message.rulecode != 2:
            continue
        if factory is not lib.Override or message.rulecode != 2:
            what = ("a rule the library does not know" if entry is None
                    else f"the rule `{entry.name}`")
            assumed.append(f"`{message.id}` (rulecode {message.rulecode}) is {what}: verify "
                           "assumes it changes no block and switches no script")
            continue
        try:
            rule = lib.Override(message, lib.parse_params(message.intopic))
            when = lib.parse_condition_text(rule.condition_text)
        except lib.RuleError:
            continue  # the run reports it and has no such rule
        target = _target(program, rule)
        if target is None:
            continue  # the run reports the override and nothing switches
        outcomes = outcomes_of(when, activity=program.name, exact_activity=exact,
                               functions=functions)
        switches.append(Switch(len(switches), message.id, outcomes, target,
                               spans.get(message.id, script.span), when))
    return tuple(switches), assumed


def _target(program: IRProgram, rule: object) -> int | None:
    """The block an override rule switches to in this script (ENDS: another script; None:
    a goal or block the script lacks, so nothing switches), as `runtime/overrides.py` finds
    it."""
    from scriptc.runtime.rules import Override

    assert isinstance(rule, Override)
    if rule.script and rule.script != program.name:
        return ENDS
    goal = rule.goal
    if isinstance(goal, str):
        if goal.isascii() and goal.isdigit():
            goal = int(goal)
        elif goal in program.goal_ids:
            goal = program.goal_ids.index(goal)
        else:
            return None
    return program.index.get((goal, rule.action, rule.block))
