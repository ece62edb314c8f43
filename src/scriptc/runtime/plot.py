"""Pictures of a run (`scriptc run --plot FILE.png|.svg`, docs/robot.md): the room seen from
above, with the robot's path, its footprint and heading, and every person, object and obstacle
the run knew, each labelled with its path over time; below it a timeline of the three tracks
(move, led, audioout) with the instruction blocks, LED commands drawn in their own colour, and
where the governor intervened.

People and objects come from two places: the scenario's placed `entities` (a path in the world
frame, drawn dashed from where they appear to where they are at the end) and the map updates
of the run (`poses`: a distance and a bearing relative to the robot, as a sensor sends them;
each turned into world coordinates with the robot's pose at that millisecond, so a scenario
made of `updates` shows its people where the robot would have seen them). The MCAP file of a
run (`--trace FILE.mcap`, views/mcap.py) places the robot and the people with the same
functions.

The robot's path is recorded by `runtime/recorded.py`'s `PathRecorder` (only `--plot`,
`--report` and `--trace FILE.mcap` use it), and the people placed and the commands timed by
its functions, which every view of a run shares. `draw_run` makes the figure from the recorded
path, the trace's events and the scenario; `plot_run` writes it. matplotlib (the `plot` extra) is
imported only inside them, with the non-interactive Agg backend.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from scriptc.runtime.recorded import (
    Sample,
    command_intervals,
    footprint_radius,
    map_positions,
)
from scriptc.runtime.trace import Event

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from scriptc.runtime.scenario import Scenario

_TRACKS = ("move", "led", "audioout")
# What each lane of the timeline shows: the track's name in the trace, and what it drives.
_LANE_LABELS = {"move": "move\n(wheels)", "led": "led\n(LEDs)", "audioout": "audioout\n(speaker)"}
_CLASS_STYLE = {"Human": ("o", "#d62728"), "Object": ("s", "#2ca02c"),
                "Obstacle": ("X", "#555555")}
_OTHER_STYLE = ("D", "#9467bd")
_ROBOT = "#1f77b4"
# An entity's path shows the time of each point up to this many points, else of the ends.
_TIMES_SHOWN = 8


def draw_run(events: list[Event], samples: Sequence[Sample] | None = None,
             scenario: Scenario | None = None) -> Figure:
    """The picture of a run, as a matplotlib Figure: above, the room seen from above (the
    robot's path and footprint, every person, object and obstacle the run knew, each labelled
    with its path over time); below, the timeline of the three tracks."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle, FancyArrow, Patch

    end = max((max(e["t"], e.get("at_rest_ms", 0)) for e in events), default=0) or 1
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 10),
                                      gridspec_kw={"height_ratios": [3, 1.5]})
    # -- the room from above -----------------------------------------------------------------
    xs = [s[1] for s in samples] if samples else [0.0]
    ys = [s[2] for s in samples] if samples else [0.0]
    radius = footprint_radius()
    top.plot(xs, ys, color=_ROBOT, lw=1.8, label="robot's path")
    top.add_patch(Circle((xs[0], ys[0]), radius, fill=False, ls=":", color=_ROBOT))
    x, y, th = (samples[-1][1:] if samples else (0.0, 0.0, 0.0))
    top.add_patch(Circle((x, y), radius, fill=False, color=_ROBOT,
                         label=f"robot's footprint (r {radius:g} m; dotted: at the start)"))
    top.add_patch(FancyArrow(x, y, 0.3 * math.cos(th), 0.3 * math.sin(th), width=0.02,
                             color=_ROBOT, length_includes_head=True, label="robot's heading"))
    xs += [x - radius, x + radius]
    ys += [y - radius, y + radius]

    def entity(objectid: str, path: list[tuple[int, float, float]], style: str) -> None:
        """One entity: its path (t, x, y) in time order, the time beside each point (the
        first and the last only, when there are many), its id beside the last."""
        cls = objectid.partition("/")[0]
        marker, colour = _CLASS_STYLE.get(cls, _OTHER_STYLE)
        (_, x0, y0), (_, x1, y1) = path[0], path[-1]
        if len(path) > 1:
            top.plot([p[1] for p in path], [p[2] for p in path], ls=style, color=colour, lw=1,
                     marker="." if style == "-" else None, ms=4)
            top.plot([x0], [y0], marker=marker, color=colour, mfc="none", ms=8, ls="none")
        timed = path if len(path) <= _TIMES_SHOWN else [path[0], path[-1]]
        for t, px, py in timed:
            top.annotate(f"{t / 1000:g} s", (px, py), textcoords="offset points",
                         xytext=(6, -10), fontsize=7, color="#555555")
        top.plot([x1], [y1], marker=marker, color=colour, ms=10, ls="none",
                 label=cls if cls not in classes else None)
        classes.add(cls)
        top.annotate(objectid, (x1, y1), textcoords="offset points", xytext=(6, 6), fontsize=8)
        xs.extend(p[1] for p in path)
        ys.extend(p[2] for p in path)

    classes: set[str] = set()
    entities = scenario.entities if scenario is not None else []
    placed = {e.objectid for e in entities}
    for placed_entity in entities:
        start = placed_entity.start
        stop = max(start, end if placed_entity.stop is None else min(placed_entity.stop, end))
        entity(placed_entity.objectid, [(start, *placed_entity.position(start)),
                                        (stop, *placed_entity.position(stop))], "--")
    sent, no_position = map_positions(events, samples or [])
    for objectid, points in sent.items():
        if objectid not in placed:
            entity(objectid, points, "-")
    extra = []
    if placed:
        extra.append(Line2D([], [], ls="--", color="#777777", lw=1,
                            label="path in the scenario (hollow: start)"))
    if any(objectid not in placed for objectid in sent):
        extra.append(Line2D([], [], ls="-", marker=".", color="#777777", lw=1,
                            label="positions the map was sent (hollow: first)"))
    no_position = [objectid for objectid in no_position if objectid not in placed]
    if no_position:
        top.text(0.01, 0.01, "known, without a position: " + ", ".join(no_position),
                 transform=top.transAxes, fontsize=8, va="bottom")
    pad = 0.5
    top.set_xlim(min(xs) - pad, max(xs) + pad)
    top.set_ylim(min(ys) - pad, max(ys) + pad)
    top.set_aspect("equal", adjustable="box")
    top.grid(True, lw=0.4, alpha=0.6)
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    handles, _labels = top.get_legend_handles_labels()
    top.legend(handles=handles + extra, loc="best", fontsize=8)
    title = next((e for e in events if e["event"] == "session_end"), None)
    top.set_title("from above" + (f" ({title['outcome']} at {title['time_ms']} ms, "
                                  f"robot {events[0].get('robot', '?')})" if title else ""))
    # -- the timeline ------------------------------------------------------------------------
    lane = {name: i for i, name in enumerate(reversed(_TRACKS))}
    for track, start, stop, command in command_intervals(events):
        y = lane[track]
        width = max(stop - start, 1) / 1000.0
        colour: tuple[float, float, float] | str
        if track == "led":
            on = command.get("turnas") == 1
            colour = (command["r"], command["g"], command["b"]) if on else (0.15, 0.15, 0.15)
        elif track == "move":
            moving = any(command[k] for k in ("v_x", "v_y", "v_theta"))
            colour = "#1f77b4" if moving else "#c7d7ea"
        else:
            colour = "#dddddd" if command.get("track_path") == "Silence" else "#ff7f0e"
        bottom.broken_barh([(start / 1000.0, width)], (y - 0.35, 0.7), facecolors=[colour],
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
    bottom.set_yticks([lane[t] for t in _TRACKS], [_LANE_LABELS[t] for t in _TRACKS])
    bottom.set_ylim(-0.6, len(_TRACKS) - 0.2)
    bottom.set_xlim(0, end / 1000.0)
    bottom.set_xlabel("time (s)")
    bottom.set_ylabel("track")
    bottom.set_title("the tracks over time")
    bottom.legend(handles=[
        Patch(facecolor="#1f77b4", label="moving"), Patch(facecolor="#c7d7ea", label="still"),
        Patch(facecolor="#33cc55", label="LEDs (their colour)"),
        Patch(facecolor="#ff7f0e", label="audio"), Patch(facecolor="#dddddd", label="Silence"),
        Line2D([], [], color="#888888", lw=0.6, ls=":", label="a block is issued"),
        Line2D([], [], color="#d62728", marker="v", ls="none", label="the governor clamped"),
        Patch(facecolor="#d62728", label="a ramp, or LEDs held dark"),
    ], loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=4, fontsize=8)
    fig.tight_layout()
    return fig


def plot_run(events: list[Event], path: str, samples: Sequence[Sample] | None = None,
             scenario: Scenario | None = None) -> None:
    """Draw the run into `path` (.png or .svg; WriteError when it cannot be written)."""
    from matplotlib import pyplot as plt

    fig = draw_run(events, samples, scenario)
    # Drawn into memory, then written by the one writer (a link's target, a FIFO, a file
    # replaced atomically; WriteError when it cannot be written).
    import io
    import os

    from scriptc.writing import write_file

    picture = io.BytesIO()
    fig.savefig(picture, format=os.path.splitext(path)[1].lstrip(".").lower())
    plt.close(fig)
    write_file(path, picture.getvalue())
