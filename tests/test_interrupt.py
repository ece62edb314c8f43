"""Ctrl-C: `scriptc.interrupt` (the first Ctrl-C is a request taken at a safe point, the second
stops at once), the session that stops between two instants with a trace of every instant
before, MuJoCo stepped in chunks that an interruption can cut, and `scriptc run` in a real
process stopped by a real SIGINT (docs/runtime.md, "Interrupting a run")."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from scriptc import interrupt
from scriptc.analysis.analyze import analyze_bytes, analyze_file
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.robots.kinematic import KinematicRobot
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace

ROOT = Path(__file__).resolve().parent.parent
TEST_ACT = ROOT / "examples" / "test_act.script"

# A move of 50 minutes: one instant at its start, the next at its end, an hour of physics in
# between (about 7 s of stepping on MuJoCo).
LONG = """\
[long]
[goal:g]
  [action]
    [b#go#blk_inst: MV("0.2, 0, 0.1, 0, 3000000") LD("0, 0, 1, 1, 0, 1000") AO()]
    [b##blk_jump: CND(! {TRUE}) TRJMP(go) FLSJMP()]
"""


def _wait_for(predicate, seconds: float = 5.0) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.001)
    return predicate()


def test_the_first_ctrl_c_is_a_request_and_the_second_stops_at_once() -> None:
    before = signal.getsignal(signal.SIGINT)
    with interrupt.catching():
        interrupt.check()  # nothing requested: nothing happens
        os.kill(os.getpid(), signal.SIGINT)
        assert _wait_for(interrupt.requested)
        with pytest.raises(interrupt.Interrupted):
            interrupt.check()
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            _wait_for(lambda: False, 2.0)
    # Leaving the block restores the handler and forgets the request.
    assert signal.getsignal(signal.SIGINT) is before
    assert not interrupt.requested()
    interrupt.check()


def test_catching_starts_with_no_request_left_over() -> None:
    interrupt.request()
    with interrupt.catching():
        assert not interrupt.requested()
        interrupt.check()


def test_deferred_holds_ctrl_c_and_sigterm_to_its_end_while_other_threads_run() -> None:
    """The system gives a signal sent to the process to any thread that does not block it (a
    worker pool's, pytest-xdist's); Python then runs the handler in the main thread: held all
    the same, delivered once each as the block ends, the handlers put back."""
    idle = threading.Event()
    other = threading.Thread(target=idle.wait, daemon=True)  # started before: signals open
    other.start()
    got: list[int] = []
    before_int = signal.getsignal(signal.SIGINT)
    before_term = signal.signal(signal.SIGTERM, lambda signum, frame: got.append(signum))
    finished = False
    try:
        with pytest.raises(KeyboardInterrupt), interrupt.deferred():
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGTERM)
            os.kill(os.getpid(), signal.SIGINT)
            _wait_for(lambda: False, 0.3)  # time for a handler to run, were one let through
            assert got == []
            finished = True
        assert finished
        assert got == [signal.SIGTERM]
        assert signal.getsignal(signal.SIGINT) is before_int
    finally:
        signal.signal(signal.SIGTERM, before_term)
        idle.set()
        other.join()


def test_a_worker_forked_inside_deferred_is_ended_by_sigterm_and_ignores_ctrl_c() -> None:
    from scriptc.ops.workers import start_worker

    with interrupt.deferred():
        pid = os.fork()
        if pid == 0:  # the worker: started as the pool starts it, then waits to be stopped
            try:
                start_worker()
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(10)
            finally:
                os._exit(3)
    time.sleep(0.3)
    os.kill(pid, signal.SIGTERM)
    _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGTERM


class StopAt(KinematicRobot):
    """A kinematic robot that asks to stop (as Ctrl-C would) once advanced to `at` ms."""

    def __init__(self, at: int) -> None:
        super().__init__()
        self.at = at

    def advance(self, t_ms: int) -> None:
        super().advance(t_ms)
        if t_ms >= self.at:
            interrupt.request()


def _test_act() -> IRProgram:
    analysis = analyze_file(TEST_ACT)
    return IRProgram(analysis.script, "test_act.script")


def test_an_interrupted_session_keeps_every_instant_before_and_says_so() -> None:
    """The request comes in the middle of an instant (the robot is advanced by a handler):
    that instant is finished, the next is not begun. The trace is the uninterrupted run's up to
    that instant, whole, then `session_end` with the outcome `interrupted`."""
    full = Trace()
    Session([_test_act()], trace=full).run()
    trace = Trace()
    with interrupt.catching():
        result = Session([_test_act()], trace=trace, robot=StopAt(5000)).run()
    assert not interrupt.requested()
    assert result.outcome == "interrupted"
    end = trace.events[-1]
    assert (end["event"], end["outcome"], end["t"], end["time_ms"]) == \
        ("session_end", "interrupted", result.time_ms, result.time_ms)
    kept = trace.events[:-1]
    assert kept == full.events[:len(kept)]
    # Whole instants: the last one kept is at the time reached, and the uninterrupted run
    # has nothing more at that time (the next event is a later instant).
    assert kept[-1]["t"] == result.time_ms >= 5000
    assert full.events[len(kept)]["t"] > result.time_ms
    assert result.loads[-1].ended_by is None  # the script was running, and still is


def test_mujoco_steps_in_chunks_that_change_nothing_and_an_interruption_cuts() -> None:
    pytest.importorskip("mujoco")
    from scriptc.robot.profile import DEFAULT_PROFILE
    from scriptc.runtime.robots import mujoco as backend

    # Governed moves (every change a ramp) of 7.5 s and 12.3 s: stepped in chunks, or each
    # interval in one call, the same steps, so the same trace and pose, to the last bit.
    text = ("[m]\n[goal:g]\n[action]\n[b##blk_inst: MV(\"0.3, 0.1, 0.5, 0, 7500\", "
            "\"0, 0.2, -0.4, 0, 12300\") LD() AO()]\n[b##blk_terminus]\n")
    analysis = analyze_bytes("m.script", text.encode(), "script")

    def run() -> tuple[str, object]:
        trace = Trace()
        robot = backend.MujocoRobot()
        Session([IRProgram(analysis.script, "m.script")], robot=robot, trace=trace,
                profile=DEFAULT_PROFILE).run()
        return trace.text(), robot

    chunked, chunked_robot = run()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(backend, "CHUNK_STEPS", 10**9)  # one mj_step call per interval
        whole, whole_robot = run()
    assert chunked == whole and chunked_robot.pose() == whole_robot.pose()
    assert chunked_robot.steps == whole_robot.steps > 19_800

    robot = backend.MujocoRobot()
    robot.set_velocity(0, 0.2, 0, 0)  # at once: no ramp
    with interrupt.catching():
        interrupt.request()
        with pytest.raises(interrupt.Interrupted):
            robot.advance(3_600_000)
    chunk_ms = backend.CHUNK_STEPS // robot.steps_per_ms
    assert robot.time_ms == chunk_ms  # one chunk, then the check between two chunks
    assert robot.pose().x == pytest.approx(0.2 * chunk_ms / 1000, rel=1e-3)


@pytest.mark.slow
def test_a_mujoco_session_stops_within_the_long_physics_of_one_interval() -> None:
    """The only instants are 0 ms and the ends of the LED command and of the move; the request
    comes while the physics is stepped towards the move's end: the session ends there, at the
    time the physics reached."""
    pytest.importorskip("mujoco")
    analysis = analyze_bytes("long.script", LONG.encode(), "script")
    trace = Trace()
    session = Session([IRProgram(analysis.script, "long.script")], robot="mujoco", trace=trace)
    timer = threading.Timer(0.3, interrupt.request)
    with interrupt.catching():
        timer.start()
        started = time.perf_counter()
        result = session.run(3_600_000)
        took = time.perf_counter() - started
    timer.join()
    assert result.outcome == "interrupted"
    assert 1000 < result.time_ms < 3_000_000 and result.time_ms == session.robot.time_ms
    assert took < 3.0  # the whole move takes about 6 s of stepping
    assert [e["t"] for e in trace.events][-3:] == [0, 1000, result.time_ms]  # the LED's end
    assert trace.events[-2]["event"] == "cmd_stop"


def _mapped(pid: int, library: str) -> bool:
    try:
        return library in Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return False


@pytest.mark.slow
@pytest.mark.skipif(sys.platform != "linux", reason="reads /proc/PID/maps to see MuJoCo loaded")
def test_ctrl_c_stops_scriptc_run_on_mujoco_at_once_with_its_trace(tmp_path: Path) -> None:
    """A real `scriptc run` on MuJoCo with a long `--until`, a real SIGINT once the run has
    started: exit 130 within half a second (plus the process's own exit), the summary says
    what was interrupted, and the trace is valid and complete up to the interruption: the
    same as a run stopped by `--until` at the time reached."""
    pytest.importorskip("mujoco")
    script = tmp_path / "long.script"
    script.write_text(LONG, encoding="utf-8")
    trace = tmp_path / "run.jsonl"
    command = [sys.executable, "-m", "scriptc", "run", str(script), "--until", "3600000",
               "--trace", str(trace)]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, cwd=tmp_path)
    try:
        # MuJoCo is loaded just before the session is made; give it a moment to start.
        assert _wait_for(lambda: _mapped(process.pid, "libmujoco"), 60.0)
        time.sleep(1.5)
        assert process.poll() is None, process.communicate()
        sent = time.perf_counter()
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=10)
        latency = time.perf_counter() - sent
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    print(f"\nCtrl-C to exit of `scriptc run` on MuJoCo: {latency * 1000:.0f} ms")
    assert process.returncode == 130, err
    assert latency < 1.5, latency  # the stop itself is one chunk of physics (about 10 ms)
    assert out.startswith("interrupted at ") and (
        f"stopped by Ctrl-C while `long` ({script}) was running" in out.splitlines()[0]), out
    events = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    assert f"trace: {trace} ({len(events)} events, up to the interruption)" in out, out
    end = events[-1]
    assert (end["event"], end["outcome"]) == ("session_end", "interrupted")
    reached = end["time_ms"]
    assert 1000 < reached < 3_000_000
    # The same run stopped at that time by --until writes the same instants.
    reference = tmp_path / "until.jsonl"
    done = subprocess.run([*command[:-4], "--until", str(reached), "--trace", str(reference)],
                          capture_output=True, text=True, cwd=tmp_path, check=False)
    assert done.returncode == 0, done.stderr
    same = [json.loads(line) for line in reference.read_text(encoding="utf-8").splitlines()]
    assert events[1:-1] == same[1:len(events) - 1]
    # What the reference has beyond is its end at that time: the governor brakes, then ends.
    assert {e["event"] for e in same[len(events) - 1:]} <= {"governor", "session_end"}
    assert {e["t"] for e in same[len(events) - 1:]} == {reached}
