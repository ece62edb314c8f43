"""Figures of the MuJoCo robot (docs/robot.md): prints them, asserts nothing.

1. A 10-minute activity whose move changes every second (600 moves on the move track, LEDs
   changing with them), run by `scriptc run --robot mujoco` in a fresh process: wall time with
   process start included, and the real-time factor. The governor is on (the default): every
   change of the move is a ramp at the acceleration limits, stepped in batches.
2. The bare `mj_step` rate of the same model over the same 600,000 steps (the physical limit),
   and the interpreter's overhead as a ratio (in-process run time / bare stepping time).
3. Model load (compile the shipped MJCF) and the first step, in a fresh process, beside the
   import of mujoco itself.
4. Ctrl-C: a run of a 50-minute move (`--until` an hour), sent SIGINT once it runs: the time
   from the signal to the process's exit (status 130), and the time of one chunk of physics
   (`CHUNK_STEPS` steps), the most the session waits before it sees the request.

    python bench/bench_mujoco.py
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

MINUTES = 10
REPEAT = 3


def activity() -> str:
    moves, leds = [], []
    for i in range(MINUTES * 60):
        a = i * 0.7
        moves.append(f'"{0.3 * math.cos(a):.3f}, {0.3 * math.sin(a):.3f}, '
                     f'{0.8 * math.sin(a / 3):.3f}, 0, 1000"')
        leds.append(f'"{i % 2}, {(i // 2) % 2}, 1, 1, 0, 1000"')
    return ("[ten_minutes]\n[goal:g]\n[action]\n"
            f"[b##blk_inst: MV({', '.join(moves)}) LD({', '.join(leds)}) AO()]\n"
            "[b##blk_terminus]\n")


def best(f, n=REPEAT):
    times = []
    for _ in range(n):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return min(times), out


def main() -> None:
    simulated = MINUTES * 60.0
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "ten_minutes.script")
        with open(path, "w", encoding="utf-8") as f:
            f.write(activity())

        def cli():
            done = subprocess.run([sys.executable, "-m", "scriptc", "run", path, "--robot",
                                   "mujoco", "--json"], capture_output=True, text=True,
                                  check=True)
            return json.loads(done.stdout)

        wall, summary = best(cli)
        print(f"10-minute activity, 600 moves, scriptc run --robot mujoco (process start "
              f"included): {wall:.2f} s wall, {simulated / wall:.0f}x real time "
              f"(outcome {summary['outcome']} at {summary['time_ms']} ms)")

        # In process: the same run without process start, and the bare stepping.
        from scriptc.analysis.analyze import analyze_file
        from scriptc.robot.profile import DEFAULT_PROFILE
        from scriptc.runtime.interp import IRProgram
        from scriptc.runtime.robots.mujoco import MujocoRobot, load_model
        from scriptc.runtime.session import Session
        from scriptc.runtime.trace import Trace

        analysis = analyze_file(path, "script")

        def in_process():
            robot = MujocoRobot()
            session = Session([IRProgram(analysis.script, path)], robot=robot,
                              trace=Trace(False), profile=DEFAULT_PROFILE)
            session.run()
            return robot.steps, session.governor.clamps

        run_s, (steps, clamps) = best(in_process)

        import mujoco

        model = load_model()

        def bare():
            data = mujoco.MjData(model)
            data.act[:] = (0.2, 0.1, 0.3)  # the velocity setpoints (ctrl is their rate)
            mujoco.mj_step(model, data, nstep=steps)

        bare_s, _ = best(bare)
        print(f"in process: {run_s:.3f} s for {steps:,} physics steps "
              f"(the robot brakes to rest after the end), {clamps} governor clamps (ramps), "
              f"{simulated / run_s:.0f}x real time")
        print(f"bare mj_step of the same model: {bare_s:.3f} s, "
              f"{bare_s / steps * 1e6:.2f} us/step, {simulated / bare_s:.0f}x real time "
              "(the physical limit)")
        print(f"interpreter overhead: {run_s / bare_s:.2f}x the bare stepping "
              f"({(run_s - bare_s) * 1000:.0f} ms over {steps:,} steps)")

    probe = ("import time\nt0 = time.perf_counter()\nimport mujoco\nt1 = time.perf_counter()\n"
             "from scriptc.runtime.robots.mujoco import MujocoRobot\nt2 = time.perf_counter()\n"
             "r = MujocoRobot()\nr.set_velocity(0, 0.25, 0, 0)\nr.advance(1)\n"
             "t3 = time.perf_counter()\nprint(t1 - t0, t3 - t2)\n")
    loads = []
    for _ in range(REPEAT):
        done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                              check=True)
        loads.append(tuple(map(float, done.stdout.split())))
    imp = min(x[0] for x in loads)
    load = min(x[1] for x in loads)
    print(f"fresh process: import mujoco {imp * 1000:.0f} ms; model load (compile the shipped "
          f"MJCF) and first step {load * 1000:.1f} ms")
    ctrl_c()


LONG = ('[long]\n[goal:g]\n[action]\n[b#go#blk_inst: MV("0.2, 0, 0.1, 0, 3000000") '
        'LD("0, 0, 1, 1, 0, 1000") AO()]\n[b##blk_jump: CND(! {TRUE}) TRJMP(go) FLSJMP()]\n')


def ctrl_c() -> None:
    from scriptc.runtime.robots.mujoco import CHUNK_STEPS, MujocoRobot

    robot = MujocoRobot()
    robot.set_velocity(0, 0.2, 0, 0.1)
    chunks = []
    for i in range(20):
        t = time.perf_counter()
        robot.advance((i + 1) * CHUNK_STEPS // robot.steps_per_ms)
        chunks.append(time.perf_counter() - t)
    if not os.path.exists("/proc/self/maps"):
        print("Ctrl-C: needs /proc to see when the run has started (Linux)")
        return
    latencies = []
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "long.script")
        with open(path, "w", encoding="utf-8") as f:
            f.write(LONG)
        for _ in range(REPEAT):
            process = subprocess.Popen([sys.executable, "-m", "scriptc", "run", path, "--until",
                                        "3600000", "--trace", os.path.join(tmp, "t.jsonl")],
                                       stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            maps = Path(f"/proc/{process.pid}/maps")
            while "libmujoco" not in maps.read_text():
                time.sleep(0.001)
            time.sleep(1.5)  # the model is loaded and the session runs
            sent = time.perf_counter()
            process.send_signal(signal.SIGINT)
            process.communicate()
            latencies.append(time.perf_counter() - sent)
            assert process.returncode == 130, process.returncode
    print(f"Ctrl-C during a run of an hour on MuJoCo: exit 130 {min(latencies) * 1000:.0f} to "
          f"{max(latencies) * 1000:.0f} ms after the signal (process exit included); one chunk "
          f"of {CHUNK_STEPS:,} steps takes {min(chunks) * 1000:.1f} to {max(chunks) * 1000:.1f} "
          "ms")


if __name__ == "__main__":
    main()
