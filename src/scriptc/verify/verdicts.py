"""The properties, decided from an exploration and confirmed by replays (docs/verify.md,
"Properties").

Each property is `proved`, `violated` or `unknown`:

- what holds of *every* run (`terminates`, `no-stall`, `no-progress`, `safety`, the bounds of
  `duration`, a goal or block that no run reaches) is proved from the exploration, which
  follows every run (and possibly runs no world makes: a proof over more runs than there are
  holds of the real ones); it needs the exploration complete, else it is `unknown`;
- what holds of *some* run (a goal or block reached, a loop that never ends, the fastest and
  the slowest session) is a path the exploration found: it is written out as a world
  (`witness.build_world`) and replayed by the runtime, and only when the replay does it is
  it `confirmed`. A violation whose world could not be made is `unknown`, never `violated`.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from scriptc import interrupt
from scriptc.runtime.loop import RunResult
from scriptc.runtime.status import NO_PROGRESS, READ
from scriptc.source import Span
from scriptc.verify.explore import (
    MAX_RECORDS,
    Cycle,
    Exploration,
    Reach,
    Record,
    Visit,
    explore,
    trail,
)
from scriptc.verify.model import JUMP, Model, Step
from scriptc.verify.timeset import TimeSet
from scriptc.verify.witness import Built, Runner, build_world

__all__ = ["PROPERTIES", "PROVED", "UNKNOWN", "VIOLATED", "Finding", "Item", "Verification",
           "Witness", "verify_model"]

PROVED, VIOLATED, UNKNOWN = "proved", "violated", "unknown"
PROPERTIES = ("terminates", "goals", "blocks", "duration", "no-stall", "no-progress", "safety")
# Replays spent confirming that blocks are reached, beyond those of goals and durations.
BLOCK_REPLAYS = 16
# The ways to reach a goal tried, earliest first, until a world is made for one.
WAYS_TRIED = 3


@dataclass
class Witness:
    """A run verify wrote out as a world and replayed: `name` what it shows (`slowest`,
    `goal:ID`, `no-stall`...), the path (`visits`), the world (`world`), the replay's result
    and whether it showed what was claimed (`confirmed`, `why` when not). `until` is the time
    limit of the replay (a run that must not end by then), `governed` whether the replay ran
    with the safety governor."""

    name: str
    visits: list[Visit]
    world: Built
    claim: str
    until: int | None = None
    governed: bool = False
    confirmed: bool = False
    why: str = ""
    result: RunResult | None = None
    path: str | None = None  # where the scenario file was written (set by the caller)


@dataclass(frozen=True, slots=True)
class Item:
    """One thing a violated property is about (a goal, a block, a loop), where it is, what
    to say of it and why."""

    span: Span
    message: str
    notes: tuple[str, ...] = ()
    key: str = ""  # the goal's id, the block's path


@dataclass
class Finding:
    """One property's verdict: `status`, `detail` (a sentence), where it points (`span`:
    the loop, the goal, the block, the jump; None for the script as a whole), further
    `notes`, the run that shows it (`witness`, for a violation or an asked witness), and for
    a violation each thing it is about (`items`)."""

    property: str
    status: str
    detail: str
    span: Span | None = None
    notes: list[str] = field(default_factory=list)
    witness: Witness | None = None
    items: list[Item] = field(default_factory=list)


@dataclass
class Verification:
    """The verdicts on one script, the session's least and greatest duration (ms; `max`
    None when unbounded or unknown), what was explored and how long it took, and the
    witnesses asked for (`--witness`)."""

    model: Model
    exploration: Exploration
    findings: list[Finding]
    duration_min: int | None
    duration_max: int | None
    unbounded: bool
    witnesses: list[Witness]
    replays: int
    seconds: float
    interrupted: bool = False  # Ctrl-C stopped the exploration or a replay
    reached_goals: frozenset[str] = frozenset()  # goals a replay reached

    @property
    def states(self) -> int:
        return self.exploration.count

    def finding(self, name: str) -> Finding:
        return next(f for f in self.findings if f.property == name)

    @property
    def violated(self) -> bool:
        return any(f.status == VIOLATED for f in self.findings)


def verify_model(model: Model, runner: Runner, *, witnesses: Sequence[str] = (),
                 unsafe: dict[int, list[str]] | None = None, max_records: int | None = None,
                 interrupted: Callable[[], bool] | None = None,
                 progress: Callable[[int], None] | None = None) -> Verification:
    """Explore `model` and decide every property (see the module's docstring). `unsafe` maps
    the index of each instruction block the safety checks find outside the robot profile to
    what they say; `witnesses` are the runs asked for: `fastest`, `slowest`, or a goal id.
    `interrupted` and `progress` are the exploration's (`explore`)."""
    started = time.perf_counter()
    found = explore(model, max_records=max_records or MAX_RECORDS, interrupted=interrupted,
                    progress=progress)
    judge = _Judge(model, found, runner, interrupted)
    findings = judge.findings(unsafe or {})
    asked = [judge.asked(name) for name in witnesses]
    return Verification(model, found, findings, judge.min, judge.max, judge.unbounded,
                        asked, runner.runs, time.perf_counter() - started,
                        judge.stopped or found.bound == "interrupted",
                        frozenset(judge.confirmed_goals))


class _Judge:
    """Decides the properties of one exploration (see the module's docstring)."""

    def __init__(self, model: Model, found: Exploration, runner: Runner,
                 interrupted: Callable[[], bool] | None = None) -> None:
        self.interrupted = interrupted
        self.stopped = False  # Ctrl-C came: no more replays
        self.model = model
        self.found = found
        self.runner = runner
        self.complete = found.complete
        ends = found.end_times()
        self.min: int | None = ends.min() if ends else None
        self.stall = self._stall()
        self.zeno = self._zero_time_cycle()
        self.unbounded = self.stall is not None
        top = ends.max() if ends else None
        self.max: int | None = None if self.unbounded or not self.complete else top
        self._ways: dict[int, list[tuple[Step, bool | None, TimeSet]]] | None = None
        self.confirmed_blocks: set[str] = set()
        self.confirmed_goals: set[str] = set()
        self._witnesses: dict[str, Witness] = {}

    # -- replays --------------------------------------------------------------------------------

    def _replay(self, name: str, visits: list[Visit], claim: str,
                check: Callable[[RunResult], str], until: int | None = None,
                governed: bool = False) -> Witness:
        """Make the world of `visits`, replay it, and ask `check` of the run ("" when it shows
        the claim, else why not)."""
        if name in self._witnesses:
            return self._witnesses[name]
        if self.stopped or self.found.bound == "interrupted" or (
                self.interrupted is not None and self.interrupted()):  # Ctrl-C: no more
            self.stopped = True
            witness = Witness(name, visits, Built(ok=False, why="interrupted"), claim, until,
                              governed, why="interrupted before its replay")
            self._witnesses[name] = witness
            return witness
        try:
            world = build_world(self.model, visits, self.runner, until=until,
                                governed=governed)
        except interrupt.Interrupted:
            self.stopped = True
            world = Built(ok=False, why="interrupted during its replay")
        witness = Witness(name, visits, world, claim, until, governed)
        if world.ok and world.result is not None:
            # The run that took the path is the replay: it went to `until` (or to the end).
            witness.result = world.result
            witness.why = check(world.result)
            witness.confirmed = not witness.why
            self._note(world.result)
        else:
            witness.why = world.why
        self._witnesses[name] = witness
        return witness

    def _note(self, result: RunResult) -> None:
        """The blocks and goals a replay reached (confirmed reachable)."""
        for e in result.trace.events:
            kind = e["event"]
            if kind in ("block", "jump", "terminus", "sensor"):
                self.confirmed_blocks.add(str(e["path"]))
            elif kind == "goal" and e.get("record") == "reached":
                self.confirmed_goals.add(str(e["goalid"]))
        # A terminus or a jump shows its own block; instruction blocks show as `block`; a
        # block read on the way to one (a sensor) as `sensor`.

    def _end_witness(self, name: str, t: int) -> Witness:
        record = next(r for r in self.found.ends if t in r.times)
        visits = trail(record, t)

        def check(result: RunResult) -> str:
            if result.outcome != "completed":
                return f"the replay ended `{result.outcome}`, not completed"
            if result.time_ms != t:
                return f"the replay's session lasted {result.time_ms} ms, not {t} ms"
            return ""

        return self._replay(name, visits, f"the session ends at {t} ms", check)

    # -- the properties -------------------------------------------------------------------------

    def findings(self, unsafe: dict[int, list[str]]) -> list[Finding]:
        out = {"no-stall": self._no_stall(), "no-progress": self._no_progress()}
        out["terminates"] = self._terminates(out["no-stall"], out["no-progress"])
        out["goals"] = self._goals()
        out["duration"] = self._duration()
        out["blocks"] = self._blocks()
        out["safety"] = self._safety(unsafe)
        return [out[name] for name in PROPERTIES]

    def _incomplete(self, name: str, what: str) -> Finding:
        return Finding(name, UNKNOWN, f"{what}: the exploration stopped ({self.found.bound})")

    def _stall(self) -> tuple[Record, Cycle] | None:
        """A loop the world can keep going forever: a cycle taken without end."""
        for records in self.found.records:
            for record in records:
                for cycle, turns in record.loops:
                    if turns is None:
                        return record, cycle
        return None

    def _no_stall(self) -> Finding:
        if self.stall is None:
            if not self.complete:
                return self._incomplete("no-stall", "no run was found that waits forever")
            return Finding("no-stall", PROVED, "every run leaves every loop it enters")
        record, loop = self.stall
        start = record.base.min()
        t = start + 2 * loop.period
        visits = trail(record, t)
        until = t + loop.period
        jumps = [m.node for m in loop.moves if m.via is not None]
        where = self.model.steps[jumps[-1] if jumps else record.block]

        def check(result: RunResult) -> str:
            if result.outcome != "until":
                return f"the replay ended `{result.outcome}` at {result.time_ms} ms"
            return ""

        witness = self._replay("no-stall", visits, f"the run is still in the loop at {until} ms",
                               check, until=until)
        status = VIOLATED if witness.confirmed else UNKNOWN
        detail = (f"a world can keep the robot in the loop through `{_name(where)}` forever: "
                  f"from {start} ms, every {loop.period} ms, no exit is ever forced")
        if not witness.confirmed:
            detail += f" (not confirmed: {witness.why})"
        note = (f"the loop turns every {loop.period} ms from {start} ms, and only the world "
                "can end it: nothing the robot decides forces a way out")
        items = [Item(where.span, "a world can keep the robot in this loop forever", (note,))]
        return Finding("no-stall", status, detail, where.span, witness=witness, items=items)

    def _zero_time_cycle(self) -> list[tuple[int, int]] | None:
        """A cycle of moves that take no time, and an instant at which a run can go round it:
        the blocks of the cycle as (block, instant) in order; None when there is none."""
        edges = self.found.zero_edges
        succ: dict[int, list[int]] = {}
        for (a, b) in edges:
            succ.setdefault(a, []).append(b)
        # Only the blocks of a strongly connected set of such moves can be on a cycle (none in
        # a script lint passed: F002). Instants at each from which a cycle can be followed for
        # ever: the greatest fixpoint of "there is a move to a block that can go on".
        cyclic = _on_cycles(succ)
        succ = {a: [b for b in bs if b in cyclic] for a, bs in succ.items() if a in cyclic}
        alive = {a: TimeSet.all() for a in succ}
        changed = True
        while changed:
            changed = False
            for a in list(alive):
                can = TimeSet.empty()
                for b in succ.get(a, ()):
                    if b in alive:
                        can = can | (edges[(a, b)] & alive[b])
                if can != alive[a]:
                    changed = True
                    if can:
                        alive[a] = can
                    else:
                        del alive[a]
        if not alive:
            return None
        node = min(alive, key=lambda a: (alive[a].min(), a))
        t = alive[node].min()
        cycle = [(node, t)]
        seen = {node}
        here = node
        while True:
            nxt = min(b for b in succ[here] if b in alive and t in edges[(here, b)]
                      and t in alive[b])
            cycle.append((nxt, t))
            if nxt in seen:
                return cycle
            seen.add(nxt)
            here = nxt

    def _no_progress(self) -> Finding:
        cycle = self.zeno
        if cycle is None:
            if not self.complete:
                return self._incomplete("no-progress", "no cycle that lets no time pass was "
                                        "found")
            return Finding("no-progress", PROVED, "time passes on every cycle a run can take")
        end = self.model.end
        first, t = cycle[0]
        record = next(r for r in self.found.by_state[first] if t in r.times)
        visits = trail(record, t)
        for (a, _), (b, _) in itertools.pairwise(cycle):
            step = self.model.steps[a % end]
            via = (b % end == step.on_true) if step.kind == JUMP else None
            visits.append(Visit(b % end, t, via))
        step = self.model.steps[first % end]

        def check(result: RunResult) -> str:
            codes = {e.get("code") for e in result.errors if e.get("fatal")}
            if result.outcome == "error" and codes & {NO_PROGRESS, READ}:
                return ""
            return f"the replay ended `{result.outcome}` without the run-time error"

        witness = self._replay("no-progress", visits, f"the run goes round without time "
                               f"passing at {t} ms", check)
        names = ", ".join(f"`{_name(self.model.steps[a % end])}`" for a, _ in cycle[:-1])
        status = VIOLATED if witness.confirmed else UNKNOWN
        detail = f"at {t} ms a run can go round {names} without time passing"
        if not witness.confirmed:
            detail += f" (not confirmed: {witness.why})"
        items = [Item(step.span, "a run can go round these blocks without time passing",
                      (f"at {t} ms: {names}, and back",))]
        return Finding("no-progress", status, detail, step.span, witness=witness, items=items)

    def _terminates(self, stall: Finding, zeno: Finding) -> Finding:
        for cause in (stall, zeno):
            if cause.status == VIOLATED:
                return Finding("terminates", VIOLATED, f"a run never ends: {cause.detail}",
                               cause.span, witness=cause.witness)
        if stall.status == PROVED and zeno.status == PROVED:
            return Finding("terminates", PROVED, "every run ends, in every world")
        return Finding("terminates", UNKNOWN, "not decided: "
                       + "; ".join(f.detail for f in (stall, zeno) if f.status == UNKNOWN))

    def _goals(self) -> Finding:
        model, found = self.model, self.found
        notes: list[str] = []
        missing: list[int] = []
        unconfirmed: list[str] = []
        # The goal reached latest first: its run passes most of the others.
        order = sorted(range(len(model.goal_ids)),
                       key=lambda g: -(_latest(found.reached.get(g, ())) or -1))
        for g in order:
            goalid = model.goal_ids[g]
            if goalid in self.confirmed_goals:
                continue
            reaches = found.reached.get(g)
            if not reaches:
                missing.append(g)
                continue
            witness = self._goal_witness(g)
            if not witness.confirmed:
                unconfirmed.append(goalid)
        span = None
        items = []
        if missing:
            for g in missing:
                why = self._why_unreached_goal(g)
                notes.append(f"goal `{model.goal_ids[g]}` is never reached: {why}")
                items.append(Item(model.goal_spans[g], f"no world reaches the goal "
                                  f"`{model.goal_ids[g]}`", (why,), model.goal_ids[g]))
            span = model.goal_spans[missing[0]]
            if self.complete:
                names = ", ".join(f"`{model.goal_ids[g]}`" for g in missing)
                return Finding("goals", VIOLATED, f"no world reaches {names}", span, notes,
                               items=items)
        if unconfirmed or missing:
            what = []
            if missing:
                what.append("the exploration stopped before reaching "
                            + _some([model.goal_ids[g] for g in missing]))
            if unconfirmed:
                what.append("no replay confirmed " + _some(unconfirmed))
            return Finding("goals", UNKNOWN, "; ".join(what), span, notes)
        return Finding("goals", PROVED,
                       f"each of the {len(model.goal_ids)} goals is reached in some world")

    def _goal_witness(self, g: int) -> Witness:
        """A run that reaches goal `g`: the earliest way the exploration found first, then
        (when no world could be made for it) the next ways, up to WAYS_TRIED."""
        goalid = self.model.goal_ids[g]
        name = f"goal:{goalid}"
        if name in self._witnesses:
            return self._witnesses[name]

        def check(result: RunResult) -> str:
            if any(e["event"] == "goal" and e.get("goalid") == goalid
                   and e.get("record") == "reached" for e in result.trace.events):
                return ""
            return f"the replay did not reach `{goalid}`"

        ways = sorted(self.found.reached[g], key=lambda r: r.times.min())
        witness: Witness | None = None
        for k, reach in enumerate(ways[:WAYS_TRIED]):
            t = reach.times.min()
            visits = trail(reach.record, t)
            visits.append(Visit(reach.to, t + reach.delay, reach.via))
            witness = self._replay(f"{name}#{k}", visits, f"goal `{goalid}` is reached", check,
                                   until=t + reach.delay)
            if witness.confirmed:
                break
        assert witness is not None
        witness.name = name
        self._witnesses[name] = witness
        return witness

    def asked(self, name: str) -> Witness:
        """The witness asked with `--witness NAME`."""
        if name in ("fastest", "slowest"):
            t = self.min if name == "fastest" else self.max
            if t is None:
                what = "ends" if name == "fastest" else "ends at a greatest time"
                return Witness(name, [], Built(ok=False, why=f"no run {what}"), "",
                               why=f"no run {what}")
            return self._end_witness(name, t)
        if name in self.model.goal_ids:
            g = self.model.goal_ids.index(name)
            if g in self.found.reached:
                return self._goal_witness(g)
            return Witness(f"goal:{name}", [], Built(ok=False), "",
                           why=f"no world reaches `{name}`")
        raise ValueError(f"unknown witness {name!r}")

    def _duration(self) -> Finding:
        if self.min is None:
            if self.unbounded:
                return Finding("duration", PROVED, "no run ends: the session lasts forever in "
                               "every world")
            return self._incomplete("duration", "no run was found that ends")
        fastest = self._end_witness("fastest", self.min)
        notes = []
        exact_min = fastest.confirmed
        if not exact_min:
            notes.append(f"the fastest run, {self.min} ms, was not confirmed: {fastest.why}")
        if self.unbounded:
            status = PROVED if exact_min and self.stall is not None else UNKNOWN
            return Finding("duration", status, f"from {self.min} ms, without end (a run can "
                           "wait forever: no-stall)", notes=notes)
        if self.max is None:
            return Finding("duration", UNKNOWN, f"at least {self.min} ms; the greatest is not "
                           f"known: the exploration stopped ({self.found.bound})", notes=notes)
        slowest = self._end_witness("slowest", self.max)
        if not slowest.confirmed:
            notes.append(f"the slowest run, {self.max} ms, was not confirmed: {slowest.why}")
        status = PROVED if exact_min and slowest.confirmed else UNKNOWN
        span = (f"exactly {_ms(self.min)}" if self.min == self.max else
                f"between {_ms(self.min)} and {_ms(self.max)}")
        return Finding("duration", status, span, notes=notes)

    def _blocks(self) -> Finding:
        model, found = self.model, self.found
        missing = [s for s in model.steps if not found.known[s.index]]
        budget = BLOCK_REPLAYS
        # Blocks reached in the exploration but in no replay yet: the latest first.
        for step in sorted(model.steps, key=lambda s: -_max_or(found.known[s.index])):
            if not found.known[step.index] or step.address.path in self.confirmed_blocks:
                continue
            if budget == 0:
                break
            budget -= 1
            t = found.known[step.index].min()
            record = next(r for r in found.records[step.index] if t in r.times)
            visits = trail(record, t)
            path = step.address.path

            def check(result: RunResult, path: str = path) -> str:
                return "" if any(e.get("path") == path for e in result.trace.events) else \
                    f"the replay did not read `{path}`"

            self._replay(f"block:{path}", visits, f"block `{path}` is read", check, until=t)
        unconfirmed = [s for s in model.steps if found.known[s.index]
                       and s.address.path not in self.confirmed_blocks]
        whys = {s.index: self._why_unreached_block(s.index) for s in missing}
        notes = [f"block `{_name(s)}` is never read: {whys[s.index]}" for s in missing]
        span = missing[0].span if missing else None
        if missing and self.complete:
            # The blocks of a goal no run enters are said with their goal (`goals`).
            entered = {s.goal for s in model.steps if found.known[s.index]}
            items = [Item(s.span, f"no world leads the reader to the block `{_name(s)}`",
                          (whys[s.index],), s.address.path) for s in missing
                     if s.goal in entered]
            return Finding("blocks", VIOLATED, f"{len(missing)} of {len(model.steps)} blocks "
                           "are read in no world", span, notes, items=items)
        if missing or unconfirmed:
            what = []
            if missing:
                what.append(f"the exploration stopped ({found.bound}) before reading "
                            f"{len(missing)} blocks")
            if unconfirmed:
                what.append(f"{len(unconfirmed)} blocks reached were not confirmed by a replay")
            return Finding("blocks", UNKNOWN, "; ".join(what), span, notes)
        return Finding("blocks", PROVED, f"each of the {len(model.steps)} blocks is read in "
                       "some world")

    def _safety(self, unsafe: dict[int, list[str]]) -> Finding:
        reached = [(i, what) for i, what in sorted(unsafe.items()) if self.found.known[i]]
        if not reached:
            if unsafe and not self.complete:
                return self._incomplete("safety", "no block outside the profile was reached")
            extra = f" ({len(unsafe)} blocks outside it are never read)" if unsafe else ""
            return Finding("safety", PROVED, "every block a run reads keeps the robot within "
                           f"its profile{extra}")
        i, what = reached[0]
        step = self.model.steps[i]
        t = self.found.known[i].min()
        record = next(r for r in self.found.records[i] if t in r.times)
        visits = trail(record, t)
        until = t + step.length

        def check(result: RunResult) -> str:
            clamps = [e for e in result.trace.events if e["event"] == "governor"
                      and t <= int(e["t"]) <= until]
            return "" if clamps else "the governor did not intervene in the replay"

        witness = self._replay(f"safety:{step.address.path}", visits,
                               f"the governor intervenes in `{_name(step)}`", check,
                               until=until, governed=True)
        status = VIOLATED if witness.confirmed else UNKNOWN
        notes = [f"`{_name(self.model.steps[j])}`: {'; '.join(w)}" for j, w in reached]
        detail = f"a run reads `{_name(step)}`, which needs the governor: {what[0]}"
        if not witness.confirmed:
            detail += f" (not confirmed: {witness.why})"
        items = [Item(step.span, f"a run reads `{_name(step)}`, which the governor must "
                      "correct", tuple(what))]
        return Finding("safety", status, detail, step.span, notes, witness, items)

    # -- why a goal or block is never reached ---------------------------------------------------

    def _ways_in(self) -> dict[int, list[tuple[Step, bool | None, TimeSet]]]:
        """For each block, the moves that lead to it: the block they leave, the outcome,
        the instants it can be taken."""
        if self._ways is None:
            self._ways = {}
            for step in self.model.steps:
                if step.kind == JUMP:
                    outcomes = step.outcomes
                    assert outcomes is not None
                    self._ways.setdefault(step.on_true, []).append(
                        (step, True, outcomes.true_at))
                    self._ways.setdefault(step.on_false, []).append(
                        (step, False, outcomes.false_at))
                elif step.kind != "terminus":
                    self._ways.setdefault(step.next, []).append((step, None, TimeSet.all()))
        return self._ways

    def _why_unreached_block(self, index: int) -> str:
        """Why no run reads block `index`: for each way in (the block before it, a jump to
        it), why it is not taken."""
        known = self.found.known
        reasons = []
        for step, via, allowed in self._ways_in().get(index, ()):
            if not known[step.index]:
                continue  # unread itself: its own reason comes first
            at = known[step.index].describe()
            if via is None:
                reasons.append(f"`{_name(step)}` is read ({at}) but never goes on")
            else:
                word = "true" if via else "false"
                if allowed:
                    reasons.append(f"the jump `{_name(step)}` is read at {at} and is never "
                                   f"{word} then (it is {word} only at {allowed.describe()})")
                else:
                    reasons.append(f"the jump `{_name(step)}` is read at {at}, and its "
                                   f"condition is {word} in no world")
        if not reasons:
            if index == 0 or index - 1 not in {s.index for s, _, _ in
                                               self._ways_in().get(index, ())}:
                return "no jump leads to it, and the block before it never goes on to it"
            return "no block that leads to it is ever read"
        return "; ".join(reasons)

    def _why_unreached_goal(self, g: int) -> str:
        first = next((s for s in self.model.steps if s.goal == g), None)
        if first is None:
            return "it has no block"
        if self.found.known[first.index]:
            return "its blocks are read, but no run leaves it forward or ends in it"
        return self._why_unreached_block(first.index)


def _name(step: Step) -> str:
    """A block as messages name it: its label, else its path."""
    return step.label or step.address.path


def _on_cycles(succ: dict[int, list[int]]) -> set[int]:
    """The nodes of `succ` (a graph) that lie on a cycle: those of its strongly connected
    components with more than one node or a move to themselves (lint's Tarjan, F002's)."""
    from scriptc.check.flow import strongly_connected

    nodes = sorted(set(succ) | {b for bs in succ.values() for b in bs})
    index = {v: k for k, v in enumerate(nodes)}
    dense = [tuple(index[b] for b in succ.get(v, ())) for v in nodes]
    out: set[int] = set()
    for component in strongly_connected(list(range(len(nodes))), dense,
                                        [True] * len(nodes)):
        if len(component) > 1 or component[0] in dense[component[0]]:
            out.update(nodes[k] for k in component)
    return out


def _some(names: Sequence[str], shown: int = 5) -> str:
    """Names in backquotes, the first `shown` of them and how many more."""
    out = ", ".join(f"`{n}`" for n in names[:shown])
    return out + (f" and {len(names) - shown} more" if len(names) > shown else "")


def _ms(t: int) -> str:
    return f"{t} ms ({t / 1000:g} s)" if t >= 1000 else f"{t} ms"


def _latest(reaches: Sequence[Reach]) -> int | None:
    times = [r.times.max() for r in reaches]
    finite = [t for t in times if t is not None]
    return max(finite) if finite else None


def _max_or(times: TimeSet) -> int:
    if not times:
        return -1
    top = times.max()
    return top if top is not None else times.min()

