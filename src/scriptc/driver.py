"""From files to results: reading sources safely, running the front end and the checks, and
(for the CLI) finding script files. The CLI and the language server call this module; it
holds no presentation.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field

from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.gcpause import gc_paused
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.source import SourceFile


@dataclass
class Analysis:
    """A source, the script read from it (None when it could not be read at all) and every
    diagnostic about it, sorted by position."""

    source: SourceFile
    script: Script | None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.script is not None and not has_errors(self.diagnostics)


def _finish(source: SourceFile, script: Script | None, front: list[Diagnostic],
            functions: FunctionRegistry) -> Analysis:
    diagnostics = list(front)
    # Semantic checks run on a script whose front end reported no error: a broken item would
    # otherwise cascade into reports about labels and flow that are not the user's mistake
    # (docs/language.md, "Error recovery").
    if script is not None and not has_errors(front):
        from scriptc.check import check_script

        diagnostics.extend(check_script(script, source, functions=functions))
    diagnostics.sort(key=Diagnostic.sort_key)
    return Analysis(source, script, diagnostics)


def analyze_script(source: SourceFile, functions: FunctionRegistry = STANDARD) -> Analysis:
    """Parse, lower and check script syntax."""
    from scriptc.ir.lower import lower_script

    with gc_paused():
        script, front = lower_script(source)
        return _finish(source, script, front, functions)


def analyze_json(source: SourceFile, functions: FunctionRegistry = STANDARD) -> Analysis:
    """Read thesis JSON (schema, then IR) and run the same checks as for script syntax."""
    from scriptc.ir.from_json import script_from_json

    with gc_paused():
        script, front = script_from_json(source)
        return _finish(source, script, front, functions)


# ---------------------------------------------------------------------------------------------
# Reading sources: bytes in, a SourceFile out, never an exception for bad content.

_BOM = b"\xef\xbb\xbf"


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
    if data.startswith(_BOM):
        data, skipped = data[len(_BOM):], len(_BOM)
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

    from scriptc.diagnostics.model import diagnostic
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
        raise ReadError(f"`{path}` does not exist") from None
    except IsADirectoryError:
        raise ReadError(f"`{path}` is a directory, not a file") from None
    except PermissionError:
        raise ReadError(f"cannot read `{path}`: permission denied") from None
    except OSError as exc:
        raise ReadError(f"cannot read `{path}`: {exc.strerror or exc}") from None


def read_source(path: str | os.PathLike[str], name: str | None = None
                ) -> tuple[SourceFile, Diagnostic | None]:
    """Read and decode one file (see `decode_source`); `name` is the path shown to people,
    `path` by default. Raises ReadError when the file cannot be read."""
    return decode_source(name if name is not None else os.fspath(path), read_bytes(path))


def analyze_bytes(name: str, data: bytes, kind: str = "script",
                  functions: FunctionRegistry = STANDARD) -> Analysis:
    """Decode and analyse one file's bytes as script syntax (`kind="script"`) or thesis JSON
    (`kind="json"`). Undecodable content gives an Analysis with no script and P007."""
    source, problem = decode_source(name, data)
    if problem is not None:
        return Analysis(source, None, [problem])
    if kind == "script":
        return analyze_script(source, functions)
    if kind == "json":
        return analyze_json(source, functions)
    raise ValueError(f"unknown kind of source {kind!r}")


def analyze_file(path: str | os.PathLike[str], kind: str = "script", name: str | None = None,
                 functions: FunctionRegistry = STANDARD) -> Analysis:
    """Read and analyse one file; raises ReadError when it cannot be read."""
    return analyze_bytes(name if name is not None else os.fspath(path), read_bytes(path), kind,
                         functions)


# ---------------------------------------------------------------------------------------------
# Finding script files

SCRIPT_SUFFIX = ".script"


def discover_scripts(paths: list[str] | tuple[str, ...], *, search_folders: bool = True
                     ) -> list[str]:
    """The files that `scriptc lint PATH...` reads, in order.

    A file named on the command line is read whatever its suffix; a folder contributes its
    `*.script` files, recursively, sorted, skipping hidden folders and hidden files (names
    starting with a dot: `.git`, editor lock files), unless `search_folders` is false (then it
    stays in the list, and reading it fails). `-` (stdin) is kept as it is. A file reached
    twice is read once. Raises ReadError for a path that does not exist, before any is read.
    """
    missing = [p for p in paths if p != "-" and not os.path.lexists(p)]
    if missing:
        raise ReadError(f"`{missing[0]}` does not exist")
    found: list[str] = []
    seen: set[str] = set()

    def add(p: str) -> None:
        key = p if p == "-" else os.path.realpath(p)
        if key not in seen:
            seen.add(key)
            found.append(p)

    for path in paths:
        if search_folders and path != "-" and os.path.isdir(path):
            inner: list[str] = []
            for root, dirs, files in os.walk(path):
                dirs[:] = [d for d in dirs if not d.startswith(".")]
                inner.extend(os.path.join(root, f) for f in files
                             if f.endswith(SCRIPT_SUFFIX) and not f.startswith("."))
            for p in sorted(inner):
                add(p)
        else:
            add(path)
    return found


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


def analyze_paths(paths: list[str] | tuple[str, ...], kind: str = "script", *,
                  stdin: Callable[[], bytes] | None = None, stdin_name: str = "<stdin>",
                  functions: FunctionRegistry = STANDARD) -> Run:
    """Analyse every file named by `paths`: for script syntax, folders are searched for
    `*.script` files (`discover_scripts`); thesis JSON is read from the files named only.
    `-` reads `stdin()`. A path that does not exist raises ReadError before anything is read;
    a file that cannot be read is recorded in `Run.problems` and the others go on."""
    files = discover_scripts(paths, search_folders=kind == "script")
    run = Run()
    for path in files:
        try:
            if path == "-":
                if stdin is None:
                    raise ReadError("reading stdin is not supported here")
                run.results.append(analyze_bytes(stdin_name, stdin(), kind, functions))
            else:
                run.results.append(analyze_file(path, kind, functions=functions))
        except ReadError as exc:
            run.problems.append(str(exc))
    return run


# ---------------------------------------------------------------------------------------------
# Back ends and output files

# The back ends of `scriptc compile --emit`: name -> (suffix of the default output file,
# module and function turning a checked Script into the output text). Bytecode joins here.
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


def write_atomic(path: str, data: str | bytes) -> None:
    """Write `data` (text as UTF-8, exactly: no newline translation) to `path` so that
    readers see either the old file or the whole new one: a temporary file in the same folder,
    flushed, then renamed over the target. The new file gets the old one's permissions, or
    the usual ones for a new file (0666 less the umask). Raises OSError."""
    import tempfile

    if isinstance(data, str):
        data = data.encode("utf-8")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        mode = os.stat(path).st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{os.path.basename(path)}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


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
