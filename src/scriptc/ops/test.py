"""`scriptc test` as a library call (docs/testing.md): `test_paths` finds the test files,
checks every one before anything runs, keeps those `-k` selects, runs them in worker
processes and returns a `TestRun`; it prints nothing (the CLI renders the run with
`scriptc.testing.report` and `scriptc.diagnostics.render`).

- Discovery: `*.test.toml` under each folder given (a file named is taken whatever its name),
  sorted, skipping hidden files and folders, what `.gitignore` ignores and what the
  configuration excludes (`scriptc.project.files`, the walk `scriptc lint` uses).
- Checking: every test file found is read and checked (`scriptc.testing.read`); when one has
  a problem nothing runs (as pytest stops on an error while collecting), whatever `-k` says.
- Selection: `-k TEXT` keeps the tests whose path, as shown, or description contains TEXT,
  whatever the case; then `--shard I/N` keeps the I-th part of those
  (`scriptc.testing.shard`: the same split in every job, by recorded durations if any).
- Running (`run_one`): a test's scripts are loaded as `scriptc run` loads them
  (`scriptc.ops.programs`: checked, compiled to bytecode, run by the VM, under their
  repository's configuration, functions, rules and robot profile), and its session run
  (`scriptc.testing.run`). A test whose scripts cannot be loaded is an `error`, with the
  diagnostics that say why. A test with `snapshot = true` has its trace compared with its
  snapshot file, or the file written with `update` (`scriptc.testing.snapshot`).
- Workers: one per core (`jobs`), each test a task of its own (`scriptc.ops.workers`); results
  are handed to `on_result` in the order of the tests, as they come. Ctrl-C stops the workers
  at once; the run comes back `interrupted` with the results it had.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

from scriptc.analysis.read import ReadError
from scriptc.diagnostics.model import has_errors
from scriptc.diagnostics.render import FileResults
from scriptc.interrupt import EXIT_STATUS
from scriptc.ops.programs import (
    ConfigurationFailed,
    ProgramLoader,
    Refused,
    governed_by_default,
    load_programs,
)
from scriptc.ops.workers import PoolFailed, available_cores, map_chunks
from scriptc.paths import shown_path
from scriptc.project.files import discover
from scriptc.testing import snapshot
from scriptc.testing.model import TestFile
from scriptc.testing.read import SUFFIX, ReadTest, read_test
from scriptc.testing.run import ERROR, FAILED, TestResult, replay_command, run_test
from scriptc.testing.shard import Shard, in_shard

__all__ = ["TestOptions", "TestRun", "run_one", "select", "test_paths"]


@dataclass
class TestOptions:
    """How `test_paths` runs: `jobs` worker processes (None: one per core), `keyword` the
    text of `-k`, `executor` how scripts run (`vm`, or `ir`: the reference interpreter),
    `progress(done, total)` as tests finish, `on_result(index, result)` for each test in
    order as soon as it and those before it are done."""

    __test__ = False  # not a pytest class, despite its name

    jobs: int | None = None
    keyword: str | None = None
    executor: str = "vm"
    progress: Callable[[int, int], None] | None = None
    on_result: Callable[[int, TestResult], None] | None = None
    # `--update`: write the snapshot of each test with `snapshot = true` that is missing or
    # differs (`scriptc.testing.snapshot`), instead of failing it.
    update: bool = False
    # `--shard I/N`: run only this part of the tests selected, split by `durations` (the
    # seconds each test took, by `scriptc.testing.shard.test_key`) when they are known.
    shard: Shard | None = None
    durations: Mapping[str, float] | None = None


@dataclass
class TestRun:
    """What `test_paths` found and did: the test `files` found, `problems` met finding or
    reading them (a path that does not exist), `invalid` the test files with problems (then
    nothing ran), `tests` the tests selected, in order, and their `results` (as many as ran:
    fewer when `interrupted`), `wall_s` the seconds it took."""

    __test__ = False

    files: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    invalid: list[ReadTest] = field(default_factory=list)
    tests: list[TestFile] = field(default_factory=list)
    selected: int = 0  # how many tests `-k` selected, before the shard took its part
    results: list[TestResult] = field(default_factory=list)
    interrupted: bool = False
    wall_s: float = 0.0
    checked_s: float = 0.0  # of `wall_s`, finding, reading and checking the test files

    @property
    def exit_code(self) -> int:
        """0 every test passed, 1 a test failed, 2 a test file or a script could not be
        loaded (or a path does not exist), 130 interrupted."""
        if self.interrupted:
            return EXIT_STATUS
        if self.problems or self.invalid or any(r.status == ERROR for r in self.results):
            return 2
        return 1 if any(r.status == FAILED for r in self.results) else 0


def select(tests: Sequence[TestFile], keyword: str | None) -> list[TestFile]:
    """The tests whose path (as shown) or description contains `keyword`, whatever the case
    (all of them without one)."""
    if not keyword:
        return list(tests)
    word = keyword.casefold()
    return [t for t in tests if word in t.source.path.casefold()
            or word in t.description.casefold()]


def test_paths(paths: Sequence[str], options: TestOptions | None = None) -> TestRun:
    """Find, check, select and run the tests under `paths` (see the module's docstring)."""
    from scriptc.project.config import Resolver

    options = options or TestOptions()
    started = time.perf_counter()
    run = TestRun()
    files, run.problems = discover(list(paths), resolver=Resolver(), suffix=SUFFIX)
    for path in files:
        if path == "-":
            run.problems.append("a test cannot be read from stdin: name its file")
            continue
        run.files.append(path)
        try:
            read = read_test(path)
        except ReadError as exc:
            run.problems.append(str(exc))
            continue
        if read.test is None:
            run.invalid.append(read)
        else:
            run.tests.append(read.test)
    if run.problems or run.invalid:
        run.wall_s = time.perf_counter() - started
        return run
    run.tests = select(run.tests, options.keyword)
    run.selected = len(run.tests)
    if options.shard is not None:
        run.tests = in_shard(run.tests, options.shard, options.durations)
    run.checked_s = time.perf_counter() - started
    try:
        _run_all(run, options)
    except KeyboardInterrupt:
        run.interrupted = True
    run.wall_s = time.perf_counter() - started
    return run


def _run_all(run: TestRun, options: TestOptions) -> None:
    """Run every selected test, in workers when there are several and several cores; the
    results in the order of the tests (`run.results`, `options.on_result`)."""
    tests, total = run.tests, len(run.tests)
    finished: dict[int, TestResult] = {}

    def done(i: int, result: TestResult) -> None:
        finished[i] = result
        if options.progress is not None:
            options.progress(len(finished), total)
        while len(run.results) in finished:  # hand over in order, as soon as possible
            k = len(run.results)
            run.results.append(finished[k])
            if options.on_result is not None:
                options.on_result(k, finished[k])

    jobs = options.jobs or available_cores()
    if total:
        # Once, before any test is timed: the first test would pay for the imports (its
        # seconds are what `--durations` records and shards are balanced by).
        _prepare(tests[0], options.executor)
    if jobs > 1 and total > 1:
        from concurrent.futures.process import BrokenProcessPool

        # Chunks of a few tests: fewer messages than one per test, and still eight chunks a
        # worker or more to even out the load (a test may be long).
        size = max(1, min(8, total // (8 * jobs)))
        chunks = [list(range(i, min(i + size, total))) for i in range(0, total, size)]
        try:
            map_chunks(_run_chunk, [[(tests[i], options.executor, options.update)
                                     for i in chunk]
                                    for chunk in chunks], jobs,
                       lambda c, k, result: done(chunks[c][k], result))
            return
        except PoolFailed:
            pass  # no worker processes here (a sandbox): this process runs them all
        except BrokenProcessPool:
            pass  # a worker died (killed, out of memory): the rest run here
    for i, test in enumerate(tests):
        if i not in finished:
            done(i, run_one(test, options.executor, update=options.update))


def _prepare(test: TestFile, executor: str) -> None:
    """What every worker would do first, done once here before any test is timed and any
    worker forked: importing the front ends, code generation, the runtime and the robot, and
    reading the grammar (about 0.2 s a process otherwise). The first test's scripts are
    loaded for it; whatever goes wrong there is the test's to report when it runs."""
    import contextlib

    with contextlib.suppress(Exception):
        load_programs(test.scripts, executor)
    from scriptc.runtime import configured, robots  # noqa: F401 (imported for the workers)

    with contextlib.suppress(Exception):
        robots.make_robot(test.robot)


def _run_chunk(items: list[tuple[TestFile, str, bool]]) -> list[TestResult]:
    return [run_one(test, executor, update=update) for test, executor, update in items]


def run_one(test: TestFile, executor: str = "vm", *, update: bool = False) -> TestResult:
    """Load the scripts of `test` as `scriptc run` does and run it (`scriptc.testing.run`),
    its snapshot judged, or written with `update`; a test that cannot start is a result with
    the status `error` saying why."""
    started = time.perf_counter()
    governor = test.governor if test.governor is not None else governed_by_default(test.robot)
    replay = replay_command(test, governor)

    def error(reason: str, problems: Sequence[FileResults] = ()) -> TestResult:
        return TestResult(test.source.path, test.description, ERROR, replay, reason=reason,
                          problems=tuple((p.source, tuple(p.diagnostics)) for p in problems),
                          wall_s=time.perf_counter() - started)

    try:
        loaded = load_programs(test.scripts, executor)
    except ConfigurationFailed as exc:
        return error(str(exc), exc.setup.problems)
    except (ReadError, Refused) as exc:
        return error(str(exc))
    if not loaded.ok:
        broken = [a for a in loaded.analyses if has_errors(a.diagnostics)]
        names = ", ".join(f"`{shown_path(a.source.path)}`" for a in broken)
        return error(f"{names} {'has' if len(broken) == 1 else 'have'} errors", broken)
    from scriptc.runtime.configured import ConfiguredError, implementations_for, rules_for
    from scriptc.runtime.robots import make_robot

    settings = loaded.setup.settings
    try:
        functions, rules = implementations_for(settings), rules_for(settings)
    except ConfiguredError as exc:
        return error(str(exc))
    try:
        robot = make_robot(test.robot)
    except Exception as exc:
        return error(f"the robot `{test.robot}` cannot start: {exc}")
    programs = [p for p in loaded.programs if p is not None]  # all of them: `loaded.ok`
    result = run_test(test, programs, robot,
                      profile=loaded.setup.profile if governor else None,
                      loader=ProgramLoader(executor), functions=functions, rules=rules)
    # The snapshot is judged (and with `update` written) where the trace is: in the worker.
    result = snapshot.judge(test, result, update=update)
    return replace(result, wall_s=time.perf_counter() - started)
