"""Reading a test file (`*.test.toml`, docs/testing.md) and checking it whole before anything
runs, as a scenario file is checked: every problem is a diagnostic of family T in the test
file, at the key or value it is about, with its line and column (`tomllib` gives no positions:
`scriptc.project.config.tomlpos` finds them).

In order: the bytes and the TOML syntax (T001; `read_toml`, the configuration's reader), the
shape by the JSON Schema `schemas/test.schema.json` (T002 for an unknown key, with the known
key it is close to; T003 for the rest; `TomlChecker`, the configuration's checker), the number
policy, then what a schema cannot say (T003): one kind of expectation per `[[expect]]` and no
key of another kind, trace event kinds and their fields (from the trace's schema), the form of
`count`, windows in order, instants within `until`, an `at` that checks something, the form of
`distance.to`. The files a test names must exist (T004), and its world must be a scenario
(T005): a world file is read as `scriptc run --world` reads it; an inline `[world]` table is
checked by the same code, at its place in the test file.
"""

from __future__ import annotations

import difflib
import json
import os
import re
from dataclasses import dataclass
from functools import cache
from typing import Any

from scriptc.analysis.read import read_bytes
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.frontend.jsonpos import JsonNode, Member
from scriptc.paths import shown_path
from scriptc.project.config.load import read_toml
from scriptc.project.config.tomlpos import KeyPath, KeySpans, TOMLTable, string_offsets
from scriptc.project.config.validate import TomlChecker
from scriptc.runtime.scenario import Scenario, ScenarioError, load_scenario, scenario_from_tree
from scriptc.runtime.trace import EVENT_KINDS
from scriptc.source import SourceFile, Span
from scriptc.testing import SUFFIX, is_test_file
from scriptc.testing.model import (
    DEFAULT_ROBOT,
    DEFAULT_TOLERANCE,
    DEFAULT_UNTIL,
    END,
    Count,
    DistanceExpectation,
    EventExpectation,
    Expectation,
    PoseExpectation,
    SessionExpectation,
    StateExpectation,
    TestFile,
    Window,
)

__all__ = ["SUFFIX", "ReadTest", "is_test_file", "read_test", "test_from_text"]

# The keys of each kind of expectation (`name` goes with all of them).
KINDS: dict[str, tuple[str, ...]] = {
    "event": ("event", "where", "within", "count"),
    "at": ("at", "pose", "led", "audio", "block"),
    "outcome": ("outcome", "time"),
    "distance": ("distance", "within"),
}
# The keys that make an `[[expect]]` of a kind, in the order they are looked for.
_KIND_OF = {"event": "event", "at": "at", "outcome": "outcome", "time": "outcome",
            "distance": "distance"}
_COUNT = re.compile(r"\s*(>=|<=|==)?\s*([0-9]+)\s*")
_ENTITY = re.compile(r"(Human|Object|Obstacle)/(\*|[^/*]+)")


@dataclass(frozen=True, slots=True)
class ReadTest:
    """A test file read: its source, the test when it has no problem, else its diagnostics
    (sorted by position)."""

    source: SourceFile
    test: TestFile | None
    diagnostics: list[Diagnostic]


@cache
def schema() -> dict[str, Any]:
    from scriptc.resources import schema_path

    loaded: dict[str, Any] = json.loads(schema_path("test.schema.json").read_text(
        encoding="utf-8"))
    return loaded


@cache
def event_fields() -> dict[str, tuple[str, ...] | None]:
    """The fields of each kind of trace event (the trace's schema), `t` and `event` aside;
    None for a kind whose events may have any field (`rule_note`)."""
    from scriptc.resources import schema_path

    trace = json.loads(schema_path("trace.schema.json").read_text(encoding="utf-8"))
    out: dict[str, tuple[str, ...] | None] = {}
    for kind in EVENT_KINDS:
        definition = trace["$defs"][kind]
        fields = tuple(k for k in definition.get("properties", {}) if k not in ("t", "event"))
        out[kind] = None if definition.get("additionalProperties", False) is not False \
            else fields
    return out


def read_test(path: str) -> ReadTest:
    """Read and check the test file `path`; raises ReadError when it cannot be read at all."""
    return test_from_bytes(read_bytes(path), path)


def test_from_bytes(data: bytes, path: str) -> ReadTest:
    """The test file `path` whose content is `data` (see `read_test`)."""
    text, table, problem = read_toml(data, what="the test file", syntax="T001", value="T003")
    source = SourceFile(shown_path(path), text)
    if table is None:
        assert problem is not None  # a file that is not read says why
        return ReadTest(source, None, [problem])
    return _check(table, source, path)


def test_from_text(text: str, path: str) -> ReadTest:
    """The test file `path` whose text is `text` (tests, the language server)."""
    return test_from_bytes(text.encode("utf-8"), path)


# ---------------------------------------------------------------------------------------------


class _Checker(TomlChecker):
    """The schema's checks (`TomlChecker`), then what a schema cannot say; `expectations`
    collects the expectations read."""

    def __init__(self, source: SourceFile, path: str) -> None:
        super().__init__(source, schema=schema(), unknown="T002", invalid="T003",
                         what="the test file", reference="docs/testing.md")
        self.path = path
        self.folder = os.path.dirname(path)
        self.until = DEFAULT_UNTIL

    def schema_error(self, error: Any) -> None:
        if tuple(error.absolute_path) == ("expect",) and error.validator == "type" \
                and isinstance(error.instance, dict):
            self.report("T003", "`expect` must be an array of tables, not a table", ("expect",),
                        at="key", help="write each expectation as an `[[expect]]` table (two "
                        "brackets), one after the other")
            return
        super().schema_error(error)

    def span(self, path: KeyPath, at: str = "value") -> Span:
        return self.positions.find(path, prefer=at)

    # -- files ---------------------------------------------------------------------------------

    def resolve(self, written: str) -> str:
        """A path of the test file, as a path from the working folder."""
        return os.path.normpath(os.path.join(self.folder, written))

    def scripts(self, table: TOMLTable) -> tuple[str, ...]:
        found = []
        for i, written in _strings(table.get("scripts")):
            path = self.resolve(written)
            if not os.path.isfile(path):
                self.missing(f"the script `{written}`", path, ("scripts", i))
            found.append(path)
        return tuple(found)

    def missing(self, what: str, path: str, at: KeyPath) -> None:
        """`path` (`what` the test names) is not a file: it does not exist, or is a folder."""
        problem = "is a folder, not a file" if os.path.isdir(path) else "does not exist"
        self.report("T004", f"{what} {problem}", at,
                    notes=(_relative_note(path),))

    def world(self, table: TOMLTable) -> tuple[Scenario | None, str | None]:
        world = table.get("world")
        if isinstance(world, str):
            path = self.resolve(world)
            if not os.path.isfile(path):
                self.missing(f"the world file `{world}`", path, ("world",))
                return None, None
            try:
                return load_scenario(path), path
            except ScenarioError as exc:
                for problem, position in zip(exc.problems, exc.positions, strict=True):
                    at = f":{position[0]}:{position[1]}" if position is not None else ""
                    self.report("T005", f"the world `{shown_path(path)}{at}`: {problem}",
                                ("world",), help="a world file is a scenario, as `scriptc run "
                                "--world` reads it (docs/runtime.md)")
                return None, None
        if isinstance(world, dict):
            root = _tree(world, ("world",), self.positions, self.source.text)
            try:
                return scenario_from_tree(root, self.source, self.folder or ".",
                                          offsets=_toml_string_offsets), self.path
            except ScenarioError as exc:
                for problem, span in zip(exc.problems, exc.spans, strict=True):
                    self.out.append(diagnostic(
                        "T005", f"in `[world]`: {problem}",
                        span if span is not None else self.span(("world",), "key"),
                        help="a `[world]` table has the keys of a scenario file "
                        "(docs/runtime.md)"))
        return None, None

    # -- expectations --------------------------------------------------------------------------

    def expectations(self, table: TOMLTable) -> list[Expectation]:
        items = table.get("expect")
        if not isinstance(items, list):
            return []
        out = []
        for i, item in enumerate(items):
            if isinstance(item, dict):
                expectation = self.expectation(i, item)
                if expectation is not None:
                    out.append(expectation)
        return out

    def expectation(self, i: int, item: TOMLTable) -> Expectation | None:
        at: KeyPath = ("expect", i)
        kinds = list(dict.fromkeys(_KIND_OF[k] for k in item if k in _KIND_OF))
        if not kinds:
            self.report("T003", f"`expect[{i}]` says nothing to check", at, at="key",
                        help="give it `event`, `at`, `outcome`, `time` or `distance` "
                        "(docs/testing.md)")
            return None
        if len(kinds) > 1:
            first, second = (next(k for k in item if _KIND_OF.get(k) == kind) for kind in
                             kinds[:2])
            self.report("T003", f"`expect[{i}]` holds two kinds of expectation: `{first}` and "
                        f"`{second}`", at + (second,), at="key",
                        help="write each in its own `[[expect]]`")
            return None
        kind = kinds[0]
        allowed = (*KINDS[kind], "name")
        wrong = False
        for key in item:
            if key not in allowed and key in {k for keys in KINDS.values() for k in keys}:
                owner = next(k for k, keys in KINDS.items() if key in keys)
                self.report("T003", f"`{key}` belongs to an `{owner}` expectation, not to an "
                            f"`{kind}` one", at + (key,), at="key",
                            help=f"the keys of an `{kind}` expectation are "
                            + ", ".join(f"`{k}`" for k in allowed))
                wrong = True
        name = item.get("name")
        name = name if isinstance(name, str) else f"expect #{i + 1}"
        span = self.span(at)
        read = {"event": self.event, "at": self.state, "outcome": self.session,
                "distance": self.distance}[kind]
        expectation = read(i, name, span, item)  # its own problems, reported either way
        return None if wrong else expectation

    def window(self, i: int, item: TOMLTable) -> Window | None:
        within = item.get("within")
        if within is None:
            return Window()
        if not (isinstance(within, list) and len(within) == 2
                and all(isinstance(t, int) and not isinstance(t, bool) for t in within)):
            return None  # the schema said why
        start, end = within
        if start > end:
            self.report("T003", f"`expect[{i}].within` ends before it starts ({start} > "
                        f"{end} ms)", ("expect", i, "within"),
                        help="write the window as [from, to]")
            return None
        if start > self.until:
            self.report("T003", f"`expect[{i}].within` starts at {start} ms, after `until` "
                        f"({self.until} ms): the run never gets there", ("expect", i, "within"))
            return None
        return Window(start, end)

    def event(self, i: int, name: str, span: Span, item: TOMLTable) -> EventExpectation | None:
        at: KeyPath = ("expect", i)
        event, where = item.get("event"), item.get("where", {})
        ok = isinstance(event, str) and isinstance(where, dict)
        if isinstance(event, str) and event not in EVENT_KINDS:
            self.unknown_word("T003", f"`{event}` is not a kind of trace event", event,
                              EVENT_KINDS, at + ("event",),
                              "the kinds are listed in docs/runtime.md, The trace")
            ok = False
        elif isinstance(event, str) and isinstance(where, dict):
            fields = event_fields()[event] or ()
            for key in where if event_fields()[event] is not None else ():
                if key not in fields:
                    self.unknown_word("T003", f"a `{event}` event has no field `{key}`", key,
                                      fields, at + ("where", key),
                                      "its fields are " + ", ".join(f"`{f}`" for f in fields),
                                      prefer="key")
                    ok = False
        count = self.count(i, item.get("count", ">=1"))
        window = self.window(i, item)
        if not ok or count is None or window is None:
            return None
        assert isinstance(event, str) and isinstance(where, dict)
        return EventExpectation(i, name, span, event, where, window, count)

    def count(self, i: int, value: Any) -> Count | None:
        if isinstance(value, int) and not isinstance(value, bool):
            if value < 0:
                self.report("T003", f"`expect[{i}].count` must be at least 0, not {value}",
                            ("expect", i, "count"))
                return None
            return Count("==", value)
        if not isinstance(value, str):
            return None  # the schema said why
        m = _COUNT.fullmatch(value)
        if m is None:
            self.report("T003", f"`expect[{i}].count` must be \"N\", \">=N\" or \"<=N\", not "
                        f"`{value}`", ("expect", i, "count"),
                        help="\"2\": exactly two; \">=1\": at least one; \"0\": never")
            return None
        return Count(m.group(1) or "==", int(m.group(2)))

    def state(self, i: int, name: str, span: Span, item: TOMLTable) -> StateExpectation | None:
        path: KeyPath = ("expect", i)
        when, ok = item.get("at"), True
        instant: int | None = None
        if isinstance(when, str) and when != END:
            self.report("T003", f"`expect[{i}].at` must be a time in ms or \"end\", not "
                        f"`{when}`", path + ("at",))
            ok = False
        elif isinstance(when, int) and not isinstance(when, bool):
            if when < 0:
                self.report("T003", f"`expect[{i}].at` must be at least 0, not {when}",
                            path + ("at",))
                ok = False
            elif when > self.until:
                self.report("T003", f"`expect[{i}].at` is {when} ms, after `until` "
                            f"({self.until} ms): the run never gets there", path + ("at",),
                            help="check the state at an instant before `until`, or at \"end\"")
                ok = False
            instant = when
        elif when != END:
            ok = False  # the schema said why
        if not any(key in item for key in ("pose", "led", "audio", "block")):
            self.report("T003", f"`expect[{i}]` checks nothing at its instant", path + ("at",),
                        at="key", help="give it `pose`, `led`, `audio` or `block`")
            ok = False
        pose = self.pose(i, item.get("pose"))
        led, led_off = self.led(i, item.get("led"))
        audio, block = item.get("audio"), item.get("block")
        if not ok or ("pose" in item and pose is None) or ("led" in item and led is None
                                                          and not led_off):
            return None
        if (audio is not None and not isinstance(audio, str)) or \
                (block is not None and not isinstance(block, str)):
            return None
        return StateExpectation(i, name, span, instant, pose, led, led_off,
                                None if audio is None else "" if audio == "none" else audio,
                                None if block is None else "" if block == "none" else block)

    def pose(self, i: int, value: Any) -> PoseExpectation | None:
        if not isinstance(value, dict):
            return None
        axes = {k: v for k, v in value.items() if k in ("x", "y", "theta")
                and isinstance(v, (int, float)) and not isinstance(v, bool)}
        if not any(k in value for k in ("x", "y", "theta")):
            self.report("T003", f"`expect[{i}].pose` checks nothing", ("expect", i, "pose"),
                        help="give it any of `x`, `y` and `theta`")
            return None
        tolerance = value.get("tolerance", DEFAULT_TOLERANCE)
        if len(axes) != sum(1 for k in value if k in ("x", "y", "theta")) or \
                not isinstance(tolerance, (int, float)) or isinstance(tolerance, bool):
            return None  # the schema said why
        x, y, theta = (float(axes[k]) if k in axes else None for k in ("x", "y", "theta"))
        return PoseExpectation(x, y, theta, float(tolerance))

    def led(self, i: int, value: Any) -> tuple[tuple[float, float, float] | None, bool]:
        if isinstance(value, str):
            if value != "off":
                self.report("T003", f"`expect[{i}].led` must be a colour [r, g, b] or \"off\", "
                            f"not `{value}`", ("expect", i, "led"))
            return None, value == "off"
        if isinstance(value, list) and len(value) == 3 and all(
                isinstance(c, (int, float)) and not isinstance(c, bool) for c in value):
            return (float(value[0]), float(value[1]), float(value[2])), False
        return None, False

    def session(self, i: int, name: str, span: Span, item: TOMLTable
                ) -> SessionExpectation | None:
        outcome, time = item.get("outcome"), item.get("time", {})
        if not isinstance(time, dict) or (outcome is not None and not isinstance(outcome, str)):
            return None
        low, high = time.get("min"), time.get("max")
        if "time" in item and low is None and high is None:
            self.report("T003", f"`expect[{i}].time` checks nothing", ("expect", i, "time"),
                        help="give it `min`, `max` or both (ms)")
            return None
        if isinstance(low, int) and isinstance(high, int) and low > high:
            self.report("T003", f"`expect[{i}].time` has `min` ({low} ms) above `max` "
                        f"({high} ms)", ("expect", i, "time"))
            return None
        if (low is not None and not isinstance(low, int)) or \
                (high is not None and not isinstance(high, int)):
            return None
        return SessionExpectation(i, name, span, outcome, low, high)

    def distance(self, i: int, name: str, span: Span, item: TOMLTable
                 ) -> DistanceExpectation | None:
        value = item.get("distance")
        window = self.window(i, item)
        if not isinstance(value, dict):
            return None
        to, low = value.get("to"), value.get("min")
        if isinstance(to, str) and _ENTITY.fullmatch(to) is None:
            self.report("T003", f"`expect[{i}].distance.to` must be `Class/ID` or `Class/*` "
                        f"of a Human, Object or Obstacle, not `{to}`",
                        ("expect", i, "distance", "to"),
                        help="`Human/kid1` is one child, `Human/*` every person")
            return None
        if not isinstance(to, str) or not isinstance(low, (int, float)) or \
                isinstance(low, bool) or window is None:
            return None
        return DistanceExpectation(i, name, span, to, float(low), window)

    def unknown_word(self, code: str, message: str, word: str, known: tuple[str, ...] | list[str],
                     path: KeyPath, otherwise: str, prefer: str = "value") -> None:
        close = difflib.get_close_matches(word, list(known), n=1, cutoff=0.6)
        self.report(code, message, path, at=prefer,
                    help=f"did you mean `{close[0]}`?" if close else otherwise)


def _relative_note(path: str) -> str:
    return f"a test's paths are relative to the test file: this is `{shown_path(path)}`"


def _strings(value: Any) -> list[tuple[int, str]]:
    return [(i, v) for i, v in enumerate(value) if isinstance(v, str)] \
        if isinstance(value, list) else []


def _check(table: TOMLTable, source: SourceFile, path: str) -> ReadTest:
    checker = _Checker(source, path)
    checker.check_schema(table)
    before = len(checker.out)
    checker.numbers(table)
    beyond_policy = len(checker.out) > before
    until = table.get("until", DEFAULT_UNTIL)
    if isinstance(until, int) and not isinstance(until, bool):
        checker.until = until
    scripts = checker.scripts(table)
    # A world with numbers beyond the policy was reported whole (`numbers`); the scenario's
    # ranges would let a NaN through.
    world, world_arg = (None, None) if beyond_policy else checker.world(table)
    expectations = checker.expectations(table)
    problems = sorted(checker.out, key=Diagnostic.sort_key)
    if problems:
        return ReadTest(source, None, problems)
    description = table.get("description", "")
    governor = table.get("governor")
    return ReadTest(source, TestFile(
        path=path, source=source, description=description if isinstance(description, str)
        else "", scripts=scripts, world=world, world_arg=world_arg,
        robot=table.get("robot", DEFAULT_ROBOT), governor=governor if isinstance(governor, bool)
        else None, until=checker.until, expectations=tuple(expectations),
        head=checker.span(("scripts",), "key"),
        snapshot=checker.span(("snapshot",), "key") if table.get("snapshot") is True
        else None), [])


# -- a TOML table as located JSON nodes (the `[world]` table, read as a scenario) ---------------


def _tree(table: TOMLTable, prefix: KeyPath, spans: KeySpans, text: str) -> JsonNode:
    """The table at `prefix` as the nodes the scenario's reader takes (`jsonpos`), each with
    the span of its value in the TOML text, each member with its key's."""
    def made(value: Any, path: KeyPath) -> JsonNode:
        span = spans.find(path)
        if isinstance(value, dict):
            return JsonNode("object", span.start, span.end)
        if isinstance(value, list):
            return JsonNode("array", span.start, span.end)
        if isinstance(value, bool):
            return JsonNode("boolean", span.start, span.end, value)
        if isinstance(value, (int, float)):
            return JsonNode("number", span.start, span.end, value, text[span.start:span.end])
        if isinstance(value, str):
            return JsonNode("string", span.start, span.end, value)
        return JsonNode("string", span.start, span.end, str(value))  # a date or a time

    root = made(table, prefix)
    stack: list[tuple[Any, KeyPath, JsonNode]] = [(table, prefix, root)]
    while stack:
        value, path, node = stack.pop()
        if isinstance(value, dict):
            for key, inner in value.items():
                child = made(inner, path + (key,))
                key_span = spans.find(path + (key,), prefer="key")
                node.members.append(Member(key, key_span.start, key_span.end, child))
                stack.append((inner, path + (key,), child))
        elif isinstance(value, list):
            for index, inner in enumerate(value):
                child = made(inner, path + (index,))
                node.items.append(child)
                stack.append((inner, path + (index,), child))
    return root


def _toml_string_offsets(text: str, node: JsonNode) -> list[int]:
    return string_offsets(text, node.span)
