"""IR -> the canonical script syntax (docs/language.md): what `scriptc decompile` writes and
what the Python API returns for a script built in code.

One item per line, laid out by the canonical layout (`scriptc.emit.printer`, the formatter's
own): `[action]` indented two spaces under its goal, blocks four, the formatter's spacing, and
an item wider than the line width wrapped as the formatter wraps it. So `scriptc fmt --check`
has nothing to say about a printed script. No blank lines and no comments (the IR has none).
Conditions are the canonical `toparse` text (`scriptc.emit.condition`), laid out token by
token. Labels print as they are in the IR, so a script read from thesis JSON shows the labels
the reader invented for jump targets (`g0_a0_b4`, docs/json.md).

This module builds the tokens of each item from the IR; where the blanks go is the layout's
business alone. A name is one token whatever it holds, so a name that is not an identifier is
printed as given (and reported by the analysis), never split.

The text compiles back to the same thesis JSON: `emit_json(lower(format_script(s)))` equals
`emit_json(s)` for every script `s` that `emit_json` accepts and whose strings hold no line
break and no leading or trailing blank in an audio path (the script syntax cannot write those;
the JSON reader rejects them, see `schemas/thesis-script.schema.json`).
"""

from __future__ import annotations

from collections.abc import Callable

from scriptc.emit.condition import condition_text
from scriptc.emit.printer import (
    ACTION_INDENT,
    BLOCK_INDENT,
    GOAL_INDENT,
    INSTRUCTION,
    JUMP,
    SENSOR,
    LayoutError,
    Tok,
    command_text,
    lay_out,
    piece,
    tokens,
)
from scriptc.ir.nodes import (
    AudioCommand,
    Block,
    InstructionBlock,
    JumpBlock,
    LedCommand,
    MoveCommand,
    Name,
    RuleMessage,
    Script,
    SensorBlock,
    TerminusBlock,
)
from scriptc.language import quote

__all__ = ["ConditionText", "format_block", "format_rule_message", "format_script"]

ConditionText = Callable[[JumpBlock], str]
"""What a jump's `CND(...)` holds: by default the canonical text of its IR condition; the
Python API passes the condition text its caller wrote."""


def _default_condition(block: JumpBlock) -> str:
    return condition_text(block.condition)


def _toks(*pieces: str) -> list[Tok]:
    return [piece(p) for p in pieces]


def _rule_message_tokens(message: RuleMessage) -> list[Tok]:
    return _toks("[", message.kind, ":", message.rulecode.text, ",", message.id.text, ",",
                 quote(message.intopic.value), ",", quote(message.outtopic.value), ",",
                 message.action.text, ",", message.mutex.text, "]")


def _move(cmd: MoveCommand) -> str:
    return command_text(n.text for n in (cmd.v_x, cmd.v_y, cmd.v_theta, cmd.wait_t,
                                         cmd.duration))


def _led(cmd: LedCommand) -> str:
    return command_text(n.text for n in (cmd.r, cmd.g, cmd.b, cmd.turnas, cmd.wait_t,
                                         cmd.duration))


def _audio(cmd: AudioCommand) -> str:
    # docs/language.md: the path is everything before the last two commas, so commas in the
    # path need no escape; quotes and backslashes get the language's two escapes.
    return command_text((quote(cmd.track_path.value)[1:-1], cmd.wait_t.text, cmd.duration.text))


def _label(name: Name | None) -> list[Tok]:
    return [piece(name.text)] if name is not None else []


def _track(name: str, commands: list[str]) -> list[Tok]:
    toks = _toks(name, "(")
    for i, command in enumerate(commands):
        if i:
            toks.append(piece(","))
        toks.append(piece(command))
    toks.append(piece(")"))
    return toks


def _condition_tokens(text: str) -> list[Tok]:
    """The tokens of a condition's text; text that is not made of the language's tokens (a
    caller's mistake, which the analysis reports) stays one piece, as written."""
    try:
        return tokens(text)
    except LayoutError:
        return [Tok("raw", text)]


def _block_tokens(block: Block, condition: ConditionText) -> tuple[list[Tok], str]:
    """The tokens of a block item and the kind of its body (where it may wrap)."""
    head = [*_toks("[", "b", "#"), *_label(block.label), piece("#")]
    if isinstance(block, InstructionBlock):
        return [*head, *_toks("blk_inst", ":"),
                *_track("MV", [_move(c) for c in block.moves]),
                *_track("LD", [_led(c) for c in block.leds]),
                *_track("AO", [_audio(c) for c in block.audios]), piece("]")], INSTRUCTION
    if isinstance(block, JumpBlock):
        return [*head, *_toks("blk_jump", ":", "CND", "("),
                *_condition_tokens(condition(block)), *_toks(")", "TRJMP", "("),
                *_label(block.true_target), *_toks(")", "FLSJMP", "("),
                *_label(block.false_target), *_toks(")", "]")], JUMP
    if isinstance(block, TerminusBlock):
        return [*head, *_toks("blk_terminus", "]")], ""
    if isinstance(block, SensorBlock):
        if not block.payload:
            return [*head, *_toks("blk_sens", "]")], ""
        toks = [*head, *_toks("blk_sens", ":")]
        for i, text in enumerate(block.payload):
            if i:
                toks.append(piece(","))
            toks.append(piece(quote(text.value)))
        return [*toks, piece("]")], SENSOR
    raise TypeError(f"not a block: {block!r}")


def format_rule_message(message: RuleMessage) -> str:
    """`[alfa:0, kick_starter, "", "", C, U]`."""
    return lay_out(_rule_message_tokens(message), "", 0)


def format_block(block: Block, condition: ConditionText = _default_condition) -> str:
    """One block item as it stands in a script (laid out at the blocks' indentation, so a
    wrapped block's later lines carry their alignment), without the indentation of its
    first line."""
    toks, body = _block_tokens(block, condition)
    return lay_out(toks, body, len(BLOCK_INDENT))


def format_script(script: Script, condition: ConditionText = _default_condition) -> str:
    """The canonical script text of `script` (ends with a newline). `condition` gives the
    text of each jump's condition (default: the canonical text of its IR)."""
    lines = [lay_out(_toks("[", script.name.text, "]"), "", len(GOAL_INDENT))]
    lines.extend(format_rule_message(m) for m in script.alfa)
    lines.extend(format_rule_message(m) for m in script.omega)
    for goal in script.goals:
        lines.append(GOAL_INDENT + lay_out(_toks("[", "goal", ":", goal.id.text, "]"), "",
                                           len(GOAL_INDENT)))
        for action in goal.actions:
            lines.append(ACTION_INDENT + lay_out(_toks("[", "action", "]"), "",
                                                 len(ACTION_INDENT)))
            lines.extend(BLOCK_INDENT + format_block(b, condition) for b in action.blocks)
    return "\n".join(lines) + "\n"
