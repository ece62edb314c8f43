"""The scripts of a session (thesis 3.2, 4.2 steps 6, 7 and 1; docs/runtime.md "The LIFO,
idle_activity and the end of a session", "The block reader"): the LIFO of queued scripts,
`idle_activity`, the programs a session knows by name or path, and the running script, from
its load to its unload, with its block reading.

- Loading a script starts a fresh executor at its first block, resets the map's script info,
  creates (or restarts) its Activity entity, sets `RobotStatus/startingtime`, issues its alfa
  messages (`mutex.Mutex.hand_over`) and asks for a read. Unloading stops its block, records
  its goal (`goals.Goals.leave`), issues its omega messages and ends every binding.
- Step 6 (`load_when_free`): the next script is loaded when none runs (the top of the LIFO;
  when the LIFO is empty, the session completes if told to stop then, else `idle_activity`
  runs); `idle_activity` is left at once when a real script is queued.
- Step 7 (`read`): when the block with the actuators is consumed (or none was issued yet),
  the executor reads up to the next instruction block (`sink.ReaderSink` hears what it meets);
  a script that ends is unloaded and the next one loaded, in the same step. A read that fails
  (a jump to no block, the read limit, a VM trap) is fatal (`read`).
- Step 1 (`issue`): the block read, or the one a rule changed, goes to the actuators.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

from scriptc.runtime.actuators import Actuators
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.evaluate import EvalContext
from scriptc.runtime.executor import End, Executor, Issue, Loadable, ReadLimit
from scriptc.runtime.goals import Goals
from scriptc.runtime.loading import Loader
from scriptc.runtime.mutex import Mutex
from scriptc.runtime.sink import ReaderSink
from scriptc.runtime.status import NO_PROGRESS, READ, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import World


@dataclass
class LoadRecord:
    """One load of a script, for the summary."""

    script: str
    path: str
    reason: str
    loaded_ms: int
    ended_ms: int | None = None
    ended_by: str | None = None
    goals: dict[str, str] = field(default_factory=dict)  # goal id -> last record
    reached: set[str] = field(default_factory=set)

    def as_dict(self) -> dict[str, object]:
        return {"script": self.script, "path": self.path, "reason": self.reason,
                "loaded_ms": self.loaded_ms, "ended_ms": self.ended_ms,
                "ended_by": self.ended_by, "goals": dict(self.goals)}


class Catalogue:
    """The programs a session knows, by activity name and by absolute path (the first of a
    name wins), and the loader of others by path (`loading.Loader`). Names that are not
    activity names are paths relative to `folder` (the scenario's; else the working folder)."""

    __slots__ = ("folder", "loader", "programs")

    def __init__(self, programs: Iterable[Loadable], folder: str | None = None,
                 loader: Loader | None = None) -> None:
        self.programs: dict[str, Loadable] = {}
        for program in programs:
            self.programs.setdefault(program.name, program)
            if program.path:
                self.programs.setdefault(os.path.abspath(program.path), program)
        self.folder = folder
        self.loader = loader

    def find(self, name: str) -> Loadable | None:
        """A program by activity name, by path, or loaded by path through the loader (which
        may raise `loading.LoadError`); None when none is found and there is no loader."""
        program = self.programs.get(name)
        if program is not None:
            return program
        base = self.folder if self.folder is not None else os.getcwd()
        path = os.path.abspath(os.path.join(base, name))
        program = self.programs.get(path)
        if program is not None or self.loader is None:
            return program
        program = self.loader(path)
        self.programs[path] = program
        return program


class Scripts:
    """The LIFO, `idle_activity` and the running script (see the module's docstring).

    `executor` and `program` are the running script's (None between two scripts); `loads`
    every load so far, the last one the running script's. `need_read`: the block with the
    actuators is consumed (or none was issued), so step 7 reads; `pending_issue`: a block was
    read and step 1 issues it."""

    __slots__ = (
        "actuators",
        "bindings",
        "catalogue",
        "ctx",
        "executor",
        "goals",
        "idle",
        "issued_label",
        "issued_path",
        "lifo",
        "loads",
        "max_loops",
        "mutex",
        "need_read",
        "pending_issue",
        "program",
        "sink",
        "status",
        "stop_when_done",
        "trace",
        "world",
    )

    def __init__(self, programs: Sequence[Loadable], idle: Loadable, catalogue: Catalogue, *,
                 stop_when_done: bool,
                 world: World, trace: Trace, status: RunStatus, goals: Goals, sink: ReaderSink,
                 mutex: Mutex, bindings: Bindings, actuators: Actuators, ctx: EvalContext,
                 max_loops: int) -> None:
        self.lifo: list[Loadable] = list(reversed(programs))  # the top is the last
        self.idle = idle
        self.catalogue = catalogue
        self.stop_when_done = stop_when_done
        self.world = world
        self.trace = trace
        self.status = status
        self.goals = goals
        self.sink = sink
        self.mutex = mutex
        self.bindings = bindings
        self.actuators = actuators
        self.ctx = ctx
        self.max_loops = max_loops
        self.executor: Executor | None = None
        self.program: Loadable | None = None
        self.loads: list[LoadRecord] = []
        self.need_read = False
        self.pending_issue = False
        self.issued_path = ""
        self.issued_label = ""

    def find(self, name: str) -> Loadable | None:
        """A program an override or `script_vect` names (see `Catalogue.find`)."""
        return self.catalogue.find(name)

    def queue(self, programs: list[Loadable]) -> None:
        """The LIFO becomes `programs`, in the order they will run."""
        self.lifo = list(reversed(programs))

    # -- loading and unloading ------------------------------------------------------------------

    def next(self, now: int) -> None:
        """Load the top of the LIFO; when it is empty, complete the session or run idle."""
        if self.lifo:
            self.load(now, self.lifo.pop(), "queue")
        elif self.stop_when_done:
            self.status.finish("completed")
        else:
            self.load(now, self.idle, "idle")

    def load(self, now: int, program: Loadable, reason: str) -> None:
        executor = program.executor()
        executor.start()
        self.executor = executor
        self.program = program
        name = executor.name
        record = LoadRecord(name, program.path, reason, now)
        self.loads.append(record)
        self.goals.begin(name, executor.goal_ids, record)
        self.sink.start(executor)
        world = self.world
        info = world.script
        info.currentactivity = name
        info.goal = info.action = info.blockid = -1
        info.goalid = info.path = ""
        info.block = None
        info.changed = False
        info.submove = info.subled = info.subaout = 0
        world.start_activity(name, now)
        world.robot.fields["startingtime"] = now
        world.robot.fields["elapsedtime"] = 0
        self.trace.emit(now, "script_load", script=name, path=program.path, reason=reason)
        self.mutex.hand_over(now, executor.alfa, "alfa", name)
        self.need_read = True
        self.pending_issue = False

    def unload(self, now: int, how: str) -> None:
        """Stop the running script (`how`: the `script_unload` reason); nothing if none runs."""
        executor = self.executor
        if executor is None:
            return
        if self.actuators.block_active:
            self.actuators.cancel(now)
        self.goals.leave(how)
        self.trace.emit(now, "script_unload", script=executor.name, reason=how)
        record = self.loads[-1]
        record.ended_ms, record.ended_by = now, how
        self.mutex.hand_over(now, executor.omega, "omega", executor.name)
        self.bindings.end_script()
        self.update_elapsed(now)
        info = self.world.script
        info.block = None
        info.override = None
        self.executor = None
        self.program = None
        self.goals.end()
        self.need_read = False
        self.pending_issue = False

    def update_elapsed(self, now: int) -> None:
        """The running script's Activity entity: its `elapsedtime` up to `now`."""
        if self.executor is not None:
            activity = self.world.entity("Activity", self.executor.name)
            if activity is not None:
                activity.fields["elapsedtime"] = now - activity.fields["startingtime"]

    # -- the loop's steps -----------------------------------------------------------------------

    def load_when_free(self, now: int) -> None:
        """Step 6: load the next script when none runs, or leave `idle_activity` when a real
        script is queued."""
        if self.executor is None:
            self.next(now)
        elif self.program is self.idle and self.lifo:
            self.unload(now, "idle_escape")
            self.next(now)

    def read(self, now: int) -> None:
        """Step 7: read until an instruction block; scripts that end are replaced."""
        status = self.status
        ended = 0
        while not status.done:
            if ended > self.max_loops:
                status.fatal(now, NO_PROGRESS,
                             f"{ended} scripts ended at {now} ms without time passing (an "
                             "idle_activity that ends at once?)")
                return
            executor = self.executor
            if executor is None:
                self.next(now)
                continue
            self.ctx.now = now
            try:
                result = executor.read(self.ctx, self.sink)
            except (ReadLimit, RuntimeError) as exc:
                status.fatal(now, READ, str(exc))
                return
            if isinstance(result, Issue):
                info = self.world.script
                info.block = result.instruction
                info.changed = False
                self.issued_path = result.position.path
                self.issued_label = result.label
                self.need_read = False
                self.pending_issue = True
                return
            assert isinstance(result, End)
            if result.how == "terminus" and result.position is not None:
                self.trace.emit(now, "terminus", script=executor.name,
                                path=result.position.path)
            self.unload(now, result.how)
            self.next(now)
            ended += 1

    def issue(self, now: int) -> None:
        """Step 1: issue the block to the actuators if it is new or a rule changed it."""
        info = self.world.script
        if (self.pending_issue or info.changed) and info.block is not None \
                and self.executor is not None:
            self.trace.emit(now, "block", script=self.executor.name, path=self.issued_path,
                            label=self.issued_label, changed=info.changed)
            self.pending_issue = False
            info.changed = False
            self.actuators.issue(now, info.block)

    def reread(self) -> None:
        """Drop the block read and read again (an override seeking in the running script)."""
        self.world.script.block = None
        self.pending_issue = False
        self.need_read = True

    def consumed(self, now: int) -> None:
        """The actuators' callback: the block is consumed, so the next step 7 reads."""
        if self.executor is not None:
            self.trace.emit(now, "block_done", script=self.executor.name,
                            path=self.issued_path)
        self.need_read = True
