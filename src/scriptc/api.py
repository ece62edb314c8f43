"""A Python API for script generators (docs/api.md).

The thesis's generators (`ScriptGen.cpp`, `DanceExample.cpp`) wrote the JSON line by line by
hand. This module builds a script in code, or fills a script template with parameters, and
gives the same diagnostics as `scriptc lint` and the validated JSON or bytecode:

    from scriptc.api import Activity, move, led, audio
    act = Activity("dance")
    act.alfa(0, "kick_starter", action="C", mutex="U")
    act.omega(0, "kick_starter", action="R", mutex="L")
    a = act.goal("dance").action()
    a.instruction(moves=[move(0.2, 0, 0, wait=0, duration=1000)], label="start")
    a.jump("! {TRUE}", true="start")
    a.terminus()
    built = act.build()
    built.json() if built.ok else print(built.report())

How: the builder makes IR nodes with placeholder spans, prints them with the canonical printer
(`scriptc.emit.script`), and analyses the printed text with
`scriptc.analysis.analyze.analyze_script`. So the diagnostics are exactly the CLI's on
`Built.script_text`, and their positions point
into that text. A condition is given as text and printed into its jump block token for token,
only its blanks laid out as the formatter lays them out (text that is not made of the
language's tokens is printed exactly as written), so an error in it points at what the caller
wrote. The printed script is in the formatter's layout: `scriptc fmt --check` passes it.

Templates: `fill(template, **params)` replaces `${name}` placeholders (`$$` is a literal `$`);
inside a string literal the value is escaped as the language requires.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from decimal import Decimal

from scriptc.analysis.analyze import Analysis
from scriptc.emit.script import format_script
from scriptc.ir import nodes as ir
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.language import quote
from scriptc.robot.profile import Profile
from scriptc.source import SourceFile, Span

__all__ = [
    "Action",
    "Activity",
    "BuildError",
    "Built",
    "Goal",
    "Numeric",
    "audio",
    "build_text",
    "fill",
    "fill_text",
    "led",
    "move",
    "number_text",
]

Numeric = int | float | str | Decimal
"""A number for a command or message: an int, a finite float, a Decimal, or the number's text
(kept as written: `"0.20"` stays `0.20` in the JSON)."""

_NOWHERE = Span(0, 0)  # placeholder span of built IR nodes (the analysis uses printed text)


class BuildError(ValueError):
    """The script has errors, so it has no JSON or bytecode; the message is the report."""


# ---------------------------------------------------------------------------------------------
# Values


def number_text(value: Numeric, what: str = "a number") -> str:
    """The text of a number as the script writes it: ints and Decimals as `str`, floats as
    their shortest `repr` (`0.2` -> `"0.2"`), strings as given (stripped). Raises ValueError
    for NaN, infinities, booleans, empty strings and other types; a string that is not a
    number is kept, and the analysis reports it (V001/P codes), as for a hand-written script.
    """
    if isinstance(value, bool):
        raise ValueError(f"{what} must be a number, not the boolean {value!r}")
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{what} must be a finite number, not {value!r}")
        text = repr(value)
        return text
    if isinstance(value, Decimal):
        if not value.is_finite():
            raise ValueError(f"{what} must be a finite number, not {value}")
        return str(value)
    if isinstance(value, str):
        text = value.strip()
        if not text:
            raise ValueError(f"{what} is empty")
        if any(c in text for c in '\r\n",[]%'):
            raise ValueError(f"{what} {value!r} holds a character a number cannot hold")
        try:
            parsed = float(text)
        except ValueError:
            return text  # not a number: reported by the analysis with its position
        if not math.isfinite(parsed):
            raise ValueError(f"{what} must be a finite number, not {value!r}")
        return text
    raise ValueError(f"{what} must be an int, float, Decimal or str, not {type(value).__name__}")


def _num(value: Numeric, what: str) -> ir.Number:
    return ir.Number(number_text(value, what), _NOWHERE)


def _text(value: str, what: str) -> ir.Text:
    if not isinstance(value, str):
        raise ValueError(f"{what} must be a string, not {type(value).__name__}")
    if "\n" in value or "\r" in value:
        raise ValueError(f"{what} {value!r} holds a line break, which a script string cannot")
    return ir.Text(value, _NOWHERE)


def _name(value: str, what: str) -> ir.Name:
    if not isinstance(value, str):
        raise ValueError(f"{what} must be a string, not {type(value).__name__}")
    if "\n" in value or "\r" in value:
        raise ValueError(f"{what} {value!r} holds a line break")
    # Anything else is printed as given; an invalid name is reported by the analysis.
    return ir.Name(value, _NOWHERE)


def _label(value: str | None) -> ir.Name | None:
    return None if value is None or value == "" else _name(value, "the label")


def move(v_x: Numeric, v_y: Numeric, v_theta: Numeric, *, wait: Numeric = 0,
         duration: Numeric) -> ir.MoveCommand:
    """A move command: speeds `v_x`, `v_y`, `v_theta`, then `wait` and `duration` in ms."""
    return ir.MoveCommand(_num(v_x, "`v_x`"), _num(v_y, "`v_y`"), _num(v_theta, "`v_theta`"),
                          _num(wait, "`wait_t`"), _num(duration, "`duration`"), _NOWHERE)


def led(r: Numeric, g: Numeric, b: Numeric, turnas: Numeric = 1, *, wait: Numeric = 0,
        duration: Numeric) -> ir.LedCommand:
    """A led command: colour channels `r`, `g`, `b`, `turnas`, then `wait` and `duration`."""
    return ir.LedCommand(_num(r, "`r`"), _num(g, "`g`"), _num(b, "`b`"),
                         _num(turnas, "`turnas`"), _num(wait, "`wait_t`"),
                         _num(duration, "`duration`"), _NOWHERE)


def audio(track_path: str, *, wait: Numeric = 0, duration: Numeric) -> ir.AudioCommand:
    """An audio command: the track's path (commas allowed), then `wait` and `duration`."""
    path = _text(track_path, "the audio track path")
    if path.value != path.value.strip():
        raise ValueError(f"the audio track path {track_path!r} starts or ends with a blank")
    return ir.AudioCommand(path, _num(wait, "`wait_t`"), _num(duration, "`duration`"), _NOWHERE)


# ---------------------------------------------------------------------------------------------
# The builder

# The printer needs a Condition; the condition text the caller wrote is printed instead.
_PLACEHOLDER_CONDITION = ir.Condition((), (), _NOWHERE, bare_true=True)


@dataclass
class _Jump:
    """A jump block whose condition is text (printed into `CND(...)` token for token)."""

    label: str | None
    condition: str
    true: str | None
    false: str | None

    def block(self) -> ir.JumpBlock:
        return ir.JumpBlock(_label(self.label), _PLACEHOLDER_CONDITION, _label(self.true),
                            _label(self.false), _NOWHERE)


class Action:
    """The blocks of one `[action]`, in order. Each method appends a block and returns the
    action, so calls can be chained."""

    def __init__(self) -> None:
        self._blocks: list[ir.Block | _Jump] = []

    def instruction(self, moves: Iterable[ir.MoveCommand] = (),
                    leds: Iterable[ir.LedCommand] = (),
                    audios: Iterable[ir.AudioCommand] = (), *,
                    label: str | None = None) -> Action:
        """An instruction block: its three tracks (from `move`, `led`, `audio`) run together."""
        moves, leds, audios = tuple(moves), tuple(leds), tuple(audios)
        for kind, items, cls in (("moves", moves, ir.MoveCommand), ("leds", leds, ir.LedCommand),
                                 ("audios", audios, ir.AudioCommand)):
            for item in items:
                if not isinstance(item, cls):
                    raise ValueError(f"`{kind}` holds {item!r}; build commands with "
                                     f"`{cls.__name__[:-7].lower()}(...)`")
        self._blocks.append(ir.InstructionBlock(_label(label), moves, leds, audios, _NOWHERE))
        return self

    def jump(self, condition: str, *, true: str | None = None, false: str | None = None,
             label: str | None = None) -> Action:
        """A jump block: `condition` in the rule grammar (e.g. `"! {TRUE}"`), written token for
        token (its blanks laid out as the formatter does);
        `true`/`false` are the labels to jump to (None: continue with the next block)."""
        if not isinstance(condition, str):
            raise ValueError(f"the condition must be a string, not {type(condition).__name__}")
        for name in (label, true, false):
            _label(name)  # refuse what cannot be printed now, not at build time
        self._blocks.append(_Jump(label or None, condition, true or None, false or None))
        return self

    def terminus(self, *, label: str | None = None) -> Action:
        """A terminus block: the activity ends here."""
        self._blocks.append(ir.TerminusBlock(_label(label), _NOWHERE))
        return self

    def sensor(self, *payload: str, label: str | None = None) -> Action:
        """A sensor block (`blk_sens`) with optional payload strings."""
        texts = tuple(_text(p, "a sensor payload") for p in payload)
        self._blocks.append(ir.SensorBlock(_label(label), texts, _NOWHERE))
        return self


class Goal:
    """A `[goal:ID]` and its actions."""

    def __init__(self, goal_id: str) -> None:
        self.id = _name(goal_id, "the goal id")
        self._actions: list[Action] = []

    def action(self) -> Action:
        """Append a new `[action]` to the goal and return it."""
        action = Action()
        self._actions.append(action)
        return action


class Activity:
    """A script under construction: its name, alfa and omega messages, and goals."""

    def __init__(self, name: str) -> None:
        self.name = _name(name, "the activity name")
        self._alfa: list[ir.RuleMessage] = []
        self._omega: list[ir.RuleMessage] = []
        self._goals: list[Goal] = []

    def _message(self, kind: str, rulecode: Numeric, rule_id: str, intopic: str,
                 outtopic: str, action: str, mutex: str) -> ir.RuleMessage:
        return ir.RuleMessage(kind, _num(rulecode, "the rulecode"), _name(rule_id, "the rule id"),
                              _text(intopic, "the intopic"), _text(outtopic, "the outtopic"),
                              _name(action, "the rule action"), _name(mutex, "the mutex command"),
                              _NOWHERE)

    def alfa(self, rulecode: Numeric, rule_id: str, *, intopic: str = "", outtopic: str = "",
             action: str, mutex: str) -> Activity:
        """An alfa message (`[alfa:RULECODE, ID, "in", "out", ACTION, MUTEX]`)."""
        self._alfa.append(self._message("alfa", rulecode, rule_id, intopic, outtopic, action,
                                        mutex))
        return self

    def omega(self, rulecode: Numeric, rule_id: str, *, intopic: str = "", outtopic: str = "",
              action: str, mutex: str) -> Activity:
        """An omega message (`[omega:RULECODE, ID, "in", "out", ACTION, MUTEX]`)."""
        self._omega.append(self._message("omega", rulecode, rule_id, intopic, outtopic, action,
                                          mutex))
        return self

    def goal(self, goal_id: str) -> Goal:
        """Append a new `[goal:ID]` and return it."""
        goal = Goal(goal_id)
        self._goals.append(goal)
        return goal

    def to_ir(self) -> ir.Script:
        """The activity as IR (placeholder spans; each jump's condition is `{TRUE}` here, the
        text given to `jump` is printed by `script_text`)."""
        return self._ir({})

    def _ir(self, conditions: dict[int, str]) -> ir.Script:
        """The IR, recording in `conditions` the caller's condition text of each jump block
        (by the block's identity)."""
        def block(b: ir.Block | _Jump) -> ir.Block:
            if not isinstance(b, _Jump):
                return b
            jump = b.block()
            conditions[id(jump)] = b.condition
            return jump

        goals = tuple(
            ir.Goal(goal.id, tuple(ir.Action(tuple(block(b) for b in action._blocks), _NOWHERE)
                                   for action in goal._actions), _NOWHERE)
            for goal in self._goals)
        return ir.Script(self.name, tuple(self._alfa), tuple(self._omega), goals, _NOWHERE)

    def script_text(self) -> str:
        """The canonical script text of the activity (what `build` analyses): the canonical
        printer's text of the activity, each jump's condition the text given to `jump`, laid
        out as the formatter lays it out (only its blanks can change)."""
        conditions: dict[int, str] = {}
        script = self._ir(conditions)
        return format_script(script, lambda jump: conditions[id(jump)])

    def build(self, path: str | None = None, *, functions: FunctionRegistry = STANDARD,
              profile: Profile | None = None) -> Built:
        """Print and analyse the activity; `path` is the name diagnostics show
        (`NAME.script` by default). `functions` and `profile` are those of `build_text`."""
        return build_text(self.script_text(), path or f"{self.name.text}.script",
                          functions=functions, profile=profile)


# ---------------------------------------------------------------------------------------------
# The result


class Built(Analysis):
    """A script text and what `scriptc lint` finds in it (same codes, same positions): an
    `Analysis` (`source`, `script`, `diagnostics`, `ok`, `errors`, `codes`) that also gives
    its report, its JSON and its bytecode."""

    __slots__ = ()

    @property
    def script_text(self) -> str:
        return self.source.text

    def report(self, format: str = "text") -> str:
        """The diagnostics rendered as the CLI renders them (`text`, `json`, `sarif`,
        `github`)."""
        from scriptc.diagnostics.render import render

        return render(format, [self])

    def _checked(self) -> ir.Script:
        if not self.ok or self.script is None:
            n = len(self.errors)
            raise BuildError(f"the script has {n} error{'s' if n != 1 else ''}, so it cannot "
                             f"be compiled:\n{self.report()}")
        return self.script

    def json(self) -> str:
        """The thesis JSON text; raises BuildError when the script has errors."""
        from scriptc.ops.build import emit

        return emit(self._checked(), "json")

    def bytecode(self) -> bytes:
        """The `.scb` bytecode; raises BuildError when the script has errors."""
        from scriptc.ops.build import emit

        return emit(self._checked(), "bytecode", self.source)


def build_text(text: str, path: str = "<generated>.script", *,
               functions: FunctionRegistry = STANDARD, profile: Profile | None = None) -> Built:
    """Analyse script text as `scriptc lint` does without configuration files: with the
    standard B/F/E functions and the default robot profile unless `functions` (a
    `scriptc.ir.builtins.FunctionRegistry`) or `profile` (a `scriptc.robot.profile.Profile`) say
    otherwise."""
    from scriptc.analysis.analyze import analyze_script

    analysis = analyze_script(SourceFile(path, text), functions, profile)
    return Built(analysis.source, analysis.script, analysis.diagnostics, analysis.suppressed)


# ---------------------------------------------------------------------------------------------
# Templates

# `${name}` (a Python identifier) or `$$`. `${` never occurs in the language: `$` only
# starts an attribute name (`$mood`), which is an identifier.
_PLACEHOLDER = re.compile(r"\$\$|\$\{([A-Za-z_][A-Za-z0-9_]*)\}|\$\{")


def _value_text(name: str, value: object, in_string: bool) -> str:
    if isinstance(value, str):
        if in_string and ("\n" in value or "\r" in value):
            raise ValueError(f"the value of `{name}` holds a line break, which a script "
                             "string cannot")
        return quote(value)[1:-1] if in_string else value
    if isinstance(value, (bool, int, float, Decimal)):
        return number_text(value, f"the value of `{name}`")
    raise ValueError(f"the value of `{name}` must be a str or a number, "
                     f"not {type(value).__name__}")


def fill_text(template: str, params: Mapping[str, object] | None = None, /,
              **kwargs: object) -> str:
    """The template with its placeholders replaced: `${name}` by the value of `name` (a
    string, or a number written as `number_text` writes it), `$$` by `$`. Inside a string
    literal of the template (`"..."`) a string value is escaped (`\\` and `"`); outside, it
    is inserted as it is (a label, a condition). Raises ValueError for a placeholder with no
    value, a value no placeholder uses, or a malformed `${`."""
    values = dict(params or {})
    values.update(kwargs)
    out: list[str] = []
    used: set[str] = set()
    missing: list[str] = []
    pos = 0
    in_string = in_comment = False
    i = 0
    n = len(template)
    while i < n:
        c = template[i]
        if in_string:
            if c == "\\" and i + 1 < n and template[i + 1] in '\\"':
                i += 2
                continue
            if c == '"' or c in "\r\n":
                in_string = False
        elif in_comment:
            if c == "%":
                in_comment = False
        elif c == '"':
            in_string = True
        elif c == "%":
            in_comment = True
        if c == "$":
            m = _PLACEHOLDER.match(template, i)
            if m is not None:
                out.append(template[pos:i])
                if m.group(0) == "$$":
                    out.append("$")
                elif m.group(1) is None:
                    raise ValueError(f"malformed placeholder at offset {i}: write `${{name}}` "
                                     "(a Python identifier), or `$$` for a literal `$`")
                else:
                    key = m.group(1)
                    used.add(key)
                    if key in values:
                        out.append(_value_text(key, values[key], in_string))
                    elif key not in missing:
                        missing.append(key)
                i = pos = m.end()
                continue
        i += 1
    out.append(template[pos:])
    if missing:
        raise ValueError("no value for the placeholder" + ("s " if len(missing) > 1 else " ")
                         + ", ".join(f"`${{{k}}}`" for k in missing))
    unused = sorted(set(values) - used)
    if unused:
        raise ValueError("no placeholder uses " + ", ".join(f"`{k}`" for k in unused))
    return "".join(out)


def fill(template: str, params: Mapping[str, object] | None = None, /, *,
         path: str = "<template>.script", functions: FunctionRegistry = STANDARD,
         profile: Profile | None = None, **kwargs: object) -> Built:
    """Fill the template (`fill_text`) and analyse the result (`build_text`). Values named
    `path`, `functions` or `profile` must be given in the `params` mapping."""
    return build_text(fill_text(template, params, **kwargs), path, functions=functions,
                      profile=profile)
