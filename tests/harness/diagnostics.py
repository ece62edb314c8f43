"""The expected form of a file's diagnostics (`NAME.diagnostics`, `NAME.lint`): the whole
rendered diagnostic, its exact span, and the text after its fix.

For each diagnostic, in the order the analysis reports them:

- the block `scriptc lint` prints (`diagnostics/render.py`'s text format, without colour): the
  message, ` --> file:line:col`, the source lines with `^^^` under the span and `---` under
  each label, then the notes and the help;
- `span: LINE:COL-ENDLINE:ENDCOL`, the span itself (1-based, columns in code points, the end
  exclusive): the carets cannot show an empty span or the end of one that runs over lines;
- when it has a fix, `fix (safe): MESSAGE` (or `unsafe`), then the lines the fix changes, as
  they are before (`- LINE | text`) and after (`+ LINE | text`) it: the fix is applied alone
  by the one applier (`scriptc.diagnostics.edits.apply_edits`); line breaks other than `\\n`
  and control characters are shown as their control pictures (`␍`, `␉`); then
  `after the fix: gone` when the analysis of the fixed text no longer reports the diagnostic
  and reports nothing new, or the list of what went (`  - CODE message`) and what came
  (`  + CODE message`).

Diagnostics are separated by an empty line and followed by the renderer's summary
(`error: 2 errors, 1 warning emitted`). When two fixes or more are safe, a last line says what
`scriptc lint --fix` does with them all (its rounds of fixes, `scriptc.ops.lint`): how many it
applies, and what is left (`then nothing left`, or `then left:` and the codes and messages). A
clean file has an empty expected file.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Callable, Sequence

from scriptc.diagnostics.edits import apply_edits
from scriptc.diagnostics.model import Diagnostic
from scriptc.diagnostics.render import render_text, summary
from scriptc.source import SourceFile, Span

# What the analysis of a text says of it: the fixed text is analysed again through this.
Analyse = Callable[[str], Sequence[Diagnostic]]
# What `scriptc lint --fix` does to the file: how many fixes it applies, and the text it writes.
FixAll = Callable[[], tuple[int, str]]


def rendered(source: SourceFile, diagnostics: Sequence[Diagnostic], again: Analyse,
             fix_all: FixAll | None = None) -> str:
    """The expected file of `diagnostics` of `source` (the module docstring). `again` analyses
    the text after a fix, as `source` was analysed; `fix_all`, when given, is what
    `scriptc lint --fix` does to the file: it is shown when two fixes or more are safe."""
    if not diagnostics:
        return ""
    before = Counter((d.code, d.message) for d in diagnostics)
    blocks = []
    for d in diagnostics:
        lines = [_block(source, d), f"span: {_span(source, d.span)}"]
        if d.fix is not None:
            lines += _fix_lines(source, d, before, again)
        blocks.append("\n".join(lines) + "\n")
    out = "\n".join(blocks) + "\n" + summary([(source, diagnostics)]) + "\n"
    if fix_all is not None and sum(1 for d in diagnostics if d.fix and d.fix.safe) >= 2:
        applied, text = fix_all()
        left = again(text)
        out += f"\nscriptc lint --fix: {applied} fixes applied, then " + (
            "nothing left\n" if not left else
            "left:\n" + "".join(f"  {d.code} {d.message}\n" for d in left))
    return out


def _block(source: SourceFile, d: Diagnostic) -> str:
    """The renderer's block of one diagnostic, without the summary line after it."""
    text = render_text([(source, [d])])
    tail = "\n\n" + summary([(source, [d])]) + "\n"
    assert text.endswith(tail), text
    return text[: -len(tail)]


def _span(source: SourceFile, span: Span) -> str:
    a, b = source.position(span.start), source.position(span.end)
    return f"{a.line}:{a.column}-{b.line}:{b.column}"


def _fix_lines(source: SourceFile, d: Diagnostic, before: Counter, again: Analyse) -> list[str]:
    fix = d.fix
    assert fix is not None
    lines = [f"fix ({'safe' if fix.safe else 'unsafe'}): {fix.message}"]
    if not fix.edits:
        return [*lines, "  (no edits)"]
    after_text = apply_edits(source.text, fix.edits)
    lines += changed_lines(source.text, after_text, [e.span for e in fix.edits])
    after = Counter((a.code, a.message) for a in again(after_text))
    gone = sorted((before - after).elements())
    new = sorted((after - before).elements())
    if gone == [(d.code, d.message)] and not new:
        lines.append("after the fix: gone")
    elif not gone and not new:
        lines.append("after the fix: the same diagnostics")
    else:
        lines.append("after the fix:")
        lines += [f"  - {code} {message}" for code, message in gone]
        lines += [f"  + {code} {message}" for code, message in new]
    return lines


def changed_lines(before: str, after: str, spans: Sequence[Span]) -> list[str]:
    """The lines the edits of `spans` change, before (`- N | text`) and after (`+ N | text`),
    without the lines that come out the same at either end."""
    old = SourceFile("", before)
    first = min(old.line_of(s.start) for s in spans)
    last = max(old.line_of(s.end - 1 if s.end > s.start else s.start) for s in spans)
    start = old.line_starts[first]
    end = old.line_starts[last + 1] if last + 1 < len(old.line_starts) else len(before)
    removed = before[start:end].splitlines(keepends=True)
    added = after[start:end + len(after) - len(before)].splitlines(keepends=True)
    same = 0
    while same < min(len(removed), len(added)) and removed[same] == added[same]:
        same += 1
    removed, added, first = removed[same:], added[same:], first + same
    while removed and added and removed[-1] == added[-1]:
        removed.pop()
        added.pop()
    width = len(str(first + max(len(removed), len(added), 1)))

    def row(sign: str, number: int, line: str) -> str:
        shown = _shown(line)
        return f"{sign} {number:>{width}} |" + (f" {shown}" if shown else "")

    out = [row("-", first + 1 + i, line) for i, line in enumerate(removed)]
    out += [row("+", first + 1 + i, line) for i, line in enumerate(added)]
    for lines, sign in ((removed, "-"), (added, "+")):
        if lines and not lines[-1].endswith(("\n", "\r")):
            out.append(f"{sign} \\ no line break at the end of the file")
    return out


def _shown(line: str) -> str:
    """A line without its `\\n`, every other control character as its control picture (a
    `\\r\\n` line break shows as `␍`)."""
    line = line.removesuffix("\n")
    return "".join(chr(0x2400 + ord(ch)) if ord(ch) < 0x20 else "\u2421" if ch == "\x7f" else ch
                   for ch in line)


_HEADER = re.compile(r"^(error|warning|info)\[([A-Z][0-9]{3})\]: (.*)$")


def parsed(text: str) -> list[tuple[str, str, str, str]]:
    """The (span, severity, code, message) of each diagnostic of an expected file, in order: the
    header line and the `span:` line of each block."""
    out = []
    header = None
    for line in text.splitlines():
        m = _HEADER.match(line)
        if m:
            header = m.groups()
        elif line.startswith("span: ") and header is not None:
            severity, code, message = header
            out.append((line[len("span: "):], severity, code, message))
            header = None
    return out
