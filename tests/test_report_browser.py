"""The report of a run in a real browser: Debian's Chromium, headless, driven over the DevTools
protocol (tests/chromium.py). The page renders from the file alone, asks for nothing else,
says nothing in the console, and one cursor moves every view: a real mouse moved over one
chart moves the cursor of the others, the room's robot, the readout and the flow's
highlighted block; hovering the room moves the charts; dragging zooms every chart alike.

The `browser` tier (and `slow`). Without Chromium these tests fail, naming what to install:
CI installs it (.ci/run)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from chromium import Chromium, available
from test_views_report import EXAMPLES, ROOT, example

from scriptc.runtime.interp import IRProgram
from scriptc.runtime.robots import make_robot
from scriptc.views.report import ScriptSource, report_html

pytestmark = [pytest.mark.browser, pytest.mark.slow]

READY = "window.scriptcReport && window.scriptcReport.ready"
# What the page says of its views (each chart's cursor, in CSS pixels; -10: none).
STATE = """(() => { const r = window.scriptcReport;
  return { time: r.time, block: r.highlighted, lefts: r.charts.map(c => c.cursor.left),
           scales: r.charts.map(c => [c.scales.x.min, c.scales.x.max]),
           readout: document.getElementById('readout').textContent,
           room: (() => { const d = document.getElementById('room').toDataURL();
                          let h = 0;
                          for (let i = 0; i < d.length; i++) h = (h * 31 + d.charCodeAt(i)) | 0;
                          return h; })(),
           running: [...document.querySelectorAll('svg.flow rect.running')].length };
})()"""


@pytest.fixture(scope="module")
def browser():
    why = available()
    if why is not None:
        pytest.fail(f"the browser tests need Chromium: {why}")
    with Chromium(width=1280, height=1500) as chromium:
        yield chromium


def open_page(browser: Chromium, page: Path) -> dict:
    browser.events.clear()
    browser.open(page.as_uri())
    browser.wait_for(READY)
    return browser.evaluate(STATE)


def chart_point(browser: Chromium, chart: int, seconds: float) -> tuple[float, float]:
    """The page coordinates of `seconds` on a chart (0 tracks, 1 velocity, 2 events)."""
    return tuple(browser.evaluate(
        f"(() => {{ const u = scriptcReport.charts[{chart}];"
        " const r = u.over.getBoundingClientRect();"
        f" return [r.left + u.valToPos({seconds}, 'x'), r.top + r.height / 2]; }})()"))


@pytest.fixture(scope="module")
def approach_page(tmp_path_factory) -> Path:
    events, samples, script = example("approach", robot="mujoco")
    sources = [ScriptSource("approach", str(EXAMPLES / "approach.script"), script)]
    page = tmp_path_factory.mktemp("report") / "approach.html"
    page.write_text(report_html(events, sources, samples=samples), encoding="utf-8")
    return page


def test_the_page_renders_from_the_file_alone_without_a_problem(browser, approach_page):
    state = open_page(browser, approach_page)
    assert browser.problems == []
    assert browser.requests == [approach_page.as_uri()]  # nothing else is asked for
    assert browser.evaluate("document.querySelectorAll('.uplot').length") == 3
    blocks = browser.evaluate("document.querySelectorAll('svg.flow rect.block').length")
    assert blocks >= 14  # every block of the approach, and the end
    assert state["running"] == 1 and state["block"] == "goal0/act0/blk2"  # the first step
    assert "completed" in browser.evaluate("document.querySelector('table.summary').textContent")
    print(f"\nready {browser.evaluate('scriptcReport.readyAt'):.0f} ms after the page began "
          "to load")


def test_one_cursor_moves_every_view(browser, approach_page):
    before = open_page(browser, approach_page)
    x, y = chart_point(browser, 1, 2.2)  # the velocity chart, during a step
    browser.mouse_move(x, y)
    during = browser.evaluate(STATE)
    assert all(left > 0 for left in during["lefts"])  # every chart's cursor moved
    assert during["time"] == pytest.approx(2200, abs=40)
    assert during["room"] != before["room"]  # the robot moved on the map
    shown = float(re.search(r"time([0-9.]+) s", during["readout"]).group(1))
    assert shown == pytest.approx(2.2, abs=0.04)
    assert during["block"] == "goal0/act0/blk2" and during["running"] == 1
    x, y = chart_point(browser, 0, 10.0)  # the tracks chart, while the child is welcomed
    browser.mouse_move(x, y)
    after = browser.evaluate(STATE)
    assert after["time"] == pytest.approx(10_000, abs=40)
    assert after["block"] == "goal2/act0/blk0" != during["block"]  # the highlight moved
    assert all(a != b for a, b in zip(after["lefts"], during["lefts"], strict=True))
    x, y = chart_point(browser, 2, 0.5)  # the events chart
    browser.mouse_move(x, y)
    assert browser.evaluate(STATE)["time"] == pytest.approx(500, abs=40)
    assert browser.problems == []


def test_hovering_the_room_moves_the_charts(browser, approach_page):
    open_page(browser, approach_page)
    # the robot's path ends 0.9 m ahead: hovering there puts the cursor where it got there
    point = browser.evaluate("scriptcReport.roomPoint(0.9, 0)")
    browser.mouse_move(*point)
    state = browser.evaluate(STATE)
    assert 6500 < state["time"] < 7200  # at the end of its last step
    assert all(left > 0 for left in state["lefts"])
    assert browser.problems == []


def test_dragging_zooms_every_chart_alike(browser, approach_page):
    open_page(browser, approach_page)
    x0, y = chart_point(browser, 1, 2.0)
    x1, _ = chart_point(browser, 1, 6.0)
    browser.mouse("mousePressed", x0, y)
    for k in range(1, 6):
        browser.mouse_move(x0 + (x1 - x0) * k / 5, y, buttons=1)
    assert browser.evaluate(STATE)["time"] == pytest.approx(6000, abs=60)  # dragging moves
    browser.mouse("mouseReleased", x1, y)
    scales = browser.evaluate(STATE)["scales"]
    assert scales[0] == pytest.approx([2.0, 6.0], abs=0.05)
    assert all(s == pytest.approx(scales[0]) for s in scales)
    assert browser.problems == []


def test_a_ten_minute_session_renders(browser, tmp_path):
    """bench/bench_run.py's activity: 601 blocks, three children, ten minutes."""
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_run import activity_text, scenario

    from scriptc.analysis.analyze import analyze_bytes
    from scriptc.runtime.scenario import scenario_from_data
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace

    script = analyze_bytes("ten.script", activity_text().encode()).script
    trace = Trace()
    Session([IRProgram(script, "ten.script")], scenario=scenario_from_data(scenario(600_000)),
            robot=make_robot("kinematic"), trace=trace).run(700_000)
    page = tmp_path / "ten.html"
    page.write_text(report_html(trace.events, [ScriptSource("ten_minutes", "ten.script",
                                                            script)]), encoding="utf-8")
    state = open_page(browser, page)
    assert browser.problems == [] and state["running"] == 1
    assert browser.evaluate("scriptcReport.model.entities.length") == 3
    browser.mouse_move(*chart_point(browser, 1, 500.0))
    state = browser.evaluate(STATE)
    assert state["time"] == pytest.approx(500_000, abs=1000)
    # the block running then is far down the flow: scrolled to, drawn, highlighted
    assert state["running"] == 1 and state["block"].startswith("goal8/")  # block 250 of 601
    assert browser.evaluate("document.getElementById('flow').scrollTop") > 10_000
    print(f"\n10-minute session, {page.stat().st_size / 1e6:.2f} MB: ready "
          f"{browser.evaluate('scriptcReport.readyAt'):.0f} ms after the page began to load; "
          f"{browser.evaluate('JSON.stringify(scriptcReport.timings)')}")


ODD = {
    "a trace of one event": [{"t": 0, "event": "session_start"}],
    "the idle activity and a fatal error": [
        {"t": 0, "event": "session_start", "scripts": [], "robot": "kinematic"},
        {"t": 0, "event": "script_load", "script": "idle_activity", "path": "",
         "reason": "idle"},
        {"t": 0, "event": "block", "script": "idle_activity", "path": "goal0/act0/blk0",
         "label": "breathe", "changed": False},
        {"t": 5, "event": "error", "code": "read", "message": "<b>é 🤖</b>", "fatal": True},
        {"t": 5, "event": "session_end", "outcome": "error", "time_ms": 5,
         "pose": {"x": 0, "y": 0, "theta": 0}}],
}


@pytest.mark.parametrize("name", list(ODD))
def test_odd_traces_render_too(browser, tmp_path, name):
    from scriptc.ops.report import find_sources

    events = ODD[name]
    page = tmp_path / "odd.html"
    page.write_text(report_html(events, find_sources(events)[0]), encoding="utf-8")
    open_page(browser, page)
    browser.mouse_move(*chart_point(browser, 1, 0.004))
    assert browser.problems == []
    if "error" in name:
        assert browser.evaluate("scriptcReport.highlighted") == "goal0/act0/blk0"
        summary = browser.evaluate("document.querySelector('table.summary').textContent")
        assert "<b>é 🤖</b>" in summary  # shown as text, not markup
