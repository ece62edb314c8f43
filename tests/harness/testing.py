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
            return
        first, second = run_one(read.test), run_one(read.test)
    assert first.as_dict() == second.as_dict() and first.events == second.events, \
        "two runs of the test differ"
    found = failures(read.test, first)
    expect(diagnostics_file, rendered(read.source, found, lambda _text: found))
    expect(result_file, json.dumps(first.as_dict(), indent=1, ensure_ascii=False) + "\n")


def checks() -> list[Check]:
    out = []
    for path in files("testing", f"*{SUFFIX}"):
        diagnostics_file, result_file = _outputs(path)
        reads = tuple(p for p in files("testing", f"{_stem(path)}.*")
                      if p not in (path, diagnostics_file, result_file))
        expected = (diagnostics_file, result_file) if result_file.exists() \
            else (diagnostics_file,)
        out.append(Check("test", path, expected, lambda p=path: _case(p), reads=reads))
    return out

