"""What test results say to people (docs/testing.md, "Output"): each failed expectation as a
diagnostic in the compiler's style (T006) in the test file, pointing at its `[[expect]]`,
saying what was expected and what the run did instead, its help the `scriptc run` command that
replays the run; the line of each test; the summary of a run. Diagnostics are rendered by
`scriptc.diagnostics.render`, as every verb's are; the formats for machines (JUnit, GitHub
annotations) are other renderers over the same data.
"""

from __future__ import annotations

from collections.abc import Sequence

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.diagnostics.render import paint, plural
from scriptc.source import SourceFile
from scriptc.testing.expect import Verdict
from scriptc.testing.model import TestFile
from scriptc.testing.run import ERROR, FAILED, PASSED, TestResult

__all__ = ["diagnosed", "failure", "failures", "summary_line", "test_line"]

_WORD = {PASSED: ("PASS ", "bold green"), FAILED: ("FAIL ", "bold red"),
         ERROR: ("ERROR", "bold red")}


def failure(test: TestFile, result: TestResult, verdict: Verdict) -> Diagnostic:
    """The diagnostic of one failed expectation, at its `[[expect]]` (the implicit one, a run
    stopped by a run-time error, at the test's `scripts`; the snapshot, at `snapshot`)."""
    span = test.head
    for expectation in test.expectations:
        if expectation.index == verdict.index:
            span = expectation.span
    if verdict.code == "T007" and test.snapshot is not None:
        span = test.snapshot
    return diagnostic(
        verdict.code, f"`{verdict.name}`: expected {verdict.expected}, found {verdict.found}",
        span,
        notes=("\n".join(verdict.notes),) if verdict.notes else (),
        help=f"replay the run: {result.replay}")


def failures(test: TestFile, result: TestResult) -> list[Diagnostic]:
    """The diagnostics of every failed expectation of a result, in the file's order."""
    return [failure(test, result, v) for v in result.verdicts if not v.passed]


def diagnosed(test: TestFile, result: TestResult
              ) -> list[tuple[SourceFile, Sequence[Diagnostic]]]:
    """What a result reports as diagnostics, file by file: a failed test's failed
    expectations in its test file, a test that could not run the diagnostics of the files that
    stopped it (nothing for a test that passed)."""
    if result.status == FAILED:
        return [(test.source, failures(test, result))]
    if result.status == ERROR:
        return [(source, list(diagnostics)) for source, diagnostics in result.problems]
    return []


def _seconds(s: float) -> str:
    return f"{s:.3f} s" if s < 10 else f"{s:.1f} s"


def test_line(result: TestResult, *, wall: bool = True, color: bool = False) -> str:
    """`PASS  greeting.test.toml (8.000 s simulated, 0.021 s)`: one test, one line (`wall`:
    with the seconds it took)."""
    word, style = _WORD[result.status]
    head = paint(word, style) if color else word
    if result.status == ERROR:
        return f"{head} {result.path}: {result.reason}\n"
    timing = f"{result.time_ms / 1000:.3f} s simulated" if result.time_ms is not None else ""
    if wall:
        timing += f", {_seconds(result.wall_s)}"
    tail = ""
    if result.status == FAILED:
        failed = len(result.failures)
        tail = f": {failed} of {plural(len(result.verdicts), 'expectation')} failed"
    return f"{head} {result.path} ({timing}){tail}\n"


def summary_line(results: Sequence[TestResult], wall_s: float | None = None, *,
                 color: bool = False) -> str:
    """`3 passed, 1 failed; 68.000 s simulated in 0.52 s`: the run as a whole."""
    counts = {status: sum(1 for r in results if r.status == status)
              for status in (PASSED, FAILED, ERROR)}
    parts = [f"{counts[PASSED]} passed"]
    if counts[FAILED]:
        parts.append(f"{counts[FAILED]} failed")
    if counts[ERROR]:
        parts.append(plural(counts[ERROR], "error"))
    text = ", ".join(parts)
    if color:
        text = paint(text, "bold red" if counts[FAILED] or counts[ERROR] else "bold green")
    simulated = sum(r.time_ms or 0 for r in results) / 1000
    timing = f"; {simulated:.3f} s simulated"
    if wall_s is not None:
        timing += f" in {_seconds(wall_s)}"
    return f"{text}{timing}\n"
