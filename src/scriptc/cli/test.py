"""`scriptc test [PATH...] [-k TEXT] [-j N]`: run the tests of an activity (`*.test.toml`,
docs/testing.md) in simulated time and say which passed.

Every test file found under the paths (default `.`) is checked before anything runs; a test
file with a problem is reported as the compiler reports a script, and nothing runs. Each test
selected then runs in a worker process; one line per test goes to stdout as it finishes (pass
or fail, simulated and wall time), then every failed expectation as a diagnostic pointing at
its `[[expect]]`, with the `scriptc run` command that replays the run, then a summary. On a
terminal with many tests a progress bar shows on stderr and the lines come at the end.
`--format github` gives the failures as GitHub workflow annotations instead, `--junit FILE`
writes a JUnit XML report (`scriptc.testing.junit`), `--shard I/N` (or TEST_TOTAL_SHARDS and
TEST_SHARD_INDEX) runs one part of the tests, balanced by `--durations FILE`
(`scriptc.testing.shard`). `--update` writes the snapshots of tests with `snapshot = true`
(`scriptc.testing.snapshot`); `--coverage`, `--lcov FILE`, `--coverage-data FILE` and
`--fail-under PERCENT` say what the tests reached of their scripts (`scriptc.ops.coverage`).
`--report DIR` writes the report of each test's run into DIR, one HTML page each, and an
`index.html` (`scriptc.ops.report.write_test_reports`).

Exit status: 0 every test passed, 1 a test failed (or the coverage is under `--fail-under`),
2 a test file or a script could not be loaded (or a path does not exist), 130 interrupted
(Ctrl-C: the workers stop at once, and what ran is reported). The work is
`scriptc.ops.test.test_paths`'s; this module prints it.
"""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

import click

from scriptc.cli.common import (
    PROGRESS_MIN_FILES,
    CliError,
    Progress,
    check_output,
    use_color,
    write,
    write_output,
)
from scriptc.ops.programs import EXECUTORS

if TYPE_CHECKING:
    from collections.abc import Sequence
    from datetime import datetime

    from scriptc.diagnostics.model import Diagnostic
    from scriptc.ops.test import TestRun
    from scriptc.source import SourceFile
    from scriptc.testing.shard import Shard

FORMATS = ("text", "github")


@click.command("test")
@click.argument("paths", nargs=-1)
@click.option("-k", "keyword", metavar="TEXT",
              help="Run only the tests whose path or description contains TEXT (any case).")
@click.option("-j", "--jobs", "jobs", type=click.IntRange(min=1), metavar="N",
              help="Worker processes (default: one per core).")
@click.option("--executor", "executor", type=click.Choice(EXECUTORS), default="vm",
              show_default=True,
              help="How .script and .json files run: vm (bytecode) or ir (the reference "
                   "interpreter), as for `scriptc run`.")
@click.option("-q", "--quiet", is_flag=True, help="No line for a test that passes, no bar.")
@click.option("--format", "format_", type=click.Choice(FORMATS), default="text",
              show_default=True,
              help="How failures are shown: text, or github (workflow annotations at each "
                   "failed [[expect]]).")
@click.option("--junit", "junit_file", metavar="FILE", help="Write a JUnit XML report to FILE.")
@click.option("--shard", "shard_text", metavar="I/N",
              help="Run the I-th of N parts of the tests (1-based); without it, "
                   "TEST_TOTAL_SHARDS and TEST_SHARD_INDEX (0-based) say the part.")
@click.option("--durations", "durations_file", metavar="FILE",
              help="The seconds each test took: shards are balanced by them; a run that is "
                   "not sharded records its tests' in FILE.")
@click.option("--update", is_flag=True,
              help="Write the snapshot (NAME.trace.jsonl) of each test with `snapshot = true` "
                   "that is missing or differs, instead of failing the test.")
@click.option("--coverage", "show_coverage", is_flag=True,
              help="Print what the tests reached of their scripts: blocks issued, jump "
                   "outcomes taken, goals reached, rules fired, and what was never reached.")
@click.option("--lcov", "lcov_file", metavar="FILE",
              help="Write the coverage to FILE as an LCOV tracefile (editors, coverage "
                   "services).")
@click.option("--coverage-data", "coverage_file", metavar="FILE",
              help="Write the coverage to FILE as data (JSON) that `scriptc merge` merges.")
@click.option("--fail-under", "fail_under", type=click.FloatRange(0, 100), metavar="PERCENT",
              help="Fail (exit 1) when the blocks issued or the jump outcomes taken are under "
                   "PERCENT of all.")
@click.option("--report", "report_dir", metavar="DIR",
              help="Write the report of each test's run into DIR: one HTML page per test "
                   "(the room, the tracks, the events, the flow) and an index.html.")
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], keyword: str | None, jobs: int | None,
            executor: str, quiet: bool, format_: str, junit_file: str | None,
            shard_text: str | None, durations_file: str | None, update: bool,
            show_coverage: bool, lcov_file: str | None, coverage_file: str | None,
            fail_under: float | None, report_dir: str | None) -> None:
    """Run the tests (*.test.toml) under PATH... (default: the working folder).

    A test runs scripts in simulated time, in a world, and checks what the run did: events
    of the trace, the robot's state at an instant, the outcome, distances kept to people.
    """
    from datetime import datetime

    from scriptc.diagnostics.render import render
    from scriptc.ops.test import TestOptions, test_paths
    from scriptc.testing.report import diagnosed, summary_line, test_line
    from scriptc.testing.run import PASSED, TestResult
    from scriptc.testing.shard import ShardError, read_durations

    shard = _shard(shard_text)
    for output in (junit_file, durations_file if shard is None else None, lcov_file,
                   coverage_file):
        if output is not None:
            check_output(output)
    if report_dir is not None and os.path.exists(report_dir) and not os.path.isdir(report_dir):
        raise CliError(f"--report `{report_dir}`: not a folder (the reports go into a folder, "
                       "one page per test)")
    try:
        durations = read_durations(durations_file) if durations_file else None
    except ShardError as exc:
        raise CliError(str(exc)) from None
    if shard is not None and durations_file and durations is None:
        write(f"warning: no durations recorded in `{durations_file}` yet: the shards are "
              "balanced by the number of tests\n", err=True)
    started = datetime.now().astimezone()
    color = use_color(sys.stdout)
    progress = Progress(quiet, label="testing")
    held: list[TestResult] = []  # the lines wait for the end while a bar is shown

    def on_result(_index: int, result: TestResult) -> None:
        if progress.enabled and progress.total >= PROGRESS_MIN_FILES:
            held.append(result)
        elif not (quiet and result.status == PASSED):
            write(test_line(result, color=color))

    options = TestOptions(jobs=jobs, keyword=keyword, executor=executor, progress=progress,
                          on_result=on_result, shard=shard, durations=durations,
                          update=update)
    try:
        run = test_paths(paths or (".",), options)
    finally:
        progress.close()
    for result in held:
        if not (quiet and result.status == PASSED):
            write(test_line(result, color=color))
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if run.invalid:
        write(render(format_, [(r.source, r.diagnostics) for r in run.invalid], color=color))
        write("error: fix the test files first: no test ran\n", err=True)
        _write_outputs(run, junit_file, shard, durations_file, durations, executor, keyword,
                       started)
        ctx.exit(run.exit_code)
    if not run.files and not run.problems:
        write("warning: no test files (*.test.toml) found under the given paths\n", err=True)
    elif not run.selected and keyword and not run.problems:
        write(f"warning: no test matches `-k {keyword}` ({len(run.files)} found)\n", err=True)
    elif shard is not None and not run.problems:
        write(f"shard {shard}: {len(run.tests)} of the {run.selected} tests\n", err=True)
    reports: list[tuple[SourceFile, Sequence[Diagnostic]]] = []
    by_path = {t.source.path: t for t in run.tests}
    for result in run.results:
        reports += diagnosed(by_path[result.path], result)
    if reports:
        write(("\n" if format_ == "text" else "") + render(format_, reports, color=color))
    if run.interrupted:
        write(f"error: interrupted (Ctrl-C): {len(run.results)} of {len(run.tests)} tests "
              "ran\n", err=True)
    for result in run.results:
        for written in result.written:
            write(f"wrote the snapshot {written}\n")
    if run.results:
        write(summary_line(run.results, run.wall_s, color=color))
    _write_outputs(run, junit_file, shard, durations_file, durations, executor, keyword, started)
    if report_dir is not None and run.results:
        _reports(run, report_dir)
    under = _coverage(run, show_coverage, lcov_file, coverage_file, fail_under)
    ctx.exit(1 if under and run.exit_code == 0 else run.exit_code)


def _reports(run: TestRun, folder: str) -> None:
    """The report of each test's run, in `folder` (`scriptc.ops.report.write_test_reports`)."""
    from scriptc.ops.report import write_test_reports
    from scriptc.writing import WriteError

    try:
        written, warnings = write_test_reports(run.tests, run.results, folder)
    except (WriteError, OSError) as exc:
        raise CliError(f"--report `{folder}`: {exc}") from None
    write("".join(f"warning: {w}\n" for w in warnings), err=True)
    write(f"wrote {len(written) - 1} reports of runs and their index, "
          f"{os.path.join(folder, 'index.html')}\n", err=True)


def _shard(text: str | None) -> Shard | None:
    """The shard to run: `--shard I/N`, else the one TEST_TOTAL_SHARDS and TEST_SHARD_INDEX
    name (and then TEST_SHARD_STATUS_FILE, when set, is touched: Bazel's way of asking a
    runner to say that it shards), else None. A shard that names none is a CliError."""
    from scriptc.testing.shard import (
        STATUS_VARIABLE,
        ShardError,
        parse_shard,
        shard_from_environment,
    )

    try:
        if text is not None:
            return parse_shard(text)
        shard = shard_from_environment(os.environ)
    except ShardError as exc:
        raise CliError(str(exc)) from None
    status = os.environ.get(STATUS_VARIABLE)
    if shard is not None and status:
        write_output(status, b"")
    return shard


def _write_outputs(run: TestRun, junit_file: str | None, shard: Shard | None,
                   durations_file: str | None, durations: dict[str, float] | None,
                   executor: str, keyword: str | None, started: datetime) -> None:
    """The files the run writes: its JUnit report, and the durations of the tests it ran
    when it is not sharded (a shard only reads them: see `scriptc.testing.shard`)."""
    import socket

    from scriptc import __version__
    from scriptc.testing import junit
    from scriptc.testing.shard import durations_text, recorded

    if junit_file is not None:
        properties = [("scriptc", __version__), ("executor", executor)]
        if keyword:
            properties.append(("keyword", keyword))
        if shard is not None:
            properties.append(("shard", str(shard)))
        write_output(junit_file, junit.report(
            run.tests, run.results, invalid=run.invalid, interrupted=run.interrupted,
            properties=properties, wall_s=run.wall_s, timestamp=started,
            hostname=socket.gethostname()))
    if durations_file is not None and shard is None and run.results:
        write_output(durations_file, durations_text(recorded(durations, run.results)))


def _coverage(run: TestRun, show: bool, lcov_file: str | None, coverage_file: str | None,
              fail_under: float | None) -> bool:
    """What the tests reached of their scripts (`scriptc.ops.coverage`), when an option asks:
    the summary printed, the LCOV and data files written; True when it is under
    `fail_under` (said on stderr). Nothing is measured for a run that did not finish."""
    if not (show or lcov_file or coverage_file or fail_under is not None) \
            or run.interrupted or not run.results:
        return False
    from scriptc.ops.coverage import measure
    from scriptc.testing.coverage import below, lcov, summary

    coverage = measure(run.tests, run.results)
    if show:
        write("\n" + summary(coverage))
    if lcov_file is not None:
        write_output(lcov_file, lcov(coverage))
    if coverage_file is not None:
        write_output(coverage_file, coverage.text())
    if fail_under is None:
        return False
    short = below(coverage, fail_under)
    if short:
        write(f"error: coverage under {fail_under:g}%: {'; '.join(short)}\n", err=True)
    return bool(short)
