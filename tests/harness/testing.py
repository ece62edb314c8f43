"""The `test` aspect of case files: a test file (`*.test.toml`, docs/testing.md), what
`scriptc test` says of it.

Under tests/cases/testing/:

- `NAME.test.toml` is a case, read from tests/cases/ (its paths are relative to it; the scripts
  are the examples' and the runtime cases'). `NAME.diagnostics` holds what `scriptc test`
  reports in the test file, in the form of every diagnostics file (harness/diagnostics.py):
  the problems of a test file that does not check (T001-T005), or the failed expectations of
  its run (T006); empty when it passes.
- `NAME.result.json` (a test file that checks) is the result of its run as data
  (`TestResult.as_dict`: the status, the simulated time, each expectation's verdict with what
  was expected, what was found and the notes, the replay command), without the wall time. The
  test runs twice: both results and both traces must be identical.
- `NAME.junit.xml` and `NAME.github`, where they exist (a case opts in by having them): the
  JUnit report of that one test (`scriptc test --junit`, its seconds 0 and without the run's
  timestamp, machine and properties) and its GitHub annotations (`--format github`).
- Other files named `NAME.*` (a world file) are what the case reads.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

from harness import CASES, Check, expect, files, relative
from harness.diagnostics import rendered

TESTING = CASES / "testing"
SUFFIX = ".test.toml"


def _stem(path: Path) -> str:
    return path.name[: -len(SUFFIX)]


def _outputs(path: Path) -> tuple[Path, Path]:
    return (path.with_name(_stem(path) + ".diagnostics"),
            path.with_name(_stem(path) + ".result.json"))


def _machine_outputs(path: Path) -> tuple[Path, ...]:
    """The JUnit report and the GitHub annotations of the case, those it opted in to."""
    return tuple(p for p in (path.with_name(_stem(path) + ".junit.xml"),
                             path.with_name(_stem(path) + ".github")) if p.exists())


def _machine(path: Path, read, result) -> None:
    """`NAME.junit.xml` and `NAME.github` (see the module's docstring), when the case has
    them: for a test file with problems (`result` None), or for the result of its run."""
    from dataclasses import replace

    from scriptc.diagnostics.render import render
    from scriptc.testing import junit
    from scriptc.testing.report import diagnosed

    junit_file, github_file = (path.with_name(_stem(path) + suffix)
                               for suffix in (".junit.xml", ".github"))
    with contextlib.chdir(CASES):
        if result is None:
            xml = junit.report([], [], invalid=[read])
            annotations = render("github", [(read.source, read.diagnostics)])
        else:
            xml = junit.report([read.test], [replace(result, wall_s=0.0)])
            annotations = render("github", diagnosed(read.test, result))
    if junit_file.exists():
        expect(junit_file, xml)
    if github_file.exists():
        expect(github_file, annotations)


def _case(path: Path) -> None:
    from scriptc.ops.test import run_one
    from scriptc.testing.read import read_test, test_from_text
    from scriptc.testing.report import failures

    diagnostics_file, result_file = _outputs(path)
    name = relative(path)
    with contextlib.chdir(CASES):
        read = read_test(name)
        if read.test is None:
            expect(diagnostics_file, rendered(
                read.source, read.diagnostics, lambda text: test_from_text(text, name).diagnostics))
            assert not result_file.exists(), f"{relative(result_file)}: the test does not check"
            _machine(path, read, None)
            return
        first, second = run_one(read.test), run_one(read.test)
    assert first.as_dict() == second.as_dict() and first.events == second.events, \
        "two runs of the test differ"
    found = failures(read.test, first)
    expect(diagnostics_file, rendered(read.source, found, lambda _text: found))
    expect(result_file, json.dumps(first.as_dict(), indent=1, ensure_ascii=False) + "\n")
    _machine(path, read, first)


def checks() -> list[Check]:
    out = []
    for path in files("testing", f"*{SUFFIX}"):
        diagnostics_file, result_file = _outputs(path)
        machine = _machine_outputs(path)
        reads = tuple(p for p in files("testing", f"{_stem(path)}.*")
                      if p not in (path, diagnostics_file, result_file, *machine))
        expected = ((diagnostics_file, result_file) if result_file.exists()
                    else (diagnostics_file,)) + machine
        out.append(Check("test", path, expected, lambda p=path: _case(p), reads=reads))
    return out

