"""Compile speed: a generated ~1 MB script (10,000 blocks, half of them jumps with conditions)
end to end (scan, parse, lower, check, emit JSON: the library functions that `scriptc compile`
calls), beside lark's raw parse of the same items, and the growth from 0.1 MB to 1 MB (10x the
input should cost at most ~11x the time).

    python bench/bench_compile.py [--runs N]

CPU time of this process, best of N runs (the machine may be shared).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from generate import big_script

from scriptc.analysis.analyze import analyze_script
from scriptc.ops.build import emit
from scriptc.source import SourceFile
from scriptc.syntax.parser import script_lark
from scriptc.syntax.scan import scan


def best(fn, runs: int) -> float:
    times = []
    for _ in range(runs):
        t = time.process_time()
        fn()
        times.append(time.process_time() - t)
    return min(times)


def compile_text(text: str) -> str:
    analysis = analyze_script(SourceFile("big.script", text))
    assert analysis.ok, analysis.diagnostics[:3]
    return emit(analysis.script, "json")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    big = big_script(10_000)
    small = big_script(1_000)
    mb = len(big.encode()) / 1e6
    parser = script_lark()
    items = [big[r.span.start : r.span.end] for r in scan(big).items]
    raw = best(lambda: [parser.parse(s, start="item") for s in items], args.runs)
    full = best(lambda: compile_text(big), args.runs)
    tiny = best(lambda: compile_text(small), args.runs)
    print(f"input: {mb:.2f} MB, 10,000 blocks (5,000 conditions)")
    print(f"lark raw parse of the items:   {raw:6.3f} s  {mb / raw:5.2f} MB/s")
    print(f"compile end to end (to JSON):  {full:6.3f} s  {mb / full:5.2f} MB/s"
          "   (target >= 2.5 MB/s)")
    print(f"growth 1,000 -> 10,000 blocks: x{full / tiny:.1f} time for x10 input   (target <= ~11)")


if __name__ == "__main__":
    main()
