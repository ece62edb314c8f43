"""How a session loads a script it meets by path during a run (a `script_vect` update, an
override naming a file): through a `Loader` handed to it by its caller. The runtime declares
what it needs here and imports nothing above itself; `scriptc run` hands it
`scriptc.ops.programs.ProgramLoader`, which reads, checks and compiles the file as `run` does
for the files on its command line.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from scriptc.runtime.executor import Loadable

__all__ = ["LoadError", "Loader"]


class LoadError(Exception):
    """A script that cannot be loaded (a loader's failure: missing file, compile errors); the
    message says why, and the session reports it in the trace."""


class Loader(Protocol):
    """Loads the program of a script file by its absolute path, or raises LoadError."""

    def __call__(self, path: str) -> Loadable: ...
