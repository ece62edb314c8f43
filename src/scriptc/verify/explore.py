"""The exploration: every instant at which the block reader can arrive at each block, for
every world (docs/verify.md, "The method").

The robot's side is exact: an instruction block issued at `t` is consumed at `t + length`,
reading the next blocks takes no time, a jump decided by the clock goes where the clock says.
The world's side is free: a jump the world decides goes both ways. What is computed for each
block is a `TimeSet`, the exact set of instants the reader can arrive there, grown by a
worklist of *records*: each record is a set of instants newly known at one block, with the
record it came from (so a run to any instant can be written out again, `trail`).

A loop that waits is not unrolled: when a record comes back to a block it descends from after
`d` ms, the same path can be taken again and again for as long as every timed jump on it
keeps its outcome (each instant moves by `d` with every turn, and the clock's thresholds say
how many turns stay on the same side of every one of them): the turns are added at once
(`TimeSet.repeat`), one record, whatever the wait's length, and without end when no threshold
is ever crossed (a loop the world can keep going forever). This is exact: every instant added
is one a run reaches by that path.

Two loops that no instant distinguishes are not found this way (a loop with two paths of
different lengths): they are followed turn by turn, up to the exploration's bound
(`max_records`), past which the answer is `unknown`.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from scriptc.verify.model import INSTRUCTION, JUMP, SENSOR, TERMINUS, Model
from scriptc.verify.timeset import TimeSet, TooComplex

__all__ = ["ENDED", "Exploration", "Loop", "Reach", "Record", "Visit", "explore", "trail"]

ENDED = -1  # the node of a record that says when the script ends

# How far back a record's ancestors are searched for the same block (a loop's length).
LOOP_SEARCH = 200
# The default bound on records (each a set of instants at one block).
MAX_RECORDS = 2_000_000


@dataclass(slots=True, eq=False)
class Loop:
    """The turns of a loop added at once: `path` the records of one turn (the last at the
    block the loop comes back to), `period` its delay; the record's instants are those of the
    turn's last record moved by whole periods."""

    path: tuple[Record, ...]
    period: int


@dataclass(slots=True, eq=False)
class Record:
    """Instants newly known at one block (`node`; ENDED for the script's end) and how they
    were reached: from `parent`'s instants, `delay` ms later, by `via` (a jump's outcome,
    True or False; None after an instruction block, a sensor block or the start). `ended` is
    "terminus" or "past_end" for an end record; `loop` is set on the record of a loop's turns
    added at once (its parent is the turn they repeat)."""

    node: int
    times: TimeSet
    parent: Record | None
    via: bool | None
    delay: int
    serial: int
    ended: str = ""
    loop: Loop | None = None


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
    block `i` in the order found (breadth first); `ends` the end records; `zero_edges` every
    move between two blocks that takes no time, with the instants it happens at (the
    material of a cycle that lets no time pass); `reached[g]` the first record by which goal
    `g` is reached (left forward, or the script ends in it), `reached_at[g]` the instants.
    `complete` is False when a bound stopped it (`bound` says which)."""

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
    accelerated: int = 0  # loops whose turns were added at once

    def end_times(self) -> TimeSet:
        """Every instant at which the script can end."""
        out = TimeSet.empty()
        for record in self.ends:
            out = out | record.times
        return out


def explore(model: Model, *, max_records: int = MAX_RECORDS,
            interrupted: Callable[[], bool] | None = None,
            progress: Callable[[int], None] | None = None) -> Exploration:
    """Explore `model` from its first block at 0 ms (see the module's docstring).
    `interrupted()` is asked now and then: when it says yes, the exploration stops there,
    incomplete; `progress(count)` is told now and then how many records were made."""
    started = time.perf_counter()
    steps, end = model.steps, model.end
    found = Exploration(model, [TimeSet.empty() for _ in steps], [[] for _ in steps])
    queue: deque[Record] = deque()
    serial = 0

    def add(node: int, times: TimeSet, parent: Record | None, via: bool | None,
            delay: int, ended: str = "") -> None:
        nonlocal serial
        serial += 1
        queue.append(Record(node, times, parent, via, delay, serial, ended))

    if end == 0:  # no block: the script ends as it starts
        add(ENDED, TimeSet.point(0), None, None, 0, "past_end")
    else:
        add(0, TimeSet.point(0), None, None, 0)
    try:
        while queue:
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
            record = queue.popleft()
            found.count += 1
            if record.node == ENDED:
                found.ends.append(record)
                last = record.parent
                if last is not None:  # the goal the script ends in is reached
                    found.reached.setdefault(model.steps[last.node].goal, []).append(
                        Reach(last, record.times.shift(-record.delay), ENDED, record.via,
                              record.delay))
                continue
            i = record.node
            new = record.times - found.known[i]
            if not new:
                continue
            record.times = new
            record = _accelerate(found, record)
            found.known[i] = found.known[i] | record.times
            found.records[i].append(record)
            times = record.times
            step = steps[i]
            if step.kind == INSTRUCTION:
                _move(found, add, record, step.next, times.shift(step.length), None,
                      step.length)
            elif step.kind == JUMP:
                outcomes = step.outcomes
                assert outcomes is not None
                yes, no = times & outcomes.true_at, times & outcomes.false_at
                if yes:
                    _move(found, add, record, step.on_true, yes, True, 0)
                if no:
                    _move(found, add, record, step.on_false, no, False, 0)
            elif step.kind == TERMINUS:
                add(ENDED, times, record, None, 0, "terminus")
            else:
                assert step.kind == SENSOR
                _move(found, add, record, step.next, times, None, 0)
    except TooComplex as exc:
        found.complete = False
        found.bound = str(exc)
    found.seconds = time.perf_counter() - started
    return found


def _move(found: Exploration, add: Callable[..., None], record: Record, to: int,
          times: TimeSet, via: bool | None, delay: int) -> None:
    """The reader goes from `record`'s block to block `to` (past the end: the script ends)."""
    model = found.model
    if to >= model.end:
        add(ENDED, times, record, via, delay, "past_end")
        return
    if delay == 0:
        key = (record.node, to)
        found.zero_edges[key] = found.zero_edges.get(key, TimeSet.empty()) | times
    here, there = model.steps[record.node].goal, model.steps[to].goal
    if there > here:  # leaving a goal forward reaches it (runtime/goals.py)
        found.reached.setdefault(here, []).append(
            Reach(record, times.shift(-delay), to, via, delay))
    add(to, times, record, via, delay)


def _accelerate(found: Exploration, record: Record) -> Record:
    """`record` (its instants new at its block) with the turns of the loop it closes added at
    once, when it closes one and more than one turn keeps every timed jump's outcome (see the
    module's docstring); else `record` itself."""
    node, times = record.node, record.times
    path: list[Record] = []
    period = 0
    ancestor = record
    for _ in range(LOOP_SEARCH):
        period += ancestor.delay
        path.append(ancestor)
        parent = ancestor.parent
        if parent is None or parent.node == ENDED:
            return record
        if parent.node == node:
            ancestor = parent
            break
        ancestor = parent
    else:
        return record
    if period <= 0:
        return record  # a cycle that lets no time pass: `zero_edges` has it
    if any(r.loop is not None for r in path):
        return record  # a turn that holds another loop's turns has no one delay
    path.reverse()  # from the first block after the ancestor to `record`
    turns = _turns(found.model, path, times, period)
    if turns is not None and turns < 2:
        return record
    found.accelerated += 1
    more = times.repeat(period, turns)
    return Record(node, more, record, None, 0, record.serial, loop=Loop(tuple(path), period))


def _turns(model: Model, path: list[Record], times: TimeSet, period: int) -> int | None:
    """How many turns of the loop `path` (one turn, `period` ms) the instants `times` can take
    with every timed jump on it keeping the outcome it had; None: without end."""
    lo, hi = times.min(), times.max()
    turns: int | None = None
    offset = 0
    for record in path:
        jump = record.parent
        assert jump is not None
        step = model.steps[jump.node]
        if step.kind == JUMP and record.via is not None:
            outcomes = step.outcomes
            assert outcomes is not None
            allowed = outcomes.true_at if record.via else outcomes.false_at
            span = _interval_around(allowed, lo + offset, None if hi is None else hi + offset)
            if span is None:
                return 0
            last = span[1]
            if last is not None:
                if hi is None:
                    return 0
                k = (last - (hi + offset)) // period + 1
                turns = k if turns is None else min(turns, k)
        offset += record.delay
    return turns


def _interval_around(allowed: TimeSet, lo: int, hi: int | None) -> tuple[int, int | None] | None:
    """The run of consecutive instants of `allowed` that holds `lo` to `hi` (`hi` None: every
    instant from `lo`), as (first, last or None); None when no such run holds them all."""
    for start, step, count in allowed.pieces:
        last = None if count is None else start + step * (count - 1)
        if step != 1 and count != 1:
            continue
        if start <= lo and (last is None or (hi is not None and hi <= last)):
            return start, last
    return None


def trail(record: Record, t: int) -> list[Visit]:
    """A run that arrives at `record`'s block at `t` (one of its instants): every block it
    reads, in order, from the first at 0 ms."""
    out: list[Visit] = []
    current: Record | None = record
    while current is not None:
        loop = current.loop
        if loop is not None:
            base = current.parent
            assert base is not None
            turns = 0
            while t - turns * loop.period not in base.times:
                turns += 1
            # The turns, last first: each the loop's path ending at `t`, `t - period`, ...
            for k in range(turns):
                at = t - k * loop.period
                for step in reversed(loop.path):
                    out.append(Visit(step.node, at, step.via))
                    at -= step.delay
            t -= turns * loop.period
            current = base
            continue
        out.append(Visit(current.node, t, current.via))
        t -= current.delay
        current = current.parent
    out.reverse()
    return out
