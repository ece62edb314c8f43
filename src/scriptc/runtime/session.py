"""The session: the wiring of the runtime's jobs into one run of queued scripts in simulated
time (thesis 4.2; docs/runtime.md). Shared by every executor: it drives whatever `Executor` a
`Loadable` makes.

Each job has its module and a narrow interface; the session builds them over one map
(`World`), one set of bindings, one event queue, one trace and one robot, and hands each the
others it needs:

- `status.RunStatus`   the instant under way, the end and its outcome, the problems reported
- `loop.Loop`          the event loop: the instants and the order of each (steps 4-8, 1)
- `scripts.Scripts`    the LIFO, `idle_activity`, loading and unloading, block reading
- `sink.ReaderSink`    what an executor reports while reading (the `ReadSink`)
- `goals.Goals`        goal records and `goalreached`
- `mutex.Mutex`        the chain of rules: the alfa/omega hand-over, the lock, the chain pass;
                       rule bodies act through `mutex.RuleEffects` (a `rules.RuleHost`)
- `overrides.Overrides` compulsory switches and `Script/script_vect`
- `updates.Updates`    map updates posted and applied
- `operator.Operator`  the operator's joystick

A test or a model checker may build these jobs itself, with its own robot or sink, and drive
the same semantics; `Session` is the arrangement `scriptc run` uses.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from scriptc.runtime.actuators import Actuators
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.clock import EventQueue
from scriptc.runtime.evaluate import EvalContext
from scriptc.runtime.executor import Loadable
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS, Implementations
from scriptc.runtime.goals import Goals
from scriptc.runtime.loading import Loader, LoadError
from scriptc.runtime.loop import MAX_LOOPS_PER_INSTANT, Loop, Observation, RunResult
from scriptc.runtime.mutex import Mutex, RuleEffects
from scriptc.runtime.operator import Operator
from scriptc.runtime.overrides import Overrides
from scriptc.runtime.robots import Drive, Robot, make_robot
from scriptc.runtime.rules import STANDARD_RULES, RuleLibrary
from scriptc.runtime.scenario import Scenario
from scriptc.runtime.scripts import Catalogue, LoadRecord, Scripts
from scriptc.runtime.sink import ReaderSink
from scriptc.runtime.status import FUNCTION, RunStatus
from scriptc.runtime.trace import Trace
from scriptc.runtime.updates import Updates
from scriptc.runtime.world import World

if TYPE_CHECKING:  # imported when a run has them (below)
    from scriptc.robot.profile import Profile
    from scriptc.runtime.governor import Governor
    from scriptc.runtime.sensing import Sensing

__all__ = ["MAX_LOOPS_PER_INSTANT", "LoadError", "LoadRecord", "Observation", "RunResult",
           "Session"]


class Session:
    """A run of queued scripts (see the module's docstring).

    `programs` run in the order given (the LIFO holds them top first). `catalogue` adds
    programs that may be named by an override or a `script_vect` update without being
    queued; `loader(path) -> Loadable` loads others by path (raising LoadError:
    `scriptc.runtime.loading`). `idle` replaces
    the built-in `idle_activity`."""

    def __init__(self, programs: list[Loadable] | tuple[Loadable, ...] = (), *,
                 scenario: Scenario | None = None, robot: str | Robot = "kinematic",
                 functions: Implementations = STANDARD_IMPLEMENTATIONS,
                 rules: RuleLibrary = STANDARD_RULES, trace: Trace | None = None,
                 idle: Loadable | None = None, stop_when_done: bool = True,
                 catalogue: list[Loadable] | tuple[Loadable, ...] = (),
                 loader: Loader | None = None,
                 max_loops_per_instant: int = MAX_LOOPS_PER_INSTANT,
                 profile: Profile | None = None) -> None:
        self.programs = list(programs)
        self.scenario = scenario
        self.world = world = World()
        self.bindings = bindings = Bindings()
        self.queue = queue = EventQueue()
        self.trace = trace = trace if trace is not None else Trace()
        backend = make_robot(robot) if isinstance(robot, str) else robot
        self.robot: Drive = backend
        # The safety governor (runtime/governor.py) when a robot profile is given, and the
        # simulated sensing of the scenario's placed entities (runtime/sensing.py).
        self.governor: Governor | None = None
        if profile is not None:
            from scriptc.runtime.governor import Governor

            self.robot = self.governor = Governor(backend, profile, trace)
        self.sensing: Sensing | None = None
        if scenario is not None and scenario.entities:
            from scriptc.runtime.sensing import Sensing

            self.sensing = Sensing(scenario.entities, scenario.sensing_rate_hz,
                                   scenario.sensing_range)
            if self.governor is not None:
                self.governor.nearest = self.sensing.nearest_human
        self.actuators = actuators = Actuators(queue, self.robot, trace, world)
        self.status = status = RunStatus(trace, on_fatal=actuators.cancel)
        self.goals = goals = Goals(world, trace, status)
        self.functions = functions
        self.ctx = ctx = EvalContext(
            world, bindings, functions, goals=goals,
            on_error=lambda message: status.report(status.now, FUNCTION, message))
        self.updates = updates = Updates(world, trace, status)
        self.mutex = mutex = Mutex(rules, trace, status, ctx, actuators,
                                   RuleEffects(world, bindings, trace, goals, updates))
        if idle is None:
            from scriptc.runtime.idle import idle_program

            idle = idle_program()
        self.sink = sink = ReaderSink(world, goals, trace, status)
        known = Catalogue((*catalogue, *self.programs, idle),
                          scenario.folder if scenario is not None else None, loader)
        self.scripts = scripts = Scripts(
            self.programs, idle, known, stop_when_done=stop_when_done, world=world,
            trace=trace, status=status, goals=goals, sink=sink, mutex=mutex,
            bindings=bindings, actuators=actuators, ctx=ctx, max_loops=max_loops_per_instant)
        actuators.on_consumed = scripts.consumed
        self.overrides = overrides = Overrides(world, trace, status, scripts, goals, actuators)
        updates.on_script_vect = overrides.script_vect
        self.operator = Operator(trace, actuators, status)
        self.loop = Loop(status=status, trace=trace, queue=queue, robot=self.robot,
                         governor=self.governor, sensing=self.sensing, scenario=scenario,
                         world=world, bindings=bindings, actuators=actuators, scripts=scripts,
                         overrides=overrides, mutex=mutex, updates=updates,
                         operator=self.operator, script_names=[p.name for p in self.programs],
                         max_loops=max_loops_per_instant)
        governor = self.governor
        if governor is not None:
            from scriptc.runtime.governor import PRIO_WAKE

            # A held LED onset: the governor is woken when the flash window frees (an event
            # only runs that hold LEDs get; its handler is not a loop of the session).
            governor.wake = lambda t: queue.push(t, PRIO_WAKE, self.loop.on_wake, governor)

    def run(self, until: int | None = None, observe: Iterable[int] = ()) -> RunResult:
        """Run to the end (runtime/loop.py); `until` caps simulated time (ms); the state at
        each millisecond of `observe` the run reaches is in the result's `observations`."""
        return self.loop.run(until, observe)
