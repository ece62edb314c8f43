"""From files to results: reading sources safely, running the front end and the checks (with
the script's suppression comments), and, for the CLI, finding script files and linting many
of them with their configuration, the cache, worker processes and fixes (`lint_paths`). The
CLI and the language server call this module; it holds no presentation.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from scriptc import interrupt
from scriptc.diagnostics.edits import apply_fixes
from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.analysis.finish import finish
from scriptc.gcpause import gc_paused
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.paths import shown_path
from scriptc.source import SourceFile
from scriptc.writing import UTF8_BOM, WriteError, encode_like, write_file


@dataclass
class Analysis:
    """A source, the script read from it (None when it could not be read at all) and every
    diagnostic about it, sorted by position. `suppressed` holds what the script's suppression
    comments hid (`scriptc.analysis.suppress`; never an error)."""

    source: SourceFile
    script: Script | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    suppressed: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.script is not None and not has_errors(self.diagnostics)


def _finish(source: SourceFile, script: Script | None, front: list[Diagnostic],
            functions: FunctionRegistry, kind: str = "json", profile=None) -> Analysis:
    diagnostics, suppressed = finish(source, script, front, functions=functions, kind=kind,
                                     profile=profile)
    return Analysis(source, script, diagnostics, suppressed)


def analyze_script(source: SourceFile, functions: FunctionRegistry = STANDARD,
                   profile=None) -> Analysis:
    """Parse, lower and check script syntax."""
    from scriptc.frontend.script import lower_script

    with gc_paused():
        script, front = lower_script(source)
        return _finish(source, script, front, functions, "script", profile)


def analyze_json(source: SourceFile, functions: FunctionRegistry = STANDARD,
                 profile=None) -> Analysis:
    """Read thesis JSON (schema, then IR) and run the same checks as for script syntax."""
    from scriptc.frontend.thesis_json import script_from_json

    with gc_paused():
        script, front = script_from_json(source)
        return _finish(source, script, front, functions, "json", profile)


# ---------------------------------------------------------------------------------------------
# Reading sources: bytes in, a SourceFile out, never an exception for bad content.

class ReadError(Exception):
    """A file that cannot be read at all (missing, a directory, no permission). The content
    of a file is never a ReadError: bad bytes are a P007 diagnostic (`decode_source`)."""


def decode_source(path: str, data: bytes) -> tuple[SourceFile, Diagnostic | None]:
    """Decode the bytes of a script or JSON file as UTF-8, with a leading BOM stripped.

    Invalid UTF-8 and NUL bytes (binary content) give a P007 diagnostic at the first bad
    byte; its line and column are those of the text decoded up to there. The SourceFile then
    holds the whole content with each bad byte replaced by U+FFFD, so that offsets before
    the bad byte are exact and a renderer can show the offending line.
    """
    skipped = 0
    if data.startswith(UTF8_BOM):
        data, skipped = data[len(UTF8_BOM):], len(UTF8_BOM)
    bad: int | None = None
    message = ""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad = exc.start
        message = f"the file is not UTF-8 text: byte 0x{data[bad]:02x} is not valid UTF-8"
        text = data.decode("utf-8", errors="replace")
    nul = data.find(b"\x00", 0, bad)
    if nul != -1:
        bad = nul
        message = "the file is not text: it holds a NUL byte (is it a binary file?)"
    if bad is None:
        return SourceFile(path, text), None

    from scriptc.diagnostics.codes import diagnostic
    from scriptc.source import Span

    # The prefix before the first bad byte is valid UTF-8, so its length in code points is
    # the offset of the bad byte in `text` (the replacement keeps the prefix unchanged).
    offset = len(data[:bad].decode("utf-8"))
    notes = [f"at byte offset {bad + skipped} of the file"]
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        notes.append("the file starts with a UTF-16 byte order mark: it is UTF-16, not UTF-8")
    source = SourceFile(path, text)
    return source, diagnostic(
        "P007",
        message,
        Span(offset, min(offset + 1, len(text))),
        notes=notes,
        help="save the file as UTF-8 (scripts are text; binary files cannot be read)",
    )


def read_bytes(path: str | os.PathLike[str]) -> bytes:
    """The content of a file, or a ReadError that says why it cannot be read."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except FileNotFoundError:
        raise ReadError(f"`{shown_path(os.fspath(path))}` does not exist") from None
    except IsADirectoryError:
        raise ReadError(f"`{shown_path(os.fspath(path))}` is a directory, not a file") from None
    except PermissionError:
        raise ReadError(f"cannot read `{shown_path(os.fspath(path))}`: permission denied") \
            from None
    except OSError as exc:
        raise ReadError(f"cannot read `{shown_path(os.fspath(path))}`: "
                        f"{exc.strerror or exc}") from None


def read_source(path: str | os.PathLike[str], name: str | None = None
                ) -> tuple[SourceFile, Diagnostic | None]:
    """Read and decode one file (see `decode_source`); `name` is the path shown to people,
    `path` by default. Raises ReadError when the file cannot be read."""
    return decode_source(name if name is not None else os.fspath(path), read_bytes(path))


def analyze_bytes(name: str, data: bytes, kind: str = "script",
                  functions: FunctionRegistry = STANDARD, profile=None) -> Analysis:
    """Decode and analyse one file's bytes as script syntax (`kind="script"`) or thesis JSON
    (`kind="json"`). Undecodable content gives an Analysis with no script and P007."""
    source, problem = decode_source(name, data)
    if problem is not None:
        return Analysis(source, None, [problem])
    if kind == "script":
        return analyze_script(source, functions, profile)
    if kind == "json":
        return analyze_json(source, functions, profile)
    raise ValueError(f"unknown kind of source {kind!r}")


def analyze_file(path: str | os.PathLike[str], kind: str = "script", name: str | None = None,
                 functions: FunctionRegistry = STANDARD, profile=None) -> Analysis:
    """Read and analyse one file; raises ReadError when it cannot be read."""
    return analyze_bytes(name if name is not None else os.fspath(path), read_bytes(path), kind,
                         functions, profile)


# ---------------------------------------------------------------------------------------------
# Many files


@dataclass
class Run:
    """The results of analysing several files (`scriptc lint`, `scriptc check`), and the files
    that could not be read at all."""

    results: list[Analysis] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        """The CLI's status: 2 when a file could not be read, 1 when a diagnostic is an error,
        0 otherwise (warnings and info alone pass)."""
        if self.problems:
            return 2
        return 1 if any(has_errors(r.diagnostics) for r in self.results) else 0


# ---------------------------------------------------------------------------------------------
# Back ends and output files

# The back ends of `scriptc compile --emit`: name -> (suffix of the default output file,
# module and function turning a checked Script into the output: text, or bytes for bytecode).
EMITTERS: dict[str, tuple[str, str, str]] = {
    "json": (".json", "scriptc.emit.json", "emit_json"),
    "bytecode": (".scb", "scriptc.emit.codegen", "emit_bytecode"),
}
# Back ends that also take the SourceFile: the bytecode records lines and columns of spans.
_WITH_SOURCE = frozenset({"bytecode"})


def emit(script: Script, back_end: str = "json", source: SourceFile | None = None
         ) -> str | bytes:
    """The output of one back end for a checked script: text (json) or bytes (bytecode).
    `source`, when given, lets the bytecode carry source lines (docs/bytecode.md)."""
    import importlib

    _suffix, module, function = EMITTERS[back_end]
    emitter = getattr(importlib.import_module(module), function)
    with gc_paused():
        if back_end in _WITH_SOURCE:
            return emitter(script, source)
        return emitter(script)


def decompile(script: Script) -> str:
    """Script syntax for a script (read from thesis JSON)."""
    from scriptc.emit.script import format_script

    return format_script(script)


def default_output(input_path: str, back_end: str = "json") -> str:
    """Where `scriptc compile FILE` writes without `-o`: beside the input, its suffix
    replaced by the back end's (`dance.script` -> `dance.json`); stdout (`-`) for stdin."""
    if input_path == "-":
        return "-"
    root, _ext = os.path.splitext(input_path)
    return root + EMITTERS[back_end][0]


def same_file(a: str, b: str) -> bool:
    """True when two paths name the same file (existing or not)."""
    if a == "-" or b == "-":
        return False
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


# ---------------------------------------------------------------------------------------------
# The code registry, for `scriptc explain`


def suggest_codes(query: str, limit: int = 3) -> list[str]:
    """Codes (or names) close to a mistyped one, best first."""
    import difflib

    from scriptc.diagnostics.codes import all_codes

    codes = {c.code: c.code for c in all_codes()}
    names = {c.name: c.code for c in all_codes()}
    hits = difflib.get_close_matches(query.upper(), list(codes), n=limit, cutoff=0.5)
    hits += [names[n] for n in difflib.get_close_matches(query.lower(), list(names), n=limit,
                                                         cutoff=0.6)]
    return list(dict.fromkeys(hits))[:limit]


# ---------------------------------------------------------------------------------------------
# Linting a repository: configuration, suppressions, the cache, workers, fixes
#
# `lint_paths` is what `scriptc lint` and `scriptc check` run. Per file: find its
# configuration (`scriptc.project.config.Resolver`), look its result up in the cache (content +
# configuration + scriptc), analyse the misses (in worker processes when there is enough work
# to pay for them), then apply the configuration's policy (selection, per-file ignores,
# severities). The cache holds what the analysis found, before the policy, so the policy is
# always today's.


# The classes of this section are plain classes, not dataclasses: `scriptc lint` imports
# this module on every run, and generating dataclass methods costs milliseconds of it.


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
                 diff: bool = False, unsafe_fixes: bool = False, selection=None) -> None:
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


class FileReport:
    """What linting one file reports (renderers read `source` and `diagnostics`); `path` is
    the file as named (`-` for stdin), `cached` whether the result came from the cache,
    `fixed` how many fixes `--fix` applied to it (or, with `diff`, would apply), and
    `fixed_text` the text `--fix` would write, when `diff` asked for it and it differs."""

    __slots__ = ("source", "diagnostics", "path", "cached", "fixed", "fixed_text")

    def __init__(self, source: SourceFile, diagnostics: list[Diagnostic], path: str = "",
                 cached: bool = False, fixed: int = 0, fixed_text: str | None = None) -> None:
        self.source = source
        self.diagnostics = diagnostics
        self.path = path
        self.cached = cached
        self.fixed = fixed
        self.fixed_text = fixed_text

    def __repr__(self) -> str:
        return f"FileReport({self.source.path!r}, {len(self.diagnostics)} diagnostics)"

    @property
    def fixable(self) -> int:
        return self.fixes(unsafe=False)

    def fixes(self, unsafe: bool = False) -> int:
        """How many diagnostics have a fix `--fix` takes: the safe ones, and the unsafe ones
        too with `unsafe` (`--unsafe-fixes`)."""
        return sum(1 for d in self.diagnostics if d.fix is not None and (unsafe or d.fix.safe))


class LintRun(Run):
    """`Run` with the configurations' own reports first in `results`, and counts: files
    read, results from the cache, fixes applied and the files they changed. `unsafe_fixes`:
    whether the unsafe fixes count as available."""

    def __init__(self, files: int = 0, unsafe_fixes: bool = False) -> None:
        super().__init__()
        self.files = files
        self.cached = 0
        self.fixed = 0
        self.fixed_files = 0
        self.unsafe_fixes = unsafe_fixes
        self.configs = 0  # how many of `results`, at the start, are configuration files

    @property
    def fixable(self) -> int:
        """The fixes `--fix` would apply (with `--unsafe-fixes`, the unsafe ones too)."""
        return sum(r.fixes(self.unsafe_fixes) for r in self.results if isinstance(r, FileReport))

    @property
    def hidden_fixes(self) -> int:
        """The unsafe fixes left out because `--unsafe-fixes` was not given."""
        if self.unsafe_fixes:
            return 0
        return sum(r.fixes(True) - r.fixes(False) for r in self.results
                   if isinstance(r, FileReport))


def available_cores() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def discover(paths: list[str] | tuple[str, ...], kind: str = "script", *,
             resolver=None, force_exclude: bool = False) -> tuple[list[str], list[str]]:
    """The files `scriptc lint PATH...`, `scriptc check PATH...` and `scriptc fmt PATH...`
    read, in order, and the problems met finding them. A file named on the command line is
    read whatever its suffix; a folder contributes its `*.script` files (for `kind` "json":
    its `.json` files that are thesis scripts, `is_thesis_json`), recursively and sorted,
    skipping hidden files and folders, what .gitignore files ignore and what the
    configuration excludes (`scriptc.project.files`); `-` (stdin) is kept; a file reached twice is
    read once. A path that does not exist and a folder that cannot be read are problems, each
    named, and the other paths go on. With `force_exclude` the configuration's `exclude`
    applies to files named on the command line too (for pre-commit, which names every
    changed file)."""
    from scriptc.project.files import SCRIPT_SUFFIX, Walker

    walker = Walker(resolver.for_folder if resolver is not None else None,
                    suffix=".json" if kind == "json" else SCRIPT_SUFFIX,
                    accept=is_thesis_json if kind == "json" else None)
    found: list[str] = []
    problems: list[str] = []
    seen: set[str] = set()
    for path in paths:
        if path != "-" and not os.path.lexists(path):
            problems.append(f"`{shown_path(path)}` does not exist")
            continue
        if path != "-" and os.path.isdir(path):
            inner = walker.walk(path)
            problems += walker.problems
            walker.problems.clear()
        elif force_exclude and path != "-" and walker.excluded(os.path.abspath(path), False):
            inner = []
        else:
            inner = [path]
        for p in inner:
            key = p if p == "-" else os.path.realpath(p)
            if key not in seen:
                seen.add(key)
                found.append(p)
    return found, problems


def is_thesis_json(path: str) -> bool:
    """Whether a `.json` file met in a folder is a thesis script (not a scenario, not a
    `package.json`): its top-level object has `activityname`; or, when it does not read as
    JSON at all (a broken script is still a script), its text names `"activityname"`. A file
    that cannot be read counts, so that reading it reports why."""
    import json

    try:
        data = read_bytes(path)
    except ReadError:
        return True
    if data.startswith(UTF8_BOM):
        data = data[len(UTF8_BOM):]
    try:
        value = json.loads(data)
    except (ValueError, RecursionError):
        return b'"activityname"' in data
    return isinstance(value, dict) and "activityname" in value


# Worker processes: the registry of each set of user functions is built once per worker.
_registries: dict[tuple, FunctionRegistry] = {}


def _registry(functions: tuple) -> FunctionRegistry:
    if not functions:
        return STANDARD
    registry = _registries.get(functions)
    if registry is None:
        registry = _registries[functions] = STANDARD.extended(functions)
    return registry


def _analyze_task(task: tuple) -> list[Diagnostic]:
    """Analyse one file (in a worker or in this process): its diagnostics after its own
    suppressions, before the configuration's policy. A task is (name, bytes, kind, the
    declared functions' signatures, the robot profile)."""
    name, data, kind, functions, profile = task
    return analyze_bytes(name, data, kind, _registry(functions), profile=profile).diagnostics


def _analyze_chunk(tasks: list[tuple[str, bytes, str, tuple]]) -> list[list[Diagnostic]]:
    return [_analyze_task(task) for task in tasks]


# Below this much text, starting worker processes costs more than it saves (the front end
# reads about 0.6 MB/s on one core).
PARALLEL_MIN_BYTES = 100_000


def _analyze_all(tasks: list[tuple[str, bytes, str, tuple]], jobs: int,
                 done: Callable[[int, list[Diagnostic]], None]) -> None:
    """Analyse every task, calling `done(index, diagnostics)` as each finishes: in worker
    processes when there are several tasks and enough text, else here."""
    total = sum(len(t[1]) for t in tasks)
    if jobs > 1 and len(tasks) > 1 and total >= PARALLEL_MIN_BYTES:
        try:
            _analyze_parallel(tasks, jobs, done)
            return
        except _PoolFailed:
            pass  # no worker processes here (a sandbox): one process does it all
    for i, task in enumerate(tasks):
        done(i, _analyze_task(task))


class _PoolFailed(Exception):
    pass


def _analyze_parallel(tasks: list[tuple[str, bytes, str, tuple]], jobs: int,
                      done: Callable[[int, list[Diagnostic]], None]) -> None:
    import multiprocessing
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    # `fork` where the platform has it: the workers start with scriptc already imported.
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else None)
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
    try:
        pool = ProcessPoolExecutor(max_workers=min(jobs, len(chunks)), mp_context=context,
                                   initializer=_worker_start)
    except (OSError, ValueError, NotImplementedError) as exc:
        raise _PoolFailed from exc
    try:
        # The workers are started by the first submissions; Ctrl-C is held back meanwhile,
        # so that none starts before it ignores Ctrl-C (`_worker_start`).
        with interrupt.deferred():
            pending = {pool.submit(_analyze_chunk, [tasks[i] for i in chunk]): chunk
                       for chunk in chunks}
        while pending:
            ready, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in ready:
                chunk = pending.pop(future)
                for i, diagnostics in zip(chunk, future.result()):
                    finished.add(i)
                    done(i, diagnostics)
    except BrokenProcessPool:
        # A worker died (killed, out of memory): finish the rest here.
        _stop_workers(pool)
        for i, task in enumerate(tasks):
            if i not in finished:
                done(i, _analyze_task(task))
    except BaseException:
        # Ctrl-C (or a failure here): the workers are stopped now, not after their chunks.
        _stop_workers(pool)
        raise
    else:
        pool.shutdown(wait=True)


def _worker_start() -> None:
    """The start of a worker process: Ctrl-C is the parent's to handle (a terminal sends it to
    every process of the command; the parent stops the workers). The worker was forked with
    Ctrl-C and SIGTERM held back (`interrupt.deferred`): SIGTERM, by which the parent stops
    it, must reach it again."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})


def _stop_workers(pool) -> None:
    """Stop a process pool at once: pending work cancelled, the workers terminated and
    waited for (none is left behind). `shutdown` alone would wait for the chunks already
    running; the pool has no public way to terminate its workers before Python 3.14
    (`terminate_workers`), so they are taken from its `_processes`."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout=5)
        if process.is_alive():
            process.kill()
            process.join()
    pool.shutdown(wait=True)


MAX_FIX_ROUNDS = 10


def lint_paths(paths: list[str] | tuple[str, ...], kind: str = "script", *,
               stdin: Callable[[], bytes] | None = None, stdin_name: str = "<stdin>",
               options: LintOptions | None = None) -> LintRun:
    """Lint (`kind="script"`) or check (`kind="json"`) every file named by `paths`, with the
    configuration of each file, its cached result when it has one, worker processes for the
    rest and, with `options.fix`, the safe fixes applied (files rewritten atomically). A path
    that does not exist, a folder or a file that cannot be read is recorded in `problems`,
    and the others go on. Files are named by `scriptc.paths.shown_path`."""
    from scriptc.project.config import Resolver

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

    # Read every file, and look each up in the cache.
    entries: list[tuple[str, str, bytes, Any, str | None]] = []  # path, name, data, settings, key
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
        entries.append((path, name, data, settings, key))

    found: list[list[Diagnostic] | None] = [None] * len(entries)
    total = len(entries)
    finished = 0

    def tick() -> None:
        if options.progress is not None:
            options.progress(finished, total)

    if cache is not None:
        for i, (_path, _name, _data, _settings, key) in enumerate(entries):
            found[i] = cache.get_result(key)
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
        key = entries[i][4]
        if key is not None and key in first_of:
            same[first_of[key]].append(i)
            continue
        if key is not None:
            first_of[key] = i
        missing.append(i)
        same[i] = [i]

    def done(j: int, diagnostics: list[Diagnostic]) -> None:
        nonlocal finished
        i = missing[j]
        for k in same[i]:
            found[k] = diagnostics
        if cache is not None:
            cache.put_result(entries[i][4], diagnostics)
        finished += len(same[i])
        tick()

    tasks = [(entries[i][1], entries[i][2], kind,
              tuple(f.signature for f in entries[i][3].functions),
              entries[i][3].robot) for i in missing]
    _analyze_all(tasks, options.jobs or available_cores(), done)

    reports: list[FileReport] = []
    for i, (path, name, data, settings, _key) in enumerate(entries):
        source, _problem = decode_source(name, data)
        shown = None if path == "-" and stdin_name == "<stdin>" else name
        diagnostics = settings.apply(found[i], shown)
        report = FileReport(source, diagnostics, path, cached=i in hits)
        fixing = options.diff or (options.fix and path != "-")
        if fixing and report.fixes(options.unsafe_fixes):
            try:
                report = _fix_file(report, data, kind, settings, cache,
                                   unsafe=options.unsafe_fixes, write=not options.diff)
            except WriteError as exc:
                run.problems.append(f"{exc}: its fixes were not written")
            run.fixed += report.fixed
            run.fixed_files += 1 if report.fixed else 0
        reports.append(report)

    configs = [FileReport(c.source, c.diagnostics, c.source.path)
               for c in resolver.configs if c.diagnostics]
    run.results = [*configs, *reports]
    run.configs = len(configs)
    return run


def _fix_file(report: FileReport, data: bytes, kind: str, settings, cache, *,
              unsafe: bool = False, write: bool = True) -> FileReport:
    """Apply the safe fixes of a file (the unsafe ones too with `unsafe`) until none is left
    (or MAX_FIX_ROUNDS), re-linting after each round; write the file atomically when it
    changed (WriteError when it cannot be written). Without `write` nothing is written: the
    report keeps the file as it is, with the text the fixes give in `fixed_text`."""
    source, diagnostics = report.source, report.diagnostics
    text = source.text
    functions = tuple(f.signature for f in settings.functions)
    profile = settings.robot
    fixed = 0
    for _round in range(MAX_FIX_ROUNDS):
        fixes = [d.fix for d in diagnostics if d.fix is not None and (unsafe or d.fix.safe)]
        if not fixes:
            break
        new_text, applied = apply_fixes(text, fixes)
        if not applied or new_text == text:
            break
        fixed += applied
        text = new_text
        raw = _analyze_task((source.path, text.encode("utf-8"), kind, functions, profile))
        diagnostics = settings.apply(raw, source.path)
    if text == source.text:
        return report
    if not write:
        return FileReport(source, report.diagnostics, report.path, report.cached, fixed=fixed,
                          fixed_text=text)
    new_data = encode_like(text, data)
    write_file(report.path, new_data)
    if cache is not None:
        cache.put_result(cache.result_key(kind, settings.digest, new_data), raw)
    return FileReport(SourceFile(source.path, text), diagnostics, report.path, fixed=fixed)


def configuration_failed(reports: list[FileReport]) -> bool:
    """Whether the configuration reports of `settings_for` hold an error: `compile`,
    `decompile` and `run` do nothing then (docs/configuration.md); warnings do not stop them."""
    return any(has_errors(r.diagnostics) for r in reports)


def settings_for(path: str, *, cache: bool = True):
    """The configuration of one file (`scriptc compile FILE`): its `Settings`, and a report of
    the configuration file's own problems (empty when it has none). `path` may be a file
    name that does not exist (`--stdin-filename`): its folder is searched."""
    from scriptc.project.config import Resolver

    store = None
    if cache:
        from scriptc.project.cache import Cache, default_cache_dir
        from scriptc.project.config import project_root

        # The cache of the file's project, wherever scriptc runs (as `lint_paths`).
        store = Cache(default_cache_dir(project_root(path if path not in ("-", "<stdin>")
                                                     else ".")))
    resolver = Resolver(store)
    settings = resolver.for_file(path if path not in ("-", "<stdin>") else "-")
    reports = [FileReport(c.source, c.diagnostics, c.source.path)
               for c in resolver.configs if c.diagnostics]
    return settings, reports
