"""Repository lint: `scriptc lint DIR` over a generated repository, cold and from the cache.

The repository holds N scripts (default 1,000) of 100 to 200 blocks each (`generate.py`'s
`big_script(n)`, n varying with the file), about 23 KB each; with `--varied`, scripts in many
shapes (`varied_script`), about 20 KB each. Each figure is the wall time of a
fresh `scriptc lint DIR` process (interpreter start included), with Python's bytecode cache
warm (a temporary PYTHONPYCACHEPREFIX, as an installed wheel has):

- cold: an empty `.scriptc_cache`, so every file is analysed (in `--jobs` workers);
- cached: the same command again, nothing changed: every result comes from the cache;
- one changed: one file edited, the rest from the cache.

The results cache is keyed by scriptc's own code too (modification times of its modules): run
the benchmark on a tree nobody is editing, or the cached runs analyse everything again.

Targets: >= 100 files/s cold on 2 cores, >= 1,000 files/s cached. Then, for the cold run,
where the time goes: one process analysing a sample of the files, split into the front end
(scan, parse, lower), the checks and the rest, to compare with the front end's speed.

    .venv/bin/python bench/bench_lint_repo.py [--files N] [--jobs J] [--runs R] [--varied]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from generate import big_script, varied_script  # noqa: E402 - after the path to bench/ is set


def make_repository(root: Path, files: int, varied: bool = False) -> int:
    """Write the scripts (in folders of 100) and return their total size in bytes."""
    total = 0
    for i in range(files):
        blocks = 100 + (i * 37) % 101  # 100..200, spread over the files
        # Each file its own activity name: no two files are the same (identical files are
        # analysed once, which would flatter the cold figure).
        if varied:
            text = varied_script(blocks, i)
        else:
            text = big_script(blocks - blocks % 2).replace("[big_activity]", f"[activity{i:04d}]",
                                                           1)
        path = root / f"pack{i // 100:02d}" / f"activity{i:04d}.script"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        total += len(text.encode("utf-8"))
    return total


def lint(root: Path, jobs: int, env: dict[str, str]) -> tuple[float, float, str]:
    """Wall and CPU seconds (the process and its workers) of one `scriptc lint DIR`."""
    argv = [sys.executable, "-m", "scriptc", "lint", str(root), "--jobs", str(jobs)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    # Not check=True: a failure is reported below with lint's own output.
    done = subprocess.run(argv, capture_output=True, text=True, env=env, cwd=root, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    if done.returncode != 0:
        sys.exit(f"scriptc lint failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return wall, cpu, done.stderr.strip()


def show(label: str, files: int, size: int, wall: float, cpu: float, jobs: int,
         target: str = "") -> None:
    # On a busy machine the wall time says more about the neighbours than about scriptc; the
    # CPU time spread over the jobs is what an idle machine would take at least.
    idle = max(cpu / jobs, 1e-9)
    print(f"{label:<12} {wall:6.2f} s wall {files / wall:7.0f} files/s "
          f"{size / wall / 1e6:5.2f} MB/s | {cpu:6.2f} s CPU, on {jobs} idle cores "
          f"~{files / idle:5.0f} files/s  {target}")


def where_the_time_goes(root: Path, sample: int) -> None:
    """One process, a sample of the files: front end, checks, the rest (reading, hashing,
    suppressions, the policy), per file."""
    from scriptc.analysis.read import decode_source
    from scriptc.check import check_script
    from scriptc.frontend.script import lower_script
    from scriptc.gcpause import gc_paused

    paths = sorted(root.rglob("*.script"))[:sample]
    front = checks = 0.0
    size = 0
    lower_script(decode_source("warm", paths[0].read_bytes())[0])  # build the parser first
    start = time.perf_counter()
    for path in paths:
        data = path.read_bytes()
        size += len(data)
        source, _ = decode_source(str(path), data)
        with gc_paused():
            t0 = time.perf_counter()
            script, _diagnostics = lower_script(source)
            t1 = time.perf_counter()
            check_script(script, source)
            t2 = time.perf_counter()
        front += t1 - t0
        checks += t2 - t1
    total = time.perf_counter() - start
    n = len(paths)
    print(f"where the time goes (one process, {n} files, {size / n / 1000:.1f} KB each):")
    print(f"  front end (scan, parse, lower): {front / n * 1000:6.1f} ms/file "
          f"({size / front / 1e6:.2f} MB/s), {front / total:.0%}")
    print(f"  checks:                         {checks / n * 1000:6.1f} ms/file, "
          f"{checks / total:.0%}")
    print(f"  the rest:                       {(total - front - checks) / n * 1000:6.1f} "
          f"ms/file, {(total - front - checks) / total:.0%}")
    per_core = n / total
    print(f"  one core: {per_core:.1f} files/s, so {2 * per_core:.0f} files/s at best on 2")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--files", type=int, default=1000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--runs", type=int, default=3, help="runs of the cached figure")
    parser.add_argument("--sample", type=int, default=40, help="files profiled in-process")
    parser.add_argument("--varied", action="store_true",
                        help="scripts in many shapes (generate.varied_script: 0-3 commands per "
                             "track, six kinds of condition, comments) instead of two")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "repo"
        root.mkdir()
        size = make_repository(root, args.files, args.varied)
        # The generated moves go up to 0.9 m/s: the repository's robot profile allows them,
        # so that the figures are those of a clean repository (rendering thousands of
        # warnings is another benchmark).
        (root / "scriptc.toml").write_text(
            "[robot]\nmax-linear-speed = 1.0\nmax-angular-speed = 2.0\n\n"
            '[lint]\nignore = ["K001"]\n', encoding="utf-8")
        env = {k: v for k, v in os.environ.items()
               if k not in ("PYTHONDONTWRITEBYTECODE", "SCRIPTC_CACHE_DIR", "FORCE_COLOR")}
        env["PYTHONPYCACHEPREFIX"] = str(Path(tmp) / "pycache")
        subprocess.run([sys.executable, "-m", "scriptc", "--version"], env=env,
                       capture_output=True, check=True)  # write the bytecode cache
        print(f"repository: {args.files} scripts, {size / 1e6:.1f} MB "
              f"({size / args.files / 1000:.1f} KB each), {args.jobs} jobs, "
              f"{os.cpu_count()} cores")

        wall, cpu, summary = lint(root, args.jobs, env)
        show("cold:", args.files, size, wall, cpu, args.jobs, "(target >= 100 files/s)")
        print(f"             {summary}")
        cached = [lint(root, args.jobs, env) for _ in range(args.runs)]
        wall = statistics.median(w for w, _, _ in cached)
        cpu = statistics.median(c for _, c, _ in cached)
        show("cached:", args.files, size, wall, cpu, 1, "(target >= 1000 files/s)")
        print(f"             {cached[-1][2]}")
        one = sorted(root.rglob("*.script"))[0]
        one.write_text(one.read_text(encoding="utf-8") + "% edited %\n", encoding="utf-8")
        wall, cpu, summary = lint(root, args.jobs, env)
        show("one changed:", args.files, size, wall, cpu, 1)
        print(f"             {summary}")
        where_the_time_goes(root, args.sample)


if __name__ == "__main__":
    main()
