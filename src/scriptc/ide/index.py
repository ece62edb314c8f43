"""What is where in one analysed script: the index editor features look things up in.

Built per snapshot, in steps, so that a request on a large script pays only for what it
reads (a hover on a 90 KB script stays under a millisecond):

- at once, one loop over the blocks: each block with its address, its JSON path
  `goalG/actA/blkB` and its position in execution order (`blocks`, by the offset of its
  item), the first block carrying each label (`label_blocks`, `label_paths`), the rule
  messages and goals by item;
- per item, when a feature asks about it: the names in it (`occurrences_in`), each an
  `Occurrence` saying what it is (label, alias, rule id, function, class, field, scope...)
  and whether it defines or uses the name;
- for the whole script, when a feature needs every use of a name (references, rename): all
  occurrences in text order (`tables`), and the CLASS assignments binding each alias
  (`alias_bindings`).

Only items that parsed are in the IR, so an item being typed (broken) contributes nothing;
features that must see every use of a name (rename) refuse while the text has syntax errors.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

from scriptc.ir.nodes import (
    AliasRef,
    AttAssignment,
    AttRef,
    Block,
    Call,
    CallEvaluation,
    CallTest,
    ClassAssignment,
    Condition,
    FieldRef,
    FieldTest,
    Goal,
    InstructionBlock,
    JumpBlock,
    RuleMessage,
    TrueEvaluation,
    VarAssignment,
    VarRef,
    block_path,
)
from scriptc.ir.walk import ConditionVisitor
from scriptc.source import Span


@dataclass(frozen=True, slots=True)
class BlockInfo:
    """A block and where it is in the script: its (goal, action, block) address, its JSON
    path `goalG/actA/blkB` and its position in execution order."""

    address: tuple[int, int, int]
    path: str
    block: Block
    order: int  # position in execution order (in `ScriptIndex.block_list`)

    @property
    def duration_ms(self) -> float | None:
        return block_duration(self.block)


@dataclass(frozen=True, slots=True)
class Occurrence:
    """A name in the text. `kind` is one of: "activity", "goal", "label", "alias", "this",
    "rule", "function", "class", "field", "scope", "var", "att", "operator", "action-letter",
    "mutex-letter"; `role` is "definition" or "reference". `detail` is what the kind needs
    to be explained: the Call of a function, the class name of a field (None when unknown),
    the RuleMessage of a rule id or letter, the ClassAssignment binding an alias."""

    span: Span
    kind: str
    name: str
    role: str
    detail: object = None


def track_time(commands) -> float | None:
    """The time a track takes: the sum of `wait_t + duration` over its commands (docs/runtime.md,
    "Instruction blocks"), None when a time is not a number, or not a finite one (`1e999`,
    which the checks report as V003, or a sum too large to represent)."""
    total = 0.0
    for command in commands:
        wait, duration = command.wait_t.value, command.duration.value
        if wait is None or duration is None:
            return None
        total += wait + duration
    return total if math.isfinite(total) else None


def block_duration(block: Block) -> float | None:
    """The time an instruction block keeps the robot busy: the longest of its three tracks
    (they start together), None when a time is not a readable number; 0 for the other
    blocks (reading a jump, a sensor block or a terminus takes no time)."""
    if not isinstance(block, InstructionBlock):
        return 0
    times: list[float] = []
    for track in (block.moves, block.leds, block.audios):
        time = track_time(track)
        if time is None:
            return None
        times.append(time)
    return max(times)


class ScriptIndex:
    """Built in two steps, so that a hover on a large script stays cheap: the blocks and the
    labels at once (one loop over the blocks), the names of an item when a feature asks
    about that item (`occurrences_in`), and the tables by name over the whole script when a
    feature needs every use of a name (`tables`)."""

    def __init__(self, snapshot) -> None:
        # Weak: the snapshot keeps its index (`Snapshot.index`), and a strong reference back
        # would make every analysed version a reference cycle, which only a full collection
        # frees (the language server runs one only when idle).
        self.snapshot = weakref.proxy(snapshot)
        self.blocks: dict[int, BlockInfo] = {}  # by item start
        self.block_list: list[BlockInfo] = []
        self.label_paths: dict[str, str] = {}  # label -> path of the first block carrying it
        self.label_blocks: dict[str, BlockInfo] = {}
        self.messages: dict[int, RuleMessage] = {}  # by item start
        self._items: dict[int, list[Occurrence]] = {}
        self._tables: Tables | None = None
        self._bindings: dict[str, list[ClassAssignment]] | None = None
        self.goals: dict[int, Goal] = {}  # by item start
        script = snapshot.script
        if script is None:  # no item could be read: an index with nothing in it
            return
        for message in (*script.alfa, *script.omega):
            self.messages[message.span.start] = message
        for g, goal in enumerate(script.goals):
            for a, action in enumerate(goal.actions):
                for b, block in enumerate(action.blocks):
                    info = BlockInfo((g, a, b), block_path((g, a, b)), block,
                                     len(self.block_list))
                    self.blocks[block.span.start] = info
                    self.block_list.append(info)
                    label = block.label
                    if label is not None and label.text and label.text not in self.label_paths:
                        self.label_paths[label.text] = info.path
                        self.label_blocks[label.text] = info
        self.goals = {goal.span.start: goal for goal in script.goals}

    # -- the names of one item ----------------------------------------------------------------

    def occurrences_in(self, item_start: int) -> list[Occurrence]:
        """The names in the item starting at `item_start`, in text order."""
        found = self._items.get(item_start)
        if found is None:
            found = self._items[item_start] = _ItemWalker(self).walk(item_start)
        return found

    def occurrence_at(self, offset: int) -> Occurrence | None:
        """The name under the cursor: one whose span holds `offset`, or ends at it (the
        cursor just after a word is still on it)."""
        item = self.snapshot.item_at(offset)
        if item is None:
            return None
        best = None
        for o in self.occurrences_in(item.span.start):
            if o.span.start <= offset < o.span.end:
                return o
            if o.span.end == offset:
                best = o
        return best

    def block_at(self, offset: int) -> BlockInfo | None:
        item = self.snapshot.item_at(offset)
        if item is None:
            return None
        return self.blocks.get(item.span.start)

    # -- every name of the script ---------------------------------------------------------------

    @property
    def tables(self) -> Tables:
        if self._tables is None:
            self._tables = Tables(self)
        return self._tables

    @property
    def alias_bindings(self) -> dict[str, list[ClassAssignment]]:
        """The CLASS assignments binding each alias, in execution order."""
        if self._bindings is None:
            bindings: dict[str, list[ClassAssignment]] = {}
            for info in self.block_list:
                if isinstance(info.block, JumpBlock):
                    for asg in info.block.condition.assignments:
                        if isinstance(asg, ClassAssignment) and not asg.alias.is_this:
                            bindings.setdefault(asg.alias.name.text, []).append(asg)
            self._bindings = bindings
        return self._bindings

    def alias_class(self, alias: str) -> str | None:
        """The class an alias is bound to, when every CLASS assignment binding it agrees."""
        classes = {a.class_name.text for a in self.alias_bindings.get(alias, ())}
        return classes.pop() if len(classes) == 1 else None

    def occurrences_of(self, kind: str, name: str) -> list[Occurrence]:
        """Every occurrence of a name of one kind, in text order."""
        return [o for o in self.tables.all_occurrences if o.kind == kind and o.name == name]


class Tables:
    """Every name of the whole script, in text order."""

    def __init__(self, index: ScriptIndex) -> None:
        self.all_occurrences: list[Occurrence] = []
        script = index.snapshot.script
        if script is None:
            return
        starts = set(index.messages) | set(index.blocks) | set(index.goals)
        if script.name.text:
            starts.add(index.snapshot.item_at(script.name.span.start).span.start)
        for start in sorted(starts):
            self.all_occurrences.extend(index.occurrences_in(start))


class _ItemWalker(ConditionVisitor):
    """Collects the names of one item from its IR."""

    def __init__(self, index: ScriptIndex) -> None:
        self.index = index
        self.out: list[Occurrence] = []

    def add(self, span: Span, kind: str, name: str, role: str = "reference", detail=None) -> None:
        self.out.append(Occurrence(span, kind, name, role, detail))

    def walk(self, start: int) -> list[Occurrence]:
        index = self.index
        script = index.snapshot.script
        if script is not None and script.name.text and script.name.span.start > start and (
                index.snapshot.item_at(script.name.span.start).span.start == start):
            self.add(script.name.span, "activity", script.name.text, "definition")
        message = index.messages.get(start)
        if message is not None:
            self.message(message)
        goal = index.goals.get(start)
        if goal is not None and goal.id.text:
            self.add(goal.id.span, "goal", goal.id.text, "definition", goal)
        info = index.blocks.get(start)
        if info is not None:
            self.block(info)
        self.out.sort(key=lambda o: o.span.start)
        return self.out

    def message(self, message: RuleMessage) -> None:
        script = self.index.snapshot.script
        first = next(m for m in (*script.alfa, *script.omega) if m.id.text == message.id.text)
        role = "definition" if first is message else "reference"
        self.add(message.id.span, "rule", message.id.text, role, message)
        self.add(message.action.span, "action-letter", message.action.text, detail=message)
        self.add(message.mutex.span, "mutex-letter", message.mutex.text, detail=message)

    def block(self, info: BlockInfo) -> None:
        block = info.block
        label = block.label
        if label is not None and label.text:
            self.add(label.span, "label", label.text, "definition", info)
        if isinstance(block, JumpBlock):
            self.condition(block.condition)
            for target in (block.true_target, block.false_target):
                if target is not None and target.text:
                    self.add(target.span, "label", target.text, "reference", info)

    def condition(self, condition: Condition) -> None:
        bound: dict[str, str] = {}  # alias -> class, bound so far in this condition
        for node in (*condition.assignments, *condition.evaluations):
            self.visit(node, bound)

    # The nodes of a condition (ConditionVisitor): `bound` maps the aliases bound so far in the
    # condition to their classes; `this_class` is the class whose tests hold a value, if any.

    def visit_class_assignment(self, asg: ClassAssignment, bound: dict[str, str]) -> None:
        cls = asg.class_name.text
        self.add(asg.class_name.span, "class", cls)
        self.add(asg.scope.span, "scope", asg.scope.text)
        alias = asg.alias
        if alias.is_this:
            self.add(alias.span, "this", alias.name.text, detail=cls)
        else:
            self.add(alias.span, "alias", alias.name.text, "definition", asg)
        for test in asg.tests:
            self.visit(test, bound, cls)
        if not alias.is_this:
            bound[alias.name.text] = cls

    def visit_var_assignment(self, asg: VarAssignment, bound: dict[str, str]) -> None:
        self.add(asg.var.span, "var", asg.var.name.text, "definition")
        self.add(asg.scope.span, "scope", asg.scope.text)
        self.call(asg.call, bound, None)

    def visit_att_assignment(self, asg: AttAssignment, bound: dict[str, str]) -> None:
        self.visit(asg.alias, bound, None)
        self.add(asg.att.span, "att", asg.att.text, "definition")
        self.add(asg.scope.span, "scope", asg.scope.text)
        self.call(asg.call, bound, None)

    def visit_call_evaluation(self, ev: CallEvaluation, bound: dict[str, str]) -> None:
        self.call(ev.call, bound, None)

    def visit_true_evaluation(self, ev: TrueEvaluation, bound: dict[str, str]) -> None:
        pass  # no name in it

    def visit_field_test(self, test: FieldTest, bound: dict[str, str], cls: str) -> None:
        self.add(test.field.span, "field", test.field.text, detail=cls)
        self.add(test.op.span, "operator", test.op.text)
        self.visit(test.value, bound, cls)

    def visit_call_test(self, test: CallTest, bound: dict[str, str], cls: str) -> None:
        self.call(test.call, bound, cls)

    def call(self, call: Call, bound: dict[str, str], this_class: str | None) -> None:
        self.add(call.name.span, "function", call.name.text, detail=call)
        for arg in call.args:
            self.visit(arg, bound, this_class)

    def visit_alias(self, value: AliasRef, bound: dict[str, str], this_class: str | None) -> None:
        if value.is_this:
            self.add(value.span, "this", value.name.text, detail=this_class)
        else:
            self.add(value.span, "alias", value.name.text)

    def visit_field(self, value: FieldRef, bound: dict[str, str], this_class: str | None) -> None:
        self.visit(value.alias, bound, this_class)
        alias = value.alias
        if alias.is_this:
            cls = this_class
        else:
            cls = bound.get(alias.name.text) or self.index.alias_class(alias.name.text)
        self.add(value.field.span, "field", value.field.text, detail=cls)

    def visit_att(self, value: AttRef, bound: dict[str, str], this_class: str | None) -> None:
        self.visit(value.alias, bound, this_class)
        self.add(value.att.span, "att", value.att.text)

    def visit_var(self, value: VarRef, bound: dict[str, str], this_class: str | None) -> None:
        self.add(value.span, "var", value.name.text)

    def visit_number(self, value, bound: dict[str, str], this_class: str | None) -> None:
        pass  # a literal names nothing

    visit_string = visit_number
