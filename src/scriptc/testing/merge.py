"""`scriptc merge OUTPUT INPUT...` as a library call: the outputs of the shards of a test run,
merged into one (docs/testing.md, "Merging the shards' outputs").

What is merged is said by the OUTPUT's name (its suffix), and where one suffix fits several
kinds, by what the inputs hold: `KINDS` is the table of what `scriptc merge` knows, a kind a
row. A new kind of output is a new row: the suffixes of the files it writes, how to recognise
an input it reads, and how to merge the inputs' contents into the output's text. Without a
suffix to go by (OUTPUT `-`, stdout), the inputs' contents decide alone.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from scriptc.testing import coverage, junit

__all__ = ["KINDS", "Input", "Kind", "MergeError", "kind_for", "merge_files", "read_inputs"]

# An input: its name as given, and its content.
Input = tuple[str, bytes]


class MergeError(Exception):
    """Nothing can be merged: an input missing or of another kind, an output whose kind is
    unknown. The message names the file and says what to do."""


@dataclass(frozen=True)
class Kind:
    """A kind of output `scriptc merge` writes: its `name` for people, the `suffixes` of the
    files it writes, whether an input's content is one it `reads`, and how it `merges` inputs
    into the output's text and notes for the person merging (raising ValueError, naming the
    input, for one it cannot read)."""

    name: str
    suffixes: tuple[str, ...]
    reads: Callable[[bytes], bool]
    merges: Callable[[Sequence[Input]], tuple[str, list[str]]]


KINDS: tuple[Kind, ...] = (
    Kind("JUnit XML", (".xml",), junit.is_junit, junit.merge),
    Kind("scriptc coverage data", (".json",), coverage.is_data, coverage.merge_data),
    Kind("LCOV tracefile (from scriptc coverage data)", (".info", ".lcov"), coverage.is_data,
         coverage.merge_lcov),
)


def _described() -> str:
    return ", ".join(f"{' or '.join(k.suffixes)} ({k.name})" for k in KINDS)


def kind_for(output: str, inputs: Sequence[Input]) -> Kind:
    """The kind `output` is to be: among those its suffix names (any, for `-`), the first that
    reads every input."""
    if output == "-":
        candidates = list(KINDS)
    else:
        name = os.path.basename(output).lower()
        candidates = [k for k in KINDS if name.endswith(k.suffixes)]
        if not candidates:
            raise MergeError(f"`{output}`: scriptc merge cannot tell what to write by this "
                             f"name: end it with {_described()}")
    for kind in candidates:
        if all(kind.reads(data) for _name, data in inputs):
            return kind
    closest = max(candidates, key=lambda k: sum(k.reads(data) for _name, data in inputs))
    stranger = next(name for name, data in inputs if not closest.reads(data))
    target = "" if output == "-" else f" (what `{output}` is to be)"
    raise MergeError(f"`{stranger}` is not a {closest.name} file{target}: merge files of "
                     "one kind")


def read_inputs(paths: Sequence[str]) -> list[Input]:
    """The contents of the inputs, each read whole; one that cannot be read is a MergeError."""
    inputs = []
    for path in paths:
        try:
            with open(path, "rb") as f:
                inputs.append((path, f.read()))
        except FileNotFoundError:
            raise MergeError(f"`{path}` does not exist") from None
        except IsADirectoryError:
            raise MergeError(f"`{path}` is a folder: name the files to merge") from None
        except OSError as exc:
            raise MergeError(f"cannot read `{path}`: {exc.strerror or exc}") from None
    return inputs


def merge_files(output: str, paths: Sequence[str]) -> tuple[Kind, str, list[str]]:
    """Read the inputs, choose the output's kind and merge them: the kind, and the text to
    write with the notes for the person merging."""
    inputs = read_inputs(paths)
    kind = kind_for(output, inputs)
    try:
        text, notes = kind.merges(inputs)
    except ValueError as exc:
        raise MergeError(str(exc)) from None
    return kind, text, notes
