"""Thesis JSON -> the typed IR (for `scriptc check FILE.json` and `scriptc decompile`).

Three stages, each reporting in its own code:
1. `scriptc.frontend.jsonpos` parses the text, keeping the span of every key and value
   (J001 on text that is not JSON, at the exact position);
2. the document is validated against `schemas/thesis-script.schema.json`, plus the one rule a
   JSON Schema cannot state, that `goalN`, `actN` and `blkN` are numbered from 0 without gaps
   (J002 per violation: the span is the offending value, or the key for an unknown or
   misnumbered key; the message and `Diagnostic.path` name the JSON path such as
   `goal0/act0/blk1/move/0/wait_t`);
3. the IR is built with spans pointing into the JSON text. Numbers go through `read_number`
   like the script syntax's; `toparse` strings are parsed by the rule grammar
   (`scriptc.frontend.script.parse_condition`), with positions mapped back through JSON
   escapes; jump paths that name no block are J003.

The JSON has no labels: jumps name paths. The reader invents a label for every block some jump
targets, named after its path (`goal0/act0/blk4` -> `g0_a0_b4`), so the IR (and the script
text `decompile` writes from it) has a label wherever a jump needs one, and no other labels.
A J003 jump keeps a target of the same form (`g0_a0_b9`, or, when the text is not a path at
all, that text with every character a label cannot hold turned into `_`), which no block
carries: the IR stays honest about the jump pointing nowhere, and a checker run on it reports
the unknown label.

The IR is built only from a document of the right shape: after J001 or J002 the script is None.
A valid document is recognised by the schema file compiled to Python code ahead of time
(`thesis_validator.py`, fastjsonschema's output, kept current by `python -m scriptc.generate`);
jsonschema runs only on a document that is not valid, to list what is wrong, and is imported
then, so neither a lint of scripts nor a check of a valid document pays for it.
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Iterable, Mapping, Sequence
from functools import cache
from typing import TYPE_CHECKING

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.frontend.jsonpos import (
    JsonError,
    JsonNode,
    Member,
    parse_json,
    string_offsets,
)
from scriptc.gcpause import gc_paused
from scriptc.ir import nodes as ir
from scriptc.ir.fields import read_number
from scriptc.ir.shift import map_spans, shift
from scriptc.language import MUTEXES, RULE_ACTIONS, name_problem, to_name
from scriptc.numbers import MAX_DIGITS, JSONValue, whole_number
from scriptc.source import SourceFile, Span

if TYPE_CHECKING:  # (imported where it runs: only for a document that is not valid)
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import ValidationError

__all__ = ["invented_label", "script_from_json"]

SCHEMA_NAME = "thesis-script.schema.json"
_SCHEMA_DEPTH = 10
_INDEXED = {"goal": re.compile(r"goal(0|[1-9][0-9]*)"), "act": re.compile(r"act(0|[1-9][0-9]*)"),
            "blk": re.compile(r"blk(0|[1-9][0-9]*)")}
_PATH = re.compile(r"goal(0|[1-9][0-9]*)/act(0|[1-9][0-9]*)/blk(0|[1-9][0-9]*)")
# The letters as the thesis JSON writes them: their ASCII codes.
_ACTION_LETTERS = {ord(letter): letter for letter in RULE_ACTIONS}
_MUTEX_LETTERS = {ord(letter): letter for letter in MUTEXES}


# The index of a key or path written with more digits than any number holds (no file has that
# many goals or blocks): larger than every other index, and never converted (scriptc.numbers).
_HUGE_INDEX = 10 ** MAX_DIGITS


def _index(digits: str) -> int:
    """The number of `goalN`, `actN`, `blkN` (the digits of N, as the patterns match them)."""
    value = whole_number(digits)
    return _HUGE_INDEX if value is None else value


def invented_label(address: tuple[int, int, int]) -> str:
    """The label the reader gives the block at `address`: `g0_a0_b4`."""
    g, a, b = address
    return f"g{g}_a{a}_b{b}"


def script_from_json(source: SourceFile) -> tuple[ir.Script | None, list[Diagnostic]]:
    """Read thesis JSON. The script is None when the text is not JSON (J001) or not shaped
    like a thesis script (J002)."""
    with gc_paused():  # nothing built here forms a cycle (see scriptc.gcpause)
        return _read(source)


def _read(source: SourceFile) -> tuple[ir.Script | None, list[Diagnostic]]:
    try:
        root = parse_json(source.text)
    except JsonError as error:
        return None, [
            diagnostic(
                "J001",
                error.message,
                error.span,
                labels=tuple(Label(span, message) for span, message in error.labels),
            )
        ]
    problems = _schema_problems(root, source.text)
    problems.extend(_numbering_problems(root))
    if problems:
        return None, _dedupe(problems)
    return _Reader(source, root).script()


def _dedupe(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    seen: set[tuple[Span, str]] = set()
    out: list[Diagnostic] = []
    for d in diagnostics:
        key = (d.span, d.message)
        if key not in seen:
            seen.add(key)
            out.append(d)
    out.sort(key=Diagnostic.sort_key)
    return out


# ---------------------------------------------------------------------------------------------
# Shape: the JSON Schema, with messages written for people


@cache
def _schema() -> dict[str, JSONValue]:
    from scriptc.resources import schema_path

    schema: dict[str, JSONValue] = json.loads(schema_path(SCHEMA_NAME).read_text(encoding="utf-8"))
    return schema


@cache
def _validator() -> Draft202012Validator:
    import jsonschema

    return jsonschema.Draft202012Validator(_schema())


def _is_valid(instance: object) -> bool:
    """Whether the document is valid (tests hold the answer equal to jsonschema's). The schema
    compiled to Python by fastjsonschema (`thesis_validator.py`, generated from the schema
    file by `python -m scriptc.generate`) says yes to a valid document far sooner than
    jsonschema (a 10,000-block file: a fifth of a second, where jsonschema takes seconds)."""
    from scriptc.frontend.thesis_validator import JsonSchemaValueException, validate

    try:
        validate(instance)  # type: ignore[no-untyped-call]  # fastjsonschema's code: no types
    except JsonSchemaValueException:
        return False
    return True


def _join(steps: Iterable[str | int]) -> str:
    return "/".join(str(s) for s in steps)


def _where(path: str) -> str:
    return f"`{path}`" if path else "the top-level value"


_KIND_PHRASE = {"object": "an object", "array": "an array", "string": "a string",
                "integer": "an integer", "number": "a number", "boolean": "a boolean",
                "null": "`null`"}


def _shown_value(node: JsonNode, source: str) -> str:
    if node.kind == "object":
        return "an object"
    if node.kind == "array":
        return "an array"
    text = source[node.start:node.end]
    if len(text) > 40:
        text = text[:37] + "..."
    if node.kind == "string":
        return f"the string `{text}`"
    if node.kind == "number":
        return f"the number `{text}`"
    return f"`{text}`"


_SHAPE_HELP = {
    "": "a thesis script is an object with `activityname`, `alfarulemessages`, "
        "`omegarulemessages` and `goal0`, `goal1`, ...",
    "goal": "a goal holds `goalid` and its actions `act0`, `act1`, ...",
    "act": "an action holds its blocks `blk0`, `blk1`, ...",
    "instruction": "an instruction block holds `type`, `flagged` (always `\"flag\"`), `move`, "
                   "`led` and `audioout` (empty arrays included)",
    "jump": "a jump block holds `type`, `toparse`, `truejump` and `falsejump`",
    "terminus": "a terminus block holds `type` only",
    "sensor": "a sensor block holds `type` and `payload` (an array of strings)",
    "block": "a block holds `type`: `instruction`, `jump`, `terminus` or `sensor`",
    "message": "a rule message holds `rulecode`, `id`, `intopic`, `outtopic`, `action` and "
               "`mutexcmd`",
    "move": "a move holds `v_x`, `v_y`, `v_theta`, `wait_t` and `duration`",
    "led": "a led command holds `r`, `g`, `b`, `turnas`, `wait_t` and `duration`",
    "audioout": "an audio command holds `track_path`, `wait_t` and `duration`",
}


def _shape_of(steps: Sequence[str | int], instance: JSONValue) -> str:
    """Which kind of object the path `steps` names (a key of `_SHAPE_HELP`)."""
    if not steps:
        return ""
    last = steps[-1]
    if isinstance(last, int) and len(steps) >= 2:
        parent = steps[-2]
        if parent in ("alfarulemessages", "omegarulemessages"):
            return "message"
        if parent in ("move", "led", "audioout"):
            return parent
    if isinstance(last, str):
        if _INDEXED["goal"].fullmatch(last) and len(steps) == 1:
            return "goal"
        if _INDEXED["act"].fullmatch(last) and len(steps) == 2:
            return "act"
        if _INDEXED["blk"].fullmatch(last) and len(steps) == 3:
            kind = instance.get("type") if isinstance(instance, dict) else None
            if isinstance(kind, str) and kind in ("instruction", "jump", "terminus", "sensor"):
                return kind
            return "block"
    return ""


_NUMBER_TEXT_KEYS = {"v_x", "v_y", "v_theta", "r", "g", "b"}
_INTEGER_KEYS = {"wait_t", "duration", "turnas", "rulecode"}
_NAME_KEYS = {"activityname", "goalid", "id"}


def _type_help(steps: Sequence[str | int], node: JsonNode, expected: str,
               source: str) -> str | None:
    last = steps[-1] if steps else None
    if last in _NUMBER_TEXT_KEYS and node.kind == "number":
        return (f"the thesis JSON writes speeds and colour channels as strings: "
                f"`\"{source[node.start:node.end]}\"`")
    if last in _INTEGER_KEYS and node.kind == "string":
        inner = node.value
        if isinstance(inner, str) and re.fullmatch(r"-?[0-9]+", inner):
            return f"write the number without quotes: `{inner}`"
        return "write a whole number without quotes"
    if last in _INTEGER_KEYS and node.kind == "number":
        return "times, `turnas` and rulecodes are whole numbers"
    if expected == "array" and last in ("move", "led", "audioout", "payload"):
        return f"write `[]` when the block has no {last} command" if last != "payload" \
            else "write `[]` for no payload"
    return None


def _schema_problems(root: JsonNode, source_text: str) -> list[Diagnostic]:
    # The schema looks 7 levels deep (top, goal, action, block, track, command, field);
    # deeper containers are left empty, which changes no answer of the schema's and lets the
    # validators, which recurse and print values with repr, cope with any nesting.
    instance = root.to_python(max_depth=_SCHEMA_DEPTH)
    if _is_valid(instance):
        return []
    out: list[Diagnostic] = []
    done_required: set[str] = set()
    error: ValidationError  # (jsonschema's stubs leave iter_errors' items untyped)
    for error in _validator().iter_errors(instance):
        steps = list(error.absolute_path)
        path = _join(steps)
        node, member = root.locate(steps)
        validator = error.validator
        # The failing keyword's value in the schema, and the value it failed on.
        keyword_value: JSONValue = error.validator_value
        failed: JSONValue = error.instance
        if validator == "required":
            if path in done_required:
                continue
            done_required.add(path)
            missing = [k for k in keyword_value if k not in failed]
            span = member.key_span if member is not None else Span(node.start, node.start + 1)
            shape = _shape_of(steps, failed)
            for key in missing:
                out.append(diagnostic(
                    "J002",
                    f"{_where(path) if path else 'the top-level object'} has no key `{key}`",
                    span, help=_SHAPE_HELP.get(shape), path=_join([*steps, key]) or None))
        elif validator == "additionalProperties":
            schema = error.schema
            if not isinstance(schema, Mapping):  # (a keyword's error: its schema object)
                schema = {}
            known = set(schema.get("properties", {}))
            patterns = [re.compile(p) for p in schema.get("patternProperties", {})]
            shape = _shape_of(steps, failed)
            for m in node.members:
                if m.key in known or any(p.search(m.key) for p in patterns):
                    continue
                out.append(diagnostic(
                    "J002",
                    f"{_where(path) if path else 'the top-level object'} has an unknown key "
                    f"`{m.key}`",
                    m.key_span, help=_misnumbered_help(m.key) or _SHAPE_HELP.get(shape),
                    path=_join([*steps, m.key])))
        elif validator == "type":
            expected: str = (keyword_value if isinstance(keyword_value, str)
                             else keyword_value[0])
            out.append(diagnostic(
                "J002",
                f"{_where(path)} must be {_KIND_PHRASE.get(expected, expected)}, found "
                f"{_shown_value(node, source_text)}",
                node.span, help=_type_help(steps, node, expected, source_text),
                path=path or None))
        elif validator == "pattern":
            out.append(_pattern_problem(steps, path, node, source_text))
        elif validator in ("enum", "const"):
            out.append(_enum_problem(steps, path, node, validator == "enum", keyword_value,
                                     source_text))
        else:  # not produced by the shipped schema; kept readable for a changed schema
            out.append(diagnostic("J002", f"{_where(path)}: {error.message}", node.span,
                                  path=path or None))
    return out


def _misnumbered_help(key: str) -> str | None:
    m = re.fullmatch(r"(goal|act|blk)0+([0-9]+)", key)
    if m:
        return f"numbers have no leading zeros: `{m.group(1)}{m.group(2).lstrip('0') or '0'}`"
    return None


def _pattern_problem(steps: Sequence[str | int], path: str, node: JsonNode,
                     source: str) -> Diagnostic:
    last = steps[-1] if steps else None
    shown = _shown_value(node, source)
    if last in _NAME_KEYS:
        message = f"{_where(path)} is {shown}, which is not a name"
        help_ = ("names start with a letter or `_` and go on with letters, digits, `_` and `-` "
                 "(the script syntax cannot write other names)")
    elif last in _NUMBER_TEXT_KEYS:
        message = f"{_where(path)} must hold a decimal number, found {shown}"
        help_ = "write the number as text, such as `\"10\"` or `\"-0.5\"`"
    elif (last == "track_path" and isinstance(node.value, str)
          and not re.search(r"[\n\r]", node.value)):
        end = "starts" if node.value[:1].isspace() else "ends"
        message = f"{_where(path)} {end} with a blank: {shown}"
        help_ = ("the script syntax trims audio paths, so it cannot write this one: remove the "
                 "blank")
    else:
        message = f"{_where(path)} holds a line break"
        help_ = "the script syntax cannot write a line break inside a string: remove it"
    return diagnostic("J002", message, node.span, help=help_, path=path or None)


def _enum_problem(steps: Sequence[str | int], path: str, node: JsonNode, is_enum: bool,
                  allowed_value: JSONValue, source: str) -> Diagnostic:
    """`node` is none of the values an `enum` (`is_enum`, `allowed_value` a list) or `const`
    (`allowed_value` the one value) allows."""
    last = steps[-1] if steps else None
    shown = _shown_value(node, source)
    if last == "action":
        choices = ", ".join(f"{code} (`{letter}`)" for code, letter in _ACTION_LETTERS.items())
        return diagnostic("J002", f"{_where(path)} must be the ASCII code of a rule action, "
                          f"found {shown}", node.span, help=f"use one of {choices}",
                          path=path)
    if last == "mutexcmd":
        choices = ", ".join(f"{code} (`{letter}`)" for code, letter in _MUTEX_LETTERS.items())
        return diagnostic("J002", f"{_where(path)} must be the ASCII code of a mutex command, "
                          f"found {shown}", node.span, help=f"use one of {choices}",
                          path=path)
    if last == "type":
        return diagnostic("J002", f"{_where(path)} must be a block type, found {shown}",
                          node.span,
                          help="use `\"instruction\"`, `\"jump\"`, `\"terminus\"` or `\"sensor\"`",
                          path=path)
    if last == "flagged":
        return diagnostic("J002", f"{_where(path)} must be `\"flag\"`, found {shown}", node.span,
                          help="the thesis writes `\"flagged\":\"flag\"` in every instruction "
                          "block", path=path)
    allowed = allowed_value if is_enum else [allowed_value]
    listed = ", ".join(f"`{json.dumps(v)}`" for v in allowed)
    return diagnostic("J002", f"{_where(path)} must be one of {listed}, found {shown}",
                      node.span, path=path or None)


def _numbering_problems(root: JsonNode) -> list[Diagnostic]:
    """`goalN`, `actN`, `blkN` are numbered 0, 1, 2, ... without gaps (docs/json.md: "numbering
    starts at 0 inside each parent"; the robot walks them in order)."""
    out: list[Diagnostic] = []
    if root.kind != "object":
        return out
    work: list[tuple[JsonNode, str, str]] = [(root, "goal", "")]
    while work:
        node, prefix, path = work.pop()
        indexed: list[tuple[int, Member]] = []
        for m in node.members:
            if _INDEXED[prefix].fullmatch(m.key):
                indexed.append((_index(m.key[len(prefix):]), m))
        indexed.sort(key=lambda pair: pair[0])
        for expected, (index, m) in enumerate(indexed):
            if index != expected:
                where = f"`{path}`" if path else "the top-level object"
                out.append(diagnostic(
                    "J002",
                    f"{where} has `{m.key}` but no `{prefix}{expected}`: keys are numbered from 0 "
                    "without gaps",
                    m.key_span,
                    help=f"rename `{m.key}` to `{prefix}{expected}` (and the jump paths that name "
                    "it)",
                    path=f"{path}/{m.key}" if path else m.key))
                break
        child = {"goal": "act", "act": "blk"}.get(prefix)
        if child:
            for _, m in indexed:
                if m.value.kind == "object":
                    work.append((m.value, child, f"{path}/{m.key}" if path else m.key))
    return out


# ---------------------------------------------------------------------------------------------
# The IR


# A condition as `parse_condition` gives it: the condition (None when it does not parse) and
# the diagnostics.
_Parsed = tuple[ir.Condition | None, list[Diagnostic]]


def _parse_condition(text: str, base: int) -> _Parsed:
    from scriptc.frontend.script import parse_condition

    return parse_condition(text, base)


class _ConditionCache:
    """Files repeat conditions (every jump of the thesis's files is `! {TRUE}`): each distinct
    text is parsed once, at offset 0, and moved to where it stands."""

    def __init__(self) -> None:
        self._parsed: dict[str, _Parsed] = {}

    def parse(self, text: str, base: int) -> _Parsed:
        parsed = self._parsed.get(text)
        if parsed is None:
            parsed = self._parsed[text] = _parse_condition(text, 0)
        if base == 0:
            return parsed
        condition, problems = parsed
        return shift(condition, base), [shift(d, base) for d in problems]


# The reader reads a document the schema has checked: what it requires is there, of its kind.


def _required(node: JsonNode, key: str) -> JsonNode:
    """The value of `key` in an object of the checked document."""
    value = node.get(key)
    assert value is not None, key
    return value


def _string(node: JsonNode) -> str:
    """The value of a string of the checked document."""
    value = node.value
    assert isinstance(value, str), node
    return value


def _integer(node: JsonNode) -> int:
    """The value of an integer of the checked document."""
    value = node.value
    assert isinstance(value, int), node
    return value


def _json_escape_edit(edit: TextEdit) -> TextEdit:
    # A fix written for the condition's text lands inside a JSON string.
    return TextEdit(edit.span, json.dumps(edit.new_text, ensure_ascii=False)[1:-1])


class _Reader:
    def __init__(self, source: SourceFile, root: JsonNode) -> None:
        self.source = source
        self.root = root
        self.diagnostics: list[Diagnostic] = []
        self.addresses: dict[str, tuple[int, int, int]] = {}
        self.targets: set[tuple[int, int, int]] = set()
        self.conditions = _ConditionCache()

    # -- leaves -----------------------------------------------------------------------------

    def name(self, node: JsonNode) -> ir.Name:
        return ir.Name(_string(node), node.content_span)

    def text(self, node: JsonNode) -> ir.Text:
        return ir.Text(_string(node), node.span)

    def number_text(self, node: JsonNode, what: str) -> ir.Number:
        number, problem = read_number(_string(node), node.content_span, what)
        if problem is not None:
            self.diagnostics.append(problem)
        return number

    def integer(self, node: JsonNode, what: str) -> ir.Number:
        number, problem = read_number(node.raw, node.span, what)
        if problem is not None:
            self.diagnostics.append(problem)
        return number

    # -- structure --------------------------------------------------------------------------

    @staticmethod
    def indexed(node: JsonNode, prefix: str) -> list[Member]:
        pattern = _INDEXED[prefix]
        found = [(_index(m.key[len(prefix):]), m) for m in node.members
                 if pattern.fullmatch(m.key)]
        found.sort(key=lambda pair: pair[0])
        return [m for _, m in found]

    def script(self) -> tuple[ir.Script, list[Diagnostic]]:
        root = self.root
        goals_json = self.indexed(root, "goal")
        # First pass: every block's path, and which blocks jumps target.
        for g, gm in enumerate(goals_json):
            for a, am in enumerate(self.indexed(gm.value, "act")):
                for b, _bm in enumerate(self.indexed(am.value, "blk")):
                    self.addresses[f"goal{g}/act{a}/blk{b}"] = (g, a, b)
        for gm in goals_json:
            for am in self.indexed(gm.value, "act"):
                for bm in self.indexed(am.value, "blk"):
                    if _required(bm.value, "type").value == "jump":
                        for key in ("truejump", "falsejump"):
                            address = self.addresses.get(_string(_required(bm.value, key)))
                            if address is not None:
                                self.targets.add(address)

        alfa = tuple(self.rule_message(n, "alfa")
                     for n in _required(root, "alfarulemessages").items)
        omega = tuple(self.rule_message(n, "omega")
                      for n in _required(root, "omegarulemessages").items)
        goals: list[ir.Goal] = []
        for g, gm in enumerate(goals_json):
            actions: list[ir.Action] = []
            for a, am in enumerate(self.indexed(gm.value, "act")):
                blocks = tuple(self.block((g, a, b), bm)
                               for b, bm in enumerate(self.indexed(am.value, "blk")))
                actions.append(ir.Action(blocks, am.key_span))
            goals.append(ir.Goal(self.name(_required(gm.value, "goalid")), tuple(actions),
                                 gm.key_span))
        activity = self.name(_required(root, "activityname"))
        self.activity_name(activity)
        script = ir.Script(activity, alfa, omega, tuple(goals), root.span)
        self.diagnostics.sort(key=Diagnostic.sort_key)
        return script, self.diagnostics

    def activity_name(self, name: ir.Name) -> None:
        """The schema holds every name to the name pattern; an activity name must also not be
        a word that opens an item, or the script `decompile` writes would not compile."""
        problem = name_problem(name.text, activity=True)
        if problem is not None:
            self.diagnostics.append(diagnostic(
                "J002", f"`activityname` is `{name.text}`, which cannot name an activity: "
                f"{problem}", name.span, help="give the activity another name",
                path="activityname"))

    def rule_message(self, node: JsonNode, kind: str) -> ir.RuleMessage:
        action = _required(node, "action")
        mutex = _required(node, "mutexcmd")
        return ir.RuleMessage(
            kind=kind,
            rulecode=self.integer(_required(node, "rulecode"), "the rulecode"),
            id=self.name(_required(node, "id")),
            intopic=self.text(_required(node, "intopic")),
            outtopic=self.text(_required(node, "outtopic")),
            action=ir.Name(_ACTION_LETTERS[_integer(action)], action.span),
            mutex=ir.Name(_MUTEX_LETTERS[_integer(mutex)], mutex.span),
            span=node.span,
        )

    def block(self, address: tuple[int, int, int], member: Member) -> ir.Block:
        node = member.value
        span = Span(member.key_start, node.end)
        label = (ir.Name(invented_label(address), member.key_span)
                 if address in self.targets else None)
        kind = _required(node, "type").value
        if kind == "instruction":
            return ir.InstructionBlock(
                label,
                tuple(self.move(n) for n in _required(node, "move").items),
                tuple(self.led(n) for n in _required(node, "led").items),
                tuple(self.audio(n) for n in _required(node, "audioout").items),
                span,
            )
        if kind == "jump":
            toparse = _required(node, "toparse")
            return ir.JumpBlock(
                label=label,
                condition=self.condition(toparse),
                true_target=self.target(_required(node, "truejump"), address, "truejump"),
                false_target=self.target(_required(node, "falsejump"), address, "falsejump"),
                span=span,
                condition_text=_string(toparse),
            )
        if kind == "terminus":
            return ir.TerminusBlock(label, span)
        return ir.SensorBlock(label, tuple(self.text(n) for n in _required(node, "payload").items),
                              span)

    # -- commands ---------------------------------------------------------------------------

    def move(self, node: JsonNode) -> ir.MoveCommand:
        return ir.MoveCommand(
            self.number_text(_required(node, "v_x"), "`v_x`"),
            self.number_text(_required(node, "v_y"), "`v_y`"),
            self.number_text(_required(node, "v_theta"), "`v_theta`"),
            self.integer(_required(node, "wait_t"), "`wait_t`"),
            self.integer(_required(node, "duration"), "`duration`"),
            node.span,
        )

    def led(self, node: JsonNode) -> ir.LedCommand:
        return ir.LedCommand(
            self.number_text(_required(node, "r"), "`r`"),
            self.number_text(_required(node, "g"), "`g`"),
            self.number_text(_required(node, "b"), "`b`"),
            self.integer(_required(node, "turnas"), "`turnas`"),
            self.integer(_required(node, "wait_t"), "`wait_t`"),
            self.integer(_required(node, "duration"), "`duration`"),
            node.span,
        )

    def audio(self, node: JsonNode) -> ir.AudioCommand:
        path = _required(node, "track_path")
        return ir.AudioCommand(
            ir.Text(_string(path), path.content_span),
            self.integer(_required(node, "wait_t"), "`wait_t`"),
            self.integer(_required(node, "duration"), "`duration`"),
            node.span,
        )

    # -- jumps ------------------------------------------------------------------------------

    def condition(self, node: JsonNode) -> ir.Condition:
        text = _string(node)
        base = node.start + 1
        if self.source.text[base:node.end - 1] == text:
            condition, problems = self.conditions.parse(text, base)
        else:
            # Escapes make the value shorter than its text: parse the value, then map each
            # position back to the character of the JSON text it came from.
            offsets = string_offsets(self.source.text, node)
            last = len(offsets) - 1

            def remap(span: Span) -> Span:
                return Span(offsets[min(span.start, last)], offsets[min(span.end, last)])

            condition, problems = self.conditions.parse(text, 0)
            condition = map_spans(condition, remap)
            mapped = []
            for problem in problems:
                d = map_spans(problem, remap)
                if d.fix is not None:
                    d = dataclasses.replace(d, fix=Fix(d.fix.message, tuple(
                        _json_escape_edit(e) for e in d.fix.edits), d.fix.safe))
                mapped.append(d)
            problems = mapped
        self.diagnostics.extend(problems)
        if condition is None:
            # Reported above; the block keeps an empty condition so the rest can be checked.
            condition = ir.Condition((), (), node.content_span)
        return condition

    def target(self, node: JsonNode, address: tuple[int, int, int], key: str) -> ir.Name | None:
        path = _string(node)
        if path == "":
            return None
        span = node.content_span
        found = self.addresses.get(path)
        if found is not None:
            return ir.Name(invented_label(found), span)
        where = f"goal{address[0]}/act{address[1]}/blk{address[2]}/{key}"
        m = _PATH.fullmatch(path)
        if m:
            message = f"`{where}` is `{path}`, which names no block of the script"
            name = f"g{m.group(1)}_a{m.group(2)}_b{m.group(3)}"  # invented_label's form
            help_ = self._path_help(m)
        else:
            message = f"`{where}` is `{path}`, which is not a block path `goalG/actA/blkB`"
            name = to_name(path)
            help_ = ("write the path of the target block, such as `goal0/act0/blk4`, or `\"\"` "
                     "to go on with the next block")
        self.diagnostics.append(diagnostic("J003", message, span, help=help_, path=where))
        return ir.Name(name, span)

    def _path_help(self, m: re.Match[str]) -> str:
        g, a = _index(m.group(1)), _index(m.group(2))
        blocks = sorted(b for (gg, aa, b) in self.addresses.values() if gg == g and aa == a)
        if blocks:
            return (f"`goal{g}/act{a}` has blocks `blk0` to `blk{blocks[-1]}`")
        acts = sorted({aa for (gg, aa, _b) in self.addresses.values() if gg == g})
        if acts:
            return f"`goal{g}` has actions `act0` to `act{acts[-1]}`"
        goals = sorted({gg for (gg, _a, _b) in self.addresses.values()})
        return f"the script has goals `goal0` to `goal{goals[-1]}`"
