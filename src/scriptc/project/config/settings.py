"""The configuration as data: `Settings` (one configuration file, read and checked), the robot
profile, the user's functions and rules, and the policy that turns what the checks found into
what is reported (selection, per-file ignores, severity overrides).

Errors are not policy: a script with an error does not work on the robot, so `select`,
`ignore`, per-file ignores and severity overrides choose among warnings and info messages
only (docs/configuration.md, "Errors are always reported"). Selectors name a code (`F001`),
its name (`unreachable-block`), a prefix of codes (`F`, `F00`) or `ALL`; the most specific
matching selector decides, and `ignore` wins a tie with `select`, as in ruff.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from functools import cached_property
from typing import TYPE_CHECKING, Any, NamedTuple

from scriptc.diagnostics.model import Diagnostic, Severity
from scriptc.ir.builtins import Function, Param
from scriptc.robot.profile import DEFAULT_PROFILE, Profile

if TYPE_CHECKING:  # pathspec is imported for per-file ignores only
    from pathspec import GitIgnoreSpec

ALL = "ALL"
SEVERITIES = {"error": Severity.ERROR, "warning": Severity.WARNING, "info": Severity.INFO}


# ---------------------------------------------------------------------------------------------
# Selectors


def selector_specificity(selector: str, code: str, name: str) -> int | None:
    """How specifically `selector` names `code` (None: not at all). `ALL` is 0, a prefix its
    length, a whole code or its name 10."""
    if selector == ALL:
        return 0
    if selector.lower() == name:
        return 10
    upper = selector.upper()
    if code.startswith(upper):
        return 10 if upper == code else len(upper)
    return None


def selected_codes(selector: str, *, at_run_time: bool = False) -> list[str]:
    """The codes lint may report that a selector names (empty when it names none); with
    `at_run_time`, the run-time codes it names instead (family X: lint never reports them)."""
    from scriptc.diagnostics.codes import all_codes

    return [c.code for c in all_codes() if c.at_run_time == at_run_time
            and selector_specificity(selector, c.code, c.name) is not None]


def run_time_refusal(selector: str) -> str | None:
    """Why a selector that names no code lint reports is refused when it names run-time codes
    (None when it names none of those either)."""
    codes = selected_codes(selector, at_run_time=True)
    if not codes:
        return None
    shown = codes[0] if len(codes) == 1 else f"{codes[0]}..{codes[-1]}"
    return (f"`{selector}` names only run-time codes ({shown}), which lint never reports: they "
            "are in the trace of `scriptc run`")


def _best(selectors: Iterable[str], code: str, name: str) -> int | None:
    best = None
    for selector in selectors:
        s = selector_specificity(selector, code, name)
        if s is not None and (best is None or s > best):
            best = s
    return best


def _decide(selects: Iterable[str], ignores: Iterable[str], code: str, name: str
            ) -> bool | None:
    """Whether one layer of selectors reports `code`: the more specific selector wins and
    `ignore` wins a tie; None when the layer names the code in neither list."""
    chosen = _best(selects, code, name)
    dropped = _best(ignores, code, name)
    if chosen is None and dropped is None:
        return None
    return chosen is not None and (dropped is None or chosen > dropped)


class RuleSelection(NamedTuple):
    """A layer of rule selection over the configuration's (`scriptc lint --select`,
    `--extend-select`, `--ignore`), as ruff layers its command line over its configuration:
    `select` (when given) starts again from nothing, so the configuration's `select` and
    `ignore` no longer apply; `extend_select` adds codes and `ignore` drops codes over
    whatever the layer below reports. Within the layer, the more specific selector wins and
    `ignore` wins a tie. Errors stay reported whatever it says."""

    select: tuple[str, ...] | None = None
    extend_select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()

    def reports(self, below: bool, code: str, name: str) -> bool:
        """Whether `code` is reported, given whether the layer below reports it."""
        if self.select is not None:
            return bool(_decide((*self.select, *self.extend_select), self.ignore, code, name))
        decided = _decide(self.extend_select, self.ignore, code, name)
        return below if decided is None else decided


# ---------------------------------------------------------------------------------------------
# The parts of a configuration


# A Python object as `module:attribute` (`activity.functions:smiling`), dotted names of ASCII
# identifiers on both sides: what `implementation` holds (schemas/config.schema.json is written
# from it by `python -m scriptc.generate`).
IMPLEMENTATION_PATTERN = (r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*"
                          r":[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*")


class ImplementationError(Exception):
    """A declared implementation (`module:attr`) that cannot be imported."""


# What a repository's own Python code gives for a `module:attr` implementation (a function of
# the rule grammar, a rule): the runtime calls it as its kind says; nothing here can know more.
UserObject = Any


def import_implementation(spec: str, root: str) -> UserObject:
    """The object a `module:attr` implementation names, imported with `root` (the folder of
    the configuration) first on the import path. Raises ImplementationError."""
    import importlib
    import sys

    module_name, _, attribute = spec.partition(":")
    if not module_name or not attribute:
        raise ImplementationError(f"`{spec}` is not of the form `module:attribute`")
    if root not in sys.path:
        sys.path.insert(0, root)
    try:
        obj = importlib.import_module(module_name)
    except Exception as exc:  # the user's module may raise anything
        raise ImplementationError(f"cannot import `{module_name}` (for `{spec}`): "
                                  f"{type(exc).__name__}: {exc}") from exc
    for part in attribute.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise ImplementationError(f"`{module_name}` has no attribute `{attribute}` "
                                      f"(for `{spec}`)") from None
    return obj


class UserFunction(NamedTuple):
    """A function of the rule grammar declared by the repository (`[[functions]]`)."""

    name: str
    kind: str  # "B", "F" or "E"
    arity: int
    implementation: str  # "module:attr"
    params: tuple[str, ...] = ()
    doc: str = ""
    root: str = "."  # the folder of the configuration that declares it

    @property
    def signature(self) -> Function:
        """The signature the checks use (`scriptc.ir.builtins.Function`)."""
        names = self.params or tuple(f"arg{i + 1}" for i in range(self.arity))
        return Function(self.name, self.kind, tuple(Param(n, "") for n in names),
                        self.doc or f"declared in the configuration ({self.implementation})",
                        origin="config")

    def load(self) -> UserObject:
        """Import the implementation (only when asked: linting never does)."""
        return import_implementation(self.implementation, self.root)


class UserRule(NamedTuple):
    """A rule implemented by the repository (`[[rules]]`): the id alfa and omega messages
    name, its optional rulecode, and its implementation."""

    name: str
    implementation: str
    rulecode: int | None = None
    doc: str = ""
    root: str = "."

    def load(self) -> UserObject:
        return import_implementation(self.implementation, self.root)


# ---------------------------------------------------------------------------------------------
# Settings


class Settings:
    """One configuration, read and checked. `Settings()` is the default (no file).

    `path` is the configuration file (None for the default), `root` the folder its paths are
    relative to, `digest` a hash of its bytes (part of the cache key of every result), `robot`
    the robot profile (`[robot]` over the defaults: what the safety checks and the governor
    keep). A plain
    class rather than a dataclass: `scriptc lint` imports it on every run, and generating a
    dataclass's methods costs milliseconds of cold start. Treat it as immutable.
    """

    FIELDS = ("path", "root", "digest", "select", "ignore", "per_file_ignores", "severity",
              "exclude", "respect_gitignore", "audio_root", "robot", "functions", "rules",
              "selection")

    def __init__(self, path: str | None = None, root: str = ".", digest: str = "",
                 select: tuple[str, ...] = (ALL,), ignore: tuple[str, ...] = (),
                 per_file_ignores: tuple[tuple[str, tuple[str, ...]], ...] = (),
                 severity: tuple[tuple[str, str], ...] = (), exclude: tuple[str, ...] = (),
                 respect_gitignore: bool = True, audio_root: str = ".",
                 robot: Profile = DEFAULT_PROFILE, functions: tuple[UserFunction, ...] = (),
                 rules: tuple[UserRule, ...] = (),
                 selection: RuleSelection | None = None) -> None:
        self.path = path
        self.root = root
        self.digest = digest
        self.select = select
        self.ignore = ignore
        self.per_file_ignores = per_file_ignores
        self.severity = severity
        self.exclude = exclude
        self.respect_gitignore = respect_gitignore
        self.audio_root = audio_root
        self.robot = robot
        self.functions = functions
        self.rules = rules
        # The command line's layer of rule selection (`scriptc lint --select ...`), if any.
        self.selection = selection

    def with_selection(self, selection: RuleSelection | None) -> Settings:
        """These settings with the command line's rule selection over them."""
        values = {name: getattr(self, name) for name in self.FIELDS}
        values["selection"] = selection
        return Settings(**values)

    def _values(self) -> tuple[object, ...]:
        return tuple(getattr(self, name) for name in self.FIELDS)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Settings) and self._values() == other._values()

    def __hash__(self) -> int:
        return hash(self._values())

    def __repr__(self) -> str:
        return "Settings(" + ", ".join(f"{n}={getattr(self, n)!r}" for n in self.FIELDS) + ")"

    @property
    def audio_root_path(self) -> str:
        return os.path.normpath(os.path.join(self.root, self.audio_root))

    def function(self, name: str) -> UserFunction | None:
        return next((f for f in self.functions if f.name == name), None)

    def rule(self, name: str) -> UserRule | None:
        return next((r for r in self.rules if r.name == name), None)

    @cached_property
    def _table(self) -> dict[str, tuple[bool, Severity | None]]:
        """code -> (reported?, overridden severity) for every code lint may report."""
        from scriptc.diagnostics.codes import lint_codes

        table: dict[str, tuple[bool, Severity | None]] = {}
        overrides = [(selector, SEVERITIES[value]) for selector, value in self.severity
                     if value in SEVERITIES]
        for c in lint_codes():
            if c.severity is Severity.ERROR:
                table[c.code] = (True, None)
                continue
            reported = bool(_decide(self.select, self.ignore, c.code, c.name))
            if self.selection is not None:
                reported = self.selection.reports(reported, c.code, c.name)
            best, severity = None, None
            for selector, value in overrides:
                s = selector_specificity(selector, c.code, c.name)
                if s is not None and (best is None or s >= best):
                    best, severity = s, value
            table[c.code] = (reported, severity if severity is not c.severity else None)
        return table

    def policy(self) -> dict[str, tuple[bool, Severity]]:
        """code -> (whether it is reported, the severity it is reported with), for every code
        lint may report, before per-file ignores (`scriptc show-settings`)."""
        from scriptc.diagnostics.codes import lint_codes

        table = self._table
        return {c.code: (table[c.code][0], table[c.code][1] or c.severity) for c in lint_codes()}

    @cached_property
    def _per_file(self) -> list[tuple[GitIgnoreSpec, tuple[str, ...]]]:
        import pathspec

        out: list[tuple[GitIgnoreSpec, tuple[str, ...]]] = []
        for pattern, selectors in self.per_file_ignores:
            try:
                spec = pathspec.GitIgnoreSpec.from_lines([pattern])
            except Exception:  # reported by validation (C002)
                continue
            out.append((spec, selectors))
        return out

    def relative(self, path: str) -> str | None:
        """`path` relative to the root with forward slashes, or None outside it."""
        try:
            rel = os.path.relpath(os.path.abspath(path), os.path.abspath(self.root))
        except ValueError:
            return None
        if rel == ".." or rel.startswith(".." + os.sep):
            return None
        return rel.replace(os.sep, "/")

    def ignored_here(self, path: str | None) -> tuple[str, ...]:
        """The per-file-ignores selectors that apply to `path`."""
        if not self.per_file_ignores or path is None:
            return ()
        rel = self.relative(path)
        if rel is None:
            return ()
        out: list[str] = []
        for spec, selectors in self._per_file:
            if spec.match_file(rel):
                out.extend(selectors)
        return tuple(out)

    def apply(self, diagnostics: Sequence[Diagnostic], path: str | None = None
              ) -> list[Diagnostic]:
        """What is reported of `diagnostics` (of the file `path`): unselected and ignored
        warnings and infos dropped, severities overridden. Errors pass unchanged."""
        if self.select == (ALL,) and not self.ignore and not self.severity and \
                not self.per_file_ignores and self.selection is None:
            return list(diagnostics)
        table = self._table
        here = self.ignored_here(path)
        out: list[Diagnostic] = []
        for d in diagnostics:
            reported, severity = table.get(d.code, (True, None))
            if d.severity is Severity.ERROR:
                out.append(d)
                continue
            if not reported:
                continue
            if here:
                from scriptc.diagnostics.codes import lookup

                name = lookup(d.code).name
                if _best(here, d.code, name) is not None:
                    continue
            if severity is not None and severity is not d.severity:
                import dataclasses

                out.append(dataclasses.replace(d, severity=severity))
            else:
                out.append(d)
        return out
