"""The HTML report of a run (`scriptc run --report`, `scriptc report TRACE`, `scriptc test
--report`; docs/views.md): one self-contained page, scrubbed with one cursor.

The page shows the summary at the top (how the run ended and when, the goals, the errors, the
governor's clamps), the room from above (the robot's path, the people, objects and obstacles
and their paths), the three tracks on one timeline (the LEDs painted in the colour they were
lit, audio named, moves with their speed), the velocity, the events on the same time axis
(jumps with their outcome, rules, the operator, the governor's clamps in a warning colour,
errors), and the flow of each script with the block running highlighted. Hovering (or dragging
over) any chart moves the cursor of every view.

How it is made: the data of the run (`scriptc.views.run_data`) is a JSON model whose numeric
arrays point into one buffer of float32 values; the model and the buffer are deflated (zlib)
and put into the page as base64, which the page inflates with the browser's
`DecompressionStream`. The page's script (`assets/report.js`), its style (`assets/report.css`)
and uPlot (`assets/uPlot.iife.min.js`, MIT, vendored with its licence) are inlined into the
template (`assets/report.html`); a Content-Security-Policy forbids every load from outside.
The same events give the same bytes (no clock, no random, no set order; zlib at one level).

Everything the run's text puts into the page is escaped: the summary is HTML escaped here, and
the page's script writes every text of the model with `textContent`, never as markup.
"""

from __future__ import annotations

import base64
import html
import json
import re
import struct
import sys
import zlib
from array import array
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources

from scriptc.ir import nodes as ir
from scriptc.numbers import json_dumps
from scriptc.runtime.commands import BlockAddress
from scriptc.runtime.interp import IRProgram, JumpTargetError
from scriptc.runtime.recorded import map_positions
from scriptc.runtime.trace import Event
from scriptc.views import run_data
from scriptc.views.run_data import Sample

__all__ = ["ASSETS", "TEMPLATE_FILES", "FlowBlock", "ScriptSource", "flow_of", "page_model",
           "report_html", "template_digest"]

# The files of the page, in `assets/`: the template and what is inlined into it.
TEMPLATE_FILES = ("report.html", "report.css", "report.js")
ASSETS = (*TEMPLATE_FILES, "uPlot.iife.min.js", "uPlot.min.css", "uPlot.LICENSE")
# The version of the model the page's script reads.
MODEL_VERSION = 1
# A placeholder of the template (`@@NAME@@`), replaced once, in one pass.
_PLACEHOLDER = re.compile(r"@@([A-Z_]+)@@")


@dataclass(frozen=True, slots=True)
class ScriptSource:
    """A script the run loaded (a `script_load` of the trace): its activity name, its path as
    the trace names it, and its IR (None when it could not be read: `problem` says why, and
    the page shows that instead of its flow)."""

    script: str
    path: str
    ir: ir.Script | None = None
    problem: str = ""


@dataclass(frozen=True, slots=True)
class FlowBlock:
    """A block of a script's flow: its path (`goal0/act0/blk2`), kind (`instruction`, `jump`,
    `terminus`, `sensor`), label, what it does in a few words (`text`), its goal and action
    (indices), for a jump the indices of its true and false targets (the number of blocks:
    past the end; -1: a label no block carries), whether a path from the start reaches it,
    whether its false edge is never taken (a condition that cannot be false), its commands one
    a line (`detail`, at most `DETAIL_LINES`) and the colours of its lights."""

    path: str
    kind: str
    label: str
    text: str
    goal: int
    action: int
    targets: tuple[int, int] | None = None
    reachable: bool = True
    never: bool = False
    detail: str = ""
    colours: tuple[str, ...] = ()


# A block's commands listed in its tooltip, at most; its lights' colours shown, at most.
DETAIL_LINES = 12
COLOURS = 8


def _seconds(ms: int) -> str:
    return f"{ms / 1000:g} s"


def _instruction_text(program: IRProgram, i: int) -> str:
    commands = program.instructions[i]
    parts = []
    if commands.moves:
        moving = [m for m in commands.moves if m.v_x or m.v_y or m.v_theta]
        fastest = max((abs(complex(m.v_x, m.v_y)) for m in moving), default=0.0)
        parts.append(f"move x{len(commands.moves)}" + (f" up to {fastest:.2g} m/s"
                                                       if fastest else ""))
    if commands.leds:
        parts.append(f"led x{len(commands.leds)}")
    parts += [f"audio {a.track_path}" for a in commands.audios if a.track_path != "Silence"]
    parts.append(_seconds(commands.length))
    return ", ".join(parts)


def flow_of(script: ir.Script, path: str = "") -> list[FlowBlock]:
    """The blocks of `script` in execution order, as `scriptc graph` draws them
    (`scriptc.views.graph.flow_graph`: the jumps' targets as the block reader follows them, the
    blocks no path reaches); a script that was not checked, whose jump names a label no block
    carries, gets its flow without that edge."""
    from scriptc.views.graph import flow_graph

    program = IRProgram(script, path)
    try:
        graph = flow_graph(script)
    except JumpTargetError:
        graph = None
    never = {e.source for e in graph.edges if e.never} if graph is not None else set()
    nodes = {n.index: n for n in graph.nodes if n.index is not None} if graph else {}
    out = []
    for i, (address, block) in enumerate(program.blocks):
        label = block.label.text if block.label is not None else ""
        where = BlockAddress(*address).path
        goal, action = address[0], address[1]
        node = nodes.get(i)
        lines = [f"{line.track} {line.text}".strip() for line in node.lines] if node else []
        detail = "\n".join(lines[:DETAIL_LINES])
        if len(lines) > DETAIL_LINES:
            detail += f"\n… {len(lines) - DETAIL_LINES} more"
        colours = tuple(dict.fromkeys(line.colour for line in node.lines
                                      if line.colour is not None))[:COLOURS] if node else ()
        reachable = node.reachable if node is not None else True
        if isinstance(block, ir.InstructionBlock):
            kind, text = "instruction", _instruction_text(program, i)
        elif isinstance(block, ir.SensorBlock):
            kind, text = "sensor", ", ".join(p.value for p in block.payload)
        elif isinstance(block, ir.TerminusBlock):
            kind, text = "terminus", "the script ends"
        else:
            assert isinstance(block, ir.JumpBlock)
            found = []
            for name in (block.true_target, block.false_target):
                try:
                    found.append(program.target(name, i))
                except JumpTargetError:
                    found.append(-1)
            text = program.conditions[i]
            out.append(FlowBlock(where, "jump", label, text, goal, action, (found[0], found[1]),
                                 reachable, f"b{i}" in never, text))
            continue
        out.append(FlowBlock(where, kind, label, text, goal, action, None, reachable, False,
                             detail, colours))
    return out


# -- the model ----------------------------------------------------------------------------------


class _Buffer:
    """The float32 values of the model's arrays, one after the other; an array in the model is
    `{"@": [offset, count]}` into them."""

    def __init__(self) -> None:
        self.values = array("f")

    def add(self, values: Iterable[float]) -> dict[str, list[int]]:
        start = len(self.values)
        self.values.extend(values)
        return {"@": [start, len(self.values) - start]}

    def columns(self, rows: Sequence[Sequence[float]], names: str) -> dict[str, object]:
        """Each column of `rows` as an array, named by the words of `names` in order."""
        keys = names.split()
        return {key: self.add(row[k] for row in rows) for k, key in enumerate(keys)}

    def data(self) -> bytes:
        values = array("f", self.values)
        if sys.byteorder == "big":
            values.byteswap()  # the page reads little-endian float32
        return values.tobytes()


class _Texts:
    """The model's texts, each once; an index stands for a text in the arrays."""

    def __init__(self) -> None:
        self.texts: list[str] = []
        self.index: dict[str, int] = {}

    def __call__(self, text: str) -> int:
        i = self.index.get(text)
        if i is None:
            i = self.index[text] = len(self.texts)
            self.texts.append(text)
        return i


@cache
def _footprint() -> float:
    from scriptc.runtime.recorded import footprint_radius

    return footprint_radius()


def page_model(events: Sequence[Event], sources: Sequence[ScriptSource] = (),
               samples: Sequence[Sample] | None = None,
               summary: run_data.Summary | None = None) -> tuple[dict[str, object], bytes]:
    """The model the page draws (JSON data) and the float32 buffer its arrays point into.
    `samples` is the robot's recorded path (`PathRecorder.samples`); without it the path is
    reconstructed from the trace (`run_data.reconstruct_path`)."""
    buffer, texts = _Buffer(), _Texts()
    recorded = samples is not None
    end = run_data.end_ms(events)
    if summary is None:
        summary = run_data.summarize_run(events)
    path = list(samples) if samples is not None else run_data.reconstruct_path(events, end=end)
    gap = run_data.path_gap(path, events)
    thin = run_data.thin_path(path)
    entities = []
    for objectid, points in map_positions(events, path)[0].items():
        entities.append({"id": objectid, "cls": objectid.partition("/")[0],
                         **buffer.columns(points, "t x y")})
    segments = run_data.track_segments(events, end)
    move = [(s.start, s.end, *s.values) for s in segments["move"]]
    led = [(s.start, s.end, *s.values, s.lit) for s in segments["led"]]
    audio = [(s.start, s.end, texts(s.name)) for s in segments["audioout"]]
    velocity = [(t, *v) for t, v in run_data.velocity_steps(events)]
    # In time order (a clamp is written when the governor applies it: after later events).
    marks = sorted(((m.t, m.lane, m.style, texts(m.text)) for m in run_data.markers(events)),
                   key=lambda row: row[0])
    loads, visited = run_data.visits(events)
    visited.sort(key=lambda v: v.t)
    flows, load_flow = _flows(loads, sources)
    index = [{b.path: i for i, b in enumerate(flow.blocks)} for flow in flows]
    visit_rows = [(v.t, v.load, index[load_flow[v.load]].get(v.path, -1), v.kind)
                  for v in visited]
    pose = summary.pose
    model: dict[str, object] = {
        "version": MODEL_VERSION,
        "end": end,
        "robot": {"radius": _footprint(), "recorded": recorded,
                  "gap": None if gap is None else round(gap, 4),
                  "end": None if pose is None else list(pose)},
        "path": buffer.columns(thin, "t x y h"),
        "entities": entities,
        "tracks": {"move": buffer.columns(move, "s e vx vy vw"),
                   "led": buffer.columns(led, "s e r g b lit"),
                   "audioout": buffer.columns(audio, "s e name")},
        "velocity": buffer.columns(velocity, "t vx vy vw"),
        "lanes": list(run_data.LANES),
        "markers": buffer.columns(marks, "t lane style text"),
        "loads": [{"script": s, "path": p, "flow": f}
                  for (s, p), f in zip(loads, load_flow, strict=True)],
        "flows": [{"script": f.script, "path": f.path, "problem": f.problem, "goals": f.goals,
                   "blocks": [_block_row(b) for b in f.blocks]} for f in flows],
        "visits": buffer.columns(visit_rows, "t load block kind"),
        "texts": texts.texts,
    }
    return model, buffer.data()


def _block_row(b: FlowBlock) -> list[object]:
    """A block as the page reads it: path, kind, label, text, goal, action, the true and false
    targets (-2: not a jump), reachable, never, detail, colours."""
    return [b.path, b.kind, b.label, b.text, b.goal, b.action,
            *(b.targets if b.targets is not None else (-2, -2)), int(b.reachable),
            int(b.never), b.detail, list(b.colours)]


@dataclass(frozen=True, slots=True)
class _Flow:
    script: str
    path: str
    problem: str
    goals: list[str]
    blocks: list[FlowBlock]


def _flows(loads: Sequence[tuple[str, str]], sources: Sequence[ScriptSource]
           ) -> tuple[list[_Flow], list[int]]:
    """One flow per script the run loaded (by name and path, each once: without its IR, a flow
    of no block that says why), and the flow of each load."""
    flows: list[_Flow] = []
    by_key: dict[tuple[str, str], int] = {}
    given = {(s.script, s.path): s for s in sources}
    load_flow = []
    for key in loads:
        if key not in by_key:
            source = given.get(key) or ScriptSource(*key, None, "the report was not given it")
            script = source.ir
            by_key[key] = len(flows)
            flows.append(_Flow(*key, source.problem,
                               [g.id.text for g in script.goals] if script is not None else [],
                               flow_of(script, key[1]) if script is not None else []))
        load_flow.append(by_key[key])
    return flows, load_flow


def _payload(model: dict[str, object], data: bytes) -> str:
    """The model and its buffer as the page reads them: the JSON's length (4 bytes, little
    endian), the JSON, zeros to a multiple of 4, the buffer; deflated, then base64."""
    text = json_dumps(model, ensure_ascii=False, separators=(",", ":")).encode("utf-8")
    pad = b"\0" * (-(4 + len(text)) % 4)
    raw = struct.pack("<I", len(text)) + text + pad + data
    return base64.b64encode(zlib.compress(raw, 9)).decode("ascii")


# -- the page -----------------------------------------------------------------------------------


@cache
def _asset(name: str) -> str:
    return resources.files("scriptc.views").joinpath("assets", name).read_text("utf-8")


def template_digest() -> str:
    """A digest of the page's template, style and script: what a picture of the page
    (docs/img/report-*.png) was made from."""
    import hashlib

    digest = hashlib.sha256()
    for name in TEMPLATE_FILES:
        digest.update(name.encode() + b"\0" + _asset(name).encode("utf-8") + b"\0")
    return digest.hexdigest()


def _inline(text: str, tag: str) -> str:
    """`text` to put between `<tag>` and `</tag>`: it must not close the element (the
    vendored and written files are held to that here, not rewritten)."""
    if f"</{tag}" in text.lower() or "<!--" in text:
        raise ValueError(f"an inlined asset contains `</{tag}` or `<!--`")
    return text


def _summary_html(s: run_data.Summary, sources: Sequence[ScriptSource],
                  model: dict[str, object]) -> str:
    """The summary at the top of the page, as HTML (every text escaped)."""
    e = html.escape
    rows: list[tuple[str, str]] = []
    outcome = (f"<b class=\"outcome {e(s.outcome)}\">{e(s.outcome)}</b> at {s.time_ms:,} ms "
               f"({s.time_ms / 1000:.3f} s simulated)")
    if s.at_rest_ms is not None and s.at_rest_ms != s.time_ms:
        outcome += f", at rest at {s.at_rest_ms:,} ms"
    rows.append(("outcome", outcome))
    rows.append(("scripts", ", ".join(f"<code>{e(x)}</code>" for x in s.scripts) or "none"))
    # The goals of the scripts that ran (each script once, by name), and those reached.
    goals_of = {src.script: len(src.ir.goals) for src in sources if src.ir is not None}
    reached = sum(1 for _sc, _g, r in s.goals if r == "reached")
    known = sum(goals_of.values())
    goals = ", ".join(f"<code>{e(g)}</code> <span class=\"{e(r)}\">{e(r)}</span>"
                      for _sc, g, r in s.goals) or "no goal recorded"
    if known:
        goals = f"{reached} of {known} reached: " + goals
    rows.append(("goals", goals))
    if s.errors:
        errors = "".join(f"<li><span class=\"t\">{t:,} ms</span> <code>{e(code)}</code>"
                         f"{' (fatal)' if fatal else ''}: {e(message)}</li>"
                         for t, code, message, fatal in s.errors)
        rows.append(("errors", f"<span class=\"error\">{len(s.errors)}</span><ul>{errors}</ul>"))
    else:
        rows.append(("errors", "none"))
    if s.governed:
        why = ", ".join(f"{e(r)} {n}" for r, n in s.reasons)
        rows.append(("governor", f"<span class=\"warning\">{s.clamps} clamps</span> ({why})"
                     if s.clamps else "on, no clamp"))
    else:
        rows.append(("governor", "off"))
    robot = e(s.robot or "?")
    if s.pose is not None:
        x, y, theta = s.pose
        robot += f", ended at x = {x:.3f} m, y = {y:.3f} m, θ = {theta:.3f} rad"
    rows.append(("robot", robot))
    if s.scenario:
        rows.append(("scenario", f"<code>{e(s.scenario)}</code>"))
    notes = []
    info = model["robot"]
    assert isinstance(info, dict)
    if not info["recorded"]:
        gap = info["gap"]
        note = "the path is reconstructed from the trace's velocity changes"
        if isinstance(gap, float) and gap >= 0.01:
            note += f"; it ends {gap:.2f} m from where the run ended (marked ✕)"
        notes.append(note)
    notes += [f"no flow for <code>{e(src.script)}</code>: {e(src.problem)}" for src in sources
              if src.ir is None and src.problem]
    if notes:
        rows.append(("notes", "<br>".join(notes)))
    rows.append(("events", f"{s.events:,}"))
    return "\n".join(f"<tr><th>{name}</th><td>{value}</td></tr>" for name, value in rows)


def report_html(events: Sequence[Event], sources: Sequence[ScriptSource] = (), *,
                samples: Sequence[Sample] | None = None, title: str | None = None) -> str:
    """The page of the run whose trace is `events`: `sources` are the scripts it loaded (for
    their flows), `samples` the robot's recorded path (else reconstructed), `title` the
    page's (default: the scripts and how the run ended)."""
    summary = run_data.summarize_run(events)
    model, data = page_model(events, sources, samples, summary)
    if title is None:
        title = (f"{', '.join(summary.scripts) or 'a run'}: {summary.outcome} at "
                 f"{summary.time_ms / 1000:.3f} s")
    parts = {
        "TITLE": html.escape(title),
        "STYLE": _inline(_asset("uPlot.min.css") + "\n" + _asset("report.css"), "style"),
        "SUMMARY": _summary_html(summary, sources, model),
        "DATA": _payload(model, data),
        "UPLOT": _inline(_asset("uPlot.iife.min.js"), "script"),
        "SCRIPT": _inline(_asset("report.js"), "script"),
    }
    template = _asset("report.html")
    return _PLACEHOLDER.sub(lambda m: parts[m.group(1)], template)


def model_of_page(page: str) -> tuple[dict[str, object], bytes]:
    """The model and buffer a page carries (the inverse of `_payload`, for tests and tools)."""
    found = re.search(r'<script type="application/x-scriptc-run" id="run">([^<]*)</script>', page)
    if found is None:
        raise ValueError("not a scriptc report: no run data in the page")
    raw = zlib.decompress(base64.b64decode(found.group(1)))
    (n,) = struct.unpack("<I", raw[:4])
    model = json.loads(raw[4:4 + n].decode("utf-8"))
    start = 4 + n + (-(4 + n) % 4)
    return model, raw[start:]
