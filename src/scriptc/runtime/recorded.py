"""What a run leaves to look at beside its trace, and what every view of a run reads from a
trace the same way: the robot's path (`PathRecorder` samples the backend's pose; `pose_at`
interpolates), where the map put each person, object and obstacle (`map_positions`), and
when each command of each track ran (`command_intervals`). The picture of `--plot`
(`runtime/plot.py`), the MCAP file (`views/mcap.py`) and the HTML report (`views/report.py`)
all place the robot and the people, and paint the tracks, with these functions.

A trace read from a file may hold anything: each function takes what it understands of an
event (a number that is a number, a text that is a text) and passes over the rest.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterable, Sequence

from scriptc.runtime.commands import TRACKS
from scriptc.runtime.robots import Pose, Ramp, Robot
from scriptc.runtime.trace import Event

__all__ = ["POSITIONED", "PathRecorder", "Sample", "command_intervals", "footprint_radius",
           "map_positions", "pose_at"]

# A recorded pose: (t_ms, x, y, theta).
Sample = tuple[int, float, float, float]

# The map's classes that have a position (`poses` updates: positionrho, positiontheta).
POSITIONED = ("Human", "Object", "Obstacle")


class PathRecorder:
    """A `Robot` wrapper that records `(t_ms, x, y, theta)` samples every `every_ms` of
    simulated time (the physics is stepped in those chunks: the same steps, so the same
    result)."""

    def __init__(self, robot: Robot, every_ms: int = 20) -> None:
        self.robot = robot
        self.name = getattr(robot, "name", type(robot).__name__)
        self.every = every_ms
        self.t = 0
        p = robot.pose()
        self.samples: list[Sample] = [(0, p.x, p.y, p.theta)]

    def __getattr__(self, name: str) -> object:
        """The backend's own attributes (`set_led`, `time_ms`, ...), as the backend has them."""
        return getattr(self.robot, name)

    def advance(self, t_ms: int) -> None:
        while self.t < t_ms:
            step = min(t_ms, (self.t // self.every + 1) * self.every)
            self.robot.advance(step)
            self.t = step
            p = self.robot.pose()
            self.samples.append((step, p.x, p.y, p.theta))

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp: Ramp | None = None) -> None:
        self.advance(t_ms)
        self.robot.set_velocity(t_ms, v_x, v_y, v_theta, ramp=ramp)

    def pose(self) -> Pose:
        return self.robot.pose()

    def ghost(self) -> Robot:
        """The backend's ghost (`Robot.ghost`): where the robot will be is not its path."""
        return self.robot.ghost()


def footprint_radius() -> float:
    """The radius of the robot's base in the MuJoCo model (`teo.xml`, geom `base`): what the
    views draw as the robot's footprint."""
    from importlib import resources
    from xml.etree import ElementTree

    model = resources.files("scriptc.runtime.robots").joinpath("teo.xml").read_text("utf-8")
    base = ElementTree.fromstring(model).find(".//geom[@name='base']")
    size = None if base is None else base.get("size")
    assert size is not None, "the shipped model's geom `base` has a size"
    return float(size.split()[0])


def pose_at(samples: Sequence[Sample], t_ms: int, times: Sequence[int] | None = None
            ) -> tuple[float, float, float]:
    """The robot's (x, y, theta) at `t_ms`, interpolated between the recorded samples (the
    origin facing +x before any). `times`: the samples' times, when the caller asks for many
    poses (made once, not at each call)."""
    if not samples:
        return 0.0, 0.0, 0.0
    if times is None:
        times = [s[0] for s in samples]
    i = bisect.bisect_right(times, t_ms)
    if i == 0:
        return samples[0][1:]
    if i == len(samples) or samples[i - 1][0] == t_ms:
        return samples[i - 1][1:]
    (t0, x0, y0, theta0), (t1, x1, y1, theta1) = samples[i - 1], samples[i]
    f = (t_ms - t0) / (t1 - t0)
    return x0 + f * (x1 - x0), y0 + f * (y1 - y0), theta0 + f * (theta1 - theta0)


def _number(value: object) -> float | None:
    """A finite JSON number (not a boolean), else None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def _t(event: Event) -> int:
    """An event's millisecond (0 when it has none that is a whole number >= 0)."""
    t = event.get("t")
    return t if isinstance(t, int) and not isinstance(t, bool) and t >= 0 else 0


def map_positions(events: Iterable[Event], samples: Sequence[Sample]
                  ) -> tuple[dict[str, list[tuple[int, float, float]]], list[str]]:
    """Where the map put each person, object and obstacle, in the world frame: for every
    applied `poses` update, the entity's `positionrho` and `positiontheta` (relative to the
    robot, as a sensor sends them; a message may carry one of the two, the other keeping its
    value) turned into world coordinates with the robot's pose at that millisecond. Returns
    `{objectid: [(t, x, y), ...]}`, each in time order and the ids in the order they first
    appear, and the ids the map knew without a position (only `tracking` updates, say)."""
    polar: dict[str, dict[str, float]] = {}
    paths: dict[str, list[tuple[int, float, float]]] = {}
    known: list[str] = []
    times = [s[0] for s in samples]
    for e in events:
        if e.get("event") != "update" or e.get("status") != "applied":
            continue
        objectid = e.get("objectid")
        if not isinstance(objectid, str) or objectid.partition("/")[0] not in POSITIONED:
            continue
        if objectid not in known:
            known.append(objectid)
        value = e.get("value")
        if e.get("attributename") != "poses" or not isinstance(value, dict):
            continue
        state = polar.setdefault(objectid, {})
        for key in ("positionrho", "positiontheta"):
            number = _number(value.get(key))
            if number is not None:
                state[key] = number
        if len(state) == 2:
            t = _t(e)
            x, y, theta = pose_at(samples, t, times)
            bearing = theta + state["positiontheta"]
            paths.setdefault(objectid, []).append(
                (t, x + state["positionrho"] * math.cos(bearing),
                 y + state["positionrho"] * math.sin(bearing)))
    return paths, [objectid for objectid in known if objectid not in paths]


def command_intervals(events: Iterable[Event], end: int | None = None
                      ) -> list[tuple[str, int, int, Event]]:
    """(track, start, end, command) of every command that ran, from `cmd_start` and
    `cmd_stop` events, by track (move, led, audioout) and time: a command started again
    without its stop ends at the new start, and one still running at the end runs to `end`
    (None: the last event's time)."""
    running: dict[str, tuple[int, Event]] = {}
    out: list[tuple[str, int, int, Event]] = []
    last = 0
    for e in events:
        t = _t(e)
        last = max(last, t)
        track = e.get("track")
        if not isinstance(track, str) or track not in TRACKS:
            continue
        if e.get("event") == "cmd_start":
            command = e.get("command")
            if track in running:  # a start without its stop: it ends here
                start, previous = running.pop(track)
                out.append((track, start, t, previous))
            running[track] = (t, command if isinstance(command, dict) else {})
        elif e.get("event") == "cmd_stop" and track in running:
            start, command = running.pop(track)
            out.append((track, start, t, command))
    stop = last if end is None else end
    out += [(track, start, max(start, stop), command)
            for track, (start, command) in running.items()]
    out.sort(key=lambda c: (TRACKS.index(c[0]), c[1], c[2]))
    return out
