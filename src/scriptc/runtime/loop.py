"""The event loop: the instants of a session in simulated time, each in the same order
(thesis 4.2; docs/runtime.md "Time and the loop" and "The order of an instant").

An instant is a millisecond at which something is due (and 0 ms, the session's start). At
each one (`Loop._instants`): the physics is brought up to it, every event due at it is handled
(the actuators' tracks, the operator's timers and events, scenario updates and sensor
readings are posted, not yet applied), and only then does the loop run (`_iterate`), as many
times as there is something to do at that instant. So a jump read at `t` sees every update
that arrived at `t`, at 0 ms as at any other. One loop, at the instant `now`:

4. apply every pending map update (`updates.Updates.apply`);
5. apply a compulsory script switch a rule raised (`overrides.Overrides.apply`);
6. load the next script when none runs, or leave `idle_activity` if a real script is queued
   (`scripts.Scripts.load_when_free`);
7. if the block with the actuators is consumed (or none was issued yet), read blocks
   (`scripts.Scripts.read`); the block reader's `L` bindings end here;
8. pass the map through the chain of rules unless the mutex is locked
   (`mutex.Mutex.pass_chain`); `T` bindings end;
1. issue the block to the actuators if it is new or a rule changed it (`Scripts.issue`);
2. (the script info is published as it changes.)

Step 3, "wait for something to change", is the event queue: the loop jumps to the next event
and loops again at that instant until nothing more happens there (a rule's override, a block
consumed as it is issued, updates a rule posted); after `max_loops` loops at one instant the
session stops (`no-progress`). Nothing reads the wall clock. At the end of each instant the
outputs go to the robot: with the safety governor (a profile), it applies the instant's
velocity command then (its ramps, runtime/governor.py) and shows the LEDs its flash limit
allows; a held LED onset gets a wake-up event that is not an instant of the loop.

The session ends when every queued script has ended (`completed`), at `until`, when nothing
can happen any more (`stalled`: no event is scheduled and the wheels are still, as when the
operator froze the block; it ends at once, `until` or not), on a fatal error (`error`), or when
interrupted (`interrupted`: Ctrl-C under `scriptc.interrupt.catching()`, taken between two
instants or between two chunks of physics; the trace holds every instant before).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypedDict

from scriptc import interrupt
from scriptc.runtime.actuators import ZERO, Actuators
from scriptc.runtime.bindings import READER, Bindings
from scriptc.runtime.clock import PRIO_OPERATOR, PRIO_START, PRIO_UPDATE, EventQueue
from scriptc.runtime.mutex import Mutex
from scriptc.runtime.operator import Operator
from scriptc.runtime.overrides import Overrides
from scriptc.runtime.robots import Drive, Pose, RobotFailure, is_display, is_stepped
from scriptc.runtime.scenario import Scenario, TimedUpdate
from scriptc.runtime.scripts import LoadRecord, Scripts
from scriptc.runtime.status import NO_PROGRESS, ROBOT_UNSTABLE, RunStatus
from scriptc.runtime.trace import Event, Trace
from scriptc.runtime.updates import Updates
from scriptc.runtime.world import World, parse_update

if TYPE_CHECKING:  # made by the session only when a run has them (imported there lazily)
    from scriptc.runtime.governor import Governor
    from scriptc.runtime.sensing import Sensing

# Loops at one instant before the session gives up: a cycle of jumps and blocks that take no
# time, or rules that keep raising work, never let time pass.
MAX_LOOPS_PER_INSTANT = 10_000


@dataclass(frozen=True, slots=True)
class Observation:
    """The robot's outputs at one millisecond `t`, after everything that happens at it (a
    test's `at`; docs/runtime.md, "Observing a run"): where it is, the colour its LEDs show
    (None: off; with the governor, what the flash limit lets it show), the audio track that
    plays (None: none, or paused while the block is frozen), and the instruction block running
    (issued, not yet consumed: its `label`, "" for a block without one, its `path` and its
    `script`; all None when none runs)."""

    t: int
    pose: Pose
    led: tuple[float, float, float] | None
    audio: str | None
    block: str | None
    path: str | None
    script: str | None

    def as_dict(self) -> dict[str, object]:
        return {"t": self.t, "pose": self.pose.as_dict(),
                "led": None if self.led is None else list(self.led), "audio": self.audio,
                "block": self.block, "path": self.path, "script": self.script}


class GovernorSummary(TypedDict):
    """How many times the governor intervened (`governor` trace events), and how many of them
    for each reason, in the order first met (an event may have two: a speed clamped and
    ramped)."""

    clamps: int
    reasons: dict[str, int]


@dataclass
class RunResult:
    """What a run of a session gives (`scriptc run` prints it: runtime/summary.py)."""

    outcome: str  # "completed", "until", "stalled", "error" or "interrupted"
    time_ms: int
    pose: Pose
    loads: list[LoadRecord]
    errors: list[Event]
    events: int
    trace: Trace
    # With the governor: the millisecond the robot came to rest after the activity's end
    # (it brakes at the profile's accelerations; `pose` is where it stopped).
    at_rest_ms: int | None = None
    # With the governor: how many times it intervened (`governor` trace events), and how many
    # of them for each reason (an event may have two: a speed clamped and ramped).
    governor: GovernorSummary | None = None
    # The state at each millisecond `run` was asked to observe that the run reached, in time
    # order, and at the end (the robot at rest; None when interrupted).
    observations: list[Observation] = field(default_factory=list)
    final: Observation | None = None

    def as_dict(self) -> dict[str, object]:
        data: dict[str, object] = {
            "outcome": self.outcome,
            "time_ms": self.time_ms,
            "pose": self.pose.as_dict(),
            "scripts": [load.as_dict() for load in self.loads],
            "errors": [{k: v for k, v in e.items() if k != "event"} for e in self.errors],
            "events": self.events,
        }
        if self.at_rest_ms is not None:
            data["at_rest_ms"] = self.at_rest_ms
        if self.governor is not None:
            data["governor"] = self.governor
        return data


class Loop:
    """The instants and the order of each (see the module's docstring). It drives the jobs a
    session wires together; it holds no state of its own but the robot's outputs."""

    def __init__(self, *, status: RunStatus, trace: Trace, queue: EventQueue, robot: Drive,
                 governor: Governor | None, sensing: Sensing | None, scenario: Scenario | None,
                 world: World, bindings: Bindings,
                 actuators: Actuators, scripts: Scripts, overrides: Overrides, mutex: Mutex,
                 updates: Updates, operator: Operator, script_names: list[str],
                 max_loops: int = MAX_LOOPS_PER_INSTANT) -> None:
        self.status = status
        self.trace = trace
        self.queue = queue
        self.robot = robot
        self.governor = governor
        self.sensing = sensing
        self.scenario = scenario
        self.world = world
        self.bindings = bindings
        self.actuators = actuators
        self.scripts = scripts
        self.overrides = overrides
        self.mutex = mutex
        self.updates = updates
        self.operator = operator
        self.script_names = script_names
        self.max_loops = max_loops
        # A backend that shows the LEDs and the speaker (MuJoCo's model); the governor sees the
        # LEDs and applies its pending command at the end of every instant.
        self._display = robot if is_display(robot) else None
        self._show_outputs = self._display is not None or governor is not None
        # A backend that steps its physics (`stepped`: MuJoCo) is brought up to each instant
        # before the instant's events, where stepping can be interrupted and costs the same
        # steps as inside a handler; the kinematic robot is advanced where it is needed only
        # (its closed form would round differently if cut in more pieces).
        self._stepped = robot if is_stepped(robot) else None
        self._catch_up = self._stepped is not None
        # The milliseconds still to observe (latest first) and the states observed (`run`).
        self._probes: list[int] = []
        self._observed: list[Observation] = []

    def run(self, until: int | None = None, observe: Iterable[int] = ()) -> RunResult:
        """Run to the end (see the module's docstring); `until` caps simulated time (ms). The
        state at each millisecond of `observe` is recorded (`RunResult.observations`) when the
        run reaches it, after everything that happens at it; observing changes nothing of the
        run (the robot is looked ahead through a ghost, `Robot.ghost`)."""
        status, trace, queue, governor = self.status, self.trace, self.queue, self.governor
        self._probes = sorted(set(observe), reverse=True)
        self._observed = []
        governed: dict[str, object] = {}
        if governor is not None:  # the limits the governor keeps, as the trace's header
            governed["profile"] = governor.profile.limits()
        trace.emit(0, "session_start", scripts=self.script_names,
                   robot=getattr(self.robot, "name", type(self.robot).__name__),
                   until=until, scenario=self.scenario.path if self.scenario else None,
                   **governed)
        if self.scenario is not None:
            for tu in self.scenario.updates:
                queue.push(tu.at, PRIO_UPDATE, self._on_update, tu)
            for op in self.scenario.operator:
                queue.push(op.at, PRIO_OPERATOR, self.operator.on_event, op)
        if self.sensing is not None:
            queue.push(0, PRIO_UPDATE, self._on_sense, self.sensing)
        # The session's start makes 0 ms an instant like any other: its events are handled
        # first, then the loop loads the first script (step 6) and reads it.
        queue.push(0, PRIO_START, self._on_start, None)
        failed = False
        settled: dict[str, int] = {}
        try:
            try:
                self._instants(until)
            except RobotFailure as exc:
                status.fatal(status.now, ROBOT_UNSTABLE, str(exc))
                failed = True
            # The instants the run reached after its last one (to `until`, or the instant it
            # ended at), before the robot brakes.
            self._observe(status.now)
            try:
                self.robot.advance(status.now)
                if governor is not None and not failed:
                    # The activity is over, the robot may still be braking: the physics goes
                    # on until it is at rest, and the pose is where it stops (docs/robot.md).
                    settled["at_rest_ms"] = governor.come_to_rest(status.now)
            except RobotFailure:
                pass  # already reported, or the braking failed: the pose is the last one
        except interrupt.Interrupted:
            settled = {}
            self._interrupted()
        pose = self.robot.pose()
        trace.emit(status.now, "session_end", outcome=status.outcome, time_ms=status.now,
                   pose=pose.as_dict(), **settled)
        final = None if status.outcome == "interrupted" else self._state(status.now, pose)
        return RunResult(status.outcome, status.now, pose, self.scripts.loads, trace.errors,
                         trace.count, trace, settled.get("at_rest_ms"),
                         None if governor is None else
                         GovernorSummary(clamps=governor.clamps, reasons=dict(governor.reasons)),
                         self._observed, final)

    def _instants(self, until: int | None) -> None:
        """The instants, each in the same order (see the module's docstring): the physics up to
        it, every event due at it, then the loop as long as there is something to do."""
        queue, robot, status = self.queue, self.robot, self.status
        while not status.done:
            interrupt.check()
            t = queue.next_time()
            if t is None:
                # Nothing is scheduled: nothing can happen any more. With wheels still turning
                # (an operator's drive without end) the robot goes on to the time limit.
                if until is not None and self.actuators.applied != ZERO:
                    status.now, status.outcome = until, "until"
                else:
                    status.outcome = "stalled"
                break
            if until is not None and t > until:
                status.now, status.outcome = until, "until"
                break
            if self._probes and self._probes[-1] < t:
                self._observe(t - 1)  # between the last instant and this one
            if self._catch_up:
                robot.advance(t)
            happened = False
            while (item := queue.pop_due(t)) is not None:
                happened = item[0](t, item[1]) or happened
            if happened:
                status.now = t
                self._settle(t)
                if self._show_outputs:
                    self._outputs()
            if self._probes and self._probes[-1] == t:
                self._observe(t)  # after everything at this instant

    def _settle(self, now: int) -> None:
        """Loop at `now` while there is something to do there, up to `max_loops` times."""
        status = self.status
        for _ in range(self.max_loops):
            if status.done or not self._iterate(now):
                return
        status.fatal(now, NO_PROGRESS,
                     f"the loop ran {self.max_loops} times at {now} ms without time "
                     "passing (blocks that take no time in a cycle, or rules that keep raising "
                     "work)")

    def _iterate(self, now: int) -> bool:
        """One loop at `now`; True when another loop must run at the same instant."""
        world, status, scripts = self.world, self.status, self.scripts
        info = world.script
        # 4. apply pending updates
        if world.pending:
            self.updates.apply(now)
        scripts.update_elapsed(now)
        # 5. a compulsory script switch
        if info.override is not None and not status.done:
            self.overrides.apply(now)
        # 6. load the next script when none runs (the session's start), leave idle_activity
        # when a real script waits
        if not status.done:
            scripts.load_when_free(now)
        # 7. read blocks
        if scripts.need_read and not status.done:
            scripts.read(now)
        self.bindings.end_owner(READER)
        if status.done:
            return False
        # 8. the chain of rules
        self.mutex.pass_chain(now)
        self.bindings.end_loop()
        # 1. issue the block
        scripts.issue(now)
        return scripts.need_read or info.override is not None or bool(world.pending)

    # -- the event queue's handlers (each says whether it makes an instant) ---------------------

    def _on_start(self, now: int, _arg: None) -> bool:
        """The session's start: an instant at 0 ms (the loop's step 6 loads the first script)."""
        return True

    def _on_update(self, now: int, tu: TimedUpdate) -> bool:
        """A scenario's update arrives (applied at the next step 4)."""
        self.status.now = now
        self.updates.post(now, tu.update)
        return True

    def _on_sense(self, now: int, sensing: Sensing) -> bool:
        """Simulated sensing (runtime/sensing.py): where the placed entities are relative to
        the robot the physics moved, as `poses` updates; then the next reading."""
        self.status.now = now
        robot = self.robot
        robot.advance(now)
        pose = robot.pose()
        for objectid, rho, theta in sensing.read(now, pose):
            self.updates.post(now, parse_update(objectid, "poses", "R",
                                                {"positionrho": rho, "positiontheta": theta}))
        if self.governor is not None:
            self.governor.recheck(now)
        self.queue.push(now + sensing.period, PRIO_UPDATE, self._on_sense, sensing)
        return True

    def on_wake(self, now: int, governor: Governor) -> bool:
        """The governor's flash window frees: it shows what the script asks now. Not a loop of
        the session (nothing of the script changed), so the handler says nothing happened."""
        governor.wake_led(now, self.actuators.led)
        return False

    # -- observing the state (a test's `at`) ----------------------------------------------------

    def _observe(self, through: int) -> None:
        """Record the state at each millisecond to observe up to `through`: no instant falls
        between the last one handled and `through`, so each is that instant's state with the
        robot looked ahead to its millisecond."""
        probes = self._probes
        while probes and probes[-1] <= through:
            t = probes.pop()
            self._observed.append(self._state(t, self._pose_at(t)))

    def _pose_at(self, t: int) -> Pose:
        """Where the robot is at `t` (at or after the physics' time), from a ghost that moves
        on its own: advancing the robot itself would cut its motion at `t` and round it
        differently from the run that is not observed."""
        ghost = self.robot.ghost()
        # A failure of the physics: the run itself meets it and reports it; the ghost got
        # as far as it could.
        with contextlib.suppress(RobotFailure):
            ghost.advance(t)
        return ghost.pose()

    def _state(self, t: int, pose: Pose) -> Observation:
        actuators, scripts = self.actuators, self.scripts
        led = actuators.led if self.governor is None else self.governor.led_shown
        audio = None if actuators.audio_paused else actuators.audio
        running = actuators.block_active and scripts.executor is not None
        return Observation(
            t, pose, None if led is None else (led[0], led[1], led[2]), audio,
            scripts.issued_label if running else None,
            scripts.issued_path if running else None,
            scripts.executor.name if running and scripts.executor is not None else None)

    # -- the end of an instant, and of an interrupted run ---------------------------------------

    def _outputs(self) -> None:
        """The end of an instant: the LEDs and the speaker into a robot model that shows them
        (MuJoCo's materials), through the governor when there is one."""
        display = self._display
        if self.governor is not None:
            self.governor.end_instant(self.status.now, self.actuators.led)
        elif display is not None:
            display.set_led(self.actuators.led)
        if display is not None:
            display.set_audio(self.actuators.audio)

    def _interrupted(self) -> None:
        """Ctrl-C (`interrupt.check` raised): the session stops where it is. No instant was
        under way (checks are made between instants and between chunks of physics), so the
        trace holds every instant up to `now`; the time reached is where the physics got."""
        status = self.status
        status.finish("interrupted")
        if self._stepped is not None:
            # Stepped up to each instant, the physics is at the last one or on its way to the
            # next one (or to the time limit, or braking after the end): nothing happened
            # between, so that is the time reached.
            status.now = self._stepped.time_ms
        else:
            # The kinematic robot may lag behind the last instant (it is advanced where it is
            # needed): bringing it there costs nothing.
            self.robot.advance(status.now)
