"""The runtime's jobs through their own interfaces (docs/runtime.md, "How it is built"): what a
rule body may do through its `RuleContext` and `RuleHost`, the hand-over of rule messages and
every transition of the chain, the chain pass and the lock, goal records, map updates,
overrides and `script_vect`, the operator, the catalogue and the LIFO, and the run's status.
Each job is built from its collaborators, as a test runner or a model checker would build
it, and driven without a whole run."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from scriptc.analysis.analyze import analyze_bytes
from scriptc.runtime.actuators import Actuators
from scriptc.runtime.bindings import READER, Bindings
from scriptc.runtime.clock import EventQueue
from scriptc.runtime.commands import BlockCommands, Move, RuleMessage
from scriptc.runtime.goals import Goals
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.loading import LoadError
from scriptc.runtime.rules import (
    STANDARD_RULES,
    Override,
    Rule,
    RuleChain,
    RuleContext,
    RuleError,
    RuleHost,
    parse_condition_text,
    parse_params,
)
from scriptc.runtime.scenario import OperatorEvent, scenario_from_data
from scriptc.runtime.scripts import Catalogue, LoadRecord
from scriptc.runtime.session import Session
from scriptc.runtime.status import NO_PROGRESS, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.updates import Updates
from scriptc.runtime.world import World, parse_update

PLAIN = """\
[plain]
[goal:first]
  [action]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
[goal:second]
  [action]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
    [b##blk_terminus]
"""


def program(text: str = PLAIN, name: str = "t.script") -> IRProgram:
    analysis = analyze_bytes(name, text.encode(), "script")
    assert analysis.script is not None, analysis.diagnostics
    return IRProgram(analysis.script, name)


def started(*programs: IRProgram, **kwargs) -> Session:
    """A session whose first script is loaded and read at 0 ms (the loop's first instant)."""
    session = Session(list(programs) or [program()], **kwargs)
    session.scripts.load_when_free(0)
    session.scripts.read(0)
    return session


def message(action: str, mutex: str = "M", rid: str = "r", rulecode: int = 0,
            intopic: str = "") -> RuleMessage:
    return RuleMessage("alfa", rulecode, rid, intopic, "", action, mutex)


# -- a rule body through its RuleContext: every effect goes to its host ----------------------


@dataclass
class Host:
    """A RuleHost that records what a body asked."""

    world: World = field(default_factory=World)
    bindings: Bindings = field(default_factory=Bindings)
    calls: list = field(default_factory=list)

    def hold_motion(self) -> None:
        self.calls.append(("hold",))

    def record_goal(self, kind: str, goalid: str, by: str) -> None:
        self.calls.append(("goal", kind, goalid, by))

    def post_update(self, objectid, attributename, policy, jsonmsg, by: str) -> None:
        self.calls.append(("update", objectid, attributename, policy, jsonmsg, by))

    def note(self, now: int, rule: Rule, message: str, data: dict) -> None:
        self.calls.append(("note", now, rule.id, message, data))


def _context(host: Host, now: int = 40) -> RuleContext:
    rule = STANDARD_RULES.make(message("A", rid="helper", rulecode=0))
    return RuleContext(host, rule, now, evaluation=None)


def test_a_rule_context_acts_only_through_its_host() -> None:
    host = Host()
    assert isinstance(host, object) and RuleHost  # the protocol a test may implement
    ctx = _context(host)
    assert ctx.world is host.world and ctx.bindings is host.bindings
    ctx.hold_motion()
    ctx.record_goal("failed", "g1")
    ctx.post_update("Human/kid", "poses", "R", {"positionrho": 1.0})
    ctx.note("hello", entity="Human/kid")
    assert host.calls == [
        ("hold",),
        ("goal", "failed", "g1", "helper"),
        ("update", "Human/kid", "poses", "R", {"positionrho": 1.0}, "helper"),
        ("note", 40, "helper", "hello", {"entity": "Human/kid"}),
    ]


def test_the_standard_bodies_through_their_context() -> None:
    """kick_starter writes the time since the script started; a rule shows its class, id and
    rulecode; override's defaults; safety_stop's parameters are checked when it is made."""
    host = Host()
    ctx = _context(host, now=1000)
    host.world.robot.fields["startingtime"] = 300
    ctx.rule.on_true(ctx)
    assert host.world.robot.fields["elapsedtime"] == 700
    del host.world.robot.fields["startingtime"]
    ctx.rule.on_true(ctx)
    assert host.world.robot.fields["elapsedtime"] == 1000  # no start known: from 0
    assert repr(ctx.rule) == "<KickStarter helper (0)>"
    assert ctx.evaluation is None  # what the pass gave the context (here: nothing)
    override = Override(message("A", rid="o", rulecode=2))
    assert (override.script, override.goal, override.action, override.block) == ("", 0, 0, 0)
    assert override.condition.is_constant_true and override.params == {}
    for params, problem in [("distance=near", "`distance` must be a number, found `near`"),
                            ("class=Dog", "`class` is Human, Obstacle or Object, not `Dog`")]:
        with pytest.raises(RuleError) as info:
            STANDARD_RULES.make(message("A", rulecode=1, intopic=params))
        assert str(info.value) == f"safety_stop: {problem}"
    for cls in ("Human", "Obstacle", "Object"):
        guard = STANDARD_RULES.make(message("A", rulecode=1, intopic=f"class={cls}"))
        assert (guard.cls, guard.distance) == (cls, 0.5)


def test_rule_parameters_are_read_around_their_spaces() -> None:
    assert parse_params(" distance = 0.6 ;  class = Object ; ") == {"distance": "0.6",
                                                                    "class": "Object"}
    assert parse_params("when = {TRUE} ") == {"when": "{TRUE}"}
    assert parse_params("   ") == {}


def test_a_rule_body_reads_its_conditions_evaluation() -> None:
    seen = []
    library = STANDARD_RULES.extended()
    library.register_simple(
        80, "near", "{CLASS #Human L ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}",
        on_true=lambda ctx: seen.append((ctx.evaluation.value, dict(ctx.evaluation.bindings))),
        on_false=lambda ctx: seen.append((ctx.evaluation.value, {})))
    session = started(trace=Trace(), rules=library)
    session.mutex.hand_over(0, (RuleMessage("alfa", 80, "n", "", "", "A", "U"),), "alfa",
                            "plain")
    session.mutex.pass_chain(1)
    session.world.post(parse_update("Human/kid", "poses", "R", {"positionrho": 0.5}))
    session.updates.apply(2)
    session.mutex.pass_chain(2)
    assert seen == [(False, {}), (True, {"?kid": "Human/kid"})]


def test_a_rule_context_changes_the_map_and_the_bindings() -> None:
    host = Host()
    ctx = _context(host)
    block = object()
    assert ctx.block is None
    ctx.replace_block(block)
    info = host.world.script
    assert ctx.block is block and info.changed
    assert host.calls[-1][3] == "block changed"
    ctx.override("other", "g2", 1, 2)
    request = info.override
    assert (request.script, request.goal, request.action, request.block, request.by) == \
        ("other", "g2", 1, 2, "helper")
    ctx.set_var("count", "3")
    ctx.set_var("@mood", "calm", "T")
    assert host.bindings.get_var("@count") == "3" and host.bindings.get_var("@mood") == "calm"
    count = host.bindings.vars["@count"]
    assert count.scope == "U" and count.owner == "helper"
    assert host.bindings.vars["@mood"].scope == "T"
    host.world.apply(parse_update("Human/kid", "poses", "R", {"positionrho": 1.0}), 0)
    host.bindings.bind("?kid", host.world.entity("Human", "kid"), "U", READER)
    ctx.set_att("?kid", "$mood", "happy")
    assert host.bindings.get_att("?kid", "mood") == "happy"
    ctx.drop_alias("?kid")
    assert host.bindings.lookup("?kid") is None and host.bindings.get_att("?kid", "mood") is None
    before = ctx.rule.condition
    ctx.set_condition("! {E: eq(1, 1)}")
    assert ctx.rule.condition is not before and ctx.rule.condition is not None
    with pytest.raises(ValueError, match="condition `"):
        ctx.set_condition("{NOT A CONDITION")


# -- the session's host (mutex.RuleEffects) ------------------------------------------------------


def test_the_sessions_rule_effects_reach_goals_updates_and_the_trace() -> None:
    session = started(trace=Trace())
    effects, trace = session.mutex.effects, session.trace
    session.status.now = 7
    assert effects.held is False  # no body has asked yet
    effects.hold_motion()
    assert effects.held
    effects.record_goal("failed", "first", by="watch")
    assert trace.events[-1] == {"t": 7, "event": "goal", "script": "plain", "goalid": "first",
                                "record": "failed", "by": "watch"}
    assert session.world.goal_records("goalfailed")[-1]["timestamp"] == 7
    with pytest.raises(ValueError, match="reached, interrupted or failed"):
        effects.record_goal("won", "first", by="watch")
    effects.post_update("Human/kid", "poses", "X", {"positionrho": 1.0}, by="watch")
    error = trace.errors[-1]
    assert error["code"] == "update" and error["message"].startswith("watch: ")
    assert not session.world.pending
    effects.post_update("Human/kid", "poses", "R", {"positionrho": 1.0}, by="watch")
    assert len(session.world.pending) == 1
    rule = STANDARD_RULES.make(message("A", rid="watch", rulecode=0))
    effects.note(7, rule, "seen", {"n": 1})
    assert trace.events[-1] == {"t": 7, "event": "rule_note", "id": "watch", "rulecode": 0,
                                "message": "seen", "n": 1}


# -- the hand-over: every action in every state of the chain (docs/runtime.md's table) ----------


def _apply(session: Session, action: str, kind: str = "alfa", rulecode: int = 0) -> dict:
    session.mutex.hand_over(0, (RuleMessage(kind, rulecode, "r", "", "", action, "M"),),
                            kind, "plain")
    return [e for e in session.trace.events if e["event"] == "rule"][-1]


def _in_state(state: str) -> Session:
    session = started(trace=Trace())
    for action in {"unknown": (), "active": ("A",), "delayed": ("D",),
                   "removed": ("A", "R")}[state]:
        _apply(session, action)
    return session


TRANSITIONS = {
    # (action, state): (result, note or None, chain after, held after)
    ("A", "unknown"): ("added", None, ["r"], {}),
    ("A", "active"): ("unchanged", "already in the chain", ["r"], {}),
    ("A", "delayed"): ("added", None, ["r"], {}),
    ("A", "removed"): ("added", None, ["r"], {}),
    ("R", "unknown"): ("unchanged", "not in the chain: nothing to remove", [], {}),
    ("R", "active"): ("removed", None, [], {"r": "removed"}),
    ("R", "delayed"): ("removed", "was held back, not in the chain", [], {"r": "removed"}),
    ("R", "removed"): ("unchanged", "not in the chain: nothing to remove", [], {"r": "removed"}),
    ("D", "unknown"): ("delayed", None, [], {"r": "delayed"}),
    ("D", "active"): ("unchanged", "already in the chain", ["r"], {}),
    ("D", "delayed"): ("delayed", None, [], {"r": "delayed"}),
    ("D", "removed"): ("delayed", None, [], {"r": "delayed"}),
    ("B", "unknown"): ("added", "was not delayed: created and added", ["r"], {}),
    ("B", "active"): ("unchanged", "already in the chain", ["r"], {}),
    ("B", "delayed"): ("brought back", None, ["r"], {}),
    ("B", "removed"): ("brought back", "was removed, not delayed", ["r"], {}),
    ("C", "unknown"): ("added", "was not removed: created and added", ["r"], {}),
    ("C", "active"): ("unchanged", "already in the chain", ["r"], {}),
    ("C", "delayed"): ("recovered", "was delayed, not removed", ["r"], {}),
    ("C", "removed"): ("recovered", None, ["r"], {}),
}


@pytest.mark.parametrize("action, state", list(TRANSITIONS), ids=lambda x: x)
def test_every_rule_action_in_every_state(action: str, state: str) -> None:
    session = _in_state(state)
    before = session.mutex.chain.held.get("r")
    event = _apply(session, action)
    result, note, chain, held = TRANSITIONS[action, state]
    assert (event["result"], event.get("note"), event["chain"]) == (result, note, chain)
    chain_now = session.mutex.chain
    assert chain_now.ids() == chain
    assert {k: v[1] for k, v in chain_now.held.items()} == held
    if (action, state) in (("C", "removed"), ("B", "delayed")):
        # Put back, not made again: the same rule with its state.
        assert chain_now.active[0] is before[0]


def test_a_delayed_rule_removed_then_recovered_is_the_same_rule() -> None:
    session = _in_state("delayed")
    delayed = session.mutex.chain.held["r"][0]
    assert _apply(session, "R")["result"] == "removed"
    assert _apply(session, "C")["result"] == "recovered"
    assert session.mutex.chain.active == [delayed]


def test_an_unknown_rule_action_is_the_messages_problem() -> None:
    """M005 rejects it in a checked script; run unchecked, the message fails (`rule`) and the
    chain is as it was."""
    with pytest.raises(RuleError, match=r"^unknown rule action `X`$"):
        RuleChain().apply(message("X"), STANDARD_RULES)
    session = _in_state("active")
    event = _apply(session, "X")
    assert (event["result"], event["chain"]) == ("failed", ["r"])
    assert session.trace.errors[-1]["message"] == "`r` (rulecode 0): unknown rule action `X`"


def test_the_rule_library_registers_by_rulecode_within_u32() -> None:
    library = STANDARD_RULES.extended()
    assert [(e.rulecode, e.name, e.origin) for e in library] == [
        (0, "kick_starter", "standard"), (1, "safety_stop", "standard"),
        (2, "override", "standard")]
    for code in (0xFFFFFFFF, 0):
        entry = library.register(code, "mine", Rule)
        assert library.get(code) is entry and entry.origin == "user"
    assert [e.rulecode for e in library][-1] == 0xFFFFFFFF  # in rulecode order
    for code in (-1, 0x1_0000_0000):
        with pytest.raises(ValueError, match=f"unsigned 32-bit integer, not {code}"):
            library.register(code, "mine", Rule)
    named = library.register_named("waving", Rule)
    assert named.origin == "user" and library.get(77, "waving") is named
    assert library.get(77) is None and library.get(77, "nobody") is None
    simple = library.register_simple(5, "five", "{TRUE}")
    assert library.get(5) is simple and simple.origin == "user"
    with pytest.raises(dataclasses.FrozenInstanceError):
        simple.name = "other"  # an entry is what the library was given


def test_a_rule_context_has_defaults_for_what_it_is_not_told() -> None:
    host = Host()
    ctx = _context(host)
    ctx.override("other")
    request = host.world.script.override
    assert (request.script, request.goal, request.action, request.block) == ("other", 0, 0, 0)
    host.world.apply(parse_update("Human/kid", "poses", "R", {"positionrho": 1.0}), 0)
    host.bindings.bind("?kid", host.world.entity("Human", "kid"), "U", READER)
    ctx.set_att("?kid", "mood", "calm")
    assert host.bindings.atts["?kid", "mood"].scope == "U"


@pytest.mark.parametrize("params, problem", [
    ("1x=2", "parameters are `key=value` pairs separated by `;`, found `1x=2`"),
    ("a b=2", "parameters are `key=value` pairs separated by `;`, found `a b=2`"),
    # what is wrong is quoted without the spaces after the `;` before it
    ("distance=0.6;   near", "parameters are `key=value` pairs separated by `;`, found `near`"),
])
def test_rule_parameters_need_a_name_before_each_equals_sign(params: str, problem: str) -> None:
    with pytest.raises(RuleError) as info:
        parse_params(params)
    assert str(info.value) == problem


def test_a_rule_keeps_the_message_that_made_it() -> None:
    made = RuleMessage("alfa", 2, "o", "script=next", "robot/answers", "A", "U")
    rule = STANDARD_RULES.make(made)
    assert rule.message is made and rule.message.outtopic == "robot/answers"
    assert (rule.id, rule.rulecode, rule.params) == ("o", 2, {"script": "next"})


def test_an_override_with_an_empty_when_holds_always() -> None:
    rule = STANDARD_RULES.make(message("A", rulecode=2, intopic="when="))
    assert rule.params == {"when": ""} and rule.condition.is_constant_true


def test_an_override_at_a_path_that_is_no_path_cannot_be_made() -> None:
    with pytest.raises(RuleError, match="`at` is a path `goalG/actA/blkB`, found `goal1/blk2`"):
        STANDARD_RULES.make(message("A", rulecode=2, intopic="at=goal1/blk2"))
    rule = STANDARD_RULES.make(message("A", rulecode=2, intopic="at=goal1/act2/blk3; goal=x"))
    assert (rule.goal, rule.action, rule.block) == (1, 2, 3)  # `at` wins over `goal`


def test_a_rule_that_cannot_be_made_is_reported_and_fails() -> None:
    session = started(trace=Trace())
    session.mutex.hand_over(0, (RuleMessage("alfa", 1, "safety", "distance=close", "", "A",
                                            "U"),), "alfa", "plain")
    error, rule = session.trace.errors[-1], session.trace.of_kind("rule")[-1]
    assert error["code"] == "rule" and "`distance` must be a number" in error["message"]
    assert rule["result"] == "failed" and rule["chain"] == []


def test_an_unknown_rulecode_makes_a_rule_that_does_nothing_reported_once() -> None:
    session = started(trace=Trace())
    _apply(session, "A", rulecode=999)
    assert [e["code"] for e in session.trace.errors] == ["unknown-rulecode"]
    session.mutex.pass_chain(0)
    session.mutex.pass_chain(1)
    assert [e["code"] for e in session.trace.errors] == ["unknown-rulecode"]


# -- the lock ------------------------------------------------------------------------------------


def _misuses(session: Session) -> list[str]:
    return [e["message"] for e in session.trace.errors if e["code"] == "mutex-misuse"]


@pytest.mark.parametrize("kind, letters, expected, locked", [
    ("alfa", "MU", [], False),
    ("omega", "LM", [], True),
    ("alfa", "LU", [("`r0` (alfa of `plain`) locks the map, which the previous omega had "
                    "already locked"),
                    ("`r0` locks the map in the alfa list of `plain` (alfa messages must not "
                    "lock)")], False),
    ("alfa", "UM", [("`r0` unlocks the map before the end of the alfa list of `plain`: rules "
                    "see a half-built chain")], False),
    ("alfa", "MM", [("the alfa list of `plain` leaves the map locked (its last message must be "
                    "`U`): rules do not run until a `U`")], True),
    ("omega", "ML", [("the omega list of `plain` changes the chain without locking the map "
                     "first (its first message must be `L`)")], True),
    ("omega", "LL", [("`r1` (omega of `plain`) locks the map, which omega of `plain` had "
                     "already locked")], True),
    ("omega", "LU", [("`r1` unlocks the map in the omega list of `plain` (omega messages must "
                     "not unlock)")], False),
])
def test_mutex_misuse_is_reported_and_the_lock_does_what_the_messages_say(
        kind: str, letters: str, expected: list[str], locked: bool) -> None:
    session = started(trace=Trace())
    mutex = session.mutex
    mutex.lock(0, "the previous omega")  # as a script is loaded after another's omega
    if kind == "omega":
        mutex.unlock(0, "the alfa")
    messages = tuple(RuleMessage(kind, 0, f"r{i}", "", "", "A", letter)
                     for i, letter in enumerate(letters))
    mutex.hand_over(0, messages, kind, "plain")
    assert _misuses(session) == expected
    assert mutex.chain.locked == locked


def test_a_script_without_alfa_messages_completes_the_hand_over() -> None:
    session = started(trace=Trace())
    session.mutex.lock(0, "omega of `before`")
    session.mutex.hand_over(0, (), "alfa", "plain")
    assert not session.mutex.chain.locked
    assert (session.trace.events[-1]["by"]
            == "`plain` has no alfa messages: the hand-over is complete")
    assert not _misuses(session)


def test_the_chain_is_skipped_while_locked_said_once_per_lock() -> None:
    session = started(trace=Trace())
    _apply(session, "A")
    mutex = session.mutex
    mutex.lock(0, "a test")
    for now in (1, 2):
        mutex.pass_chain(now)
    skipped = [e for e in session.trace.of_kind("mutex") if "note" in e]
    assert [e["t"] for e in skipped] == [1]
    mutex.unlock(3, "a test")
    mutex.lock(4, "a test")
    mutex.pass_chain(5)
    assert [e["t"] for e in session.trace.of_kind("mutex") if "note" in e] == [1, 5]


def _chained(*rules: tuple[int, str, type[Rule]]) -> Session:
    """A started session whose alfa list added these rules (rulecode, id, class), in order."""
    library = STANDARD_RULES.extended()
    for rulecode, rid, cls in rules:
        library.register(rulecode, rid, cls)
    session = started(trace=Trace(), rules=library)
    session.mutex.hand_over(0, tuple(
        RuleMessage("alfa", rulecode, rid, "", "", "A", "U" if k == len(rules) - 1 else "M")
        for k, (rulecode, rid, _cls) in enumerate(rules)), "alfa", "plain")
    return session


def test_the_chain_pass_runs_each_rule_in_turn_and_survives_a_body_that_raises() -> None:
    turns = []

    class Boom(Rule):
        def on_true(self, ctx):
            turns.append(("boom", ctx.now))
            raise ZeroDivisionError("no")

    class Holder(Rule):
        condition_text = "{CLASS #Human L ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}"

        def on_true(self, ctx):
            turns.append(("hold", ctx.bindings.lookup("?kid").key))
            ctx.hold_motion()

        def on_false(self, ctx):
            turns.append(("free", ctx.now))

    session = _chained((70, "b", Boom), (71, "h", Holder))
    session.mutex.pass_chain(1)
    assert turns == [("boom", 1), ("free", 1)] and not session.actuators.hold
    error = session.trace.errors[-1]
    assert error["code"] == "rule" and "rule `b` (rulecode 70) raised ZeroDivisionError: no" \
        in error["message"]
    session.world.post(parse_update("Human/kid", "poses", "R", {"positionrho": 0.5}))
    session.updates.apply(2)
    session.mutex.pass_chain(2)
    assert turns[-1] == ("hold", "Human/kid") and session.actuators.hold
    assert session.bindings.lookup("?kid") is None  # the rule's L binding ended with its turn
    session.mutex.hand_over(3, (RuleMessage("omega", 70, "b", "", "", "R", "M"),
                                RuleMessage("omega", 71, "h", "", "", "R", "M")), "omega", "plain")
    session.mutex.pass_chain(3)
    assert not session.actuators.hold  # an empty chain holds nothing


def test_a_condition_that_cannot_be_evaluated_is_the_rules_problem_not_the_runs() -> None:
    """A body may set its condition as IR (`self.condition`), past the checks a text gets
    (`parse_condition_text`): one over a class the map does not hold is reported (`rule`)
    and the chain goes on with the next rule."""
    turns = []

    class Stray(Rule):
        def __init__(self, message, params=None):
            super().__init__(message, params)
            text = "{CLASS #Human U ?d (?THIS>&positionrho OP< 1)} ! {TRUE}"
            condition = parse_condition_text(text)
            (assignment,) = condition.assignments
            dog = dataclasses.replace(assignment.class_name, text="#Dog")
            self.condition = dataclasses.replace(
                condition, assignments=(dataclasses.replace(assignment, class_name=dog),))

    class After(Rule):
        def on_true(self, ctx):
            turns.append(ctx.now)

    session = _chained((72, "s", Stray), (73, "a", After))
    session.mutex.pass_chain(1)
    assert turns == [1]
    error = session.trace.errors[-1]
    assert (error["code"], error["message"], error["fatal"]) == (
        "rule", "rule `s` (rulecode 72) raised EvaluationError: the map has no class `Dog`",
        False)


def test_an_unchecked_program_over_a_class_the_map_lacks_stops_with_a_read_error() -> None:
    """Lint (R001) and codegen refuse it; run anyway, both executors stop the run with the
    same fault, never an exception."""
    from scriptc import bytecode
    from scriptc.emit.codegen import codegen
    from scriptc.runtime.vm import program_from_bytecode

    text = ("[t]\n[goal:g]\n[action]\n[b##blk_jump: CND({CLASS #Dog U ?k "
            "(?THIS>&positionrho OP< 1)} ! {TRUE}) TRJMP() FLSJMP()]\n[b##blk_terminus]\n")
    analysis = analyze_bytes("dog.script", text.encode(), "script")
    assert [d.code for d in analysis.diagnostics] == ["R001"]
    session = Session([IRProgram(analysis.script, "dog.script")], trace=Trace())
    assert session.run(100).outcome == "error"
    assert session.trace.errors == [{"t": 0, "event": "error", "code": "read", "fatal": True,
                                     "message": "the map has no class `Dog`"}]
    human = analyze_bytes("human.script", text.replace("#Dog", "#Human").encode(), "script")
    program = codegen(human.script, human.source)
    dog = dataclasses.replace(program, constants=tuple(
        "Dog" if c == "Human" else c for c in program.constants))
    session = Session([program_from_bytecode(bytecode.verify(dog), "dog.scb")], trace=Trace())
    assert session.run(100).outcome == "error"
    (error,) = session.trace.errors
    assert error["code"] == "read" and error["message"].startswith("goal0/act0/blk0 (line 4")
    assert error["message"].endswith("the map has no class `Dog`")


def test_a_rules_condition_is_checked_when_the_rule_is_made() -> None:
    """What lint says of a script's condition, for a condition given as text (a `when=`
    parameter, `register_simple`, `set_condition`): a syntax error, a class the map does not
    hold, a scope the language does not know (tests/cases/runtime/rule_conditions.script)."""
    for text, problem in [
        ("{CLASS #Dog U ?d (?THIS>&positionrho OP< 1)} ! {TRUE}",
         "unknown class `Dog` (the classes of the map are Human, Obstacle, Object, Activity)"),
        ("{CLASS #Human Q ?d (?THIS>&positionrho OP< 1)} ! {TRUE}",
         "unknown scope `Q` (the scopes are U, L, T)"),
        ("{VAR @t X F: now()} ! {TRUE}", "unknown scope `X` (the scopes are U, L, T)"),
        ('! {E: eq("a\\q", 1)}', "unknown escape `\\q` in a string"),
    ]:
        with pytest.raises(RuleError) as info:
            parse_condition_text(text)
        assert str(info.value) == f"condition `{text}`: {problem}"
    with pytest.raises(RuleError, match="unknown class `Dog`"):
        STANDARD_RULES.extended().register_simple(
            99, "dog", "{CLASS #Dog U ?d (?THIS>&positionrho OP< 1)} ! {TRUE}")
    for cls in ("Human", "Obstacle", "Object", "Activity"):
        for scope in "ULT":
            text = f"{{CLASS #{cls} {scope} ?d (?THIS>&positionrho OP< 1)}} ! {{TRUE}}"
            assert parse_condition_text(text).assignments


def test_a_rule_fires_when_its_condition_starts_to_hold_named_by_the_script_that_put_it() -> None:
    class Near(Rule):
        condition_text = "{CLASS #Human L ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}"

        def __eq__(self, other: object) -> bool:  # a library's rule may compare by value
            return isinstance(other, Near)

        __hash__ = None  # type: ignore[assignment]  (and be unhashable, as such classes are)

        def on_true(self, ctx):
            ctx.note("near")

    library = STANDARD_RULES.extended()
    library.register(71, "near", Near)
    session = started(trace=Trace(), rules=library)
    mutex = session.mutex

    def place(now: int, rho: float) -> None:
        session.world.post(parse_update("Human/kid", "poses", "R", {"positionrho": rho}))
        session.updates.apply(now)

    def fired() -> list[tuple[int, str, str]]:
        return [(e["t"], e["script"], e["id"]) for e in session.trace.of_kind("rule_fire")]

    mutex.hand_over(0, (RuleMessage("alfa", 71, "n", "", "", "A", "M"),
                        RuleMessage("alfa", 0, "k", "", "", "A", "U")), "alfa", "plain")
    mutex.pass_chain(1)  # `{TRUE}` holds on its first pass: it fires once, not on every pass
    mutex.pass_chain(2)
    assert fired() == [(1, "plain", "k")]
    place(3, 0.5)
    for now in (3, 4):  # the child stays close: one firing
        mutex.pass_chain(now)
    place(5, 2.0)
    mutex.pass_chain(5)
    place(6, 0.5)
    mutex.pass_chain(6)  # it comes back: the rule fires again
    assert fired() == [(1, "plain", "k"), (3, "plain", "n"), (6, "plain", "n")]
    at_3 = [e["event"] for e in session.trace.events if e["t"] == 3]
    assert at_3 == ["update", "rule_fire", "rule_note"]  # the firing, then its body
    assert [e["t"] for e in session.trace.of_kind("rule_note")] == [3, 4, 6]
    # Taken out and recovered by another script between two passes: its next pass is its
    # first again, and the firing is that script's.
    mutex.hand_over(7, (RuleMessage("omega", 71, "n", "", "", "R", "M"),), "omega", "plain")
    mutex.hand_over(7, (RuleMessage("alfa", 71, "n", "", "", "C", "U"),), "alfa", "other")
    mutex.pass_chain(8)
    assert fired()[-1] == (8, "other", "n")
    mutex.lock(9, "a test")  # a skipped pass changes nothing
    mutex.pass_chain(9)
    mutex.unlock(10, "a test")
    mutex.pass_chain(10)
    assert fired()[-1] == (8, "other", "n")


# -- goal records -----------------------------------------------------------------------------


def _goals() -> tuple[Goals, Trace, RunStatus, World]:
    trace, world = Trace(), World()
    status = RunStatus(trace)
    goals = Goals(world, trace, status)
    goals.begin("act", ("a", "b", "c"), LoadRecord("act", "act.script", "queue", 0))
    return goals, trace, status, world


def test_goals_follow_the_reader() -> None:
    goals, trace, status, world = _goals()
    goals.visit(0)
    goals.visit(0)
    goals.visit(2)  # a jump forward: `a` reached
    goals.visit(1)  # a jump back: nothing
    status.now = 5
    goals.leave("terminus")  # the goal it ends in is reached
    assert [(e["goalid"], e["record"], e["t"]) for e in trace.of_kind("goal")] == \
        [("a", "reached", 0), ("b", "reached", 5)]
    assert goals.load.goals == {"a": "reached", "b": "reached"}
    assert goals.reached("a") and goals.reached("b") and not goals.reached("c")
    assert [r["goalid"] for r in world.goal_records("goalreached")] == ["a", "b"]


@pytest.mark.parametrize("how", ["override", "restart", "idle_escape"])
def test_a_script_stopped_from_outside_interrupts_its_goal(how: str) -> None:
    goals, trace, _status, _world = _goals()
    goals.visit(1)
    goals.leave(how)
    goals.end()
    assert [(e["goalid"], e["record"], e["script"]) for e in trace.of_kind("goal")] == \
        [("b", "interrupted", "act")]
    goals.record("failed", "c", by="rule")  # after the end: no script runs
    assert trace.events[-1]["script"] == "" and trace.events[-1]["by"] == "rule"


def test_a_seek_interrupts_the_goal_and_enters_afresh() -> None:
    goals, trace, _status, _world = _goals()
    goals.interrupt()  # no goal entered yet: nothing
    goals.visit(2)
    goals.interrupt()
    goals.visit(0)  # entered afresh: not a jump back
    goals.visit(1)
    assert [(e["goalid"], e["record"]) for e in trace.of_kind("goal")] == \
        [("c", "interrupted"), ("a", "reached")]


def test_goalreached_counts_a_sensors_record_since_the_load_only() -> None:
    goals, _trace, _status, world = _goals()
    goals.load = LoadRecord("act", "act.script", "queue", 100)
    world.robot.append("goalreached", {"goalid": "x", "timestamp": 99})
    world.robot.append("goalreached", {"goalid": "y", "timestamp": 100, "activity": "other"})
    assert not goals.reached("x") and not goals.reached("y")
    world.robot.append("goalreached", {"goalid": "x", "timestamp": 100})
    assert goals.reached("x")
    goals.load = None
    assert not goals.reached("x")


# -- map updates ----------------------------------------------------------------------------


def test_updates_are_posted_then_applied_and_script_vect_handed_on() -> None:
    trace, world = Trace(), World()
    handed = []
    updates = Updates(world, trace, RunStatus(trace), lambda now, value: handed.append(value))
    updates.post(3, parse_update("Human/kid", "poses", "R", {"positionrho": 1.0}))
    updates.post(3, parse_update("Human/kid", "poses", "R", {"positionrho": 2.0}))
    assert [e["status"] for e in trace.of_kind("update")] == ["dropped"]
    updates.post(3, parse_update("Script", "script_vect", "R",
                                 {"update": ["x"], "restart": "s_false"}))
    updates.apply(3)
    assert [e["status"] for e in trace.of_kind("update")] == ["dropped", "applied", "applied"]
    assert world.entity("Human", "kid").fields["positionrho"] == 2.0
    assert handed == [{"update": ["x"], "restart": "s_false"}]
    assert not world.pending


# -- overrides and script_vect ------------------------------------------------------------------

TWO_GOALS = """\
[two]
[goal:start]
  [action]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
[goal:finish]
  [action]
    [b##blk_inst: MV() LD() AO("Silence, 0, 1000")]
    [b##blk_terminus]
"""


def _override(session: Session, script: str, goal=0, action=0, block=0) -> None:
    from scriptc.runtime.world import OverrideRequest

    session.world.script.override = OverrideRequest(script, goal, action, block, "switch")
    session.overrides.apply(0)


def test_an_override_to_another_script_by_goal_id() -> None:
    session = started(program(), catalogue=[program(TWO_GOALS, "two.script")], trace=Trace())
    _override(session, "two", "finish")
    trace = session.trace
    assert trace.of_kind("override")[-1] == {"t": 0, "event": "override", "by": "switch",
                                             "script": "plain", "to": "two",
                                             "at": "goal1/act0/blk0"}
    assert [e["reason"] for e in trace.of_kind("script_unload", "script_load")] == \
        ["queue", "override", "override"]
    assert session.scripts.executor.name == "two"
    session.scripts.read(0)
    assert session.scripts.issued_path == "goal1/act0/blk0"


@pytest.mark.parametrize("script, goal, block, problem", [
    ("nobody", 0, 0, "override by `switch`: no script named `nobody`"),
    ("two", "middle", 0, "override by `switch`: `two` has no goal `middle`"),
])
def test_an_override_that_cannot_be_carried_out_switches_nothing(script, goal, block,
                                                                 problem) -> None:
    session = started(program(), catalogue=[program(TWO_GOALS, "two.script")], trace=Trace())
    _override(session, script, goal, block=block)
    assert session.trace.errors[-1]["message"] == problem
    assert session.scripts.executor.name == "plain" and session.world.script.override is None


def test_an_override_to_a_missing_block_of_another_script_starts_it_at_its_first() -> None:
    session = started(program(), catalogue=[program(TWO_GOALS, "two.script")], trace=Trace())
    _override(session, "two", 0, block=9)
    assert session.trace.errors[-1]["message"].endswith(": it starts at its first block")
    assert session.scripts.executor.name == "two"


def test_an_override_to_the_running_script_is_a_seek() -> None:
    session = started(program(TWO_GOALS, "two.script"), trace=Trace())
    session.scripts.issue(0)
    session.bindings.set_var("@kept", "yes", "U", "r")
    _override(session, "two", 1)
    trace = session.trace
    assert trace.of_kind("goal")[-1]["record"] == "interrupted"
    assert trace.of_kind("cmd_stop")[-1].get("cancelled") is True
    assert session.scripts.need_read and not session.scripts.pending_issue
    assert session.world.script.block is None
    assert session.bindings.get_var("@kept") == "yes"  # bindings kept
    assert not trace.of_kind("script_unload")
    _override(session, "two", 0, block=7)
    assert trace.errors[-1]["code"] == "override" and "has no block" in trace.errors[-1]["message"]


def test_a_loader_failure_is_the_overrides_problem() -> None:
    def loader(path: str):
        raise LoadError(f"`{Path(path).name}` has errors")

    session = started(program(), loader=loader, trace=Trace())
    _override(session, "broken.script")
    assert session.trace.errors[-1]["message"] == "override by `switch`: `broken.script` has errors"


def test_script_vect_replaces_the_queue_and_restarts() -> None:
    two = program(TWO_GOALS, "two.script")
    session = started(program(), catalogue=[two], trace=Trace())
    session.overrides.script_vect(0, {"update": ["two", "nobody"], "restart": "s_false"})
    assert session.trace.errors[-1]["code"] == "script_vect"
    assert session.scripts.lifo == [two] and session.world.script.script_vect == ["two"]
    assert session.scripts.executor.name == "plain"
    session.overrides.script_vect(0, {"update": ["two"], "restart": "s_true"})
    assert [e["reason"] for e in session.trace.of_kind("script_unload")] == ["restart"]
    assert session.scripts.executor.name == "two" and session.scripts.lifo == []


# -- the operator ---------------------------------------------------------------------------------


def test_the_operators_joystick_needs_the_safety_lock() -> None:
    session = started(trace=Trace())
    operator, act = session.operator, session.actuators
    assert operator.on_event(5, OperatorEvent(5, "drive", {"v_x": 0.2}, 0)) is True
    assert session.status.now == 5 and session.trace.events[-1]["ignored"] is True
    assert not act.driving
    operator.press(6, OperatorEvent(6, "safety_lock", {"held": True}, 1))
    operator.press(6, OperatorEvent(6, "drive", {"v_x": 0.2, "duration": 10}, 2))
    assert act.driving and act.drive_v == (0.2, 0.0, 0.0)
    operator.press(7, OperatorEvent(7, "interrupt", {}, 3))
    operator.press(8, OperatorEvent(8, "interrupt", {}, 4))
    operator.press(9, OperatorEvent(9, "interrupt", {"on": True}, 5))
    assert [e["on"] for e in session.trace.of_kind("operator") if e["command"] == "interrupt"] == \
        [True, False, True]
    assert act.frozen


# -- scripts: the catalogue, the LIFO, idle ------------------------------------------------------


def test_the_catalogue_finds_by_name_path_and_loader_and_keeps_what_it_loaded(
        tmp_path: Path) -> None:
    plain = program(name=str(tmp_path / "plain.script"))
    loaded = []

    def loader(path: str):
        loaded.append(path)
        return plain

    catalogue = Catalogue([plain], str(tmp_path), loader)
    assert catalogue.find("plain") is plain
    assert catalogue.find("plain.script") is plain  # its path, relative to the folder
    assert catalogue.find("other.script") is plain and catalogue.find("other.script") is plain
    assert loaded == [str(tmp_path / "other.script")]
    assert Catalogue([], str(tmp_path)).find("nothing") is None


def test_the_lifo_runs_in_order_then_idles_or_completes() -> None:
    a, b = program(name="a.script"), program(name="b.script")
    session = Session([a, b], stop_when_done=False, trace=Trace())
    scripts = session.scripts
    assert scripts.lifo == [b, a]
    scripts.load_when_free(0)
    assert scripts.program is a
    scripts.unload(0, "terminus")
    scripts.next(0)
    scripts.unload(0, "terminus")
    scripts.next(0)
    assert scripts.program is scripts.idle
    scripts.queue([a])
    scripts.load_when_free(0)  # a real script waits: idle is left
    assert scripts.program is a
    assert [(r.script, r.reason, r.ended_by) for r in scripts.loads][-2:] == \
        [("idle_activity", "idle", "idle_escape"), ("plain", "queue", None)]
    scripts.unload(0, "terminus")
    assert not session.status.done
    session.scripts.stop_when_done = True
    scripts.next(0)
    assert session.status.done and session.status.outcome == "completed"


# -- the actuators' effects on the map ------------------------------------------------------------

TRACKS = """\
[tracks]
[goal:g]
  [action]
    [b##blk_inst: MV("0.1, 0, 0, 100, 200", "0, 0, 0.5, 0, 300") LD("1, 0.5, 0, 1, 50, 100")
                  AO("song.wav, 0, 400")]
    [b##blk_inst: MV("0.2, 0, 0, 0, 1000") LD("0, 0, 1, 1, 0, 1000") AO("song.wav, 0, 1000")]
    [b##blk_terminus]
"""


def _ran_until(until: int, operator=()) -> Session:
    scenario = scenario_from_data({"operator": list(operator)}) if operator else None
    session = Session([program(TRACKS)], trace=Trace(), scenario=scenario)
    session.run(until)
    return session


def test_the_actuators_write_each_commands_progress_and_history_to_the_map() -> None:
    """After each command the map gets the number of commands done on its track
    (`Script/submove`, `subled`, `subaout`) and a history record of what it did
    (`RobotStatus/speed`, `led`, `audioout`), its latest value in the robot's fields."""
    world = _ran_until(350).world
    info, robot = world.script, world.robot
    assert (info.submove, info.subled, info.subaout) == (1, 1, 0)
    assert list(robot.history["speed"]) == [
        {"xspeed": 0.1, "yspeed": 0.0, "thetaspeed": 0.0, "duration": 200, "startingtime": 100}]
    assert list(robot.history["led"]) == [
        {"r": 1.0, "g": 0.5, "b": 0.0, "frequency": 0, "duration": 100, "startingtime": 50}]
    assert "audioout" not in robot.history
    assert robot.fields["speed"] is robot.history["speed"][-1]
    assert _ran_until(450).world.script.subaout == 1
    world = _ran_until(650).world
    info, robot = world.script, world.robot
    # The second block began at 600: its progress starts again from 0.
    assert (info.submove, info.subled, info.subaout) == (0, 0, 0)
    assert [r["duration"] for r in robot.history["speed"]] == [200, 300]
    assert robot.history["speed"][1]["thetaspeed"] == 0.5
    assert list(robot.history["audioout"]) == [
        {"duration": 400, "startingtime": 0, "trackpath": "song.wav"}]


def test_a_cancelled_command_is_in_the_history_with_the_time_it_ran_and_no_progress() -> None:
    session = _ran_until(1000)
    assert session.world.script.submove == 0
    session.actuators.cancel(1000)
    robot = session.world.robot
    assert robot.history["speed"][-1] == {"xspeed": 0.2, "yspeed": 0.0, "thetaspeed": 0.0,
                                          "duration": 400, "startingtime": 600}
    assert robot.history["led"][-1]["duration"] == 400
    assert robot.history["audioout"][-1]["duration"] == 400
    assert session.world.script.submove == 0 and not session.actuators.block_active
    assert [e["track"] for e in session.trace.of_kind("cmd_stop") if e.get("cancelled")] == \
        ["move", "led", "audioout"]


def test_a_frozen_block_pauses_its_audio_and_resumes_where_it_stopped() -> None:
    """The operator's interrupt at 200 ms (the safety lock held) freezes the block's clock
    until 500 ms: the audio pauses (observed as none), and every command ends 300 ms later
    than written."""
    operator = [{"at": 0, "command": "safety_lock", "held": True},
                {"at": 200, "command": "interrupt"}, {"at": 500, "command": "interrupt"}]
    scenario = scenario_from_data({"operator": operator})
    session = Session([program(TRACKS)], trace=Trace(), scenario=scenario)
    seen = {o.t: o for o in session.run(2500, observe=(150, 250, 550)).observations}
    assert (seen[150].audio, seen[250].audio, seen[550].audio) == ("song.wav", None, "song.wav")
    robot = session.world.robot
    assert [(r["startingtime"], r["duration"]) for r in robot.history["speed"]][:2] == \
        [(100, 200 + 300), (600, 300)]
    assert robot.history["audioout"][0] == {"duration": 700, "startingtime": 0,
                                            "trackpath": "song.wav"}


# -- the actuators alone: a queue, a robot, a trace and a map -------------------------------------


class Wheels:
    """A robot (the `Drive` the actuators need) that keeps the velocities it is given."""

    name = "wheels"

    def __init__(self) -> None:
        self.given: list[tuple[int, float, float, float]] = []

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float) -> None:
        self.given.append((t_ms, v_x, v_y, v_theta))


def _actuators() -> tuple[Actuators, EventQueue, Wheels, Trace]:
    queue, wheels, trace = EventQueue(), Wheels(), Trace()
    return Actuators(queue, wheels, trace, World()), queue, wheels, trace


def _until(queue: EventQueue, t: int) -> None:
    """Run every event due by `t`, in order."""
    while (due := queue.next_time()) is not None and due <= t:
        while (item := queue.pop_due(due)) is not None:
            item[0](due, item[1])


def _stops(trace: Trace) -> list[tuple[int, str, bool]]:
    return [(e["t"], e["track"], e.get("cancelled", False)) for e in trace.of_kind("cmd_stop")]


STEP = BlockCommands(moves=(Move(0.1, 0.0, 0.0, 0, 100),))


def test_a_block_alone_is_consumed_when_its_tracks_are_done() -> None:
    act, queue, wheels, trace = _actuators()  # no `on_consumed`: nobody to tell
    act.issue(0, STEP)
    assert act.block_active
    _until(queue, 99)
    assert act.block_active
    _until(queue, 100)
    assert not act.block_active and len(queue) == 0
    assert wheels.given == [(0, 0.1, 0.0, 0.0), (100, 0.0, 0.0, 0.0)]
    act.issue(100, BlockCommands())  # no command at all: consumed as it is issued
    assert not act.block_active and _stops(trace) == [(100, "move", False)]


@pytest.mark.parametrize("presses", [
    [(40, True), (70, True), (100, False)],  # already frozen at 70: the 60 ms left stay 60
    [(40, True), (100, False), (130, False)],  # already running at 130: not put off
])
def test_freezing_twice_or_thawing_twice_changes_nothing(presses) -> None:
    act, queue, _wheels, trace = _actuators()
    act.issue(0, STEP)
    for t, on in presses:
        _until(queue, t - 1)
        act.freeze(t, on)
    _until(queue, 1000)
    assert _stops(trace) == [(160, "move", False)]


def test_a_block_frozen_at_the_instant_it_ends_is_consumed_when_it_thaws() -> None:
    consumed = []
    act, queue, _wheels, trace = _actuators()
    act.on_consumed = consumed.append
    act.issue(0, STEP)
    _until(queue, 99)
    act.freeze(100, True)  # before the track's event at 100 runs
    _until(queue, 300)
    assert consumed == [] and act.block_active
    act.freeze(300, False)
    assert consumed == [300] and not act.block_active
    assert _stops(trace) == [(300, "move", False)]


def test_a_block_issued_while_frozen_starts_when_it_thaws() -> None:
    act, queue, _wheels, trace = _actuators()
    act.freeze(0, True)
    act.issue(10, BlockCommands(moves=(Move(0.1, 0.0, 0.0, 20, 100),)))
    _until(queue, 500)
    assert not trace.of_kind("cmd_start")
    act.freeze(500, False)
    _until(queue, 1000)
    assert [e["t"] for e in trace.of_kind("cmd_start")] == [520]
    assert _stops(trace) == [(620, "move", False)]


def test_a_cancelled_block_leaves_nothing_to_start_later() -> None:
    act, queue, _wheels, trace = _actuators()
    act.issue(0, BlockCommands(moves=(Move(0.1, 0.0, 0.0, 500, 100),)))
    act.cancel(100)  # the move still waits: it never starts
    assert not act.block_active
    act.freeze(200, True)
    act.freeze(300, False)
    _until(queue, 2000)
    assert not trace.of_kind("cmd_start") and not _stops(trace)


def test_thawing_with_no_block_issued_consumes_nothing() -> None:
    consumed = []
    act, queue, wheels, _trace = _actuators()
    act.on_consumed = consumed.append
    act.freeze(10, True)
    act.freeze(20, False)
    _until(queue, 100)
    assert consumed == [] and not act.block_active and wheels.given == []


class Planning(Wheels):
    """A robot that plans each block's moves ahead (a `Planner`, as the safety governor is):
    it keeps what it is told."""

    def __init__(self) -> None:
        super().__init__()
        self.told: list[tuple] = []

    def plan_block(self, t_ms: int, moves: tuple[Move, ...], length: int) -> None:
        self.told.append(("plan", t_ms, moves, length))

    def drop_plan(self, t_ms: int) -> None:
        self.told.append(("drop", t_ms))


@pytest.mark.parametrize("take, give", [
    (lambda act, t: act.freeze(t, True), lambda act, t: act.freeze(t, False)),
    (lambda act, t: act.set_hold(t, True), lambda act, t: act.set_hold(t, False)),
    (lambda act, t: act.drive(t, (0.2, 0.0, 0.0), None), lambda act, t: act.set_safety(t, False)),
], ids=["frozen", "held", "driven"])
def test_a_planning_robot_plans_the_blocks_the_script_drives_and_drops_what_it_cannot(
        take, give) -> None:
    """The governor plans a block's moves when it is issued, only while the script has the
    wheels (not while the block is frozen, a rule holds motion or the operator drives); a
    block cancelled, or whatever else takes the wheels, drops the plan."""
    robot = Planning()
    act = Actuators(EventQueue(), robot, Trace(), World())
    block = BlockCommands(moves=(Move(0.1, 0.0, 0.0, 0, 100), Move(0.0, 0.0, 0.0, 50, 100)))
    act.issue(0, block)
    assert robot.told == [("plan", 0, block.moves, 250)]
    act.cancel(10)
    assert robot.told[1:] == [("drop", 10)]
    take(act, 20)  # the wheels are taken from the script: its plan is dropped...
    # ...and a block issued meanwhile is not planned (its move waits: it does not take the
    # wheels back from the operator)
    act.issue(30, BlockCommands(moves=(Move(0.1, 0.0, 0.0, 100, 100),)))
    assert robot.told[2:] == [("drop", 20), ("drop", 30)]
    give(act, 40)
    act.issue(50, block)  # a block replaced: the one running is dropped, the new one planned
    assert robot.told[4:] == [("drop", 40), ("drop", 50), ("plan", 50, block.moves, 250)]


def test_the_operators_drives_and_the_safety_lock() -> None:
    act, queue, wheels, trace = _actuators()
    act.issue(0, BlockCommands(moves=(Move(0.1, 0.0, 0.0, 0, 1000),)))
    act.set_safety(100, True)
    act.drive(100, (0.5, 0.0, 0.0), 100)  # until 200...
    act.drive(150, (0.0, 0.5, 0.0), 100)  # ...replaced at 150, until 250
    act.set_safety(180, True)  # held again: the drive goes on
    _until(queue, 240)
    assert act.driving and act.effective_velocity() == (0.0, 0.5, 0.0)
    _until(queue, 250)
    # The drive cancelled the running move command: the wheels stop, the move does not resume.
    assert not act.driving and act.effective_velocity() == (0.0, 0.0, 0.0)
    assert wheels.given[-3:] == [(100, 0.5, 0.0, 0.0), (150, 0.0, 0.5, 0.0),
                                 (250, 0.0, 0.0, 0.0)]
    assert trace.of_kind("velocity")[-1]["cause"] == "operator"
    act.drive(300, (0.2, 0.0, 0.0), None)
    act.set_safety(400, False)  # released: the drive ends at once
    assert not act.driving and wheels.given[-1] == (400, 0.0, 0.0, 0.0)


def test_a_drive_ending_is_an_instant_of_the_run() -> None:
    """The end of a timed drive changes the wheels: the loop settles at that instant (the
    chain passes), as at any other event that changed something."""
    passes = []
    library = STANDARD_RULES.extended()
    library.register_simple(81, "watch", "{TRUE}", on_true=lambda ctx: passes.append(ctx.now))
    operator = [{"at": 0, "command": "safety_lock", "held": True},
                {"at": 100, "command": "drive", "v_x": 0.3, "duration": 50}]
    text = PLAIN.replace("[plain]\n", '[plain]\n[alfa:81, watch, "", "", A, U]\n'
                         '[omega:81, watch, "", "", R, L]\n')
    session = Session([program(text)], trace=Trace(), rules=library,
                      scenario=scenario_from_data({"operator": operator}))
    session.run(500)
    assert 150 in passes and 125 not in passes
    # A drive replaced before its end: its end is no instant (nothing changes then).
    operator.append({"at": 200, "command": "drive", "v_x": 0.3, "duration": 50})
    operator.append({"at": 220, "command": "drive", "v_x": 0.1, "duration": 100})
    passes.clear()
    session = Session([program(text)], trace=Trace(), rules=library,
                      scenario=scenario_from_data({"operator": operator}))
    session.run(500)
    assert 250 not in passes and 320 in passes


def test_a_cancelled_blocks_queued_events_are_no_instants() -> None:
    """An override seeks the second goal when a child comes at 300 ms: the running block is
    cancelled, and the track event it had queued (its audio's end at 1000) makes no instant of
    the run (at 1300 the new block ends the script, whose omega locks the chain)."""
    passes = []
    library = STANDARD_RULES.extended()
    library.register_simple(82, "watch", "{TRUE}", on_true=lambda ctx: passes.append(ctx.now))
    when = "{CLASS #Human U ?k (?THIS>&positionrho OP< 1)} ! {TRUE}"
    text = TWO_GOALS.replace("[two]\n", f'[two]\n[alfa:2, seek, "goal=finish; when={when}", "", '
                             'A, M]\n[alfa:82, watch, "", "", A, U]\n'
                             '[omega:82, watch, "", "", R, L]\n[omega:2, seek, "", "", R, M]\n')
    world = {"updates": [{"at": 300, "objectid": "Human/kid", "attributename": "poses",
                          "policy": "R", "jsonmsg": {"positionrho": 0.5}}]}
    session = Session([program(text, "two.script")], trace=Trace(), rules=library,
                      scenario=scenario_from_data(world))
    session.run(2000)
    assert [e["t"] for e in session.trace.of_kind("cmd_stop")] == [300, 1300]
    assert passes == [0, 300, 300]  # the start, the update, the seek's loop; not 1000


# -- the run's status ---------------------------------------------------------------------------


def test_a_fatal_problem_stops_the_actuators_and_ends_the_run() -> None:
    trace = Trace()
    stopped = []
    status = RunStatus(trace, on_fatal=stopped.append)
    status.report(1, "update", "a warning")
    assert not status.done and not stopped
    status.fatal(2, NO_PROGRESS, "stuck")
    assert stopped == [2] and status.done and status.outcome == "error"
    assert [(e["code"], e["fatal"]) for e in trace.errors] == [("update", False),
                                                               ("no-progress", True)]
