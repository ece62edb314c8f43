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

What no cycle covers is followed turn by turn (two loops whose lengths differ, turning into each
other without end), up to the exploration's bound (`max_records`), past which the answer is
`unknown`.
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from scriptc.verify.conditions import ALWAYS
from scriptc.verify.model import INSTRUCTION, JUMP, SENSOR, TERMINUS, Model
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
    outcome; None otherwise), to block `to`, possible at the instants `allowed` of `node`."""

    node: int
    to: int
    via: bool | None
    delay: int
    allowed: TimeSet


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
    """Instants newly known at one block (`node`; ENDED for the script's end): `base` those
    its `sources` brought, `times` those and the turns of the `loops` taken from them (each a
    cycle and how many turns, None: without end). `ended` is "terminus" or "past_end" for an
    end record."""

    node: int
    times: TimeSet
    base: TimeSet
    sources: list[Source]
    serial: int
    ended: str = ""
    loops: list[tuple[Cycle, int | None]] = field(default_factory=list)


@dataclass(frozen=True, slots=True)
class Visit:
    """One block a run reads (`node`; ENDED at its end), at `t`, entered by `via`."""

    node: int
    t: int
    via: bool | None


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

    `known[i]` is every instant the reader arrives at block `i`; `records[i]` the records at
    block `i` in the order made; `ends` the end records; `zero_edges` every move between two
    blocks that takes no time, with the instants it happens at (the material of a cycle that
    lets no time pass); `reached[g]` how goal `g` is reached (left forward, or the script ends
    in it). `complete` is False when a bound stopped it (`bound` says which)."""

    model: Model
    known: list[TimeSet]
    records: list[list[Record]]
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


def moves(model: Model, i: int) -> list[Move]:
    """The moves of the reader from block `i` (to `model.end`: past the last block)."""
    step = model.steps[i]
    if step.kind == INSTRUCTION:
        return [Move(i, step.next, None, step.length, ALWAYS)]
    if step.kind == JUMP:
        outcomes = step.outcomes
        assert outcomes is not None
        return [Move(i, step.on_true, True, 0, outcomes.true_at),
                Move(i, step.on_false, False, 0, outcomes.false_at)]
    if step.kind == SENSOR:
        return [Move(i, step.next, None, 0, ALWAYS)]
    assert step.kind == TERMINUS
    return []


def cycles(model: Model) -> dict[int, list[Cycle]]:
    """The cycles of the script that take time, by head (see the module's docstring): a head
    is a block a later block moves back to; its cycles are the simple paths from it back to
    it through blocks after it that can lead back to it (at most MAX_CYCLES, each of at most
    MAX_CYCLE_BLOCKS blocks)."""
    out_moves = [[m for m in moves(model, i) if m.allowed] for i in range(model.end)]
    into: dict[int, list[int]] = {}
    for i, ms in enumerate(out_moves):
        for m in ms:
            into.setdefault(m.to, []).append(i)
    heads = sorted({m.to for i, ms in enumerate(out_moves) for m in ms if m.to <= i})
    out: dict[int, list[Cycle]] = {}
    for head in heads:
        # The blocks after the head from which it can be reached again: a cycle goes through
        # these only.
        back = {head}
        stack = [head]
        while stack:
            for j in into.get(stack.pop(), ()):
                if j > head and j not in back:
                    back.add(j)
                    stack.append(j)
        found: list[Cycle] = []
        for path in _paths_back(out_moves, head, back):
            period = sum(m.delay for m in path)
            if period > 0:
                found.append(Cycle(head, path, period))
        if found:
            out[head] = found
    return out


def _paths_back(out_moves: list[list[Move]], head: int, back: set[int]
                ) -> Iterator[tuple[Move, ...]]:
    """Simple paths from `head` back to it through the blocks of `back`, depth first."""
    count = steps = 0
    stack: list[tuple[int, tuple[Move, ...], frozenset[int]]] = [(head, (), frozenset())]
    while stack and count < MAX_CYCLES and steps < MAX_CYCLE_BLOCKS * MAX_CYCLES * 8:
        node, path, seen = stack.pop()
        steps += 1
        if len(path) >= MAX_CYCLE_BLOCKS:
            continue
        for move in reversed(out_moves[node]):
            if move.to == head:
                count += 1
                yield (*path, move)
            elif move.to in back and move.to not in seen:
                stack.append((move.to, (*path, move), seen | {move.to}))


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
    loops = cycles(model)
    out_moves = [moves(model, i) for i in range(end)]
    pending: dict[int, tuple[TimeSet, list[Source]]] = {}
    heap: list[tuple[int, int]] = []
    serial = 0

    def arrive(to: int, times: TimeSet, source: Source | None) -> None:
        nonlocal serial
        if to >= end:  # past the last block: the script ends
            serial += 1
            record = Record(ENDED, times, times, [source] if source else [], serial,
                            "past_end")
            _ended(found, record)
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
        arrive(0, TimeSet.point(0), None)
    else:
        arrive(0, TimeSet.point(0), None)
    try:
        while heap:
            _, i = heapq.heappop(heap)
            entry = pending.pop(i, None)
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
            new = times - found.known[i]
            if not new:
                continue
            serial += 1
            found.count += 1
            record = Record(i, new, new, sources, serial)
            for cycle in loops.get(i, ()):
                turns = _turns(cycle, new)
                if turns is None or turns >= 2:
                    record.loops.append((cycle, turns))
                    record.times = record.times | new.repeat(cycle.period, turns)
                    found.accelerated += 1
            found.known[i] = found.known[i] | record.times
            found.records[i].append(record)
            step = model.steps[i]
            if step.kind == TERMINUS:
                serial += 1
                _ended(found, Record(ENDED, record.times, record.times,
                                     [Source(record, Move(i, ENDED, None, 0, ALWAYS))], serial,
                                     "terminus"))
                continue
            for move in out_moves[i]:
                at = record.times if move.allowed is ALWAYS else record.times & move.allowed
                if not at:
                    continue
                if move.delay == 0 and move.to < end:
                    key = (i, move.to)
                    found.zero_edges[key] = found.zero_edges.get(key, TimeSet.empty()) | at
                if move.to < end and model.steps[move.to].goal > step.goal:
                    # leaving a goal forward reaches it (runtime/goals.py)
                    found.reached.setdefault(step.goal, []).append(
                        Reach(record, at, move.to, move.via, move.delay))
                arrive(move.to, at.shift(move.delay) if move.delay else at,
                       Source(record, move))
    except TooComplex as exc:
        found.complete = False
        found.bound = str(exc)
    found.seconds = time.perf_counter() - started
    return found


def _ended(found: Exploration, record: Record) -> None:
    """An end record: the goal of the block read last is reached."""
    found.ends.append(record)
    for source in record.sources:
        last = source.parent
        found.reached.setdefault(found.model.steps[last.node].goal, []).append(
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
    """A run that arrives at `record`'s block at `t` (one of its instants): every block it
    reads, in order, from the first at 0 ms. Where several moves lead to the same instant,
    one from a block `prefer` likes is taken when there is one."""
    out: list[Visit] = []
    current: Record | None = record
    via: bool | None = None
    while current is not None:
        if current.node == ENDED:
            source = current.sources[0] if current.sources else None
            out.append(Visit(ENDED, t, source.move.via if source else None))
            if source is None:
                break
            t -= source.move.delay
            current = source.parent
            continue
        if t not in current.base:
            t = _unwind(current, t, out)
        source = _source(current, t, prefer)
        via = source.move.via if source is not None else None
        out.append(Visit(current.node, t, via))
        if source is None:
            break
        t -= source.move.delay
        current = source.parent
    out.reverse()
    return out


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
    raise AssertionError(f"{t} ms is not an instant of the record at block {record.node}")


def _source(record: Record, t: int, prefer: Callable[[int], bool] | None) -> Source | None:
    """A source of `record` that brings the instant `t` (None for the start)."""
    fallback = None
    for source in record.sources:
        before = t - source.move.delay
        if before in source.parent.times and before in source.move.allowed:
            if prefer is None or prefer(source.parent.node):
                return source
            fallback = fallback or source
    if fallback is None and record.sources:
        raise AssertionError(f"no move brings {t} ms to block {record.node}")
    return fallback
