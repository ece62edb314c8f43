"""The exploration: every instant at which the block reader can arrive at each block, for
every world (docs/verify.md, "The method").

The robot's side is exact: an instruction block issued at `t` is consumed at `t + length`,
reading the next blocks takes no time, a jump decided by the clock goes where the clock says.
The world's side is free: a jump the world decides goes both ways. What is computed for each
block is a `TimeSet`, the exact set of instants the reader can arrive there. It grows by
*records*: a record is a set of instants newly known at one block, made from the moves that
led there (its *sources*, each from an earlier record), so that a run to any instant can be
written out again (`trail`). Blocks are taken earliest instant first, and what arrives at a
block before it is taken is merged into one record.

A loop that waits is not unrolled. The cycles of the script are found once (`cycles`): from a
loop's head (a block some later block jumps back to), each path that comes back to it, with
its length in ms and the timed jumps on it. When a record is made at a head, each cycle is
taken as many turns as every timed jump on it keeps the outcome the cycle needs (each turn
moves every instant by the cycle's length, and the clock's thresholds say how many turns stay
on the same side of every one of them): the turns are added at once (`TimeSet.repeat`),
whatever the wait's length, and without end when no threshold is ever crossed (a loop the world
can keep going forever). This is exact: every instant added is one a run reaches by that path.

Override rules (`model.Switch`) make the exploration's states blocks *and* the switches that
have fired: a switch fires once, at any instant its condition allows while the reader is at an
instruction block (the chain passes at every instant, and the world can make one at any
millisecond), and the reader goes on at its target block; a switch whose condition the world
has no part in must fire as soon as it can, so the block is not finished then. A state is one
int, `fired * blocks + block`.

What no cycle covers is followed turn by turn (two loops whose lengths differ, turning into each
other without end), up to the exploration's bound (`max_records`), past which the answer is
`unknown`.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from scriptc.verify.conditions import ALWAYS, Outcomes
from scriptc.verify.model import ENDS, INSTRUCTION, JUMP, SENSOR, TERMINUS, Model, Step
from scriptc.verify.timeset import TimeSet, TooComplex

__all__ = ["ENDED", "Cycle", "Exploration", "Reach", "Record", "Source", "Visit", "cycles",
           "explore", "trail"]

ENDED = -1  # the node of a record that says when the script ends

# The default bound on records (each a set of instants at one block).
MAX_RECORDS = 2_000_000
# Cycles looked for from one head, and their greatest length in blocks.
MAX_CYCLES = 8
MAX_CYCLE_BLOCKS = 64


@dataclass(frozen=True, slots=True)
class Move:
    """One move of the reader: from block `node`, `delay` ms later, by `via` (a jump's
    outcome; None otherwise), to block `to`, possible at the instants `allowed` of `node`.
    A switch's move (`switch`, its bit) happens from an arrival at `node` that `gate` holds,
    at any instant from `delay` to `delay + spread` ms after it that `allowed` holds, and goes
    to `to` (ENDED: the run ends)."""

    node: int
    to: int
    via: bool | None
    delay: int
    allowed: TimeSet
    spread: int = 0
    switch: int = -1
    gate: TimeSet = ALWAYS
    values: int = -1  # the valuation after it (-1: the same as before)

    def valuation_after(self, before: int) -> int:
        """The number of the valuation after the move, from `before`."""
        return before if self.values < 0 else self.values


@dataclass(frozen=True, slots=True)
class Cycle:
    """A path from a loop's head back to it: its moves in order and its length (`period`,
    ms)."""

    head: int
    moves: tuple[Move, ...]
    period: int


@dataclass(slots=True, eq=False)
class Source:
    """A move that brought instants to a record: from `parent`'s instants, by `move`."""

    parent: Record
    move: Move


@dataclass(slots=True, eq=False)
class Record:
    """Instants newly known at one state (`node`: a block and the switches fired; ENDED for the
    script's end; `block` is the block): `base` those its `sources` brought, `times` those
    and the turns of the `loops` taken from them (each a
    cycle and how many turns, None: without end). `ended` is "terminus" or "past_end" for an
    end record."""

    node: int
    times: TimeSet
    base: TimeSet
    sources: list[Source]
    serial: int
    ended: str = ""
    loops: list[tuple[Cycle, int | None]] = field(default_factory=list)
    block: int = ENDED


@dataclass(frozen=True, slots=True)
class Visit:
    """One block a run reads (`node`; ENDED at its end), at `t`, entered by `via`, or by the
    switch of bit `switch` firing at `t`."""

    node: int
    t: int
    via: bool | None
    switch: int = -1


@dataclass(frozen=True, slots=True)
class Reach:
    """A goal reached: by leaving `record`'s block at its instants `times`, `delay` ms after
    them, for block `to` (ENDED: the script ends there), by `via`."""

    record: Record
    times: TimeSet
    to: int
    via: bool | None
    delay: int


@dataclass
class Exploration:
    """What the exploration found (see the module's docstring).

    `known[i]` is every instant the reader arrives at block `i`, whatever has fired;
    `records[i]` the records at block `i` in the order made; `states` and `by_state` the
    same for each state; `ends` the end records; `zero_edges` every move between two states
    that takes no time, with the instants it happens at (the material of a cycle that lets no
    time pass); `reached[g]` how goal `g` is reached (left forward, or the script ends in
    it). `complete` is False when a bound stopped it (`bound` says which)."""

    model: Model
    known: list[TimeSet]
    records: list[list[Record]]
    states: dict[int, TimeSet] = field(default_factory=dict)
    by_state: dict[int, list[Record]] = field(default_factory=dict)
    ends: list[Record] = field(default_factory=list)
    zero_edges: dict[tuple[int, int], TimeSet] = field(default_factory=dict)
    reached: dict[int, list[Reach]] = field(default_factory=dict)
    complete: bool = True
    bound: str = ""
    count: int = 0  # records made
    seconds: float = 0.0
    accelerated: int = 0  # cycles whose turns were added at once

    def end_times(self) -> TimeSet:
        """Every instant at which the script can end."""
        out = TimeSet.empty()
        for record in self.ends:
            out = out | record.times
        return out


def moves(model: Model, i: int, fired: int = 0, valuation: int = 0) -> list[Move]:
    """The moves of the reader from block `i` (to `model.end`: past the last block) when the
    switches of the bits `fired` have fired and the tracked variables hold the valuation
    numbered `valuation`: the block's own, and from an instruction block each switch that may
    still fire."""
    step = model.steps[i]
    if step.kind == JUMP:
        return [Move(i, step.on_true if branch.outcome else step.on_false, branch.outcome, 0,
                     branch.at, values=after)
                for branch, after in model.branches(i, valuation)]
    if step.kind == SENSOR:
        return [Move(i, step.next, None, 0, ALWAYS)]
    if step.kind == TERMINUS:
        return []
    assert step.kind == INSTRUCTION
    cleared = model.cleared(valuation)  # the reader's step ends: its L and T variables go
    out: list[Move] = []
    finished = ALWAYS
    for switch in model.switches:
        if fired >> switch.bit & 1:
            continue
        to = ENDED if switch.target == ENDS else switch.target
        out += _switch_moves(step, switch.when, switch.bit, to, cleared)
        if not switch.when.world:
            # Nothing of the world holds it back: at an instant of the block where it holds,
            # the chain fires it, and the block is not finished from that arrival.
            for o in step.instants:
                finished = finished & _earlier(switch.when.false_at, o)
    out.insert(0, Move(i, step.next, None, step.length, finished, values=cleared))
    return out


def _earlier(times: TimeSet, offset: int) -> TimeSet:
    """The arrivals `t` with `t + offset` in `times`."""
    return times.clip(offset, None).shift(-offset) if offset else times


def _switch_moves(step: Step, when: Outcomes, bit: int, to: int, values: int) -> list[Move]:
    """The moves of a switch from the instruction block `step` (see `moves`): the world can
    make an instant of the run at any millisecond, so the switch fires at any instant of the
    block its condition allows, unless the condition is decided without the world: then it
    fires no later than the block's own first instant where it holds. One move per stretch
    between two of the block's instants (the first: the issue itself): from an arrival at
    which the condition was false at every earlier instant of the block, at any instant of
    the stretch it holds."""
    i, length = step.index, step.length
    if when.world:
        return [Move(i, to, None, 0, when.true_at, max(length - 1, 0), bit, values=values)]
    out: list[Move] = []
    gate = ALWAYS
    bounds = [*step.instants, max(length - 1, 0)]
    for k, o in enumerate(step.instants):
        if k == 0:
            out.append(Move(i, to, None, 0, when.true_at, 0, bit, gate, values))
        else:
            start = step.instants[k - 1] + 1
            out.append(Move(i, to, None, start, when.true_at, o - start, bit, gate, values))
        gate = gate & _earlier(when.false_at, o)
    last = step.instants[-1]
    if bounds[-1] > last:  # after the last instant, before the end: only the world's instants
        out.append(Move(i, to, None, last + 1, when.true_at, bounds[-1] - last - 1, bit, gate,
                        values))
    return out


def cycles(model: Model, fired: int = 0, valuation: int = 0) -> dict[int, list[Cycle]]:
    """The cycles of the script that take time, by head, in the state of the switches `fired`
    and the valuation numbered `valuation` (see the module's docstring): a head is a block a
    later block can move back to; its cycles are the simple paths from it back to it, in the
    same valuation, through blocks after it that can lead back to it (at most MAX_CYCLES,
    each of at most MAX_CYCLE_BLOCKS blocks). A switch's move is on no cycle: a switch fires
    once."""
    into: dict[int, list[int]] = {}
    heads: set[int] = set()
    for step in model.steps:
        targets = ((step.on_true, step.on_false) if step.kind == JUMP else
                   () if step.kind == TERMINUS else (step.next,))
        for to in targets:
            into.setdefault(to, []).append(step.index)
            if to <= step.index:
                heads.add(to)
    cache: dict[tuple[int, int], list[Move]] = {}

    def ways(block: int, values: int) -> list[Move]:
        found = cache.get((block, values))
        if found is None:
            found = cache[(block, values)] = [
                m for m in moves(model, block, fired, values) if m.allowed and m.switch < 0]
        return found

    out: dict[int, list[Cycle]] = {}
    for head in sorted(heads):
        # The blocks after the head from which it can be reached again, whatever the values:
        # a cycle goes through these only.
        back = {head}
        stack = [head]
        while stack:
            for j in into.get(stack.pop(), ()):
                if j > head and j not in back:
                    back.add(j)
                    stack.append(j)
        found: list[Cycle] = []
        for path in _paths_back(ways, head, valuation, back):
            period = sum(m.delay for m in path)
            if period > 0:
                found.append(Cycle(head, path, period))
        if found:
            out[head] = found
    return out


def _paths_back(ways: Callable[[int, int], list[Move]], head: int, valuation: int,
                back: set[int]) -> Iterator[tuple[Move, ...]]:
    """Simple paths from `head` back to it in the same valuation, through the blocks of
    `back`, depth first."""
    count = steps = 0
    stack: list[tuple[int, int, tuple[Move, ...], frozenset[tuple[int, int]]]] = [
        (head, valuation, (), frozenset())]
    while stack and count < MAX_CYCLES and steps < MAX_CYCLE_BLOCKS * MAX_CYCLES * 8:
        node, values, path, seen = stack.pop()
        steps += 1
        if len(path) >= MAX_CYCLE_BLOCKS:
            continue
        for move in reversed(ways(node, values)):
            after = move.valuation_after(values)
            if move.to == head:
                if after == valuation:
                    count += 1
                    yield (*path, move)
            elif move.to in back and (move.to, after) not in seen:
                stack.append((move.to, after, (*path, move), seen | {(move.to, after)}))


def explore(model: Model, *, max_records: int = MAX_RECORDS,
            interrupted: Callable[[], bool] | None = None,
            progress: Callable[[int], None] | None = None) -> Exploration:
    """Explore `model` from its first block at 0 ms (see the module's docstring).
    `interrupted()` is asked now and then: when it says yes, the exploration stops there,
    incomplete; `progress(count)` is told now and then how many records were made."""
    started = time.perf_counter()
    end = model.end
    found = Exploration(model, [TimeSet.empty() for _ in model.steps],
                        [[] for _ in model.steps])
    loops: dict[tuple[int, int], dict[int, list[Cycle]]] = {}  # state -> head -> cycles
    width = 1 << len(model.switches)  # the sets of switches fired

    def state(valuation: int, fired: int, block: int) -> int:
        """A state's number: block x switches fired x valuation (decoded with divmod)."""
        return (valuation * width + fired) * end + block

    out_moves: dict[int, list[Move]] = {}  # state -> moves
    pending: dict[int, tuple[TimeSet, list[Source]]] = {}
    heap: list[tuple[int, int]] = []
    serial = 0

    def arrive(to: int, times: TimeSet, source: Source | None, ended: str = "") -> None:
        nonlocal serial
        if ended:  # the script ends
            serial += 1
            _ended(found, Record(ENDED, times, times, [source] if source else [], serial,
                                 ended))
            return
        had = pending.get(to)
        if had is None:
            pending[to] = (times, [source] if source else [])
            heapq.heappush(heap, (times.min(), to))
        else:
            merged = had[0] | times
            if source is not None:
                had[1].append(source)
            pending[to] = (merged, had[1])
            if times.min() < had[0].min():
                heapq.heappush(heap, (times.min(), to))

    if end == 0:  # no block: the script ends as it starts
        arrive(ENDED, TimeSet.point(0), None, "past_end")
    else:
        arrive(0, TimeSet.point(0), None)
    try:
        while heap:
            _, node = heapq.heappop(heap)
            entry = pending.pop(node, None)
            if entry is None:
                continue  # taken already, at an earlier instant
            if found.count >= max_records:
                found.complete = False
                found.bound = f"{max_records:,} sets of instants explored"
                break
            if found.count % 1024 == 0:
                if interrupted is not None and interrupted():
                    found.complete = False
                    found.bound = "interrupted"
                    break
                if progress is not None:
                    progress(found.count)
            times, sources = entry
            rest, i = divmod(node, end)
            valuation, fired = divmod(rest, width)
            known = found.states.get(node, TimeSet.empty())
            new = times - known
            if not new:
                continue
            serial += 1
            found.count += 1
            record = Record(node, new, new, sources, serial, block=i)
            heads = loops.get((fired, valuation))
            if heads is None:
                heads = loops[(fired, valuation)] = cycles(model, fired, valuation)
            for cycle in heads.get(i, ()):
                turns = _turns(cycle, new)
                if turns is None or turns >= 2:
                    record.loops.append((cycle, turns))
                    record.times = record.times | new.repeat(cycle.period, turns)
                    found.accelerated += 1
            found.states[node] = known | record.times
            found.known[i] = found.known[i] | record.times
            found.by_state.setdefault(node, []).append(record)
            found.records[i].append(record)
            step = model.steps[i]
            if step.kind == TERMINUS:
                serial += 1
                _ended(found, Record(ENDED, record.times, record.times,
                                     [Source(record, Move(i, ENDED, None, 0, ALWAYS))], serial,
                                     "terminus"))
                continue
            ways = out_moves.get(node)
            if ways is None:
                ways = out_moves[node] = moves(model, i, fired, valuation)
            for move in ways:
                if move.switch >= 0:
                    gated = record.times if move.gate is ALWAYS else record.times & move.gate
                    if not gated:
                        continue
                    if move.delay:
                        gated = gated.shift(move.delay)
                    at = (gated.repeat(1, move.spread) if move.spread else gated) & move.allowed
                    if not at:
                        continue
                    if move.to == ENDED:
                        arrive(ENDED, at, Source(record, move), "override")
                    else:
                        arrive(state(move.valuation_after(valuation), fired | 1 << move.switch,
                                     move.to), at, Source(record, move))
                    continue
                at = record.times if move.allowed is ALWAYS else record.times & move.allowed
                if not at:
                    continue
                later = at.shift(move.delay) if move.delay else at
                if move.to >= end:
                    arrive(ENDED, later, Source(record, move), "past_end")
                    continue
                to = state(move.valuation_after(valuation), fired, move.to)
                if move.delay == 0:
                    key = (node, to)
                    found.zero_edges[key] = found.zero_edges.get(key, TimeSet.empty()) | at
                if model.steps[move.to].goal > step.goal:
                    # leaving a goal forward reaches it (runtime/goals.py)
                    found.reached.setdefault(step.goal, []).append(
                        Reach(record, at, move.to, move.via, move.delay))
                arrive(to, later, Source(record, move))
    except TooComplex as exc:
        found.complete = False
        found.bound = str(exc)
    found.seconds = time.perf_counter() - started
    return found


def _ended(found: Exploration, record: Record) -> None:
    """An end record: the goal of the block read last is reached when the script ends on
    its own (a terminus, past the last block), not when a switch to another script ends it
    (the runtime records the goal as interrupted)."""
    found.ends.append(record)
    if record.ended == "override":
        return
    for source in record.sources:
        last = source.parent
        found.reached.setdefault(found.model.steps[last.block].goal, []).append(
            Reach(last, record.times.shift(-source.move.delay), ENDED, source.move.via,
                  source.move.delay))


def _turns(cycle: Cycle, times: TimeSet) -> int | None:
    """How many turns of `cycle` the instants `times` at its head can take with every timed
    jump on it keeping the outcome the cycle needs; None: without end."""
    lo, hi = times.min(), times.max()
    turns: int | None = None
    offset = 0
    for move in cycle.moves:
        allowed = move.allowed
        if allowed is not ALWAYS:
            span = _interval_around(allowed, lo + offset, None if hi is None else hi + offset)
            if span is None:
                return 0
            last = span[1]
            if last is not None:
                if hi is None:
                    return 0
                k = (last - (hi + offset)) // cycle.period + 1
                turns = k if turns is None else min(turns, k)
        offset += move.delay
    return turns


def _interval_around(allowed: TimeSet, lo: int, hi: int | None) -> tuple[int, int | None] | None:
    """The run of consecutive instants of `allowed` that holds `lo` to `hi` (`hi` None: every
    instant from `lo`), as (first, last or None); None when no such run holds them all."""
    for start, step, count in allowed.pieces:
        if step != 1 and count != 1:
            continue
        last = None if count is None else start + count - 1
        if start <= lo and (last is None or (hi is not None and hi <= last)):
            return start, last
    return None


def trail(record: Record, t: int,
          prefer: Callable[[int], bool] | None = None) -> list[Visit]:
    """A run that arrives at `record`'s state at `t` (one of its instants): every block it
    reads, in order, from the first at 0 ms. Where several moves lead to the same instant,
    one from a block `prefer` likes is taken when there is one."""
    out: list[Visit] = []
    current: Record | None = record
    while current is not None:
        if current.node != ENDED and t not in current.base:
            t = _unwind(current, t, out)
        source = _source(current, t, prefer)
        move = source.move if source is not None else None
        out.append(Visit(current.block, t, move.via if move is not None else None,
                         move.switch if move is not None else -1))
        if source is None:
            break
        assert move is not None
        t = _before(source, t)
        current = source.parent
    out.reverse()
    return out


def _before(source: Source, t: int) -> int:
    """The instant at the source's record from which its move brings `t`."""
    move = source.move
    if move.switch >= 0:  # fired between `delay` and `delay + spread` ms after arriving there
        before = _fired_from(source, t)
        assert before is not None
        return before
    return t - move.delay


def _fired_from(source: Source, t: int) -> int | None:
    """An arrival at the source's record from which its switch can fire at `t`."""
    move = source.move
    if t not in move.allowed:
        return None
    times = source.parent.times
    at = times.last_at_most(t - move.delay)
    while at is not None and t - move.delay - at <= move.spread:
        if at in move.gate:
            return at
        at = times.last_at_most(at - 1) if at > 0 else None
    return None


def _unwind(record: Record, t: int, out: list[Visit]) -> int:
    """`t` came by turns of one of `record`'s loops: write those turns (last first) and
    return the instant at the head they started from."""
    for cycle, turns in record.loops:
        j = 1
        while turns is None or j <= turns:
            if t - j * cycle.period < record.base.min():
                break
            if t - j * cycle.period in record.base:
                for k in range(j):
                    at = t - k * cycle.period
                    for move in reversed(cycle.moves):
                        out.append(Visit(move.to, at, move.via))
                        at -= move.delay
                return t - j * cycle.period
            j += 1
    raise AssertionError(f"{t} ms is not an instant of the record at block {record.block}")


def _source(record: Record, t: int, prefer: Callable[[int], bool] | None) -> Source | None:
    """A source of `record` that brings the instant `t` (None for the start)."""
    fallback = None
    for source in record.sources:
        move = source.move
        if move.switch >= 0:
            ok = _fired_from(source, t) is not None
        else:
            before = t - move.delay
            ok = before in source.parent.times and before in move.allowed
        if ok:
            if prefer is None or prefer(source.parent.block):
                return source
            fallback = fallback or source
    if fallback is None and record.sources:
        raise AssertionError(f"no move brings {t} ms to block {record.block}")
    return fallback
