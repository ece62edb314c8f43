"""The `coverage` aspect of case files: a suite of tests and what `scriptc test --coverage`
measures over it (docs/testing.md, "Coverage").

Under tests/cases/coverage/:

- `NAME/` is a case: a folder of test files (`*.test.toml`) and the scripts they run, every
  file in it an input. Its tests run from tests/cases/ (`scriptc test coverage/NAME`), one
  worker, and each must run (pass or fail, not an error).
- `NAME.coverage` is the summary `--coverage` prints (each script's share of blocks, jump
  outcomes, goals and rules, and what no test reached, with its line), `NAME.info` the LCOV
  tracefile of `--lcov`, `NAME.coverage.json` the coverage data of `--coverage-data`. The data
  read back gives the same coverage, byte for byte.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

from harness import CASES, Check, expect, files, relative

COVERAGE = CASES / "coverage"


def _outputs(folder: Path) -> tuple[Path, Path, Path]:
    return tuple(folder.with_name(folder.name + suffix)  # type: ignore[return-value]
                 for suffix in (".coverage", ".info", ".coverage.json"))


def _case(folder: Path) -> None:
    from scriptc.ops.coverage import measure
    from scriptc.ops.test import TestOptions, test_paths
    from scriptc.testing.coverage import from_data, lcov, summary
    from scriptc.testing.run import ERROR

    summary_file, lcov_file, data_file = _outputs(folder)
    with contextlib.chdir(CASES):
        run = test_paths([relative(folder)], TestOptions(jobs=1))
        assert not run.problems and not run.invalid and run.results, (run.problems, run.invalid)
        errors = [r.path for r in run.results if r.status == ERROR]
        assert not errors, f"these tests could not run: {errors}"
        coverage = measure(run.tests, run.results)
    expect(summary_file, summary(coverage))
    expect(lcov_file, lcov(coverage))
    text = coverage.text()
    expect(data_file, text)
    assert from_data(json.loads(text), data_file.name).text() == text, "the data reads back"


def checks() -> list[Check]:
    folders = sorted({p.relative_to(COVERAGE).parts[0] for p in files("coverage")
                      if len(p.relative_to(COVERAGE).parts) > 1})
    out = []
    for name in folders:
        folder = COVERAGE / name
        reads = tuple(p for p in files(f"coverage/{name}"))
        out.append(Check("coverage", folder, _outputs(folder), lambda f=folder: _case(f),
                         reads=reads))
    return out
