"""Where the grammar and schema files are: inside the installed wheel (`scriptc/grammar`,
`scriptc/schemas`, put there by the build) or, in a source checkout, in the repository's
top-level `grammar/` and `schemas/`, which are the single sources of both."""

from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


@cache
def data_dir(kind: str) -> Path:
    """The folder holding `kind` ("grammar" or "schemas")."""
    for candidate in (_PACKAGE / kind, _PACKAGE.parent.parent / kind):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"scriptc is installed without its {kind}/ folder")


def grammar_path(name: str) -> Path:
    return data_dir("grammar") / name


def schema_path(name: str) -> Path:
    return data_dir("schemas") / name
