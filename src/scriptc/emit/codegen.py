"""IR -> a bytecode Program (docs/bytecode.md): the bridge between the IR and `scriptc.bytecode`,
which knows nothing of the IR.

Each block becomes a run of instructions, in the order of the script:

- instruction block: MOVE/LED/AUDIO per command (numbers as constants that keep the written
  text, times as u32), then ISSUE, NEXT_BLOCK;
- jump block: COND (its handler is the false exit; its text the condition's canonical text,
  which the VM reports with the jump), the assignments left to right, the
  evaluations left to right, the true exit; then the false exit. An exit is GOTO to the
  labelled block, or NEXT_BLOCK for an empty target. A CLASS assignment is FIND, NEXT_CANDIDATE,
  each test followed by JUMP_IF_FALSE back to NEXT_CANDIDATE, then BIND; a VAR assignment is
  its function's arguments, CALL_F, SET_VAR; an ATT assignment BOUND, the arguments, CALL_F,
  SET_ATT; an E evaluation is its arguments, CALL_E, JUMP_IF_FALSE to the false exit; `{TRUE}`
  is the true exit itself (what follows it is never reached, so it is not compiled:
  docs/rules.md);
- terminus: END; sensor block: PAYLOAD per text, SENSE, NEXT_BLOCK.

Constants are shared (one per distinct text or number text). Each instruction's source span is
that of the command, test, assignment or evaluation it comes from; with the source at hand the
program also carries the line table, so positions survive without the script.

`codegen` expects a script that passed the checks; what it cannot express (a label on two
blocks, a jump to no label, `?THIS` outside a test, a time that is not a whole u32) raises
CodegenError rather than produce a program the verifier would refuse.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from decimal import Decimal, InvalidOperation
from itertools import starmap

from scriptc.bytecode.code import Assembler, JumpTarget
from scriptc.bytecode.encode import encode
from scriptc.bytecode.program import (
    ActionRecord,
    BlockRecord,
    CodeSpan,
    Constant,
    GoalRecord,
    MessageRecord,
    Num,
    Program,
)
from scriptc.emit.condition import condition_text
from scriptc.ir import nodes as ir
from scriptc.ir.nodes import (
    AliasRef,
    AttAssignment,
    AttRef,
    Call,
    CallTest,
    ClassAssignment,
    Condition,
    FieldRef,
    FieldTest,
    InstructionBlock,
    JumpBlock,
    Name,
    Number,
    NumberValue,
    RuleMessage,
    Script,
    SensorBlock,
    StringValue,
    TerminusBlock,
    TrueEvaluation,
    VarAssignment,
    VarRef,
)
from scriptc.ir.walk import ConditionVisitor
from scriptc.language import MUTEXES, OPERATORS, RULE_ACTIONS, SCOPES
from scriptc.numbers import whole_number
from scriptc.source import SourceFile, Span

__all__ = ["CodegenError", "codegen", "emit_bytecode"]

_U32 = 0xFFFF_FFFF


class CodegenError(ValueError):
    """The script cannot be compiled to bytecode (it did not pass the checks)."""


def emit_bytecode(script: Script, source: SourceFile | None = None) -> bytes:
    """The `.scb` bytes of a checked script (the `bytecode` back end of `scriptc compile`)."""
    return encode(codegen(script, source))


def codegen(script: Script, source: SourceFile | None = None) -> Program:
    """The Program of a checked script; with `source`, positions carry lines and columns."""
    return _Codegen(script, source).program()


def _with(sigil: str, text: str) -> str:
    return text if text.startswith(sigil) else sigil + text


def _without(sigil: str, text: str) -> str:
    return text[len(sigil):] if text.startswith(sigil) else text


class _Codegen(ConditionVisitor):
    def __init__(self, script: Script, source: SourceFile | None) -> None:
        self.script = script
        self.source = source
        self.constants: list[Constant] = []
        self.pool: dict[tuple[int, str], int] = {}
        self.asm = Assembler()
        self.labels: dict[str, int] = {}
        self.commands: dict[tuple[str, ...], bytes] = {}  # a command's texts -> its code

    # -- constants --------------------------------------------------------------------------

    def text(self, value: str) -> int:
        key = (1, value)
        index = self.pool.get(key)
        if index is None:
            index = self.pool[key] = len(self.constants)
            self.constants.append(value)
        return index

    def number(self, number: Number) -> int:
        key = (2, number.text)
        index = self.pool.get(key)
        if index is None:
            value = number.value
            if value is None or not math.isfinite(value):
                raise CodegenError(f"`{number.text}` is not a finite number")
            index = self.pool[key] = len(self.constants)
            self.constants.append(Num(value, number.text))
        return index

    @staticmethod
    def whole(number: Number, what: str) -> int:
        text = number.text
        if text.isascii() and text.isdigit():
            value = whole_number(text)
            if value is None:
                raise CodegenError(f"{what} `{text[:20]}...` does not fit in 32 bits")
        else:
            try:
                exact = Decimal(text.strip())
            except InvalidOperation:
                raise CodegenError(f"{what} `{text}` is not a number") from None
            if not exact.is_finite() or exact != exact.to_integral_value():
                raise CodegenError(f"{what} `{text}` is not a whole number")
            value = int(exact)
        if not 0 <= value <= _U32:
            raise CodegenError(f"{what} `{text}` does not fit in 32 bits")
        return value

    @staticmethod
    def letter(name: Name, allowed: Mapping[str, str], what: str) -> str:
        text = name.text
        if text not in allowed:
            raise CodegenError(f"{what} `{text}` is not one of {', '.join(allowed)}")
        return text

    # -- the script ---------------------------------------------------------------------------

    def program(self) -> Program:
        script = self.script
        for i, (_address, block) in enumerate(script.blocks()):
            label = block.label
            if label is not None and label.text:
                if label.text in self.labels:
                    raise CodegenError(f"the label `{label.text}` is on two blocks")
                self.labels[label.text] = i
        name = self.text(script.name.text)
        alfa = tuple(self.message(m) for m in script.alfa)
        omega = tuple(self.message(m) for m in script.omega)
        goals: list[GoalRecord] = []
        actions: list[ActionRecord] = []
        blocks: list[BlockRecord] = []
        for goal in script.goals:
            goals.append(GoalRecord(self.text(goal.id.text), len(goal.actions), Span(*goal.span)))
            for action in goal.actions:
                actions.append(ActionRecord(len(action.blocks), Span(*action.span)))
                for block in action.blocks:
                    blocks.append(self.block(block, len(blocks)))
        # The source's name comes last, so that the rest of the program (the code above all)
        # is the same whether or not it was compiled with its source.
        source = None
        lines: tuple[int, ...] = ()
        if self.source is not None:
            source = self.text(os.path.basename(self.source.path) or self.source.path)
            lines = tuple(self.source.line_starts)
        return Program(
            name=name,
            source=source,
            constants=tuple(self.constants),
            alfa=alfa,
            omega=omega,
            goals=tuple(goals),
            actions=tuple(actions),
            blocks=tuple(blocks),
            code=bytes(self.asm.code),
            lines=lines,
            spans=tuple(starmap(CodeSpan, self.asm.spans)),
        )

    def message(self, m: RuleMessage) -> MessageRecord:
        return MessageRecord(
            rulecode=self.whole(m.rulecode, "the rulecode"),
            id=self.text(m.id.text),
            intopic=self.text(m.intopic.value),
            outtopic=self.text(m.outtopic.value),
            action=self.letter(m.action, RULE_ACTIONS, "the rule action"),
            mutex=self.letter(m.mutex, MUTEXES, "the mutex command"),
            span=Span(*m.span),
        )

    def block(self, block: ir.Block, index: int) -> BlockRecord:
        asm = self.asm
        start = asm.offset
        label = block.label
        label_index = self.text(label.text) if label is not None and label.text else None
        span = block.span
        if isinstance(block, InstructionBlock):
            kind = "I"
            whole = self.whole
            # Scripts repeat their commands: an encoded command is replayed from a cache keyed
            # by its texts (its constants, hence its bytes, are the same every time).
            cache = self.commands
            for mv in block.moves:
                asm.mark(*mv.span)
                key: tuple[str, ...] = ("M", mv.v_x.text, mv.v_y.text, mv.v_theta.text,
                                        mv.wait_t.text, mv.duration.text)
                encoded = cache.get(key)
                if encoded is not None:
                    asm.replay(encoded)
                    continue
                at = asm.offset
                asm.emit("MOVE", self.number(mv.v_x), self.number(mv.v_y),
                         self.number(mv.v_theta), whole(mv.wait_t, "`wait_t`"),
                         whole(mv.duration, "`duration`"))
                cache[key] = asm.since(at)
            for led in block.leds:
                asm.mark(*led.span)
                key = ("L", led.r.text, led.g.text, led.b.text, led.turnas.text,
                       led.wait_t.text, led.duration.text)
                encoded = cache.get(key)
                if encoded is not None:
                    asm.replay(encoded)
                    continue
                turnas = whole(led.turnas, "`turnas`")
                if turnas > 1:
                    raise CodegenError(f"`turnas` `{led.turnas.text}` is not 0 or 1")
                at = asm.offset
                asm.emit("LED", self.number(led.r), self.number(led.g), self.number(led.b),
                         turnas, whole(led.wait_t, "`wait_t`"), whole(led.duration, "`duration`"))
                cache[key] = asm.since(at)
            for ao in block.audios:
                asm.mark(*ao.span)
                key = ("A", ao.track_path.value, ao.wait_t.text, ao.duration.text)
                encoded = cache.get(key)
                if encoded is not None:
                    asm.replay(encoded)
                    continue
                at = asm.offset
                asm.emit("AUDIO", self.text(ao.track_path.value), whole(ao.wait_t, "`wait_t`"),
                         whole(ao.duration, "`duration`"))
                cache[key] = asm.since(at)
            asm.mark(*span)
            asm.emit("ISSUE")
            asm.emit("NEXT_BLOCK")
        elif isinstance(block, JumpBlock):
            kind = "J"
            self.condition(block, index)
        elif isinstance(block, TerminusBlock):
            kind = "T"
            asm.mark(*span)
            asm.emit("END")
        elif isinstance(block, SensorBlock):
            kind = "S"
            for text in block.payload:
                asm.mark(*text.span)
                asm.emit("PAYLOAD", self.text(text.value))
            asm.mark(*span)
            asm.emit("SENSE")
            asm.emit("NEXT_BLOCK")
        else:
            raise TypeError(f"not a block: {block!r}")
        return BlockRecord(kind, label_index, start, Span(*span))

    # -- conditions ---------------------------------------------------------------------------

    def exit(self, target: Name | None, block: JumpBlock) -> None:
        """GOTO the labelled block, or NEXT_BLOCK for an empty target."""
        asm = self.asm
        if target is None or not target.text:
            asm.mark(*block.span)
            asm.emit("NEXT_BLOCK")
            return
        index = self.labels.get(target.text)
        if index is None:
            raise CodegenError(f"a jump names the label `{target.text}`, which no block "
                               "carries")
        asm.mark(*target.span)
        asm.emit("GOTO", index)

    def condition(self, block: JumpBlock, index: int) -> None:
        asm = self.asm
        condition: Condition = block.condition
        false_exit = JumpTarget()
        asm.mark(*condition.span)
        asm.emit("COND", false_exit, self.text(condition_text(condition)))
        reached_true = condition.bare_true
        if not reached_true:
            for assignment in condition.assignments:
                asm.mark(*assignment.span)
                self.visit(assignment, false_exit)
            for evaluation in condition.evaluations:
                if isinstance(evaluation, TrueEvaluation):
                    reached_true = True
                    break
                asm.mark(*evaluation.span)
                self.call(evaluation.call, "CALL_E", False)
                asm.emit("JUMP_IF_FALSE", false_exit)
        self.exit(block.true_target, block)
        asm.place(false_exit)
        self.exit(block.false_target, block)

    # -- the nodes of a condition (ConditionVisitor) -----------------------------------------

    def visit_class_assignment(self, assignment: ClassAssignment, false_exit: JumpTarget) -> None:
        asm = self.asm
        bind = JumpTarget()
        asm.emit("FIND", self.text(_without("#", assignment.class_name.text)),
                 self.text(self.alias(assignment.alias, False)),
                 self.scope(assignment.scope), bind)
        retry = JumpTarget()
        asm.place(retry)
        asm.emit("NEXT_CANDIDATE")
        for test in assignment.tests:
            asm.mark(*test.span)
            self.visit(test)
            asm.emit("JUMP_IF_FALSE", retry)
        asm.mark(*assignment.span)
        asm.place(bind)
        asm.emit("BIND")

    def visit_var_assignment(self, assignment: VarAssignment, false_exit: JumpTarget) -> None:
        self.call(assignment.call, "CALL_F", False)
        self.asm.emit("SET_VAR", self.scope(assignment.scope),
                      self.text(_with("@", assignment.var.name.text)))

    def visit_att_assignment(self, assignment: AttAssignment, false_exit: JumpTarget) -> None:
        # The alias is checked before the function is called, as the reference interpreter
        # does (runtime/evaluate.py): a function that fails is reported.
        alias = self.text(self.alias(assignment.alias, False))
        self.asm.emit("BOUND", alias)
        self.call(assignment.call, "CALL_F", False)
        self.asm.emit("SET_ATT", self.scope(assignment.scope), alias,
                      self.text(_without("$", assignment.att.text)))

    def visit_field_test(self, test: FieldTest) -> None:
        self.asm.emit("PUSH_THIS_FIELD", self.text(_without("&", test.field.text)))
        self.visit(test.value, True)
        self.asm.emit("COMPARE", ord(self.comparison(test.op)))

    def visit_call_test(self, test: CallTest) -> None:
        self.call(test.call, "CALL_B", True)

    def visit_number(self, value: NumberValue, in_test: bool) -> None:
        self.asm.emit("PUSH_CONST", self.number(value.number))

    def visit_string(self, value: StringValue, in_test: bool) -> None:
        self.asm.emit("PUSH_CONST", self.text(value.text.value))

    def visit_alias(self, value: AliasRef, in_test: bool) -> None:
        if value.is_this:
            self.alias(value, in_test)
            self.asm.emit("PUSH_THIS")
        else:
            self.asm.emit("PUSH_ALIAS", self.text(self.alias(value, in_test)))

    def visit_field(self, value: FieldRef, in_test: bool) -> None:
        field = self.text(_without("&", value.field.text))
        if value.alias.is_this:
            self.alias(value.alias, in_test)
            self.asm.emit("PUSH_THIS_FIELD", field)
        else:
            self.asm.emit("PUSH_FIELD", self.text(self.alias(value.alias, in_test)), field)

    def visit_att(self, value: AttRef, in_test: bool) -> None:
        # Attributes belong to aliases, not to entities, so `?THIS>$att` reads the attribute
        # of the alias `?THIS` (which no assignment sets), as the reference interpreter does.
        self.asm.emit("PUSH_ATT", self.text(self.alias(value.alias, in_test)),
                      self.text(_without("$", value.att.text)))

    def visit_var(self, value: VarRef, in_test: bool) -> None:
        self.asm.emit("PUSH_VAR", self.text(_with("@", value.name.text)))

    @staticmethod
    def alias(alias: AliasRef, in_test: bool) -> str:
        if alias.is_this and not in_test:
            raise CodegenError("`?THIS` names the candidate of a CLASS test and nothing "
                               "outside one")
        return _with("?", alias.name.text)

    def scope(self, scope: Name) -> int:
        return ord(self.letter(scope, SCOPES, "the scope"))

    @staticmethod
    def comparison(op: Name) -> str:
        written = op.text if op.text.startswith("OP") else "OP" + op.text
        if written not in OPERATORS:
            raise CodegenError(f"unknown comparison `{op.text}`")
        return written.removeprefix("OP")

    def call(self, call: Call, opcode: str, in_test: bool) -> None:
        if len(call.args) > 255:
            raise CodegenError(f"`{call.name.text}` is called with more than 255 arguments")
        for arg in call.args:
            self.visit(arg, in_test)
        self.asm.emit(opcode, self.text(call.name.text), len(call.args))
