"""A long mutation-fuzzing campaign over every entry point (the mutations, entry points and laws
of tests/fuzzing.py; the suite runs a short one under hypothesis, tests/test_fuzz.py).

    python bench/fuzz.py [--seconds N] [--seed S] [--entry NAME ...] [--save DIR]

Entry points take turns, each input a real example mutated one to three times. It prints, per
entry point, the inputs tried and the failures, then each failure class (a broken law, or a
crash and where it was raised) with how often it happened and the smallest input that showed
it; `--save DIR` writes those inputs (`CLASS.ENTRY.bin`) to replay with
`fuzzing.drive(entry, seed, data)`. An input slower than `--slow` seconds counts as a failure
of its own class (`ENTRY: slow`); one still running after `--hang` seconds is stopped (an
alarm signal) and counts as `ENTRY: hang`. A new class is printed (and saved) as soon as it
is found. Exit status 1 when anything failed.
"""

from __future__ import annotations

import argparse
import random
import re
import signal
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import fuzzing


class Hang(Exception):
    """Raised by the alarm in the input that ran past `--hang` seconds."""


def _alarm(_signum, _frame) -> None:
    raise Hang


def _save(folder: Path | None, problem: str, entry: str, data: bytes) -> None:
    if folder is None:
        return
    folder.mkdir(parents=True, exist_ok=True)
    slug = re.sub(r"[^A-Za-z0-9]+", "-", problem).strip("-")[:60]
    (folder / f"{slug}.{entry}.bin").write_bytes(data)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="how long to run")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random mutations")
    parser.add_argument("--entry", action="append", choices=sorted(fuzzing.ENTRIES),
                        help="entry points to drive (default: all)")
    parser.add_argument("--save", type=Path, help="write the smallest input of each class here")
    parser.add_argument("--slow", type=float, default=60.0,
                        help="an input taking longer (s) is a failure of class `slow`")
    parser.add_argument("--hang", type=float, default=120.0,
                        help="an input still running after this (s) is stopped: `hang`")
    args = parser.parse_args(argv)
    signal.signal(signal.SIGALRM, _alarm)

    rng = random.Random(args.seed)
    entries = args.entry or list(fuzzing.ENTRIES)
    tried: Counter[str] = Counter()
    failed: Counter[str] = Counter()
    classes: Counter[str] = Counter()
    smallest: dict[str, tuple[str, str, bytes]] = {}
    seconds: Counter[str] = Counter()
    deadline = time.monotonic() + args.seconds
    turn = 0
    while time.monotonic() < deadline:
        entry = entries[turn % len(entries)]
        turn += 1
        seeds = fuzzing.SEEDS[fuzzing.ENTRIES[entry].kind]
        seed_name, seed = seeds[rng.randrange(len(seeds))]
        data = fuzzing.mutate(seed, rng.randint)
        tried[entry] += 1
        start = time.monotonic()
        problem = None
        signal.setitimer(signal.ITIMER_REAL, args.hang)
        try:
            fuzzing.drive(entry, seed_name, data)
        except Hang:
            problem = f"{entry}: hang (more than {args.hang:g} s)"
        except Exception as exc:  # every failure is counted, by class
            problem = fuzzing.classify(entry, exc)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        took = time.monotonic() - start
        seconds[entry] += took
        if problem is None and took > args.slow:
            problem = f"{entry}: slow (more than {args.slow:g} s)"
        if problem is not None:
            failed[entry] += 1
            classes[problem] += 1
            if problem not in smallest:
                print(f"new class after {sum(tried.values())} inputs: {problem} "
                      f"({len(data)} bytes, from {seed_name})", flush=True)
            if problem not in smallest or len(data) < len(smallest[problem][2]):
                smallest[problem] = (entry, seed_name, data)
                _save(args.save, problem, entry, data)

    print(f"{sum(tried.values())} inputs in {args.seconds:g} s (seed {args.seed})")
    print(f"{'entry point':<12} {'inputs':>8} {'failures':>9} {'ms/input':>9}")
    for entry in entries:
        per = 1000 * seconds[entry] / tried[entry] if tried[entry] else 0.0
        print(f"{entry:<12} {tried[entry]:>8} {failed[entry]:>9} {per:>9.1f}")
    if not classes:
        print("no failure")
        return 0
    print("failures by class:")
    for problem, count in classes.most_common():
        entry, seed_name, data = smallest[problem]
        print(f"  {count:>6}  {problem}  (smallest: {len(data)} bytes, from {seed_name})")
    return 1


if __name__ == "__main__":
    sys.exit(main())
