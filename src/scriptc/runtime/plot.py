"""Pictures of a run (`scriptc run --plot FILE.png|.svg`, docs/robot.md): the robot's trajectory
seen from above with the scenario's people, objects and obstacles, and below it a timeline of
the three tracks (move, led, audioout) with the instruction blocks, LED commands drawn in their
own colour.

`PathRecorder` wraps a robot backend and samples its pose every `every_ms` of simulated time
(the physics is stepped in those chunks: the same steps, so the same result; only `--plot`
uses it). `plot_run` draws from the recorded path and the trace's events. matplotlib (the
`plot` extra) is imported only inside `plot_run`, with the non-interactive Agg backend.
"""

from __future__ import annotations

import math

from scriptc.runtime.robots import Pose


class PathRecorder:
    """A `Robot` wrapper that records `(t_ms, x, y, theta)` samples."""

    def __init__(self, robot, every_ms: int = 20) -> None:
        self.robot = robot
        self.name = getattr(robot, "name", type(robot).__name__)
        self.every = every_ms
        self.t = 0
        p = robot.pose()
        self.samples: list[tuple[int, float, float, float]] = [(0, p.x, p.y, p.theta)]

    def __getattr__(self, name: str):
        return getattr(self.robot, name)

    def advance(self, t_ms: int) -> None:
        while self.t < t_ms:
            step = min(t_ms, (self.t // self.every + 1) * self.every)
            self.robot.advance(step)
            self.t = step
            p = self.robot.pose()
            self.samples.append((step, p.x, p.y, p.theta))

    def set_velocity(self, t_ms: int, v_x: float, v_y: float, v_theta: float,
                     ramp=None) -> None:
        self.advance(t_ms)
        self.robot.set_velocity(t_ms, v_x, v_y, v_theta, ramp=ramp)

    def pose(self) -> Pose:
        return self.robot.pose()


_TRACKS = ("move", "led", "audioout")
_CLASS_STYLE = {"Human": ("o", "#d62728"), "Object": ("s", "#2ca02c"),
                "Obstacle": ("X", "#555555")}


def _intervals(events):
    """(track, start, end, command) of every command that ran, from cmd_start/cmd_stop."""
    running, out = {}, []
    end_t = 0
    for e in events:
        end_t = max(end_t, e["t"])
        if e["event"] == "cmd_start":
            running[e["track"]] = (e["t"], e["command"])
        elif e["event"] == "cmd_stop" and e["track"] in running:
            start, command = running.pop(e["track"])
            out.append((e["track"], start, e["t"], command))
    for track, (start, command) in running.items():
        out.append((track, start, end_t, command))
    return out


def plot_run(events: list[dict], path: str, samples=None, scenario=None) -> None:
    """Draw the run into `path` (.png or .svg)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt
    from matplotlib.patches import Circle, FancyArrow

    end = max((max(e["t"], e.get("at_rest_ms", 0)) for e in events), default=0) or 1
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 9),
                                      gridspec_kw={"height_ratios": [3, 1.3]})
    # -- the trajectory from above -----------------------------------------------------------
    xs = [s[1] for s in samples] if samples else [0.0]
    ys = [s[2] for s in samples] if samples else [0.0]
    top.plot(xs, ys, color="#1f77b4", lw=1.8, label="robot")
    top.add_patch(Circle((xs[0], ys[0]), 0.22, fill=False, ls=":", color="#1f77b4"))
    if samples:
        t, x, y, th = samples[-1]
        top.add_patch(Circle((x, y), 0.22, fill=False, color="#1f77b4"))
        top.add_patch(FancyArrow(x, y, 0.3 * math.cos(th), 0.3 * math.sin(th), width=0.02,
                                 color="#1f77b4", length_includes_head=True))
    seen = set()
    for entity in getattr(scenario, "entities", ()) or ():
        marker, colour = _CLASS_STYLE.get(entity.cls, ("D", "#9467bd"))
        x0, y0 = entity.position(entity.start)
        x1, y1 = entity.position(end)
        if (x0, y0) != (x1, y1):
            top.plot([x0, x1], [y0, y1], ls="--", color=colour, lw=1)
        top.plot([x1], [y1], marker=marker, color=colour, ms=10, ls="none",
                 label=entity.cls if entity.cls not in seen else None)
        seen.add(entity.cls)
        top.annotate(entity.objectid.partition("/")[2], (x1, y1), textcoords="offset points",
                     xytext=(6, 6), fontsize=8)
        xs += [x0, x1]
        ys += [y0, y1]
    pad = 0.5
    top.set_xlim(min(xs) - pad, max(xs) + pad)
    top.set_ylim(min(ys) - pad, max(ys) + pad)
    top.set_aspect("equal", adjustable="box")
    top.grid(True, lw=0.4, alpha=0.6)
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    top.legend(loc="best", fontsize=8)
    title = next((e for e in events if e["event"] == "session_end"), None)
    top.set_title("trajectory from above" + (f" ({title['outcome']} at {title['time_ms']} ms, "
                                             f"robot {events[0].get('robot', '?')})"
                                             if title else ""))
    # -- the timeline ------------------------------------------------------------------------
    lane = {name: i for i, name in enumerate(reversed(_TRACKS))}
    for track, start, stop, command in _intervals(events):
        y = lane[track]
        width = max(stop - start, 1) / 1000.0
        if track == "led":
            on = command.get("turnas") == 1
            colour = (command["r"], command["g"], command["b"]) if on else (0.15, 0.15, 0.15)
            bottom.broken_barh([(start / 1000.0, width)], (y - 0.35, 0.7), facecolors=[colour],
                               edgecolors="#333333", lw=0.4)
        elif track == "move":
            moving = any(command[k] for k in ("v_x", "v_y", "v_theta"))
            bottom.broken_barh([(start / 1000.0, width)], (y - 0.35, 0.7),
                               facecolors=["#1f77b4" if moving else "#c7d7ea"],
                               edgecolors="#333333", lw=0.4)
        else:
            silent = command.get("track_path") == "Silence"
            bottom.broken_barh([(start / 1000.0, width)], (y - 0.35, 0.7),
                               facecolors=["#dddddd" if silent else "#ff7f0e"],
                               edgecolors="#333333", lw=0.4)
    for e in events:
        if e["event"] == "block":
            bottom.axvline(e["t"] / 1000.0, color="#888888", lw=0.6, ls=":")
        elif e["event"] == "governor":
            led = "led-flash" in e["reasons"]
            y = lane["led" if led else "move"]
            bottom.plot([e["t"] / 1000.0], [y + 0.45], marker="v", color="#d62728", ms=5)
            # a ramp, or an LED onset held dark: a red bar under the lane for its duration
            until = e["t"] + e["ramp_ms"] if "ramp_ms" in e else e.get("until")
            if until is not None:
                bottom.broken_barh([(e["t"] / 1000.0, (until - e["t"]) / 1000.0)],
                                   (y - 0.45, 0.08), facecolors=["#d62728"])
    bottom.set_yticks([lane[t] for t in _TRACKS], list(_TRACKS))
    bottom.set_ylim(-0.6, len(_TRACKS) - 0.2)
    bottom.set_xlim(0, end / 1000.0)
    bottom.set_xlabel("time (s); dotted: a block is issued; red marks: the governor clamped "
                      "(bars: ramps, LEDs held dark)")
    bottom.set_title("tracks per block")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
