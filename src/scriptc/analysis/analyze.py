"""Analysing one source: the front end of its kind (script syntax or thesis JSON), then, for
every caller alike, the semantic checks, sorting, and the script's own suppression comments
(`finish`). `scriptc lint`, `compile`, `run`, the Python API and the language server's
incremental analysis (`scriptc.ide.incremental`, which runs its own front end and then
`finish`) all end here, so an editor shows exactly what `scriptc lint` prints.

`Analysis` is the one result type: a source, the script read from it and its diagnostics.
What a caller adds is a subclass that keeps these fields (`ops.lint.FileReport`: the path,
the cache and the fixes; `api.Built`: the JSON and bytecode;
`ide.incremental.IncrementalAnalysis`: the scan and the parsed items).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from scriptc.analysis.read import decode_source, read_bytes
from scriptc.diagnostics.model import Diagnostic, Severity, has_errors
from scriptc.gcpause import gc_paused
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.source import SourceFile, SourceKind

if TYPE_CHECKING:  # types only: a lint whose results are cached never needs the IR's nodes
    from scriptc.ir.nodes import Script
    from scriptc.robot.profile import Profile

__all__ = ["Analysis", "analyze_bytes", "analyze_file", "analyze_json", "analyze_script",
           "analyze_source", "finish"]


class Analysis:
    """A source, the script read from it (None when it could not be read at all) and every
    diagnostic about it, sorted by position. `suppressed` holds what the script's suppression
    comments hid (`scriptc.analysis.suppress`; never an error).

    A plain class, not a dataclass: `scriptc lint` imports it on every run, and generating
    a dataclass's methods costs milliseconds of its cold start."""

    __slots__ = ("diagnostics", "script", "source", "suppressed")

    def __init__(self, source: SourceFile, script: Script | None,
                 diagnostics: list[Diagnostic] | None = None,
                 suppressed: list[Diagnostic] | None = None) -> None:
        self.source = source
        self.script = script
        self.diagnostics = [] if diagnostics is None else diagnostics
        self.suppressed = [] if suppressed is None else suppressed

    def __repr__(self) -> str:
        return (f"{type(self).__name__}({self.source.path!r}, "
                f"{len(self.diagnostics)} diagnostics)")

    @property
    def ok(self) -> bool:
        """True when the script was read and no diagnostic is an error."""
        return self.script is not None and not has_errors(self.diagnostics)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def codes(self) -> list[str]:
        return [d.code for d in self.diagnostics]


def finish(source: SourceFile, script: Script | None, front: list[Diagnostic], *,
           functions: FunctionRegistry = STANDARD, kind: SourceKind = SourceKind.SCRIPT,
           profile: Profile | None = None) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """The diagnostics of a lowered script (sorted by position) and those its suppression
    comments hid. `front` are the front end's; `kind` is the source's (JSON has no comments,
    so no suppressions); `profile` is the robot profile of the safety checks."""
    diagnostics = list(front)
    # Semantic checks run on a script whose front end reported no error: a broken item would
    # otherwise cascade into reports about labels and flow that are not the user's mistake
    # (docs/language.md, "Error recovery").
    checked = False
    if script is not None and not has_errors(front):
        from scriptc.check import check_script

        checked = True
        diagnostics.extend(check_script(script, source, functions=functions, profile=profile,
                                        kind=kind))
    diagnostics.sort(key=Diagnostic.sort_key)
    suppressed: list[Diagnostic] = []
    # Suppression comments are part of the script; one substring search when there are none.
    if kind == SourceKind.SCRIPT and "scriptc:" in source.text:
        from scriptc.analysis.suppress import apply_suppressions

        diagnostics, suppressed = apply_suppressions(source, diagnostics, checked=checked)
    return diagnostics, suppressed


# The front end of each kind of source that is analysed: module and function turning a
# SourceFile into a Script (or None) and the front end's diagnostics. Imported on first use.
_FRONT_ENDS = {
    SourceKind.SCRIPT: ("scriptc.frontend.script", "lower_script"),
    SourceKind.JSON: ("scriptc.frontend.thesis_json", "script_from_json"),
}


def analyze_source(source: SourceFile, kind: SourceKind = SourceKind.SCRIPT,
                   functions: FunctionRegistry = STANDARD,
                   profile: Profile | None = None) -> Analysis:
    """Read `source` with the front end of its kind, then `finish` (bytecode is not analysed:
    it is decoded and verified, `scriptc.bytecode`)."""
    import importlib

    kind = SourceKind(kind)
    if kind not in _FRONT_ENDS:
        raise ValueError(f"a source of kind {kind!r} is not analysed")
    module, function = _FRONT_ENDS[kind]
    front_end = getattr(importlib.import_module(module), function)
    with gc_paused():
        script, front = front_end(source)
        return Analysis(source, script, *finish(source, script, front, functions=functions,
                                                kind=kind, profile=profile))


def analyze_script(source: SourceFile, functions: FunctionRegistry = STANDARD,
                   profile: Profile | None = None) -> Analysis:
    """Parse, lower and check script syntax."""
    return analyze_source(source, SourceKind.SCRIPT, functions, profile)


def analyze_json(source: SourceFile, functions: FunctionRegistry = STANDARD,
                 profile: Profile | None = None) -> Analysis:
    """Read thesis JSON (schema, then IR) and run the same checks as for script syntax."""
    return analyze_source(source, SourceKind.JSON, functions, profile)


def analyze_bytes(name: str, data: bytes, kind: SourceKind = SourceKind.SCRIPT,
                  functions: FunctionRegistry = STANDARD,
                  profile: Profile | None = None) -> Analysis:
    """Decode (`scriptc.analysis.read.decode_source`) and analyse one file's bytes, shown as
    `name`. Undecodable content gives an Analysis with no script and P007."""
    source, problem = decode_source(name, data)
    if problem is not None:
        return Analysis(source, None, [problem])
    return analyze_source(source, kind, functions, profile)


def analyze_file(path: str | os.PathLike[str], kind: SourceKind = SourceKind.SCRIPT,
                 name: str | None = None,
                 functions: FunctionRegistry = STANDARD,
                 profile: Profile | None = None) -> Analysis:
    """Read and analyse one file, shown as `name` (`path` by default); raises
    `scriptc.analysis.read.ReadError` when it cannot be read."""
    return analyze_bytes(name if name is not None else os.fspath(path), read_bytes(path), kind,
                         functions, profile)
