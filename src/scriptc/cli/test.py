"""`scriptc test [PATH...] [-k TEXT] [-j N]`: run the tests of an activity (`*.test.toml`,
docs/testing.md) in simulated time and say which passed.

Every test file found under the paths (default `.`) is checked before anything runs; a test
file with a problem is reported as the compiler reports a script, and nothing runs. Each test
selected then runs in a worker process; one line per test goes to stdout as it finishes (pass
or fail, simulated and wall time), then every failed expectation as a diagnostic pointing at
its `[[expect]]`, with the `scriptc run` command that replays the run, then a summary. On a
terminal with many tests a progress bar shows on stderr and the lines come at the end.

Exit status: 0 every test passed, 1 a test failed, 2 a test file or a script could not be
loaded (or a path does not exist), 130 interrupted (Ctrl-C: the workers stop at once, and what
ran is reported). The work is `scriptc.ops.test.test_paths`'s; this module prints it.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import click

from scriptc.cli.common import PROGRESS_MIN_FILES, Progress, use_color, write
from scriptc.ops.programs import EXECUTORS

if TYPE_CHECKING:
    from collections.abc import Sequence

    from scriptc.diagnostics.model import Diagnostic
    from scriptc.source import SourceFile


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
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], keyword: str | None, jobs: int | None,
            executor: str, quiet: bool) -> None:
    """Run the tests (*.test.toml) under PATH... (default: the working folder).

    A test runs scripts in simulated time, in a world, and checks what the run did: events
    of the trace, the robot's state at an instant, the outcome, distances kept to people.
    """
    from scriptc.diagnostics.render import render
    from scriptc.ops.test import TestOptions, test_paths
    from scriptc.testing.report import failures, summary_line, test_line
    from scriptc.testing.run import ERROR, FAILED, PASSED, TestResult

    color = use_color(sys.stdout)
    progress = Progress(quiet, label="testing")
    held: list[TestResult] = []  # the lines wait for the end while a bar is shown

    def on_result(_index: int, result: TestResult) -> None:
        if progress.enabled and progress.total >= PROGRESS_MIN_FILES:
            held.append(result)
        elif not (quiet and result.status == PASSED):
            write(test_line(result, color=color))

    options = TestOptions(jobs=jobs, keyword=keyword, executor=executor, progress=progress,
                          on_result=on_result)
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
        write(render("text", [(r.source, r.diagnostics) for r in run.invalid], color=color))
        write("error: fix the test files first: no test ran\n", err=True)
        ctx.exit(run.exit_code)
    if not run.files and not run.problems:
        write("warning: no test files (*.test.toml) found under the given paths\n", err=True)
    elif not run.tests and keyword and not run.problems:
        write(f"warning: no test matches `-k {keyword}` ({len(run.files)} found)\n", err=True)
    reports: list[tuple[SourceFile, Sequence[Diagnostic]]] = []
    by_path = {t.source.path: t for t in run.tests}
    for result in run.results:
        if result.status == FAILED:
            test = by_path[result.path]
            reports.append((test.source, failures(test, result)))
        elif result.status == ERROR:
            reports += [(source, list(diagnostics)) for source, diagnostics in result.problems]
    if reports:
        write("\n" + render("text", reports, color=color))
    if run.interrupted:
        write(f"error: interrupted (Ctrl-C): {len(run.results)} of {len(run.tests)} tests "
              "ran\n", err=True)
    if run.results:
        write(summary_line(run.results, run.wall_s, color=color))
    ctx.exit(run.exit_code)
