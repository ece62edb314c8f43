"""Mutation testing of scriptc's own modules: how many small, plausible bugs the suite catches.

    .venv/bin/python bench/mutate.py src/scriptc/check/flow.py [MODULE ...] [--jobs 2]
        [--max N] [--only LINE[,LINE...]] [--show-survivors] [--json FILE]

For each module it makes mutants, one change each, by rewriting the module's syntax tree:
comparisons flipped (`<` to `<=`, `==` to `!=`, `in` to `not in`, ...), `and` and `or`
swapped, `not` dropped, arithmetic operators swapped (`+` to `-`, ...), constants moved (a
number `n` to `n + 1`, `True` to `False`, a non-empty string to another), and statements
dropped (a statement replaced by `pass`; a `return x` by `return None`). Each mutant is run
against the tests that cover the mutated line (coverage.py with one context per test, measured
once per run over the whole suite), in a fresh interpreter whose `scriptc` is a copy of the
source tree with that one change; it is *killed* when a test fails (or the tests time out:
five times their normal duration), *survives* when they all pass, and counts as surviving when
no test covers its line. The score of a module is killed / mutants.

Tests that reach a module only through a subprocess (`scriptc ...` run as a program) are not
seen by the coverage contexts: such mutants are tried against no test and survive. The
modules this is meant for are tested in-process.

It prints a line per module (mutants, killed, score), and with `--show-survivors` each
surviving mutant as `file:line: what changed`, the place to write a test.
"""

from __future__ import annotations

import argparse
import ast
import copy
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"

_COMPARE_SWAP = {
    ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt,
    ast.Eq: ast.NotEq, ast.NotEq: ast.Eq, ast.In: ast.NotIn, ast.NotIn: ast.In,
    ast.Is: ast.IsNot, ast.IsNot: ast.Is,
}
_BINOP_SWAP = {
    ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.FloorDiv, ast.Div: ast.Mult,
    ast.FloorDiv: ast.Mult, ast.Mod: ast.FloorDiv, ast.BitAnd: ast.BitOr, ast.BitOr: ast.BitAnd,
    ast.LShift: ast.RShift, ast.RShift: ast.LShift,
}


@dataclass(frozen=True)
class Mutant:
    path: Path          # the module's file
    index: int          # which mutation site of the file, in walk order
    line: int           # the first line of the mutated node
    end_line: int
    what: str           # a short description ("`<` to `<=`")
    source: str         # the whole mutated module


def _docstring_nodes(tree: ast.AST) -> set[int]:
    """The ids of docstring expression statements: mutating them is never interesting."""
    found: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                found.add(id(body[0]))
                found.add(id(body[0].value))
    return found


def _skippable(node: ast.AST) -> bool:
    """Statements whose removal says nothing: imports, `pass`, `...`, declarations of types,
    the `__future__` import, `raise` of a not-implemented."""
    if isinstance(node, (ast.Import, ast.ImportFrom, ast.Pass, ast.Global, ast.Nonlocal)):
        return True
    if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
        return True
    if isinstance(node, ast.AnnAssign) and node.value is None:
        return True
    return False


def _sites(tree: ast.AST) -> list[tuple[ast.AST, str, object]]:
    """Every (node, kind, detail) that can be mutated, in a fixed order."""
    docs = _docstring_nodes(tree)
    sites: list[tuple[ast.AST, str, object]] = []
    in_annotation: set[int] = set()
    for node in ast.walk(tree):
        for field in ("annotation", "returns"):
            ann = getattr(node, field, None)
            if ann is not None:
                in_annotation.update(id(n) for n in ast.walk(ann))
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for dec in node.decorator_list:
                in_annotation.update(id(n) for n in ast.walk(dec))
    for node in ast.walk(tree):
        if id(node) in docs or id(node) in in_annotation:
            continue
        if isinstance(node, ast.Compare):
            for k, op in enumerate(node.ops):
                if type(op) in _COMPARE_SWAP:
                    sites.append((node, "compare", k))
        elif isinstance(node, ast.BoolOp):
            sites.append((node, "boolop", None))
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            sites.append((node, "not", None))
        elif isinstance(node, ast.BinOp) and type(node.op) in _BINOP_SWAP:
            sites.append((node, "binop", None))
        elif isinstance(node, ast.Constant) and not isinstance(node.value, bytes):
            if isinstance(node.value, bool) or isinstance(node.value, (int, float)) \
                    or (isinstance(node.value, str) and node.value):
                sites.append((node, "constant", None))
        if isinstance(node, ast.stmt) and not _skippable(node) \
                and not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            if isinstance(node, ast.Return) and node.value is not None:
                sites.append((node, "return", None))
            elif not isinstance(node, ast.Return):
                sites.append((node, "drop", None))
    return sites


def _mutate(node: ast.AST, kind: str, detail: object) -> tuple[ast.AST, str]:
    """A mutated copy of `node` and a description of the change."""
    new = copy.deepcopy(node)
    if kind == "compare":
        op = new.ops[detail]
        swapped = _COMPARE_SWAP[type(op)]()
        new.ops[detail] = swapped
        return new, f"`{_op_text(op)}` to `{_op_text(swapped)}`"
    if kind == "boolop":
        new.op = ast.Or() if isinstance(new.op, ast.And) else ast.And()
        return new, f"`{'and' if isinstance(node.op, ast.And) else 'or'}` to " \
                    f"`{'or' if isinstance(node.op, ast.And) else 'and'}`"
    if kind == "not":
        return new.operand, "`not` dropped"
    if kind == "binop":
        swapped = _BINOP_SWAP[type(new.op)]()
        text = f"`{_op_text(new.op)}` to `{_op_text(swapped)}`"
        new.op = swapped
        return new, text
    if kind == "constant":
        value = node.value
        if isinstance(value, bool):
            new.value = not value
        elif isinstance(value, (int, float)):
            new.value = value + 1
        else:
            new.value = "\x00mutated\x00"
        return new, f"{value!r} to {new.value!r}"
    if kind == "return":
        new.value = ast.Constant(None)
        return new, "`return ...` to `return None`"
    if kind == "drop":
        return ast.Pass(), "statement dropped"
    raise ValueError(kind)


def _op_text(op: ast.AST) -> str:
    return {
        ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!=",
        ast.In: "in", ast.NotIn: "not in", ast.Is: "is", ast.IsNot: "is not", ast.Add: "+",
        ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//", ast.Mod: "%",
        ast.BitAnd: "&", ast.BitOr: "|", ast.LShift: "<<", ast.RShift: ">>",
    }[type(op)]


class _Replace(ast.NodeTransformer):
    def __init__(self, target: ast.AST, replacement: ast.AST) -> None:
        self.target = target
        self.replacement = replacement

    def generic_visit(self, node: ast.AST) -> ast.AST:
        if node is self.target:
            return self.replacement
        return super().generic_visit(node)


def mutants(path: Path) -> list[Mutant]:
    """Every mutant of one module. Each is the whole module printed again by `ast.unparse`
    (comments are lost; the meaning is the original's but for the one change)."""
    text = path.read_text(encoding="utf-8")
    found = []
    sites = _sites(ast.parse(text))
    for index, (_node, kind, detail) in enumerate(sites):
        tree = ast.parse(text)  # a fresh tree: the sites of it are found in the same order
        node, kind2, detail2 = _sites(tree)[index]
        assert (kind2, detail2) == (kind, detail)
        replacement, what = _mutate(node, kind, detail)
        mutated = _Replace(node, replacement).visit(tree)
        ast.fix_missing_locations(mutated)
        try:
            source = ast.unparse(mutated)
            compile(source, str(path), "exec")
        except (SyntaxError, ValueError):
            continue
        found.append(Mutant(path, index, node.lineno, getattr(node, "end_lineno", node.lineno)
                            or node.lineno, what, source))
    return found


# ---------------------------------------------------------------------------------------------
# Which tests cover which lines

def coverage_map(modules: list[Path], jobs_dir: Path) -> tuple[dict[Path, dict[int, set[str]]],
                                                               dict[str, float]]:
    """For each module, line -> the node ids of the tests that ran it; and the duration of
    each test. One run of the whole suite under coverage.py with per-test contexts."""
    rc = jobs_dir / "coveragerc"
    data = jobs_dir / "coverage.data"
    include = ",".join(str(m) for m in modules)
    rc.write_text("[run]\nbranch = false\ndynamic_context = test_function\n"
                  f"data_file = {data}\ninclude = {include}\n", encoding="utf-8")
    report = jobs_dir / "durations.json"
    plugin = jobs_dir / "mutate_durations.py"
    plugin.write_text(
        "import json, time\n"
        "_d = {}\n"
        "def pytest_runtest_logreport(report):\n"
        "    if report.when == 'call':\n"
        "        _d[report.nodeid] = _d.get(report.nodeid, 0) + report.duration\n"
        "def pytest_sessionfinish(session):\n"
        f"    open({str(report)!r}, 'w').write(json.dumps(_d))\n", encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(jobs_dir))
    subprocess.run([sys.executable, "-m", "coverage", "run", f"--rcfile={rc}", "-m", "pytest",
                    "-q", "-p", "no:cacheprovider", "-p", "mutate_durations",
                    "--no-header", "-o", "addopts="], cwd=ROOT, env=env, check=False,
                   stdout=subprocess.DEVNULL)
    out = jobs_dir / "coverage.json"
    subprocess.run([sys.executable, "-m", "coverage", "json", f"--rcfile={rc}", "--show-contexts",
                    "-o", str(out)], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
    files = json.loads(out.read_text())["files"]
    lines: dict[Path, dict[int, set[str]]] = {}
    for name, entry in files.items():
        path = (ROOT / name).resolve()
        per_line: dict[int, set[str]] = {}
        at_import: list[int] = []
        for line, contexts in entry.get("contexts", {}).items():
            tests = {_node_id(c) for c in contexts if c}
            if tests:
                per_line[int(line)] = tests
            elif "" in contexts:
                at_import.append(int(line))
        # Lines run when the module is imported (constants, tables) belong to no test: every
        # test that runs the module's code depends on them.
        users = set().union(*per_line.values()) if per_line else set()
        for line in at_import:
            per_line[line] = users
        lines[path] = per_line
    durations = json.loads(report.read_text()) if report.exists() else {}
    return lines, durations


def _node_id(context: str) -> str:
    """coverage's test_function context (`tests.test_x.test_y|run`, or with a class,
    `tests.test_x.TestZ.test_y|run`) as a pytest node id."""
    name = context.split("|", 1)[0]
    parts = name.split(".")
    # The module is the longest prefix that is a file under the repository.
    for cut in range(len(parts) - 1, 0, -1):
        candidate = ROOT.joinpath(*parts[:cut]).with_suffix(".py")
        if candidate.exists():
            return "::".join([candidate.relative_to(ROOT).as_posix(), *parts[cut:]])
    return name


# ---------------------------------------------------------------------------------------------
# Running one mutant

def _tree_copy(base: Path) -> Path:
    """A copy of src/scriptc with the grammar and schemas beside it, as in the checkout."""
    shutil.copytree(SRC / "scriptc", base / "src" / "scriptc",
                    ignore=shutil.ignore_patterns("__pycache__"))
    for data in ("grammar", "schemas"):
        os.symlink(ROOT / data, base / data)
    return base / "src"


def run_mutant(mutant: Mutant, tests: list[str], timeout: float, work: Path) -> str:
    """'killed', 'survived' or 'timeout' (a kill) for one mutant, in the copy `work`."""
    if not tests:
        return "uncovered"
    target = work / mutant.path.relative_to(SRC)
    original = target.read_text(encoding="utf-8")
    target.write_text(mutant.source, encoding="utf-8")
    try:
        env = dict(os.environ, PYTHONPATH=str(work), PYTHONDONTWRITEBYTECODE="1")
        # pytest's node ids of parametrized tests carry their parameters; coverage's contexts
        # do not, so a test function is named by its file and name (every parameter runs).
        try:
            result = subprocess.run(
                [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
                 "--no-header", "-o", "addopts=", *sorted(tests)],
                cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                timeout=timeout)
        except subprocess.TimeoutExpired:
            return "timeout"
        return "survived" if result.returncode == 0 else "killed"
    finally:
        target.write_text(original, encoding="utf-8")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="+", type=Path)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--max", type=int, default=0, help="at most this many mutants a module")
    parser.add_argument("--only", default="", help="only mutants on these lines (comma-separated)")
    parser.add_argument("--show-survivors", action="store_true")
    parser.add_argument("--json", type=Path, help="write every mutant's result here")
    parser.add_argument("--map", type=Path,
                        help="keep the coverage map in this file and reuse it when it exists "
                             "(delete it when tests were added: new tests are not in it)")
    args = parser.parse_args()
    modules = [m.resolve() for m in args.modules]
    only = {int(x) for x in args.only.split(",") if x}

    with tempfile.TemporaryDirectory(prefix="scriptc-mutate-") as tmp:
        tmp_path = Path(tmp)
        started = time.perf_counter()
        saved = None
        if args.map is not None and args.map.exists():
            saved = json.loads(args.map.read_text(encoding="utf-8"))
            if not all(str(m) in saved["lines"] for m in modules):
                saved = None  # made for other modules
        if saved is not None:
            lines = {Path(p): {int(k): set(v) for k, v in per.items()}
                     for p, per in saved["lines"].items()}
            durations = saved["durations"]
        else:
            lines, durations = coverage_map(modules, tmp_path)
            if args.map is not None:
                args.map.write_text(json.dumps({
                    "lines": {str(p): {k: sorted(v) for k, v in per.items()}
                              for p, per in lines.items()},
                    "durations": durations}), encoding="utf-8")
        print(f"coverage of the suite: {time.perf_counter() - started:.0f} s", flush=True)
        works = [_tree_copy(tmp_path / f"w{i}") for i in range(args.jobs)]
        free = list(works)
        results: list[dict] = []
        for module in modules:
            found = mutants(module)
            if only:
                found = [m for m in found if m.line in only]
            if args.max:
                found = found[:args.max]
            covered = lines.get(module, {})

            def tests_of(m: Mutant) -> list[str]:
                hit: set[str] = set()
                for line in range(m.line, m.end_line + 1):
                    hit |= covered.get(line, set())
                # Test functions, not their parameters (see run_mutant).
                return sorted({t.split("[", 1)[0] for t in hit})

            def one(m: Mutant) -> tuple[Mutant, str]:
                work = free.pop()
                try:
                    tests = tests_of(m)
                    budget = sum(durations.get(t, 0.5) for t in tests)
                    return m, run_mutant(m, tests, max(20.0, 5 * budget + 10), work)
                finally:
                    free.append(work)

            started = time.perf_counter()
            with ThreadPoolExecutor(max_workers=args.jobs) as pool:
                outcomes = list(pool.map(one, found))
            killed = sum(1 for _m, r in outcomes if r in ("killed", "timeout"))
            total = len(outcomes)
            rel = module.relative_to(ROOT)
            score = 100.0 * killed / total if total else 100.0
            print(f"{rel}: {total} mutants, {killed} killed, {score:.1f}% "
                  f"({time.perf_counter() - started:.0f} s)", flush=True)
            for m, r in outcomes:
                results.append({"file": str(rel), "line": m.line, "what": m.what, "result": r})
                if args.show_survivors and r in ("survived", "uncovered"):
                    print(f"  {rel}:{m.line}: {m.what} ({r})")
        if args.json:
            args.json.write_text(json.dumps(results, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
