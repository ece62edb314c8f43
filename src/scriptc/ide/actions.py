"""Code actions: the fixes the diagnostics carry, offered where the cursor or selection is.

Each diagnostic with a `fix` (a mutex letter in the wrong place, a jump to a misspelt label,
`<` written for `OP<`, a script without a terminus, a missing track...) gives one quick fix;
safe fixes (`Fix.safe`) are marked preferred, so an editor may apply them at once. The
`source.fixAll` action applies every safe fix of the document whose edits do not overlap.
"""

from __future__ import annotations

from scriptc.diagnostics.edits import compatible
from scriptc.diagnostics.model import Diagnostic, TextEdit
from scriptc.ide.answers import CodeAction
from scriptc.ide.snapshot import Snapshot
from scriptc.source import Span

__all__ = ["code_actions", "fix_all"]


def _meets(a: Span, b: Span) -> bool:
    """True when two spans overlap or touch (an empty span at the cursor meets the word)."""
    return a.start <= b.end and b.start <= a.end


def code_actions(snapshot: Snapshot, span: Span, only: tuple[str, ...] | None = None
                 ) -> list[CodeAction]:
    """Quick fixes for the diagnostics meeting `span`, then the fix-all action. `only`
    limits the kinds, as the protocol's `context.only` does (a kind includes its
    sub-kinds: "source" asks for "source.fixAll")."""

    def wanted(kind: str) -> bool:
        return only is None or any(kind == o or kind.startswith(o + ".") for o in only)

    out: list[CodeAction] = []
    if wanted("quickfix"):
        for d in snapshot.diagnostics:
            if d.fix is not None and d.fix.edits and _meets(d.span, span):
                out.append(CodeAction(d.fix.message, "quickfix", d.fix.edits, (d,), d.fix.safe))
    if wanted("source.fixAll"):
        everything = fix_all(snapshot)
        if everything is not None:
            out.append(everything)
    return out


def fix_all(snapshot: Snapshot) -> CodeAction | None:
    """Every safe fix of the document that can go with the others (the one overlap rule of
    `diagnostics.edits`, as `lint --fix` applies them), as one action."""
    candidates = [(d, fix) for d in snapshot.diagnostics
                  if (fix := d.fix) is not None and fix.safe and fix.edits]
    taken = iter(compatible([fix for _, fix in candidates]))
    fixed: list[Diagnostic] = []
    edits: list[TextEdit] = []
    next_fix = next(taken, None)
    for d, fix in candidates:  # `compatible` keeps the order: walk both lists together
        if fix is next_fix:
            fixed.append(d)
            edits.extend(fix.edits)
            next_fix = next(taken, None)
    if not fixed:
        return None
    edits.sort(key=lambda e: (e.span.start, e.span.end))
    title = f"Apply {len(fixed)} safe fix{'es' * (len(fixed) != 1)} (scriptc)"
    return CodeAction(title, "source.fixAll", tuple(edits), tuple(fixed), False)
