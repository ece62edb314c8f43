"""Bytecode speed and size: the 10,000-block benchmark script (half of the blocks jumps with
a CLASS search) through codegen (IR -> Program), encode (Program -> bytes), decode, verify and
the listing, and the size of the .scb beside the thesis JSON of the same script.

    python bench/bench_bytecode.py [--runs N] [--blocks N]

CPU time of this process, best of N runs (the machine may be shared). The front end (parse,
lower, check) is not counted: bench_compile.py measures it.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from generate import big_script

from scriptc.analysis.analyze import analyze_script
from scriptc.bytecode import decode, disassemble, encode, verify
from scriptc.emit.codegen import codegen
from scriptc.gcpause import gc_paused
from scriptc.ops.build import emit
from scriptc.source import SourceFile


def best(fn, runs: int):
    times = []
    result = None
    for _ in range(runs):
        t = time.process_time()
        result = fn()
        times.append(time.process_time() - t)
    return min(times), result


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--blocks", type=int, default=10_000)
    args = ap.parse_args()
    source = SourceFile("big.script", big_script(args.blocks))
    analysis = analyze_script(source)
    assert analysis.ok, analysis.diagnostics[:3]
    script = analysis.script

    def gen():
        with gc_paused():  # as `scriptc.ops.build.emit` runs back ends
            return codegen(script, source)

    t_codegen, program = best(gen, args.runs)
    t_encode, data = best(lambda: encode(program), args.runs)
    t_decode, decoded = best(lambda: decode(data), args.runs)
    t_verify, _ = best(lambda: verify(decoded), args.runs)
    t_listing, listing = best(lambda: disassemble(decoded), 1)
    assert decoded == program
    json_size = len(emit(script, "json").encode("utf-8"))
    code = len(program.code)
    print(f"script: {len(source.text.encode()) / 1e6:.2f} MB, {len(program.blocks):,} blocks, "
          f"{len(program.constants):,} constants, {len(program.spans):,} code spans")
    print(f"codegen (IR -> Program):  {t_codegen:6.3f} s")
    print(f"encode  (Program -> .scb): {t_encode:6.3f} s")
    print(f"decode  (.scb -> Program): {t_decode:6.3f} s")
    print(f"verify:                   {t_verify:6.3f} s")
    print(f"encode + verify:          {t_encode + t_verify:6.3f} s   (target well under 0.5 s)")
    print(f"compile back end (codegen + encode): {t_codegen + t_encode:6.3f} s")
    print(f"load (decode + verify):              {t_decode + t_verify:6.3f} s")
    print(f"listing (dis):            {t_listing:6.3f} s   ({listing.count(chr(10)):,} lines)")
    print(f".scb size: {len(data) / 1e6:.2f} MB ({code / 1e6:.2f} MB of code), thesis JSON "
          f"{json_size / 1e6:.2f} MB: {len(data) / json_size:.0%} of the JSON")


if __name__ == "__main__":
    main()
