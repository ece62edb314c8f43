"""Finding and reading configuration files.

A file's configuration is the nearest `scriptc.toml`, or `pyproject.toml` with a
`[tool.scriptc]` table, in its folder or a folder above (a `pyproject.toml` without that
table is not a configuration, and the search goes on upwards; in one folder `scriptc.toml`
wins). Only the nearest configuration applies: configurations do not merge.

Reading one costs a `tomllib` parse. Checking it (the JSON Schema and the rest, in
`validate.py`) imports `jsonschema`, so its outcome is cached by the file's content: on the
fast path of `scriptc lint`, an unchanged configuration is read, never validated again.
A configuration with problems still applies, less the parts that are wrong.
"""

from __future__ import annotations

import os
import re
import sys
from typing import TYPE_CHECKING, NamedTuple

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.encoding import decode
from scriptc.language import FUNCTION_KINDS, is_name
from scriptc.numbers import MAX_DIGITS, number_problem
from scriptc.paths import shown_path
from scriptc.project.config.settings import (
    ALL,
    IMPLEMENTATION_PATTERN,
    SEVERITIES,
    RuleSelection,
    Settings,
    UserFunction,
    UserRule,
)
from scriptc.project.config.tomlpos import TOMLTable, TOMLValue
from scriptc.robot.limits import LIMITS
from scriptc.robot.profile import Profile
from scriptc.source import SourceFile, Span

if TYPE_CHECKING:
    from scriptc.project.cache import Cache

CONFIG_FILES = ("scriptc.toml", "pyproject.toml")
# Patterns are compiled on first use (`re` caches them): most runs never need them.
_TOOL_TABLE = r"^[ \t]*\[[ \t]*tool[ \t]*\.[ \t]*[\"']?scriptc\b"
_TOML_POSITION = r"\(at line (\d+), column (\d+)\)$"


def _read(path: str) -> bytes | None:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


# What a pyproject.toml configuring scriptc must contain: `[tool.scriptc...]`, a dotted key
# `tool.scriptc.x = `, or `scriptc = {` / `scriptc.x = ` under `[tool]`. A file with none of
# these is not parsed at all (tomllib costs 8 ms of cold start). A string in an array that
# starts with `"scriptc.` (mypy's and import-linter's module lists) is not such a key.
_MAYBE_TOOL = (rb"tool\s*\.\s*[\"']?scriptc\b"
               rb"|^\s*(?:scriptc|\"scriptc\"|'scriptc')\s*(?:=\s*\{|\.[^=\n]*=)")


def _pyproject_names_scriptc(data: bytes) -> bool:
    """Whether a pyproject.toml configures scriptc (cheap: most never mention it)."""
    if re.search(_MAYBE_TOOL, data, re.MULTILINE) is None:
        return False
    import tomllib

    try:
        table = tomllib.loads(data.decode("utf-8"))
    except (ValueError, RecursionError):  # not UTF-8 or TOML, or a value Python cannot read
        # A broken file that seems to hold the table is ours to report.
        return bool(re.search(_TOOL_TABLE, data.decode("utf-8", errors="replace"),
                              re.MULTILINE))
    tool = table.get("tool")
    return isinstance(tool, dict) and isinstance(tool.get("scriptc"), dict)


def config_in(folder: str) -> str | None:
    """The configuration file of `folder` itself, or None."""
    candidate = os.path.join(folder, "scriptc.toml")
    if os.path.isfile(candidate):
        return candidate
    candidate = os.path.join(folder, "pyproject.toml")
    if os.path.isfile(candidate):
        data = _read(candidate)
        if data is not None and _pyproject_names_scriptc(data):
            return candidate
    return None


def find_config(start: str) -> str | None:
    """The configuration that applies to `start` (a file or a folder): the nearest one in it
    or above it, as an absolute path, or None."""
    folder = os.path.abspath(start)
    if not os.path.isdir(folder):
        folder = os.path.dirname(folder)
    while True:
        found = config_in(folder)
        if found is not None:
            return found
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


def project_root(start: str = ".", *, config: str | None = None,
                 isolated: bool = False) -> str:
    """The root of the project `start` (a file or folder) belongs to: the folder of the
    configuration (`config` when one is forced, else the one that applies to `start`), else
    (no configuration, or `isolated`) the working folder `.`."""
    if config:
        return os.path.dirname(os.path.abspath(config))
    found = None if isolated else find_config(start)
    return os.path.dirname(found) if found else "."


def config_candidates(start: str) -> list[str]:
    """The files whose creation, change or deletion can change the configuration of `start`
    (a file or a folder), existing or not: the configuration files its folder and each folder
    above may hold, up to the folder of the nearest configuration (what is above it does not
    count while it is there). For a watcher of the configuration (the language server's,
    when the editor watches no files)."""
    folder = os.path.abspath(start)
    if not os.path.isdir(folder):
        folder = os.path.dirname(folder)
    out: list[str] = []
    while True:
        out += [os.path.join(folder, name) for name in CONFIG_FILES]
        parent = os.path.dirname(folder)
        if config_in(folder) is not None or parent == folder:
            return out
        folder = parent


class ConfigFile(NamedTuple):
    """A configuration file read: its settings, its text and what is wrong in it."""

    settings: Settings
    source: SourceFile
    diagnostics: list[Diagnostic]


class TomlRead(NamedTuple):
    """A TOML file's bytes read (`read_toml`): its text, its table, or the one problem that
    stopped the reading (then `table` is None)."""

    text: str
    table: TOMLTable | None
    problem: Diagnostic | None


def read_toml(data: bytes, *, what: str = "the configuration", syntax: str = "C005",
              value: str = "C002") -> TomlRead:
    """Decode and parse a TOML file (a configuration, a test file): bytes that are not UTF-8
    text and TOML syntax errors are a diagnostic of the code `syntax` at their place; an
    integer too long to read one of `value` (the number policy's error); arrays or tables
    nested too deep for `tomllib` one of `syntax`. `what` names the file in messages ("the
    configuration is not valid TOML: ...")."""
    import tomllib

    decoded = decode(data)
    text = decoded.text
    if decoded.bad is not None:
        return TomlRead(text, None, diagnostic(
            syntax, f"{what} is not valid TOML: {decoded.problem}",
            Span(decoded.bad, min(decoded.bad + 1, len(text))),
            notes=[f"at byte offset {decoded.byte} of the file"]))
    try:
        return TomlRead(text, tomllib.loads(text), None)
    except tomllib.TOMLDecodeError as exc:
        return TomlRead(text, None, _toml_error(text, exc, what, syntax))
    except ValueError:  # tomllib converts integers with int(): more than 4,300 digits fail
        return TomlRead(text, None, _long_integer(text, value))
    except RecursionError:  # tomllib recurses into nested arrays and inline tables
        return TomlRead(text, None, _too_deep(text, what, syntax))


def _toml_error(text: str, exc: Exception, what: str, code: str) -> Diagnostic:
    message = str(exc)
    m = re.search(_TOML_POSITION, message)
    if m is not None:
        line, column = int(m.group(1)), int(m.group(2))
        message = message[:m.start()].rstrip()
        source = SourceFile("", text)
        starts = source.line_starts
        offset = starts[min(line, len(starts)) - 1] + column - 1
    else:
        message = message.replace(" (at end of document)", "")
        offset = len(text)
    offset = max(0, min(offset, len(text)))
    first = message[:1].lower() + message[1:]
    return diagnostic(code, f"{what} is not valid TOML: {first}",
                      Span(offset, min(offset + 1, len(text))),
                      help="see https://toml.io for the syntax")


def _long_integer(text: str, code: str) -> Diagnostic:
    """The integer too long for Python to read, which stopped tomllib: the number policy's
    error at the first run of more digits than Python converts."""
    limit = sys.get_int_max_str_digits() or 4300
    run = re.search(rf"[0-9](?:_?[0-9]){{{limit},}}", text)
    span = Span(run.start(), run.end()) if run else Span(0, 0)
    written = text[span.start:span.end]
    problem = number_problem(10 ** MAX_DIGITS, written) if written else None
    return diagnostic(code, problem or "an integer too large to read", span,
                      help="write a number within a double's range")


def _too_deep(text: str, what: str, code: str) -> Diagnostic:
    """Arrays or inline tables nested deeper than tomllib can read (it recurses): an error at
    the first long run of openers."""
    run = re.search(r"[\[{](?:\s*[\[{]){50,}", text)
    span = Span(run.start(), run.start() + 1) if run else Span(0, 0)
    return diagnostic(code, f"{what} nests arrays or tables too deeply to be read",
                      span, help=f"{what}'s values nest a level or two")


def load_config(path: str, cache: Cache | None = None, *,
                pyproject: bool | None = None) -> ConfigFile:
    """Read, check and build the configuration in `path` (a scriptc.toml or pyproject.toml;
    `pyproject` says which when the file's name does not). Never raises: problems are
    diagnostics in the file. `cache` keeps the outcome of checking by the file's content."""
    from scriptc.project.cache import code_fingerprint, digest

    path = os.path.abspath(path)
    root = os.path.dirname(path)
    shown = shown_path(path)
    data = _read(path)
    if data is None:
        source = SourceFile(shown, "")
        return ConfigFile(Settings(path=path, root=root), source, [
            diagnostic("C005", "the configuration file cannot be read", Span(0, 0))])
    file_digest = digest(data)
    base = Settings(path=path, root=root, digest=file_digest)
    text, document, problem = read_toml(data)
    source = SourceFile(shown, text)
    if document is None:
        assert problem is not None  # a file that is not read says why
        return ConfigFile(base, source, [problem])
    prefix: tuple[str, ...] = ()
    table: TOMLValue = document
    if pyproject is None:
        pyproject = os.path.basename(path) == "pyproject.toml"
    if pyproject:
        prefix = ("tool", "scriptc")
        table = document.get("tool", {}).get("scriptc", {})
        if not isinstance(table, dict):
            table = {}

    key = digest(code_fingerprint(), "config", "pyproject" if pyproject else "scriptc", data)
    diagnostics = None
    if cache is not None:
        from scriptc.project.cache import load_diagnostic

        entry = cache.get("config", key)
        if isinstance(entry, list):
            try:
                diagnostics = [load_diagnostic(row) for row in entry]
            except (TypeError, ValueError, KeyError):
                diagnostics = None
    if diagnostics is None:
        from scriptc.project.config.validate import check_config

        diagnostics = check_config(table, source, prefix)
        if cache is not None:
            from scriptc.project.cache import dump_diagnostic

            cache.put("config", key, [dump_diagnostic(d) for d in diagnostics])
    return ConfigFile(build_settings(table, path=path, root=root, digest=file_digest),
                      source, diagnostics)


# ---------------------------------------------------------------------------------------------
# From the table to Settings: defensive, since a configuration with problems still applies
# (each wrong value was reported by the checks and is left at its default here).


def _strings(value: TOMLValue) -> tuple[str, ...]:
    if not isinstance(value, list):
        return ()
    return tuple(v for v in value if isinstance(v, str) and v)


def _number(value: TOMLValue) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            number_problem(value) is not None:  # nan, inf, beyond a double: reported
        return None
    return float(value)


def _name(value: TOMLValue) -> str | None:
    if isinstance(value, str) and is_name(value):
        return value
    return None


def _implementation(value: TOMLValue) -> str | None:
    if isinstance(value, str) and re.fullmatch(IMPLEMENTATION_PATTERN, value):
        return value
    return None


def build_settings(table: TOMLTable, *, path: str | None = None, root: str = ".",
                   digest: str = "") -> Settings:
    """Settings from a configuration table (values of the wrong type are left out)."""
    from scriptc.ir.builtins import STANDARD

    lint = table.get("lint")
    if not isinstance(lint, dict):
        lint = {}
    select = _strings(lint.get("select")) if "select" in lint else (ALL,)
    pfi = lint.get("per-file-ignores")
    per_file = tuple((pattern, _strings(codes)) for pattern, codes in pfi.items()
                     if pattern and _strings(codes)) if isinstance(pfi, dict) else ()
    sev = lint.get("severity")
    severity = tuple((k, v) for k, v in sev.items()
                     if isinstance(v, str) and v in SEVERITIES) if isinstance(sev, dict) else ()

    # A limit outside its range was reported by the checks (the schema's ranges are the
    # table's): like a missing one, it keeps its default (robot/limits.py).
    robot_table = table.get("robot")
    if not isinstance(robot_table, dict):
        robot_table = {}
    given: dict[str, float] = {}
    for limit in LIMITS:
        value = _number(robot_table.get(limit.key))
        if value is not None and limit.accepts(value):
            given[limit.key] = value

    functions: list[UserFunction] = []
    for item in table.get("functions", ()) if isinstance(table.get("functions"), list) else ():
        if not isinstance(item, dict):
            continue
        name, kind = _name(item.get("name")), item.get("kind")
        implementation = _implementation(item.get("implementation"))
        params = item.get("params")
        params = tuple(p for p in params if _name(p)) if isinstance(params, list) else ()
        arity = item.get("arity")
        if isinstance(arity, bool) or not isinstance(arity, int) or not 0 <= arity <= 255:
            arity = len(params) if isinstance(item.get("params"), list) else None
        if params and len(params) != arity:
            params = ()
        # (a kind that is no text, say an array, is not looked up: it cannot be a key)
        if name is None or not isinstance(kind, str) or kind not in FUNCTION_KINDS or \
                implementation is None or arity is None or STANDARD.get(name) is not None or \
                any(f.name == name for f in functions):
            continue
        doc = item.get("doc")
        if not isinstance(doc, str):
            doc = ""
        functions.append(UserFunction(name, kind, arity, implementation, params, doc, root))

    rules: list[UserRule] = []
    for item in table.get("rules", ()) if isinstance(table.get("rules"), list) else ():
        if not isinstance(item, dict):
            continue
        name = _name(item.get("name"))
        implementation = _implementation(item.get("implementation"))
        code = item.get("rulecode")
        if isinstance(code, bool) or not isinstance(code, int) or not 0 <= code < 2 ** 32:
            code = None
        if name is None or implementation is None or any(r.name == name for r in rules):
            continue
        doc = item.get("doc")
        if not isinstance(doc, str):
            doc = ""
        rules.append(UserRule(name, implementation, code, doc, root))

    audio = table.get("audio-root")
    respect = table.get("respect-gitignore")
    return Settings(
        path=path,
        root=root,
        digest=digest,
        select=select,
        ignore=_strings(lint.get("ignore")),
        per_file_ignores=per_file,
        severity=severity,
        exclude=_strings(table.get("exclude")),
        respect_gitignore=respect if isinstance(respect, bool) else True,
        audio_root=audio if isinstance(audio, str) and audio else ".",
        robot=Profile.given(given, source=path or "config"),
        functions=tuple(functions),
        rules=tuple(rules),
    )


# ---------------------------------------------------------------------------------------------
# Many files: each folder's configuration found once


class Resolver:
    """The configuration of each file of a run, each folder searched and each configuration
    file read once. `config` forces one file for all (`--config`); `isolated` uses none
    (`--isolated`); `selection` is the command line's rule selection, laid over every
    configuration (`--select`, `--extend-select`, `--ignore`)."""

    def __init__(self, cache: Cache | None = None, *, config: str | None = None,
                 isolated: bool = False, selection: RuleSelection | None = None) -> None:
        self.cache = cache
        self.forced = os.path.abspath(config) if config else None
        self.isolated = isolated
        self.selection = selection
        self._by_folder: dict[str, str | None] = {}
        self._files: dict[str, ConfigFile] = {}
        self._selected: dict[str | None, Settings] = {}
        self.default = Settings()

    def config_path(self, folder: str) -> str | None:
        if self.isolated:
            return None
        if self.forced:
            return self.forced
        folder = os.path.abspath(folder)
        pending = []
        found: str | None = None
        while True:
            if folder in self._by_folder:
                found = self._by_folder[folder]
                break
            here = config_in(folder)
            if here is not None:
                found = here
                self._by_folder[folder] = here
                break
            pending.append(folder)
            parent = os.path.dirname(folder)
            if parent == folder:
                break
            folder = parent
        for p in pending:
            self._by_folder[p] = found
        return found

    def file(self, path: str) -> ConfigFile:
        loaded = self._files.get(path)
        if loaded is None:
            loaded = self._files[path] = load_config(path, self.cache)
        return loaded

    def for_folder(self, folder: str) -> Settings:
        path = self.config_path(folder)
        settings = self.default if path is None else self.file(path).settings
        if self.selection is None:
            return settings
        selected = self._selected.get(path)
        if selected is None:
            selected = self._selected[path] = settings.with_selection(self.selection)
        return selected

    def for_file(self, path: str) -> Settings:
        """The settings of the file `path` (`-` and names of stdin: the working folder's)."""
        return self.for_folder(os.path.dirname(os.path.abspath(path)))

    @property
    def configs(self) -> list[ConfigFile]:
        """Every configuration file read so far, in the order they were read."""
        return list(self._files.values())
