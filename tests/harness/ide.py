"""The `ide` aspect of case files: the editor API (scriptc.ide) at a cursor.

A case is `tests/cases/ide/FEATURE_NAME.script`: a script with the cursor written `$0` (and,
for features that take a range, the range's end written `$1`), whose first comment may give
arguments (`% ide: rename new_name %`). The feature is the file name's first word: hover,
complete, definition, references, rename, symbols, folding, tokens, actions, hints. The
expected result is beside it, `FEATURE_NAME.expect`, in a plain text form written by the
functions below (positions as 1-based `line:column` in code points, with the text they
cover).

The markers are removed before analysis; the `.diagnostics` file beside each case is what
`scriptc lint` says of the file as it is on disk, markers included (the `diagnostics` aspect).
"""

from __future__ import annotations

import re
from pathlib import Path

from harness import CASES, Check, beside, expect
from scriptc.diagnostics.edits import apply_edits
from scriptc.ide import actions, completion, hints, hover, navigation, outline, tokens
from scriptc.ide.answers import RenameError
from scriptc.ide.snapshot import Snapshot
from scriptc.source import Span

IDE = CASES / "ide"
CASE_FILES = sorted(IDE.glob("*.script"))
_ARGS = re.compile(r"%\s*ide:\s*([^%]*)%")


def _load(path: Path) -> tuple[Snapshot, int | None, int | None, list[str]]:
    raw = path.read_text(encoding="utf-8")
    args = _ARGS.search(raw)
    cursor = end = None
    text = raw
    if "$0" in text:
        cursor = text.index("$0")
        text = text.replace("$0", "", 1)
    if "$1" in text:
        end = text.index("$1")
        text = text.replace("$1", "", 1)
    return Snapshot.of_text(text, path.name), cursor, end, (args.group(1).split() if args else [])


def _at(snapshot: Snapshot, offset: int) -> str:
    p = snapshot.source.position(offset)
    return f"{p.line}:{p.column}"


def _span(snapshot: Snapshot, span: Span) -> str:
    covered = snapshot.text[span.start:span.end]
    shown = (covered if len(covered) <= 60 and "\n" not in covered
             else covered[:57].split("\n")[0] + "...")
    return f"{_at(snapshot, span.start)}-{_at(snapshot, span.end)} `{shown}`"


def _hover(s: Snapshot, cursor: int, end, args) -> str:
    h = hover.hover(s, cursor)
    return "(nothing)\n" if h is None else f"{_span(s, h.span)}\n\n{h.markdown}\n"


def _complete(s: Snapshot, cursor: int, end, args) -> str:
    items = completion.complete(s, cursor)
    if not items:
        return "(nothing)\n"
    spans = {_span(s, i.span) for i in items}
    lines = [f"replacing {', '.join(sorted(spans))}"]
    for i in items:
        line = f"{i.label} ({i.kind})"
        if i.detail:
            line += f" {i.detail}"
        if i.snippet and i.snippet != i.label:
            line += f"  snippet: {i.snippet}"
        lines.append(line)
    return "\n".join(lines) + "\n"


def _definition(s: Snapshot, cursor: int, end, args) -> str:
    spans = navigation.definition(s, cursor)
    return "".join(_span(s, sp) + "\n" for sp in spans) or "(nothing)\n"


def _references(s: Snapshot, cursor: int, end, args) -> str:
    include = "no-declaration" not in args
    spans = navigation.references(s, cursor, include)
    return "".join(_span(s, sp) + "\n" for sp in spans) or "(nothing)\n"


def _rename(s: Snapshot, cursor: int, end, args) -> str:
    try:
        span, name = navigation.prepare_rename(s, cursor)
        edits = navigation.rename(s, cursor, args[0])
    except RenameError as error:
        return f"refused: {error}\n"
    return f"renaming {_span(s, span)} ({name})\n\n{apply_edits(s.text, edits)}"


def _symbols(s: Snapshot, cursor, end, args) -> str:
    out = []

    def walk(symbols, depth):
        for sym in symbols:
            out.append(f"{'  ' * depth}{sym.kind} {sym.name} [{_at(s, sym.span.start)}-"
                       f"{_at(s, sym.span.end)}] {sym.detail}".rstrip())
            walk(sym.children, depth + 1)

    walk(outline.document_symbols(s), 0)
    return "\n".join(out) + "\n"


def _folding(s: Snapshot, cursor, end, args) -> str:
    out = []
    for f in outline.folding_ranges(s):
        a = s.source.position(f.span.start).line
        b = s.source.position(max(f.span.start, f.span.end - 1)).line
        if b > a:
            out.append(f"{a}-{b} {f.kind}")
    return "\n".join(out) + "\n"


def _tokens(s: Snapshot, cursor, end, args) -> str:
    span = Span(cursor, end) if cursor is not None and end is not None else None
    out = []
    for t in tokens.semantic_tokens(s, span):
        mods = "+" + "+".join(t.modifiers) if t.modifiers else ""
        text = s.text[t.span.start:t.span.end]
        shown = text if "\n" not in text else text.split("\n")[0] + "..."
        out.append(f"{_at(s, t.span.start)} {t.type}{mods} `{shown}`")
    return "\n".join(out) + "\n"


def _actions(s: Snapshot, cursor, end, args) -> str:
    span = Span(cursor, end if end is not None else cursor)
    only = tuple(args) if args else None
    out = []
    for a in actions.code_actions(s, span, only):
        codes = ", ".join(d.code for d in a.diagnostics)
        out.append(f"== {a.title} ({a.kind}{', preferred' if a.preferred else ''}; {codes})\n"
                   f"{apply_edits(s.text, list(a.edits))}")
    return "\n".join(out) or "(nothing)\n"


def _hints(s: Snapshot, cursor, end, args) -> str:
    span = Span(cursor, end) if cursor is not None and end is not None else None
    return "".join(f"{_at(s, h.offset)} {h.kind}: {h.label}\n" for h in hints.inlay_hints(s, span))


FEATURES = {
    "hover": _hover,
    "complete": _complete,
    "definition": _definition,
    "references": _references,
    "rename": _rename,
    "symbols": _symbols,
    "folding": _folding,
    "tokens": _tokens,
    "actions": _actions,
    "hints": _hints,
}


def _check(path: Path) -> None:
    feature = path.stem.split("_")[0]
    assert feature in FEATURES, (f"{path.name}: the file name must start with one of "
                                 f"{list(FEATURES)}")
    snapshot, cursor, end, args = _load(path)
    expect(beside(path, ".expect"), FEATURES[feature](snapshot, cursor, end, args))


def checks() -> list[Check]:
    return [Check("ide", p, (beside(p, ".expect"),), lambda p=p: _check(p)) for p in CASE_FILES]
