"""`scriptc verify` (docs/verify.md): each property proved and violated on small scripts whose
answers are computed by hand in the comments, the runs it writes replayed by `scriptc run`, its
outputs read back, and the law that makes verify and run agree: every run the runtime makes,
in any world, is one the exploration found."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.analysis.analyze import analyze_bytes
from scriptc.cli.main import cli
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.rules import STANDARD_RULES
from scriptc.runtime.scenario import Scenario, TimedUpdate
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import parse_update
from scriptc.verify.explore import explore
from scriptc.verify.model import Model
from scriptc.verify.timeset import TimeSet
from scriptc.verify.verdicts import PROVED, UNKNOWN, VIOLATED, verify_model
from scriptc.verify.witness import Runner

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def model_of(text: str, *, checked: bool = True) -> Model:
    analysis = analyze_bytes("t.script", text.encode())
    assert analysis.script is not None
    if checked:
        assert not [d for d in analysis.diagnostics if d.severity.value == "error"], \
            analysis.diagnostics
    return Model(IRProgram(analysis.script, "t.script"))


def verified(text: str, **kwargs):
    model = model_of(text, checked=kwargs.pop("checked", True))
    runner = Runner(model.program, STANDARD_IMPLEMENTATIONS, STANDARD_RULES, DEFAULT_PROFILE)
    return verify_model(model, runner, **kwargs)


def statuses(verification) -> dict[str, str]:
    return {f.property: f.status for f in verification.findings}


LED = 'LD("0.2, 0.8, 0.3, 1, 0, {ms}")'
NEAR = "{CLASS #Human U ?kid (B: near(1.0))} ! {TRUE}"


def late(ms: int) -> str:
    return f"{{CLASS #Activity T ?me (?THIS>&elapsedtime OP> {ms})}} ! {{TRUE}}"


def inst(label: str, ms: int) -> str:
    return f"    [b#{label}#blk_inst: MV() {LED.format(ms=ms)} AO()]\n"


# -- duration, by hand ------------------------------------------------------------------------

BRANCH = ("[branch]\n[goal:g]\n  [action]\n" + inst("intro", 1000)
          + f"    [b##blk_jump: CND({NEAR}) TRJMP(short) FLSJMP(long)]\n"
          + inst("short", 500) + "    [b##blk_terminus]\n"
          + inst("long", 2000) + "    [b##blk_terminus]\n")


def test_a_branch_on_the_world_gives_both_durations() -> None:
    # intro 1000 ms, then short (500 ms) or long (2000 ms): 1500 or 3000 ms, both worlds.
    v = verified(BRANCH, witnesses=("fastest", "slowest"))
    assert (v.duration_min, v.duration_max) == (1500, 3000)
    assert set(statuses(v).values()) == {PROVED}
    fastest, slowest = v.witnesses
    assert fastest.confirmed and fastest.result.time_ms == 1500
    assert slowest.confirmed and slowest.result.time_ms == 3000


TIMEOUT = ("[timeout]\n[goal:g]\n  [action]\n" + inst("wait", 700)
           + f"    [b##blk_jump: CND({NEAR}) TRJMP(hello) FLSJMP()]\n"
           + f"    [b##blk_jump: CND({late(10000)}) TRJMP(bye) FLSJMP(wait)]\n"
           + inst("hello", 1000) + "    [b##blk_terminus]\n"
           + inst("bye", 300) + "    [b##blk_terminus]\n")


def test_a_wait_left_on_a_timeout_is_taken_whole() -> None:
    # `wait` starts at 0, 700, ...; the jumps are read when it ends, at 700 k ms. A child at
    # the first reading: 700 + 1000 = 1700 ms. The time-out holds from 10001 ms: first read
    # at 10500 ms (after the 15th wait, started at 9800): bye ends at 10800. At 10500 the
    # child is seen first if there is one: 10500 + 1000 = 11500 ms, the greatest.
    v = verified(TIMEOUT)
    assert (v.duration_min, v.duration_max) == (1700, 11500)
    wait = v.model.steps[0]
    assert v.exploration.known[wait.index].pieces == ((0, 700, 15),)  # 0, 700, ..., 9800
    assert v.exploration.accelerated >= 1  # the turns were added at once, not one by one
    assert statuses(v)["terminates"] == PROVED and statuses(v)["duration"] == PROVED


def test_the_turns_stop_at_the_threshold_whatever_its_distance() -> None:
    # A loop of 500 ms left when the elapsed time passes 1,000,000 ms: `wait` starts 2,001
    # times (0 to 1,000,000 ms), and the exploration is still a handful of records.
    text = TIMEOUT.replace("700", "500").replace("10000", "1000000")
    found = explore(model_of(text))
    assert found.known[0].pieces == ((0, 500, 2001),)
    assert found.count < 20
    assert found.end_times().max() == 1000500 + 1000


# -- the properties violated -------------------------------------------------------------------

STALL = ("[stall]\n[goal:g]\n  [action]\n" + inst("wait", 500)
         + f"    [b##blk_jump: CND({NEAR}) TRJMP(hello) FLSJMP(wait)]\n"
         + inst("hello", 1000) + "    [b##blk_terminus]\n")


def test_a_loop_without_timeout_never_ends() -> None:
    v = verified(STALL)
    s = statuses(v)
    assert s["no-stall"] == VIOLATED and s["terminates"] == VIOLATED
    assert v.duration_min == 1500 and v.duration_max is None and v.unbounded
    witness = v.finding("no-stall").witness
    assert witness.confirmed and witness.result.outcome == "until"
    assert witness.until == 1500  # two turns from 0 ms, then one more
    assert "forever" in v.finding("no-stall").detail


def test_a_cycle_that_lets_no_time_pass_is_found_in_an_unchecked_script() -> None:
    # Lint refuses it (F002) and so does `scriptc verify`; through the library, the cycle
    # a -> b -> a at 0 ms is found and replayed: the runtime stops with a read error.
    text = ("[spin]\n[goal:g]\n  [action]\n"
            f"    [b#a#blk_jump: CND({NEAR}) TRJMP(b) FLSJMP(end)]\n"
            "    [b#b#blk_jump: CND({CLASS #Object T ?o (B: near(1.0))} ! {TRUE}) "
            "TRJMP(a) FLSJMP(end)]\n" + inst("end", 100) + "    [b##blk_terminus]\n")
    v = verified(text, checked=False)
    finding = v.finding("no-progress")
    assert finding.status == VIOLATED, finding.detail
    assert finding.witness.result.outcome == "error"
    assert statuses(v)["terminates"] == VIOLATED


UNREACHABLE = ("[never]\n[goal:g]\n  [action]\n" + inst("w", 700)
               + "    [b##blk_jump: CND({CLASS #Activity T ?me (?THIS>&elapsedtime OP< 500)}"
               " ! {TRUE}) TRJMP(fast) FLSJMP(end)]\n"
               + "    [b#end#blk_terminus]\n[goal:quick]\n  [action]\n" + inst("fast", 1000)
               + "    [b##blk_terminus]\n")


def test_a_goal_behind_a_time_that_has_passed_is_never_reached() -> None:
    # The jump is read at 700 ms and is true before 500 ms only.
    v = verified(UNREACHABLE)
    goals = v.finding("goals")
    assert goals.status == VIOLATED and "`quick`" in goals.detail
    assert "read at 700 ms" in goals.items[0].notes[0]
    assert "0 to 499 ms" in goals.items[0].notes[0]
    assert v.finding("blocks").status == VIOLATED
    assert v.duration_min == v.duration_max == 700


UNSAFE = ("[rush]\n[goal:g]\n  [action]\n"
          "    [b##blk_jump: CND({CLASS #Human U ?kid (B: near(1.5))} ! {TRUE}) TRJMP(fast) "
          "FLSJMP(end)]\n    [b#fast#blk_inst: MV(\"0.9, 0, 0, 100, 1000\") LD() AO()]\n"
          + inst("end", 1000) + "    [b##blk_terminus]\n")


def test_a_block_above_the_profile_that_a_run_reads_needs_the_governor() -> None:
    model = model_of(UNSAFE.replace("[b#fast", "% scriptc: ignore[K001] %\n    [b#fast"))
    runner = Runner(model.program, STANDARD_IMPLEMENTATIONS, STANDARD_RULES, DEFAULT_PROFILE)
    v = verify_model(model, runner, unsafe={1: ["too fast (K001)"]})
    safety = v.finding("safety")
    assert safety.status == VIOLATED and safety.witness.confirmed
    assert safety.witness.governed
    assert any(e["event"] == "governor" for e in safety.witness.result.trace.events)
    # The same block, never read, is no violation.
    never = model_of(UNSAFE.replace("B: near(1.5)", "B: near(1.5), ?THIS>&positionrho OP> 2")
                     .replace("[b#fast", "% scriptc: ignore[K001] %\n    [b#fast"))
    v = verify_model(never, Runner(never.program, STANDARD_IMPLEMENTATIONS, STANDARD_RULES,
                                   DEFAULT_PROFILE), unsafe={1: ["too fast (K001)"]})
    assert v.finding("safety").status == PROVED
    assert "never read" in v.finding("safety").detail


def test_a_bound_makes_what_it_stops_unknown_never_proved() -> None:
    v = verified(TIMEOUT, max_records=2)
    s = statuses(v)
    assert s["terminates"] == UNKNOWN and s["no-stall"] == UNKNOWN
    assert "2 sets of instants" in v.finding("no-stall").detail
    assert v.duration_max is None


def test_an_unconfirmed_run_is_unknown_not_violated() -> None:
    # Near is within 1 m, very near within 0.5 m: not near and very near at one instant is
    # a run verify finds (each condition the world's on its own) and no world makes.
    text = ("[near]\n[goal:g]\n  [action]\n"
            "    [b##blk_jump: CND({CLASS #Human T ?a (B: near(1.0))} ! {TRUE}) TRJMP(close) "
            "FLSJMP()]\n"
            "    [b##blk_jump: CND({CLASS #Human T ?b (B: near(0.5))} ! {TRUE}) TRJMP(busy) "
            "FLSJMP(calm)]\n"
            + inst("busy", 300) + "    [b##blk_terminus]\n"
            + inst("calm", 1000) + "    [b##blk_terminus]\n"
            + inst("close", 2000) + "    [b##blk_terminus]\n")
    v = verified(text)
    assert statuses(v)["blocks"] == UNKNOWN and statuses(v)["duration"] == UNKNOWN
    assert statuses(v)["goals"] == PROVED  # through `calm` or `close`


MODE = ("[mode]\n[goal:g]\n  [action]\n"
        '    [b##blk_jump: CND({VAR @mode U F: str("calm")} ! {TRUE}) TRJMP() FLSJMP()]\n'
        + inst("w", 500)
        + '    [b##blk_jump: CND(! {E: eq(@mode, "busy")}) TRJMP(busy) FLSJMP(calm)]\n'
        + inst("busy", 300) + "    [b##blk_terminus]\n"
        + inst("calm", 1000) + "    [b##blk_terminus]\n")


def test_a_variable_given_a_constant_is_the_robots() -> None:
    # `@mode` is "calm" (scope U) from the first reading: the jump after the wait compares it
    # with "busy", false: `busy` is never read, the session lasts 500 + 1000 ms.
    v = verified(MODE)
    assert v.model.tracked == {"@mode"}
    assert (v.duration_min, v.duration_max) == (1500, 1500)
    blocks = v.finding("blocks")
    assert blocks.status == VIOLATED  # `busy` and the terminus after it
    assert [i.key for i in blocks.items] == ["goal0/act0/blk3", "goal0/act0/blk4"]
    assert statuses(v)["duration"] == PROVED


def test_a_variable_of_scope_l_is_gone_once_time_passes() -> None:
    # With scope L the reader's step ends at `w`: `@mode` is unset when the jump reads it,
    # and no comparison with a missing value holds, `neq` included.
    text = MODE.replace("VAR @mode U", "VAR @mode L").replace("eq(@mode", "neq(@mode")
    v = verified(text)
    assert (v.duration_min, v.duration_max) == (1500, 1500)  # `neq` false: calm
    same_read = MODE.replace("VAR @mode U", "VAR @mode L").replace(inst("w", 500), "")
    v = verified(same_read)  # read in the same step, before any time passes: still set
    assert (v.duration_min, v.duration_max) == (1000, 1000)


def test_a_variable_given_the_time_or_the_world_is_the_worlds() -> None:
    v = verified(MODE.replace('F: str("calm")', "F: now()"))
    assert not v.model.tracked and (v.duration_min, v.duration_max) == (800, 1500)


# -- the rule library's overrides --------------------------------------------------------------

TIME_UP = ('[time_up]\n[alfa:2, time_up, "goal=bye;when=' + late(4000).replace('"', '\\"')
           + '", "", A, U]\n[omega:2, time_up, "", "", R, L]\n[goal:play]\n  [action]\n'
           + inst("wait", 1000)
           + f"    [b##blk_jump: CND({NEAR}) TRJMP(done) FLSJMP(wait)]\n"
           + "    [b#done#blk_terminus]\n[goal:bye]\n  [action]\n"
           + "    % scriptc: ignore[unreachable-block] %\n" + inst("bye", 1000)
           + "    [b##blk_terminus]\n")


def test_an_override_on_the_clock_fires_at_the_blocks_first_instant_after_it() -> None:
    # `wait` starts at 0, 1000, ...; the override holds from 4001 ms. Issued at 4000 the block
    # has no instant of its own before 5000 (its LED runs 0-1000): the world may make one
    # from 4001 (bye ends 5001-5999), else the chain fires it at 5000, after the jump read
    # then (bye ends 6000). A child seen at 1000 ms ends it at once.
    v = verified(TIME_UP, witnesses=("slowest", "bye"))
    assert not v.model.assumed and len(v.model.switches) == 1
    assert (v.duration_min, v.duration_max) == (1000, 6000)
    assert statuses(v)["duration"] == PROVED and statuses(v)["goals"] == PROVED
    slowest = v.witnesses[0]
    assert slowest.confirmed and any(e["event"] == "override" and e["t"] == 5000
                                     for e in slowest.result.trace.events)
    # The ends: a child seen at a reading (1000, ..., 5000 ms), or bye after the override.
    assert v.exploration.end_times() == (TimeSet.progression(1000, 1000, 5)
                                         | TimeSet.interval(5001, 6000))


def test_an_override_at_once_never_lets_the_first_block_finish() -> None:
    # `when` is {TRUE}: the chain fires it at 0 ms, when the first block is issued.
    text = TIME_UP.replace("goal=bye;when=" + late(4000).replace('"', '\\"'), "goal=bye")
    v = verified(text)
    assert (v.duration_min, v.duration_max) == (1000, 1000)
    assert statuses(v)["blocks"] == VIOLATED  # the jump and `done` are never read
    assert v.exploration.known[1] == v.exploration.known[2] == TimeSet.empty()


def test_an_override_the_world_decides_may_come_at_any_instant() -> None:
    text = TIME_UP.replace("when=" + late(4000).replace('"', '\\"'),
                           "when={CLASS #Human L ?k (?THIS>&positionrho OP> 3.0)} ! {TRUE}")
    v = verified(text, witnesses=("bye",))
    # A child far away at any millisecond: bye from 0 to ... a run that never ends (the
    # child neither comes near nor goes far): no-stall is violated.
    assert v.duration_min == 1000 and statuses(v)["no-stall"] == VIOLATED
    assert v.witnesses[0].confirmed


# -- the command line ---------------------------------------------------------------------------

def run_cli(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR",)}
    return subprocess.run([sys.executable, "-m", "scriptc", *args], cwd=cwd, text=True,
                          capture_output=True, env=env, timeout=120, check=False)


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    for name, text in (("branch", BRANCH), ("stall", STALL), ("never", UNREACHABLE)):
        (tmp_path / f"{name}.script").write_text(text, encoding="utf-8")
    (tmp_path / "broken.script").write_text("[broken]\n[goal:g]\n", encoding="utf-8")
    return tmp_path


def test_exit_status_says_what_was_found(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(folder)
    runner = CliRunner()
    assert runner.invoke(cli, ["verify", "branch.script"]).exit_code == 0
    assert runner.invoke(cli, ["verify", "stall.script"]).exit_code == 1
    assert runner.invoke(cli, ["verify", "never.script"]).exit_code == 1
    result = runner.invoke(cli, ["verify", "broken.script"])
    assert result.exit_code == 2 and "not verified" in result.output
    assert runner.invoke(cli, ["verify", "nothing.script"]).exit_code == 2
    result = runner.invoke(cli, ["verify", "branch.script", "--witness", "nope"])
    assert result.exit_code == 2 and "has no goal `nope`" in result.output


@pytest.mark.slow  # a process of its own
def test_json_is_one_object_per_file(folder: Path) -> None:
    done = run_cli(["verify", "--json", "branch.script", "stall.script"], folder)
    assert done.returncode == 1, done.stderr
    objects = [json.loads(line) for line in done.stdout.splitlines()]
    assert [o["file"] for o in objects] == ["branch.script", "stall.script"]
    first, second = objects
    assert first["duration_ms"] == {"min": 1500, "max": 3000}
    assert {p["property"] for p in first["properties"]} == {
        "terminates", "goals", "blocks", "duration", "no-stall", "no-progress", "safety"}
    assert second["duration_ms"]["max"] is None
    stall = next(p for p in second["properties"] if p["property"] == "no-stall")
    assert stall["status"] == "violated"
    assert stall["counterexample"] == os.path.join("scriptc-verify",
                                                   "stall.no-stall.world.json")
    assert isinstance(first["states"], int) and first["seconds"] >= 0


@pytest.mark.slow  # a process of its own
def test_sarif_and_github_point_at_the_line(folder: Path) -> None:
    sarif = json.loads(run_cli(["verify", "--format", "sarif", "never.script"], folder).stdout)
    results = sarif["runs"][0]["results"]
    assert {r["ruleId"] for r in results} == {"Y002"}
    region = results[0]["locations"][0]["physicalLocation"]["region"]
    assert region["startLine"] == 7  # `[goal:quick]`
    github = run_cli(["verify", "--format", "github", "stall.script"], folder).stdout
    assert github.startswith("::error file=") and "line=5" in github and "Y001" in github


@pytest.mark.slow  # a process of its own
def test_text_shows_each_property_and_the_replay(folder: Path) -> None:
    done = run_cli(["verify", "--stats", "stall.script"], folder)
    out = done.stdout
    assert "  no-stall     violated" in out and "  goals        proved" in out
    assert "error[Y001]" in out and " --> stall.script:5:5" in out
    assert "sets of instants explored" in out
    assert ("help: replay it: scriptc run stall.script --world "
            "scriptc-verify/stall.no-stall.world.json --until 1500") in out
    assert ("wrote scriptc-verify/stall.no-stall.world.json (no-stall, confirmed by a "
            "replay)") in out
    done = run_cli(["verify", "stall.script", "--witness", "slowest"], folder)
    assert "no run written for `--witness slowest`: no run ends at a greatest time" in done.stdout


@pytest.mark.slow  # a process of its own
def test_a_terminal_sees_the_exploration_under_way(tmp_path: Path) -> None:
    """On a terminal (stderr a pseudo-terminal here) a status line says how far the
    exploration is; it goes away at the end, and stdout stays the report."""
    import pty

    sys.path.insert(0, str(ROOT / "bench"))
    from generate import waiting_script

    (tmp_path / "long.script").write_text(waiting_script(100), encoding="utf-8")
    leader, follower = pty.openpty()
    env = {k: v for k, v in os.environ.items() if k not in ("TERM", "NO_COLOR")}
    proc = subprocess.Popen([sys.executable, "-m", "scriptc", "verify", "long.script"],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=follower,
                            env={**env, "TERM": "xterm"})
    os.close(follower)
    seen = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:  # the process closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    out, _ = proc.communicate(timeout=120)
    os.close(leader)
    assert proc.returncode == 0
    assert b"verifying long.script: " in seen and b"sets of instants explored" in seen
    assert out.decode().startswith("verify long.script\n")


@pytest.mark.slow  # a process of its own
def test_the_counterexamples_replay_through_scriptc_run(folder: Path) -> None:
    assert run_cli(["verify", "stall.script", "branch.script", "--witness", "slowest",
                    "--witness", "g"], folder).returncode == 1
    scenarios = folder / "scriptc-verify"
    names = sorted(p.name for p in scenarios.iterdir())
    assert names == ["branch.goal-g.world.json", "branch.slowest.world.json",
                     "stall.goal-g.world.json", "stall.no-stall.world.json"]
    stall = run_cli(["run", "stall.script", "--world", "scriptc-verify/stall.no-stall.world.json",
                     "--until", "1500", "--robot", "kinematic", "--json"], folder)
    assert json.loads(stall.stdout)["outcome"] == "until"
    slowest = run_cli(["run", "branch.script", "--world",
                       "scriptc-verify/branch.slowest.world.json", "--robot", "kinematic",
                       "--json"], folder)
    summary = json.loads(slowest.stdout)
    assert summary["outcome"] == "completed" and summary["time_ms"] == 3000
    goal = run_cli(["run", "branch.script", "--world", "scriptc-verify/branch.goal-g.world.json",
                    "--robot", "kinematic", "--trace", "-"], folder)
    events = [json.loads(line) for line in goal.stdout.splitlines() if line.startswith("{")]
    assert any(e["event"] == "goal" and e["goalid"] == "g" and e["record"] == "reached"
               for e in events)


@pytest.mark.slow
def test_ctrl_c_stops_at_once_with_what_was_decided(tmp_path: Path) -> None:
    sys.path.insert(0, str(ROOT / "bench"))
    from generate import waiting_script

    (tmp_path / "long.script").write_text(waiting_script(400), encoding="utf-8")
    proc = subprocess.Popen([sys.executable, "-m", "scriptc", "verify", "long.script"],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    time.sleep(4.0)  # reading and checking the 4,000 blocks done: exploring or replaying
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert time.monotonic() - sent < 3.0
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    assert "unknown" in out  # what was not decided is said so


# -- the examples -------------------------------------------------------------------------------

def documented_durations() -> dict[str, tuple[int, int]]:
    """The table of examples/README.md, "What `scriptc verify` proves": each activity's
    shortest and longest session, in ms."""
    import re

    text = (EXAMPLES / "README.md").read_text(encoding="utf-8")
    section = text.split("## What `scriptc verify` proves", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| `(\w+)` \| ([\d.]+) s \| ([\d.]+) s \|$", section, re.MULTILINE)
    return {name: (round(float(lo) * 1000), round(float(hi) * 1000)) for name, lo, hi in rows}


def test_the_documented_table_names_every_example() -> None:
    assert set(documented_durations()) == {p.stem for p in EXAMPLES.glob("*.script")}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.script")))
def test_every_example_is_verified(name: str) -> None:
    """What examples/README.md says was proved of each example, and its session times."""
    from scriptc.ops.verify import VerifyOptions, verify_file

    result = verify_file(str(EXAMPLES / f"{name}.script"), VerifyOptions(counterexamples=None))
    assert result.verification is not None, result.problem
    found = statuses(result.verification)
    expected = dict.fromkeys(found, PROVED)
    if name == "test_act":  # the thesis's listing: it jumps over its last block, always,
        expected["blocks"] = VIOLATED  # and dances at 10 m/s (the thesis had no profile)
        expected["safety"] = VIOLATED
    assert found == expected
    v = result.verification
    assert (v.duration_min, v.duration_max) == documented_durations()[name]


# -- the law: verify and run agree ---------------------------------------------------------------

@st.composite
def activities(draw) -> str:
    """Small activities: instruction blocks of random lengths, jumps on the world (a child
    near), on the elapsed time, or that set or compare a variable, to random labels forwards
    and backwards, a terminus, and sometimes an override to the second goal (when the child
    is far, when a time has passed, or at once)."""
    n = draw(st.integers(3, 9))
    labels = [f"b{i}" for i in range(n)]
    lines = ["[random_activity]\n"]
    switch = draw(st.sampled_from(["", "", "world", "time", "true"]))
    if switch:
        when = {"world": "when={CLASS #Human L ?k (?THIS>&positionrho OP> 3.0)} ! {TRUE}",
                "time": f"when={late(draw(st.sampled_from([300, 1200, 2600])))}",
                "true": ""}[switch]
        lines.append(f'[alfa:2, jump_away, "goal=g1;{when}", "", A, U]\n'
                     '[omega:2, jump_away, "", "", R, L]\n')
    lines.append("[goal:g0]\n  [action]\n")
    for i in range(n):
        if i == n // 2:
            lines.append("[goal:g1]\n  [action]\n")
        kind = draw(st.sampled_from(["inst", "inst", "world", "time", "end", "set", "test"]))
        if kind == "inst" or i == 0:
            ms = draw(st.sampled_from([0, 100, 300, 500, 700]))
            lines.append(inst(labels[i], ms) if ms else
                         f"    [b#{labels[i]}#blk_inst: MV() LD() AO(\"Silence, 0, 200\")]\n")
        elif kind == "end":
            lines.append(f"    [b#{labels[i]}#blk_terminus]\n")
        else:
            if kind == "set":  # a variable given a text, of some scope
                scope, value = draw(st.sampled_from("ULT")), draw(st.sampled_from("ab"))
                cond = f'{{VAR @m {scope} F: str("{value}")}} ! {{TRUE}}'
            elif kind == "test":
                cond = f'! {{E: {draw(st.sampled_from(["eq", "neq"]))}(@m, "a")}}'
            else:
                cond = NEAR if kind == "world" else late(draw(st.sampled_from([400, 1000, 2500])))
            target = labels[draw(st.integers(0, n - 1))]
            lines.append(f"    [b#{labels[i]}#blk_jump: CND({cond}) TRJMP({target}) FLSJMP()]\n")
    lines.append("    [b##blk_terminus]\n")
    return "".join(lines)


@st.composite
def worlds(draw) -> list[tuple[int, float]]:
    """A child who comes and goes: (instant, distance) updates."""
    times = sorted(draw(st.lists(st.integers(0, 5000), max_size=6, unique=True)))
    return [(t, draw(st.sampled_from([0.5, 0.9, 2.0, 4.0]))) for t in times]


@settings(max_examples=60, deadline=None)
@given(activities(), worlds())
def test_every_run_is_one_the_exploration_found(text: str, world: list[tuple[int, float]]
                                                ) -> None:
    analysis = analyze_bytes("r.script", text.encode())
    if analysis.script is None or any(d.severity.value == "error" for d in analysis.diagnostics):
        return  # lint refuses it (F002, a jump cycle without time): verify does too
    program = IRProgram(analysis.script, "r.script")
    found = explore(Model(program))
    if not found.complete:  # a bound reached (sets too complex): nothing is claimed
        assert found.bound
        return
    updates = [TimedUpdate(t, parse_update("Human/kid", "poses", "R",
                                           {"positionrho": rho, "positiontheta": 0.0}), k)
               for k, (t, rho) in enumerate(world)]
    trace = Trace()
    result = Session((program,), scenario=Scenario(updates=updates), trace=trace).run(20000)
    # Every block the run read (a jump, an instruction block issued) it read at an instant
    # the exploration knows for that block; the session ends at an instant it knows for the
    # end, or goes on past the time limit only if the exploration has runs that do.
    paths = {step.address.path: step.index for step in Model(program).steps}
    for e in trace.events:
        if e["event"] in ("jump", "block"):
            assert e["t"] in found.known[paths[e["path"]]], (e, found.known[paths[e["path"]]])
    if result.outcome == "completed":
        assert result.time_ms in found.end_times()
    if result.outcome == "until":
        ends = found.end_times()
        assert not ends or ends.max() is None or ends.max() > 20000 \
            or any(r.times.is_infinite for rs in found.records for r in rs)


@settings(max_examples=40, deadline=None)
@given(st.data())
def test_any_checked_script_is_verified_without_fault(data: st.DataObject) -> None:
    """Scripts of every shape (rule messages with any rulecode, every kind of condition):
    verify never fails, every property has one of the three verdicts, a violation of what
    exists (a loop without end, a block outside the profile) is never said without its
    replay, and the report renders."""
    from strategies import scripts

    from scriptc.diagnostics.render import render
    from scriptc.verify.report import as_data, diagnostics

    text = data.draw(scripts())
    analysis = analyze_bytes("s.script", text.encode())
    if analysis.script is None or any(d.severity.value == "error" for d in analysis.diagnostics):
        return
    v = verified(text, max_records=3000)
    for f in v.findings:
        assert f.status in (PROVED, VIOLATED, UNKNOWN)
        if f.status == VIOLATED and f.property in ("no-stall", "safety", "no-progress"):
            assert f.witness is not None and f.witness.confirmed
    render("text", [(analysis.source, diagnostics(v, {}))])
    json.dumps(as_data("s.script", v, {}, []))
