"""The cache of results under `.scriptc_cache/`: what linting a file found, keyed by the file's
content, the configuration and the version of scriptc, so that a file that did not change is
not analysed again; and the checked configuration files, so that `jsonschema` is imported only
when a configuration file changed.

Layout: `.scriptc_cache/CACHEDIR.TAG` (the cache-directory tagging standard: backup tools
skip the folder), `.scriptc_cache/.gitignore` (`*`: git ignores the whole folder), then one
folder per scriptc version holding content-addressed entries (`results/ab/abcd....json`,
`project/config/....json`). Entries are written to a temporary file and renamed into place, so two
runs at once never see half an entry; an entry that cannot be read is a miss. Deleting the
folder is always safe.

The cache knows nothing of the configuration: its callers give it its root and the material
of its keys (the configuration's digest among them).

The key of an entry includes a fingerprint of scriptc's own code (size and modification time
of its modules and grammars), so that in a source checkout a change to a check is never
hidden behind the results of the old code.
"""

from __future__ import annotations

import contextlib
import json
import os
from functools import cache

from scriptc import __version__
from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity, TextEdit
from scriptc.numbers import JSONValue
from scriptc.source import Span
from scriptc.writing import create_file, replace_file

CACHE_DIR_NAME = ".scriptc_cache"
CACHEDIR_TAG = (
    "Signature: 8a477f597d28d172789f06886806bc55\n"
    "# This file is a cache directory tag created by scriptc.\n"
    "# For information about cache directory tags see https://bford.info/cachedir/\n"
)

try:  # the builtin module: hashlib would import OpenSSL (5 ms of cold start)
    from _blake2 import blake2b
except ImportError:  # pragma: no cover - other Python implementations
    from hashlib import blake2b

def digest(*parts: bytes | str) -> str:
    """A hex digest of the parts (each length-prefixed, so that parts cannot run together)."""
    h = blake2b(digest_size=20)
    for part in parts:
        data = part.encode("utf-8") if isinstance(part, str) else part
        h.update(len(data).to_bytes(8, "little"))
        h.update(data)
    return h.hexdigest()


@cache
def code_fingerprint() -> str:
    """The version of scriptc and the size and modification time of each of its modules and
    grammar files (about a hundred `stat` calls, once per process: memoised)."""
    from scriptc.resources import data_dir

    package = os.path.dirname(os.path.abspath(__file__))
    rows = [__version__]
    folders = [package]
    with contextlib.suppress(FileNotFoundError):
        folders.append(str(data_dir("grammar")))
    while folders:
        folder = folders.pop()
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for entry in entries:
            if entry.is_dir(follow_symlinks=False):
                if entry.name != "__pycache__":
                    folders.append(entry.path)
            elif entry.name.endswith((".py", ".lark")):
                st = entry.stat()
                rows.append(f"{entry.path}\0{st.st_mtime_ns}\0{st.st_size}")
    rows.sort()
    return digest("\n".join(rows))


# ---------------------------------------------------------------------------------------------
# Diagnostics as JSON

# An entry as the cache stores it is a JSONValue (a diagnostic is a list of texts, numbers,
# booleans, None and lists of them: `dump_diagnostic`), checked by whoever reads it back.


def dump_diagnostic(d: Diagnostic) -> list[JSONValue]:
    return [
        d.code, d.severity.value, d.message, d.span.start, d.span.end,
        [[label.span.start, label.span.end, label.message] for label in d.labels],
        list(d.notes), d.help,
        None if d.fix is None else [d.fix.message, d.fix.safe,
                                    [[e.span.start, e.span.end, e.new_text] for e in d.fix.edits]],
        d.path,
    ]


def load_diagnostic(row: list[JSONValue]) -> Diagnostic:
    code, severity, message, start, end, labels, notes, help_, fix, path = row
    return Diagnostic(
        code=code,
        severity=Severity(severity),
        message=message,
        span=Span(start, end),
        labels=tuple(Label(Span(s, e), m) for s, e, m in labels),
        notes=tuple(notes),
        help=help_,
        fix=None if fix is None else Fix(fix[0], tuple(TextEdit(Span(s, e), t)
                                                       for s, e, t in fix[2]), fix[1]),
        path=path,
    )


# ---------------------------------------------------------------------------------------------
# The cache folder


class Cache:
    """Entries in `folder` (a `.scriptc_cache`), created on first write."""

    def __init__(self, folder: str) -> None:
        self.folder = folder
        self.base = os.path.join(folder, __version__)
        self._made: set[str] = set()

    def _path(self, kind: str, key: str) -> str:
        return os.path.join(self.base, kind, key[:2], key + ".json")

    def get(self, kind: str, key: str) -> JSONValue | None:
        """The entry `key` of `kind` ("results", "config"), or None."""
        try:
            with open(self._path(kind, key), "rb") as f:
                return json.loads(f.read())
        except (OSError, ValueError):
            return None

    def put(self, kind: str, key: str, value: JSONValue) -> None:
        """Store an entry; a cache that cannot be written is silently not used."""
        path = self._path(kind, key)
        folder = os.path.dirname(path)
        try:
            if folder not in self._made:
                self._prepare()
                os.makedirs(folder, exist_ok=True)
                self._made.add(folder)
            data = json.dumps(value, separators=(",", ":"), ensure_ascii=False).encode("utf-8")
            # Atomic, as every file scriptc writes, without the flush to disk: an entry lost
            # in a crash is only a miss.
            replace_file(path, data, durable=False)
        except OSError:
            pass

    def _prepare(self) -> None:
        """The cache folder with its tag and .gitignore, made once."""
        if self.folder in self._made:
            return
        os.makedirs(self.folder, exist_ok=True)
        for name, text in (("CACHEDIR.TAG", CACHEDIR_TAG),
                           (".gitignore", "# Created by scriptc: the cache is not source.\n*\n")):
            target = os.path.join(self.folder, name)
            if not os.path.exists(target):
                with contextlib.suppress(FileExistsError):  # another run made it meanwhile
                    create_file(target, text.encode("utf-8"))
        self._made.add(self.folder)

    # Results of analysing one file.

    def result_key(self, kind: str, config_digest: str, data: bytes) -> str:
        return digest(code_fingerprint(), kind, config_digest, data)

    def get_result(self, key: str) -> list[Diagnostic] | None:
        entry = self.get("results", key)
        if not isinstance(entry, list):
            return None
        try:
            return [load_diagnostic(row) for row in entry]
        except (TypeError, ValueError, KeyError):
            return None

    def put_result(self, key: str, diagnostics: list[Diagnostic]) -> None:
        self.put("results", key, [dump_diagnostic(d) for d in diagnostics])


def default_cache_dir(root: str = ".") -> str:
    """Where the cache goes without `--cache-dir`: `SCRIPTC_CACHE_DIR`, else the folder
    `.scriptc_cache` in the project's `root` (`scriptc.project.config.project_root`: the folder
    of the configuration, so that from a subfolder or from outside the project it is the same
    folder)."""
    return os.environ.get("SCRIPTC_CACHE_DIR") or os.path.join(root, CACHE_DIR_NAME)
