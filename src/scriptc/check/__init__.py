"""The semantic checks: what a script that parsed and lowered may still get wrong.

`check_script(script, source, functions=STANDARD)` runs every pass of `PASSES` over one
script and returns their diagnostics sorted by position. The driver calls it only when the
front end reported no error (a broken item would cascade into reports that are not the user's
mistake).

A pass is a function `pass(ctx: Context) -> list[Diagnostic]`, one module each. Passes report,
never transform; they share the tables of one `Context` (blocks in execution order, the label
table), built once per script. The order of `PASSES`, which is the order their findings are
produced before sorting:

1. `messages.check_messages`     M001-M005  rule messages and the mutex (thesis 4.4)
2. `labels.check_labels`         L001-L003  labels and goal ids
3. `flow.check_flow`             F001-F003  control flow between blocks
4. `values.check_values`         V003-V007  numbers in commands, messages and conditions
5. `conditions.check_conditions` R001-R009  the rule grammar against classes and functions
6. `audio.check_audio`           A001-A003  audio track paths
7. `safety.check_safety`         K001-K003  speeds, flashing LEDs and the governor's ramps
                                            (`ramps.py`) against the robot profile

Importing this package loads only the standard library, `scriptc.ir`/`scriptc.diagnostics`,
`scriptc.robot.profile` and `scriptc.robot.motion` (difflib is imported when a suggestion is
needed).
"""

from __future__ import annotations

from scriptc.check.audio import check_audio
from scriptc.check.conditions import check_conditions
from scriptc.check.context import Context
from scriptc.check.flow import check_flow
from scriptc.check.labels import check_labels
from scriptc.check.messages import check_messages
from scriptc.check.ranges import check_values
from scriptc.check.safety import check_safety
from scriptc.diagnostics.model import Diagnostic
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import Script
from scriptc.robot.profile import Profile
from scriptc.source import SourceFile, SourceKind

PASSES = (
    check_messages,
    check_labels,
    check_flow,
    check_values,
    check_conditions,
    check_audio,
    check_safety,
)

__all__ = ["PASSES", "Context", "check_script"]


def check_script(
    script: Script, source: SourceFile, *, functions: FunctionRegistry = STANDARD,
    profile: Profile | None = None, kind: SourceKind = SourceKind.SCRIPT,
) -> list[Diagnostic]:
    """Every diagnostic the semantic passes find in `script`, sorted by position. `profile`
    is the robot profile the safety pass checks against (None: the defaults); `kind` is the
    syntax of `source`, "script" or "json" (thesis JSON gets no fixes: they are edits in
    script syntax)."""
    ctx = Context(script, source, functions, profile, kind)
    diagnostics: list[Diagnostic] = []
    for check in PASSES:
        diagnostics.extend(check(ctx))
    diagnostics.sort(key=Diagnostic.sort_key)
    return diagnostics
