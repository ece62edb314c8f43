"""What follows the front end, for every caller alike: the semantic checks, sorting, and the
script's own suppression comments. The driver (CLI) and the language server's incremental
analysis (`scriptc.ide`) both finish an analysis here, so an editor shows exactly what
`scriptc lint` prints.
"""

from __future__ import annotations

from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.source import SourceFile


def finish(source: SourceFile, script: Script | None, front: list[Diagnostic], *,
           functions: FunctionRegistry = STANDARD, kind: str = "script", profile=None
           ) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """The diagnostics of a lowered script (sorted by position) and those its suppression
    comments hid. `front` are the front end's; `kind` is "script" or "json" (JSON has no
    comments, so no suppressions); `profile` is the robot profile of the safety checks."""
    diagnostics = list(front)
    # Semantic checks run on a script whose front end reported no error: a broken item would
    # otherwise cascade into reports about labels and flow that are not the user's mistake
    # (docs/language.md, "Error recovery").
    checked = script is not None and not has_errors(front)
    if checked:
        from scriptc.check import check_script

        diagnostics.extend(check_script(script, source, functions=functions, profile=profile,
                                        kind=kind))
    diagnostics.sort(key=Diagnostic.sort_key)
    suppressed: list[Diagnostic] = []
    # Suppression comments are part of the script; one substring search when there are none.
    if kind == "script" and "scriptc:" in source.text:
        from scriptc.analysis.suppress import apply_suppressions

        diagnostics, suppressed = apply_suppressions(source, diagnostics, checked=checked)
    return diagnostics, suppressed
