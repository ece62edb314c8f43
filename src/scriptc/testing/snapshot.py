"""Snapshots (docs/testing.md, "Snapshots"): with `snapshot = true`, a test's whole trace is
part of the test. The trace must equal the snapshot file `NAME.trace.jsonl` beside the test
file (`NAME`: the test file's name without `.test.toml`), a JSON-lines trace as `scriptc run
--trace` writes it; `scriptc test --update` writes the file when it is missing or differs.

What is kept is portable: the paths the trace names (`script_load`'s `path`, `session_start`'s
`scenario`) are written relative to the test file's folder, with forward slashes, whatever
the working folder `scriptc test` runs in and however the test names its scripts (a run names
them from the working folder, and a script loaded by path during the run by its absolute
path).

A difference is told as events, not as text (`differences`): the two traces are aligned
(`difflib`'s matching of the events' lines) and the first events that differ are listed with
their times: the pairs that differ side by side with the fields that differ, the events only
the run wrote, the events only the snapshot has. The verdict (`judge`) is a `Verdict` with the
code T007, at the test's `snapshot` key.
"""

from __future__ import annotations

import difflib
import json
import os
from collections.abc import Sequence
from dataclasses import dataclass, replace

from scriptc.encoding import decode
from scriptc.paths import shown_path
from scriptc.runtime.trace import Event, dumps
from scriptc.testing import SUFFIX
from scriptc.testing.expect import Verdict, shown_event
from scriptc.testing.model import TestFile
from scriptc.testing.run import FAILED, PASSED, TestResult
from scriptc.writing import WriteError, write_file

__all__ = ["CODE", "NAME", "SNAPSHOT_SUFFIX", "Difference", "differences", "judge", "portable",
           "snapshot_path", "snapshot_text"]

# The code of a snapshot's verdict, and its name in reports.
CODE = "T007"
NAME = "snapshot"
SNAPSHOT_SUFFIX = ".trace.jsonl"
# How many differing events a failure lists (the first ones).
SHOWN = 5
# The fields of trace events that name files, by kind.
_PATH_FIELDS = {"script_load": "path", "session_start": "scenario"}


def snapshot_path(test_path: str) -> str:
    """`tests/greeting.trace.jsonl` for `tests/greeting.test.toml` (the same folder)."""
    base = test_path[: -len(SUFFIX)] if test_path.endswith(SUFFIX) else test_path
    return base + SNAPSHOT_SUFFIX


def _relative(path: str, folder: str) -> str:
    try:
        relative = os.path.relpath(os.path.abspath(path), folder)
    except ValueError:  # another drive (Windows): no relative path
        return path
    return relative.replace(os.sep, "/") if os.sep != "/" else relative


def portable(events: Sequence[Event], test_path: str) -> list[Event]:
    """The events with the paths they name made relative to the test file's folder."""
    folder = os.path.dirname(os.path.abspath(test_path))
    out = []
    for event in events:
        field = _PATH_FIELDS.get(str(event["event"]))
        value = event.get(field) if field is not None else None
        if field is not None and isinstance(value, str) and value:
            out.append({**event, field: _relative(value, folder)})
        else:
            out.append(event)
    return out


def snapshot_text(events: Sequence[Event], test_path: str) -> str:
    """The snapshot file of a run of the test at `test_path`: its portable events, a JSON
    line each."""
    return "".join(dumps(e) + "\n" for e in portable(events, test_path))


@dataclass(frozen=True, slots=True)
class Difference:
    """One place where the traces differ: the event of the snapshot (`expected`, None when
    only the run has it) and of the run (`found`, None when only the snapshot has it), with
    their 1-based line numbers in each."""

    expected: Event | None
    found: Event | None
    expected_line: int
    found_line: int

    def words(self) -> list[str]:
        """The difference in a note: a line or two, each event with its time."""
        if self.found is None:
            assert self.expected is not None
            line = self.expected_line
            return [f"only in the snapshot (line {line}): {_shown(self.expected)}"]
        if self.expected is None:
            return [f"only in the run (event {self.found_line}): {_shown(self.found)}"]
        fields = _differing(self.expected, self.found)
        return [f"the snapshot (line {self.expected_line}): {_shown(self.expected)}",
                f"  the run (event {self.found_line}): {_shown(self.found)}"
                + (f" ({', '.join(f'`{f}`' for f in fields)} "
                   f"{'differs' if len(fields) == 1 else 'differ'})" if fields else "")]


def _shown(event: Event) -> str:
    """`at 3000 ms: block {"label": "hello", ...}`."""
    head, _, rest = shown_event(event).partition(": ")
    return f"{head}: {event.get('event')} {rest}"


def _differing(a: Event, b: Event) -> list[str]:
    keys = list(a) + [k for k in b if k not in a]
    return [k for k in keys if k not in a or k not in b or a[k] != b[k]]


def differences(expected: Sequence[str], found: Sequence[str]) -> list[Difference]:
    """Where the lines of the snapshot (`expected`) and of the run (`found`), each an event,
    differ, in order: the traces aligned by their longest matching runs of events; a stretch
    replaced by another pairs its events one by one, and the events left over are only in
    one of them."""
    start = 0
    while start < min(len(expected), len(found)) and expected[start] == found[start]:
        start += 1
    end_e, end_f = len(expected), len(found)
    while end_e > start and end_f > start and expected[end_e - 1] == found[end_f - 1]:
        end_e, end_f = end_e - 1, end_f - 1
    matcher = difflib.SequenceMatcher(None, expected[start:end_e], found[start:end_f],
                                      autojunk=False)
    out = []
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        for k in range(max(i2 - i1, j2 - j1)):
            i, j = start + i1 + k, start + j1 + k
            out.append(Difference(_event(expected[i]) if i < start + i2 else None,
                                  _event(found[j]) if j < start + j2 else None,
                                  i + 1 if i < start + i2 else start + i2,
                                  j + 1 if j < start + j2 else start + j2))
    return out


def _event(line: str) -> Event:
    value = json.loads(line)
    if not isinstance(value, dict):
        raise ValueError("not an event")
    return value


def _read(path: str) -> tuple[list[str] | None, str]:
    """The lines of the snapshot file, or None and why it cannot be compared."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        return None, f"no snapshot: `{shown_path(path)}` does not exist"
    except OSError as exc:
        return None, f"`{shown_path(path)}` cannot be read ({exc.strerror or exc})"
    decoded = decode(data)
    if decoded.bad is not None:
        return None, f"`{shown_path(path)}` is not a trace: {decoded.problem}"
    lines = decoded.text.splitlines()
    for number, line in enumerate(lines, 1):
        try:
            event = json.loads(line)
        except ValueError:
            event = None
        if not isinstance(event, dict) or not isinstance(event.get("event"), str) \
                or not isinstance(event.get("t"), int):
            return None, (f"`{shown_path(path)}` is not a trace: line {number} is not an "
                          "event (a JSON object with `t` and `event`)")
    return lines, ""


def judge(test: TestFile, result: TestResult, *, update: bool = False) -> TestResult:
    """`result` with the snapshot's verdict when `test` has `snapshot = true` (unchanged
    otherwise, and when the test could not run). With `update`, a snapshot that is missing or
    differs is written (`result.written` names it) and the verdict holds."""
    if test.snapshot is None or result.status not in (PASSED, FAILED):
        return result
    path = snapshot_path(test.path)
    text = snapshot_text(result.events, test.path)
    found = text.splitlines()
    expected_lines, problem = _read(path)
    shown = shown_path(path)
    expected = f"the trace to equal the snapshot `{shown}`"
    update_hint = f"scriptc test {_quoted(test.source.path)} --update"
    if expected_lines is not None and expected_lines == found:
        verdict = Verdict(None, NAME, True, expected, f"{len(found)} events, the same",
                          code=CODE)
        return replace(result, verdicts=(*result.verdicts, verdict))
    if update:
        try:
            write_file(path, text)
        except WriteError as exc:
            verdict = Verdict(None, NAME, False, expected, f"it cannot be written: {exc}",
                              code=CODE)
            return replace(result, verdicts=(*result.verdicts, verdict), status=FAILED)
        what = "written" if expected_lines is None and problem.startswith("no snapshot") \
            else "written again"
        verdict = Verdict(None, NAME, True, expected, f"{len(found)} events, {what}",
                          code=CODE)
        return replace(result, verdicts=(*result.verdicts, verdict),
                       written=(*result.written, shown))
    if expected_lines is None:
        verdict = Verdict(None, NAME, False, expected, problem,
                          (f"write it from this run: {update_hint}",), code=CODE)
    else:
        diffs = differences(expected_lines, found)
        first = diffs[0]
        when = (first.found or first.expected or {}).get("t")
        if len(diffs) == 1:
            notes: list[str] = ["the event that differs:"]
        elif len(diffs) <= SHOWN:
            notes = ["the events that differ:"]
        else:
            notes = [f"the first {SHOWN} of the {len(diffs)} events that differ:"]
        for d in diffs[:SHOWN]:
            notes += d.words()
        notes.append(f"the run wrote {len(found)} events, the snapshot has "
                     f"{len(expected_lines)}; if the run is right, write the snapshot again: "
                     f"{update_hint}")
        found_words = (f"1 event that differs, at {when} ms" if len(diffs) == 1 else
                       f"{len(diffs)} events that differ, the first at {when} ms")
        verdict = Verdict(None, NAME, False, expected, found_words, tuple(notes), code=CODE)
    return replace(result, verdicts=(*result.verdicts, verdict), status=FAILED)


def _quoted(path: str) -> str:
    import shlex

    return shlex.quote(path.replace(os.sep, "/") if os.sep != "/" else path)
