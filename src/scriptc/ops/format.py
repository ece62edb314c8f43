"""`scriptc fmt` as a library call: `FormatRun` finds the files (as `lint` walks folders),
formats each in the canonical layout (`scriptc.formatter`) and, unless it is a dry run,
rewrites the files that change, atomically; each file's outcome is yielded as it is done, for
the caller to report. `unified_diff` is the diff `fmt --diff` and `lint --diff` print.

A file with syntax errors (or that is not UTF-8 text) is never rewritten: it is `REFUSED`,
with its diagnostics. Read from stdin, a file's output is what goes to stdout: the formatted
text, or the input unchanged when it is refused or already formatted, so that an editor that
pipes its buffer through `scriptc fmt -` never loses it.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator

from scriptc.analysis.analyze import Analysis
from scriptc.analysis.read import ReadError, decode_source, read_bytes
from scriptc.encoding import encode_like
from scriptc.paths import shown_path
from scriptc.writing import WriteError, write_file

__all__ = ["FileFormat", "FormatRun", "unified_diff"]

_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+$")


def unified_diff(old: str, new: str, name: str) -> str:
    """A unified diff of two texts, line endings kept, `\\ No newline at end of file` marked."""
    import difflib

    out: list[str] = []
    for line in difflib.unified_diff(_LINES.findall(old), _LINES.findall(new),
                                     fromfile=name, tofile=name):
        out.append(line)
        if not line.endswith(("\n", "\r")):
            out.append("\n\\ No newline at end of file\n")
    return "".join(out)


class FileFormat:
    """The outcome of formatting one file (`path` as named, `-` for stdin; `name` as shown).

    `status` is one of: UNREADABLE (`error` says why), REFUSED (`analysis` holds the syntax
    errors that stop it), UNCHANGED, CHANGED (a dry run: nothing written), REFORMATTED
    (written; for stdin, `stdout` holds it), UNWRITTEN (the new text could not be written:
    `error` says why). `old` and `new` are the texts before and after; `stdout` the bytes to
    write to standard output for stdin (None for a file)."""

    UNREADABLE = "unreadable"
    REFUSED = "refused"
    UNCHANGED = "unchanged"
    CHANGED = "changed"
    REFORMATTED = "reformatted"
    UNWRITTEN = "unwritten"

    __slots__ = ("analysis", "error", "name", "new", "old", "path", "status", "stdout")

    def __init__(self, path: str, name: str, status: str, *, error: str = "",
                 analysis: Analysis | None = None, old: str = "", new: str = "",
                 stdout: bytes | None = None) -> None:
        self.path = path
        self.name = name
        self.status = status
        self.error = error
        self.analysis = analysis
        self.old = old
        self.new = new
        self.stdout = stdout

    def __repr__(self) -> str:
        return f"FileFormat({self.name!r}, {self.status})"


class FormatRun:
    """`scriptc fmt PATH...`: `files` and `problems` (paths that do not exist, folders that
    cannot be read) are found at once; iterating formats each file and yields its
    `FileFormat`. `dry` (`--check`, `--diff`) writes nothing; `skip_invalid` makes a refused
    file pass. `exit_code` is the verb's status once iterated: 2 a path or file could not
    be read or written, 1 a file was refused or (dry) would change, else 0."""

    def __init__(self, paths: list[str] | tuple[str, ...], *,
                 stdin: Callable[[], bytes] | None = None, stdin_name: str = "<stdin>",
                 dry: bool = False, skip_invalid: bool = False) -> None:
        from scriptc.project.config import Resolver
        from scriptc.project.files import discover

        self.stdin = stdin
        self.stdin_name = stdin_name
        self.dry = dry
        self.skip_invalid = skip_invalid
        # The same walk as `scriptc lint`: .gitignore and the configuration's exclusions.
        self.files, self.problems = discover(paths, resolver=Resolver())
        self.unreadable = len(self.problems)
        self.changed = self.refused = 0

    def __iter__(self) -> Iterator[FileFormat]:
        for path in self.files:
            outcome = self.format_file(path)
            if outcome.status in (FileFormat.UNREADABLE, FileFormat.UNWRITTEN):
                self.unreadable += 1
            elif outcome.status == FileFormat.REFUSED and not self.skip_invalid:
                self.refused += 1
            elif outcome.status in (FileFormat.CHANGED, FileFormat.REFORMATTED):
                self.changed += 1
            yield outcome

    @property
    def exit_code(self) -> int:
        if self.unreadable:
            return 2
        return 1 if self.refused or (self.dry and self.changed) else 0

    def format_file(self, path: str) -> FileFormat:
        """Format one file (`-`: stdin), and write it when it changes (unless `dry`)."""
        from scriptc.formatter import format_text

        stdin = path == "-"
        name = shown_path(self.stdin_name if stdin else path)
        try:
            if stdin:
                if self.stdin is None:
                    raise ReadError("reading stdin is not supported here")
                data = self.stdin()
            else:
                data = read_bytes(path)
        except ReadError as exc:
            return FileFormat(path, name, FileFormat.UNREADABLE, error=str(exc))
        # The input as it came, for stdin when nothing else is written (not on a dry run,
        # whose stdout is the list or the diff).
        echo = data if stdin and not self.dry else None
        source, problem = decode_source(name, data)
        if problem is not None:
            return FileFormat(path, name, FileFormat.REFUSED, old=source.text,
                              analysis=Analysis(source, None, [problem]), stdout=echo)
        result = format_text(source.text)
        if result.refused or result.text is None:
            return FileFormat(path, name, FileFormat.REFUSED, old=source.text,
                              analysis=Analysis(source, None, result.diagnostics), stdout=echo)
        formatted = result.text
        new = encode_like(formatted, data)
        if new == data:
            return FileFormat(path, name, FileFormat.UNCHANGED, old=source.text,
                              new=formatted, stdout=echo)
        if self.dry:
            return FileFormat(path, name, FileFormat.CHANGED, old=source.text, new=formatted)
        if stdin:
            return FileFormat(path, name, FileFormat.REFORMATTED, old=source.text,
                              new=formatted, stdout=new)
        try:
            write_file(path, new)
        except WriteError as exc:
            return FileFormat(path, name, FileFormat.UNWRITTEN, error=str(exc),
                              old=source.text, new=formatted)
        return FileFormat(path, name, FileFormat.REFORMATTED, old=source.text, new=formatted)
