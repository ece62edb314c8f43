"""The actuators: an instruction block's three timed tracks, what the robot's wheels, LEDs
and speaker are doing, and the operator's joystick (thesis 3.1, 5.3; docs/runtime.md). Shared by
every executor: an executor hands over a `BlockCommands`, the actuators do the rest.

Track timing (exact to the millisecond): the three tracks (`move`, `led`, `audioout`) start
together when the block is issued. On each track a command waits `wait_t` ms (from the end of
the previous command of the track, or from the issue), runs `duration` ms, then stops:
stopping a move sets zero velocity, a LED command turns the LEDs off, an audio command stops
its track. A command's stop and the next command's start at the same millisecond happen in
that order. The block is consumed when all three tracks are done (a block with no command at
all is consumed as it is issued). Each track schedules one event at a time (its next phase
change), so a command costs two events whatever its length.

After each command the map gets its progress (`Script/submove`, `subled`, `subaout`: the
number of commands done) and a history record (`RobotStatus/speed`, `led`, `audioout`).

Velocity: what the wheels get is, in this order of precedence,
1. the operator's drive command while it lasts (the joystick, with the safety lock held);
2. zero while the block is frozen (the joystick's "interrupt block execution") or while a rule
   holds motion (the safety stop);
3. the running move command's velocity, else zero.
An operator's drive cancels the move command running when it starts (that command does not
come back when the drive ends); a script move that starts later takes the wheels back
(thesis 5.3: the two "override among themselves, cancelling the current one"). A drive while
the block is frozen cancels nothing: the operator drives "in a blocking way", and when the
block resumes its move command goes on.

Freezing stops the block's clock: no command starts or stops, the remaining times are kept,
the audio is paused; unfreezing goes on where it stopped.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, TypeGuard

from scriptc.runtime.clock import PRIO_OPERATOR_TIMER, PRIO_TRACK, EventQueue
from scriptc.runtime.commands import SILENCE, TRACKS, Audio, BlockCommands, Command, Led, Move
from scriptc.runtime.robots import Drive
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import World

ZERO = (0.0, 0.0, 0.0)
_PROGRESS_FIELD = ("submove", "subled", "subaout")


class Track:
    __slots__ = ("commands", "end", "i", "index", "name", "phase", "remaining", "started")

    def __init__(self, index: int) -> None:
        self.index = index
        self.name = TRACKS[index]
        self.commands: tuple[Command, ...] = ()
        self.i = 0
        self.phase = "done"  # "wait", "run" or "done"
        self.end = 0  # when the current phase ends
        self.remaining = 0  # of the current phase, while frozen
        self.started = 0  # when the running command started


class Planner(Protocol):
    """A robot that plans a block's moves ahead (the safety governor, runtime/governor.py)."""

    def plan_block(self, t_ms: int, moves: tuple[Move, ...], length: int) -> None: ...

    def drop_plan(self, t_ms: int) -> None: ...


def _plans(robot: Drive) -> TypeGuard[Planner]:
    """Whether the robot plans blocks ahead (a `Planner`)."""
    return hasattr(robot, "plan_block")


class Actuators:
    def __init__(self, queue: EventQueue, robot: Drive, trace: Trace, world: World) -> None:
        self.queue = queue
        self.robot = robot
        self.trace = trace
        self.world = world
        self.tracks = [Track(k) for k in range(3)]
        self.on_consumed: Callable[[int], None] | None = None  # when a block is consumed
        self.block_active = False  # a block is issued and not yet consumed (nor cancelled)
        self._tick = 0  # generation of scheduled track events (stale ones are ignored)
        self.frozen = False
        self.hold = False
        self.script_v = ZERO  # the running move command's velocity, while script_moving
        self.script_moving = False  # a move command has the wheels
        self.driving = False
        self.drive_v = ZERO  # the operator's velocity, while driving
        self._drive_gen = 0  # generation of timed drives (a replaced drive's end is stale)
        self.safety_held = False
        self.applied = ZERO
        self.led: tuple[float, float, float] | None = None
        self.audio: str | None = None
        self.audio_paused = False
        # A robot that plans a block's moves ahead (the safety governor): told of each block
        # and of whatever else changes the wheels.
        self._planner = robot if _plans(robot) else None

    # -- blocks -----------------------------------------------------------------------------

    def issue(self, now: int, instruction: BlockCommands) -> None:
        """Start a block from its beginning (cancelling the one running, if any)."""
        # Every track is done here, and no event of an earlier block is live: a consumed
        # block's tracks are all done, and cancelling one (below) or freezing it makes its
        # queued events stale.
        if self.block_active:
            self.cancel(now)
        self.block_active = True
        info = self.world.script
        info.submove = info.subled = info.subaout = 0
        for track in self.tracks:
            track.commands = instruction.track(track.index)
            track.i = 0
            if track.commands:
                track.phase = "wait"
                track.end = now + track.commands[0].wait_t
                track.remaining = track.end - now
        if self._planner is not None:
            # The governor sees the block's move track ahead (its ramps are centred on the
            # changes): only while the script has the wheels.
            if self.driving or self.frozen or self.hold:
                self._planner.drop_plan(now)
            else:
                self._planner.plan_block(now, instruction.moves, instruction.length)
        if not self.frozen:
            for track in self.tracks:
                self._progress(track, now)
        self._check_consumed(now)

    def cancel(self, now: int) -> None:
        """Stop whatever runs (a script unloaded, a block replaced): running commands stop
        (`cmd_stop` with `cancelled`), the block is dropped without being consumed."""
        self._tick += 1
        if self._planner is not None:
            self._planner.drop_plan(now)
        for track in self.tracks:
            if track.phase == "run":
                self._stop(track, now, cancelled=True)
            track.phase = "done"
        self.block_active = False

    def _on_track(self, now: int, arg: tuple[int, int]) -> bool:
        tick, k = arg
        if tick != self._tick:
            return False  # scheduled before a cancel, a freeze or a new block
        self._progress(self.tracks[k], now)
        self._check_consumed(now)
        return True

    def _progress(self, track: Track, now: int) -> None:
        """Every phase change of `track` due by `now`, then schedule the next."""
        while track.phase != "done" and track.end <= now:
            command = track.commands[track.i]
            if track.phase == "wait":
                track.phase = "run"
                track.started = track.end
                track.end += command.duration
                self._start(track, command, track.started)
            else:
                stopped_at = track.end
                self._stop(track, stopped_at)
                track.i += 1
                if track.i < len(track.commands):
                    track.phase = "wait"
                    track.end = stopped_at + track.commands[track.i].wait_t
                else:
                    track.phase = "done"
        if track.phase != "done":
            self.queue.push(track.end, PRIO_TRACK + track.index, self._on_track,
                            (self._tick, track.index))

    def _check_consumed(self, now: int) -> None:
        if self.block_active and all(t.phase == "done" for t in self.tracks):
            self.block_active = False
            if self.on_consumed is not None:
                self.on_consumed(now)

    def _start(self, track: Track, command: Command, now: int) -> None:
        self.trace.emit(now, "cmd_start", track=track.name, index=track.i,
                        command=command.as_dict())
        if isinstance(command, Move):
            self.script_v = (command.v_x, command.v_y, command.v_theta)
            self.script_moving = True
            self.driving = False  # a script command takes the wheels back from the operator
            self._apply_velocity(now, "script")
        elif isinstance(command, Led):
            self.led = (command.r, command.g, command.b) if command.turnas == 1 else None
        elif isinstance(command, Audio):
            self.audio = None if command.track_path == SILENCE else command.track_path

    def _stop(self, track: Track, now: int, cancelled: bool = False) -> None:
        command = track.commands[track.i]
        if cancelled:
            self.trace.emit(now, "cmd_stop", track=track.name, index=track.i, cancelled=True)
        else:
            self.trace.emit(now, "cmd_stop", track=track.name, index=track.i)
        ran = now - track.started
        robot = self.world.robot
        if isinstance(command, Move):
            if self.script_moving:
                self.script_moving = False
                self._apply_velocity(now, "script")
            robot.append("speed", {"xspeed": command.v_x, "yspeed": command.v_y,
                                   "thetaspeed": command.v_theta, "duration": ran,
                                   "startingtime": track.started})
        elif isinstance(command, Led):
            self.led = None
            robot.append("led", {"r": command.r, "g": command.g, "b": command.b,
                                 "frequency": 0, "duration": ran, "startingtime": track.started})
        else:
            self.audio = None
            robot.append("audioout", {"duration": ran, "startingtime": track.started,
                                      "trackpath": command.track_path})
        if not cancelled:
            setattr(self.world.script, _PROGRESS_FIELD[track.index], track.i + 1)

    # -- velocity ---------------------------------------------------------------------------

    def effective_velocity(self) -> tuple[float, float, float]:
        if self.driving:
            return self.drive_v
        if self.frozen or self.hold:
            return ZERO
        return self.script_v if self.script_moving else ZERO

    def _apply_velocity(self, now: int, cause: str) -> None:
        if cause != "script" and self._planner is not None:
            self._planner.drop_plan(now)  # the operator, a freeze or a hold: not the block's plan
        v = self.effective_velocity()
        if v != self.applied:
            self.robot.set_velocity(now, *v)
            self.applied = v
            self.trace.emit(now, "velocity", v_x=v[0], v_y=v[1], v_theta=v[2], cause=cause)

    def set_hold(self, now: int, on: bool) -> None:
        """A rule holds the wheels still (the safety stop) while `on`."""
        if on != self.hold:
            self.hold = on
            self._apply_velocity(now, "hold")

    # -- the operator (thesis 5.3: the fake actuator's joystick) ------------------------------

    def set_safety(self, now: int, held: bool) -> None:
        self.safety_held = held
        if not held and self.driving:
            self.driving = False
            self._apply_velocity(now, "operator")

    def drive(self, now: int, v: tuple[float, float, float], duration: int | None) -> None:
        """The operator's velocity command (the caller checked the safety lock)."""
        self._drive_gen += 1
        self.driving = True
        self.drive_v = v
        if not self.frozen:
            # The running move command is cancelled (thesis 5.3). While the block is frozen
            # the operator drives "in a blocking way": the block resumes as it was.
            self.script_moving = False
        self._apply_velocity(now, "operator")
        if duration is not None:
            self.queue.push(now + duration, PRIO_OPERATOR_TIMER, self._on_drive_end,
                            self._drive_gen)

    def _on_drive_end(self, now: int, gen: int) -> bool:
        if gen == self._drive_gen and self.driving:
            self.driving = False
            self._apply_velocity(now, "operator")
            return True
        return False

    def freeze(self, now: int, on: bool) -> None:
        """Freeze (or resume) the block's clock."""
        if on == self.frozen:
            return
        self.frozen = on
        if on:
            self._tick += 1
            for track in self.tracks:
                if track.phase != "done":
                    track.remaining = track.end - now
            if self.audio is not None:
                self.audio_paused = True
        else:  # (the freeze made every queued phase change stale: queue them again)
            self.audio_paused = False
            for track in self.tracks:
                if track.phase != "done":
                    track.end = now + track.remaining
            for track in self.tracks:
                self._progress(track, now)
        self._apply_velocity(now, "freeze")
        if not on:
            self._check_consumed(now)
