"""Figures of `scriptc run --trace FILE.mcap` (views/mcap.py, docs/views.md): prints them,
asserts nothing.

The 10-minute MuJoCo activity of bench/bench_mujoco.py (600 moves, the LEDs changing with
them, the governor on) with two children and a ball placed in the world, sensed at the
default rate as the robot moves: the session is run once in process with its path recorded
(as `scriptc run` records it for an .mcap file), then the MCAP file is written from its trace
and path (best of 3, CPU-bound, in process): its size, the time to write it, its messages by
topic, and the JSON lines trace of the same run for comparison.

    python bench/bench_mcap.py
"""

from __future__ import annotations

import io
import json
import os
import tempfile
import time
from collections import Counter

from bench_mujoco import MINUTES, activity

REPEAT = 3
WORLD = {"entities": [
    {"objectid": "Human/kid1", "x": 1.5, "y": 0.5, "v_x": -0.001, "v_y": 0.0005},
    {"objectid": "Human/kid2", "x": -1.0, "y": 1.2},
    {"objectid": "Object/ball1", "x": 0.8, "y": -0.7, "v_y": 0.001},
]}


def main() -> None:
    from mcap.reader import make_reader

    from scriptc.analysis.analyze import analyze_file
    from scriptc.robot.profile import DEFAULT_PROFILE
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.recorded import PathRecorder
    from scriptc.runtime.robots.mujoco import MujocoRobot
    from scriptc.runtime.scenario import load_scenario
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace
    from scriptc.views.mcap import write_mcap

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "ten_minutes.script")
        with open(path, "w", encoding="utf-8") as f:
            f.write(activity())
        world = os.path.join(tmp, "children.json")
        with open(world, "w", encoding="utf-8") as f:
            json.dump(WORLD, f)
        analysis = analyze_file(path, "script")
        recorder = PathRecorder(MujocoRobot())
        trace = Trace()
        session = Session([IRProgram(analysis.script, path)], robot=recorder, trace=trace,
                          scenario=load_scenario(world), profile=DEFAULT_PROFILE)
        t = time.perf_counter()
        result = session.run()
        run_s = time.perf_counter() - t
    events, samples = trace.events, recorder.samples
    print(f"{MINUTES}-minute MuJoCo session: {result.outcome} at {result.time_ms} ms, "
          f"{len(events):,} trace events, {len(samples):,} path samples (run with the path "
          f"recorded: {run_s:.2f} s)")

    times = []
    data = b""
    for _ in range(REPEAT):
        t = time.process_time()
        data = write_mcap(events, samples)
        times.append(time.process_time() - t)
    jsonl = trace.text().encode("utf-8")
    topics: Counter[str] = Counter()
    reader = make_reader(io.BytesIO(data))
    for _schema, channel, _message in reader.iter_messages(log_time_order=False):
        topics[channel.topic] += 1
    print(f"MCAP file: {len(data) / 1e6:.2f} MB ({len(data):,} bytes, zstd chunks), "
          f"{sum(topics.values()):,} messages, written in {min(times):.2f} s CPU (best of "
          f"{REPEAT}; {max(times):.2f} s worst)")
    print(f"the JSON lines trace of the same run: {len(jsonl) / 1e6:.2f} MB")
    print("messages by topic: " + ", ".join(f"{topic} {count:,}"
                                            for topic, count in sorted(topics.items())))


if __name__ == "__main__":
    main()
