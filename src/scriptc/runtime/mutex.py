"""The map's mutex and what it guards (thesis 4.4, 4.2 step 8; docs/runtime.md "Rules" and
"The mutex"): the hand-over of a script's alfa and omega lists, which build the chain of rules
message by message, locking and unlocking the map as their mutex letters say; and the chain
pass, which runs each active rule's turn while the map is not locked.

The hand-over (`Mutex.hand_over`): `L` locks before its message is carried out, `U` unlocks
after, `M` does neither; a script without alfa messages completes the hand-over (its load
unlocks the map). Misuse (what M001 and M002 reject in a checked script) is reported with code
`mutex-misuse`, never fatal, and the lock does what the messages say. A rule that cannot be
made is reported (`rule`), one whose rulecode the library lacks does nothing (reported once,
`unknown-rulecode`).

The chain pass (`Mutex.pass_chain`): skipped while locked (said once per lock); otherwise each
active rule, in chain order, evaluates its condition (owning its `L` bindings, which end with
its turn) and its body runs `on_true` or `on_false` with a `rules.RuleContext` over
`RuleEffects`, the narrow door through which a body acts on the session. A condition that
cannot be evaluated or a body that raises is reported (`rule`) and the chain goes on. Motion
is held for the pass iff a body asked. A rule fires (a `rule_fire` event, before its
`on_true`) when its condition holds on a pass and did
not on the rule's previous pass (or the rule had none in the chain): one event per time it
starts to hold, not one per pass (a `{TRUE}` rule fires once), which is what coverage counts.
"""

from __future__ import annotations

from scriptc.numbers import JSONValue
from scriptc.runtime.actuators import Actuators
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.commands import RuleMessage
from scriptc.runtime.evaluate import EvalContext, evaluate
from scriptc.runtime.goals import Goals
from scriptc.runtime.rules import (
    Rule,
    RuleChain,
    RuleContext,
    RuleError,
    RuleLibrary,
    UnknownRule,
)
from scriptc.runtime.status import MUTEX_MISUSE, RULE, UNKNOWN_RULECODE, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.updates import Updates
from scriptc.runtime.world import Record, World


class RuleEffects:
    """What a rule body reaches through its `RuleContext` (the `rules.RuleHost` protocol):
    the map and its bindings, holding motion for the pass, goal records, map updates and
    notes in the trace. `held` says whether a body asked to hold motion in this pass."""

    __slots__ = ("bindings", "goals", "held", "trace", "updates", "world")

    def __init__(self, world: World, bindings: Bindings, trace: Trace, goals: Goals,
                 updates: Updates) -> None:
        self.world = world
        self.bindings = bindings
        self.trace = trace
        self.goals = goals
        self.updates = updates
        self.held = False

    def hold_motion(self) -> None:
        self.held = True

    def record_goal(self, kind: str, goalid: str, by: str) -> None:
        self.goals.record(kind, goalid, by=by)

    def post_update(self, objectid: str, attributename: str, policy: str, jsonmsg: JSONValue,
                    by: str) -> None:
        self.updates.post_message(objectid, attributename, policy, jsonmsg, source=by)

    def note(self, now: int, rule: Rule, message: str, data: Record) -> None:
        self.trace.emit(now, "rule_note", id=rule.id, rulecode=rule.rulecode, message=message,
                        **data)


# The results of a message that put a rule in the chain (`RuleChain.apply`).
_JOINED = ("added", "brought back", "recovered")


class Mutex:
    """The chain of rules, its lock, the hand-over and the chain pass (see the module's
    docstring)."""

    __slots__ = (
        "actuators",
        "bindings",
        "chain",
        "ctx",
        "effects",
        "holding",
        "joined_by",
        "library",
        "skip_reported",
        "status",
        "trace",
    )

    def __init__(self, library: RuleLibrary, trace: Trace, status: RunStatus, ctx: EvalContext,
                 actuators: Actuators, effects: RuleEffects) -> None:
        self.chain = RuleChain()
        self.library = library
        self.trace = trace
        self.status = status
        self.ctx = ctx
        self.bindings = ctx.bindings
        self.actuators = actuators
        self.effects = effects
        self.skip_reported = False  # the skipped pass of this lock is in the trace
        # The rules (by `id()`) whose condition held on their last pass in the chain: a rule
        # fires (`rule_fire`) when its condition holds and it is not among them. Rules are
        # known by identity, not by equality or hash (a library's rule class may define
        # either); `joined_by` keeps every rule that joined the chain, so no identity is
        # reused while the session runs.
        self.holding: set[int] = set()
        # The script whose message last put each rule (by `id()`) in the chain (`A`, or `B`
        # and `C` bringing it back), named by its `rule_fire` events.
        self.joined_by: dict[int, tuple[Rule, str]] = {}

    def _joined(self, rule: Rule | None, script: str) -> None:
        """`rule` joined the chain by a message of `script`: its next pass is its first."""
        if rule is not None:
            self.joined_by[id(rule)] = (rule, script)
            self.holding.discard(id(rule))

    def _misuse(self, now: int, message: str) -> None:
        self.status.report(now, MUTEX_MISUSE, message)

    def hand_over(self, now: int, messages: tuple[RuleMessage, ...], kind: str,
                  script: str) -> None:
        """Issue a script's alfa or omega list (`kind`) with its mutex letters (thesis 4.4)."""
        chain = self.chain
        last = len(messages) - 1
        for i, m in enumerate(messages):
            if m.mutex == "L":
                if chain.locked:
                    self._misuse(now, f"`{m.id}` ({kind} of `{script}`) locks the map, which "
                                      f"{chain.locked_by} had already locked")
                if kind == "alfa":
                    self._misuse(now, f"`{m.id}` locks the map in the alfa list of `{script}` "
                                      "(alfa messages must not lock)")
                self.lock(now, f"{kind} of `{script}`")
            elif kind == "omega" and i == 0:
                self._misuse(now, f"the omega list of `{script}` changes the chain without "
                                  "locking the map first (its first message must be `L`)")
            try:
                result, note, rule = chain.apply(m, self.library)
            except RuleError as exc:
                self.status.report(now, RULE, f"`{m.id}` (rulecode {m.rulecode}): {exc}")
                result, note, rule = "failed", None, None
            if result in _JOINED:
                self._joined(chain.find(m.id), script)
            fields = {"script": script, "message": kind, "rulecode": m.rulecode, "id": m.id,
                      "action": m.action, "mutex": m.mutex, "result": result}
            if note:
                fields["note"] = note
            fields["chain"] = chain.ids()
            self.trace.emit(now, "rule", **fields)
            if isinstance(rule, UnknownRule):
                self.status.report(now, UNKNOWN_RULECODE,
                                   f"rulecode {m.rulecode} (`{m.id}`) is not in the rule "
                                   "library: the rule does nothing")
            if m.mutex == "U":
                if kind == "omega":
                    self._misuse(now, f"`{m.id}` unlocks the map in the omega list of "
                                      f"`{script}` (omega messages must not unlock)")
                elif i != last:
                    self._misuse(now, f"`{m.id}` unlocks the map before the end of the alfa "
                                      f"list of `{script}`: rules see a half-built chain")
                self.unlock(now, f"{kind} of `{script}`")
        if kind == "alfa" and chain.locked:
            if not messages:
                # A script without alfa messages takes the chain as the previous omega left it.
                self.unlock(now, f"`{script}` has no alfa messages: the hand-over is complete")
            else:
                self._misuse(now, f"the alfa list of `{script}` leaves the map locked (its last "
                                  "message must be `U`): rules do not run until a `U`")

    def lock(self, now: int, by: str) -> None:
        chain = self.chain
        chain.locked = True
        chain.locked_by = by
        self.skip_reported = False
        self.trace.emit(now, "mutex", state="locked", by=by)

    def unlock(self, now: int, by: str) -> None:
        chain = self.chain
        if chain.locked:
            chain.locked = False
            chain.locked_by = ""
            self.trace.emit(now, "mutex", state="unlocked", by=by)

    def pass_chain(self, now: int) -> None:
        """Step 8: the map passes through the active rules, unless it is locked."""
        chain = self.chain
        if chain.locked:
            if not self.skip_reported:
                self.skip_reported = True
                self.trace.emit(now, "mutex", state="locked", by=chain.locked_by,
                                note="the map does not pass through the chain while locked")
            return
        actuators = self.actuators
        effects = self.effects
        effects.held = False
        ctx, bindings = self.ctx, self.bindings
        holding, self.holding = self.holding, set()
        for rule in list(chain.active):
            ctx.begin(rule.id, now)
            try:
                evaluation = evaluate(rule.condition, ctx)
                rctx = RuleContext(effects, rule, now, evaluation)
                if evaluation.value:
                    self.holding.add(id(rule))
                    if id(rule) not in holding:
                        joined = self.joined_by.get(id(rule))
                        self.trace.emit(now, "rule_fire", script=joined[1] if joined else "",
                                        id=rule.id, rulecode=rule.rulecode)
                    rule.on_true(rctx)
                else:
                    rule.on_false(rctx)
            except Exception as exc:  # a rule's bug must not stop the robot
                self.status.report(now, RULE, f"rule `{rule.id}` (rulecode {rule.rulecode}) "
                                              f"raised {type(exc).__name__}: {exc}")
            bindings.end_owner(rule.id)
        actuators.set_hold(now, effects.held)
