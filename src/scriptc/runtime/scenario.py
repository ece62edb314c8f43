"""Scenario (world) files: what happens around the robot during a run, as data. Shared by
every executor.

A scenario is JSON (`schemas/scenario.schema.json`):

    {"updates": [{"at": 500, "objectid": "Human/kid1", "attributename": "poses",
                  "policy": "R", "jsonmsg": "{\\"positionrho\\": 0.8, \\"positiontheta\\": 0}"}],
     "operator": [{"at": 1000, "command": "safety_lock", "held": true},
                  {"at": 1200, "command": "drive", "v_x": 0.2, "duration": 500},
                  {"at": 3000, "command": "interrupt"}]}

`updates` are MapUpdate messages as the thesis's Wizard-of-Oz sensors would send them (thesis
4.5, tables 4.1/4.2); `jsonmsg` is the message's text or the JSON value itself. `operator` are
the joystick's events (thesis 5.3). A file is read whole and checked before the run starts,
as every JSON file of scriptc is read: `scriptc.frontend.jsonpos` (strict JSON, the number policy
of `scriptc.numbers`, at most MAX_DEPTH levels deep), then the shape and the declared ranges by
the JSON Schema (jsonschema is imported only here, only when a scenario is given), then every
update against the map's tables. Every problem is reported at once, each with its line and
column in the file and where in the document (`updates[2].policy`); an unknown key says which
known key it is close to. A `jsonmsg` given as text is pointed into, escapes and all.
"""

from __future__ import annotations

import difflib
import json
import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import cache
from typing import TYPE_CHECKING

from scriptc.analysis.read import ReadError, read_bytes
from scriptc.encoding import decode
from scriptc.frontend.jsonpos import JsonError, JsonNode, Member, parse_json, string_offsets
from scriptc.numbers import JSONValue
from scriptc.runtime.world import (
    JSONMSG_DEPTH,
    MapUpdate,
    Record,
    UpdateError,
    parse_update,
)
from scriptc.source import SourceFile, Span

if TYPE_CHECKING:
    from jsonschema import Draft202012Validator

    from scriptc.runtime.sensing import PlacedEntity

SCHEMA_NAME = "scenario.schema.json"


# Scenario values nest a few levels; an `audioin` jsonmsg may nest more, and goes on to code
# that recurses (jsonschema, the trace's JSON writer): the jsonmsg texts' bound holds for the
# file too. Deeper is an error at its bracket.
MAX_DEPTH = JSONMSG_DEPTH


class ScenarioError(Exception):
    """A scenario file that cannot be used: `problems` says each thing wrong (`where: what`),
    `positions` where it is in the file: (line, column), 1-based, or None when the file could
    not be read at all."""

    def __init__(self, path: str, problems: list[str],
                 positions: list[tuple[int, int] | None] | None = None,
                 spans: list[Span | None] | None = None) -> None:
        self.path = path
        self.problems = problems
        self.positions = positions if positions is not None else [None] * len(problems)
        # Where each problem is as a span of the file's text (None: the file as a whole), for
        # a reader that shows it in its source (a test file's `[world]` table).
        self.spans = spans if spans is not None else [None] * len(problems)
        super().__init__(f"scenario `{path}`: " + "; ".join(problems))

    def lines(self) -> list[str]:
        """One line per problem: `scenario FILE:LINE:COLUMN: where: what`."""
        out = []
        for problem, position in zip(self.problems, self.positions, strict=True):
            at = f":{position[0]}:{position[1]}" if position is not None else ""
            out.append(f"scenario {self.path}{at}: {problem}")
        return out


@dataclass(frozen=True, slots=True)
class TimedUpdate:
    """A map update of a scenario and the time it is delivered at."""

    at: int
    update: MapUpdate
    index: int  # position in the file's `updates`


@dataclass(frozen=True, slots=True)
class OperatorEvent:
    """An operator's joystick command of a scenario, at its time."""

    at: int
    command: str  # "safety_lock", "drive" or "interrupt"
    params: Record
    index: int


@dataclass
class Scenario:
    """A world file: timed map updates, operator events, placed entities."""

    path: str = ""  # as shown in traces and messages
    updates: list[TimedUpdate] = field(default_factory=list)
    operator: list[OperatorEvent] = field(default_factory=list)
    folder: str = ""  # where paths in the scenario (a `script_vect` update) are resolved from
    # Placed people, objects and obstacles, sensed by the simulation (runtime/sensing.py).
    entities: list[PlacedEntity] = field(default_factory=list)
    sensing_rate_hz: float = 10.0
    sensing_range: float | None = None


@cache
def _schema() -> Record:
    from scriptc.resources import schema_path

    schema: Record = json.loads(schema_path(SCHEMA_NAME).read_text(encoding="utf-8"))
    return schema


@cache
def _validator() -> Draft202012Validator:
    import jsonschema

    return jsonschema.Draft202012Validator(_schema())


def _where(steps: Iterable[str | int]) -> str:
    out = ""
    for step in steps:
        out += f"[{step}]" if isinstance(step, int) else (f".{step}" if out else str(step))
    return out or "the top level"


class _Problems:
    """The problems of one file, each with its position."""

    def __init__(self, source: SourceFile) -> None:
        self.source = source
        self.messages: list[str] = []
        self.positions: list[tuple[int, int] | None] = []
        self.spans: list[Span] = []

    def add(self, where: str, message: str, span: Span) -> None:
        position = self.source.position(min(span.start, len(self.source.text)))
        self.messages.append(f"{where}: {message}" if where else message)
        self.positions.append((position.line, position.column))
        self.spans.append(span)

    def raise_if_any(self) -> None:
        if self.messages:
            order = sorted(range(len(self.messages)), key=lambda i: self.spans[i].start)
            raise ScenarioError(self.source.path, [self.messages[i] for i in order],
                                [self.positions[i] for i in order],
                                [self.spans[i] for i in order])


def _shown(node: JsonNode, text: str) -> str:
    if node.kind in ("object", "array"):
        return f"an {node.kind}"
    written = text[node.start:node.end]
    return f"`{written[:37]}...`" if len(written) > 40 else f"`{written}`"


_TYPE_PHRASE = {"object": "an object", "array": "an array", "string": "a string",
                "integer": "a whole number", "number": "a number", "boolean": "`true` or `false`",
                "null": "`null`"}


def _schema_problems(root: JsonNode, problems: _Problems) -> None:
    """The JSON Schema's findings, in words, at the value (or the key) they are about."""
    text = problems.source.text
    forbidden_seen: set[tuple[int, str]] = set()
    errors = sorted(_validator().iter_errors(root.to_python()),
                    key=lambda e: list(map(str, e.absolute_path)))
    for error in errors:
        steps = list(error.absolute_path)
        where = _where(steps)
        node, _member = root.locate(steps)
        kind = error.validator
        schema = error.schema
        if kind == "additionalProperties":
            known = sorted(schema.get("properties", {}))
            for m in node.members:
                if m.key in known:
                    continue
                close = difflib.get_close_matches(m.key, known, n=1, cutoff=0.6)
                hint = (f"did you mean `{close[0]}`?" if close
                        else f"the keys here are {', '.join(f'`{k}`' for k in known)}")
                problems.add(where if steps else "", f"unknown key `{m.key}` ({hint})",
                             m.key_span)
        elif schema is False:
            # Keys the command of an operator event does not take (`"v_x": false` under an
            # `if`/`then`): jsonschema's path stops at the object, so find them in it.
            for m, what in _forbidden(node):
                if (m.key_start, m.key) not in forbidden_seen:
                    forbidden_seen.add((m.key_start, m.key))
                    problems.add(where, f"`{m.key}` is not a key of {what}", m.key_span)
        elif kind == "required":
            for key in error.validator_value:
                if node.get(key) is None:
                    problems.add(where, f"the key `{key}` is missing",
                                 Span(node.start, node.start + 1))
        elif kind == "type":
            expected = error.validator_value
            expected = [expected] if isinstance(expected, str) else expected
            phrase = " or ".join(_TYPE_PHRASE.get(t, t) for t in expected)
            problems.add(where, f"must be {phrase}, found {_shown(node, text)}", node.span)
        elif kind in ("enum", "const"):
            allowed = error.validator_value if kind == "enum" else [error.validator_value]
            close = [] if not isinstance(node.value, str) else difflib.get_close_matches(
                node.value, [a for a in allowed if isinstance(a, str)], n=1, cutoff=0.6)
            listed = ", ".join(f"`{a}`" for a in allowed)
            hint = f" (did you mean `{close[0]}`?)" if close else ""
            problems.add(where, f"must be one of {listed}, found {_shown(node, text)}{hint}",
                         node.span)
        elif kind in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
            bound = error.validator_value
            phrase = {"minimum": f"at least {bound}", "maximum": f"at most {bound}",
                      "exclusiveMinimum": f"greater than {bound}",
                      "exclusiveMaximum": f"less than {bound}"}[kind]
            problems.add(where, f"must be {phrase}, found {_shown(node, text)}", node.span)
        elif kind == "pattern":  # the description says the form (`Class/ID`: ...)
            form = schema.get("description", "of the form the schema gives").rstrip(".")
            problems.add(where, f"must be {form}, found {_shown(node, text)}", node.span)
        elif kind == "minLength":
            problems.add(where, "must not be empty", node.span)
        elif kind in ("if", "allOf"):
            continue  # the findings of their parts are reported on their own
        else:  # not produced by the shipped schema; kept readable for a changed schema
            problems.add(where, error.message, node.span)


def _forbidden(node: JsonNode) -> list[tuple[Member, str]]:
    """The members of `node` that a conditional rule of the schema forbids: the rules
    `{"if": {"properties": {K: {"const": C}}}, "then": {"properties": {KEY: false}}}` whose
    `K` is `C` in `node`; each with what the rule is about (`a `drive` event`)."""
    out = []
    for definition in _schema()["$defs"].values():
        for rule in definition.get("allOf", ()) if isinstance(definition, dict) else ():
            condition = rule.get("if", {}).get("properties", {})
            if not condition or not all(
                    (given := node.get(k)) is not None and given.value == c.get("const")
                    for k, c in condition.items()):
                continue
            banned = rule.get("then", {}).get("properties", {})
            what = " ".join(f"a `{c.get('const')}` event" for c in condition.values())
            out += [(m, what) for m in node.members if banned.get(m.key) is False]
    return out


def _update_span(item: JsonNode, exc: UpdateError, text: str,
                 offsets: StringOffsets = string_offsets) -> Span:
    """Where an update's problem is: inside its jsonmsg when the map said where (a key of the
    record, a place in its text), else the field it is about."""
    member = item.member(exc.field)
    if member is None:
        return Span(item.start, item.start + 1)
    node = member.value
    if exc.span is not None and node.kind == "string":
        where = offsets(text, node)
        last = len(where) - 1
        return Span(where[min(exc.span.start, last)], where[min(exc.span.end, last)])
    if exc.key is not None and node.kind == "object":
        inner = node.member(exc.key)
        if inner is not None:
            return inner.key_span if exc.unknown_key else inner.value.span
    return node.span


def scenario_from_text(text: str, path: str = "<scenario>", folder: str | None = None
                       ) -> Scenario:
    """A scenario from the text of a scenario file; raises ScenarioError listing every
    problem with its line and column. `folder` (default: the current directory) is where the
    scenario's paths are resolved from."""
    source = SourceFile(path, text)
    try:
        root = parse_json(text, max_depth=MAX_DEPTH)
    except JsonError as exc:
        raise ScenarioError(path, [exc.message], [(exc.line, exc.column)]) \
            from None
    return scenario_from_tree(root, source, folder)


# Where each character of a string value is in its document (`jsonpos.string_offsets` for
# JSON): how a problem inside a `jsonmsg` given as text is pointed at.
StringOffsets = Callable[[str, JsonNode], list[int]]


def scenario_from_tree(root: JsonNode, source: SourceFile, folder: str | None = None, *,
                       offsets: StringOffsets = string_offsets) -> Scenario:
    """A scenario from a document already read with the positions of its values: a JSON
    file's (`scenario_from_text`), or a table of another format given as the same nodes (a
    test file's `[world]` table, with TOML's `offsets` of string characters). Checked as a
    file is; raises ScenarioError."""
    path, text = source.path, source.text
    problems = _Problems(source)
    _schema_problems(root, problems)
    problems.raise_if_any()
    data = root.to_python()
    assert isinstance(data, dict)  # the schema has checked it: an object
    scenario = Scenario(path, folder=folder if folder is not None else os.getcwd())
    updates = root.get("updates")
    update_nodes = updates.items if updates is not None else []
    for i, item in enumerate(data.get("updates", ())):
        try:
            update = parse_update(item["objectid"], item["attributename"], item["policy"],
                                  item["jsonmsg"])
        except UpdateError as exc:
            node = update_nodes[i]
            problems.add(f"updates[{i}] (at {item['at']} ms)", str(exc),
                         _update_span(node, exc, text, offsets))
            continue
        scenario.updates.append(TimedUpdate(item["at"], update, i))
    for i, item in enumerate(data.get("operator", ())):
        params = {k: v for k, v in item.items() if k not in ("at", "command")}
        scenario.operator.append(OperatorEvent(item["at"], item["command"], params, i))
    if data.get("entities"):
        from scriptc.runtime.sensing import PlacedEntity

        for item in data["entities"]:
            scenario.entities.append(PlacedEntity.from_data(item))
    sensing = data.get("sensing", {})
    scenario.sensing_rate_hz = float(sensing.get("rate_hz", 10.0))
    scenario.sensing_range = sensing.get("range")
    problems.raise_if_any()
    scenario.updates.sort(key=lambda u: u.at)
    scenario.operator.sort(key=lambda o: o.at)
    return scenario


def scenario_from_data(data: JSONValue, path: str = "<scenario>", folder: str | None = None
                       ) -> Scenario:
    """A scenario from parsed JSON (a dict, as tests and generators build one): written as
    JSON text and read as a file is, so the same rules hold (a NaN in `data` is refused as
    in a file). Raises ScenarioError."""
    try:
        text = json.dumps(data, indent=1, ensure_ascii=False)
    except (TypeError, ValueError, RecursionError) as exc:
        raise ScenarioError(path, [f"not JSON data: {exc}"]) from None
    return scenario_from_text(text, path, folder)


def load_scenario(path: str) -> Scenario:
    """Read and check a scenario file; raises ScenarioError (also when it cannot be read)."""
    try:
        raw = read_bytes(path)
    except ReadError as exc:
        raise ScenarioError(path, [exc.reason]) from None
    decoded = decode(raw)
    text = decoded.text
    if decoded.bad is not None:
        line = text.count("\n", 0, decoded.bad) + 1
        column = decoded.bad - (text.rfind("\n", 0, decoded.bad) + 1) + 1
        raise ScenarioError(path, [f"{decoded.problem} (byte {decoded.byte} of the file)"],
                            [(line, column)])
    return scenario_from_text(text, path, os.path.dirname(os.path.abspath(path)))
