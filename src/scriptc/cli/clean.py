"""`scriptc clean [PATH]`: remove the cache of the project PATH is in (default: the working
folder), the folder `scriptc lint PATH` uses (`--cache-dir`, `SCRIPTC_CACHE_DIR`, else
`.scriptc_cache` in the project's root), and any other `.scriptc_cache` folder below PATH (the
caches of sub-projects with their own configuration), as `ruff clean` does for its caches.

Only a folder that scriptc made is removed: one holding the `CACHEDIR.TAG` scriptc writes. A
`--cache-dir` pointing at anything else is refused, never emptied. Each folder removed is
named on stderr with what it held. Exit status: 0 (also when there was nothing to remove), 2 (a
folder that cannot be removed, or is not a cache of scriptc).
"""

from __future__ import annotations

import contextlib
import os
import shutil

import click

from scriptc.cli.common import CliError, write
from scriptc.project.cache import CACHE_DIR_NAME, CACHEDIR_TAG

# Folders never searched for sub-projects' caches.
_SKIPPED = frozenset({".git", ".hg", ".svn", ".venv", "node_modules", "__pycache__"})


def is_scriptc_cache(folder: str) -> bool:
    """Whether `folder` is a cache scriptc made (its CACHEDIR.TAG is scriptc's)."""
    try:
        with open(os.path.join(folder, "CACHEDIR.TAG"), encoding="utf-8") as f:
            return f.read() == CACHEDIR_TAG
    except (OSError, UnicodeDecodeError):
        return False


def _size(folder: str) -> tuple[int, int]:
    """How many files a folder holds (recursively), and their bytes."""
    files = size = 0
    for root, _dirs, names in os.walk(folder):
        for name in names:
            files += 1
            with contextlib.suppress(OSError):  # gone since the walk listed it: no bytes
                size += os.lstat(os.path.join(root, name)).st_size
    return files, size


def human_size(size: int) -> str:
    """`812 bytes`, `61.2 KB`, `3.0 MB`, `1.5 GB`: a size as people read it."""
    if size < 1024:
        return f"{size} bytes"
    scaled = float(size)
    for unit in ("KB", "MB"):
        scaled /= 1024
        if scaled < 1024:
            return f"{scaled:.1f} {unit}"
    return f"{scaled / 1024:.1f} GB"


def caches_below(path: str) -> list[str]:
    """The `.scriptc_cache` folders below `path` (links not followed)."""
    found = []
    for root, dirs, _names in os.walk(path):
        if CACHE_DIR_NAME in dirs:
            found.append(os.path.join(root, CACHE_DIR_NAME))
        dirs[:] = sorted(d for d in dirs if d not in _SKIPPED and d != CACHE_DIR_NAME
                         and not os.path.islink(os.path.join(root, d)))
    return found


@click.command("clean")
@click.argument("path", default=".", type=click.Path(exists=True, file_okay=False))
@click.option("--cache-dir", metavar="DIR", envvar="SCRIPTC_CACHE_DIR",
              type=click.Path(file_okay=False),
              help="The cache folder to remove, as given to `lint --cache-dir`.")
@click.pass_context
def command(ctx: click.Context, path: str, cache_dir: str | None) -> None:
    """Remove the cache folder of the project PATH is in (default: here), and the caches of
    sub-projects below PATH."""
    from scriptc.paths import shown_path
    from scriptc.project.cache import default_cache_dir
    from scriptc.project.config import project_root

    main = cache_dir or default_cache_dir(project_root(path))
    candidates = [main, *caches_below(path)]
    removed = refused = 0
    seen: set[str] = set()
    for folder in candidates:
        real = os.path.realpath(folder)
        if real in seen or not os.path.isdir(folder):
            continue
        seen.add(real)
        shown = shown_path(os.path.abspath(folder))
        if not is_scriptc_cache(folder):
            write(f"error: `{shown}` is not a cache of scriptc (it has no CACHEDIR.TAG "
                  "written by scriptc): not removed\n", err=True)
            refused += 1
            continue
        files, size = _size(folder)
        try:
            shutil.rmtree(folder)
        except OSError as exc:
            raise CliError(f"cannot remove `{shown}`: {exc.strerror or exc}") from None
        write(f"removed `{shown}` ({files} files, {human_size(size)})\n", err=True)
        removed += 1
    if not removed and not refused:
        write(f"nothing to remove: no cache at `{shown_path(os.path.abspath(main))}`\n",
              err=True)
    ctx.exit(2 if refused else 0)
