"""Cold start of `scriptc lint`: the wall time of a fresh process linting one small script.

Budget: 60 ms on the reference machine, where a bare `python -c pass` takes about 11 ms (the
CLI's lazy imports exist for it: docs/performance.md).
Each run is a new interpreter, so every import is paid again; the operating system's file
cache is warm after the first run, as it is for a user who lints repeatedly. The headline
figure has Python's bytecode cache (as an installed wheel has: pip compiles it), kept in a
temporary PYTHONPYCACHEPREFIX so the source tree is left alone; the second figure is without
it (PYTHONDONTWRITEBYTECODE=1, as in some development shells: every module is compiled
again in every process). CPU time (user + system of the child) is printed beside the wall
time because it moves less when the machine is busy.

    .venv/bin/python bench/bench_lint_startup.py [SCRIPT] [--runs N] [--importtime]
        [--instructions]

SCRIPT defaults to the first file of examples/*.script (the thesis example when there is
none). `--importtime` also prints the ten slowest imports of one run (python -X importtime).
`--instructions` also counts the instructions of one cold run with valgrind (cachegrind), the
figure that does not move with the machine's load or speed, beside those of a bare
interpreter (`python -c pass`) and of `import click` alone, the floor of any click CLI.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BUDGET_MS = 60.0
THESIS_EXAMPLE = (
    "[example_act]\n"
    '[alfa:16,my_rule,"\\\\myinputtopic","\\\\myoutputtopic",A,M]\n'
    '[alfa:0,kick_starter,"","",R,U]\n'
    '[omega:0,kick_starter,"","",C,L]\n'
    "[goal:blinking_and_stop]\n"
    "[action]\n"
    '[b##blk_inst: MV() LD("0, 0, 1, 1, 0, 100", "0, 0, 1, 1, 0, 100") AO()]\n'
)


def command(script: Path) -> list[str]:
    """The installed `scriptc` next to this interpreter, else `python -m scriptc`."""
    installed = Path(sys.executable).with_name("scriptc")
    base = [str(installed)] if installed.exists() else [sys.executable, "-m", "scriptc"]
    return [*base, "lint", str(script)]


def measure(script: Path, runs: int, env: dict[str, str]) -> tuple[list[float], list[float]]:
    """Wall and CPU milliseconds of `runs` cold processes."""
    argv = command(script)
    walls, cpus = [], []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        # Status 1 is lint's answer about the script (errors): checked below.
        done = subprocess.run(argv, capture_output=True, env=env, check=False)
        walls.append((time.perf_counter() - start) * 1000)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append((after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime) * 1000)
        if done.returncode not in (0, 1):
            sys.exit(f"scriptc failed ({done.returncode}): {done.stderr.decode()}")
    return walls, cpus


def report(label: str, walls: list[float], cpus: list[float]) -> float:
    median = statistics.median(walls)
    print(f"  {label}: median {median:.1f} ms wall (min {min(walls):.1f}, max {max(walls):.1f}), "
          f"{statistics.median(cpus):.1f} ms CPU")
    return median


def slowest_imports(script: Path, env: dict[str, str], count: int = 10) -> list[tuple[int, str]]:
    argv = [sys.executable, "-X", "importtime", "-m", "scriptc", "lint", str(script)]
    # Only the import times on stderr are read: lint's status says nothing about them.
    err = subprocess.run(argv, capture_output=True, text=True, env=env, check=False).stderr
    rows = []
    for line in err.splitlines():
        if line.startswith("import time:") and "|" in line and "cumulative" not in line:
            _self, cumulative, name = line[len("import time:"):].split("|")
            if not name.startswith("   "):  # top-level imports only: cumulative counts once
                rows.append((int(cumulative), name.strip()))
    return sorted(rows, reverse=True)[:count]


def instructions(argv: list[str], env: dict[str, str]) -> int | None:
    """Instructions executed by `argv`, counted by valgrind's cachegrind (None without it)."""
    if shutil.which("valgrind") is None:
        return None
    done = subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=no",
                           "--cachegrind-out-file=/dev/null", *argv],
                          capture_output=True, text=True, env=env, check=False)
    found = re.search(r"I\s+refs:\s+([\d,]+)", done.stderr)
    return int(found.group(1).replace(",", "")) if found else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("script", nargs="?", type=Path)
    parser.add_argument("--runs", type=int, default=21)
    parser.add_argument("--importtime", action="store_true")
    parser.add_argument("--instructions", action="store_true")
    args = parser.parse_args()

    script = args.script
    with tempfile.TemporaryDirectory() as tmp:
        if script is None:
            examples = sorted((ROOT / "examples").glob("*.script"))
            if examples:
                script = examples[0]
            else:
                script = Path(tmp) / "thesis_example.script"
                script.write_text(THESIS_EXAMPLE, encoding="utf-8")
        base = {k: v for k, v in os.environ.items()
                if k not in ("FORCE_COLOR", "PYTHONPROFILEIMPORTTIME", "PYTHONDONTWRITEBYTECODE")}
        cached = {**base, "PYTHONPYCACHEPREFIX": str(Path(tmp) / "pycache")}
        uncached = {**base, "PYTHONDONTWRITEBYTECODE": "1"}
        measure(script, 2, cached)  # warm the file cache and write the bytecode cache
        print(f"cold `scriptc lint {script.name}`, {args.runs} runs each:")
        median = report("with bytecode cache", *measure(script, args.runs, cached))
        report("without bytecode cache", *measure(script, args.runs, uncached))
        verdict = "within" if median <= BUDGET_MS else "OVER"
        print(f"{verdict} the {BUDGET_MS:.0f} ms budget (with bytecode cache)")
        if args.importtime:
            print("slowest top-level imports of one run (cumulative ms, bytecode cached):")
            for micros, name in slowest_imports(script, cached):
                print(f"  {micros / 1000:7.1f}  {name}")
        if args.instructions:
            print("instructions of one cold run (valgrind), bytecode cached:")
            for label, argv in (("python -c pass", [sys.executable, "-c", "pass"]),
                                ("python -c 'import click'", [sys.executable, "-c",
                                                               "import click"]),
                                (f"scriptc lint {script.name}",
                                 [sys.executable, "-m", "scriptc", "lint", str(script)])):
                count = instructions(argv, cached)
                shown = "valgrind is not installed" if count is None else f"{count / 1e6:,.0f}M"
                print(f"  {label:32} {shown}")


if __name__ == "__main__":
    main()
