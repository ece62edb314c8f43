"""Finding the script files of a folder for `scriptc lint DIR`: a walk that skips hidden files
and folders, what `.gitignore` files ignore, and what the configuration excludes; and the
files a run of `lint`, `check` or `fmt` reads from its command line's paths (`discover`).

The .gitignore rules are git's (matched by `pathspec`, whose GitIgnoreSpec follows git's
behaviour): every `.gitignore` from the repository's root down to the file applies, with
patterns relative to the folder holding it; a deeper file's decision (a match, or a `!`
negation) wins over a shallower one's, and within one file the last matching pattern wins;
patterns ending in `/` match folders only; a pattern with a `/` before its end is anchored to
its folder; a folder that is ignored is not entered, so nothing inside it can be brought back
(git's rule too). `.git/info/exclude` applies as a `.gitignore` at the repository root. The
repository's root is the nearest folder above holding `.git`; outside a repository, the
.gitignore files from the walked folder down still apply.

A configuration's `exclude` patterns (.gitignore syntax, relative to its folder) apply to the
folders each configuration governs; `respect-gitignore = false` turns .gitignore off there.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING

from scriptc.encoding import without_bom
from scriptc.paths import repository_root, shown_path
from scriptc.source import SourceKind

if TYPE_CHECKING:  # pathspec and the configuration are imported when they are needed
    from pathspec import GitIgnoreSpec

    from scriptc.project.config.load import Resolver
    from scriptc.project.config.settings import Settings

SCRIPT_SUFFIX = ".script"

# A compiled .gitignore: (absolute folder with a trailing separator, GitIgnoreSpec).
_Spec = tuple[str, "GitIgnoreSpec"]


def _compile(lines: list[str]) -> GitIgnoreSpec | None:
    import pathspec

    lines = [line for line in lines if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        return None
    try:
        return pathspec.GitIgnoreSpec.from_lines(lines)
    except Exception:  # a broken .gitignore is git's business, not ours
        return None


def _read_ignore_file(path: str) -> GitIgnoreSpec | None:
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return _compile(f.read().splitlines())
    except OSError:
        return None


def _decide(specs: list[_Spec], path: str, is_dir: bool) -> bool:
    """Whether the .gitignore specs (shallowest first) ignore the absolute `path`."""
    for base, spec in reversed(specs):
        if not path.startswith(base):
            continue
        rel = path[len(base):].replace(os.sep, "/")
        if is_dir:
            rel += "/"
        result = spec.check_file(rel)
        if result.include is not None:
            return bool(result.include)
    return False


def unreadable(shown: str, exc: OSError, folder: bool = True) -> str:
    """The message for a folder (or an entry of one) the walk cannot read: its scripts would
    be missed, so it is an error, as an unreadable file is."""
    reason = "permission denied" if isinstance(exc, PermissionError) else \
        (exc.strerror or str(exc)).lower()
    if folder:
        return (f"cannot read the folder `{shown_path(shown)}`: {reason}; the scripts in it "
                "were not checked (make it readable, or exclude it in the configuration)")
    return (f"cannot read `{shown_path(shown)}`: {reason}; it was not checked (make it "
            "readable, or exclude it in the configuration)")


class Walker:
    """Walks folders for scripts. `settings_for(folder)` gives the `Settings` of a folder
    (exclusions and `respect-gitignore`); without it nothing but hidden files is skipped.
    `accept(path)`, when given, has the last word on a file with the suffix (`scriptc check
    DIR` keeps the JSON files that are scripts). A folder that cannot be read is never skipped
    silently: `problems` names it, and the walk goes on."""

    def __init__(self, settings_for: Callable[[str], Settings] | None = None,
                 suffix: str = SCRIPT_SUFFIX, accept: Callable[[str], bool] | None = None
                 ) -> None:
        self.settings_for = settings_for
        self.suffix = suffix
        self.accept = accept
        self.problems: list[str] = []
        self._excludes: dict[int, _Spec | None] = {}

    def _exclude(self, settings: Settings) -> _Spec | None:
        key = id(settings)
        if key not in self._excludes:
            spec = _compile(list(settings.exclude)) if settings.exclude else None
            root = os.path.join(os.path.abspath(settings.root), "")
            self._excludes[key] = (root, spec) if spec is not None else None
        return self._excludes[key]

    def excluded(self, path: str, is_dir: bool, settings: Settings | None = None) -> bool:
        """Whether the configuration excludes `path` (absolute)."""
        if settings is None:
            if self.settings_for is None:
                return False
            settings = self.settings_for(os.path.dirname(path))
        exclude = self._exclude(settings)
        return exclude is not None and _decide([exclude], path, is_dir)

    def _respect(self, folder: str) -> bool:
        return self.settings_for is None or self.settings_for(folder).respect_gitignore

    def walk(self, top: str) -> list[str]:
        """The script files under `top`, sorted, as paths starting with `top`."""
        top_abs = os.path.abspath(top)
        specs: list[_Spec] = []
        repo = repository_root(top_abs)
        if repo is not None and self._respect(top_abs):
            spec = _read_ignore_file(os.path.join(repo, ".git", "info", "exclude"))
            if spec is not None:
                specs.append((os.path.join(repo, ""), spec))
            # The .gitignore files of the folders above `top`, from the repository's root.
            above = []
            folder = os.path.dirname(top_abs)
            while len(folder) >= len(repo) and folder.startswith(repo):
                above.append(folder)
                if folder == repo:
                    break
                folder = os.path.dirname(folder)
            for folder in reversed(above):
                spec = _read_ignore_file(os.path.join(folder, ".gitignore"))
                if spec is not None:
                    specs.append((os.path.join(folder, ""), spec))
        found: list[str] = []
        # Depth-first without recursion: (absolute folder, shown folder, specs that apply).
        stack: list[tuple[str, str, list[_Spec]]] = [(top_abs, top, specs)]
        while stack:
            folder, shown, inherited = stack.pop()
            settings = self.settings_for(folder) if self.settings_for is not None else None
            respect = settings is None or settings.respect_gitignore
            here = inherited
            if respect:
                spec = _read_ignore_file(os.path.join(folder, ".gitignore"))
                if spec is not None:
                    here = [*inherited, (os.path.join(folder, ""), spec)]
            try:
                entries = list(os.scandir(folder))
            except OSError as exc:
                self.problems.append(unreadable(shown, exc))
                continue
            for entry in entries:
                name = entry.name
                if name.startswith("."):
                    continue
                try:
                    # Symbolic links to folders are not followed (as os.walk does not): a link
                    # back up the tree would never end.
                    is_dir = entry.is_dir(follow_symlinks=False)
                    if not is_dir and entry.is_symlink() and entry.is_dir():
                        continue
                except FileNotFoundError:
                    continue  # removed while the folder was read: nothing left to check
                except OSError as exc:
                    self.problems.append(unreadable(os.path.join(shown, name), exc, False))
                    continue
                if not is_dir and not name.endswith(self.suffix):
                    continue
                path = entry.path
                if respect and here and _decide(here, path, is_dir):
                    continue
                if settings is not None and self.excluded(path, is_dir, settings):
                    continue
                if is_dir:
                    stack.append((path, os.path.join(shown, name), here))
                elif self.accept is None or self.accept(path):
                    found.append(os.path.join(shown, name))
        found.sort()
        return found


def discover(paths: list[str] | tuple[str, ...], kind: SourceKind = SourceKind.SCRIPT, *,
             resolver: Resolver | None = None, force_exclude: bool = False,
             suffix: str | None = None) -> tuple[list[str], list[str]]:
    """The files `scriptc lint PATH...`, `scriptc check PATH...` and `scriptc fmt PATH...`
    read, in order, and the problems met finding them. A file named on the command line is
    read whatever its suffix; a folder contributes its `*.script` files (for thesis JSON:
    its `.json` files that are thesis scripts, `is_thesis_json`), recursively and sorted,
    skipping hidden files and folders, what .gitignore files ignore and what the
    configuration (`resolver`, a `scriptc.project.config.Resolver`) excludes; `-` (stdin) is
    kept; a file reached twice is read once. A path that does not exist and a folder that
    cannot be read are problems, each named, and the other paths go on. With
    `force_exclude` the configuration's `exclude` applies to files named on the command line
    too (for pre-commit, which names every changed file). `suffix` is that of the files a
    folder contributes instead (`.test.toml` for `scriptc test`)."""
    json = kind == SourceKind.JSON
    walker = Walker(resolver.for_folder if resolver is not None else None,
                    suffix=suffix or (".json" if json else SCRIPT_SUFFIX),
                    accept=is_thesis_json if json and suffix is None else None)
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
        with open(path, "rb") as f:
            data = without_bom(f.read())
    except OSError:
        return True
    try:
        value = json.loads(data)
    except (ValueError, RecursionError):
        return b'"activityname"' in data
    return isinstance(value, dict) and "activityname" in value
