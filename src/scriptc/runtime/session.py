"""The session: the LIFO of scripts, `idle_activity`, and the loop of thesis 4.2 in simulated
time. Shared by every executor: it drives whatever `Executor` a `Program` makes.

An instant is a millisecond at which something is due (and 0 ms, the session's start). Every
instant has the same order (`_loop`; docs/runtime.md, "The order of an instant"): the physics
is brought up to it, then every event due at it is handled (the actuators' tracks, the
operator's timers and events, scenario updates and sensor readings are posted, not yet
applied), and only then does the loop run, as many times as there is something to do at that
instant. So a jump read at `t` sees every update that arrived at `t`, at 0 ms as at any other.

One loop (`_iterate`), at the instant `now`:

4. apply every pending map update (sensor updates that arrived at `now`, updates rules posted);
5. apply a compulsory script switch a rule raised (`ScriptInfo.override`);
6. load the next script when none runs (the session's start), or leave `idle_activity` if a
   real script is queued;
7. if the block with the actuators is consumed (or none was issued yet), read blocks
   (`Executor.read`): jumps, sensor blocks, a terminus or the end unload the script and load
   the next; the block reader's `L` bindings end here;
8. pass the map through the chain of rules (unless the mutex is locked); `T` bindings end;
1. issue the block to the actuators if it is new or a rule changed it;
2. (the script info is published as it changes.)
Step 3, "wait for something to change", is the event queue: the session jumps to the next
event (a track's next phase, an operator event, a sensor update), runs its handlers, and loops
again at that instant until nothing more happens there (a rule's override, a block consumed as
it is issued, updates a rule posted). Nothing reads the wall clock. At the end of each instant
the outputs go to the robot: with the safety governor (a profile), it applies the instant's
velocity command then (its ramps, runtime/governor.py) and shows the LEDs its flash limit
allows; a held LED onset gets a wake-up event that is not an instant of the loop.

The session ends when every queued script has ended (`stop_when_done`, what `scriptc run`
does: it does not sit in `idle_activity`), at `until`, when nothing can happen any more
(`stalled`: no event is scheduled and the wheels are still, as when the operator froze the
block; it ends at once, `until` or not), on a fatal error (`error`: a loop that never lets time
pass), or when interrupted (`interrupted`: Ctrl-C under `scriptc.interrupt.catching()`, taken
between two instants or between two chunks of physics; the trace holds every instant before).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from scriptc.numbers import whole_number
from scriptc.runtime.actuators import ZERO, Actuators
from scriptc.runtime.bindings import READER, Bindings
from scriptc import interrupt
from scriptc.runtime.clock import PRIO_OPERATOR, PRIO_START, PRIO_UPDATE, EventQueue
from scriptc.runtime.evaluate import EvalContext, Evaluation, evaluate
from scriptc.runtime.executor import End, Executor, Issue, Program, ReadLimit, SeekError
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS, Implementations
from scriptc.runtime.robots import Pose, Robot, RobotFailure, make_robot
from scriptc.runtime.rules import (
    STANDARD_RULES,
    RuleChain,
    RuleContext,
    RuleError,
    RuleLibrary,
    UnknownRule,
)
from scriptc.runtime.scenario import OperatorEvent, Scenario, TimedUpdate
from scriptc.runtime.loading import LoadError, Loader
from scriptc.runtime.trace import Trace
from scriptc.runtime.commands import Position, RuleMessage
from scriptc.runtime.world import MapUpdate, UpdateError, World, parse_update

# Loops at one instant before the session gives up: a cycle of jumps and blocks that take no
# time, or rules that keep raising work, never let time pass.
MAX_LOOPS_PER_INSTANT = 10_000


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
    reached: set = field(default_factory=set)

    def as_dict(self) -> dict:
        return {"script": self.script, "path": self.path, "reason": self.reason,
                "loaded_ms": self.loaded_ms, "ended_ms": self.ended_ms,
                "ended_by": self.ended_by, "goals": dict(self.goals)}


@dataclass
class Result:
    outcome: str  # "completed", "until", "stalled", "error" or "interrupted"
    time_ms: int
    pose: Pose
    loads: list[LoadRecord]
    errors: list[dict]
    events: int
    trace: Trace
    # With the governor: the millisecond the robot came to rest after the activity's end
    # (it brakes at the profile's accelerations; `pose` is where it stopped).
    at_rest_ms: int | None = None
    # With the governor: how many times it intervened (`governor` trace events), and how many
    # of them for each reason (an event may have two: a speed clamped and ramped).
    governor: dict | None = None

    def as_dict(self) -> dict:
        data = {
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


class Session:
    """A run of queued scripts (see the module's docstring).

    `programs` run in the order given (the LIFO holds them top first). `catalogue` adds
    programs that may be named by an override or a `script_vect` update without being
    queued; `loader(path) -> Program` loads others by path (raising LoadError). `idle` replaces
    the built-in `idle_activity`."""

    def __init__(self, programs: list[Program] | tuple[Program, ...] = (), *,
                 scenario: Scenario | None = None, robot: str | Robot = "kinematic",
                 functions: Implementations = STANDARD_IMPLEMENTATIONS,
                 rules: RuleLibrary = STANDARD_RULES, trace: Trace | None = None,
                 idle: Program | None = None, stop_when_done: bool = True,
                 catalogue: list[Program] | tuple[Program, ...] = (),
                 loader: Loader | None = None,
                 max_loops_per_instant: int = MAX_LOOPS_PER_INSTANT,
                 profile=None) -> None:
        self.max_loops = max_loops_per_instant
        self.world = World()
        self.bindings = Bindings()
        self.queue = EventQueue()
        self.trace = trace if trace is not None else Trace()
        self.robot = make_robot(robot) if isinstance(robot, str) else robot
        # The safety governor (runtime/governor.py) when a robot profile is given, and the
        # simulated sensing of the scenario's placed entities (runtime/sensing.py).
        self.governor = None
        if profile is not None:
            from scriptc.runtime.governor import PRIO_WAKE, Governor

            self.robot = self.governor = Governor(self.robot, profile, self.trace)
            # A held LED onset: the governor is woken when the flash window frees (an event
            # only runs that hold LEDs get; its handler is not a loop of the session).
            self.governor.wake = lambda t: self.queue.push(t, PRIO_WAKE, self._on_wake, None)
        self.sensing = None
        if scenario is not None and scenario.entities:
            from scriptc.runtime.sensing import Sensing

            self.sensing = Sensing(scenario.entities, scenario.sensing_rate_hz,
                                   scenario.sensing_range)
            if self.governor is not None:
                self.governor.nearest = self.sensing.nearest_human
        # A backend that shows the LEDs and the speaker (MuJoCo's model); the governor sees the
        # LEDs and applies its pending command at the end of every instant.
        self._shows = hasattr(self.robot, "set_led")
        self._show_outputs = self._shows or self.governor is not None
        # A backend that steps its physics (`stepped`: MuJoCo) is brought up to each instant
        # before the instant's events, where stepping can be interrupted and costs the same
        # steps as inside a handler; the kinematic robot is advanced where it is needed only
        # (its closed form would round differently if cut in more pieces).
        self._catch_up = bool(getattr(self.robot, "stepped", False))
        self.actuators = Actuators(self.queue, self.robot, self.trace, self.world)
        self.actuators.on_consumed = self._consumed
        self.chain = RuleChain()
        self.rules = rules
        self.functions = functions
        self.ctx = EvalContext(self.world, self.bindings, functions, session=self,
                               on_error=self._function_error)
        self.scenario = scenario
        self.stop_when_done = stop_when_done
        self.loader = loader
        if idle is None:
            from scriptc.runtime.idle import idle_program

            idle = idle_program()
        self.idle = idle
        self.programs = list(programs)
        self.lifo: list[Program] = list(reversed(self.programs))
        self.catalogue: dict[str, Program] = {}
        for program in (*catalogue, *self.programs, idle):
            self.catalogue.setdefault(program.name, program)
            if program.path:
                self.catalogue.setdefault(os.path.abspath(program.path), program)
        self.current: Executor | None = None
        self.current_program: Program | None = None
        self.load: LoadRecord | None = None
        self.loads: list[LoadRecord] = []
        self.cur_goal: int | None = None
        self.need_read = False
        self.pending_issue = False
        self.issued_path = ""
        self.issued_label = ""
        self.motion_hold_asserted = False
        self._skip_reported = False
        self.now = 0
        self.done = False
        self.outcome = ""

    # ---------------------------------------------------------------------------------------
    # Running

    def run(self, until: int | None = None) -> Result:
        """Run to the end (see the module's docstring); `until` caps simulated time (ms)."""
        governed = {}
        if self.governor is not None:  # the limits the governor keeps, as the trace's header
            governed["profile"] = self.governor.profile.limits()
        self.trace.emit(0, "session_start", scripts=[p.name for p in self.programs],
                        robot=getattr(self.robot, "name", type(self.robot).__name__),
                        until=until, scenario=self.scenario.path if self.scenario else None,
                        **governed)
        if self.scenario is not None:
            for tu in self.scenario.updates:
                self.queue.push(tu.at, PRIO_UPDATE, self._on_update, tu)
            for op in self.scenario.operator:
                self.queue.push(op.at, PRIO_OPERATOR, self._on_operator, op)
        if self.sensing is not None:
            self.queue.push(0, PRIO_UPDATE, self._on_sense, None)
        # The session's start makes 0 ms an instant like any other: its events are handled
        # first, then the loop loads the first script (step 6) and reads it.
        self.queue.push(0, PRIO_START, self._on_start, None)
        failed = False
        settled = {}
        try:
            try:
                self._loop(until)
            except RobotFailure as exc:
                self._fatal(self.now, "robot-unstable", str(exc))
                failed = True
            try:
                self.robot.advance(self.now)
                if self.governor is not None and not failed:
                    # The activity is over, the robot may still be braking: the physics goes
                    # on until it is at rest, and the pose is where it stops (docs/robot.md).
                    settled["at_rest_ms"] = self.governor.come_to_rest(self.now)
            except RobotFailure:
                pass  # already reported, or the braking failed: the pose is the last one
        except interrupt.Interrupted:
            settled = {}
            self._interrupted()
        pose = self.robot.pose()
        self.trace.emit(self.now, "session_end", outcome=self.outcome, time_ms=self.now,
                        pose=pose.as_dict(), **settled)
        return Result(self.outcome, self.now, pose, self.loads, self.trace.errors,
                      self.trace.count, self.trace, settled.get("at_rest_ms"),
                      None if self.governor is None else
                      {"clamps": self.governor.clamps, "reasons": dict(self.governor.reasons)})

    def _loop(self, until: int | None) -> None:
        """The instants, each in the same order (see the module's docstring): the physics up to
        it, every event due at it, then the loop as long as there is something to do."""
        queue, robot = self.queue, self.robot
        while not self.done:
            interrupt.check()
            t = queue.next_time()
            if t is None:
                # Nothing is scheduled: nothing can happen any more. With wheels still turning
                # (an operator's drive without end) the robot goes on to the time limit.
                if until is not None and self.actuators.applied != ZERO:
                    self.now, self.outcome = until, "until"
                else:
                    self.outcome = "stalled"
                break
            if until is not None and t > until:
                self.now, self.outcome = until, "until"
                break
            if self._catch_up:
                robot.advance(t)
            happened = False
            while (item := queue.pop_due(t)) is not None:
                happened = item[0](t, item[1]) or happened
            if happened:
                self.now = t
                self._settle(t)
                if self._show_outputs:
                    self._outputs()

    def _on_start(self, now: int, _arg) -> bool:
        """The session's start: an instant at 0 ms (the loop's step 6 loads the first script)."""
        return True

    def _interrupted(self) -> None:
        """Ctrl-C (`interrupt.check` raised): the session stops where it is. No instant was
        under way (checks are made between instants and between chunks of physics), so the
        trace holds every instant up to `now`; the time reached is where the physics got."""
        self.outcome = "interrupted"
        self.done = True
        if self._catch_up:
            # Stepped up to each instant, the physics is at the last one or on its way to the
            # next one (or to the time limit, or braking after the end): nothing happened
            # between, so that is the time reached.
            self.now = self.robot.time_ms
        else:
            # The kinematic robot may lag behind the last instant (it is advanced where it is
            # needed): bringing it there costs nothing.
            self.robot.advance(self.now)

    def _outputs(self) -> None:
        """The end of an instant: the LEDs and the speaker into a robot model that shows them
        (MuJoCo's materials), through the governor when there is one."""
        if self.governor is not None:
            self.governor.end_instant(self.now, self.actuators.led)
        else:
            self.robot.set_led(self.actuators.led)
        if self._shows:
            self.robot.set_audio(self.actuators.audio)

    def _on_wake(self, now: int, _arg) -> bool:
        """The governor's flash window frees: it shows what the script asks now. Not a loop of
        the session (nothing of the script changed), so the handler says nothing happened."""
        self.governor.wake_led(now, self.actuators.led)
        return False

    def _on_sense(self, now: int, _arg) -> bool:
        """Simulated sensing (runtime/sensing.py): where the placed entities are relative to
        the robot the physics moved, as `poses` updates; then the next reading."""
        self.now = now
        robot = self.robot
        robot.advance(now)
        pose = robot.pose()
        for objectid, rho, theta in self.sensing.read(now, pose):
            update = parse_update(objectid, "poses", "R",
                                  {"positionrho": rho, "positiontheta": theta})
            self._post(now, update, "sensing")
        if self.governor is not None:
            self.governor.recheck(now)
        self.queue.push(now + self.sensing.period, PRIO_UPDATE, self._on_sense, None)
        return True

    def _settle(self, now: int) -> None:
        for _ in range(self.max_loops):
            if self.done or not self._iterate(now):
                return
        self._fatal(now, "no-progress",
                    f"the loop ran {self.max_loops} times at {now} ms without time "
                    "passing (blocks that take no time in a cycle, or rules that keep raising "
                    "work)")

    def _iterate(self, now: int) -> bool:
        """One loop at `now`; True when another loop must run at the same instant."""
        world = self.world
        # 4. apply pending updates
        if world.pending:
            self._apply_updates(now)
        if self.load is not None and self.current is not None:
            activity = world.entity("Activity", self.current.name)
            if activity is not None:
                activity.fields["elapsedtime"] = now - activity.fields["startingtime"]
        # 5. a compulsory script switch
        if world.script.override is not None and not self.done:
            self._apply_override(now)
        # 6. load the next script when none runs (the session's start), leave idle_activity
        # when a real script waits
        if self.current is None and not self.done:
            self._next_script(now)
        elif self.current_program is self.idle and self.lifo and not self.done:
            self._unload(now, "idle_escape")
            self._next_script(now)
        # 7. read blocks
        if self.need_read and not self.done:
            self._read(now)
        self.bindings.end_owner(READER)
        if self.done:
            return False
        # 8. the chain of rules
        self._pass_chain(now)
        self.bindings.end_loop()
        # 1. issue the block
        info = world.script
        if (self.pending_issue or info.changed) and info.block is not None \
                and self.current is not None:
            self.trace.emit(now, "block", script=self.current.name, path=self.issued_path,
                            label=self.issued_label, changed=info.changed)
            self.pending_issue = False
            info.changed = False
            self.actuators.issue(now, info.block)
        return self.need_read or info.override is not None or bool(world.pending)

    def _fatal(self, now: int, code: str, message: str) -> None:
        self.trace.emit(now, "error", code=code, message=message, fatal=True)
        self.actuators.cancel(now)
        self.done = True
        self.outcome = "error"

    # ---------------------------------------------------------------------------------------
    # Scripts: the LIFO, loading and unloading

    def _next_script(self, now: int) -> None:
        if self.lifo:
            self._load(now, self.lifo.pop(), "queue")
        elif self.stop_when_done:
            self.done = True
            self.outcome = "completed"
        else:
            self._load(now, self.idle, "idle")

    def _load(self, now: int, program: Program, reason: str) -> None:
        executor = program.executor()
        executor.start()
        self.current = executor
        self.current_program = program
        self.cur_goal = None
        info = self.world.script
        info.currentactivity = executor.name
        info.goal = info.action = info.blockid = -1
        info.goalid = info.path = ""
        info.block = None
        info.changed = False
        info.submove = info.subled = info.subaout = 0
        self.world.start_activity(executor.name, now)
        self.world.robot.fields["startingtime"] = now
        self.world.robot.fields["elapsedtime"] = 0
        self.load = LoadRecord(executor.name, program.path, reason, now)
        self.loads.append(self.load)
        self.trace.emit(now, "script_load", script=executor.name, path=program.path,
                        reason=reason)
        self._issue_messages(now, executor.alfa, "alfa", executor.name)
        self.need_read = True
        self.pending_issue = False

    def _unload(self, now: int, how: str) -> None:
        executor = self.current
        if executor is None:
            return
        if self.actuators.block_active:
            self.actuators.cancel(now)
        if self.cur_goal is not None and self.cur_goal < len(executor.goal_ids):
            kind = "reached" if how in ("terminus", "past_end") else "interrupted"
            self.record_goal(kind, executor.goal_ids[self.cur_goal])
        self.trace.emit(now, "script_unload", script=executor.name, reason=how)
        if self.load is not None:
            self.load.ended_ms, self.load.ended_by = now, how
        self._issue_messages(now, executor.omega, "omega", executor.name)
        self.bindings.end_script()
        activity = self.world.entity("Activity", executor.name)
        if activity is not None:
            activity.fields["elapsedtime"] = now - activity.fields["startingtime"]
        self.world.script.block = None
        self.world.script.override = None
        self.current = None
        self.current_program = None
        self.need_read = False
        self.pending_issue = False

    def _read(self, now: int) -> None:
        """Step 7: read until an instruction block; scripts that end are replaced."""
        ended = 0
        while not self.done:
            if ended > self.max_loops:
                self._fatal(now, "no-progress",
                            f"{ended} scripts ended at {now} ms without time passing (an "
                            "idle_activity that ends at once?)")
                return
            if self.current is None:
                self._next_script(now)
                continue
            self.ctx.now = now
            try:
                result = self.current.read(self.ctx, self)
            except (ReadLimit, RuntimeError) as exc:
                self._fatal(now, "read", str(exc))
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
                self.trace.emit(now, "terminus", script=self.current.name,
                                path=result.position.path)
            self._unload(now, result.how)
            self._next_script(now)
            ended += 1

    def _consumed(self, now: int) -> None:
        if self.current is not None:
            self.trace.emit(now, "block_done", script=self.current.name, path=self.issued_path)
        self.need_read = True

    # -- what an executor reports while reading (the ReadSink) -------------------------------

    def visit(self, position: Position) -> None:
        executor = self.current
        info = self.world.script
        info.goal, info.action, info.blockid = position
        info.path = position.path
        if position.goal < len(executor.goal_ids):
            info.goalid = executor.goal_ids[position.goal]
        if self.cur_goal is None:
            self.cur_goal = position.goal
        elif position.goal != self.cur_goal:
            if position.goal > self.cur_goal:
                self.record_goal("reached", executor.goal_ids[self.cur_goal])
            self.cur_goal = position.goal

    def jump(self, position: Position, condition: str, evaluation: Evaluation,
             target: Position | None) -> None:
        self.trace.emit(self.now, "jump", script=self.current.name,
                        path=position.path, condition=condition, value=evaluation.value,
                        bindings=evaluation.bindings,
                        target=target.path if target is not None else None)

    def sensor(self, position: Position, payload: tuple[str, ...]) -> None:
        self.trace.emit(self.now, "sensor", script=self.current.name,
                        path=position.path, payload=list(payload))

    # -- goals --------------------------------------------------------------------------------

    def record_goal(self, kind: str, goalid: str, by: str | None = None) -> None:
        """Record a goal (`reached`, `interrupted`, `failed`) in the map and the trace."""
        if kind not in ("reached", "interrupted", "failed"):
            raise ValueError(f"a goal record is reached, interrupted or failed, not {kind!r}")
        now = self.now
        script = self.current.name if self.current is not None else ""
        self.world.robot.append("goal" + kind, {"goalid": goalid, "timestamp": now,
                                                "activity": script})
        fields = {"script": script, "goalid": goalid, "record": kind}
        if by:
            fields["by"] = by
        self.trace.emit(now, "goal", **fields)
        if self.load is not None:
            self.load.goals[goalid] = kind
            if kind == "reached":
                self.load.reached.add(goalid)

    def goal_reached(self, goalid: str) -> bool:
        """`goalreached(goalid)`: reached by the running script since it was loaded, or
        recorded as reached by a sensor (a MapUpdate without `activity`) since then."""
        if self.load is None:
            return False
        if goalid in self.load.reached:
            return True
        for record in self.world.goal_records("goalreached"):
            if (record.get("goalid") == goalid and "activity" not in record
                    and record.get("timestamp", 0) >= self.load.loaded_ms):
                return True
        return False

    # ---------------------------------------------------------------------------------------
    # Rules

    def _misuse(self, now: int, message: str) -> None:
        self.trace.emit(now, "error", code="mutex-misuse", message=message, fatal=False)

    def _issue_messages(self, now: int, messages: tuple[RuleMessage, ...], kind: str,
                        script: str) -> None:
        """Issue an alfa or omega list with its mutex commands (thesis 4.4)."""
        chain = self.chain
        last = len(messages) - 1
        for i, m in enumerate(messages):
            if m.mutex == "L":
                if chain.locked:
                    self._misuse(now, f"`{m.id}` ({kind} of `{script}`) locks the map, which "
                                      f"{chain.locked_by} had already locked")
                if kind == "alfa":
                    self._misuse(now, f"`{m.id}` locks the map in the alfa list of `{script}` "
                                      "(alfa messages must not lock)")
                self._lock(now, f"{kind} of `{script}`")
            elif kind == "omega" and i == 0:
                self._misuse(now, f"the omega list of `{script}` changes the chain without "
                                  "locking the map first (its first message must be `L`)")
            try:
                result, note, rule = chain.apply(m, self.rules)
            except RuleError as exc:
                self.trace.emit(now, "error", code="rule", message=f"`{m.id}` (rulecode "
                                f"{m.rulecode}): {exc}", fatal=False)
                result, note, rule = "failed", None, None
            fields = {"script": script, "message": kind, "rulecode": m.rulecode, "id": m.id,
                      "action": m.action, "mutex": m.mutex, "result": result}
            if note:
                fields["note"] = note
            fields["chain"] = chain.ids()
            self.trace.emit(now, "rule", **fields)
            if isinstance(rule, UnknownRule):
                self.trace.emit(now, "error", code="unknown-rulecode",
                                message=f"rulecode {m.rulecode} (`{m.id}`) is not in the rule "
                                        "library: the rule does nothing", fatal=False)
            if m.mutex == "U":
                if kind == "omega":
                    self._misuse(now, f"`{m.id}` unlocks the map in the omega list of "
                                      f"`{script}` (omega messages must not unlock)")
                elif i != last:
                    self._misuse(now, f"`{m.id}` unlocks the map before the end of the alfa "
                                      f"list of `{script}`: rules see a half-built chain")
                self._unlock(now, f"{kind} of `{script}`")
        if kind == "alfa" and chain.locked:
            if not messages:
                # A script without alfa messages takes the chain as the previous omega left it.
                self._unlock(now, f"`{script}` has no alfa messages: the hand-over is complete")
            else:
                self._misuse(now, f"the alfa list of `{script}` leaves the map locked (its last "
                                  "message must be `U`): rules do not run until a `U`")

    def _lock(self, now: int, by: str) -> None:
        self.chain.locked = True
        self.chain.locked_by = by
        self._skip_reported = False
        self.trace.emit(now, "mutex", state="locked", by=by)

    def _unlock(self, now: int, by: str) -> None:
        if self.chain.locked:
            self.chain.locked = False
            self.chain.locked_by = ""
            self.trace.emit(now, "mutex", state="unlocked", by=by)

    def _pass_chain(self, now: int) -> None:
        chain = self.chain
        if chain.locked:
            if not self._skip_reported:
                self._skip_reported = True
                self.trace.emit(now, "mutex", state="locked", by=chain.locked_by,
                                note="the map does not pass through the chain while locked")
            return
        if not chain.active:
            if self.actuators.hold:
                self.actuators.set_hold(now, False)
            return
        self.motion_hold_asserted = False
        ctx, bindings = self.ctx, self.bindings
        for rule in list(chain.active):
            ctx.begin(rule.id, now)
            evaluation = evaluate(rule.condition, ctx)
            rctx = RuleContext(self, rule, now, evaluation)
            try:
                if evaluation.value:
                    rule.on_true(rctx)
                else:
                    rule.on_false(rctx)
            except Exception as exc:  # noqa: BLE001 - a rule's bug must not stop the robot
                self.trace.emit(now, "error", code="rule",
                                message=f"rule `{rule.id}` (rulecode {rule.rulecode}) raised "
                                        f"{type(exc).__name__}: {exc}", fatal=False)
            bindings.end_owner(rule.id)
        self.actuators.set_hold(now, self.motion_hold_asserted)

    def _function_error(self, message: str) -> None:
        self.trace.emit(self.now, "error", code="function", message=message, fatal=False)

    # ---------------------------------------------------------------------------------------
    # Overrides and the LIFO from the map

    def find_program(self, name: str) -> Program | None:
        """A program by activity name, by path, or loaded by path through the loader."""
        program = self.catalogue.get(name)
        if program is not None:
            return program
        base = self.scenario.folder if self.scenario is not None else os.getcwd()
        path = os.path.abspath(os.path.join(base, name))
        program = self.catalogue.get(path)
        if program is not None or self.loader is None:
            return program
        program = self.loader(path)
        self.catalogue[path] = program
        return program

    def _apply_override(self, now: int) -> None:
        request = self.world.script.override
        self.world.script.override = None
        try:
            program = self.find_program(request.script)
        except LoadError as exc:
            program, problem = None, str(exc)
        else:
            problem = f"no script named `{request.script}`"
        if program is None:
            self.trace.emit(now, "error", code="override",
                            message=f"override by `{request.by}`: {problem}", fatal=False)
            return
        goal = request.goal
        executor = self.current
        same = executor is not None and self.current_program is program
        goal_ids = (executor.goal_ids if same else program.executor().goal_ids)
        if isinstance(goal, str):
            # (A number of hundreds of digits, beyond the number policy, names no goal.)
            index = whole_number(goal) if goal.isascii() and goal.isdigit() else None
            if index is not None:
                goal = index
            elif goal in goal_ids:
                goal = goal_ids.index(goal)
            else:
                self.trace.emit(now, "error", code="override",
                                message=f"override by `{request.by}`: `{program.name}` has no "
                                        f"goal `{goal}`", fatal=False)
                return
        position = Position(goal, request.action, request.block)
        self.trace.emit(now, "override", by=request.by,
                        script=executor.name if executor is not None else None,
                        to=program.name, at=position.path)
        if same:
            try:
                executor.seek(position)
            except SeekError as exc:
                self.trace.emit(now, "error", code="override", message=str(exc), fatal=False)
                return
            if self.cur_goal is not None:
                self.record_goal("interrupted", executor.goal_ids[self.cur_goal])
            self.cur_goal = None
            self.actuators.cancel(now)
            self.world.script.block = None
            self.pending_issue = False
            self.need_read = True
            return
        self._unload(now, "override")
        self._load(now, program, "override")
        try:
            self.current.seek(position)
        except SeekError as exc:
            self.trace.emit(now, "error", code="override",
                            message=f"{exc}: it starts at its first block", fatal=False)

    def _apply_updates(self, now: int) -> None:
        for update in self.world.take_pending():
            self.world.apply(update, now)
            self.trace.emit(now, "update", **update.as_dict(), status="applied")
            if update.attributename == "script_vect":
                self._script_vect(now, update.value)

    def _script_vect(self, now: int, value: dict) -> None:
        """Table 4.2's `Script/script_vect`: the LIFO becomes `update` (in the order the
        scripts will run); with `restart` the running script stops and the first starts."""
        programs = []
        for name in value["update"]:
            try:
                program = self.find_program(name)
            except LoadError as exc:
                self.trace.emit(now, "error", code="script_vect", message=str(exc), fatal=False)
                continue
            if program is None:
                self.trace.emit(now, "error", code="script_vect",
                                message=f"no script named `{name}`", fatal=False)
                continue
            programs.append(program)
        self.lifo = list(reversed(programs))
        self.world.script.script_vect = [p.name for p in programs]
        if value.get("restart") == "s_true" and self.current is not None \
                and self.current_program is not self.idle:
            self._unload(now, "restart")
            self._next_script(now)

    def post_update(self, objectid: str, attributename: str, policy: str, jsonmsg,
                    source: str = "") -> None:
        """A MapUpdate from inside the run (a rule); an invalid one is reported."""
        try:
            update = parse_update(objectid, attributename, policy, jsonmsg)
        except UpdateError as exc:
            self.trace.emit(self.now, "error", code="update",
                            message=f"{source or 'update'}: {exc}", fatal=False)
            return
        self._post(self.now, update, source)

    def _post(self, now: int, update: MapUpdate, source: str) -> None:
        for dropped in self.world.post(update):
            self.trace.emit(now, "update", **dropped.as_dict(), status="dropped")

    # -- scenario events ----------------------------------------------------------------------

    def _on_update(self, now: int, tu: TimedUpdate) -> bool:
        self.now = now
        self._post(now, tu.update, "scenario")
        return True

    def _on_operator(self, now: int, event: OperatorEvent) -> bool:
        self.now = now
        self._operator(now, event)
        return True

    def _operator(self, now: int, event: OperatorEvent) -> None:
        act = self.actuators
        p = event.params
        if event.command == "safety_lock":
            self.trace.emit(now, "operator", command="safety_lock", held=p["held"])
            act.set_safety(now, p["held"])
            return
        if not act.safety_held:
            self.trace.emit(now, "operator", command=event.command, ignored=True,
                            reason="the safety lock is not held")
            return
        if event.command == "drive":
            v = (float(p.get("v_x", 0)), float(p.get("v_y", 0)), float(p.get("v_theta", 0)))
            self.trace.emit(now, "operator", command="drive", v_x=v[0], v_y=v[1], v_theta=v[2],
                            duration=p.get("duration"))
            act.drive(now, v, p.get("duration"))
        else:  # interrupt
            on = p.get("on", not act.frozen)
            self.trace.emit(now, "operator", command="interrupt", on=on)
            act.freeze(now, on)
