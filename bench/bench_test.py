"""Speed of `scriptc test` (docs/testing.md).

1. One test of ten minutes of simulated time on the kinematic robot: an activity that loops
   for ten minutes (a two-second block on the three tracks and a jump over a CLASS condition
   each turn, the safety rule in the chain), a world where a child comes and goes every
   second (600 map updates), and eight expectations of every kind (events, the state at two
   instants and at the end, the outcome and time, a distance). Wall time of `run_one` (the
   scripts loaded and compiled, the session run with its trace, every expectation judged), best
   and median of N, after one run to import everything; and how it divides. Target: under
   0.1 s, most of it the runtime's.
2. 200 tests of 10 s simulated each (the greeting example, each with its own world and four
   expectations), `scriptc test -j 2` end to end in a fresh process (the interpreter's start,
   discovery, checking, the pool, the output). Target: under 10 s. And the same run in this
   process: how busy the two workers were (the tests' seconds over twice the run's).
3. Tests of uneven lengths (the loop of 5 to 40 minutes) in four shards, the way a CI matrix
   runs them: `scriptc test --shard I/4 --junit` in four fresh processes, split by count, then
   by the durations a whole run recorded (`--durations`); the four reports merged (`scriptc
   merge`) list every test exactly once. The seconds of each shard's tests, and the heaviest
   shard against an even share.

    python bench/bench_test.py [--runs N] [--tests N]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def ten_minute_activity() -> str:
    return """\
[ten_minutes]
[alfa:1, guard, "distance=0.5", "", A, U]
[omega:1, guard, "", "", R, L]
[goal:play]
  [action]
    [b#turn#blk_inst: MV("0, 0, 0.4, 0, 500", "0, 0, -0.4, 0, 500")
                      LD("0.2, 0.8, 0.3, 1, 0, 1000", "0.9, 0.6, 0.3, 1, 0, 1000")
                      AO("songs/turn.wav, 0, 1500", "Silence, 0, 500")]
    [b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE})
                  TRJMP(cheer) FLSJMP()]
    [b##blk_jump: CND({CLASS #Activity T ?me (?THIS>&elapsedtime OP> 600000)} ! {TRUE})
                  TRJMP(bye) FLSJMP(turn)]
    [b#cheer#blk_inst: MV() LD("0.2, 0.8, 0.3, 1, 0, 500") AO("songs/cheer.wav, 0, 500")]
    [b##blk_jump: CND(! {TRUE}) TRJMP(turn) FLSJMP()]
[goal:closed]
  [action]
    [b#bye#blk_inst: MV() LD("0.1, 0.2, 0.4, 1, 0, 1000") AO()]
    [b##blk_terminus]
"""


def ten_minute_test() -> str:
    updates = "\n".join(
        f'  {{ at = {t}, objectid = "Human/kid1", attributename = "poses", policy = "R", '
        f'jsonmsg = {{ positionrho = {0.8 if (t // 1000) % 7 == 3 else 2.0}, '
        f'positiontheta = 0.1 }} }},' for t in range(0, 600_000, 1000))
    return f"""\
description = "ten minutes of turn taking, a child coming close now and then"
scripts = ["ten_minutes.script"]
until = 610000

[[expect]]
event = "block"
where = {{ label = "cheer" }}
count = ">=50"

[[expect]]
event = "jump"
where = {{ value = true }}
within = [0, 60000]

[[expect]]
event = "error"
count = "0"

[[expect]]
at = 500
block = "turn"
led = [0.2, 0.8, 0.3]

[[expect]]
at = 300000
audio = "songs/turn.wav"

[[expect]]
at = "end"
block = "none"

[[expect]]
outcome = "completed"
time = {{ min = 600000, max = 610000 }}

[[expect]]
distance = {{ to = "Human/*", min = 0.5 }}

[world]
updates = [
{updates}
]
"""


def bench_ten_minutes(runs: int) -> None:
    from scriptc.ops.test import run_one
    from scriptc.testing.read import read_test

    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "ten_minutes.script").write_text(ten_minute_activity(), encoding="utf-8")
        path = os.path.join(folder, "ten.test.toml")
        Path(path).write_text(ten_minute_test(), encoding="utf-8")
        start = time.perf_counter()
        read = read_test(path)
        checking = time.perf_counter() - start
        assert read.test is not None, read.diagnostics
        test = read.test
        result = run_one(test)  # imports everything once
        assert result.status == "passed", [v for v in result.verdicts if not v.passed]
        walls = []
        for _ in range(runs):
            result = run_one(test)
            walls.append(result.wall_s)
        phases = _phases(test)
    print(f"1. a test of {result.time_ms / 60000:.1f} min simulated, kinematic robot: "
          f"{min(walls) * 1000:.1f} ms best, {statistics.median(walls) * 1000:.1f} ms median "
          f"of {runs} (target < 100 ms); {len(result.events):,} trace events, "
          f"{len(result.verdicts)} expectations")
    print(f"   of the best: loading {phases['load'] * 1000:.1f} ms, the session "
          f"{phases['run'] * 1000:.1f} ms, judging {phases['judge'] * 1000:.1f} ms; reading "
          f"and checking the test file (once, before) {checking * 1000:.1f} ms")


def _phases(test) -> dict[str, float]:
    """The best time of each part of `run_one`, measured apart."""
    from scriptc.ops.programs import load_programs
    from scriptc.runtime.robots import make_robot
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace
    from scriptc.testing.expect import Run, judge

    best = {"load": float("inf"), "run": float("inf"), "judge": float("inf")}
    for _ in range(5):
        t0 = time.perf_counter()
        loaded = load_programs(test.scripts)
        t1 = time.perf_counter()
        trace = Trace()
        result = Session(loaded.programs, scenario=test.world, robot=make_robot(test.robot),
                         trace=trace).run(test.until, test.instants)
        t2 = time.perf_counter()
        judge(test.expectations, Run(trace.events, {s.t: s for s in result.observations},
                                     result.final, result.outcome, result.time_ms))
        t3 = time.perf_counter()
        for key, seconds in (("load", t1 - t0), ("run", t2 - t1), ("judge", t3 - t2)):
            best[key] = min(best[key], seconds)
    return best


def many_tests(folder: Path, count: int) -> None:
    shutil.copy(EXAMPLES / "greeting.script", folder / "greeting.script")
    for i in range(count):
        near = 1000 + (i * 37) % 5000
        (folder / f"t{i:03d}.test.toml").write_text(f"""\
description = "test {i}: a child comes within reach at {near} ms"
scripts = ["greeting.script"]
until = 10000

[[expect]]
event = "block"
where = {{ label = "hello" }}
within = [{near}, {near + 1000}]

[[expect]]
at = {near + 1500}
block = "hello"

[[expect]]
outcome = "completed"

[[expect]]
distance = {{ to = "Human/*", min = 0.5 }}

[[world.updates]]
at = {near}
objectid = "Human/kid1"
attributename = "poses"
policy = "R"
jsonmsg = {{ positionrho = 1.0, positiontheta = 0.0 }}
""", encoding="utf-8")


def bench_many(count: int, runs: int) -> None:
    from scriptc.ops.test import TestOptions, test_paths

    with tempfile.TemporaryDirectory() as folder:
        many_tests(Path(folder), count)
        walls = []
        for _ in range(runs):
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "scriptc", "test", "-j", "2", "-q",
                                   folder], capture_output=True, text=True, check=False)
            walls.append(time.perf_counter() - start)
            assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
        run = test_paths([folder], TestOptions(jobs=2))
        assert run.exit_code == 0 and len(run.results) == count
        running = run.wall_s - run.checked_s
        busy = sum(r.wall_s for r in run.results) / (2 * running)
        simulated = sum(r.time_ms or 0 for r in run.results) / 1000
    print(f"2. {count} tests of 10 s simulated, `scriptc test -j 2` end to end: "
          f"{min(walls):.2f} s best, {statistics.median(walls):.2f} s median of {runs} "
          f"(target < 10 s); in this process {run.wall_s:.2f} s for {simulated:.0f} s "
          f"simulated: {run.checked_s:.2f} s finding and checking the test files, then "
          f"{running:.2f} s running them, the two workers busy {busy:.0%} of that")


def uneven_tests(folder: Path, count: int) -> None:
    # The loop of the ten-minute activity, for an hour.
    (folder / "loop.script").write_text(ten_minute_activity().replace("600000", "3600000"),
                                        encoding="utf-8")
    for i in range(count):
        minutes = 5 * (i % 8 + 1)
        (folder / f"u{i:03d}.test.toml").write_text(f"""\
description = "the loop for {minutes} min"
scripts = ["loop.script"]
until = {minutes * 60000}

[[expect]]
event = "error"
count = "0"
""", encoding="utf-8")


def bench_shards(count: int) -> None:
    from xml.etree import ElementTree

    def scriptc(folder: str, *args: str) -> None:
        done = subprocess.run([sys.executable, "-m", "scriptc", *args], cwd=folder,
                              capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]

    with tempfile.TemporaryDirectory() as folder:
        uneven_tests(Path(folder), count)
        scriptc(folder, "test", "-q", "-j", "1", "--durations", "durations.json")
        recorded = json.loads((Path(folder) / "durations.json").read_text())["durations"]
        for how, durations in (("by count", []), ("by recorded durations",
                                                  ["--durations", "durations.json"])):
            reports = [f"shard{i}.xml" for i in range(1, 5)]
            for i, report in enumerate(reports, 1):
                scriptc(folder, "test", "-q", "-j", "1", "--shard", f"{i}/4", "--junit",
                        report, *durations)
            scriptc(folder, "merge", "all.xml", *reports)
            names = [case.get("name") for case in ElementTree.parse(
                Path(folder) / "all.xml").getroot().iter("testcase")]
            assert len(names) == len(set(names)) == count, "a test ran twice, or not at all"
            parts = [list(ElementTree.parse(Path(folder) / report).getroot().iter(
                "testcase")) for report in reports]
            # What the split planned (the recorded seconds of each shard's tests), and what the
            # shards took (their own seconds, on a machine whose load varies meanwhile).
            planned = [sum(recorded[c.get("name")] for c in part) for part in parts]
            loads = [sum(float(c.get("time") or 0) for c in part) for part in parts]
            print(f"3. {count} tests of 5 to 40 min in 4 shards {how}: each ran exactly once "
                  f"(the merged report lists {len(names)} tests); by the recorded seconds the "
                  f"heaviest shard is {max(planned) / (sum(planned) / 4):.2f} times an even "
                  f"share; the shards' tests took {', '.join(f'{load:.2f}' for load in loads)}"
                  f" s, the heaviest {max(loads) / (sum(loads) / 4):.2f} times an even share")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--tests", type=int, default=200)
    args = parser.parse_args()
    bench_ten_minutes(args.runs)
    bench_many(args.tests, max(1, args.runs // 3))
    bench_shards(48)


if __name__ == "__main__":
    main()
