"""Hover: markdown about the thing under the cursor.

- a diagnostic code (`L003`) in a comment, or anywhere no other name claims the word: its
  heading and explanation, as `scriptc explain` prints them;
- a label (where it is defined or a jump to it): the block carrying it, its path
  `goalG/actA/blkB` and its line;
- a function: its signature and documentation, from the registry the checks use;
- a class, a field, a scope, an alias, `?THIS`, a comparison, a rule id or letter, a goal id,
  the activity name: what it is, from the tables of `scriptc.ir.builtins`;
- anywhere else in a block: the block, its path, its duration and what its tracks do (or,
  for a jump, where it goes).
"""

from __future__ import annotations

import re

from scriptc.ide.answers import Hover
from scriptc.ide.index import BlockInfo, Occurrence, track_time
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.builtins import CLASSES, field_of
from scriptc.ir.nodes import (
    AudioCommand,
    InstructionBlock,
    JumpBlock,
    LedCommand,
    MoveCommand,
    Script,
    SensorBlock,
    TerminusBlock,
)
from scriptc.language import MUTEXES, OPERATORS, RULE_ACTIONS, SCOPES
from scriptc.source import Span

__all__ = ["code_at", "format_ms", "hover"]

_WORD = re.compile(r"[A-Za-z0-9_]+")
_CODE = re.compile(r"[A-Z][0-9]{3}")
# The most commands of one track a hover lists before summing up the rest.
_MAX_COMMANDS = 4


def hover(snapshot: Snapshot, offset: int) -> Hover | None:
    script = snapshot.script
    if script is None or snapshot.in_comment(offset) is not None:
        # In a comment, or no item could be read (the index is empty): only codes to explain.
        return _code_hover(snapshot, offset)
    index = snapshot.index
    occurrence = index.occurrence_at(offset)
    if occurrence is not None:
        found = _occurrence_hover(snapshot, script, occurrence)
        if found is not None:
            return found
    code = _code_hover(snapshot, offset)
    if code is not None:
        return code
    item = snapshot.item_at(offset)
    if item is None:
        return None
    info = index.blocks.get(item.span.start)
    if info is not None:
        return Hover(block_markdown(snapshot, info), item.span)
    message = index.messages.get(item.span.start)
    if message is not None:
        return Hover(_rule_markdown(snapshot, script, message.id.text), item.span)
    goal = index.goals.get(item.span.start)
    if goal is not None:
        return Hover(_goal_markdown(script, goal), item.span)
    return None


# -- diagnostic codes --------------------------------------------------------------------------


def code_at(text: str, offset: int) -> tuple[str, Span] | None:
    """The diagnostic code written at `offset` (`L003`), if the word there is one."""
    start = offset
    while start > 0 and (text[start - 1].isalnum() or text[start - 1] == "_"):
        start -= 1
    m = _WORD.match(text, start)
    if m is None or not m.start() <= offset <= m.end() or not _CODE.fullmatch(m.group()):
        return None
    from scriptc.diagnostics.codes import REGISTRY

    if m.group() not in REGISTRY:
        return None
    return m.group(), Span(m.start(), m.end())


def code_markdown(code: str) -> str:
    from scriptc.diagnostics.codes import REGISTRY

    entry = REGISTRY[code]
    heading = f"**{entry.code}** `{entry.name}` ({entry.severity.value}): {entry.summary}"
    if entry.retired:
        heading += " (retired)"
    body = (entry.explanation or "(no explanation has been written for this code yet)").strip()
    return f"{heading}\n\n{body}"


def _code_hover(snapshot: Snapshot, offset: int) -> Hover | None:
    found = code_at(snapshot.text, offset)
    if found is None:
        return None
    code, span = found
    return Hover(code_markdown(code), span)


# -- names ------------------------------------------------------------------------------------


def _line(snapshot: Snapshot, offset: int) -> int:
    return snapshot.source.position(offset).line


def _occurrence_hover(snapshot: Snapshot, script: Script, o: Occurrence) -> Hover | None:
    text = _occurrence_markdown(snapshot, script, o)
    return Hover(text, o.span) if text else None


def _occurrence_markdown(snapshot: Snapshot, script: Script, o: Occurrence) -> str | None:
    index = snapshot.index
    kind, name = o.kind, o.name
    if kind == "label":
        info = index.label_blocks.get(name)
        if info is None:
            return f"**label** `{name}`: no block carries this label"
        where = _line(snapshot, info.block.span.start)
        text = (f"**label** `{name}` → `{info.path}`\n\n"
                f"Defined at line {where}, on {_block_kind(info)}.")
        others = [b for b in index.block_list if b.block.label is not None
                  and b.block.label.text == name and b.order != info.order]
        if others:
            lines = ", ".join(str(_line(snapshot, b.block.span.start)) for b in others)
            text += f"\n\nAlso on line {lines}: jumps go to the first (L001)."
        return text
    if kind == "function":
        return function_markdown(snapshot, name, getattr(o.detail, "kind", None))
    if kind == "class":
        return class_markdown(name)
    if kind == "field":
        # A field's detail is the class it belongs to, None when unknown.
        return field_markdown(name, o.detail if isinstance(o.detail, str) else None)
    if kind == "scope":
        meaning = SCOPES.get(name)
        return f"**scope** `{name}`: the binding lasts {meaning}" if meaning else None
    if kind == "alias":
        return _alias_markdown(snapshot, name)
    if kind == "this":
        cls = f" (a `{o.detail}`)" if o.detail else ""
        return f"`?THIS`: the candidate entity{cls} that a CLASS assignment's tests examine"
    if kind == "operator":
        word = OPERATORS.get(name)
        return f"`{name}`: the field is {word} the value" if word else None
    if kind == "rule":
        return _rule_markdown(snapshot, script, name)
    if kind in ("action-letter", "mutex-letter"):
        table, what = ((RULE_ACTIONS, "rule action") if kind == "action-letter"
                       else (MUTEXES, "mutex"))
        meaning = table.get(name)
        return f"**{what}** `{name}`: {meaning}" if meaning else None
    if kind == "goal":
        return _goal_markdown(script, o.detail)
    if kind == "activity":
        blocks = len(index.block_list)
        return (f"**activity** `{name}`: {len(script.goals)} goal{'s' * (len(script.goals) != 1)}, "
                f"{blocks} block{'s' * (blocks != 1)}")
    if kind == "var":
        return f"**variable** `{name}`: a value set by a `VAR` assignment (`F:` function)"
    if kind == "att":
        return f"**attribute** `{name}`: a value bound to an alias by an `ATT` assignment"
    return None


def function_markdown(snapshot: Snapshot, name: str, used_as: str | None = None) -> str | None:
    function = snapshot.functions.get(name)
    if function is None:
        return None
    lines = [f"```scriptc\n{function.signature}\n```", function.doc]
    if function.params:
        lines.append("\n".join(f"- `{p.name}`: {p.doc}" for p in function.params))
    if used_as is not None and used_as != function.kind:
        lines.append(f"(an `{function.kind}:` function, used here as `{used_as}:`)")
    return "\n\n".join(lines)


def class_markdown(name: str) -> str | None:
    fields = CLASSES.get(name)
    if fields is None:
        return None
    listed = "\n".join(f"- `{f.name}` ({f.type}): {f.doc}" for f in fields)
    return f"**class** `{name}` (a class of the map)\n\n{listed}"


def field_markdown(name: str, cls: str | None) -> str | None:
    if cls is not None:
        f = field_of(cls, name)
        if f is not None:
            return f"**field** `{name}` of `{cls}` ({f.type}): {f.doc}"
        return None
    owners = {c: f for c in CLASSES if (f := field_of(c, name)) is not None}
    if not owners:
        return None
    f = next(iter(owners.values()))  # the first owner's field tells the type and meaning
    return f"**field** `{name}` ({f.type}) of {', '.join(f'`{c}`' for c in owners)}: {f.doc}"


def _alias_markdown(snapshot: Snapshot, name: str) -> str:
    bindings = snapshot.index.alias_bindings.get(name, [])
    if not bindings:
        return f"**alias** `{name}`: no CLASS assignment binds it"
    sites = "\n".join(
        f"- line {_line(snapshot, b.alias.span.start)}: `{b.class_name.text}`, scope "
        f"`{b.scope.text}` ({SCOPES.get(b.scope.text, 'unknown scope')})" for b in bindings[:5])
    more = f"\n- ... and {len(bindings) - 5} more" if len(bindings) > 5 else ""
    return f"**alias** `{name}`, bound by a CLASS assignment:\n\n{sites}{more}"


def _rule_markdown(snapshot: Snapshot, script: Script, rule_id: str) -> str:
    messages = [m for m in (*script.alfa, *script.omega) if m.id.text == rule_id]
    lines = [f"**rule** `{rule_id}`"]
    for m in messages:
        lines.append(f"- line {_line(snapshot, m.span.start)}, {m.kind} "
                     f"(rulecode {m.rulecode.text}): "
                     f"`{m.action.text}` {RULE_ACTIONS.get(m.action.text, '(unknown action)')}; "
                     f"`{m.mutex.text}` {MUTEXES.get(m.mutex.text, '(unknown mutex)')}")
    return "\n".join(lines[:1]) + "\n\n" + "\n".join(lines[1:])


def _goal_markdown(script: Script, goal) -> str:
    g = script.goals.index(goal)
    blocks = sum(len(a.blocks) for a in goal.actions)
    return (f"**goal** `{goal.id.text}` (`goal{g}`): {len(goal.actions)} "
            f"action{'s' * (len(goal.actions) != 1)}, {blocks} block{'s' * (blocks != 1)}")


# -- blocks -----------------------------------------------------------------------------------


def format_ms(ms: float | None) -> str:
    """`1500 ms (1.5 s)`, `250 ms`, `?` for an unreadable time."""
    if ms is None:
        return "?"
    shown = f"{ms:g}" if ms != int(ms) else str(int(ms))
    if ms >= 1000:
        return f"{shown} ms ({ms / 1000:g} s)"
    return f"{shown} ms"


def _block_kind(info: BlockInfo) -> str:
    return {
        InstructionBlock: "an instruction block",
        JumpBlock: "a jump block",
        TerminusBlock: "a terminus block",
        SensorBlock: "a sensor block",
    }[type(info.block)]


def _title(info: BlockInfo, what: str) -> str:
    label = info.block.label
    named = f" `{label.text}`" if label is not None and label.text else ""
    return f"**{what}**{named} · `{info.path}`"


def block_markdown(snapshot: Snapshot, info: BlockInfo) -> str:
    block = info.block
    if isinstance(block, InstructionBlock):
        lines = [_title(info, "instruction block"),
                 (f"Takes **{format_ms(info.duration_ms)}**: its three tracks start together "
                  "and the block ends when the longest is done.")]
        for name, commands in (("MV", block.moves), ("LD", block.leds), ("AO", block.audios)):
            lines.append(_track_markdown(name, commands))
        return "\n\n".join(lines)
    if isinstance(block, JumpBlock):
        following = _next_path(snapshot, info)
        lines = [_title(info, "jump block"),
                 ("Takes no time: the condition is evaluated against the map when the block "
                  "is reached."),
                 f"```scriptc\n{block.condition_text}\n```"]
        targets = []
        for word, target in (("true", block.true_target), ("false", block.false_target)):
            if target is None or not target.text:
                targets.append(f"- if {word}: the next block, {following}")
            else:
                path = snapshot.index.label_paths.get(target.text)
                where = f"`{path}`" if path else "no block has this label"
                targets.append(f"- if {word}: `{target.text}` → {where}")
        lines.append("\n".join(targets))
        return "\n\n".join(lines)
    if isinstance(block, TerminusBlock):
        return f"{_title(info, 'terminus block')}\n\nEnds the script."
    payload = ", ".join(f"`{t.value}`" for t in block.payload) or "none"
    return (f"{_title(info, 'sensor block')}\n\nSends a sensor message, then goes on with the "
            f"next block, {_next_path(snapshot, info)}. Payload: {payload}.")


def _next_path(snapshot: Snapshot, info: BlockInfo) -> str:
    blocks = snapshot.index.block_list
    if info.order + 1 < len(blocks):
        return f"`{blocks[info.order + 1].path}`"
    return "(none: the script ends)"


def _track_markdown(name: str, commands) -> str:
    if not commands:
        return f"- `{name}`: nothing"
    count = len(commands)
    noun = {"MV": "move", "LD": "light", "AO": "sound"}[name]
    head = f"- `{name}`: {count} {noun}{'s' * (count != 1)}, {format_ms(track_time(commands))}"
    listed = [f"  - {_command_text(c)}" for c in commands[:_MAX_COMMANDS]]
    if count > _MAX_COMMANDS:
        listed.append(f"  - ... and {count - _MAX_COMMANDS} more")
    return head + "\n" + "\n".join(listed)


def _command_text(command) -> str:
    wait = command.wait_t.text
    prefix = "" if command.wait_t.value == 0 else f"after {wait} ms, "
    if isinstance(command, MoveCommand):
        speeds = (command.v_x, command.v_y, command.v_theta)
        if all(s.value == 0 for s in speeds):
            what = "stand still"
        else:
            what = (f"move at v_x {command.v_x.text} m/s, v_y {command.v_y.text} m/s, "
                    f"v_theta {command.v_theta.text} rad/s")
    elif isinstance(command, LedCommand):
        if command.turnas.value == 0:
            what = "LEDs off"
        else:
            what = f"LEDs rgb({command.r.text}, {command.g.text}, {command.b.text})"
    elif isinstance(command, AudioCommand):
        path = command.track_path.value
        what = "silence" if path == "Silence" else f"play `{path}`"
    else:  # pragma: no cover - the three command kinds are all there is
        what = "?"
    return f"{prefix}{what} for {command.duration.text} ms"

