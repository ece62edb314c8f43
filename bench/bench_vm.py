"""Run speed of the bytecode VM (the executor `scriptc run` uses) beside the reference
interpreter over the IR, on the workloads of `bench_run.py`:

1. The ten-minute activity with the kinematic robot (300 instruction blocks, a CLASS jump after
   each, two rules, 7,200 map updates). Target: under 0.5 s (>= 1,200x real time).
2. Condition evaluation over a map of 1,000 Humans, per jump, the VM reading one jump block
   (the whole `read`: visit, condition, exit, the jump reported to a sink).
   Target: under 1 ms per jump.

    python bench/bench_vm.py [--runs N]

CPU time of this process, best of N runs (the machine may be shared).
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_run import MINUTES, activity_text, best, scenario

from scriptc import bytecode
from scriptc.analysis.analyze import analyze_bytes
from scriptc.ops.build import emit
from scriptc.runtime.bindings import Bindings
from scriptc.runtime.evaluate import EvalContext
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import scenario_from_data
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.runtime.vm import VMProgram
from scriptc.runtime.world import World, parse_update


def programs(text: str, name: str) -> dict:
    analysis = analyze_bytes(name, text.encode(), "script")
    assert analysis.ok, [d.message for d in analysis.diagnostics][:3]
    loaded = bytecode.load(emit(analysis.script, "bytecode", analysis.source))
    return {"ir": IRProgram(analysis.script, name), "vm": VMProgram(loaded, name),
            "vm (searches interpreted)": VMProgram(loaded, name, compile_searches=False)}


def bench_activity(runs: int) -> None:
    world = scenario(MINUTES * 60_000)
    scn = scenario_from_data(world)

    def once(program, traced: bool):
        trace = Trace(enabled=traced)
        result = Session([program], scenario=scn, trace=trace).run()
        assert result.outcome == "completed", result.outcome
        return result, trace

    for label, program in programs(activity_text(), "ten_minutes.script").items():
        for traced in (False, True):
            seconds, (result, trace) = best(once, runs, program, traced)
            simulated = result.time_ms / 1000
            print(f"10-minute activity, {label:26} trace {'on ' if traced else 'off'}: "
                  f"{seconds * 1000:7.1f} ms ({simulated / seconds:,.0f}x real time); "
                  f"{trace.count:,} trace events")


class _Sink:
    def visit(self, position) -> None:
        pass

    def jump(self, position, condition, evaluation, target) -> None:
        pass

    def sensor(self, position, payload) -> None:
        pass


def bench_conditions(runs: int, n: int = 1000) -> None:
    world = World()
    for i in range(n):
        world.apply(parse_update(f"Human/h{i:04d}", "tracking", "R", {"appearanceon": i}), i)
        world.apply(parse_update(f"Human/h{i:04d}", "poses", "R",
                                 {"positionrho": 2.0 + i / 100}), i)
    ctx = EvalContext(world, Bindings(), STANDARD_IMPLEMENTATIONS)
    sink = _Sink()
    cases = [
        ("no entity passes (all 1,000 tried)",
         "{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0)} ! {TRUE}"),
        ("only the youngest passes",
         "{CLASS #Human U ?kid (?THIS>&positionrho OP> 11.985)} ! {TRUE}"),
        ("the oldest passes", "{CLASS #Human U ?kid (?THIS>&positionrho OP< 2.005)} ! {TRUE}"),
        ("two tests, a VAR and two E functions (none passes)",
         ("{CLASS #Human U ?kid (?THIS>&positionrho OP< 1.0, B: near(1.5))} {VAR @t U F: now()} "
          "! {E: gt(?kid>&permanencetime, 2000)} {E: lt(@t, 5)}")),
    ]
    repeat = 200

    def loop(executor) -> None:
        for _ in range(repeat):
            ctx.bindings.end_script()
            executor.start()
            executor.read(ctx, sink)

    for label, condition in cases:
        text = (f"[c]\n[goal:g]\n[action]\n[b##blk_jump: CND({condition}) TRJMP() FLSJMP()]\n"
                "[b##blk_terminus]\n")
        for how, program in programs(text, "c.script").items():
            seconds, _ = best(loop, runs, program.executor())
            print(f"condition over {n:,} entities, {label}, {how}: "
                  f"{seconds / repeat * 1000:.3f} ms per jump")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    bench_activity(args.runs)
    bench_conditions(args.runs)


if __name__ == "__main__":
    main()
