"""IR -> the canonical script syntax (docs/language.md): what `scriptc decompile` writes
and what the Python API returns for a script built in code.

One item per line; `[action]` indented two spaces under its goal, blocks four; no blank lines
and no comments (the IR has none). Fields of rule messages and commands are separated by `, `,
conditions use the canonical `toparse` text (`scriptc.emit.condition`). Labels print as they
are in the IR, so a script read from thesis JSON shows the labels the reader invented for jump
targets (`g0_a0_b4`, docs/json.md).

The text compiles back to the same thesis JSON: `emit_json(lower(format_script(s)))` equals
`emit_json(s)` for every script `s` that `emit_json` accepts and whose strings hold no line
break and no leading or trailing blank in an audio path (the script syntax cannot write those;
the JSON reader rejects them, see `schemas/thesis-script.schema.json`).
"""

from __future__ import annotations

from scriptc.emit.condition import condition_text, quote
from scriptc.ir.nodes import (
    AudioCommand,
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

__all__ = ["format_script", "format_block", "format_rule_message"]

GOAL_INDENT = ""
ACTION_INDENT = "  "
BLOCK_INDENT = "    "


def format_rule_message(message: RuleMessage) -> str:
    """`[alfa:0, kick_starter, "", "", C, U]`."""
    return (
        f"[{message.kind}:{message.rulecode.text}, {message.id.text}, "
        f"{quote(message.intopic.value)}, {quote(message.outtopic.value)}, "
        f"{message.action.text}, {message.mutex.text}]"
    )


def _move(cmd: MoveCommand) -> str:
    fields = (cmd.v_x, cmd.v_y, cmd.v_theta, cmd.wait_t, cmd.duration)
    return quote(", ".join(n.text for n in fields))


def _led(cmd: LedCommand) -> str:
    fields = (cmd.r, cmd.g, cmd.b, cmd.turnas, cmd.wait_t, cmd.duration)
    return quote(", ".join(n.text for n in fields))


def _audio(cmd: AudioCommand) -> str:
    # docs/language.md: the path is everything before the last two commas, so commas in the path
    # need no escape.
    return quote(f"{cmd.track_path.value}, {cmd.wait_t.text}, {cmd.duration.text}")


def _label(name: Name | None) -> str:
    return name.text if name is not None else ""


def format_block(block) -> str:
    """One block item, without indentation."""
    head = f"[b#{_label(block.label)}#"
    if isinstance(block, InstructionBlock):
        mv = ", ".join(_move(c) for c in block.moves)
        ld = ", ".join(_led(c) for c in block.leds)
        ao = ", ".join(_audio(c) for c in block.audios)
        return f"{head}blk_inst: MV({mv}) LD({ld}) AO({ao})]"
    if isinstance(block, JumpBlock):
        return (
            f"{head}blk_jump: CND({condition_text(block.condition)}) "
            f"TRJMP({_label(block.true_target)}) FLSJMP({_label(block.false_target)})]"
        )
    if isinstance(block, TerminusBlock):
        return f"{head}blk_terminus]"
    if isinstance(block, SensorBlock):
        if not block.payload:
            return f"{head}blk_sens]"
        return f"{head}blk_sens: " + ", ".join(quote(t.value) for t in block.payload) + "]"
    raise TypeError(f"not a block: {block!r}")


def format_script(script: Script) -> str:
    """The canonical script text of `script` (ends with a newline)."""
    lines = [f"[{script.name.text}]"]
    lines.extend(format_rule_message(m) for m in script.alfa)
    lines.extend(format_rule_message(m) for m in script.omega)
    for goal in script.goals:
        lines.append(f"{GOAL_INDENT}[goal:{goal.id.text}]")
        for action in goal.actions:
            lines.append(f"{ACTION_INDENT}[action]")
            lines.extend(BLOCK_INDENT + format_block(b) for b in action.blocks)
    return "\n".join(lines) + "\n"
