"""Pass 2, labels and goal ids (docs/language.md): non-empty labels are unique (L001),
goal ids are unique (L002), and every jump target names a label of the same script (L003).
"""

from __future__ import annotations

from scriptc.check.context import Context, closest, suggestion
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Label
from scriptc.ir.nodes import Name

# Suggestions cost a difflib scan over every label; past this many distinct unknown targets
# (a script generated wrongly, say) the rest get no suggestion, so the pass stays linear.
_MAX_SUGGESTIONS = 64


def check_labels(ctx: Context) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    table = ctx.labels
    for later, first in table.duplicates:
        out.append(
            diagnostic(
                "L001",
                f"the label `{later.text}` is defined more than once",
                later.span,
                labels=(Label(first.span, f"`{first.text}` first defined here"),),
                notes=("jumps to it go to the first block that carries it",),
                help="rename one of the labels, or leave this one empty (`b##`)",
            )
        )

    seen: dict[str, Name] = {}
    for goal in ctx.script.goals:
        gid = goal.id
        if not gid.text:
            continue
        first_use = seen.get(gid.text)
        if first_use is None:
            seen[gid.text] = gid
            continue
        out.append(
            diagnostic(
                "L002",
                f"the goal id `{gid.text}` is used by more than one goal",
                gid.span,
                labels=(Label(first_use.span, f"`{first_use.text}` first used here"),),
                notes=(("the map records goals as reached, interrupted or failed by id, so two "
                        "goals with one id cannot be told apart"),),
                help="give each goal its own id",
            )
        )

    suggestions: dict[str, str | None] = {}
    for _, jump in ctx.jumps:
        for target in (jump.true_target, jump.false_target):
            if target is None or not target.text or target.text in table.index:
                continue
            if target.text not in suggestions and len(suggestions) < _MAX_SUGGESTIONS:
                suggestions[target.text] = closest(target.text, table.index)
            help, fix = suggestion(
                ctx, suggestions.get(target.text), "a label", target.span, None, "jump to",
                f"add `{target.text}` as the label of a block (`[b#{target.text}#...`), "
                "or leave the target empty to go on with the next block",
            )
            out.append(
                diagnostic(
                    "L003",
                    f"no block has the label `{target.text}`",
                    target.span,
                    help=help,
                    fix=fix,
                )
            )
    return out
