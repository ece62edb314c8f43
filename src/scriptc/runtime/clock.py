"""Simulated time: one integer clock in milliseconds and a queue of future events.

Nothing in the runtime reads the wall clock (docs/runtime.md, "Time and the loop"). The
session jumps from one event to the next (a heap: each push and pop is O(log n), no
per-millisecond ticking), so a ten-minute activity costs what its events cost, not what its
minutes cost.

Events at the same millisecond are popped in a fixed order: by `prio` (the session's start,
track progress of the actuators, then the operator's timers, then operator events, then sensor
updates; see docs/runtime.md "The order of an instant"), then in the order they were pushed.
That order is what makes two runs of the same inputs identical. The session pops every event
due at a millisecond before it reads any block there.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import Any, TypeVar

# Priorities among events of the same millisecond (smaller first).
PRIO_START = -1  # the session's start: it makes 0 ms an instant even when nothing else is due
PRIO_TRACK = 0  # + track index 0..2 (move, led, audioout)
PRIO_OPERATOR_TIMER = 3
PRIO_OPERATOR = 4
PRIO_UPDATE = 5

# A handler returns False when its event turned out stale (cancelled): an instant where only
# stale events fell is not a loop (time does not even move there).
A = TypeVar("A")
Handler = Callable[[int, A], bool]

# An event's argument, as the queue holds it: whatever its handler takes (`push` checks the
# pair), of as many kinds as there are handlers.
EventArg = Any


class EventQueue:
    """Future events as `(time, prio, seq, handler, arg)`; `handler(time, arg)` runs when the
    event is popped and returns whether anything happened. Cancelling is the handler's
    business (a stale generation number in `arg` makes it return False at once), which keeps
    every operation O(log n)."""

    __slots__ = ("_heap", "_seq")

    def __init__(self) -> None:
        self._heap: list[tuple[int, int, int, Handler[EventArg], EventArg]] = []
        self._seq = 0

    def push(self, time: int, prio: int, handler: Handler[A], arg: A) -> None:
        self._seq += 1
        heapq.heappush(self._heap, (time, prio, self._seq, handler, arg))

    def next_time(self) -> int | None:
        """The time of the earliest event, or None when nothing is scheduled."""
        return self._heap[0][0] if self._heap else None

    def pop_due(self, time: int) -> tuple[Handler[EventArg], EventArg] | None:
        """The next event at `time` (None when the earliest is later or there is none)."""
        heap = self._heap
        if heap and heap[0][0] <= time:
            _t, _p, _s, handler, arg = heapq.heappop(heap)
            return handler, arg
        return None

    def __len__(self) -> int:
        return len(self._heap)
