"""`scriptc test`'s core: a test file (`*.test.toml`) as data, read and checked whole before
anything runs, its expectations judged over a run's trace and state, and one test run
(docs/testing.md).

- `model.py`: the test file as data (`TestFile`, the four kinds of `Expectation`, `Count`).
- `read.py`: reading and checking a test file (the schema, then what a schema cannot say);
  every problem a diagnostic of family T with its line and column.
- `expect.py`: each expectation judged over a run (`Verdict`s), from the run's trace and the
  states the session observed, never by simulating anything again.
- `run.py`: one test run on programs its caller loaded (`scriptc.ops.test` loads them as
  `scriptc run` does), and its result as data (`TestResult`), with the `scriptc run` command
  that replays it.
- `report.py`: what a result says to people: a failed expectation as a diagnostic pointing at
  its `[[expect]]`, the line of a test, the summary of a run.

The package sits between `scriptc.ops` and the runtime: it builds and drives a `Session`, and
knows nothing of how scripts are compiled or of the command line.
"""

__all__ = ["SUFFIX", "is_test_file"]

# What names a test file. Here, not in `read.py`, so that what only asks whether a file is a
# test (pytest's plugin, for every file of a suite; the language server) imports nothing else.
SUFFIX = ".test.toml"


def is_test_file(path: str) -> bool:
    """Whether `path` names a test file (`NAME.test.toml`)."""
    return path.endswith(SUFFIX)
