"""Run speed of the reference interpreter (`scriptc run`'s library path).

1. A ten-minute activity with the kinematic robot: 300 two-second instruction blocks (moves,
   LEDs, audio on all three tracks, several commands each), a jump with a CLASS condition
   after each, two rules in the chain (kick_starter, safety_stop), and a scenario with three
   children sending a pose every 250 ms (7,200 map updates). Target: under 0.5 s, that is at
   least 1,200x real time. Measured with and without a trace.
2. Condition evaluation over a map of 1,000 Humans, per jump: the CLASS assignment of the
   issue's done-when (`?THIS>&positionrho OP< 1.0`) when no entity passes (all 1,000 tried),
   when only the youngest does, when the oldest does; and an assignment plus E functions.
   Target: under 1 ms per jump.

    python bench/bench_run.py [--runs N]

CPU time of this process, best of N runs (the machine may be shared).
"""

from __future__ import annotations

import argparse
import time

from scriptc.analysis.analyze import analyze_bytes
from scriptc.frontend.script import parse_condition
from scriptc.runtime.bindings import READER, Bindings
from scriptc.runtime.evaluate import EvalContext, evaluate
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import scenario_from_data
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.world import World, parse_update

MINUTES = 10


def activity_text(blocks: int = 300) -> str:
    lines = ["[ten_minutes]", '[alfa:0, kick_starter, "", "", A, M]',
             '[alfa:1, guard, "distance=0.3", "", A, U]', '[omega:0, kick_starter, "", "", R, L]',
             '[omega:1, guard, "", "", R, M]']
    per_goal = 30
    for i in range(blocks):
        if i % per_goal == 0:
            lines += [f"[goal:part{i // per_goal}]", "[action]"]
        v = 0.1 + (i % 5) * 0.02
        lines.append(
            f'[b#b{i}#blk_inst: MV("{v}, 0, 0.2, 0, 500", "0, {v}, 0, 0, 500", '
            f'"-{v}, 0, -0.2, 0, 500", "0, -{v}, 0, 0, 500") '
            'LD("1, 0, 0, 1, 0, 400", "0, 1, 0, 1, 100, 400", "0, 0, 1, 1, 100, 400", '
            f'"1, 1, 1, 1, 100, 400") AO("songs/s{i % 7}.wav, 0, 1900")]')
        lines.append(
            "[b##blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} "
            "! {E: gt(?kid>&positionrho, 0.2)}) TRJMP() FLSJMP()]")
    lines.append("[b##blk_terminus]")
    return "\n".join(lines) + "\n"


def scenario(ms: int) -> dict:
    updates = []
    for t in range(0, ms, 250):
        for k in range(3):
            rho = 0.5 + ((t // 250 + 7 * k) % 20) * 0.1
            updates.append({"at": t, "objectid": f"Human/kid{k}", "attributename": "poses",
                            "policy": "R",
                            "jsonmsg": {"positionrho": rho, "positiontheta": 0.1 * k}})
    return {"updates": updates}


def best(fn, runs: int, *args) -> tuple[float, object]:
    """The least CPU time of `runs` calls of `fn(*args)`, and what the last call returned."""
    times, out = [], None
    for _ in range(runs):
        t = time.process_time()
        out = fn(*args)
        times.append(time.process_time() - t)
    return min(times), out


def bench_activity(runs: int) -> None:
    analysis = analyze_bytes("ten_minutes.script", activity_text().encode(), "script")
    assert analysis.ok, [d.message for d in analysis.diagnostics][:3]
    program = IRProgram(analysis.script, "ten_minutes.script")
    world = scenario(MINUTES * 60_000)
    scn = scenario_from_data(world)

    def once(traced: bool):
        trace = Trace(enabled=traced)
        result = Session([program], scenario=scn, trace=trace).run()
        assert result.outcome == "completed", result.outcome
        return result, trace

    for traced in (False, True):
        seconds, (result, trace) = best(once, runs, traced)
        simulated = result.time_ms / 1000
        print(f"10-minute activity, kinematic robot, trace {'on ' if traced else 'off'}: "
              f"{seconds * 1000:7.1f} ms for {simulated:.0f} s simulated "
              f"({simulated / seconds:,.0f}x real time); {trace.count:,} trace events, "
              f"{len(world['updates']):,} map updates")


def bench_conditions(runs: int, n: int = 1000) -> None:
    world = World()
    for i in range(n):
        world.apply(parse_update(f"Human/h{i:04d}", "tracking", "R", {"appearanceon": i}), i)
        world.apply(parse_update(f"Human/h{i:04d}", "poses", "R",
                                 {"positionrho": 2.0 + i / 100}), i)
    ctx = EvalContext(world, Bindings(), STANDARD_IMPLEMENTATIONS)

    def per_jump(text: str, setup=None) -> float:
        condition, problems = parse_condition(text)
        assert condition is not None and not problems, problems
        repeat = 200

        def loop():
            for _ in range(repeat):
                ctx.bindings.end_script()
                ctx.begin(READER, 0)
                evaluate(condition, ctx)

        seconds, _ = best(loop, runs)
        return seconds / repeat * 1000

    cases = [
        ("no entity passes (all 1,000 tried)",
         "{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}", None),
        ("only the youngest passes",
         "{CLASS #Human U ?kid (?THIS>&positionrho OP> 11.985)} ! {TRUE}", None),
        ("the oldest passes",
         "{CLASS #Human U ?kid (?THIS>&positionrho OP< 2.005)} ! {TRUE}", None),
        ("two tests, a VAR and two E functions (none passes)",
         ("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0, B: near(1.5))} {VAR @t U F: now()} "
          "! {E: gt(?kid>&permanencetime, 2000)} {E: lt(@t, 5)}"), None),
    ]
    for label, text, setup in cases:
        ms = per_jump(text, setup)
        print(f"condition over {n:,} entities, {label}: {ms:.3f} ms per jump")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    bench_activity(args.runs)
    bench_conditions(args.runs)


if __name__ == "__main__":
    main()
