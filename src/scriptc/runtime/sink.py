"""The read callbacks: what an executor reports while it reads the running script's blocks
(`executor.ReadSink`), turned into the map's script info, goal records and the trace.

- `visit(position)`: the script info says where the reader is (`goal`, `action`, `blockid`,
  `path`, `goalid`), and the goal records follow it (`goals.Goals.visit`);
- `jump(...)`: a `jump` event with the condition's canonical text, its value, the bindings it
  made or kept, and where it goes (null: past the end);
- `sensor(...)`: a `sensor` event with the block's payload.

Events are written at the instant under way (`RunStatus.now`) in the running script's name
(`start` at each load).
"""

from __future__ import annotations

from scriptc.runtime.commands import BlockAddress
from scriptc.runtime.evaluate import Evaluation
from scriptc.runtime.executor import Executor
from scriptc.runtime.goals import Goals
from scriptc.runtime.status import RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import World


class ReaderSink:
    """The session's `ReadSink` (see the module's docstring)."""

    __slots__ = ("goal_ids", "goals", "script", "status", "trace", "world")

    def __init__(self, world: World, goals: Goals, trace: Trace, status: RunStatus) -> None:
        self.world = world
        self.goals = goals
        self.trace = trace
        self.status = status
        self.script = ""
        self.goal_ids: tuple[str, ...] = ()

    def start(self, executor: Executor) -> None:
        """The running script from now on."""
        self.script = executor.name
        self.goal_ids = executor.goal_ids

    def visit(self, position: BlockAddress) -> None:
        info = self.world.script
        info.goal, info.action, info.blockid = position
        info.path = position.path
        if position.goal < len(self.goal_ids):
            info.goalid = self.goal_ids[position.goal]
        self.goals.visit(position.goal)

    def jump(self, position: BlockAddress, condition: str, evaluation: Evaluation,
             target: BlockAddress | None) -> None:
        self.trace.emit(self.status.now, "jump", script=self.script,
                        path=position.path, condition=condition, value=evaluation.value,
                        bindings=evaluation.bindings,
                        target=target.path if target is not None else None)

    def sensor(self, position: BlockAddress, payload: tuple[str, ...]) -> None:
        self.trace.emit(self.status.now, "sensor", script=self.script,
                        path=position.path, payload=list(payload))
