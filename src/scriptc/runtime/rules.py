"""Rules: the daisy chain the map passes through once per loop (thesis 3.2, 4.2 step 8, 4.3),
the alfa/omega messages that build it, and the library of rule bodies by `rulecode`. Shared
by every executor.

A rule is a condition in the rule grammar plus a body (Python), identified by `rulecode`
(what it does: which body) and `id` (its name). On each pass the chain evaluates each active
rule's condition in chain order (with the rule as the owner of its `L` bindings, which end
when its turn ends) and calls the body's `on_true(ctx)` or `on_false(ctx)`; the body acts on
the map through `RuleContext` (change the block about to be issued, hold motion, raise an
override, drop aliases, set VARs and ATTs, record goals, post map updates, write a note), which
reaches the session only through a `RuleHost`: the map, its bindings and four effects
(`mutex.RuleEffects` in a session; a test may hand its own).

Messages (`RuleChain.apply`): `A` creates the rule and adds it at the end of the chain; `R`
takes it out but keeps it (state and all) for `C`, which puts it back at the end; `D`
creates it held back, `B` brings a held-back rule into the chain. An action that does not fit
the rule's state does what the user most likely meant and says so in the trace (`note`):
`A` of an active rule changes nothing; `C` or `B` of a rule that is not held creates it
(the thesis's own test_act recovers `kick_starter` on load without removing it first); `R`
of a rule that is not there changes nothing.

Library rules that need parameters read them from the message's `intopic`, written as
`key=value` pairs separated by `;` (the simulation has no ROS topics): for example
`[alfa:1, safety, "distance=0.6", "", A, U]`. The built-in library (`STANDARD_RULES`,
rulecodes documented in docs/runtime.md):

- 0 `kick_starter`: keeps `RobotStatus/elapsedtime` (ms since the running script started)
  up to date on every pass; the thesis's test_act adds it on load and removes it on unload.
- 1 `safety_stop`: holds the wheels still while an entity of `class` (default `Human`) is
  closer than `distance` metres (default 0.5); the block's clock goes on.
- 2 `override`: when its condition `when` (rule grammar, default `{TRUE}`) holds, switches
  once to `script` at `at` (a path `goalG/actA/blkB`, default the first block) or at
  `goal=ID` (a goal id); `script` defaults to the running script.

Activities register their own (`RuleLibrary.register`, or `register_simple` for a condition
and a function); a repository declares them in its configuration (`[[rules]]`, read by
`runtime/configured.py`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from scriptc.ir import nodes as ir
from scriptc.ir.builtins import CLASSES
from scriptc.language import SCOPES
from scriptc.numbers import JSONValue, whole_number
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.commands import BlockCommands, RuleMessage
from scriptc.runtime.world import OverrideRequest, Record, World

if TYPE_CHECKING:
    from scriptc.runtime.evaluate import Evaluation


class RuleError(ValueError):
    """A rule that cannot be made (bad parameters, a condition that does not parse)."""


def parse_condition_text(text: str) -> ir.Condition:
    """A rule-grammar condition from text; raises RuleError with the first problem: a syntax
    error, or what lint reports of a script's condition without the script around it, a class
    the map does not hold (R001) or a scope the language does not know (R007). (A rule's
    condition is not in any script lint reads: a `when=` parameter is text to it.)"""
    from scriptc.frontend.script import parse_condition

    condition, problems = parse_condition(text)
    errors = [d for d in problems if d.severity.value == "error"]
    if condition is None or errors:
        message = errors[0].message if errors else "it does not parse"
        raise RuleError(f"condition `{text}`: {message}")
    for assignment in condition.assignments:
        scope = assignment.scope.text
        if scope not in SCOPES:
            raise RuleError(f"condition `{text}`: unknown scope `{scope}` (the scopes are "
                            f"{', '.join(SCOPES)})")
        if isinstance(assignment, ir.ClassAssignment):
            cls = assignment.class_name.text  # (lowering strips the `#`)
            if cls not in CLASSES:
                raise RuleError(f"condition `{text}`: unknown class `{cls}` (the classes of "
                                f"the map are {', '.join(CLASSES)})")
    return condition


def parse_params(text: str) -> dict[str, str]:
    """`key=value; key=value` -> dict. A `when=` pair takes the rest of the text (conditions
    hold `;` only inside strings, and may hold `=`)."""
    params: dict[str, str] = {}
    rest = text.strip()
    while rest:
        key, eq, tail = rest.partition("=")
        key = key.strip()
        if not eq or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key):
            raise RuleError(f"parameters are `key=value` pairs separated by `;`, found `{rest}`")
        if key == "when":
            params[key] = tail.strip()
            break
        value, _sep, rest = tail.partition(";")
        params[key] = value.strip()
        rest = rest.strip()
    return params


class Rule:
    """The base of rule bodies. Subclasses set `condition_text` (or `self.condition`) and
    override `on_true` / `on_false`. `message` is the rule message that made the rule (a body
    may read its `outtopic`), `params` its `key=value` parameters."""

    condition_text = "{TRUE}"

    def __init__(self, message: RuleMessage, params: dict[str, str] | None = None) -> None:
        self.message = message
        self.id = message.id
        self.rulecode = message.rulecode
        self.params = params if params is not None else {}
        self.condition: ir.Condition = parse_condition_text(self.condition_text)

    def on_true(self, ctx: RuleContext) -> None:
        pass

    def on_false(self, ctx: RuleContext) -> None:
        pass

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.id} ({self.rulecode})>"


class RuleHost(Protocol):
    """What a rule's turn reaches besides its own rule (the session's `mutex.RuleEffects`;
    a test may hand its own): the map and its bindings, and four effects."""

    world: World
    bindings: Bindings

    def hold_motion(self) -> None:
        """Keep the wheels still for this pass of the chain."""

    def record_goal(self, kind: str, goalid: str, by: str) -> None:
        """A goal record (`reached`, `interrupted`, `failed`); ValueError for another kind."""

    def post_update(self, objectid: str, attributename: str, policy: str, jsonmsg: JSONValue,
                    by: str) -> None:
        """A MapUpdate, applied at the next step 4 (one the map cannot take is reported)."""

    def note(self, now: int, rule: Rule, message: str, data: Record) -> None:
        """A `rule_note` line in the trace."""


class RuleContext:
    """What a rule body may do to the map during its turn (see the module's docstring), all
    through its `RuleHost`."""

    __slots__ = ("evaluation", "host", "now", "rule")

    def __init__(self, host: RuleHost, rule: Rule, now: int, evaluation: Evaluation) -> None:
        self.host = host
        self.rule = rule
        self.now = now
        self.evaluation = evaluation  # the condition's Evaluation (value, bindings)

    @property
    def world(self) -> World:
        return self.host.world

    @property
    def bindings(self) -> Bindings:
        return self.host.bindings

    @property
    def block(self) -> BlockCommands | None:
        """The instruction block in the map's script info (running or about to be issued)."""
        return self.host.world.script.block

    def replace_block(self, instruction: BlockCommands) -> None:
        """Change the block: it is marked `changed` and the actuators restart it."""
        info = self.host.world.script
        info.block = instruction
        info.changed = True
        self.note("block changed")

    def hold_motion(self) -> None:
        """Keep the wheels still until the next pass (assert it on every pass to keep it)."""
        self.host.hold_motion()

    def override(self, script: str, goal: int | str = 0, action: int = 0, block: int = 0) -> None:
        """Raise a compulsory script switch (applied at step 5 of the next loop)."""
        self.host.world.script.override = OverrideRequest(script, goal, action, block,
                                                          self.rule.id)

    def drop_alias(self, alias: str) -> None:
        """End the alias's binding (and its ATTs), whatever its scope."""
        self.host.bindings.unbind(alias)

    def set_var(self, name: str, value: str, scope: str = "U") -> None:
        self.host.bindings.set_var(name if name.startswith("@") else "@" + name, value,
                                   scope, self.rule.id)

    def set_att(self, alias: str, name: str, value: str, scope: str = "U") -> None:
        self.host.bindings.set_att(alias, name.lstrip("$"), value, scope, self.rule.id)

    def record_goal(self, kind: str, goalid: str) -> None:
        """Record a goal as `reached`, `interrupted` or `failed` in the map."""
        self.host.record_goal(kind, goalid, by=self.rule.id)

    def post_update(self, objectid: str, attributename: str, policy: str,
                    jsonmsg: JSONValue) -> None:
        """Send a MapUpdate as a sensor would (applied at the next step 4)."""
        self.host.post_update(objectid, attributename, policy, jsonmsg, by=self.rule.id)

    def set_condition(self, text: str) -> None:
        """Change the rule's own condition (thesis 4.3: it "can be changed on run-time")."""
        self.rule.condition = parse_condition_text(text)

    def note(self, message: str, **data: JSONValue) -> None:
        """A line in the trace (`rule_note`)."""
        self.host.note(self.now, self.rule, message, data)


# ---------------------------------------------------------------------------------------------
# The built-in library


class KickStarter(Rule):
    """Rulecode 0: keeps `RobotStatus/elapsedtime` up to date on every pass."""

    def on_true(self, ctx: RuleContext) -> None:
        status = ctx.world.robot.fields
        status["elapsedtime"] = ctx.now - status.get("startingtime", 0)


class SafetyStop(Rule):
    """Rulecode 1: holds the wheels still while an entity of `class` is closer than
    `distance` metres."""

    def __init__(self, message: RuleMessage, params: dict[str, str] | None = None) -> None:
        super().__init__(message, params)
        try:
            self.distance = float(self.params.get("distance", "0.5"))
        except ValueError:
            raise RuleError(f"safety_stop: `distance` must be a number, found "
                            f"`{self.params['distance']}`") from None
        self.cls = self.params.get("class", "Human")
        if self.cls not in ("Human", "Obstacle", "Object"):
            raise RuleError(f"safety_stop: `class` is Human, Obstacle or Object, not `{self.cls}`")
        self.engaged_by: str | None = None

    def on_true(self, ctx: RuleContext) -> None:
        # The body reads the map directly rather than through a CLASS assignment: an entity
        # holds one alias at a time, so a child the script named `?kid` would be invisible to
        # an assignment of this rule.
        closest = None
        for entity in ctx.world.candidates(self.cls):
            rho = entity.fields.get("positionrho")
            if rho is not None and rho < self.distance and (closest is None or rho < closest[1]):
                closest = (entity, rho)
        if closest is not None:
            ctx.hold_motion()
            if self.engaged_by is None:
                self.engaged_by = closest[0].key
                ctx.note(f"motion held: {closest[0].key} is {closest[1]} m away, closer than "
                         f"{self.distance} m", entity=closest[0].key)
        elif self.engaged_by is not None:
            self.engaged_by = None
            ctx.note("motion released")


_PATH_RE = re.compile(r"goal(\d+)/act(\d+)/blk(\d+)")


class Override(Rule):
    """Rulecode 2: when `when` holds, switches once to `script` at `at` (or `goal`)."""

    def __init__(self, message: RuleMessage, params: dict[str, str] | None = None) -> None:
        params = params if params is not None else {}
        self.condition_text = params.get("when", "{TRUE}") or "{TRUE}"
        super().__init__(message, params)
        self.script = params.get("script", "")
        self.goal: int | str = 0
        self.action = self.block = 0
        if "goal" in params:
            self.goal = params["goal"]
        if "at" in params:
            m = _PATH_RE.fullmatch(params["at"])
            if m is None:
                raise RuleError("override: `at` is a path `goalG/actA/blkB`, "
                                f"found `{params['at']}`")
            # Read by the number policy: None for digits beyond it.
            goal, action, block = (whole_number(x) for x in m.groups())
            if goal is None or action is None or block is None:
                raise RuleError(f"override: `at` names a goal, action or block beyond any "
                                f"script, found `{params['at'][:40]}...`")
            self.goal, self.action, self.block = goal, action, block
        self.fired = False

    def on_true(self, ctx: RuleContext) -> None:
        if self.fired:
            return
        self.fired = True
        script = self.script or ctx.world.script.currentactivity
        ctx.override(script, self.goal, self.action, self.block)


class SimpleRule(Rule):
    """A rule made of a condition text and Python callables (`RuleLibrary.register_simple`)."""

    def __init__(self, message: RuleMessage, params: dict[str, str] | None, condition: str,
                 on_true: Callable[[RuleContext], None] | None,
                 on_false: Callable[[RuleContext], None] | None) -> None:
        self.condition_text = condition
        super().__init__(message, params)
        self._on_true = on_true
        self._on_false = on_false

    def on_true(self, ctx: RuleContext) -> None:
        if self._on_true is not None:
            self._on_true(ctx)

    def on_false(self, ctx: RuleContext) -> None:
        if self._on_false is not None:
            self._on_false(ctx)


class UnknownRule(Rule):
    """The body of a rulecode the library does not have: it does nothing (reported once)."""


RuleFactory = Callable[[RuleMessage, dict[str, str]], Rule]


@dataclass(frozen=True, slots=True)
class RuleEntry:
    """An entry of the rule library: rulecode, name, factory, where it comes from."""

    rulecode: int
    name: str
    factory: RuleFactory
    doc: str
    origin: str = "standard"


class RuleLibrary:
    """Rule bodies by rulecode, and the repository's rules that are known by their id only
    (a `[[rules]]` entry of the configuration without a rulecode): a message whose rulecode
    has no body is matched by its id among those (docs/configuration.md)."""

    def __init__(self, entries: Iterable[RuleEntry] = (), named: Iterable[RuleEntry] = ()
                 ) -> None:
        self._by_code: dict[int, RuleEntry] = {e.rulecode: e for e in entries}
        self._by_name: dict[str, RuleEntry] = {e.name: e for e in named}

    def register(self, rulecode: int, name: str, factory: RuleFactory, doc: str = "",
                 origin: str = "user") -> RuleEntry:
        """Add (or replace) a rule body: `factory(message, params) -> Rule`."""
        if not 0 <= rulecode <= 0xFFFFFFFF:
            raise ValueError(f"a rulecode is an unsigned 32-bit integer, not {rulecode}")
        entry = RuleEntry(rulecode, name, factory, doc, origin)
        self._by_code[rulecode] = entry
        return entry

    def register_simple(self, rulecode: int, name: str, condition: str,
                        on_true: Callable[[RuleContext], None] | None = None,
                        on_false: Callable[[RuleContext], None] | None = None,
                        doc: str = "") -> RuleEntry:
        """A rule from a condition text and callables (each gets the RuleContext)."""
        parse_condition_text(condition)  # fail now, not when a script adds it
        return self.register(rulecode, name,
                             lambda m, p: SimpleRule(m, p, condition, on_true, on_false), doc)

    def register_named(self, name: str, factory: RuleFactory, doc: str = "",
                       origin: str = "user") -> RuleEntry:
        """Add a rule body found by the id of the messages that name it (no rulecode)."""
        entry = RuleEntry(-1, name, factory, doc, origin)
        self._by_name[name] = entry
        return entry

    def get(self, rulecode: int, rule_id: str | None = None) -> RuleEntry | None:
        entry = self._by_code.get(rulecode)
        if entry is None and rule_id is not None:
            entry = self._by_name.get(rule_id)
        return entry

    def __iter__(self) -> Iterator[RuleEntry]:
        return iter(sorted(self._by_code.values(), key=lambda e: e.rulecode))

    def extended(self) -> RuleLibrary:
        return RuleLibrary(self._by_code.values(), self._by_name.values())

    def make(self, message: RuleMessage) -> Rule:
        """A fresh rule for a message; raises RuleError. An unknown rulecode gives an
        `UnknownRule` (the caller reports it)."""
        params = parse_params(message.intopic) if "=" in message.intopic else {}
        entry = self.get(message.rulecode, message.id)
        if entry is None:
            return UnknownRule(message, params)
        return entry.factory(message, params)


STANDARD_RULES = RuleLibrary([
    RuleEntry(0, "kick_starter", KickStarter,
              "keeps RobotStatus/elapsedtime up to date on every pass"),
    RuleEntry(1, "safety_stop", SafetyStop,
              "holds the wheels still while a Human (`class`) is closer than `distance` m"),
    RuleEntry(2, "override", Override,
              "when `when` holds, switches once to `script` at `at` (or `goal`)"),
])


# ---------------------------------------------------------------------------------------------
# The chain


class RuleChain:
    """Active rules in chain order, the held ones (removed or delayed) by id, and the mutex."""

    def __init__(self) -> None:
        self.active: list[Rule] = []
        self.held: dict[str, tuple[Rule, str]] = {}  # id -> (rule, "removed" | "delayed")
        self.locked = False
        self.locked_by = ""

    def ids(self) -> list[str]:
        return [r.id for r in self.active]

    def find(self, rule_id: str) -> Rule | None:
        for rule in self.active:
            if rule.id == rule_id:
                return rule
        return None

    def apply(self, message: RuleMessage,
              library: RuleLibrary) -> tuple[str, str | None, Rule | None]:
        """Carry out one message's action: returns (result, note, the rule made if any).
        Raises RuleError when a rule must be made and cannot."""
        action, rid = message.action, message.id
        active = self.find(rid)
        held = self.held.get(rid)
        if action == "A":
            if active is not None:
                return "unchanged", "already in the chain", None
            rule = library.make(message)
            self.held.pop(rid, None)
            self.active.append(rule)
            return "added", None, rule
        if action == "R":
            if active is not None:
                self.active.remove(active)
                self.held[rid] = (active, "removed")
                return "removed", None, None
            if held is not None and held[1] == "delayed":
                self.held[rid] = (held[0], "removed")
                return "removed", "was held back, not in the chain", None
            return "unchanged", "not in the chain: nothing to remove", None
        if action == "D":
            if active is not None:
                return "unchanged", "already in the chain", None
            rule = library.make(message)
            self.held[rid] = (rule, "delayed")
            return "delayed", None, rule
        if action in ("B", "C"):
            wanted = "delayed" if action == "B" else "removed"
            if active is not None:
                return "unchanged", "already in the chain", None
            if held is not None:
                self.active.append(held[0])
                del self.held[rid]
                note = None if held[1] == wanted else f"was {held[1]}, not {wanted}"
                return ("brought back" if action == "B" else "recovered"), note, None
            rule = library.make(message)
            self.active.append(rule)
            return "added", f"was not {wanted}: created and added", rule
        raise RuleError(f"unknown rule action `{action}`")
