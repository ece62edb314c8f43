"""Mutation testing of scriptc's own modules: how many small, plausible bugs the suite catches.

    .venv/bin/python bench/mutate.py src/scriptc/check/flow.py [MODULE ...] [--jobs 2]
        [--max N] [--only LINE[,LINE...]] [--show-survivors] [--json FILE]
        [--map FILE [--refresh TESTS ...]]

For each module it makes mutants, one change each, by rewriting the module's syntax tree:
comparisons flipped (`<` to `<=`, `==` to `!=`, `in` to `not in`, ...), `and` and `or`
swapped, `not` dropped, arithmetic operators swapped (`+` to `-`, ...), constants moved (a
number `n` to `n + 1`, `True` to `False`, a non-empty string to another; one given as a
keyword argument is named with its keyword, `slots=True` to `slots=False`), and statements
dropped (a statement replaced by `pass`; a `return x` by `return None`). Each mutant is run
against the tests that cover the mutated line (coverage.py with one context per test item,
parameters included, measured once per run over the whole suite), fastest first, in a fresh
interpreter whose `scriptc` is a copy of the source tree with that one change; it is *killed*
when a test fails (or the tests time out: five times their normal duration), *survives* when
they all pass, and counts as surviving when no test covers its line. The score of a module is
killed / mutants. The tests run in two pytest processes at most (collecting a test file costs
about as much as running its tests): first those of the test files that killed most of the
module's mutants so far, then, when they all pass, the others.

The run works in a snapshot of the repository taken when it starts (tests, sources and data),
so what others edit meanwhile does not change its figures (`--rev HEAD` takes a commit, with
`--overlay PATH` for one's own files on top). Only tests that pass on the
snapshot unmutated are used (one baseline run of them first): a test that fails already
would "kill" every mutant. `--map FILE` keeps the coverage map (two to four minutes of the
suite) between runs; a module edited since moves its lines with the text, and `--refresh
tests/test_x.py` measures the tests written since and adds them.

Both the coverage run and the mutants' runs use one hypothesis profile: derandomized (the same
examples each time, so a run can be repeated), no deadline (a loaded machine must not kill a
mutant) and no example database (a mutant's failing example must not be replayed later by the
real suite).

Some mutants cannot be told from the original by any test: the change does not alter what
the module does (a `<` that cannot meet equality, a default that the caller always passes).
bench/mutate_equivalent.toml lists them, each with the reason; they are left out of the score
and counted apart ("equivalent"). An entry names the module, the mutated line's text and the
change, so it follows the line when code moves above it, and lapses (with a warning) when the
line itself changes; where the module has that text on several lines and not every one's
mutant is equivalent, the entry also names the function holding the line (`function =
"Class.method"`).

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
import difflib
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EQUIVALENT = Path(__file__).resolve().parent / "mutate_equivalent.toml"

# pytest plugins, written beside the snapshot. `mutate_profile` is loaded by every run (see
# the docstring); `mutate_contexts` by the coverage run: one coverage context per test item
# (its node id, parameters included: a case file's mutant then runs the cases that reach its
# line, not the whole harness), set around setup, call and teardown, and each item's
# duration; `mutate_outcomes` by the baseline run: the items that passed.
_PLUGINS = {
    "mutate_profile": """\
from hypothesis import settings
settings.register_profile("mutate", derandomize=True, deadline=None, database=None)
settings.load_profile("mutate")
""",
    "mutate_contexts": """\
import json, os
import coverage, pytest
_durations = {}
@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    cov = coverage.Coverage.current()
    cov.switch_context(item.nodeid)
    yield
    cov.switch_context("")
def pytest_runtest_logreport(report):
    _durations[report.nodeid] = _durations.get(report.nodeid, 0) + report.duration
def pytest_sessionfinish(session):
    with open(os.environ["MUTATE_REPORT"], "w") as f:
        json.dump(_durations, f)
""",
    "mutate_outcomes": """\
import json, os
_failed, _seen = set(), set()
def pytest_runtest_logreport(report):
    _seen.add(report.nodeid)
    if not report.passed and not (report.when == "call" and report.skipped):
        _failed.add(report.nodeid)
def pytest_sessionfinish(session):
    with open(os.environ["MUTATE_REPORT"], "w") as f:
        json.dump(sorted(_seen - _failed), f)
""",
}

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
    path: str           # the module's file, from the repository's root
    index: int          # which mutation site of the file, in walk order
    line: int           # the first line of the mutated node
    end_line: int
    what: str           # a short description ("`<` to `<=`")
    source: str         # the whole mutated module
    statement: int = 0  # the first line of the innermost statement holding the node
    function: str = ""  # the innermost function holding it ("Class.method"; "" for none)


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
    """Statements whose removal says nothing: imports, `pass`, `...`, declarations of types
    (annotations without a value, `if TYPE_CHECKING:` blocks), the `__future__` import."""
    if isinstance(node, (ast.Import, ast.ImportFrom, ast.Pass, ast.Global, ast.Nonlocal)):
        return True
    if isinstance(node, ast.If) and ast.unparse(node.test) in ("TYPE_CHECKING",
                                                                "typing.TYPE_CHECKING"):
        return True
    if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
        return True
    return isinstance(node, ast.AnnAssign) and node.value is None


def _sites(tree: ast.AST) -> list[tuple[ast.AST, str, object]]:
    """Every (node, kind, detail) that can be mutated, in a fixed order."""
    docs = _docstring_nodes(tree)
    sites: list[tuple[ast.AST, str, object]] = []
    in_annotation: set[int] = set()
    # A constant given as a keyword argument is named by its keyword (`slots=True` to
    # `slots=False`): two such constants of one line would otherwise have one description,
    # and an entry of mutate_equivalent.toml could not tell them apart.
    keywords = {id(node.value): node.arg for node in ast.walk(tree)
                if isinstance(node, ast.keyword) and node.arg is not None}
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
        elif (isinstance(node, ast.Constant) and not isinstance(node.value, bytes)
              and (isinstance(node.value, (bool, int, float))
                   or (isinstance(node.value, str) and node.value))):
            sites.append((node, "constant", keywords.get(id(node))))
        if isinstance(node, ast.stmt) and not _skippable(node) \
                and not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            if isinstance(node, ast.Return) and node.value is not None:
                if not (isinstance(node.value, ast.Constant) and node.value.value is None):
                    sites.append((node, "return", None))  # (`return None` stays itself)
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
        return new, (f"`{'and' if isinstance(node.op, ast.And) else 'or'}` to "
                     f"`{'or' if isinstance(node.op, ast.And) else 'and'}`")
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
        if detail is not None:
            return new, f"`{detail}={value!r}` to `{detail}={new.value!r}`"
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


def mutants(text: str, path: str) -> list[Mutant]:
    """Every mutant of one module (its text, its path). Each is the whole module printed again
    by `ast.unparse` (comments are lost; the meaning is the original's but for the one
    change)."""
    found = []
    original = ast.parse(text)
    sites = _sites(original)
    statements = _statement_lines(original)
    functions = _functions(original)
    for index, (site, kind, detail) in enumerate(sites):
        tree = ast.parse(text)  # a fresh tree: the sites of it are found in the same order
        node, kind2, detail2 = _sites(tree)[index]
        assert (kind2, detail2) == (kind, detail)
        replacement, what = _mutate(node, kind, detail)
        mutated = _Replace(node, replacement).visit(tree)
        ast.fix_missing_locations(mutated)
        try:
            source = ast.unparse(mutated)
            compile(source, path, "exec")
        except (SyntaxError, ValueError):
            continue
        found.append(Mutant(path, index, node.lineno, getattr(node, "end_lineno", node.lineno)
                            or node.lineno, what, source, statements.get(id(site), 0),
                            functions.get(id(site), "")))
    return found


def _functions(tree: ast.AST) -> dict[int, str]:
    """id(node) -> the qualified name of the innermost function holding it (`Class.method`,
    `function.inner`), "" outside every function."""
    found: dict[int, str] = {}
    todo: list[tuple[ast.AST, str, str]] = [(tree, "", "")]  # (node, function, scope)
    while todo:
        node, function, scope = todo.pop()
        found[id(node)] = function
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            scope = f"{scope}.{node.name}" if scope else node.name
            if not isinstance(node, ast.ClassDef):
                function = scope
        todo.extend((child, function, scope) for child in ast.iter_child_nodes(node))
    return found


def _statement_lines(tree: ast.AST) -> dict[int, int]:
    """id(node) -> the first line of the innermost statement holding it. coverage.py counts a
    statement written over several lines as run on its first line only, so the tests of a
    node on a later line of it are those of that line."""
    found: dict[int, int] = {}
    todo: list[tuple[ast.AST, int]] = [(tree, 0)]
    while todo:
        node, line = todo.pop()
        if isinstance(node, ast.stmt):
            line = node.lineno
        found[id(node)] = line
        todo.extend((child, line) for child in ast.iter_child_nodes(node))
    return found


# ---------------------------------------------------------------------------------------------
# The snapshot the run works in

def snapshot(dest: Path, rev: str | None = None, overlay: list[str] = ()) -> Path:
    """A copy of the repository at `dest`: the files git tracks or would track in the working
    tree, or the commit `rev`; then the working tree's files or folders `overlay` over it.

    Other people may be editing the checkout while a run takes its hour: the run reads its
    modules, makes its coverage map and runs every mutant in copies taken once at the start, so
    its figures describe one state of the code and of the tests. A commit is a state someone
    meant (a working tree shared with others may be half-way through their change); the
    overlay adds one's own work on top."""
    dest.mkdir(parents=True)
    if rev is not None:
        archive = subprocess.run(["git", "archive", "--format=tar", rev], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
        names = []
    else:
        names = subprocess.run(["git", "ls-files", "-z", "--cached", "--others",
                                "--exclude-standard"], cwd=ROOT, capture_output=True,
                               check=True).stdout.decode().split("\0")
    for item in overlay:
        path = (ROOT / item).resolve()
        if path.is_dir():
            names += [p.relative_to(ROOT).as_posix() for p in path.rglob("*")
                      if "__pycache__" not in p.parts]
        else:
            names.append(path.relative_to(ROOT).as_posix())
    for name in names:
        source = ROOT / name
        if name and source.is_file():
            target = dest / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)
    return dest


# A mutant can make a loop grow a list forever: its tests get this much memory (address
# space), so it dies of a MemoryError (a kill) before the machine runs short. The baseline
# runs under the same limit, so a test that needs more is left out, not counted as a kill.
MEMORY_LIMIT = 4 << 30


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def _absent_plugins(work: Path) -> list[str]:
    """`-p no:NAME` for each pytest plugin of the installed scriptc (an entry point of group
    `pytest11`) whose module the copy `work` does not have (a commit from before the plugin):
    pytest would fail to start, and every test with it."""
    from importlib.metadata import entry_points

    absent = []
    for point in entry_points(group="pytest11"):
        parts = point.value.split(":", 1)[0].split(".")
        if parts[0] != "scriptc":
            continue
        where = work / "src" / Path(*parts)
        if not where.with_suffix(".py").is_file() and not (where / "__init__.py").is_file():
            absent += ["-p", f"no:{point.name}"]
    return absent


def _pytest(work: Path, plugins: Path, args: list[str], report: Path | None = None,
            timeout: float | None = None, capture: bool = False,
            coverage_rc: Path | None = None) -> subprocess.CompletedProcess:
    """pytest in the copy `work` (its `src` first on the path), with the plugins."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(work / "src"), str(plugins)]),
               PYTHONDONTWRITEBYTECODE="1")
    if report is not None:
        env["MUTATE_REPORT"] = str(report)
    runner = [sys.executable, "-m", "pytest"] if coverage_rc is None else \
        [sys.executable, "-m", "coverage", "run", f"--rcfile={coverage_rc}", "-m", "pytest"]
    # Not check=True: pytest's status is the answer (tests failing kill the mutant).
    return subprocess.run([*runner, "-q", "-p", "no:cacheprovider", "-p", "mutate_profile",
                           *_absent_plugins(work), "--no-header", "-o", "addopts=", *args],
                          check=False,
                          cwd=work, env=env, timeout=timeout, preexec_fn=_limit_memory,
                          stdout=subprocess.PIPE if capture else subprocess.DEVNULL,
                          stderr=subprocess.STDOUT if capture else subprocess.DEVNULL)


# ---------------------------------------------------------------------------------------------
# Which tests cover which lines

Lines = dict[str, dict[int, set[str]]]  # module path -> line -> node ids


def coverage_map(work: Path, plugins: Path, modules: list[str], tests: list[str] = ()
                 ) -> tuple[Lines, dict[str, float]]:
    """For each module, line -> the node ids of the tests that ran it; and the duration of
    each test. One run of the suite (or of `tests`, pytest arguments) under coverage.py with
    per-test contexts."""
    scratch = plugins.parent
    rc = scratch / "coveragerc"
    data = scratch / "coverage.data"
    include = ",".join(str(work / m) for m in modules)
    rc.write_text("[run]\nbranch = false\n"
                  f"data_file = {data}\ninclude = {include}\n", encoding="utf-8")
    report = scratch / "durations.json"
    # A test file that cannot be collected (someone's work in progress) must not stop the
    # others: its tests are simply not in the map.
    run = _pytest(work, plugins, ["-p", "mutate_contexts", "--continue-on-collection-errors",
                                  *tests], report, capture=True, coverage_rc=rc)
    summary = run.stdout.decode(errors="replace").strip().splitlines()
    print(f"coverage run: {summary[-1] if summary else 'no output'}", flush=True)
    out = scratch / "coverage.json"
    subprocess.run([sys.executable, "-m", "coverage", "json", f"--rcfile={rc}", "--show-contexts",
                    "-o", str(out)], cwd=work, check=True, stdout=subprocess.DEVNULL)
    files = json.loads(out.read_text())["files"]
    lines: Lines = {m: {} for m in modules}
    for name, entry in files.items():
        module = (work / name).resolve().relative_to(work.resolve()).as_posix()
        per_line: dict[int, set[str]] = {}
        for line, contexts in entry.get("contexts", {}).items():
            per_line[int(line)] = {c for c in contexts if c}
        # Lines run when the module is imported (constants, tables, default arguments) belong
        # to whichever test imported it first, or to none: every test that runs the module's
        # code depends on them.
        users = set().union(*per_line.values()) if per_line else set()
        for line in import_lines((work / module).read_text(encoding="utf-8")):
            if line in per_line:
                per_line[line] = set(users)
        lines[module] = {k: v for k, v in per_line.items() if v}
    data.unlink(missing_ok=True)
    durations = json.loads(report.read_text()) if report.exists() else {}
    return lines, durations


def passing(work: Path, plugins: Path, tests: list[str]) -> set[str]:
    """Those of `tests` that pass on the unmutated copy: only they can tell a mutant (a test
    that fails already, or cannot be collected, would 'kill' every mutant)."""
    # One node id pytest cannot find (a test renamed or removed since the map was made) makes
    # it run none of them: only the ids the test files hold now are asked for.
    tests = sorted(set(tests) & collected(work, plugins, {t.split("::", 1)[0] for t in tests}))
    if not tests:
        return set()  # (pytest without node ids would run the whole suite)
    report = plugins.parent / "outcomes.json"
    report.unlink(missing_ok=True)
    _pytest(work, plugins, ["-p", "mutate_outcomes", "--continue-on-collection-errors",
                            *tests], report)
    return set(json.loads(report.read_text())) if report.exists() else set()


def collected(work: Path, plugins: Path, files: set[str]) -> set[str]:
    """The node ids pytest collects from `files` (test files of the copy `work`)."""
    files = {f for f in files if (work / f).is_file()}
    if not files:
        return set()
    run = _pytest(work, plugins, ["--collect-only", "--continue-on-collection-errors",
                                  *sorted(files)], capture=True)
    return {line for line in run.stdout.decode(errors="replace").splitlines()
            if "::" in line and line.split("::", 1)[0] in files}


def import_lines(text: str) -> set[int]:
    """The lines of a module that run when it is imported: module and class bodies, with the
    decorators and default arguments of their functions, not the functions' bodies."""
    found: set[int] = set()

    def span(node: ast.AST) -> None:
        found.update(range(node.lineno, (node.end_lineno or node.lineno) + 1))

    def body(stmts: list[ast.stmt]) -> None:
        for stmt in stmts:
            if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in [*stmt.decorator_list, *stmt.args.defaults,
                             *(d for d in stmt.args.kw_defaults if d is not None)]:
                    span(node)
            elif isinstance(stmt, ast.ClassDef):
                for node in [*stmt.decorator_list, *stmt.bases, *stmt.keywords]:
                    span(node)
                body(stmt.body)
            elif isinstance(stmt, (ast.If, ast.Try)):  # may hold functions
                for part in ("body", "orelse", "finalbody"):
                    body(getattr(stmt, part, []))
                for handler in getattr(stmt, "handlers", []):
                    body(handler.body)
                if isinstance(stmt, ast.If):
                    span(stmt.test)
            else:
                span(stmt)

    body(ast.parse(text).body)
    return found


def remap(per_line: dict[int, set[str]], old: str, new: str) -> dict[int, set[str]]:
    """A map made for the text `old` of a module, moved onto its text `new`: lines kept by the
    change keep their tests; the others (changed or added) get every test of the module."""
    if old == new:
        return per_line
    matcher = difflib.SequenceMatcher(None, old.splitlines(), new.splitlines(), autojunk=False)
    users = set().union(*per_line.values()) if per_line else set()
    moved: dict[int, set[str]] = {}
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            for k in range(i2 - i1):
                if i1 + k + 1 in per_line:
                    moved[j1 + k + 1] = per_line[i1 + k + 1]
        else:
            for line in range(j1 + 1, j2 + 1):
                moved[line] = set(users)
    return moved


def refreshed(test: str, arguments: list[str]) -> bool:
    """Whether the node id `test` is one of those the pytest `arguments` (folders, files, node
    ids with or without their parameters) select: its old entries give way to the new
    measure, and a test gone since is dropped."""
    for argument in arguments:
        chosen = argument.rstrip("/")
        if test == chosen or test.startswith((chosen + "::", chosen + "[", chosen + "/")):
            return True
    return False


def load_map(args, work: Path, plugins: Path, modules: list[str]
             ) -> tuple[Lines, dict[str, float]]:
    """The coverage map: made now, or read from --map (moved onto the modules' text now, and
    with the --refresh tests measured again), and written back to --map."""
    saved = None
    if args.map is not None and args.map.exists():
        saved = json.loads(args.map.read_text(encoding="utf-8"))
        if saved.get("version") != 2 or not all(m in saved["lines"] for m in modules):
            saved = None  # made for other modules, or by an older version of this tool
    texts = {}
    if saved is None:
        lines, durations = coverage_map(work, plugins, modules)
    else:
        # The modules may have changed since the map was made (by the fix a survivor asked
        # for): their lines move with the text.
        lines = {}
        for module, per in saved["lines"].items():
            if (work / module).exists():
                lines[module] = remap({int(k): set(v) for k, v in per.items()},
                                      saved["texts"].get(module, ""),
                                      (work / module).read_text(encoding="utf-8"))
        durations = saved["durations"]
        if args.refresh:
            fresh, fresh_durations = coverage_map(work, plugins, sorted(lines), args.refresh)
            for module, per in lines.items():
                for line in list(per):
                    per[line] = {t for t in per[line] if not refreshed(t, args.refresh)}
                for line, tests in fresh.get(module, {}).items():
                    per.setdefault(line, set()).update(tests)
            durations = {t: d for t, d in durations.items()
                         if not refreshed(t, args.refresh)} | fresh_durations
    for module in lines:
        texts[module] = (work / module).read_text(encoding="utf-8")
    if args.map is not None:
        args.map.write_text(json.dumps({
            "version": 2,
            "lines": {m: {k: sorted(v) for k, v in per.items()} for m, per in lines.items()},
            "texts": texts, "durations": durations}), encoding="utf-8")
    return lines, durations


# ---------------------------------------------------------------------------------------------
# Running one mutant

def run_mutant(mutant: Mutant, stages: list[list[str]], timeouts: list[float], work: Path,
               plugins: Path) -> tuple[str, str | None]:
    """'killed', 'survived' or 'timeout' (a kill) for one mutant, in the copy `work`, running
    the `stages` of tests (node ids that pass on the original) one after the other, each in
    the order given, and stopping at the first failure; 'uncovered' when no test runs its
    line. With it, the test file that failed first (None when none did, or it is not known).

    Stages only save time: a mutant is killed when any of its tests fails, whichever stage
    holds it. Collecting a test file costs a pytest process about as much as running its
    tests, so the files most likely to kill the mutant come first, alone."""
    stages = [s for s in stages if s]
    if not stages:
        return "uncovered", None
    target = work / mutant.path
    original = target.read_text(encoding="utf-8")
    target.write_text(mutant.source, encoding="utf-8")
    try:
        for tests, timeout in zip(stages, timeouts, strict=False):
            try:
                result = _pytest(work, plugins, ["-x", *tests], timeout=timeout, capture=True)
            except subprocess.TimeoutExpired:
                return "timeout", None
            # The same tests passed on the original copy (the baseline), so any failure is
            # the mutant's: a test failed (1), or collection broke (2; 4 when a test module's
            # parameters, computed as it is collected, run the mutated code).
            if result.returncode != 0:
                return "killed", _first_failure(result.stdout.decode(errors="replace"))
        return "survived", None
    finally:
        target.write_text(original, encoding="utf-8")


def _first_failure(output: str) -> str | None:
    """The test file of the first `FAILED` (or `ERROR`) line of pytest's short summary."""
    for line in output.splitlines():
        for mark in ("FAILED ", "ERROR "):
            if line.startswith(mark) and "::" in line:
                return line[len(mark):].split("::", 1)[0]
    return None


def stages_of(tests: list[str], kills: dict[str, int]) -> list[list[str]]:
    """`tests` in two stages: first those of the (at most two) test files that killed most
    mutants of the module so far (at the start: the file with most of these tests), then the
    others; each stage keeps the order of `tests`."""
    per_file: dict[str, int] = {}
    for t in tests:
        name = t.split("::", 1)[0]
        per_file[name] = per_file.get(name, 0) + 1
    ranked = sorted(per_file, key=lambda f: (-kills.get(f, 0), -per_file[f], f))
    first = set(ranked[:2]) if any(kills.get(f, 0) for f in ranked) else set(ranked[:1])
    return [[t for t in tests if t.split("::", 1)[0] in first],
            [t for t in tests if t.split("::", 1)[0] not in first]]


@dataclass(frozen=True)
class Equivalent:
    module: str         # the module's path from the repository's root
    line: str           # the mutated line's text, stripped
    change: str         # the mutant's description, as printed
    why: str
    function: str = ""  # the function holding the line, when the entry names one


def equivalents(path: Path = EQUIVALENT) -> list[Equivalent]:
    """The mutants listed as equivalent to the original (see the docstring)."""
    if not path.exists():
        return []
    entries = tomllib.loads(path.read_text(encoding="utf-8")).get("equivalent", [])
    return [Equivalent(e["module"], e["line"].strip(), e["change"], e["why"],
                       e.get("function", "")) for e in entries]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="+", type=Path)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--max", type=int, default=0, help="at most this many mutants a module")
    parser.add_argument("--only", default="", help="only mutants on these lines (comma-separated)")
    parser.add_argument("--show-survivors", action="store_true")
    parser.add_argument("--progress", action="store_true", help="a line per mutant as it ends")
    parser.add_argument("--json", type=Path, help="write every mutant's result here")
    parser.add_argument("--map", type=Path,
                        help="keep the coverage map in this file and reuse it when it exists "
                             "(new tests are not in it: see --refresh)")
    parser.add_argument("--rev", help="run on this commit instead of the working tree")
    parser.add_argument("--overlay", action="append", default=[], metavar="PATH",
                        help="with --rev: this file or folder of the working tree over the "
                             "commit (repeatable)")
    parser.add_argument("--refresh", action="append", default=[], metavar="TESTS",
                        help="with --map: run these tests (a pytest argument: a file or a node "
                             "id; repeatable) under coverage again and put them in the map")
    args = parser.parse_args()
    modules = [m.resolve().relative_to(ROOT).as_posix() for m in args.modules]
    only = {int(x) for x in args.only.split(",") if x}

    with tempfile.TemporaryDirectory(prefix="scriptc-mutate-") as tmp:
        tmp_path = Path(tmp)
        plugins = tmp_path / "plugins"
        plugins.mkdir()
        for name, text in _PLUGINS.items():
            (plugins / f"{name}.py").write_text(text, encoding="utf-8")
        works = [snapshot(tmp_path / "w0", args.rev, args.overlay)]
        for i in range(1, args.jobs):
            works.append(tmp_path / f"w{i}")
            shutil.copytree(works[0], works[i])
        started = time.perf_counter()
        lines, durations = load_map(args, works[0], plugins, modules)
        print(f"coverage map: {time.perf_counter() - started:.0f} s", flush=True)

        listed = equivalents()
        used: set[Equivalent] = set()
        plans = []
        for module in modules:
            text = (works[0] / module).read_text(encoding="utf-8")
            found = mutants(text, module)
            if only:
                found = [m for m in found if m.line in only]
            if args.max:
                found = found[:args.max]
            text_lines = text.splitlines()
            by_key: dict[tuple[str, str], list[Equivalent]] = {}
            for e in listed:
                if e.module == module:
                    by_key.setdefault((e.line, e.change), []).append(e)
            equivalent, kept = [], []
            for m in found:
                entry = next((e for e in by_key.get((text_lines[m.line - 1].strip(), m.what), ())
                              if e.function in ("", m.function)), None)
                if entry is None:
                    kept.append(m)
                else:
                    equivalent.append((m, entry))
                    used.add(entry)
            plans.append((module, text_lines, kept, equivalent))

        # Only tests that pass on the original can tell a mutant from it.
        started = time.perf_counter()
        wanted = {t for module, _text, found, _eq in plans for m in found
                  for line in range(m.line, m.end_line + 1)
                  for t in lines.get(module, {}).get(line, ())}
        good = passing(works[0], plugins, sorted(wanted))
        if wanted - good:
            print(f"warning: {len(wanted - good)} tests of the map fail, are gone or cannot be "
                  f"collected, and are left out (e.g. {min(wanted - good)})", flush=True)
        print(f"baseline of {len(good)} tests: {time.perf_counter() - started:.0f} s",
              flush=True)

        free = list(works)
        results: list[dict] = []
        for module, text_lines, found, equivalent in plans:
            covered = lines.get(module, {})

            # The closures run in this iteration (the pool is joined below): the loop's
            # variables are bound as defaults all the same.
            def tests_of(m: Mutant, covered: dict[int, set[str]] = covered) -> list[str]:
                hit: set[str] = set(covered.get(m.statement, ()))
                for line in range(m.line, m.end_line + 1):
                    hit |= covered.get(line, set())
                # Fastest first: most mutants are killed by the first test that fails.
                return sorted(hit & good, key=lambda t: (durations.get(t, 0.5), t))

            done: list[str] = []
            kills: dict[str, int] = {}  # test file -> mutants of this module it killed first

            def one(m: Mutant, done: list[str] = done, found: list[Mutant] = found,
                    module: str = module, kills: dict[str, int] = kills) -> tuple[Mutant, str]:
                work = free.pop()
                try:
                    stages = stages_of(tests_of(m), kills)
                    timeouts = [max(60.0, 5 * sum(durations.get(t, 0.5) for t in s) + 30)
                                for s in stages]
                    result, killer = run_mutant(m, stages, timeouts, work, plugins)
                    if killer is not None:
                        kills[killer] = kills.get(killer, 0) + 1
                    done.append(result)
                    if args.progress:
                        print(f"  [{len(done)}/{len(found)}] {module}:{m.line}: {m.what}: "
                              f"{result}", flush=True)
                    return m, result
                finally:
                    free.append(work)

            started = time.perf_counter()
            with ThreadPoolExecutor(max_workers=args.jobs) as pool:
                outcomes = list(pool.map(one, found))
            killed = sum(1 for _m, r in outcomes if r in ("killed", "timeout"))
            total = len(outcomes)
            score = 100.0 * killed / total if total else 100.0
            print(f"{module}: {total} mutants, {killed} killed, {score:.1f}%"
                  + (f" ({len(equivalent)} equivalent, left out)" if equivalent else "")
                  + f" ({time.perf_counter() - started:.0f} s)", flush=True)
            for m, r in outcomes:
                results.append({"file": module, "line": m.line, "what": m.what, "result": r})
                if args.show_survivors and r in ("survived", "uncovered"):
                    print(f"  {module}:{m.line}: {m.what} ({r})  {text_lines[m.line - 1].strip()}")
            for m, entry in equivalent:
                results.append({"file": module, "line": m.line, "what": m.what,
                                "result": "equivalent", "why": entry.why})
        for entry in listed:
            if entry not in used and entry.module in modules and not only and not args.max:
                print(f"warning: {EQUIVALENT.name} lists a mutant no longer made: "
                      f"{entry.module}: {entry.line!r}: {entry.change}", flush=True)
        if args.json:
            args.json.write_text(json.dumps(results, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
