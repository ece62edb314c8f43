"""Go to definition, find references and rename, for labels, aliases and rule ids.

- A label is defined by the block carrying it (`[b#LABEL#...`) and used by jumps
  (`TRJMP(LABEL)`, `FLSJMP(LABEL)`). When two blocks carry it (L001), both are definitions,
  the first one first (jumps go there).
- An alias (`?kid`) is defined by the CLASS assignments binding it. From a use, the binding
  earlier in the same condition is the definition; without one, every binding of the script
  (an alias bound with scope `U` lives on into later blocks).
- A rule id is named by the alfa and omega messages; the first of them defines it.

Rename refuses while items have syntax errors (an item that did not parse may hold uses the
rename would miss), refuses names the grammar does not allow, and refuses a new name that is
already taken (two labels, aliases or rules would become one).
"""

from __future__ import annotations

from scriptc.diagnostics.model import TextEdit
from scriptc.ide.answers import RenameError
from scriptc.ide.index import Occurrence
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.nodes import ClassAssignment, JumpBlock
from scriptc.language import SIGILS, THIS, is_name
from scriptc.source import Span

__all__ = ["definition", "prepare_rename", "references", "rename"]

RENAMABLE = ("label", "alias", "rule")
_WHAT = {"label": "label", "alias": "alias", "rule": "rule id"}


def _symbol(snapshot: Snapshot, offset: int) -> Occurrence | None:
    o = snapshot.index.occurrence_at(offset)
    return o if o is not None and o.kind in RENAMABLE else None


def definition(snapshot: Snapshot, offset: int) -> list[Span]:
    o = _symbol(snapshot, offset)
    if o is None:
        return []
    all_ = snapshot.index.occurrences_of(o.kind, o.name)
    definitions = [x.span for x in all_ if x.role == "definition"]
    if o.kind == "alias" and o.role == "reference":
        earlier = _binding_before(snapshot, o)
        if earlier is not None:
            return [earlier]
    return definitions


def _binding_before(snapshot: Snapshot, o: Occurrence) -> Span | None:
    """The binding of alias `o` earlier in the same condition, if any."""
    info = snapshot.index.block_at(o.span.start)
    if info is None or not isinstance(info.block, JumpBlock):
        return None
    found = None
    for asg in info.block.condition.assignments:
        if (isinstance(asg, ClassAssignment) and asg.alias.name.text == o.name
                and asg.alias.span.start < o.span.start):
            found = asg.alias.span
    return found


def references(snapshot: Snapshot, offset: int, include_declaration: bool = True) -> list[Span]:
    o = _symbol(snapshot, offset)
    if o is None:
        return []
    return [x.span for x in snapshot.index.occurrences_of(o.kind, o.name)
            if include_declaration or x.role != "definition"]


def prepare_rename(snapshot: Snapshot, offset: int) -> tuple[Span, str]:
    """The span of the name to rename and its text; RenameError when there is none or the
    rename cannot be done now."""
    o = _renamable(snapshot, offset)
    return o.span, o.name


def _renamable(snapshot: Snapshot, offset: int) -> Occurrence:
    """The name to rename at `offset`; RenameError when there is none or the rename cannot
    be done now."""
    o = _symbol(snapshot, offset)
    if o is None:
        raise RenameError("only labels, aliases and rule ids can be renamed")
    if snapshot.has_syntax_errors:
        raise RenameError(f"the script has syntax errors: fix them first, or some uses of "
                          f"`{o.name}` could be missed")
    return o


def rename(snapshot: Snapshot, offset: int, new_name: str) -> list[TextEdit]:
    o = _renamable(snapshot, offset)
    what = _WHAT[o.kind]
    new = new_name.strip()
    if o.kind == "alias":
        sigil = SIGILS["ALIAS"]
        new = new if new.startswith(sigil) else sigil + new
        valid = is_name(new[len(sigil):]) and new != THIS
    else:
        valid = is_name(new)
    if not valid:
        raise RenameError(f"`{new_name}` is not a valid {what}"
                          " (a letter or `_`, then letters, digits, `_` or `-`)")
    if new == o.name:
        return []
    if snapshot.index.occurrences_of(o.kind, new):
        raise RenameError(f"the {what} `{new}` already exists: renaming would merge the two")
    return [TextEdit(x.span, new) for x in snapshot.index.occurrences_of(o.kind, o.name)]
