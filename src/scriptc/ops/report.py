"""The report of a run as library calls (`scriptc report`, `scriptc run --report`, `scriptc test
--report`; docs/views.md): reading a trace file, finding the scripts a trace names (for their
flows), the name of each page, and writing the pages of a test run.

Where a trace's script is found (**decided**): a `script_load`'s `path` is the path the run
loaded it by (relative to the folder the run was made in, unless absolute; a test's snapshot
makes them relative to the test file). It is looked for as it is when absolute, else beside the
trace file, then in the working folder; the first file that exists is read. A script that is
not found (or cannot be read) is named in a warning that says where it was looked for, and the
page shows its run without its flow. `idle_activity` (a load without a path) is the built-in
idle program's.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from scriptc.analysis.analyze import Analysis, analyze_file
from scriptc.analysis.read import ReadError, read_bytes
from scriptc.encoding import decode
from scriptc.ir.nodes import Script
from scriptc.paths import shown_path
from scriptc.runtime.idle import IDLE_NAME, idle_script
from scriptc.runtime.trace import Event
from scriptc.source import SourceKind
from scriptc.testing.model import TestFile
from scriptc.testing.run import ERROR, TestResult
from scriptc.views.report import ScriptSource, report_html
from scriptc.views.run_data import Sample
from scriptc.writing import write_file

__all__ = ["TraceError", "default_output", "find_sources", "read_trace", "run_report",
           "test_page_name", "write_test_reports"]

# What a trace is, for the messages that say a file is not one.
_WHAT = ("a trace is JSON lines, one event each (an object with `t` and `event`), as "
         "`scriptc run --trace FILE.jsonl` writes it")


class TraceError(Exception):
    """A file that is not a trace: the message names the file and line, says what is wrong
    and what a trace is."""


def _constant(name: str) -> float:
    raise ValueError(f"{name} is not a JSON number")


def read_trace(path: str) -> list[Event]:
    """The events of the trace file `path`. Raises ReadError (it cannot be read) or
    TraceError (it is not a trace)."""
    data = read_bytes(path)
    shown = shown_path(path)
    decoded = decode(data)
    if decoded.bad is not None:
        raise TraceError(f"`{shown}` is not a trace: {decoded.problem} ({_WHAT})")
    events: list[Event] = []
    for number, line in enumerate(decoded.text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            event = json.loads(line, parse_constant=_constant)
        except (ValueError, RecursionError) as exc:
            raise TraceError(f"{shown}:{number}: not a JSON value ({exc}); {_WHAT}") from None
        if not isinstance(event, dict):
            raise TraceError(f"{shown}:{number}: a JSON {type(event).__name__}, not an event "
                             f"object; {_WHAT}")
        t, kind = event.get("t"), event.get("event")
        if isinstance(t, bool) or not isinstance(t, int) or t < 0 or not isinstance(kind, str):
            raise TraceError(f"{shown}:{number}: an object without a whole `t` (ms) and an "
                             f"`event` name; {_WHAT}")
        events.append(event)
    if not events:
        raise TraceError(f"`{shown}` is empty: {_WHAT}")
    return events


def default_output(trace_path: str) -> str:
    """The page of a trace when `-o` is not given: beside it, `.html` for its suffix
    (`run.jsonl` -> `run.html`)."""
    stem, suffix = os.path.splitext(trace_path)
    return (stem if suffix else trace_path) + ".html"


@dataclass(frozen=True, slots=True)
class _Load:
    script: str
    path: str
    line: int  # the event's number in the trace (from 1)


def _loads(events: Iterable[Event]) -> list[_Load]:
    """Each script the trace loads (by name and path), once, in order."""
    seen: dict[tuple[str, str], _Load] = {}
    for number, e in enumerate(events, 1):
        if e.get("event") != "script_load":
            continue
        script, path = e.get("script"), e.get("path")
        if isinstance(script, str) and isinstance(path, str) and (script, path) not in seen:
            seen[(script, path)] = _Load(script, path, number)
    return list(seen.values())


def _read_script(path: str) -> tuple[Script | None, str]:
    """The IR of the script (or thesis JSON) at `path`, or None and why."""
    kind = SourceKind.of_path(path)
    if kind is SourceKind.BYTECODE:
        return None, (f"`{shown_path(path)}` is bytecode, which keeps no flow to draw: make "
                      "the report of a run of its .script")
    try:
        analysis = analyze_file(path, kind, shown_path(path))
    except ReadError as exc:
        return None, str(exc)
    if analysis.script is None:
        return None, (f"`{shown_path(path)}` cannot be read into a script (run `scriptc lint "
                      f"{shown_path(path)}`)")
    return analysis.script, ""


def find_sources(events: Sequence[Event], trace_path: str | None = None, *,
                 known: Mapping[str, Script] | None = None
                 ) -> tuple[list[ScriptSource], list[str]]:
    """The scripts the trace loads, each with its IR (or why not), and a warning for each one
    not found: `known` are scripts already read (by the path the run loaded them by: `run
    --report`); the others are looked for as the module says, beside `trace_path` (None: the
    trace is not a file) and in the working folder."""
    sources, warnings = [], []
    here = os.getcwd()
    beside = os.path.dirname(os.path.abspath(trace_path)) if trace_path else None
    for load in _loads(events):
        if known is not None and load.path in known:
            sources.append(ScriptSource(load.script, load.path, known[load.path]))
            continue
        if not load.path and load.script == IDLE_NAME:
            sources.append(ScriptSource(load.script, load.path, idle_script()))
            continue
        if not load.path:
            sources.append(ScriptSource(load.script, load.path, None, "the trace names no file"))
            continue
        places = [load.path] if os.path.isabs(load.path) else [
            os.path.join(folder, load.path) for folder in (beside, here) if folder is not None]
        found = next((p for p in places if os.path.isfile(p)), None)
        if found is None:
            looked = ", ".join(f"`{shown_path(p)}`" for p in dict.fromkeys(places))
            why = (f"`{load.path}` does not exist" if os.path.isabs(load.path) else
                   f"`{load.path}` is neither beside the trace nor in the working folder")
            sources.append(ScriptSource(load.script, load.path, None, why))
            named = f"{shown_path(trace_path)}:{load.line}: " if trace_path else ""
            warnings.append(f"{named}no flow for the script `{load.script}`: {why} (looked "
                            f"for {looked}); the page shows its run without its flow: make "
                            "the report from the folder the run was made in, or put the "
                            "script there")
            continue
        script, why = _read_script(found)
        sources.append(ScriptSource(load.script, load.path, script, why))
        if script is None:
            warnings.append(f"the script `{load.script}`: {why}; the page shows its run "
                            "without its flow")
    return sources, warnings


def run_report(events: Sequence[Event], files: Sequence[str], analyses: Sequence[Analysis],
               samples: Sequence[Sample] | None = None) -> tuple[str, list[str]]:
    """The page of a run `scriptc run` just made (`run --report`): `files` as the command line
    gave them, `analyses` those of its scripts that were read (`programs.Loaded.analyses`, in
    the order of the files that are not bytecode), `samples` the path the robot took. Scripts
    the run loaded by path on its own are found as `find_sources` finds them. The page and
    the warnings."""
    read = [f for f in files if SourceKind.of_path(f) is not SourceKind.BYTECODE]
    known = {path: a.script for path, a in zip(read, analyses, strict=True)
             if a.script is not None}
    sources, warnings = find_sources(events, known=known)
    return report_html(events, sources, samples=samples), warnings


# -- the pages of a test run -------------------------------------------------------------------


def test_page_name(test_path: str, root: str) -> str:
    """The page of the test file `test_path` in a report folder: its path from `root` (the
    folder all the tests share), `.test.toml` made `.html`."""
    relative = os.path.relpath(os.path.abspath(test_path), root)
    name = relative[:-len(".test.toml")] if relative.endswith(".test.toml") else relative
    return name + ".html"


def _root(paths: Sequence[str]) -> str:
    folders = [os.path.dirname(os.path.abspath(p)) for p in paths]
    return os.path.commonpath(folders) if folders else os.getcwd()


def write_test_reports(tests: Sequence[TestFile], results: Sequence[TestResult],
                       folder: str) -> tuple[list[str], list[str]]:
    """Write the page of each test that ran into `folder` (made when missing; a test in a
    sub-folder of the others gets the same sub-folder), and `index.html`, which lists every
    test with its status and links its page. Returns the files written and the warnings (a
    script not found). Raises WriteError (`scriptc.writing`) when a page cannot be written."""
    import html

    by_path = {t.path: t for t in tests}
    root = _root([r.path for r in results])
    written: list[str] = []
    warnings: list[str] = []
    rows = []
    for result in results:
        test = by_path.get(result.path)
        description = result.description or (test.description if test else "")
        name = test_page_name(result.path, root)
        cell = html.escape(shown_path(result.path))
        if result.status != ERROR and result.events:
            sources, found = find_sources(result.events)
            warnings += [w for w in found if w not in warnings]
            title = f"{shown_path(result.path)}: {result.status}"
            if description:
                title += f": {description}"
            page = os.path.join(folder, name)
            os.makedirs(os.path.dirname(page), exist_ok=True)
            write_file(page, report_html(result.events, sources, title=title))
            written.append(page)
            cell = f"<a href=\"{html.escape(name.replace(os.sep, '/'))}\">{cell}</a>"
        what = f"{result.outcome} at {result.time_ms:,} ms" if result.time_ms is not None \
            else html.escape(result.reason)
        rows.append(f"<tr><td class=\"{result.status}\">{result.status}</td><td>{cell}</td>"
                    f"<td>{html.escape(description)}</td><td>{what}</td></tr>")
    index = os.path.join(folder, "index.html")
    os.makedirs(folder, exist_ok=True)
    write_file(index, _INDEX.replace("@@ROWS@@", "\n".join(rows)))
    written.append(index)
    return written, warnings


_INDEX = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'">
<title>scriptc test: the reports of the runs</title>
<style>
body { font: 14px/1.4 system-ui, sans-serif; margin: 16px; color: #1d232b; }
table { border-collapse: collapse; } td, th { padding: 3px 12px 3px 0; text-align: left; }
.passed { color: #2a9d3a; } .failed, .error { color: #d62728; font-weight: 600; }
</style>
</head>
<body>
<h1>The runs of the tests</h1>
<table>
<tr><th>status</th><th>test</th><th>description</th><th>run</th></tr>
@@ROWS@@
</table>
</body>
</html>
"""
