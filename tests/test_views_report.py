"""The report of a run (views/report.py, views/run_data.py, ops/report.py, `scriptc report`,
`run --report`, `test --report`): the data the page draws, read from the trace and held to what
the run did; the same bytes for the same run; bad input as clear errors; the size of a
10-minute session. The page in a real browser: tests/test_report_browser.py."""

from __future__ import annotations

import json
import math
import re
import struct
import sys
from array import array
from collections import Counter
from itertools import pairwise
from pathlib import Path

import pytest
from click.testing import CliRunner

from scriptc.analysis.analyze import analyze_bytes
from scriptc.cli.main import cli
from scriptc.ops import programs
from scriptc.ops.report import TraceError, default_output, find_sources, read_trace
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.runtime.recorded import PathRecorder, map_positions
from scriptc.runtime.robots import make_robot
from scriptc.runtime.scenario import load_scenario
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.views import run_data
from scriptc.views.report import (
    ScriptSource,
    flow_of,
    model_of_page,
    page_model,
    report_html,
    template_digest,
)

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

# Too fast for the profile (speed clamps), no wait before the first move (a late ramp), the
# LEDs flashing faster than 3 Hz (onsets held dark), a light that stays off.
GOVERNED = """[gov]
[goal:g]
  [action]
    [b#fast#blk_inst: MV("0.8, 0.2, 2.0, 0, 700", "-0.3, 0, -1, 0, 500")
                      LD("1, 0, 0, 1, 0, 100", "0, 0, 0, 0, 0, 100", "0, 1, 0, 1, 0, 100",
                         "0, 0, 0, 0, 0, 100", "0, 0, 1, 1, 0, 100", "0, 0, 0, 0, 0, 100",
                         "1, 1, 1, 1, 0, 100", "1, 0, 1, 0, 0, 300")
                      AO("songs/hi.wav, 200, 600")]
    [b##blk_jump: CND({TRUE}) TRJMP() FLSJMP(fast)]
    [b##blk_terminus]
"""


def run_session(text: str, robot: str = "kinematic", governed: bool = True,
                world: str | None = None, until: int = 60_000, path: str = "a.script"
                ) -> tuple[list[dict], list[tuple[int, float, float, float]], object]:
    """Run a script in process with its path recorded: (events, samples, its IR)."""
    analysis = analyze_bytes(path, text.encode())
    assert analysis.script is not None, analysis.diagnostics  # errors of the profile let it run
    recorder = PathRecorder(make_robot(robot))
    trace = Trace()
    session = Session([programs.checked_program(analysis, path)],
                      scenario=load_scenario(world) if world else None, robot=recorder,
                      trace=trace, profile=DEFAULT_PROFILE if governed else None)
    session.run(until)
    return trace.events, recorder.samples, analysis.script


def example(name: str, robot: str = "kinematic", governed: bool = True):
    text = (EXAMPLES / f"{name}.script").read_text(encoding="utf-8")
    world = EXAMPLES / f"{name}.world.json"
    return run_session(text, robot, governed, str(world) if world.exists() else None,
                       path=str(EXAMPLES / f"{name}.script"))


def farthest(samples, path) -> float:
    """How far apart two paths are at the milliseconds both sampled (interpolating between
    samples along an arc would add its own error)."""
    recorded = {t: (x, y) for t, x, y, _ in samples}
    both = [(recorded[t], (x, y)) for t, x, y, _ in path if t in recorded]
    assert len(both) > len(path) // 2
    return max(math.dist(a, b) for a, b in both)


# -- the data of the page ------------------------------------------------------------------------


@pytest.mark.parametrize("governed", [True, False])
def test_the_path_from_the_trace_is_the_kinematic_robots_own(governed: bool) -> None:
    events, samples, _ = run_session(GOVERNED, governed=governed)
    if governed:
        reasons = {r for e in events if e["event"] == "governor" for r in e["reasons"]}
        assert {"speed", "angular-speed", "acceleration", "led-flash"} <= reasons
    path = run_data.reconstruct_path(events)
    # within a micrometre: a ramp that turns as it moves is summed by quadrature (Kinematics)
    assert farthest(samples, path) < 1e-6
    assert run_data.path_gap(path, events) < 1e-6
    assert path[-1][0] == run_data.end_ms(events)


@pytest.mark.parametrize("name", ["approach", "turn_taking", "test_act"])
def test_the_path_of_an_example_is_the_robots_own(name: str) -> None:
    events, samples, _ = example(name)
    assert farthest(samples, run_data.reconstruct_path(events)) < 1e-6


TRACES = sorted((ROOT / "tests" / "cases" / "runtime").glob("*.trace.jsonl"))


@pytest.mark.parametrize("trace", TRACES, ids=[t.name for t in TRACES])
def test_the_path_of_every_runtime_case_ends_where_its_run_ended(trace: Path) -> None:
    events = read_trace(str(trace))
    assert any(e["event"] == "session_end" for e in events)
    assert run_data.path_gap(run_data.reconstruct_path(events), events) < 1e-6


def test_a_sample_every_20_ms_and_at_most_max_samples() -> None:
    events = [{"t": 0, "event": "session_start"}, {"t": 0, "event": "velocity", "v_x": 0.1,
              "v_y": 0.0, "v_theta": 0.0, "cause": "script"},
              {"t": 10_000_000, "event": "session_end", "outcome": "until",
               "time_ms": 10_000_000, "pose": {"x": 1000.0, "y": 0.0, "theta": 0.0}}]
    path = run_data.reconstruct_path(events)
    assert len(path) <= run_data.MAX_SAMPLES + 2
    assert path[-1] == (10_000_000, pytest.approx(1000.0), 0.0, 0.0)
    short = run_data.reconstruct_path([*events[:2], {"t": 100, "event": "session_end",
                                                     "outcome": "completed", "time_ms": 100,
                                                     "pose": {"x": 0, "y": 0, "theta": 0}}])
    assert [s[0] for s in short] == [0, 20, 40, 60, 80, 100]


def test_thinning_keeps_the_ends_of_a_still_stretch() -> None:
    still = [(t, 1.0, 2.0, 0.5) for t in range(0, 200, 20)]
    moving = [(200 + t, 1.0 + t / 100, 2.0, 0.5) for t in range(20, 100, 20)]
    thin = run_data.thin_path([*still, *moving])
    assert thin[0] == still[0] and thin[1] == still[-1] and thin[2:] == moving
    assert len(run_data.thin_path([(t, t, 0.0, 0.0) for t in range(100)], most=10)) <= 11


def test_people_are_where_plot_puts_them() -> None:
    """The page's people are where `--plot` and the MCAP file put them: the one reading of the
    map's `poses` updates (`runtime.recorded.map_positions`)."""
    events, samples, _ = example("turn_taking")
    model, _buffer = page_model(events, samples=samples)
    placed = map_positions(events, samples)[0]
    assert placed and [e["id"] for e in model["entities"]] == list(placed)


def test_the_leds_are_painted_as_they_were_lit() -> None:
    events, _, _ = run_session(GOVERNED)
    led = run_data.track_segments(events)["led"]
    holds = [(e["t"], e["until"]) for e in events
             if e["event"] == "governor" and "led-flash" in e["reasons"]]
    assert holds
    for at, until in holds:  # not lit from the held onset to when the LEDs may show again
        assert any(s.lit == 2 and s.start == at for s in led)
        stop = until if until is not None else next(s.end for s in led if s.start == at)
        assert all(s.lit != 1 for s in led if s.start < stop and s.end > at)
    assert any(s.lit == 1 and s.values == (1.0, 0.0, 0.0) for s in led)
    assert any(s.lit == 0 for s in led)  # off, as the script asked
    assert all(a.end <= b.start for a, b in pairwise(led))  # in order


def test_moves_and_audio_are_segments_with_their_speed_and_name() -> None:
    events, _, _ = run_session(GOVERNED)
    tracks = run_data.track_segments(events)
    assert [(s.start, s.end, s.values) for s in tracks["move"][:2]] == [
        (0, 700, (0.8, 0.2, 2.0)), (700, 1200, (-0.3, 0.0, -1.0))]
    assert [(s.start, s.end, s.name) for s in tracks["audioout"][:1]] == [
        (200, 800, "songs/hi.wav")]


def test_markers_say_what_happened_in_their_lanes() -> None:
    events, _, _ = run_session(GOVERNED, until=3000)
    marks = run_data.markers(events)
    lanes = {run_data.LANES[m.lane] for m in marks}
    assert {"script", "jumps", "governor"} <= lanes
    governor = [m for m in marks if run_data.LANES[m.lane] == "governor"]
    assert all(m.style == run_data.WARNING for m in governor)
    assert any("held dark" in m.text for m in governor)
    jump = next(m for m in marks if run_data.LANES[m.lane] == "jumps")
    assert jump.style == run_data.HELD and jump.text.startswith("jump at goal0/act0/blk1")
    error = run_data.markers([{"t": 5, "event": "error", "code": "read", "message": "boom",
                               "fatal": True}])
    assert error[0].style == run_data.ERROR and "read (fatal): boom" in error[0].text


def test_the_summary_of_a_run() -> None:
    events, _, _ = run_session(GOVERNED)
    summary = run_data.summarize_run(events)
    assert summary.outcome == "completed" and summary.time_ms == 1200
    assert summary.at_rest_ms is not None and summary.at_rest_ms > 1200  # braking
    assert summary.goals == (("gov", "g", "reached"),) and summary.errors == ()
    clamps = [e for e in events if e["event"] == "governor"]
    assert summary.governed and summary.clamps == len(clamps)
    assert dict(summary.reasons) == dict(Counter(r for e in clamps for r in e["reasons"]))
    assert summary.scripts == ("gov",)
    cut = run_data.summarize_run(events[:10])
    assert cut.outcome == "unfinished"


def test_the_flow_follows_the_block_reader() -> None:
    text = (EXAMPLES / "approach.script").read_text(encoding="utf-8")
    script = analyze_bytes("a.script", text.encode()).script
    flow = flow_of(script)
    by_label = {b.label: i for i, b in enumerate(flow) if b.label}
    look = flow[by_label["look"]]
    assert look.kind == "jump" and look.targets == (by_label["wait"], by_label["look"] + 1)
    assert flow[by_label["step"]].kind == "instruction"
    assert "0.2 m/s" in flow[by_label["step"]].text and flow[by_label["step"]].colours
    assert [b.kind for b in flow].count("terminus") >= 1
    # an unchecked script: a jump to a label no block carries has no edge there (-1)
    broken = analyze_bytes("b.script", b"[b]\n[goal:g]\n[action]\n"
                           b"[b##blk_jump: CND({TRUE}) TRJMP(nowhere) FLSJMP()]\n"
                           b"[b##blk_terminus]\n").script
    assert flow_of(broken)[0].targets == (-1, 1)


# -- the page ------------------------------------------------------------------------------------


def approach_page() -> tuple[list[dict], str, list[ScriptSource]]:
    events, samples, script = example("approach")
    sources = [ScriptSource("approach", str(EXAMPLES / "approach.script"), script)]
    return events, report_html(events, sources, samples=samples), sources


def test_the_same_run_gives_the_same_bytes() -> None:
    first = approach_page()[1]
    assert approach_page()[1] == first
    events, _, script = example("approach")
    sources = [ScriptSource("approach", str(EXAMPLES / "approach.script"), script)]
    assert report_html(events, sources) == report_html([dict(e) for e in events], sources)


def test_the_page_is_one_file_that_loads_nothing() -> None:
    page = approach_page()[1]
    assert "Content-Security-Policy" in page and "default-src 'none'" in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", page)
    assert "uPlot" in page and "@@" not in page
    assert page.count("<script") == 3  # the data, uPlot, the page's own


def test_the_model_carries_the_run_as_float32_arrays() -> None:
    events, page, sources = approach_page()
    model, data = model_of_page(page)
    floats = array("f", data)
    if sys.byteorder == "big":
        floats.byteswap()

    def column(ref: dict) -> list[float]:
        start, count = ref["@"]
        return list(floats[start:start + count])

    assert model["end"] == run_data.end_ms(events)
    assert model["robot"]["recorded"] is True
    marks = run_data.markers(events)
    assert column(model["markers"]["t"]) == sorted(float(m.t) for m in marks)
    texts = [model["texts"][int(i)] for i in column(model["markers"]["text"])]
    assert sorted(texts) == sorted(m.text for m in marks)
    assert [f["script"] for f in model["flows"]] == ["approach"]
    assert len(model["flows"][0]["blocks"]) == len(flow_of(sources[0].ir))
    issued = [e for e in events if e["event"] == "block"]
    kinds = column(model["visits"]["kind"])
    assert kinds.count(float(run_data.ISSUED)) == len(issued)
    assert -1.0 not in column(model["visits"]["block"])  # every visit is a block of the flow
    path_x = column(model["path"]["x"])
    assert path_x[-1] == pytest.approx(0.9, abs=1e-6)


def test_everything_the_run_says_is_escaped() -> None:
    nasty = "<script>alert(1)</script> perché 🤖 & \"quoted\""
    events = [
        {"t": 0, "event": "session_start", "scripts": [nasty], "robot": "kinematic",
         "until": 100, "scenario": nasty},
        {"t": 0, "event": "script_load", "script": nasty, "path": "", "reason": "queue"},
        {"t": 0, "event": "error", "code": "read", "message": nasty, "fatal": True},
        {"t": 0, "event": "goal", "script": nasty, "goalid": nasty, "record": "reached"},
        {"t": 0, "event": "session_end", "outcome": "error", "time_ms": 0,
         "pose": {"x": 0, "y": 0, "theta": 0}},
    ]
    page = report_html(events, find_sources(events)[0])
    assert "<script>alert" not in page and "</script> perché" not in page
    assert "&lt;script&gt;alert(1)&lt;/script&gt; perché 🤖 &amp; &quot;quoted&quot;" in page
    model, _ = model_of_page(page)
    assert any(nasty in text for text in model["texts"])  # kept whole, for textContent


def test_the_page_of_a_trace_alone_notes_a_reconstructed_path(tmp_path: Path) -> None:
    events, _, _ = run_session(GOVERNED, robot="mujoco", until=3000)
    model, _ = page_model(events)
    assert model["robot"]["recorded"] is False
    page = report_html(events)
    assert "reconstructed from the trace" in page


def test_the_picture_in_the_docs_is_of_the_current_page() -> None:
    """docs/img/report-approach.png is made by bench/report_screenshot.py from the template
    whose digest it records beside it: a change to the page's template, style or script
    needs a new picture."""
    picture = ROOT / "docs" / "img" / "report-approach.png"
    record = dict(line.split(" ", 1) for line in
                  picture.with_suffix(".txt").read_text(encoding="utf-8").splitlines())
    assert record["template"] == template_digest(), (
        "the report's template changed since docs/img/report-approach.png was made: remake "
        "it with `python bench/report_screenshot.py` (needs Chromium)")
    data = picture.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    width, height = struct.unpack(">II", data[16:24])
    assert f"{width}x{height}" == record["size"] and width == 1280 and height >= 1000


# -- reading a trace and finding its scripts ------------------------------------------------------


@pytest.mark.parametrize(("content", "said"), [
    (b'{"t": 0, "event": "session_start"}\n{"t": 1\n', "bad.jsonl:2: not a JSON value"),
    (b'[1, 2]\n', "bad.jsonl:1: a JSON list, not an event object"),
    (b'{"t": -1, "event": "x"}\n', "bad.jsonl:1: an object without a whole `t`"),
    (b'{"t": 1.5, "event": "x"}\n', "bad.jsonl:1: an object without a whole `t`"),
    (b'{"t": 0, "event": NaN}\n', "bad.jsonl:1: not a JSON value (NaN is not a JSON number)"),
    (b"\n\n", "`bad.jsonl` is empty"),
    (b'{"t": 0, "event": "x"}\x00', "is not a trace: the file is not text"),
    (b'\xff\xfe', "is not a trace: the file is not UTF-8 text"),
])
def test_a_file_that_is_not_a_trace_is_said_so(tmp_path: Path, monkeypatch, content: bytes,
                                              said: str) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.jsonl").write_bytes(content)
    with pytest.raises(TraceError) as caught:
        read_trace("bad.jsonl")
    assert said in str(caught.value) and "a trace is JSON lines" in str(caught.value)
    result = CliRunner().invoke(cli, ["report", "bad.jsonl", "-o", "out.html"])
    assert result.exit_code == 2 and said in result.output and "Traceback" not in result.output
    assert not Path("out.html").exists()


def write_trace(path: Path, events: list[dict]) -> None:
    path.write_text("".join(json.dumps(e) + "\n" for e in events), encoding="utf-8")


def test_scripts_are_found_beside_the_trace_or_in_the_working_folder(tmp_path: Path,
                                                                      monkeypatch) -> None:
    events, _, _ = run_session(GOVERNED, until=500, path="acts/gov.script")
    (tmp_path / "runs" / "acts").mkdir(parents=True)
    (tmp_path / "runs" / "acts" / "gov.script").write_text(GOVERNED, encoding="utf-8")
    write_trace(tmp_path / "runs" / "run.jsonl", events)
    monkeypatch.chdir(tmp_path)
    sources, warnings = find_sources(events, "runs/run.jsonl")
    assert warnings == [] and sources[0].ir is not None  # beside the trace
    sources, warnings = find_sources(events, None)  # not in the working folder
    assert sources[0].ir is None and "neither beside the trace nor in the working folder" \
        in sources[0].problem
    monkeypatch.chdir(tmp_path / "runs")
    assert find_sources(events, None)[0][0].ir is not None  # in the working folder
    idle = [{"t": 0, "event": "script_load", "script": "idle_activity", "path": "",
             "reason": "idle"}]
    assert find_sources(idle)[0][0].ir is not None  # the built-in idle program
    scb = [{"t": 0, "event": "script_load", "script": "b", "path": "b.scb", "reason": "queue"}]
    (tmp_path / "runs" / "b.scb").write_bytes(b"")
    assert "bytecode" in find_sources(scb)[0][0].problem


def test_scriptc_report_writes_the_page_and_says_what_is_missing(tmp_path: Path,
                                                                 monkeypatch) -> None:
    events, _, _ = run_session(GOVERNED, until=500, path="gov.script")
    write_trace(tmp_path / "run.jsonl", events)
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(cli, ["report", "run.jsonl"])
    assert result.exit_code == 0, result.output
    assert ("run.jsonl:2: no flow for the script `gov`: `gov.script` is neither beside the "
            "trace nor in the working folder") in result.output
    assert "wrote run.html" in result.output and default_output("run.jsonl") == "run.html"
    without = Path("run.html").read_bytes()
    Path("gov.script").write_text(GOVERNED, encoding="utf-8")
    result = CliRunner().invoke(cli, ["report", "run.jsonl", "-o", "with.html"])
    assert result.exit_code == 0 and "warning" not in result.output
    model, _ = model_of_page(Path("with.html").read_text(encoding="utf-8"))
    assert model["flows"][0]["blocks"]
    assert model_of_page(without.decode())[0]["flows"][0]["blocks"] == []
    again = CliRunner().invoke(cli, ["report", "run.jsonl", "-o", "-"])
    assert again.stdout == Path("with.html").read_text(encoding="utf-8")
    same = CliRunner().invoke(cli, ["report", "run.jsonl", "-o", "run.jsonl"])
    assert same.exit_code == 2 and "is the trace itself" in same.output


def test_scriptc_report_summary(tmp_path: Path, monkeypatch) -> None:
    events, _, _ = run_session(GOVERNED, until=500)
    write_trace(tmp_path / "run.jsonl", events)
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(cli, ["report", "run.jsonl", "--summary", "--lang", "it",
                                      "--markdown"])
    from scriptc.views.summary import summarize

    assert result.exit_code == 0, result.output
    assert result.stdout == summarize(events, lang="it", markdown=True)
    assert not Path("run.html").exists()  # the page only with -o
    both = CliRunner().invoke(cli, ["report", "run.jsonl", "--summary", "-o", "run.html"])
    assert both.exit_code == 0 and both.stdout == summarize(events)
    assert model_of_page(Path("run.html").read_text(encoding="utf-8"))[0]["end"] > 0


@pytest.mark.slow
def test_run_report_and_test_report(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(EXAMPLES)
    out = tmp_path / "a.html"
    args = ["run", "approach.script", "--world", "approach.world.json", "--report", str(out)]
    assert CliRunner().invoke(cli, args).exit_code == 0
    first = out.read_bytes()
    assert CliRunner().invoke(cli, args).exit_code == 0
    assert out.read_bytes() == first
    model, _ = model_of_page(first.decode())
    assert model["robot"]["recorded"] is True and model["flows"][0]["blocks"]
    folder = tmp_path / "reports"
    result = CliRunner().invoke(cli, ["test", "tests/approach.test.toml",
                                      "tests/greeting.test.toml", "--report", str(folder)])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in folder.iterdir()) == ["approach.html", "greeting.html",
                                                        "index.html"]
    index = (folder / "index.html").read_text(encoding="utf-8")
    assert 'href="approach.html"' in index and "passed" in index
    assert model_of_page((folder / "greeting.html").read_text(encoding="utf-8"))[0]["flows"]
    (tmp_path / "file").write_text("")
    refused = CliRunner().invoke(cli, ["test", "tests/greeting.test.toml", "--report",
                                       str(tmp_path / "file")])
    assert refused.exit_code == 2 and "not a folder" in refused.output


# -- a 10-minute session ---------------------------------------------------------------------------


@pytest.mark.slow
def test_a_ten_minute_session_is_under_2_mb() -> None:
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_mujoco import activity

    events, samples, script = run_session(activity(), robot="mujoco", until=700_000)
    assert run_data.summarize_run(events).time_ms == 600_000
    sources = [ScriptSource("ten_minutes", "a.script", script)]
    for page in (report_html(events, sources, samples=samples), report_html(events, sources)):
        size = len(page.encode("utf-8"))
        assert size < 2_000_000, size
        assert model_of_page(page)[0]["end"] == 600_000 + 298  # braking to rest after the end
    print(f"\n10-minute MuJoCo session: {size / 1e6:.2f} MB (trace alone: "
          f"{sum(len(json.dumps(e)) + 1 for e in events) / 1e6:.2f} MB)")
