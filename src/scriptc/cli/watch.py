"""`scriptc lint --watch`: lint, then lint again whenever a script, a configuration file or a
`.gitignore` under the paths changes, until Ctrl-C (status 130, as a shell counts a process
ended by SIGINT; ruff's `--watch` ends the same way).

The watching is watchfiles' (the Rust `notify` library: inotify on Linux, FSEvents on macOS,
ReadDirectoryChangesW on Windows), imported here only, so `scriptc lint` without `--watch`
does not pay for it. Each round is a whole `lint` run: unchanged files come from the cache, so
a round costs about what the changed files cost.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Collection

from scriptc.cli.common import CliError, write
from scriptc.project.cache import CACHE_DIR_NAME

# Besides scripts, the files whose change changes what lint reports.
WATCHED_NAMES = frozenset({"scriptc.toml", "pyproject.toml", ".gitignore"})

# How often (ms) the watcher wakes with nothing to report: the first wake-up says that it is
# watching (a change from then on is seen), and Ctrl-C is noticed between wake-ups.
WAKE_MS = 250


def _inside(path: str, folder: str) -> list[str] | None:
    """The parts of `path` below `folder`, or None when it is not below it."""
    prefix = folder.rstrip(os.sep) + os.sep
    return path[len(prefix):].split(os.sep) if path.startswith(prefix) else None


class Watched:
    """What `lint --watch PATH...` watches and which changes count.

    A file is watched through its folder: a file replaced by an atomic save (a new file renamed
    over it, as editors and `--fix` do) is a new file, and a watch on the old one would see
    nothing after the first save. So the folders watched (recursively) are the folders given,
    the folder of each file given and the folder of the configuration that applies to each
    path; a change counts when it is to a file given, to a `*.script` file inside a folder
    given, or to a configuration file or `.gitignore`, and not inside a hidden folder (the
    cache, `.git`) or a hidden file (the temporary file of an atomic write)."""

    def __init__(self, paths: tuple[str, ...]) -> None:
        from scriptc.project.config import find_config

        self.folders = {os.path.abspath(p) for p in paths if os.path.isdir(p)}
        self.files = frozenset(os.path.abspath(p) for p in paths if not os.path.isdir(p))
        watched = set(self.folders) | {os.path.dirname(f) for f in self.files}
        for path in paths:
            config = find_config(path)
            if config is not None:
                watched.add(os.path.dirname(config))
        ordered = sorted(watched)
        # A folder inside another is watched through it already.
        self.targets = [t for t in ordered if not any(_inside(t, o) for o in ordered)]

    def relevant(self, path: str) -> bool:
        """Whether a change to `path` (absolute) can change what lint reports."""
        if path in self.files:
            return True
        name = os.path.basename(path)
        folders: Collection[str]
        if name in WATCHED_NAMES:
            folders = self.targets
        elif name.endswith(".script"):
            folders = self.folders
        else:
            return False
        for folder in folders:
            parts = _inside(path, folder)
            if parts is not None:
                return not any((part.startswith(".") and part != ".gitignore") or
                               part == CACHE_DIR_NAME for part in parts)
        return False


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def watch(paths: tuple[str, ...], lint_once: Callable[[], int], *, clear: bool = False) -> int:
    """Run `lint_once` now and after every relevant change; return 130 at Ctrl-C."""
    try:
        import watchfiles
    except ImportError:  # a broken installation: watchfiles is a dependency
        raise CliError("--watch needs the watchfiles package: pip install watchfiles") from None

    watched = Watched(paths)

    def keep(_change, path: str) -> bool:
        return watched.relevant(os.path.abspath(path))

    rounds = 0
    try:
        # The watcher is set up before the first lint, so a change made while it runs is
        # seen: the first wake-up (a timeout) starts the first round.
        for changes in watchfiles.watch(*watched.targets, watch_filter=keep, step=50,
                                        rust_timeout=WAKE_MS, yield_on_timeout=True,
                                        raise_interrupt=True, ignore_permission_denied=True):
            if rounds and not changes:
                continue
            if rounds and clear and _is_terminal(sys.stdout):
                write("\x1b[2J\x1b[H")  # a clean screen for each round, as ruff does
            rounds += 1
            lint_once()
            write(f"[{time.strftime('%H:%M:%S')}] watching for changes "
                  "(Ctrl-C stops)\n", err=True)
    except KeyboardInterrupt:
        pass
    except OSError as exc:  # no watcher here (inotify's limit reached, say)
        raise CliError(f"cannot watch the files: {exc.strerror or exc}") from None
    sys.stderr.flush()
    return 130
