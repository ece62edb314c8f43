"""The MuJoCo robot: the simulated Teo/Oimi base (`teo.xml`, shipped in this package) driven by
body-frame velocities (docs/robot.md). The only module of scriptc that imports `mujoco`
(the `mujoco-core` package: the physics, without a viewer or GL; it runs headless).

Stepping (docs/robot.md, "Stepping"): the session calls `set_velocity` only when the
velocity changes, so the control is written once per change and `advance` steps the physics
up to the requested time in `mj_step(model, data, nstep=n)` calls of at most `CHUNK_STEPS`
steps. `mj_step` holds the thread in C, where Python cannot take Ctrl-C: between two chunks
`scriptc.interrupt.check()` can stop the run (an hour of physics in one call ignored Ctrl-C
for a minute). Cutting changes nothing of the physics: n steps in one call or in several are
the same steps. The session brings the robot up to each instant before handling its events
(`stepped`), so an interruption never falls inside an instant. The model's timestep is 1 ms,
so every duration of a script (whole milliseconds) lands on a whole number of steps; the step
count is integer arithmetic, never a rounded float. A move that is
consumed sets the velocity to zero (the actuators do it), and the velocity actuators (time
constant 0.1 ms) stop the base within a step.

The actuators are velocity servos on integrators (`teo.xml`): the activation is the velocity
setpoint, ctrl its rate of change. A change at once writes the activation (ctrl 0); a ramp of
the governor (`ramp`, `motion.Ramp`) is stepped in batches of constant ctrl: `mj_step(nstep=n)`
with ctrl = each axis's rate of change over the whole milliseconds between two moments where
an axis starts or ends its ramp (the activation is written to its exact value at each, so no
rounding accumulates). A ramp costs at most three batches (the plane and the turn start and
end), whatever its length.

MuJoCo does not raise on a numerical blow-up: it prints a warning and resets the state (or
zeroes a bad control). After every batch of steps the warning counters are compared with the
previous ones; any new warning raises `RobotFailure`, which the session reports as the fatal
run-time error `robot-unstable`.
"""

from __future__ import annotations

import copy
from functools import cache
from importlib import resources

import mujoco

from scriptc import interrupt
from scriptc.runtime.robots import Pose, Ramp, RobotFailure

MODEL_NAME = "teo.xml"

# The most physics steps in one `mj_step` call: 5,000 steps take about 10 ms on the machine
# of docs/robot.md's figures (2 us a step), 0.1 s on a machine ten times as loaded, so Ctrl-C
# is taken well within half a second; the Python between two chunks costs nothing measurable
# (`tests/test_interrupt.py` prints the latency; bench/bench_mujoco.py the speed).
CHUNK_STEPS = 5000

# MuJoCo's warnings go to stdout and to a MUJOCO_LOG.TXT in the current directory by default;
# scriptc keeps the last ones instead and reports them in the run's `robot-unstable` error.
_WARNINGS: list[str] = []


def _on_warning(message: str) -> None:
    del _WARNINGS[:-9]
    _WARNINGS.append(message.strip())


mujoco.set_mju_user_warning(_on_warning)


@cache
def model_xml() -> str:
    return resources.files("scriptc.runtime.robots").joinpath(MODEL_NAME).read_text("utf-8")


@cache
def load_model() -> mujoco.MjModel:
    """The compiled model (compiled once per process; each robot gets its own MjData)."""
    return mujoco.MjModel.from_xml_string(model_xml())


class MujocoRobot:
    name = "mujoco"
    # Advancing costs time in proportion to the interval (physics steps), and advancing in
    # several calls gives the same steps as in one: the session brings it up to each instant
    # before the instant's events (runtime/session.py).
    stepped = True

    def __init__(self, model: mujoco.MjModel | None = None) -> None:
        # A copy per robot: the LED materials change during a run (physics is unaffected).
        self.model = copy.copy(model if model is not None else load_model())
        self.data = mujoco.MjData(self.model)
        steps = 0.001 / self.model.opt.timestep
        self.steps_per_ms = round(steps)
        if self.steps_per_ms < 1 or abs(steps - self.steps_per_ms) > 1e-9:
            raise ValueError("the model's timestep must divide 1 ms")
        self._t = 0  # ms simulated so far
        self._v = (0.0, 0.0, 0.0)  # the velocity set (a ramp's target)
        self._ramp: Ramp | None = None
        self._warnings = 0
        m = self.model
        self._qx = m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "x")]
        self._qy = m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "y")]
        self._qyaw = m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "yaw")]
        self._leds = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_MATERIAL, name)
                      for name in ("led_left", "led_right")]
        self._led_off = [tuple(m.mat_rgba[i]) for i in self._leds]
        self.audio: str | None = None
        self.volume = 1.0  # the speaker's level, a fraction of full volume (set_volume)
        self.steps = 0  # physics steps taken (the benchmark reports it)

    # -- the Robot interface ----------------------------------------------------------------

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp: Ramp | None = None) -> None:
        self.advance(t_ms)
        self._v = (float(v_x), float(v_y), float(v_theta))
        self._ramp = ramp
        self.data.act[:] = self._v if ramp is None else ramp.velocity(t_ms)
        self.data.ctrl[:] = 0.0

    def advance(self, t_ms: int) -> None:
        while (ramp := self._ramp) is not None and self._t < t_ms:
            self._ramp_batch(ramp, t_ms)
        if t_ms > self._t:
            self._step(t_ms - self._t)

    def _ramp_batch(self, ramp: Ramp, t_ms: int) -> None:
        """Step the next milliseconds of the ramp over which ctrl is constant (up to t_ms):
        up to the next millisecond where an axis starts or ends its ramp."""
        a = self._t
        b = ramp.breaks(a, min(t_ms, ramp.end))[0]
        act, ctrl = self.data.act, [0.0, 0.0, 0.0]
        start, end = ramp.velocity(a), ramp.velocity(b)
        for i in range(3):
            if ramp.ramping(i, a, b):  # ramping: ctrl is the axis's rate, from its exact value
                ctrl[i] = ramp.step[i] * 1000.0
                act[i] = start[i]
            else:  # before or after its ramp (exactly: no rounding carried on)
                act[i] = end[i]
        self.data.ctrl[:] = ctrl
        self._step(b - a)
        if self._t >= ramp.end:
            self.data.act[:] = ramp.target
            self.data.ctrl[:] = 0.0
            self._ramp = None

    def _step(self, ms: int) -> None:
        """Step `ms` milliseconds in chunks of at most CHUNK_STEPS steps; between two chunks
        a new MuJoCo warning stops the run (RobotFailure), and so does Ctrl-C (Interrupted)."""
        chunk_ms = max(1, CHUNK_STEPS // self.steps_per_ms)
        while ms > 0:
            part = min(ms, chunk_ms)
            n = part * self.steps_per_ms
            mujoco.mj_step(self.model, self.data, nstep=n)
            self.steps += n
            self._t += part
            ms -= part
            warnings = int(self.data.warning.number.sum())
            if warnings != self._warnings:
                self._warnings = warnings
                raise RobotFailure(self._describe_warnings(self._t))
            if ms:
                interrupt.check()

    def pose(self) -> Pose:
        q = self.data.qpos
        return Pose(float(q[self._qx]), float(q[self._qy]), float(q[self._qyaw]))

    def ghost(self) -> MujocoRobot:
        """A copy that steps on its own (its own `MjData`, the model shared: a ghost never
        writes the model's LED colours): where the robot will be at a later millisecond,
        without stepping it. Stepping the robot itself to that millisecond would cut a ramp's
        batch there, and its activation is written exactly at each cut."""
        twin = copy.copy(self)
        twin.data = copy.copy(self.data)
        return twin

    # -- beyond the interface ---------------------------------------------------------------

    @property
    def velocity(self) -> tuple[float, float, float]:
        """The velocity setpoint now (within a ramp: the one reached at this ms)."""
        return self._ramp.velocity(self._t) if self._ramp is not None else self._v

    @property
    def time_ms(self) -> int:
        return self._t

    def set_led(self, rgb: tuple[float, float, float] | None) -> None:
        """Both LED strips show `rgb` (None: off); visible in the model's materials."""
        for i, off in zip(self._leds, self._led_off, strict=True):  # one colour per strip
            self.model.mat_rgba[i] = off if rgb is None else (*rgb, 1.0)

    def led_rgba(self) -> tuple[float, ...]:
        return tuple(float(c) for c in self.model.mat_rgba[self._leds[0]])

    def set_audio(self, track: str | None) -> None:
        """The speaker: audio is state (what plays), not sound."""
        self.audio = track

    def set_volume(self, level: float) -> None:
        """The speaker's level (a fraction of full volume): every track plays at it, audio
        commands carry no volume. The governor sets the profile's `max_volume`."""
        self.volume = min(1.0, max(0.0, float(level)))

    def _describe_warnings(self, t_ms: int) -> str:
        members = mujoco.mjtWarning.__members__
        names = sorted((k for k in members if k != "mjNWARNING"), key=lambda k: int(members[k]))
        found = [f"{name.removeprefix('mjWARN_')} x{int(self.data.warning[i].number)}"
                 for i, name in enumerate(names) if self.data.warning[i].number]
        last = f": {_WARNINGS[-1]}" if _WARNINGS else ""
        return (f"the physics became unstable by {t_ms} ms (MuJoCo warned "
                f"{', '.join(found)}{last}; it resets the state instead of failing)")
