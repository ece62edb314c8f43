"""`scriptc lint` and `scriptc check` as a library call: `lint_paths` lints many files with
their configuration, the cache, worker processes and fixes, and returns a `LintRun`; it
prints nothing (the CLI renders the run, `scriptc.diagnostics.render`).

Per file: find its configuration (`scriptc.project.config.Resolver`, and the setup it makes,
`scriptc.project.setup`), look its result up in the cache (content + configuration +
scriptc), analyse the misses (in worker processes when there is enough work to pay for them),
then apply the configuration's policy (selection, per-file ignores, severities). The cache
holds what the analysis found, before the policy, so the policy is always today's. Each file
is read and decoded once: the workers receive its text.

Ctrl-C: nothing here waits for a safe point. Whatever is written (cache entries, fixed files)
is put in place whole (`scriptc.writing`), and the worker processes ignore Ctrl-C and are
stopped by the parent at once, so a `KeyboardInterrupt` may fall anywhere and leaves nothing
half-done.

The classes here are plain classes, not dataclasses: `scriptc lint` imports this module on
every run, and generating dataclass methods costs milliseconds of it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, TypeAlias

from scriptc.analysis.analyze import Analysis, analyze_source
from scriptc.analysis.read import ReadError, decode_source, read_bytes
from scriptc.diagnostics.edits import apply_fixes
from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.encoding import encode_like
from scriptc.ops.workers import PoolFailed, available_cores, map_chunks
from scriptc.ops.workers import start_worker as _worker_start  # noqa: F401 (tests name it here)
from scriptc.ops.workers import stop_workers as _stop_workers  # noqa: F401
from scriptc.paths import shown_path
from scriptc.project.files import discover
from scriptc.project.setup import Setup, function_registry
from scriptc.source import SourceFile, SourceKind
from scriptc.writing import WriteError, write_file

if TYPE_CHECKING:  # types only: `scriptc lint` imports this module on every run
    from scriptc.ir.builtins import Function
    from scriptc.project.cache import Cache
    from scriptc.project.config.load import ConfigFile
    from scriptc.project.config.settings import RuleSelection, Settings
    from scriptc.robot.profile import Profile

__all__ = [
    "MAX_FIX_ROUNDS",
    "FileReport",
    "LintOptions",
    "LintRun",
    "available_cores",
    "lint_paths",
]


class LintOptions:
    """How `lint_paths` runs. `cache_dir` None: `scriptc.project.cache.default_cache_dir` of
    the project's root; `jobs` None: one worker per available core; `progress(done, total)`
    is called as files finish. `fix` rewrites files with their fixes; `diff` computes the
    same fixes and writes nothing (each report's `fixed_text`); `unsafe_fixes` takes the
    unsafe fixes too; `selection` is the command line's rule selection over every
    configuration (`config.RuleSelection`)."""

    def __init__(self, cache: bool = True, cache_dir: str | None = None, jobs: int | None = None,
                 fix: bool = False, config: str | None = None, isolated: bool = False,
                 force_exclude: bool = False,
                 progress: Callable[[int, int], None] | None = None, *,
                 diff: bool = False, unsafe_fixes: bool = False,
                 selection: RuleSelection | None = None) -> None:
        self.cache = cache
        self.cache_dir = cache_dir
        self.jobs = jobs
        self.fix = fix
        self.config = config
        self.isolated = isolated
        self.force_exclude = force_exclude
        self.progress = progress
        self.diff = diff
        self.unsafe_fixes = unsafe_fixes
        self.selection = selection


class FileReport(Analysis):
    """What linting one file reports: its `Analysis`, whose `script` is None (lint keeps
    diagnostics only: the cache and the workers hold no IR), with `path`, the file as named
    (`-` for stdin), `cached`, whether the result came from the cache, `fixed`, how many
    fixes `--fix` applied to it (or, with `diff`, would apply), and `fixed_text`, the text
    `--fix` would write, when `diff` asked for it and it differs."""

    __slots__ = ("cached", "fixed", "fixed_text", "path")

    def __init__(self, source: SourceFile, diagnostics: list[Diagnostic], path: str = "",
                 cached: bool = False, fixed: int = 0, fixed_text: str | None = None) -> None:
        super().__init__(source, None, diagnostics)
        self.path = path
        self.cached = cached
        self.fixed = fixed
        self.fixed_text = fixed_text

    @property
    def fixable(self) -> int:
        return self.fixes(unsafe=False)

    def fixes(self, unsafe: bool = False) -> int:
        """How many diagnostics have a fix `--fix` takes: the safe ones, and the unsafe ones
        too with `unsafe` (`--unsafe-fixes`)."""
        return sum(1 for d in self.diagnostics if d.fix is not None and (unsafe or d.fix.safe))


class LintRun:
    """The results of linting several files: `results`, the configuration files that have
    problems first (`configs` of them: each with its `source` and `diagnostics`) then a
    `FileReport` per file; `problems`, the paths and files that could not be read (or
    written); and counts: files read, results from the cache, fixes applied and the files
    they changed. `unsafe_fixes`: whether the unsafe fixes count as available."""

    def __init__(self, files: int = 0, unsafe_fixes: bool = False) -> None:
        self.config_files: list[ConfigFile] = []  # the configuration files that have problems
        self.reports: list[FileReport] = []  # the files' reports
        self.problems: list[str] = []
        self.files = files
        self.cached = 0
        self.fixed = 0
        self.fixed_files = 0
        self.unsafe_fixes = unsafe_fixes

    @property
    def results(self) -> list[ConfigFile | FileReport]:
        """The configuration files that have problems, then the files' reports."""
        return [*self.config_files, *self.reports]

    @property
    def configs(self) -> int:
        """How many of `results`, at the start, are configuration files."""
        return len(self.config_files)

    @property
    def exit_code(self) -> int:
        """The CLI's status: 2 when a file could not be read, 1 when a diagnostic is an error,
        0 otherwise (warnings and info alone pass)."""
        if self.problems:
            return 2
        return 1 if any(has_errors(r.diagnostics) for r in self.results) else 0

    @property
    def diff_exit_code(self) -> int:
        """The status of `--diff`: 2 when a file could not be read, 1 when there is something
        to fix or the configuration has an error, 0 otherwise."""
        if self.problems:
            return 2
        failed = any(has_errors(c.diagnostics) for c in self.results[:self.configs])
        return 1 if self.fixed or failed else 0

    @property
    def fixable(self) -> int:
        """The fixes `--fix` would apply (with `--unsafe-fixes`, the unsafe ones too)."""
        return sum(r.fixes(self.unsafe_fixes) for r in self.reports)

    @property
    def hidden_fixes(self) -> int:
        """The unsafe fixes left out because `--unsafe-fixes` was not given."""
        if self.unsafe_fixes:
            return 0
        return sum(r.fixes(True) - r.fixes(False) for r in self.reports)


# A task is one file to analyse, in a worker or here: (name, text, kind, the declared
# functions' signatures, the robot profile). Plain data, cheap to send to a worker.
Task: TypeAlias = "tuple[str, str, SourceKind, tuple[Function, ...], Profile]"


def _analyze_task(task: Task) -> list[Diagnostic]:
    """Analyse one file: its diagnostics after its own suppressions, before the
    configuration's policy."""
    name, text, kind, signatures, profile = task
    return analyze_source(SourceFile(name, text), kind, function_registry(signatures),
                          profile).diagnostics


def _analyze_chunk(tasks: list[Task]) -> list[list[Diagnostic]]:
    return [_analyze_task(task) for task in tasks]


# Below this much text, starting worker processes costs more than it saves (the front end
# reads about 0.6 MB/s on one core).
PARALLEL_MIN_BYTES = 100_000


def _analyze_all(tasks: list[Task], jobs: int,
                 done: Callable[[int, list[Diagnostic]], None]) -> None:
    """Analyse every task, calling `done(index, diagnostics)` as each finishes: in worker
    processes when there are several tasks and enough text, else here."""
    total = sum(len(t[1]) for t in tasks)
    if jobs > 1 and len(tasks) > 1 and total >= PARALLEL_MIN_BYTES:
        try:
            _analyze_parallel(tasks, jobs, done)
            return
        except PoolFailed:
            pass  # no worker processes here (a sandbox): one process does it all
    for i, task in enumerate(tasks):
        done(i, _analyze_task(task))


def _analyze_parallel(tasks: list[Task], jobs: int,
                      done: Callable[[int, list[Diagnostic]], None]) -> None:
    from concurrent.futures.process import BrokenProcessPool

    # Chunks of about 64 KB of text: few enough messages, small enough to balance the load
    # and to move the progress bar.
    chunks: list[list[int]] = [[]]
    size = 0
    for i, task in enumerate(tasks):
        if size >= 64_000:
            chunks.append([])
            size = 0
        chunks[-1].append(i)
        size += len(task[1])
    finished: set[int] = set()

    def chunk_done(c: int, k: int, diagnostics: list[Diagnostic]) -> None:
        i = chunks[c][k]
        finished.add(i)
        done(i, diagnostics)

    try:
        map_chunks(_analyze_chunk, [[tasks[i] for i in chunk] for chunk in chunks], jobs,
                   chunk_done)
    except BrokenProcessPool:
        # A worker died (killed, out of memory): finish the rest here.
        for i, task in enumerate(tasks):
            if i not in finished:
                done(i, _analyze_task(task))


MAX_FIX_ROUNDS = 10


class _Entry:
    """One file of a run, read and decoded: as named (`path`), as shown (`name`), its bytes,
    its source (and the P007 problem when its bytes are not text), its setup and its key in
    the cache."""

    __slots__ = ("data", "key", "name", "path", "problem", "setup", "source")

    def __init__(self, path: str, name: str, data: bytes, setup: Setup,
                 key: str | None) -> None:
        self.path = path
        self.name = name
        self.data = data
        self.source, self.problem = decode_source(name, data)
        self.setup = setup
        self.key = key


def lint_paths(paths: list[str] | tuple[str, ...], kind: SourceKind = SourceKind.SCRIPT, *,
               stdin: Callable[[], bytes] | None = None, stdin_name: str = "<stdin>",
               options: LintOptions | None = None) -> LintRun:
    """Lint (script syntax) or check (thesis JSON) every file named by `paths`, with the
    configuration of each file, its cached result when it has one, worker processes for the
    rest and, with `options.fix`, the safe fixes applied (files rewritten atomically). A path
    that does not exist, a folder or a file that cannot be read is recorded in `problems`,
    and the others go on. Files are named by `scriptc.paths.shown_path`."""
    from scriptc.project.config import Resolver

    kind = SourceKind(kind)
    options = options or LintOptions()
    cache = None
    if options.cache:
        from scriptc.project.cache import Cache, default_cache_dir
        from scriptc.project.config import project_root

        # The project's root is that of the first path's configuration (else here): the
        # same folder from wherever scriptc runs.
        first = next((p for p in paths if p != "-"),
                     stdin_name if stdin_name != "<stdin>" else ".")
        cache = Cache(options.cache_dir or default_cache_dir(
            project_root(first, config=options.config, isolated=options.isolated)))
    resolver = Resolver(cache, config=options.config, isolated=options.isolated,
                        selection=options.selection)
    files, problems = discover(paths, kind, resolver=resolver,
                               force_exclude=options.force_exclude)
    run = LintRun(files=len(files), unsafe_fixes=options.unsafe_fixes)
    run.problems += problems
    setups: dict[int, Setup] = {}  # one per configuration (by the Settings' identity)

    def setup_of(settings: Settings) -> Setup:
        setup = setups.get(id(settings))
        if setup is None:
            setup = setups[id(settings)] = Setup(settings)
        return setup

    # Read every file, and look each up in the cache.
    entries: list[_Entry] = []
    for path in files:
        try:
            if path == "-":
                if stdin is None:
                    raise ReadError("reading stdin is not supported here")
                data, name = stdin(), shown_path(stdin_name)
                settings = resolver.for_file(stdin_name if stdin_name != "<stdin>" else "-")
            else:
                data, name = read_bytes(path), shown_path(path)
                settings = resolver.for_file(path)
        except ReadError as exc:
            run.problems.append(str(exc))
            continue
        key = cache.result_key(kind, settings.digest, data) if cache is not None else None
        entries.append(_Entry(path, name, data, setup_of(settings), key))

    found: list[list[Diagnostic] | None] = [None] * len(entries)
    total = len(entries)
    finished = 0

    def tick() -> None:
        if options.progress is not None:
            options.progress(finished, total)

    if cache is not None:
        for i, entry in enumerate(entries):
            found[i] = cache.get_result(entry.key) if entry.key is not None else None
        run.cached = sum(1 for f in found if f is not None)
        finished = run.cached
        tick()
    hits = {i for i, f in enumerate(found) if f is not None}
    # Files with the same key (same content and configuration) are analysed once.
    missing: list[int] = []
    same: dict[int, list[int]] = {}
    first_of: dict[str, int] = {}
    for i, f in enumerate(found):
        if f is not None:
            continue
        key = entries[i].key
        if key is not None and key in first_of:
            same[first_of[key]].append(i)
            continue
        if key is not None:
            first_of[key] = i
        missing.append(i)
        same[i] = [i]

    def finish(i: int, diagnostics: list[Diagnostic]) -> None:
        nonlocal finished
        for k in same[i]:
            found[k] = diagnostics
        key = entries[i].key
        if cache is not None and key is not None:
            cache.put_result(key, diagnostics)
        finished += len(same[i])
        tick()

    # A file that is not text has its one diagnostic already (P007); the others are analysed.
    analysed: list[int] = []
    for i in missing:
        problem = entries[i].problem
        if problem is not None:
            finish(i, [problem])
        else:
            analysed.append(i)
    tasks: list[Task] = [(entries[i].name, entries[i].source.text, kind,
                          entries[i].setup.signatures, entries[i].setup.profile)
                         for i in analysed]
    _analyze_all(tasks, options.jobs or available_cores(), lambda j, d: finish(analysed[j], d))

    reports: list[FileReport] = []
    for i, entry in enumerate(entries):
        shown = None if entry.path == "-" and stdin_name == "<stdin>" else entry.name
        # Every file has its diagnostics by now: from the cache, a worker or its decoding.
        report = FileReport(entry.source, entry.setup.apply(found[i] or [], shown), entry.path,
                            cached=i in hits)
        fixing = options.diff or (options.fix and entry.path != "-")
        if fixing and report.fixes(options.unsafe_fixes):
            try:
                report = _fix_file(report, entry, kind, cache, unsafe=options.unsafe_fixes,
                                   write=not options.diff)
            except WriteError as exc:
                run.problems.append(f"{exc}: its fixes were not written")
            run.fixed += report.fixed
            run.fixed_files += 1 if report.fixed else 0
        reports.append(report)

    run.config_files = [c for c in resolver.configs if c.diagnostics]
    run.reports = reports
    return run


def _fix_file(report: FileReport, entry: _Entry, kind: SourceKind, cache: Cache | None, *,
              unsafe: bool = False, write: bool = True) -> FileReport:
    """Apply the safe fixes of a file (the unsafe ones too with `unsafe`) until none is left
    (or MAX_FIX_ROUNDS), re-linting after each round; write the file atomically when it
    changed (WriteError when it cannot be written). Without `write` nothing is written: the
    report keeps the file as it is, with the text the fixes give in `fixed_text`."""
    source, diagnostics = report.source, report.diagnostics
    setup = entry.setup
    text = source.text
    fixed = 0
    raw: list[Diagnostic] = []
    for _round in range(MAX_FIX_ROUNDS):
        fixes = [d.fix for d in diagnostics if d.fix is not None and (unsafe or d.fix.safe)]
        if not fixes:
            break
        new_text, applied = apply_fixes(text, fixes)
        if not applied or new_text == text:
            break
        fixed += applied
        text = new_text
        raw = _analyze_task((source.path, text, kind, setup.signatures, setup.profile))
        diagnostics = setup.apply(raw, source.path)
    if text == source.text:
        return report
    if not write:
        return FileReport(source, report.diagnostics, report.path, report.cached, fixed=fixed,
                          fixed_text=text)
    new_data = encode_like(text, entry.data)
    write_file(report.path, new_data)
    if cache is not None:
        cache.put_result(cache.result_key(kind, setup.settings.digest, new_data), raw)
    return FileReport(SourceFile(source.path, text), diagnostics, report.path, fixed=fixed)
