"""Goal records (docs/runtime.md "Goals"): `reached`, `interrupted`, `failed`, in the map
(`RobotStatus/goalreached`, `goalinterrupted`, `goalfailed`: `goalid`, `timestamp`,
`activity`), in the trace (`goal` events) and in the load's record for the summary; and
`goalreached(goalid)`, which conditions call.

What the block reader does decides the records: leaving a goal forward (into the next goal, or
a jump to a later one) reaches it (`visit`); a jump back records nothing (the goal will be
entered again); the goal a script ends in is reached (`leave("terminus" | "past_end")`), the
goal it is in when stopped from outside is interrupted (`leave` for any other reason, or
`interrupt` when an override seeks elsewhere in the same script). Rules record any kind
(`record`, with the rule's id as `by`), `failed` included: the reader cannot know failure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from scriptc.runtime.status import RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import World

if TYPE_CHECKING:
    from scriptc.runtime.scripts import LoadRecord

KINDS = ("reached", "interrupted", "failed")


class Goals:
    """The running script's goals: its name and goal ids, the goal it is in (`current`, an
    index; None until its first block is read), and its load's record."""

    __slots__ = ("current", "goal_ids", "load", "script", "status", "trace", "world")

    def __init__(self, world: World, trace: Trace, status: RunStatus) -> None:
        self.world = world
        self.trace = trace
        self.status = status
        self.script = ""
        self.goal_ids: tuple[str, ...] = ()
        self.current: int | None = None
        # The last load, kept after its script ends: `goalreached` and a rule's record refer
        # to it until the next script loads.
        self.load: LoadRecord | None = None

    def begin(self, script: str, goal_ids: tuple[str, ...], load: LoadRecord) -> None:
        """A script is loaded: no goal entered yet."""
        self.script = script
        self.goal_ids = goal_ids
        self.current = None
        self.load = load

    def end(self) -> None:
        """The script is unloaded (after `leave`): no script runs."""
        self.script = ""
        self.goal_ids = ()

    def visit(self, goal: int) -> None:
        """The block reader arrived at a block of goal `goal` (an index)."""
        current = self.current
        if current is None:
            self.current = goal
        elif goal != current:
            if goal > current:
                self.record("reached", self.goal_ids[current])
            self.current = goal

    def leave(self, how: str) -> None:
        """The script is unloaded (`how`: the `script_unload` reason): its goal is reached
        when the script ended on its own, interrupted otherwise."""
        current = self.current
        if current is not None and current < len(self.goal_ids):
            kind = "reached" if how in ("terminus", "past_end") else "interrupted"
            self.record(kind, self.goal_ids[current])

    def interrupt(self) -> None:
        """An override seeks elsewhere in the running script: its goal is interrupted, and the
        next block read enters a goal afresh."""
        if self.current is not None:
            self.record("interrupted", self.goal_ids[self.current])
        self.current = None

    def record(self, kind: str, goalid: str, by: str | None = None) -> None:
        """Record a goal (`reached`, `interrupted`, `failed`) in the map and the trace."""
        if kind not in KINDS:
            raise ValueError(f"a goal record is reached, interrupted or failed, not {kind!r}")
        now = self.status.now
        script = self.script
        self.world.robot.append("goal" + kind, {"goalid": goalid, "timestamp": now,
                                                "activity": script})
        fields = {"script": script, "goalid": goalid, "record": kind}
        if by:
            fields["by"] = by
        self.trace.emit(now, "goal", **fields)
        load = self.load
        if load is not None:
            load.goals[goalid] = kind
            if kind == "reached":
                load.reached.add(goalid)

    def reached(self, goalid: str) -> bool:
        """`goalreached(goalid)`: reached by the running script since it was loaded, or
        recorded as reached by a sensor (a MapUpdate without `activity`) since then."""
        load = self.load
        if load is None:
            return False
        if goalid in load.reached:
            return True
        for record in self.world.goal_records("goalreached"):
            if (record.get("goalid") == goalid and "activity" not in record
                    and record.get("timestamp", 0) >= load.loaded_ms):
                return True
        return False
