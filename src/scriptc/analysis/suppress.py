"""Suppression comments: what a script says about its own diagnostics.

    [b##blk_inst: MV() LD() AO()]   % scriptc: ignore[F001] %
    % scriptc: ignore[unreachable-block, M004] %
    % scriptc: ignore-file[F003] %

`% scriptc: ignore[CODE, ...] %` suppresses those codes on the item it stands on: the
bracketed item it is written inside, else the item that ends before it on the same line, else
the next item (a comment on a line of its own precedes the item below it). A diagnostic is on
an item when its primary span starts inside the item. `% scriptc: ignore-file[CODE, ...] %`,
anywhere, suppresses the codes in the whole file. Codes are written as codes (`L003`) or
names (`unknown-label`).

Errors cannot be suppressed (a script with an error does not work on the robot): naming one
is C004, as is naming a code that does not exist. A suppression that suppresses nothing is
C003, with a safe fix that removes it; a `scriptc:` comment that is not a suppression is
C006. C003 is not reported when the checks did not run (the file has front-end errors):
then no one knows what the suppression would have suppressed.

Suppressions are part of the file: the driver applies them in every analysis (lint, compile,
editors), before the configuration's policy. The cost for a file without `scriptc:` is one
substring search.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Severity, TextEdit
from scriptc.source import SourceFile, Span

MARKER = "scriptc:"
_DIRECTIVE = re.compile(r"\s*scriptc\s*:\s*")
_FORM = re.compile(r"(ignore-file|ignore)\s*\[([^\]\n]*)\]\s*", re.ASCII)
_CODE = re.compile(r"[^,\s]+")


@dataclass(slots=True)
class Suppression:
    """One suppression comment: the codes it names (each with the span where it is written),
    and the item it applies to (`scope`; None for the whole file, `file_level`)."""

    comment: Span
    file_level: bool
    scope: Span | None
    codes: list[tuple[str, Span]] = field(default_factory=list)  # (registry code, span)
    used: set[str] = field(default_factory=set)
    precedes: bool = False  # the comment stands before its item (rather than on it)

    def covers(self, d: Diagnostic) -> bool:
        if self.file_level:
            return True
        return self.scope is not None and self.scope.start <= d.span.start < self.scope.end


def _suggest(word: str) -> str | None:
    import difflib

    from scriptc.diagnostics.codes import lint_codes

    names = [c.code for c in lint_codes()] + [c.name for c in lint_codes()]
    close = difflib.get_close_matches(word, names, n=1, cutoff=0.6) or \
        difflib.get_close_matches(word.upper(), names, n=1, cutoff=0.6)
    return close[0] if close else None


def _scope(comment: Span, items: list[Span], starts: list[int], text: str
           ) -> tuple[Span | None, bool]:
    """The item a suppression comment applies to (see the module's docstring), and whether
    the comment precedes it (rather than standing on it)."""
    i = bisect.bisect_right(starts, comment.start) - 1
    if i >= 0 and items[i].end > comment.start:
        return items[i], False  # inside the item
    if i >= 0 and "\n" not in text[items[i].end:comment.start] and \
            "\r" not in text[items[i].end:comment.start]:
        return items[i], False  # after the item, on the line where it ends
    return (items[i + 1], True) if i + 1 < len(items) else (None, True)


def find_suppressions(source: SourceFile) -> tuple[list[Suppression], list[Diagnostic]]:
    """The suppression comments of a script, and the problems in them (C004, C006)."""
    text = source.text
    if MARKER not in text:
        return [], []
    from scriptc.diagnostics.codes import lookup
    from scriptc.syntax.scan import scan

    scanned = scan(text)
    items = [item.span for item in scanned.items]
    starts = [span.start for span in items]
    found: list[Suppression] = []
    problems: list[Diagnostic] = []
    for comment in scanned.comments:
        inner_start = comment.start + 1
        inner_end = comment.end - 1 if comment.end - comment.start >= 2 else comment.end
        head = _DIRECTIVE.match(text, inner_start, inner_end)
        if head is None:
            continue
        form = _FORM.fullmatch(text, head.end(), inner_end)
        if form is None:
            problems.append(diagnostic(
                "C006", "this `scriptc:` comment is not a suppression scriptc understands",
                comment,
                help="write `% scriptc: ignore[CODE, ...] %` for the item it stands on or "
                     "precedes, or `% scriptc: ignore-file[CODE, ...] %` for the whole file"))
            continue
        file_level = form.group(1) == "ignore-file"
        scope, precedes = (None, False) if file_level else _scope(comment, items, starts, text)
        suppression = Suppression(comment, file_level, scope, precedes=precedes)
        for m in _CODE.finditer(text, form.start(2), form.end(2)):
            word, span = m.group(), Span(m.start(), m.end())
            try:
                entry = lookup(word)
            except KeyError:
                close = _suggest(word)
                problems.append(diagnostic(
                    "C004", f"`{word}` is not a diagnostic code", span,
                    help=f"did you mean `{close}`?" if close else
                    "`scriptc explain --all` lists the codes and their names"))
                continue
            if entry.at_run_time:
                other = entry.name if word.upper() == entry.code else entry.code
                problems.append(diagnostic(
                    "C004", f"`{word}` ({other}) is a run-time code, which lint never reports",
                    span, notes=("run-time codes are in the trace of `scriptc run`",),
                    help="remove it; suppress the lint codes this item gets"))
                continue
            if entry.severity is Severity.ERROR:
                other = entry.name if word.upper() == entry.code else entry.code
                problems.append(diagnostic(
                    "C004", f"`{word}` ({other}) is an error: errors cannot be suppressed", span,
                    notes=("a script with an error does not work on the robot",),
                    help="fix the error instead"))
                continue
            suppression.codes.append((entry.code, span))
        if not suppression.codes:
            if not any(comment.start <= p.span.start < comment.end for p in problems):
                problems.append(diagnostic(
                    "C006", "this suppression names no code", comment,
                    help="list the codes to suppress: `% scriptc: ignore[F001] %`"))
            continue
        found.append(suppression)
    return found, problems


def _suppress(suppressions: list[Suppression], diagnostics: list[Diagnostic]
              ) -> tuple[list[Diagnostic], list[Diagnostic]]:
    kept: list[Diagnostic] = []
    suppressed: list[Diagnostic] = []
    for d in diagnostics:
        hit = False
        if d.severity is not Severity.ERROR:
            for s in suppressions:
                if s.covers(d) and any(code == d.code for code, _ in s.codes):
                    s.used.add(d.code)
                    hit = True
        (suppressed if hit else kept).append(d)
    return kept, suppressed


def _removal(source: SourceFile, s: Suppression, unused: set[str]) -> Fix:
    """A fix that removes the unused codes, or the whole comment when none is used."""
    text = source.text
    if all(code in unused for code, _ in s.codes):
        start, end = s.comment.start, s.comment.end
        line_start = max(text.rfind("\n", 0, start), text.rfind("\r", 0, start)) + 1
        before = text[line_start:start]
        after_end = end
        while after_end < len(text) and text[after_end] in " \t":
            after_end += 1
        if not before.strip() and (after_end == len(text) or text[after_end] in "\r\n"):
            # Alone on its line: the line goes.
            if text.startswith("\r\n", after_end):
                after_end += 2
            elif after_end < len(text):
                after_end += 1
            return Fix("remove the unused suppression",
                       (TextEdit(Span(line_start, after_end), ""),))
        # After an item: the spaces before it go too.
        while start > line_start and text[start - 1] in " \t":
            start -= 1
        return Fix("remove the unused suppression", (TextEdit(Span(start, end), ""),))
    kept_codes = [text[span.start:span.end] for code, span in s.codes if code not in unused]
    first, last = s.codes[0][1], s.codes[-1][1]
    return Fix("remove the unused codes from the suppression",
               (TextEdit(Span(first.start, last.end), ", ".join(kept_codes)),))


def apply_suppressions(source: SourceFile, diagnostics: list[Diagnostic], *, checked: bool = True
                       ) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """Apply a script's suppression comments to its diagnostics: what is still reported (the
    comments' own problems included, C003/C004/C006) and what was suppressed. `checked` says
    whether the semantic checks ran (C003 only then)."""
    suppressions, problems = find_suppressions(source)
    if not suppressions and not problems:
        return diagnostics, []
    own = ("C003", "C004", "C006")
    kept, suppressed = _suppress(suppressions, diagnostics)
    if checked:
        for s in suppressions:
            unused = {code for code, _ in s.codes if code not in s.used and code not in own}
            if not unused:
                continue
            spans = [span for code, span in s.codes if code in unused]
            listed = ", ".join(f"`{source.text[sp.start:sp.end]}`" for sp in spans)
            where = ("in this file" if s.file_level else
                     "(it stands before no item)" if s.scope is None else
                     "on the item that follows it" if s.precedes else
                     "on the item it stands on")
            problems.append(diagnostic(
                "C003", f"unused suppression: {listed} "
                f"{'suppresses' if len(spans) == 1 else 'suppress'} nothing {where}",
                Span(spans[0].start, spans[-1].end), fix=_removal(source, s, unused)))
    # The comments' own reports may be suppressed too (`ignore-file[C003]`).
    problems_kept, problems_suppressed = _suppress(suppressions, problems)
    out = kept + problems_kept
    out.sort(key=Diagnostic.sort_key)
    return out, suppressed + problems_suppressed
