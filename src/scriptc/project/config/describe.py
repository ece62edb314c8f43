"""The configuration one file gets, setting by setting, with where each value comes from
(`scriptc show-settings FILE`): the configuration file and the line of the key, or the
default. Configurations do not merge, so a value comes from the one file that applies or is
the default; a value the checks rejected is the default too, and says so.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from scriptc.diagnostics.model import Diagnostic, Severity
from scriptc.paths import shown_path
from scriptc.project.config.load import Resolver, project_root
from scriptc.project.config.settings import Settings
from scriptc.project.config.tomlpos import KeySpans, TOMLValue
from scriptc.robot.limits import LIMITS
from scriptc.source import SourceFile


@dataclass(frozen=True)
class Origin:
    """Where a value is written: a configuration file (as shown to people), line and column."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


@dataclass(frozen=True)
class Setting:
    """One setting: its key as written in `scriptc.toml` (`lint.select`), the value in force,
    and its origin (None: the default). `rejected`: the key is written but an error in its
    value left (some of) it at the default."""

    key: str
    value: TOMLValue  # as the configuration writes it (a list, a table, ...)
    origin: Origin | None = None
    rejected: bool = False


@dataclass
class SettingsReport:
    """What `describe` finds for one file."""

    file: str
    configuration: str | None  # the configuration file as shown, None for the defaults
    root: str  # the folder paths in the configuration are relative to
    cache_dir: str
    settings: list[Setting] = field(default_factory=list)
    codes: dict[str, tuple[bool, Severity]] = field(default_factory=dict)
    ignored_here: tuple[str, ...] = ()
    problems: list[Diagnostic] = field(default_factory=list)
    source: SourceFile | None = None  # the configuration, for showing its problems


def _values(settings: Settings) -> list[tuple[tuple[str, ...], TOMLValue]]:
    """(key path, value in force) of every setting, in the order docs/configuration.md has."""
    limits = settings.robot.limits()
    rows: list[tuple[tuple[str, ...], TOMLValue]] = [
        (("audio-root",), settings.audio_root),
        (("exclude",), list(settings.exclude)),
        (("respect-gitignore",), settings.respect_gitignore),
        (("lint", "select"), list(settings.select)),
        (("lint", "ignore"), list(settings.ignore)),
        (("lint", "per-file-ignores"), {pattern: list(codes)
                                        for pattern, codes in settings.per_file_ignores}),
        (("lint", "severity"), dict(settings.severity)),
    ]
    rows += [(("robot", limit.key), limits[limit.field]) for limit in LIMITS]
    rows.append((("functions",), [{"name": f.name, "kind": f.kind, "arity": f.arity,
                                   "implementation": f.implementation}
                                  for f in settings.functions]))
    rows.append((("rules",), [{"name": r.name, "rulecode": r.rulecode,
                               "implementation": r.implementation} for r in settings.rules]))
    return rows


def describe(path: str, *, config: str | None = None, isolated: bool = False
             ) -> SettingsReport:
    """The settings of the file (or folder) `path`, as `scriptc lint` would apply them, with
    the origin of each (`config` and `isolated` as `lint --config` and `--isolated`)."""
    from scriptc.project.cache import default_cache_dir

    resolver = Resolver(config=config, isolated=isolated)
    folder = path if os.path.isdir(path) else os.path.dirname(os.path.abspath(path))
    config_path = resolver.config_path(folder)
    settings = resolver.for_folder(folder)
    report = SettingsReport(
        file=path,
        configuration=None if config_path is None else shown_path(config_path),
        root=shown_path(os.path.abspath(settings.root)) if config_path else ".",
        cache_dir=shown_path(os.path.abspath(default_cache_dir(
            project_root(path, config=config, isolated=isolated)))),
        codes=settings.policy(),
        ignored_here=settings.ignored_here(path),
    )
    # the configuration's key positions, its text and its name as shown
    located: tuple[KeySpans, SourceFile, str] | None = None
    prefix: tuple[str, ...] = ()
    errors: list[Diagnostic] = []
    if config_path is not None:
        from scriptc.project.config.tomlpos import locate

        loaded = resolver.file(config_path)
        report.problems = list(loaded.diagnostics)
        report.source = loaded.source
        located = (locate(loaded.source.text), loaded.source, shown_path(config_path))
        if os.path.basename(config_path) == "pyproject.toml":
            prefix = ("tool", "scriptc")
        errors = [d for d in loaded.diagnostics if d.severity is Severity.ERROR]
    for key_path, value in _values(settings):
        origin, rejected = None, False
        if located is not None:
            positions, source, shown = located
            span = positions.key(prefix + key_path)
            if span is not None:
                position = source.position(span.start)
                origin = Origin(shown, position.line, position.column)
                whole = positions.find(prefix + key_path)
                rejected = any(whole.start <= d.span.start < max(whole.end, whole.start + 1)
                               for d in errors)
        report.settings.append(Setting(".".join(key_path), value, origin, rejected))
    return report
