"""Figures of the report of a run (docs/views.md, "The report of a run"): prints them, asserts
nothing.

Two 10-minute sessions, each run once in process with its path recorded: the MuJoCo session
of bench/bench_mujoco.py (600 moves and 600 LED commands in one block, the governor on: a ramp
at every change of the move), and the activity of bench/bench_run.py on the kinematic robot
(601 blocks, three children sending their poses every 250 ms: 7,200 map updates, two rules).
For each:

1. `run --report`: the page from the events and the recorded path (`report_html`), its size
   and the time to make and write it (best of REPEAT, CPU time);
2. `scriptc report TRACE`: the same from the trace file alone (read it, find the script,
   reconstruct the path, make and write the page), in process, and as a command in a fresh
   process (process start included);
3. with Debian's Chromium (tests/chromium.py), when it is there: how long after it began to
   load the page is drawn and its cursor live (`scriptcReport.readyAt`), best of REPEAT.

    python bench/bench_report.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "bench"), str(ROOT / "tests")]

from bench_mujoco import activity  # noqa: E402

REPEAT = 3


def best(f, n=REPEAT):
    times, out = [], None
    for _ in range(n):
        t = time.process_time()
        out = f()
        times.append(time.process_time() - t)
    return min(times), out


def measure(name: str, text: str, robot: object, scenario: object = None) -> None:
    from scriptc.analysis.analyze import analyze_file
    from scriptc.ops.report import find_sources, read_trace
    from scriptc.robot.profile import DEFAULT_PROFILE
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.recorded import PathRecorder
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace
    from scriptc.views.report import ScriptSource, report_html
    from scriptc.writing import write_file

    with tempfile.TemporaryDirectory() as tmp:
        script = os.path.join(tmp, "ten_minutes.script")
        Path(script).write_text(text, encoding="utf-8")
        analysis = analyze_file(script)
        recorder = PathRecorder(robot)
        trace = Trace()
        Session([IRProgram(analysis.script, script)], scenario=scenario, robot=recorder,
                trace=trace, profile=DEFAULT_PROFILE).run(700_000)
        events = trace.events
        trace_file = os.path.join(tmp, "run.jsonl")
        Path(trace_file).write_text(trace.text(), encoding="utf-8")
        page = os.path.join(tmp, "run.html")
        sources = [ScriptSource("ten_minutes", script, analysis.script)]
        print(f"{name}: {len(events):,} events, {len(recorder.samples):,} recorded poses, "
              f"trace {os.path.getsize(trace_file) / 1e6:.2f} MB")

        def with_path():
            html = report_html(events, sources, samples=recorder.samples)
            write_file(page, html)
            return len(html.encode("utf-8"))

        seconds, size = best(with_path)
        print(f"  run --report: page {size / 1e6:.2f} MB ({size:,} bytes), made and written in "
              f"{seconds:.2f} s CPU")

        def from_trace():
            read = read_trace(trace_file)
            found, _warnings = find_sources(read, trace_file)
            html = report_html(read, found)
            write_file(page, html)
            return len(html.encode("utf-8"))

        seconds, size = best(from_trace)
        print(f"  scriptc report TRACE (in process): page {size / 1e6:.2f} MB, trace read, "
              f"path reconstructed, page made and written in {seconds:.2f} s CPU")
        walls = []
        for _ in range(REPEAT):
            t = time.perf_counter()
            subprocess.run([sys.executable, "-m", "scriptc", "report", trace_file, "-o", page],
                           check=True, capture_output=True)
            walls.append(time.perf_counter() - t)
        print(f"  scriptc report TRACE -o FILE.html (a fresh process): {min(walls):.2f} s wall")

        from chromium import Chromium, available

        why = available()
        if why is not None:
            print(f"  in a browser: not measured ({why})")
            return
        readies = []
        with Chromium(width=1280, height=1500) as browser:
            for _ in range(REPEAT):
                browser.open(Path(page).as_uri())
                browser.wait_for("window.scriptcReport && window.scriptcReport.ready")
                readies.append(browser.evaluate(
                    "[scriptcReport.readyAt, scriptcReport.readyMs, scriptcReport.timings]"))
            problems = browser.problems
        at, drawing, timings = min(readies, key=lambda r: r[0])
        laps = ", ".join(f"{name} {ms:.0f}" for name, ms in timings.items())
        print(f"  in headless Chromium: drawn and live {at:.0f} ms after the page began to load "
              f"(best of {REPEAT}; {drawing:.0f} ms of it drawing the views, in ms: {laps}), "
              f"problems: {json.dumps(problems)}")


def main() -> None:
    from bench_run import activity_text, scenario

    from scriptc.runtime.robots.kinematic import KinematicRobot
    from scriptc.runtime.robots.mujoco import MujocoRobot
    from scriptc.runtime.scenario import scenario_from_data

    measure("10-minute MuJoCo session (bench_mujoco)", activity(), MujocoRobot())
    measure("10-minute session with three children (bench_run, kinematic)", activity_text(),
            KinematicRobot(), scenario_from_data(scenario(600_000)))


if __name__ == "__main__":
    main()
