"""IR -> the thesis JSON (docs/json.md): the file the thesis's robot software loads.

The text is laid out byte for byte as the thesis's own generator wrote it (`ScriptGen.cpp`,
whose output is `tests/data/script_gen_test_act.json`): one element per line, no indentation,
`"key":value` without spaces, `{` and `[` at the end of the line of their key, `}` and `]` on a
line of their own, an empty array as `[` newline `]`, and a final newline after the closing
brace. Key order is the thesis's (docs/json.md): `activityname`, `alfarulemessages`,
`omegarulemessages`, `goal0`, `goal1`, ...; a goal holds `goalid` then `act0`, ...; an action
`blk0`, ....

Values follow the thesis's types: speeds and colour channels are JSON strings holding the number
as written; `wait_t`, `duration`, `turnas` and `rulecode` are integers; rule actions and mutex
commands are the ASCII codes of their letters; jump targets are the paths `goalG/actA/blkB` of
the labelled blocks (`""` when the jump names no label). Strings are escaped as JSON requires
and non-ASCII text is written as raw UTF-8 (as ScriptGen.cpp did), never as `\\u` escapes.

Sensor blocks, which the thesis leaves "to be defined", are `{"type":"sensor","payload":[...]}`
with the payload strings in order (docs/json.md).

`emit_json` expects a script that passed the checks; on one it cannot express (a jump to a
label no block carries, a label on two blocks, a time that is not a whole number) it raises
`EmitError` rather than write a file the robot would misread.
"""

from __future__ import annotations

from collections.abc import Callable
from decimal import Decimal, InvalidOperation
from json.encoder import encode_basestring as _json_string
from typing import TypeVar

from scriptc.emit.condition import condition_text
from scriptc.ir.nodes import (
    AudioCommand,
    Block,
    InstructionBlock,
    JumpBlock,
    LedCommand,
    MoveCommand,
    Name,
    Number,
    RuleMessage,
    Script,
    SensorBlock,
    TerminusBlock,
    block_path,
)
from scriptc.numbers import whole_number

__all__ = ["EmitError", "emit_json", "label_paths"]


class EmitError(ValueError):
    """The script cannot be written as thesis JSON (it did not pass the checks)."""


def _integer(number: Number, what: str) -> str:
    """The JSON integer of a time, `turnas` or rulecode: the number text as a whole number
    (`1000`, `+5`, `1e3` and `1000.0` all write as integers)."""
    text = number.text
    if text.isascii() and text.isdigit():
        # The common case, and it keeps leading zeros out of the JSON (`007` -> `7`).
        if len(text) < 19 and (text[0] != "0" or len(text) == 1):
            return text  # already the integer's JSON
        whole = whole_number(text)
        if whole is None:
            raise EmitError(f"{what} `{text[:20]}...` is too large")
        return str(whole)
    try:
        value = Decimal(text.strip())
    except InvalidOperation:
        raise EmitError(f"{what} `{text}` is not a number") from None
    if not value.is_finite() or value != value.to_integral_value():
        raise EmitError(f"{what} `{text}` is not a whole number")
    return str(int(value))


def _number_string(number: Number) -> str:
    return _json_string(number.text)


def _letter_code(name: Name, what: str) -> str:
    if len(name.text) != 1:
        raise EmitError(f"{what} `{name.text}` is not a single letter")
    return str(ord(name.text))


def _array(key: str, items: list[str]) -> str:
    if not items:
        return f'"{key}":[\n]'
    return f'"{key}":[\n' + ",\n".join(items) + "\n]"


def _object(key: str, members: list[str]) -> str:
    if not members:
        return f'"{key}":{{\n}}'
    return f'"{key}":{{\n' + ",\n".join(members) + "\n}"


def _rule_message(message: RuleMessage) -> str:
    return (
        "{\n"
        f'"rulecode":{_integer(message.rulecode, "the rulecode")},\n'
        f'"id":{_json_string(message.id.text)},\n'
        f'"intopic":{_json_string(message.intopic.value)},\n'
        f'"outtopic":{_json_string(message.outtopic.value)},\n'
        f'"action":{_letter_code(message.action, "the rule action")},\n'
        f'"mutexcmd":{_letter_code(message.mutex, "the mutex command")}\n'
        "}"
    )


def _move(cmd: MoveCommand) -> str:
    return (
        "{\n"
        f'"v_x":{_number_string(cmd.v_x)},\n'
        f'"v_y":{_number_string(cmd.v_y)},\n'
        f'"v_theta":{_number_string(cmd.v_theta)},\n'
        f'"wait_t":{_integer(cmd.wait_t, "`wait_t`")},\n'
        f'"duration":{_integer(cmd.duration, "`duration`")}\n'
        "}"
    )


def _led(cmd: LedCommand) -> str:
    return (
        "{\n"
        f'"r":{_number_string(cmd.r)},\n'
        f'"g":{_number_string(cmd.g)},\n'
        f'"b":{_number_string(cmd.b)},\n'
        f'"turnas":{_integer(cmd.turnas, "`turnas`")},\n'
        f'"wait_t":{_integer(cmd.wait_t, "`wait_t`")},\n'
        f'"duration":{_integer(cmd.duration, "`duration`")}\n'
        "}"
    )


def _audio(cmd: AudioCommand) -> str:
    return (
        "{\n"
        f'"track_path":{_json_string(cmd.track_path.value)},\n'
        f'"wait_t":{_integer(cmd.wait_t, "`wait_t`")},\n'
        f'"duration":{_integer(cmd.duration, "`duration`")}\n'
        "}"
    )


def label_paths(script: Script) -> dict[str, str]:
    """Each label of the script and the JSON path of the block that carries it."""
    paths: dict[str, str] = {}
    for address, block in script.blocks():
        label = block.label
        if label is None or not label.text:
            continue
        if label.text in paths:
            raise EmitError(
                f"the label `{label.text}` is on two blocks "
                f"({paths[label.text]} and {block_path(address)})"
            )
        paths[label.text] = block_path(address)
    return paths


def _target(target: Name | None, paths: dict[str, str]) -> str:
    if target is None or not target.text:
        return '""'
    try:
        return '"' + paths[target.text] + '"'
    except KeyError:
        raise EmitError(f"a jump names the label `{target.text}`, which no block "
                        "carries") from None


_Command = TypeVar("_Command", MoveCommand, LedCommand, AudioCommand)


def _once(seen: dict[tuple[str, ...], str], command: _Command,
          write: Callable[[_Command], str]) -> str:
    """`write(command)`, or the JSON of a command alike written before."""
    texts = command.texts
    found = seen.get(texts)
    if found is None:
        found = seen[texts] = write(command)
    return found


def _block(key: str, block: Block, paths: dict[str, str], seen: dict[tuple[str, ...], str]
           ) -> str:
    """The member `key` of an action: the JSON of `block`. `seen` holds the JSON of the
    commands written so far, by their texts (`MoveCommand.texts`: a script repeats its
    commands)."""
    if isinstance(block, InstructionBlock):
        moves = _array("move", [_once(seen, c, _move) for c in block.moves])
        leds = _array("led", [_once(seen, c, _led) for c in block.leds])
        audios = _array("audioout", [_once(seen, c, _audio) for c in block.audios])
        return (f'"{key}":{{\n"type":"instruction",\n"flagged":"flag",\n'
                f"{moves},\n{leds},\n{audios}\n}}")
    if isinstance(block, JumpBlock):
        return (
            f'"{key}":{{\n"type":"jump",\n'
            f'"toparse":{_json_string(condition_text(block.condition))},\n'
            f'"truejump":{_target(block.true_target, paths)},\n'
            f'"falsejump":{_target(block.false_target, paths)}\n'
            "}"
        )
    if isinstance(block, TerminusBlock):
        return f'"{key}":{{\n"type":"terminus"\n}}'
    if isinstance(block, SensorBlock):
        return (
            f'"{key}":{{\n"type":"sensor",\n'
            + _array("payload", [_json_string(t.value) for t in block.payload])
            + "\n}"
        )
    raise TypeError(f"not a block: {block!r}")


def emit_json(script: Script) -> str:
    """The thesis JSON text of `script` (ends with a newline)."""
    paths = label_paths(script)
    seen: dict[tuple[str, ...], str] = {}  # (bounded by the script)
    members = [
        f'"activityname":{_json_string(script.name.text)}',
        _array("alfarulemessages", [_rule_message(m) for m in script.alfa]),
        _array("omegarulemessages", [_rule_message(m) for m in script.omega]),
    ]
    for g, goal in enumerate(script.goals):
        goal_members = [f'"goalid":{_json_string(goal.id.text)}']
        for a, action in enumerate(goal.actions):
            blocks = [_block(f"blk{b}", block, paths, seen)
                      for b, block in enumerate(action.blocks)]
            goal_members.append(_object(f"act{a}", blocks))
        members.append(_object(f"goal{g}", goal_members))
    return "{\n" + ",\n".join(members) + "\n}\n"
