"""How scriptc names a file in what it prints: one rule for every output format and message,
however the command line named the file (`./x/y.script`, an absolute path, or a folder that
holds it).

- `shown_path`: the name for people, and for tools run where scriptc ran (the text, grouped
  and JSON formats, and every message): relative to the working folder when the file is
  inside it, else as it was named; either way normalised (`./a//b/../c.script` is
  `a/c.script`), as ruff names files.
- `repository_path`: the name for GitHub (annotations of `--format github`, the code-scanning
  alerts of `--format sarif`), which resolves a path against the repository's root and
  attaches nothing to a path that starts with `./`: relative to the repository root, with
  forward slashes. The root is the nearest folder at or above the file that holds `.git`;
  outside a git repository, the working folder. A file outside the root has no such name
  (None).

Names that are not paths (`-`, `<stdin>`) are kept as they are. This module imports only the
standard library.
"""

from __future__ import annotations

import os


def _not_a_path(name: str) -> bool:
    return name == "-" or name.startswith("<")


def _working_folder() -> str | None:
    try:
        return os.getcwd()
    except OSError:  # the working folder was deleted
        return None


def _inside(path: str, folder: str) -> str | None:
    """`path` (absolute) relative to `folder`, or None when it is not inside it."""
    try:
        relative = os.path.relpath(path, folder)
    except ValueError:  # another drive (Windows)
        return None
    if relative == os.pardir or relative.startswith(os.pardir + os.sep):
        return None
    return relative


def shown_path(path: str) -> str:
    """The name of a file in scriptc's output (see the module's docstring)."""
    if _not_a_path(path):
        return path
    here = _working_folder()
    if here is not None:
        relative = _inside(os.path.join(here, path), here)
        if relative is not None:
            return os.path.normpath(relative)
    return os.path.normpath(path)


def repository_root(folder: str) -> str | None:
    """The nearest folder at or above `folder` holding `.git` (a folder, or a file for a
    worktree or submodule), or None."""
    folder = os.path.abspath(folder)
    while True:
        if os.path.exists(os.path.join(folder, ".git")):
            return folder
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


def repository_path(path: str, roots: dict[str, str | None] | None = None) -> str | None:
    """`path` relative to its repository's root (see the module's docstring), with forward
    slashes; None for a file outside the root. Names that are not paths are kept. `roots`,
    when given, remembers the root of each folder across calls (a renderer's many files)."""
    if _not_a_path(path):
        return path
    absolute = os.path.abspath(path)
    folder = os.path.dirname(absolute)
    if roots is not None and folder in roots:
        root = roots[folder]
    else:
        root = repository_root(folder) or _working_folder()
        if roots is not None:
            roots[folder] = root
    if root is None:
        return None
    relative = _inside(absolute, root)
    # Forward slashes, and a backslash read as a separator whatever the system (a Windows
    # path given on another system), as GitHub reads paths.
    return None if relative is None else relative.replace(os.sep, "/").replace("\\", "/")


def same_file(a: str, b: str) -> bool:
    """Whether two names name the same file (existing or not); `-` (stdin, stdout) is no file.
    An output that is an input is refused by every verb that writes (nothing the user wrote
    is overwritten)."""
    if a == "-" or b == "-":
        return False
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)
