"""Renderers: every output format of diagnostics is a function over the one model.

Each renderer takes a list of results, one per file, each with a `source` (SourceFile) and
its `diagnostics` (in the order to show them), and returns the whole output as a string:

- `render_text`   rustc style, for people (`error[L003]: ...`, ` --> file:line:col`, the source
                  line with `^^^` under the span); ANSI colours only when asked for;
- `render_json`   a JSON list, one object per diagnostic (schemas/lint-output.schema.json);
- `render_sarif`  SARIF 2.1.0, for code-scanning services;
- `render_github` GitHub Actions workflow commands (`::error file=...::message`);
- `render_grouped` one line per diagnostic under its file (ruff's grouped format: `lint`'s);

and what `scriptc lint` says of a whole run (`scriptc.ops.lint.LintRun`): `render_statistics`
(`--statistics`), `lint_summary` and `diff_summary` (the lines it ends with on stderr).

Positions shown anywhere are 1-based lines and columns counted in code points; end columns
are exclusive (the column just after the span), as in SARIF. Files are named as the library
named them (`scriptc.paths.shown_path`) in text and JSON, and relative to the repository's
root (`scriptc.paths.repository_path`) in SARIF and GitHub's format. This module imports
nothing beyond the standard library, colours included (it writes the ANSI codes itself): it
sits on the path of `scriptc lint`, whose cold start is budgeted.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Protocol, cast

from scriptc.diagnostics.model import Diagnostic, Severity
from scriptc.numbers import JSONObject
from scriptc.paths import repository_path, repository_root
from scriptc.source import SourceFile, Span

if TYPE_CHECKING:
    from scriptc.diagnostics.codes import Code


class FileResults(Protocol):
    """What a renderer needs of one file's results (`scriptc.analysis.analyze.Analysis` is
    one; so is a configuration file's `scriptc.project.config.ConfigFile`)."""

    @property
    def source(self) -> SourceFile: ...

    @property
    def diagnostics(self) -> Sequence[Diagnostic]: ...


# What the renderers take: each file's results, or plain `(source, diagnostics)` pairs.
Results = Sequence[FileResults | tuple[SourceFile, Sequence[Diagnostic]]]


def _pairs(results: Results) -> list[tuple[SourceFile, Sequence[Diagnostic]]]:
    """Accept Analysis-like objects (anything with a `source` and `diagnostics`, a
    configuration file's `ConfigFile` too, itself a tuple) or plain `(source, diagnostics)`
    pairs."""
    return [_pair(r) for r in results]


def _pair(r: FileResults | tuple[SourceFile, Sequence[Diagnostic]]
          ) -> tuple[SourceFile, Sequence[Diagnostic]]:
    if not hasattr(r, "diagnostics"):
        return r
    # (a ConfigFile is a tuple too: what has `diagnostics` is read by name)
    results = cast(FileResults, r)
    return results.source, results.diagnostics


def _code_entry(code: str) -> Code | None:
    from scriptc.diagnostics.codes import REGISTRY

    return REGISTRY.get(code)


def _code_name(code: str) -> str:
    entry = _code_entry(code)
    return entry.name if entry is not None else ""


# ---------------------------------------------------------------------------------------------
# text

TAB_WIDTH = 4  # every tab shows as this many spaces (not tab stops), as rustc does
MAX_LINE = 120  # longer source lines are cut around the span, with `...` at the cuts
_CONTEXT = 40  # characters kept before the first annotation of a cut line

_SEVERITY_STYLE = {
    Severity.ERROR: "bold red",
    Severity.WARNING: "bold yellow",
    Severity.INFO: "bold cyan",
}
_FRAME = "bold blue"  # gutter, arrow, `|`, `=` and secondary labels
_BOLD = "bold"

# A line of output: pieces of text, each with a style (words of `_SGR`) or None.
_Line = list[tuple[str, "str | None"]]

# The ANSI select-graphic-rendition parameter of each word of a style: the eight standard
# colours, which every terminal shows in its own palette.
_SGR = {"bold": "1", "red": "31", "green": "32", "yellow": "33", "blue": "34", "cyan": "36"}


def _cell(ch: str) -> tuple[str, int]:
    """What one source character shows as, and how many terminal columns that takes.

    Tabs become spaces; control characters become their visible "control picture" (U+2400
    block) so that a stray escape or NUL cannot act on the terminal; format characters (bidi
    overrides, zero-width joiners) become U+FFFD so they cannot reorder the line; combining
    marks take no column and East Asian wide characters two, so carets stay under the text.
    """
    o = ord(ch)
    if 0x20 <= o < 0x7F:
        return ch, 1
    if ch == "\t":
        return " " * TAB_WIDTH, TAB_WIDTH
    if o < 0x20:
        return chr(0x2400 + o), 1
    if o == 0x7F:
        return "\u2421", 1
    import unicodedata

    category = unicodedata.category(ch)
    if category in ("Mn", "Me"):
        return ch, 0
    if category in ("Cf", "Cc", "Cs", "Zl", "Zp"):
        return "\ufffd", 1
    return ch, 2 if unicodedata.east_asian_width(ch) in ("W", "F") else 1


def _visible(text: str) -> str:
    """A message made safe for a terminal the way source lines are (`_cell`): messages quote
    the user's text (paths, strings), which may hold escape or bidi characters."""
    if text.isprintable():
        return text
    return "".join(_cell(ch)[0] for ch in text)


class _Annotation:
    __slots__ = ("end", "line", "marker", "message", "start", "style")

    def __init__(self, source: SourceFile, span: Span, marker: str, message: str | None,
                 style: str) -> None:
        # Columns here are 0-based character indices within the line; a span running over
        # several lines is shown on its first line, up to the end of that line.
        self.line = source.line_of(min(span.start, len(source.text)))
        line_start = source.line_starts[self.line]
        line_end = source.line_end(self.line)
        self.start = span.start - line_start
        self.end = max(self.start, min(span.end, line_end) - line_start)
        self.marker = marker
        self.message = message
        self.style = style


def _snippet_line(text: str, annotations: list[_Annotation]) -> tuple[str, list[tuple[int, int]]]:
    """The displayed line and, per annotation, its display column and width. A line without
    annotations (the one line shown between two annotated lines) is cut after MAX_LINE."""
    lo, hi = 0, len(text)
    if hi > MAX_LINE and not annotations:
        hi = MAX_LINE
    elif hi > MAX_LINE:
        first = min(a.start for a in annotations)
        last = max(a.end for a in annotations)
        # Some context before the first annotation, less when that brings the last one in.
        lo = max(0, min(first, max(first - _CONTEXT, last + 5 - MAX_LINE)))
        hi = min(hi, lo + MAX_LINE)
    shown: list[str] = ["..."] if lo > 0 else []
    columns = [3 if lo > 0 else 0]  # display column at which each character of the window starts
    for ch in text[lo:hi]:
        cell, width = _cell(ch)
        shown.append(cell)
        columns.append(columns[-1] + width)
    if hi < len(text):
        shown.append("...")

    def column(index: int) -> int:
        i = min(max(index, lo), hi) - lo
        # Past the end of the line (a span on the line break, or at the end of the file)
        # the caret goes just after the text.
        return columns[i] + max(0, index - hi) if hi == len(text) else columns[i]

    places = []
    for a in annotations:
        start = column(a.start)
        places.append((start, max(1, column(a.end) - start)))
    return "".join(shown).rstrip(), places


def _diagnostic_lines(source: SourceFile, d: Diagnostic) -> list[_Line]:
    severity_style = _SEVERITY_STYLE[d.severity]
    annotations = [_Annotation(source, d.span, "^", None, severity_style)]
    annotations += [_Annotation(source, label.span, "-", label.message, _FRAME)
                    for label in d.labels]
    by_line: dict[int, list[_Annotation]] = {}
    for a in annotations:
        by_line.setdefault(a.line, []).append(a)
    shown_lines = sorted(by_line)
    # A single line between two shown lines is shown too; a longer gap becomes `...`.
    gaps_filled = []
    for i, line in enumerate(shown_lines):
        if i and line - shown_lines[i - 1] == 2:
            gaps_filled.append(line - 1)
        gaps_filled.append(line)
    width = len(str(gaps_filled[-1] + 1))
    pad = " " * width

    pos = source.position(d.span.start)
    out: list[_Line] = [
        [(f"{d.severity.value}[{d.code}]", severity_style), (": ", _BOLD),
         (_visible(d.message), _BOLD)],
        [(f"{pad}--> ", _FRAME), (f"{_visible(source.path)}:{pos.line}:{pos.column}", None)],
        [(f"{pad} |", _FRAME)],
    ]
    previous = None
    for line in gaps_filled:
        if previous is not None and line - previous > 1:
            out.append([("...", _FRAME)])
        previous = line
        here = sorted(by_line.get(line, []), key=lambda a: (a.start, a.marker != "^"))
        text, places = _snippet_line(source.line_text(line), here)
        row: _Line = [(f"{line + 1:>{width}} |", _FRAME)]
        if text:
            row.append((" " + text, None))
        out.append(row)
        for a, (column, length) in zip(here, places, strict=True):  # a place per annotation
            row = [(f"{pad} | ", _FRAME), (" " * column + a.marker * length, a.style)]
            if a.message:
                row.append((" " + _visible(a.message), a.style))
            out.append(row)

    extras: list[tuple[str, str]] = []
    if d.path:
        extras.append(("note", f"at `{d.path}`"))
    extras += [("note", note) for note in d.notes]
    if d.help:
        extras.append(("help", d.help))
    if d.fix is not None and not d.help:  # a help says it already; the fix is for editors
        extras.append(("help", d.fix.message))
    if extras:
        out.append([(f"{pad} |", _FRAME)])
    for kind, message in extras:
        first, *rest = [_visible(part) for part in message.splitlines()] or [""]
        out.append([(f"{pad} = ", _FRAME), (f"{kind}:", _BOLD), (f" {first}", None)])
        indent = " " * (len(kind) + 2)
        out += [[(f"{pad}   {indent}{more}", None)] for more in rest]
    return out


def plural(n: int, word: str, words: str | None = None) -> str:
    """`1 file`, `2 files` (`words`: the plural when it is not `word` + s)."""
    return f"{n} {word}" if n == 1 else f"{n} {words or word + 's'}"


def summary(results: Results) -> str:
    """`error: 2 errors, 1 warning emitted`, or "" when there is nothing to report."""
    counts = dict.fromkeys(Severity, 0)
    for _source, diagnostics in _pairs(results):
        for d in diagnostics:
            counts[d.severity] += 1
    parts = []
    if counts[Severity.ERROR]:
        parts.append(plural(counts[Severity.ERROR], "error"))
    if counts[Severity.WARNING]:
        parts.append(plural(counts[Severity.WARNING], "warning"))
    if counts[Severity.INFO]:
        parts.append(plural(counts[Severity.INFO], "info message"))
    if not parts:
        return ""
    worst = min((s for s in Severity if counts[s]), key=lambda s: s.rank)
    return f"{worst.value}: {', '.join(parts)} emitted"


def _summary_line(results: Results) -> _Line:
    text = summary(results)
    word, _, rest = text.partition(":")
    return [(word, _SEVERITY_STYLE[Severity(word)]), (":" + rest, _BOLD)]


def render_text(results: Results, *, color: bool = False) -> str:
    """rustc-style text. With `color`, each styled piece in ANSI colours (`_colour`)."""
    lines = _text_lines(results)
    if not color:
        return "".join("".join(text for text, _style in line) + "\n" for line in lines)
    return _colour(lines)


def _text_lines(results: Results) -> list[_Line]:
    """The lines of the text format, each a list of styled pieces."""
    lines: list[_Line] = []
    for source, diagnostics in _pairs(results):
        for d in diagnostics:
            lines += _diagnostic_lines(source, d)
            lines.append([])
    if lines:
        lines.append(_summary_line(results))
    return lines


def paint(text: str, style: str) -> str:
    """`text` in the ANSI colours of `style` (words of `_SGR`: "bold green"), for the other
    lines of a verb's output that go with its diagnostics (`scriptc test`'s PASS and FAIL)."""
    return _colour([[(text, style)]])[:-1]


def _colour(lines: list[_Line]) -> str:
    """The lines with each styled piece between its SGR code and a reset (`ESC[1;31m...ESC[0m`:
    what rich wrote for these styles, which scriptc used before; a test holds them equal). The
    pieces' text is safe for a terminal already (`_cell`, `_visible`)."""
    out = []
    for line in lines:
        for piece, style in line:
            if not piece:
                continue
            if style is None:
                out.append(piece)
            else:
                sgr = ";".join(_SGR[word] for word in style.split())
                out.append(f"\x1b[{sgr}m{piece}\x1b[0m")
        out.append("\n")
    return "".join(out)


# ---------------------------------------------------------------------------------------------
# json


def _region(source: SourceFile, span: Span) -> dict[str, int]:
    a = source.position(span.start)
    b = source.position(span.end)
    return {"line": a.line, "column": a.column, "end_line": b.line, "end_column": b.column}


def diagnostic_record(source: SourceFile, d: Diagnostic) -> JSONObject:
    """One diagnostic as the JSON object of `scriptc lint --format json`."""
    record: JSONObject = {
        "code": d.code,
        "name": _code_name(d.code),
        "severity": d.severity.value,
        "message": d.message,
        "file": source.path,
        **_region(source, d.span),
        "labels": [{"message": label.message, **_region(source, label.span)}
                   for label in d.labels],
        "notes": list(d.notes),
        "help": d.help,
        "fix": None if d.fix is None else {
            "message": d.fix.message,
            "safe": d.fix.safe,
            "edits": [{**_region(source, e.span), "new_text": e.new_text} for e in d.fix.edits],
        },
    }
    if d.path is not None:
        record["path"] = d.path
    return record


def render_json(results: Results) -> str:
    from scriptc.numbers import json_dumps  # the JSON writer: never NaN or Infinity

    records = [diagnostic_record(source, d) for source, ds in _pairs(results) for d in ds]
    return json_dumps(records, indent=2, ensure_ascii=False) + "\n"


# ---------------------------------------------------------------------------------------------
# sarif

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
# `informationUri` is optional in SARIF and the project has no public address to give, so the
# driver names itself and its version only.
_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
# The base of relative artifact URIs: the repository's root (CodeQL's name for it).
SRCROOT = "%SRCROOT%"


def artifact_uri(path: str, roots: dict[str, str | None] | None = None) -> str:
    """A SARIF artifact URI for a file: relative to the repository's root (percent-encoded,
    forward slashes: `scriptc.paths.repository_path`, what code scanning resolves), a
    `file://` URI for a file outside it."""
    from pathlib import Path
    from urllib.parse import quote

    relative = repository_path(path, roots)
    return Path(path).absolute().as_uri() if relative is None else quote(relative, safe="/")


def _section(markdown: str, title: str) -> str:
    """The text of `## title` in an explanation, or ""."""
    lines = markdown.splitlines()
    for i, line in enumerate(lines):
        if line.strip().lower() == f"## {title}".lower():
            body = []
            for more in lines[i + 1:]:
                if more.startswith("## "):
                    break
                body.append(more)
            return "\n".join(body).strip()
    return ""


def _sarif_region(source: SourceFile, span: Span) -> dict[str, int]:
    r = _region(source, span)
    return {"startLine": r["line"], "startColumn": r["column"],
            "endLine": r["end_line"], "endColumn": r["end_column"]}


def _sarif_rule(code: str) -> JSONObject:
    from scriptc.diagnostics.codes import explanation

    entry = _code_entry(code)
    if entry is None:
        return {"id": code}
    long = explanation(code)
    rule: JSONObject = {
        "id": code,
        "name": entry.name,
        "shortDescription": {"text": entry.summary},
        "fullDescription": {"text": _section(long, "What it means") or entry.summary},
        "defaultConfiguration": {"level": _SARIF_LEVEL[entry.severity]},
    }
    if long:
        rule["help"] = {"text": long, "markdown": long}
    return rule


def render_sarif(results: Results) -> str:
    import os
    from pathlib import Path

    from scriptc import __version__
    from scriptc.numbers import json_dumps

    pairs = _pairs(results)
    codes = sorted({d.code for _source, ds in pairs for d in ds})
    index = {code: i for i, code in enumerate(codes)}
    sarif_results = []
    roots: dict[str, str | None] = {}
    for source, diagnostics in pairs:
        uri = artifact_uri(source.path, roots)
        # A relative URI is relative to the repository's root, which the log names (as
        # CodeQL's logs do); an absolute one stands alone.
        artifact = {"uri": uri, "uriBaseId": SRCROOT} if not uri.startswith("file:") else \
            {"uri": uri}

        def location(span: Span, message: str | None = None, *,
                     artifact: dict[str, str] = artifact,
                     source: SourceFile = source) -> JSONObject:
            loc: JSONObject = {"physicalLocation": {
                "artifactLocation": artifact, "region": _sarif_region(source, span)}}
            if message is not None:
                loc["message"] = {"text": message}
            return loc

        for d in diagnostics:
            result: JSONObject = {
                "ruleId": d.code,
                "ruleIndex": index[d.code],
                "level": _SARIF_LEVEL[d.severity],
                "message": {"text": d.message},
                "locations": [location(d.span)],
            }
            if d.path is not None:
                result["locations"][0]["logicalLocations"] = [
                    {"fullyQualifiedName": d.path, "kind": "value"}]
            if d.labels:
                result["relatedLocations"] = [{"id": i, **location(label.span, label.message)}
                                              for i, label in enumerate(d.labels)]
            if d.fix is not None:
                result["fixes"] = [{
                    "description": {"text": d.fix.message},
                    "artifactChanges": [{
                        "artifactLocation": artifact,
                        "replacements": [{"deletedRegion": _sarif_region(source, e.span),
                                          "insertedContent": {"text": e.new_text}}
                                         for e in d.fix.edits],
                    }],
                }]
            properties: dict[str, str | list[str]] = {}
            if d.notes:
                properties["notes"] = list(d.notes)
            if d.help:
                properties["help"] = d.help
            if properties:
                result["properties"] = properties
            sarif_results.append(result)
    log: JSONObject = {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {
                "name": "scriptc",
                "version": __version__,
                "rules": [_sarif_rule(code) for code in codes],
            }},
            # Our columns count code points, not SARIF's default UTF-16 code units.
            "columnKind": "unicodeCodePoints",
            "results": sarif_results,
        }],
    }
    base = repository_root(".") or os.getcwd()
    log["runs"][0]["originalUriBaseIds"] = {
        SRCROOT: {"uri": Path(base).absolute().as_uri().rstrip("/") + "/"}}
    return json_dumps(log, indent=2, ensure_ascii=False) + "\n"


# ---------------------------------------------------------------------------------------------
# github

_GITHUB_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _escape_data(text: str) -> str:
    # GitHub's workflow-command rules (toolkit `escapeData`): `%` first, then line breaks.
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    # Property values also escape the `:` and `,` that delimit properties (`escapeProperty`).
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


def render_github(results: Results) -> str:
    """Workflow commands; `file=` is relative to the repository's root (GitHub attaches an
    annotation to a pull request's diff only so: `scriptc.paths.repository_path`)."""
    out = []
    roots: dict[str, str | None] = {}
    for source, diagnostics in _pairs(results):
        path = repository_path(source.path, roots) or source.path
        for d in diagnostics:
            r = _region(source, d.span)
            properties = ",".join(f"{key}={_escape_property(str(value))}" for key, value in (
                ("file", path), ("line", r["line"]), ("col", r["column"]),
                ("endLine", r["end_line"]), ("endColumn", r["end_column"]), ("title", d.code)))
            message = "\n".join([d.message, *(f"note: {n}" for n in d.notes),
                                 *([f"help: {d.help}"] if d.help else [])])
            out.append(f"::{_GITHUB_COMMAND[d.severity]} {properties}::{_escape_data(message)}\n")
    return "".join(out)


# ---------------------------------------------------------------------------------------------
# grouped text: one line per diagnostic, under its file (as ruff's `--output-format grouped`)


def _printable(text: str) -> str:
    return text if text.isprintable() else "".join(c if c.isprintable() else "\ufffd"
                                                   for c in text)


def render_grouped(results: Results, *, unsafe: bool = False) -> str:
    """Each file with diagnostics, then one line per diagnostic: `  LINE:COL CODE [*] severity:
    message` (`[*]`: `--fix` can fix it; with `unsafe`, `--fix --unsafe-fixes`), a blank line
    between files, and the summary."""
    out = []
    for source, diagnostics in _pairs(results):
        if not diagnostics:
            continue
        rows = []
        for d in diagnostics:
            pos = source.position(d.span.start)
            mark = "[*] " if d.fix is not None and (unsafe or d.fix.safe) else ""
            rows.append((f"{pos.line}:{pos.column}", (f"{d.code} {mark}{d.severity.value}: "
                                                      f"{_printable(d.message)}")))
        width = max(len(where) for where, _ in rows)
        out.append(f"{_printable(source.path)}:\n")
        out += [f"  {where:<{width}} {rest}\n" for where, rest in rows]
        out.append("\n")
    if out:
        out.append(summary(results) + "\n")
    return "".join(out)


RENDERERS: dict[str, Callable[..., str]] = {
    "text": render_text,
    "json": render_json,
    "sarif": render_sarif,
    "github": render_github,
}
FORMATS = tuple(RENDERERS)
# `lint` and `check` also have `grouped`, which marks what `--fix` fixes.
LINT_FORMATS = (*FORMATS, "grouped")


def render(format: str, results: Results, *, color: bool = False,
           unsafe: bool = False) -> str:
    """Render with the renderer named `format` (one of LINT_FORMATS); `color` only matters
    for text, `unsafe` for grouped (the unsafe fixes are marked as `--fix` takes them)."""
    if format == "text":
        return render_text(results, color=color)
    if format == "grouped":
        return render_grouped(results, unsafe=unsafe)
    return RENDERERS[format](results)


# ---------------------------------------------------------------------------------------------
# A lint run as a whole


class LintTotals(Protocol):
    """What the summaries read of a lint run (`scriptc.ops.lint.LintRun`): its results, the
    files read and those from the cache, the fixes applied and the files they changed, the
    fixes available (`fixable`: as `--fix` takes them; `hidden_fixes`: the unsafe ones left
    out), and whether the unsafe fixes count."""

    @property
    def results(self) -> Results: ...

    @property
    def files(self) -> int: ...

    @property
    def cached(self) -> int: ...

    @property
    def fixed(self) -> int: ...

    @property
    def fixed_files(self) -> int: ...

    @property
    def fixable(self) -> int: ...

    @property
    def hidden_fixes(self) -> int: ...

    @property
    def unsafe_fixes(self) -> bool: ...


def render_statistics(run: LintTotals, format: str) -> str:
    """`lint --statistics`: how many diagnostics of each code, most frequent first (then by
    code), with the code's name and `[*]` when `--fix` fixes every one of them (as ruff's);
    as text, or as JSON (`code`, `name`, `severity`, `count`, `fixable`) with `format`
    "json"."""
    counts: dict[str, tuple[int, bool, str]] = {}  # code -> (count, fixable, severity)
    for _source, diagnostics in _pairs(run.results):
        for d in diagnostics:
            applies = d.fix is not None and (run.unsafe_fixes or d.fix.safe)
            count, fixable, severity = counts.get(d.code, (0, True, d.severity.value))
            counts[d.code] = (count + 1, fixable and applies, severity)
    rows = sorted(counts.items(), key=lambda item: (-item[1][0], item[0]))
    if format == "json":
        import json

        records = [{"code": code, "name": _code_name(code), "severity": severity,
                    "count": count, "fixable": fixable}
                   for code, (count, fixable, severity) in rows]
        return json.dumps(records, indent=2, ensure_ascii=False) + "\n"
    if not rows:
        return ""
    width = max(len(str(count)) for _code, (count, _f, _s) in rows)
    any_fixable = any(fixable for _code, (_c, fixable, _s) in rows)
    lines = []
    for code, (count, fixable, _severity) in rows:
        mark = ("[*] " if fixable else "    ") if any_fixable else ""
        lines.append(f"{count:>{width}}\t{code}\t{mark}{_code_name(code)}\n")
    return "".join(lines)


def diff_summary(run: LintTotals) -> str:
    """The line `scriptc lint --diff` ends with on stderr."""
    if run.fixed:
        line = (f"would fix {plural(run.fixed, 'problem')} in "
                f"{plural(run.fixed_files, 'file')}")
    else:
        line = "nothing to fix"
    if run.hidden_fixes:
        line += f" ({plural(run.hidden_fixes, 'more fix', 'more fixes')} with `--unsafe-fixes`)"
    return line + "\n"


def lint_summary(run: LintTotals, several: bool = True) -> str:
    """The lines `scriptc lint` ends with on stderr: what --fix did, and (`several` files)
    what was found."""
    lines: list[str] = []
    if run.fixed:
        lines.append(f"fixed {plural(run.fixed, 'problem')} in "
                     f"{plural(run.fixed_files, 'file')}")
    if several:
        counts = dict.fromkeys(Severity, 0)
        for _source, diagnostics in _pairs(run.results):
            for d in diagnostics:
                counts[d.severity] += 1
        found = [plural(counts[Severity.ERROR], "error"),
                 plural(counts[Severity.WARNING], "warning"),
                 plural(counts[Severity.INFO], "info message")]
        # one count per severity, in the enum's order
        found = [f for f, s in zip(found, Severity, strict=True) if counts[s]] or ["no problems"]
        cached = f" ({run.cached} unchanged, from the cache)" if run.cached else ""
        line = f"checked {plural(run.files, 'file')}{cached}: {', '.join(found)}"
        if run.fixable:
            flags = "--fix --unsafe-fixes" if run.unsafe_fixes else "--fix"
            line += (f"; {plural(run.fixable, 'fix', 'fixes')} available "
                     f"(`scriptc lint {flags}` applies {'it' if run.fixable == 1 else 'them'})")
        hidden = run.hidden_fixes  # unsafe fixes, left out without --unsafe-fixes
        if hidden and run.fixable:
            line += f", {hidden} more with `--unsafe-fixes`"
        elif hidden:
            line += (f"; {plural(hidden, 'unsafe fix', 'unsafe fixes')} available (`scriptc "
                     f"lint --fix --unsafe-fixes` applies {'it' if hidden == 1 else 'them'})")
        lines.append(line)
    return "".join(line + "\n" for line in lines)
