"""Runs you can replay: a path the exploration found, turned into a world (a scenario file of
timed map updates) under which the runtime itself takes that path, and the replay that
confirms it (docs/verify.md, "Counterexamples and witnesses").

The exploration lets the world decide every jump it can decide; a path is a choice at each
of those jumps. The world is made instant by instant, in time order: at each instant where
the path needs jumps to come out a given way, the updates that make the map so are chosen
(an entity for each CLASS assignment that must pass, every entity of a class failing the
tests of one that must not, a field set for a comparison after the `!`), delivered at that
instant (a jump read at `t` sees every update that arrived at `t`), and the session is run up
to that instant to check that every jump so far went where the path goes. When a choice does
not work, the next is tried. The run is the runtime's own (`runtime.session.Session`): what
verify calls confirmed is what `scriptc run --world` shows.
"""

from __future__ import annotations

import contextlib
import itertools
import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from scriptc import interrupt
from scriptc.ir import nodes as ir
from scriptc.numbers import JSONObject, JSONValue
from scriptc.runtime.commands import as_number, format_number
from scriptc.runtime.scenario import Scenario, TimedUpdate
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Event, Trace
from scriptc.runtime.world import ENTITY_CLASSES, UpdateError, parse_update
from scriptc.verify.explore import ENDED, Visit
from scriptc.verify.model import JUMP, Model

if TYPE_CHECKING:
    from scriptc.robot.profile import Profile
    from scriptc.runtime.executor import Loadable
    from scriptc.runtime.functions import Implementations
    from scriptc.runtime.loop import RunResult
    from scriptc.runtime.rules import RuleLibrary

__all__ = ["Ask", "Built", "Runner", "build_world", "expected_jumps", "jumps_of"]

# Choices tried for the world at one instant before the path is given up as not replayable.
MAX_TRIES = 24
# Fields an update can set, by the attribute that carries them (runtime/world.py).
_POSE = ("positionrho", "positiontheta", "positionchangetime")
_TRACKING = ("permanencetime", "appearanceon")
_SINGLE = ("isfixed", "istarget", "category")


@dataclass
class Runner:
    """Runs the program under a world, as `scriptc run --world` does (on the kinematic robot:
    the world's updates are timed, so the robot's motion changes nothing of the path), with
    the governor when `governed` (the safety property)."""

    program: Loadable
    functions: Implementations
    rules: RuleLibrary
    profile: Profile | None = None
    folder: str = ""
    runs: int = 0

    def run(self, updates: Sequence[TimedUpdate], until: int | None,
            governed: bool = False) -> RunResult:
        self.runs += 1
        scenario = Scenario(path="verify", updates=list(updates), folder=self.folder)
        session = Session((self.program,), scenario=scenario, robot="kinematic",
                          functions=self.functions, rules=self.rules, trace=Trace(),
                          profile=self.profile if governed else None)
        return session.run(until)


@dataclass(frozen=True, slots=True)
class Ask:
    """The path needs the jump `step` (a block index) read at `t` to come out `outcome`; or,
    with `condition`, an override's condition to hold at `t` (the switch fires then: `tick`
    asks for an instant of the run there)."""

    t: int
    step: int
    outcome: bool
    condition: ir.Condition | None = None


@dataclass
class Built:
    """A world made for a path: its `updates` (in time order), and whether every jump of the
    path came out as the path says (`ok`; else `failed_at`, the instant no world was found
    for, and `why`)."""

    updates: list[TimedUpdate] = field(default_factory=list)
    ok: bool = True
    failed_at: int | None = None
    why: str = ""
    result: RunResult | None = None  # the run that took the path

    def as_json(self, description: str) -> JSONObject:
        """The scenario file's content (schemas/scenario.schema.json)."""
        return {"description": description,
                "updates": [{"at": u.at, "objectid": u.update.objectid,
                             "attributename": u.update.attributename,
                             "policy": u.update.policy, "jsonmsg": u.update.value}
                            for u in self.updates]}


def expected_jumps(model: Model, visits: Sequence[Visit]) -> list[tuple[int, str, bool]]:
    """The jumps a run taking `visits` reads: (instant, block path, value), in order."""
    out = []
    for before, after in itertools.pairwise(visits):
        if before.node != ENDED and model.steps[before.node].kind == JUMP:
            assert after.via is not None
            out.append((before.t, model.steps[before.node].address.path, after.via))
    return out


def jumps_of(events: Sequence[Event]) -> list[tuple[int, str, bool]]:
    """The jumps a trace shows: (instant, block path, value), in order."""
    return [(int(e["t"]), str(e["path"]), bool(e["value"])) for e in events
            if e["event"] == "jump"]


def asks_of(model: Model, visits: Sequence[Visit]) -> list[Ask]:
    """The jumps of a path that the world decides, with the outcome the path takes, and the
    switches that fire on it (their condition must hold then)."""
    out = []
    for before, after in itertools.pairwise(visits):
        if after.switch >= 0:
            switch = model.switches[after.switch]
            out.append(Ask(after.t, -1, True, switch.condition))
            continue
        if before.node == ENDED:
            continue
        step = model.steps[before.node]
        if step.kind == JUMP and step.outcomes is not None and step.outcomes.world:
            assert after.via is not None
            out.append(Ask(before.t, before.node, after.via))
    return out


def build_world(model: Model, visits: Sequence[Visit], runner: Runner, *,
                until: int | None = None, governed: bool = False, max_runs: int = 40) -> Built:
    """A world under which the runtime takes the path `visits` (see the module's docstring),
    every jump up to the path's last instant checked in the runtime's trace. The world is made
    whole, each instant's most likely choice first, and run once; where the run leaves the
    path, the next choice for that instant is tried (and the instants after it made again),
    up to `max_runs` runs. Each run goes to `until` (None: the path's last instant, or the
    end of the session if it ends there), with the governor when `governed`: the run that
    took the path is the built world's `result`. A run that Ctrl-C stopped raises
    `interrupt.Interrupted`. The path's jumps must be the first the run reads: the run goes
    on reading after the path's last block (its jump at the same instant, a cycle that lets
    no time pass going round until the runtime gives up), and those jumps are not the
    path's."""
    expected = expected_jumps(model, visits)
    instants = [(t, list(group)) for t, group in
                itertools.groupby(asks_of(model, visits), key=lambda a: a.t)]
    last = max((v.t for v in visits), default=0)
    tried: dict[int, int] = {}  # instant -> how many of its choices were tried
    known = _predicted(model, visits)
    built = Built()
    for _ in range(max_runs):
        updates = _make(model, instants, tried, known)
        if updates is None:
            break
        result = runner.run(updates, last if until is None else max(until, last), governed)
        if result.outcome == "interrupted":
            raise interrupt.Interrupted("interrupted (Ctrl-C)")
        actual = jumps_of(result.trace.events)
        wrong = _first_difference(actual[:len(expected)], expected, last)
        if wrong is None:
            built.updates = updates
            built.result = result
            return built
        # The first instant where the run left the path: its next choice, with the VAR
        # values the run really had.
        known.update(_values(e for e in result.trace.events if int(e["t"]) < wrong))
        if wrong not in dict(instants):
            built.ok, built.failed_at = False, wrong
            built.why = f"the runtime's jump at {wrong} ms does not go the path's way"
            return built
        tried[wrong] = tried.get(wrong, 0) + 1
        for t, _asks in instants:
            if t > wrong:
                tried.pop(t, None)
    built.ok = False
    built.failed_at = min((t for t in tried), default=None)
    built.why = "no world was found in which every jump goes the path's way"
    return built


def _make(model: Model, instants: list[tuple[int, list[Ask]]], tried: dict[int, int],
          known: dict[str, str]) -> list[TimedUpdate] | None:
    """The world's updates: at each instant, its choice number `tried[t]` (0: the first);
    None when an instant has no such choice left."""
    maker = _Maker(model)
    out: list[TimedUpdate] = []
    for k, (t, asks) in enumerate(instants):
        if k % 64 == 0:
            interrupt.check()
        skip = tried.get(t, 0)
        choice = next(itertools.islice(maker.choices(asks, t, known), skip, None), None)
        if choice is None:
            return None
        maker.commit(choice)
        out.extend(choice)
        if any(ask.condition is not None for ask in asks):
            out.append(_tick(t, len(choice)))
    return out


def _tick(t: int, index: int) -> TimedUpdate:
    """An update that changes nothing a condition reads (the robot's battery), so that the
    run has an instant at `t`: the chain of rules passes at every instant, and a switch's
    condition is read then."""
    return TimedUpdate(t, parse_update("RobotStatus/verify", "batterytimeleft", "R",
                                       3_600_000), index)


def _predicted(model: Model, visits: Sequence[Visit]) -> dict[str, str]:
    """The VAR values a path's run will show, as far as verify knows them: a VAR given the
    time (`F: now()`) at a jump holds that jump's instant."""
    out: dict[str, str] = {}
    for v in visits:
        if v.node == ENDED or model.steps[v.node].kind != JUMP:
            continue
        block = model.program.blocks[v.node][1]
        assert isinstance(block, ir.JumpBlock)
        for a in block.condition.assignments:
            if isinstance(a, ir.VarAssignment) and a.call.name.text == "now":
                out[a.var.name.text] = str(v.t)
    return out


def _first_difference(actual: list[tuple[int, str, bool]],
                      expected: list[tuple[int, str, bool]], upto: int) -> int | None:
    """The instant of the first jump where the run and the path differ (None: they agree up
    to `upto`)."""
    a = [j for j in actual if j[0] <= upto]
    e = [j for j in expected if j[0] <= upto]
    for x, y in zip(a, e, strict=False):
        if x != y:
            return min(x[0], y[0])
    if len(a) != len(e):
        return (a[len(e)] if len(a) > len(e) else e[len(a)])[0]
    return None


def _values(events: Iterable[Event]) -> dict[str, str]:
    """The last value of each VAR the block reader's jumps bound (`@shown` -> `1200`)."""
    out: dict[str, str] = {}
    for e in events:
        if e["event"] == "jump":
            bindings = e.get("bindings")
            if isinstance(bindings, dict):
                for name, value in bindings.items():
                    if name.startswith("@") and isinstance(value, str):
                        out[name] = value
    return out


# -- making the map ---------------------------------------------------------------------------

@dataclass
class _Bounds:
    """What one field of one entity must be: numeric bounds, an equal value, values it must
    not equal."""

    low: float | None = None
    low_strict: bool = False
    high: float | None = None
    high_strict: bool = False
    equal: object = None
    differ: list[object] = field(default_factory=list)

    def add(self, op: str, value: object) -> bool:
        """Add `field OP value`; False when it cannot hold with what is there."""
        number = as_number(value) if isinstance(value, (int, float, str)) else None
        if op == "eq":
            if self.equal is not None and self.equal != value:
                return False
            self.equal = value
            return True
        if op == "neq":
            self.differ.append(value)
            return True
        if number is None:
            return True  # a text order: left to the replay
        if op in ("lt", "le") and (self.high is None or number < self.high):
            self.high, self.high_strict = number, op == "lt"
        elif op in ("gt", "ge") and (self.low is None or number > self.low):
            self.low, self.low_strict = number, op == "gt"
        return True

    def choose(self, name: str, now: int) -> object:
        """A value that meets the bounds (a field's usual value when nothing bounds it)."""
        if self.equal is not None:
            return self.equal
        if self.low is None and self.high is None:
            if self.differ:
                return _different(self.differ)
            return _DEFAULTS.get(name, 0.0) if name != "positionchangetime" else now
        lo, hi = self.low, self.high
        if lo is not None and hi is not None:
            value = (lo + hi) / 2
        elif hi is not None:
            value = hi / 2 if 0 < hi <= 2 else hi - 1.0
        else:
            assert lo is not None
            value = lo + 1.0
        if name in _TIMES:
            value = float(math.floor(value) if hi is not None and value >= hi else
                          math.ceil(value))
            if hi is not None and (value > hi or (value == hi and self.high_strict)):
                value = hi - 1
            return int(value)
        return round(value, 3)


_DEFAULTS: dict[str, object] = {"positionrho": 1.5, "positiontheta": 0.0, "category": "thing",
                                "istarget": False, "isfixed": False, "permanencetime": 0,
                                "appearanceon": 0}
_TIMES = ("positionchangetime", "permanencetime", "appearanceon")
_NEGATION = {"eq": ("lt", "gt"), "lt": ("ge",), "gt": ("le",), "le": ("gt",), "ge": ("lt",),
             "neq": ("eq",)}
_OPS = {"OP=": "eq", "OP<": "lt", "OP>": "gt"}


def _different(values: list[object]) -> object:
    texts = {str(v) for v in values}
    for candidate in ("other", "none", "nothing"):
        if candidate not in texts:
            return candidate
    return "other-" + str(len(texts))


@dataclass(frozen=True, slots=True)
class _Test:
    """One comparison an entity's field must pass: `field op value` (standard names), or,
    with `other` (an alias and a field), `field op` that field of the other alias's entity."""

    field: str
    op: str
    value: object
    other: tuple[str, str] | None = None


class _Maker:
    """The world verify makes for a path: its entities and the fields it set (see the
    module's docstring)."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.entities: dict[str, dict[str, object]] = {}  # objectid -> fields set

    def commit(self, updates: list[TimedUpdate]) -> None:
        for u in updates:
            fields = self.entities.setdefault(u.update.objectid, {})
            if isinstance(u.update.value, dict):
                fields.update(u.update.value)
            else:
                fields[u.update.attributename] = u.update.value

    def choices(self, asks: list[Ask], t: int, known: dict[str, str]
                ) -> Iterator[list[TimedUpdate]]:
        """The worlds to try at instant `t` for `asks`, most likely first."""
        needs = [self._needs(ask, known) for ask in asks]
        # A condition that must be false is made false by one of its world parts: each
        # combination of those choices is one world to try.
        options = [list(range(max(len(n.parts), 1))) if not n.outcome else [0] for n in needs]
        seen: set[str] = set()
        for combination in itertools.islice(itertools.product(*options), MAX_TRIES):
            world = self._world(needs, combination, t)
            if world is None:
                continue
            key = repr(world)
            if key in seen:
                continue
            seen.add(key)
            yield world

    def _needs(self, ask: Ask, known: dict[str, str]) -> _Need:
        condition = ask.condition
        if condition is None:
            block = self.model.program.blocks[ask.step][1]
            assert isinstance(block, ir.JumpBlock)
            condition = block.condition
        parts: list[_WorldPart] = []
        aliases: dict[str, str] = {}
        for a in condition.assignments:
            if isinstance(a, ir.ClassAssignment):
                aliases[a.alias.name.text] = a.class_name.text
                if a.class_name.text in ENTITY_CLASSES:
                    parts.append(_WorldPart(a.class_name.text, a.alias.name.text,
                                            tuple(_tests(a.tests))))
        for e in condition.evaluations:
            if isinstance(e, ir.TrueEvaluation):
                break
            test = _evaluation_test(e, aliases, known)
            if test is not None:
                alias, t_ = test
                parts.append(_WorldPart(aliases[alias], alias, (t_,), evaluation=True))
        return _Need(ask.outcome, parts, aliases)

    def _world(self, needs: list[_Need], combination: tuple[int, ...], t: int
               ) -> list[TimedUpdate] | None:
        bounds: dict[str, dict[str, _Bounds]] = {}  # objectid -> field -> bounds
        passing: set[str] = set()

        def entity(objectid: str) -> dict[str, _Bounds]:
            return bounds.setdefault(objectid, {})

        related: list[tuple[str, _Test, str, bool]] = []  # (entity, test, class, holds)
        for need in needs:
            if need.outcome:
                for part in need.parts:
                    objectid = _objectid(part.cls, part.alias)
                    passing.add(objectid)
                    for test in part.tests:
                        if test.other is not None:
                            related.append((objectid, test, need.classes[test.other[0]], True))
                        elif not entity(objectid).setdefault(test.field, _Bounds()).add(
                                test.op, test.value):
                            return None
        for need, choice in zip(needs, combination, strict=True):
            if need.outcome or not need.parts:
                continue
            part = need.parts[choice]
            if part.evaluation:  # the comparison after the `!` fails for the bound alias
                objectid = _objectid(part.cls, part.alias)
                test = part.tests[0]
                if test.other is not None:
                    related.append((objectid, test, need.classes[test.other[0]], False))
                    continue
                for op in _NEGATION[test.op][:1]:
                    entity(objectid).setdefault(test.field, _Bounds()).add(op, test.value)
                continue
            # No entity of the class passes: each fails a test (the first it can fail).
            members = {o for o in (*self.entities, *bounds)
                       if o.startswith(part.cls + "/") and o not in passing}
            for objectid in sorted(members):
                if part.tests:
                    test = part.tests[0]
                    for op in _NEGATION[test.op][:1]:
                        entity(objectid).setdefault(test.field, _Bounds()).add(op, test.value)
        # A field compared with another entity's: bounded by the value the other gets.
        for objectid, test, other_cls, holds in related:
            assert test.other is not None
            other_id = _objectid(other_cls, test.other[0])
            other_field = test.other[1]
            fixed = bounds.get(other_id, {}).get(other_field)
            value = (fixed.choose(other_field, t) if fixed is not None else
                     self.entities.get(other_id, {}).get(other_field,
                                                          _DEFAULTS.get(other_field, t)))
            entity(other_id).setdefault(other_field, _Bounds()).add("eq", value)
            op = test.op if holds else _NEGATION[test.op][0]
            entity(objectid).setdefault(test.field, _Bounds()).add(op, value)
        return self._updates(bounds, t)

    def _updates(self, bounds: dict[str, dict[str, _Bounds]], t: int) -> list[TimedUpdate]:
        """The updates that give each entity the values its bounds choose, each field in
        the type the map holds it in (a value the map cannot take is left out: the replay
        then says whether the path is taken without it)."""
        out: list[TimedUpdate] = []

        def value(fields: dict[str, _Bounds], had: dict[str, object], name: str) -> JSONValue:
            fallback = had.get(name, t if name == "positionchangetime" else _DEFAULTS[name])
            chosen = fields[name].choose(name, t) if name in fields else fallback
            return _typed(name, chosen, fallback)

        def add(objectid: str, attribute: str, jsonmsg: JSONValue) -> None:
            with contextlib.suppress(UpdateError):
                out.append(TimedUpdate(t, parse_update(objectid, attribute, "R", jsonmsg),
                                       len(out)))

        for objectid in sorted(bounds):
            fields = bounds[objectid]
            had = self.entities.get(objectid, {})
            add(objectid, "poses", {name: value(fields, had, name) for name in _POSE})
            if any(name in fields for name in _TRACKING):
                add(objectid, "tracking", {name: value(fields, had, name)
                                           for name in _TRACKING})
            cls = objectid.split("/", 1)[0]
            for name in _SINGLE:
                if name in fields and _has_attribute(cls, name):
                    add(objectid, name, value(fields, had, name))
        return out


def _typed(name: str, value: object, fallback: object) -> JSONValue:
    """`value` as the map holds the field `name`: a number for a position, a whole number
    for a time, a text for a category, a truth value for `isfixed` and `istarget`."""
    if name in ("isfixed", "istarget"):
        return value in (True, "s_true")
    if name == "category":
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return format_number(value)
        return str(value)
    number = as_number(value) if isinstance(value, (int, float, str)) else None
    if number is None:
        number = as_number(fallback) if isinstance(fallback, (int, float, str)) else None
    if number is None:
        number = 0.0
    return int(number) if name in _TIMES else number


def _has_attribute(cls: str, name: str) -> bool:
    from scriptc.runtime.world import ATTRIBUTES

    return name in ATTRIBUTES.get(cls, {})


def _objectid(cls: str, alias: str) -> str:
    return f"{cls}/{alias.lstrip('?') or 'it'}"


@dataclass(frozen=True, slots=True)
class _WorldPart:
    """A world part of a condition: a CLASS assignment over a class of the world (its alias
    and tests), or a comparison after the `!` on a field of such an alias (`evaluation`)."""

    cls: str
    alias: str
    tests: tuple[_Test, ...]
    evaluation: bool = False


@dataclass(frozen=True, slots=True)
class _Need:
    """What one jump needs of the world: its outcome, its world parts, and the class of each
    alias its condition binds."""

    outcome: bool
    parts: list[_WorldPart]
    classes: dict[str, str]


def _tests(tests: tuple[ir.Test, ...]) -> Iterator[_Test]:
    """A CLASS assignment's tests verify can aim at: comparisons with a number or a text,
    and `near`."""
    for test in tests:
        if isinstance(test, ir.CallTest):
            call = test.call
            if call.name.text == "near" and len(call.args) == 1 \
                    and isinstance(call.args[0], ir.NumberValue):
                yield _Test("positionrho", "lt", call.args[0].number.value)
            continue
        value = _constant(test.value)
        if value is not None:
            yield _Test(test.field.text, _OPS[test.op.text], value)


def _constant(value: ir.Value) -> object:
    if isinstance(value, ir.NumberValue):
        number = value.number.value
        return number if number is not None and math.isfinite(number) else None
    if isinstance(value, ir.StringValue):
        return value.text.value
    return None


def _evaluation_test(e: ir.Evaluation, aliases: dict[str, str], known: dict[str, str]
                     ) -> tuple[str, _Test] | None:
    """A comparison after the `!` of a world alias's field with a number, a text or a VAR
    whose value the run so far shows, as a test on that alias's entity."""
    if not isinstance(e, ir.CallEvaluation) or len(e.call.args) != 2:
        return None
    name = e.call.name.text
    if name not in _NEGATION:
        return None
    a, b = e.call.args
    swapped = {"lt": "gt", "gt": "lt", "le": "ge", "ge": "le", "eq": "eq", "neq": "neq"}
    if not isinstance(a, ir.FieldRef) and isinstance(b, ir.FieldRef):
        a, b, name = b, a, swapped[name]
    if not isinstance(a, ir.FieldRef):
        return None
    alias = a.alias.name.text
    if aliases.get(alias) not in ENTITY_CLASSES:
        return None
    if isinstance(b, ir.FieldRef):
        other = b.alias.name.text
        if aliases.get(other) not in ENTITY_CLASSES or other == alias:
            return None
        return alias, _Test(a.field.text, name, None, (other, b.field.text))
    if isinstance(b, ir.VarRef):
        value: object = known.get(b.name.text)
        if value is None:
            return None
        number = as_number(str(value))
        value = number if number is not None else value
    else:
        value = _constant(b)
        if value is None:
            return None
    return alias, _Test(a.field.text, name, value)
