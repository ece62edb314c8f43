"""Shards: the tests of a run split into N parts, so that N jobs of a CI matrix run them
(docs/testing.md, "Shards").

- `Shard`: one part, `I/N` on the command line (`--shard 2/4`, 1-based) or from the variables
  Bazel and GoogleTest set (`TEST_TOTAL_SHARDS`, `TEST_SHARD_INDEX`, 0-based).
- `partition`: the split itself, a pure function of the tests' names and their recorded
  durations, so that every job computes the same split and every test is in exactly one
  part. With durations, the longest test first goes to the part with the least work so far
  (the longest-processing-time rule: the heaviest part is within the longest test of an even
  share); a test not recorded counts as the average of those recorded. Without durations,
  every test counts as one: the parts differ by one test at most.
- The durations file (`--durations FILE`): JSON, the seconds each test took, by its name
  (`test_key`: its path from the repository's root, so every job and every working folder
  name a test alike). A run that is not sharded records the tests it ran in it (`recorded`);
  a sharded run only reads it: a shard that wrote it while another was still reading it
  would split the tests differently from it.
"""

from __future__ import annotations

import heapq
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from scriptc.numbers import json_dumps
from scriptc.paths import repository_path, shown_path
from scriptc.testing.model import TestFile
from scriptc.testing.run import ERROR, TestResult

__all__ = ["INDEX_VARIABLE", "STATUS_VARIABLE", "TOTAL_VARIABLE", "Shard", "ShardError",
           "durations_text", "in_shard", "parse_shard", "partition", "read_durations",
           "recorded", "shard_from_environment", "test_key"]

# The variables of Bazel's test sharding (and GoogleTest's, as GTEST_*): how many shards, the
# 0-based index of this one, and a file a runner that shards touches to say so.
TOTAL_VARIABLE = "TEST_TOTAL_SHARDS"
INDEX_VARIABLE = "TEST_SHARD_INDEX"
STATUS_VARIABLE = "TEST_SHARD_STATUS_FILE"


class ShardError(ValueError):
    """A shard, or a durations file, that cannot be used: the message says why and what to
    write instead."""


@dataclass(frozen=True, slots=True)
class Shard:
    """The `index`-th (0-based) of `total` parts."""

    index: int
    total: int

    def __str__(self) -> str:
        return f"{self.index + 1}/{self.total}"


def parse_shard(text: str) -> Shard:
    """`I/N` (1-based, as `--shard` takes it): the I-th of N parts."""
    head, slash, tail = text.strip().partition("/")
    if not slash or not head.strip().isdigit() or not tail.strip().isdigit():
        raise ShardError(f"`{text}` is not a shard: write I/N, the I-th of N parts "
                         "(`--shard 1/4` to `--shard 4/4`)")
    index, total = int(head), int(tail)
    if total < 1 or not 1 <= index <= total:
        raise ShardError(f"`{text}` is not a shard: I goes from 1 to N, and N is 1 or more")
    return Shard(index - 1, total)


def shard_from_environment(environ: Mapping[str, str]) -> Shard | None:
    """The shard that `TEST_TOTAL_SHARDS` and `TEST_SHARD_INDEX` (0-based) name, None when
    neither is set (an empty value is not set). One without the other is an error, as in
    GoogleTest: a job that was meant to run a part must not run everything."""
    total, index = environ.get(TOTAL_VARIABLE, ""), environ.get(INDEX_VARIABLE, "")
    if not total and not index:
        return None
    if not total or not index:
        given, missing = (TOTAL_VARIABLE, INDEX_VARIABLE) if total else \
            (INDEX_VARIABLE, TOTAL_VARIABLE)
        raise ShardError(f"{given} is set but {missing} is not: set both (the number of "
                         "shards and this one's index from 0), or neither")
    if not total.strip().isdigit() or not index.strip().isdigit() or int(total) < 1 \
            or int(index) >= int(total):
        raise ShardError(f"{TOTAL_VARIABLE}={total} and {INDEX_VARIABLE}={index} name no "
                         f"shard: the index goes from 0 to {TOTAL_VARIABLE} - 1")
    return Shard(int(index), int(total))


def test_key(path: str) -> str:
    """A test's name in a durations file: its path from the repository's root, with forward
    slashes (`scriptc.paths.repository_path`), the same from any working folder; a test
    outside the repository by its path as shown."""
    return repository_path(path) or shown_path(path).replace(os.sep, "/")


def partition(keys: Sequence[str], total: int,
              durations: Mapping[str, float] | None = None) -> list[list[int]]:
    """Split the tests named `keys` into `total` parts: for each part, the indices of its
    tests, in the order of `keys`. See the module's docstring for the rule; ties go by the
    name, then to the part with the fewest tests, then to the first part."""
    known = [durations[k] for k in keys if durations is not None and k in durations]
    if known:
        average = sum(known) / len(known)
        weights = [durations[k] if durations is not None and k in durations else average
                   for k in keys]
    else:
        weights = [1.0] * len(keys)
    order = sorted(range(len(keys)), key=lambda i: (-weights[i], keys[i], i))
    parts: list[list[int]] = [[] for _ in range(total)]
    loads = [(0.0, 0, part) for part in range(total)]  # (work, tests, part): a heap
    for i in order:
        load, count, part = heapq.heappop(loads)
        parts[part].append(i)
        heapq.heappush(loads, (load + weights[i], count + 1, part))
    return [sorted(part) for part in parts]


def in_shard(tests: Sequence[TestFile], shard: Shard,
             durations: Mapping[str, float] | None = None) -> list[TestFile]:
    """The tests of `shard`, in their order."""
    keys = [test_key(test.source.path) for test in tests]
    return [tests[i] for i in partition(keys, shard.total, durations)[shard.index]]


def read_durations(path: str) -> dict[str, float] | None:
    """The durations recorded in `path` (None when the file does not exist yet: the shards
    are balanced by count); a file that is not a durations file is a ShardError."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise ShardError(f"cannot read the durations file `{path}`: "
                         f"{exc.strerror or exc}") from None
    what = (f"`{path}` is not a durations file: a JSON object whose `durations` maps each "
            "test to the seconds it took (`scriptc test --durations FILE` writes one)")
    try:
        document = json.loads(data.decode("utf-8"), parse_constant=_refuse_constant)
    except (UnicodeDecodeError, ValueError) as exc:
        raise ShardError(f"{what}: {exc}") from None
    table = document.get("durations") if isinstance(document, dict) else None
    if not isinstance(table, dict):
        raise ShardError(what)
    durations: dict[str, float] = {}
    for key, seconds in table.items():
        if isinstance(seconds, bool) or not isinstance(seconds, int | float) or seconds < 0:
            raise ShardError(f"{what}: `{key}` has {json.dumps(seconds)}")
        durations[key] = float(seconds)
    return durations


def _refuse_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number of seconds")


def recorded(durations: Mapping[str, float] | None,
             results: Sequence[TestResult]) -> dict[str, float]:
    """The durations file after a run: what it held, with the seconds of each test that ran
    (to the millisecond) in place of its old ones. A test that could not run (`error`) keeps
    its old figure: loading alone is no measure of it. Tests not run now (another folder, `-k`)
    keep theirs."""
    updated = dict(durations or {})
    for result in results:
        if result.status != ERROR:
            updated[test_key(result.path)] = round(result.wall_s, 3)
    return updated


def durations_text(durations: Mapping[str, float]) -> str:
    """A durations file's text: one test a line, sorted, so that its changes read well in a
    diff."""
    return json_dumps({"durations": dict(sorted(durations.items()))}, indent=1,
                      ensure_ascii=False) + "\n"
