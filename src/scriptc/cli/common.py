"""What the verbs share: the CLI's error type and options, a file's setup and analysis as the
verbs show them, colour choice and writing to stdout/stderr, and `lint`'s report (its
renderers are `scriptc.diagnostics.render`'s, its progress bar is here). Thin glue over
`scriptc.ops` and `scriptc.project.setup`; nothing here decides what a script means."""

from __future__ import annotations

import os
import sys
from typing import IO, TYPE_CHECKING

import click

from scriptc import interrupt, writing
from scriptc.diagnostics.render import FORMATS, LINT_FORMATS, render
from scriptc.paths import same_file

if TYPE_CHECKING:
    from rich.progress import Progress as Bar
    from rich.progress import TaskID

    from scriptc.analysis.analyze import Analysis
    from scriptc.ops.lint import LintOptions
    from scriptc.project.setup import Setup
    from scriptc.source import SourceKind


class CliError(click.ClickException):
    """A problem with the command or its files (not with the script): exit 2."""

    exit_code = 2

    def show(self, file: IO[str] | None = None) -> None:
        click.echo(f"error: {self.format_message()}", err=True)


class Stopped(CliError):
    """Ctrl-C stopped the work: exit 130, with what was interrupted and how far it got."""

    exit_code = interrupt.EXIT_STATUS


def format_option(function):
    return click.option("--format", "format_", type=click.Choice(FORMATS), default="text",
                        show_default=True, help="Output format of the diagnostics.")(function)


def lint_format_option(function):
    return click.option("--format", "format_", type=click.Choice(LINT_FORMATS), default="text",
                        show_default=True,
                        help="Output format of the diagnostics (grouped: one line each, under "
                             "its file).")(function)


def stdin_name_option(function):
    return click.option("--stdin-filename", "stdin_name", default="<stdin>", metavar="NAME",
                        help="The file name shown for input read from `-` (stdin).")(function)


def read_stdin() -> bytes:
    return sys.stdin.buffer.read()


def configured(path: str) -> Setup:
    """The setup of a file (`scriptc.project.setup.setup_for`; `path` may be the name given
    to stdin), its configuration's problems shown on stderr; when one is an error the command
    stops there with status 1: nothing is compiled or run under a configuration that does not
    say what was meant (docs/configuration.md)."""
    from scriptc.project.setup import setup_for

    setup = setup_for(path)
    if setup.problems:
        show(setup.problems, err=True)
    if setup.failed:
        stop_for_configuration()
    return setup


def stop_for_configuration() -> None:
    click.echo("error: fix the configuration first: nothing was done", err=True)
    click.get_current_context().exit(1)


def load(path: str, kind: SourceKind, stdin_name: str = "<stdin>") -> Analysis:
    """Analyse one file (or stdin for `-`) under its setup (`configured`: the repository's
    functions, robot profile and lint policy: `scriptc.ops.build.read_configured`). An
    unreadable file is a CliError."""
    from scriptc.analysis.read import ReadError
    from scriptc.ops.build import read_configured

    setup = configured(path if path != "-" else stdin_name)
    try:
        return read_configured(path, kind, setup, stdin=read_stdin, stdin_name=stdin_name)
    except ReadError as exc:
        raise CliError(str(exc)) from None


def use_color(stream: IO[str]) -> bool:
    """The group's `--color`: always, never, or auto: NO_COLOR turns colour off, FORCE_COLOR
    on, and otherwise colour goes to a terminal only (no-color.org, force-color.org)."""
    ctx = click.get_current_context(silent=True)
    obj = ctx.find_root().obj if ctx is not None else None
    mode = obj.get("color", "auto") if isinstance(obj, dict) else "auto"
    if mode != "auto":
        return mode == "always"
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR", "").lower() not in ("", "0", "false"):
        return True
    if os.environ.get("TERM") == "dumb":
        return False
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def write(text: str, *, err: bool = False) -> None:
    """Write text to stdout (or stderr) as it is, whatever the stream's encoding can hold."""
    if not text:
        return
    stream = sys.stderr if err else sys.stdout
    try:
        stream.write(text)
    except UnicodeEncodeError:
        stream.flush()
        stream.buffer.write(text.encode(stream.encoding or "utf-8", errors="replace"))
    stream.flush()


def write_bytes(data: bytes) -> None:
    """Write bytes to stdout unchanged (machine-readable output is always UTF-8)."""
    stream = sys.stdout.buffer
    stream.write(data)
    stream.flush()


def show(results: list, *, err: bool = False) -> None:
    """Diagnostics as text on stdout (or stderr), in colour when `--color` allows it. The
    other formats are `lint`'s and `check`'s (`rendered`, `emit_output`)."""
    stream = sys.stderr if err else sys.stdout
    write(render("text", results, color=use_color(stream)), err=err)


def check_output(path: str) -> None:
    """Refuse, before any work, an output path that cannot be written (a folder, a missing
    folder: `scriptc.writing.check_target`) with a CliError."""
    try:
        writing.check_target(path)
    except writing.WriteError as exc:
        raise CliError(str(exc)) from None


def write_output(path: str, text: str | bytes) -> None:
    """An output file written by the one writer (`scriptc.writing`: `-` is stdout, a link's
    target is written, a device or FIFO directly, a file atomically); a failure is a CliError.
    Text is written as UTF-8; bytes (bytecode) as they are."""
    if path == "-":
        sys.stdout.flush()  # what was written through the text layer comes first
    try:
        writing.write_file(path, text)
    except writing.WriteError as exc:
        raise CliError(str(exc)) from None


def refuse_overwriting_input(input_path: str, output_path: str) -> None:
    if same_file(input_path, output_path):
        raise CliError(f"the output `{output_path}` is the input file itself: refusing to "
                       "overwrite it (choose another file with -o)")


def report_paths(ctx: click.Context, paths: tuple[str, ...], kind: SourceKind, format_: str,
                 stdin_name: str, options: LintOptions | None = None, *,
                 quiet: bool = False, statistics: bool = False, output_file: str | None = None,
                 exit_zero: bool = False) -> None:
    """`lint` and `check`: `lint_report`, then exit with its status."""
    ctx.exit(lint_report(paths, kind, format_, stdin_name, options, quiet=quiet,
                         statistics=statistics, output_file=output_file, exit_zero=exit_zero))


def lint_report(paths: tuple[str, ...], kind: SourceKind, format_: str, stdin_name: str,
                options: LintOptions | None = None, *, quiet: bool = False,
                statistics: bool = False, output_file: str | None = None,
                exit_zero: bool = False) -> int:
    """Analyse the paths (with their configuration, the cache and worker processes:
    `scriptc.ops.lint.lint_paths`), show the diagnostics on stdout (or in `output_file`), a
    summary on stderr when several files were read, and return the run's status (a file that
    cannot be read is named on stderr and makes it 2). `statistics` shows a count per code
    instead of the diagnostics; `options.diff` the unified diff of what the fixes would change
    instead (status 1 when there is one); `exit_zero` turns status 1 into 0."""
    from scriptc.analysis.read import ReadError
    from scriptc.diagnostics.render import (
        diff_summary,
        lint_summary,
        plural,
        render_statistics,
    )
    from scriptc.ops import lint
    from scriptc.source import SourceKind

    options = options or lint.LintOptions()
    if output_file is not None:
        check_output(output_file)
    progress = Progress(quiet)
    options.progress = progress
    try:
        run = lint.lint_paths(paths, kind, stdin=read_stdin, stdin_name=stdin_name,
                              options=options)
    except ReadError as exc:
        raise CliError(str(exc)) from None
    except KeyboardInterrupt:
        # Worker processes are stopped by then, and every file written so far (cache
        # entries, fixes) was put in place whole (`scriptc.writing`).
        progress.close()
        verb = "checking" if kind == SourceKind.JSON else "linting"
        how_far = (f"{progress.done} of {plural(progress.total, 'file')} analysed"
                   if progress.total else "before any file was analysed")
        raise Stopped(f"interrupted (Ctrl-C) while {verb}, {how_far}: nothing was reported, "
                      "and no file was left half-written") from None
    finally:
        progress.close()
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if not run.files and not run.problems:
        write("warning: no script files found under the given paths\n", err=True)
    status = run.exit_code
    several = run.files > 1 or any(p != "-" and os.path.isdir(p) for p in paths)
    if options.diff:
        # As ruff's `--diff`: the changes, not the diagnostics; the configuration's own
        # problems still go to stderr, and status 1 says there is something to fix.
        configs = run.results[:run.configs]
        if configs:
            show(configs, err=True)
        output = "".join(fix_diff(r) for r in run.reports)
        emit_output(output, output_file)
        if not quiet:
            write(diff_summary(run), err=True)
        status = run.diff_exit_code
    else:
        if statistics:
            output = render_statistics(run, format_)
        else:
            color = format_ == "text" and output_file is None and use_color(sys.stdout)
            output = render(format_, run.results, color=color, unsafe=options.unsafe_fixes)
        emit_output(output, output_file, human=format_ in ("text", "grouped"))
        if not quiet and (run.fixed or (several and run.files)):
            write(lint_summary(run, several), err=True)
    return 0 if exit_zero and status == 1 else status


def emit_output(text: str, output_file: str | None, *, human: bool = False) -> None:
    """What `lint` prints, to stdout or to `--output-file` (through the one writer). Text for
    people goes through the terminal's encoding; machine formats and diffs are UTF-8 bytes."""
    if output_file is not None and output_file != "-":
        write_output(output_file, text)
    elif human:
        write(text)
    else:
        write_bytes(text.encode("utf-8"))


def fix_diff(report) -> str:
    """The unified diff of what `--fix` would change in one file (`--diff`), or ''."""
    if report.fixed_text is None:
        return ""
    from scriptc.ops.format import unified_diff

    return unified_diff(report.source.text, report.fixed_text, report.source.path)


# Below this many files no progress bar is shown: the run is over before one would help.
PROGRESS_MIN_FILES = 50


class Progress:
    """A rich progress bar on stderr, only on a terminal and only for many files (rich is
    imported then, and only then)."""

    def __init__(self, quiet: bool = False, label: str = "linting") -> None:
        self.enabled = not quiet and _stderr_is_terminal()
        self.label = label  # what the bar says is under way
        self._bar: tuple[Bar, TaskID] | None = None  # the bar shown, and its one task
        self.done = self.total = 0  # the last figures, for the message of an interruption

    def __call__(self, done: int, total: int) -> None:
        self.done, self.total = done, total
        if not self.enabled or total < PROGRESS_MIN_FILES or (done >= total and self._bar is None):
            return
        if self._bar is None:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                TextColumn,
                TimeRemainingColumn,
            )
            from rich.progress import Progress as Bar

            # No refresh thread (auto_refresh off, refreshed on each update): worker
            # processes are forked while the bar runs, and a fork must not copy a thread
            # that may hold a lock.
            bar = Bar(TextColumn(self.label), BarColumn(), MofNCompleteColumn(),
                      TimeRemainingColumn(), console=Console(stderr=True), transient=True,
                      auto_refresh=False)
            bar.start()
            self._bar = bar, bar.add_task("lint", total=total)
        bar, task = self._bar
        bar.update(task, completed=done, total=total)
        bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._bar[0].stop()
            self._bar = None


def _stderr_is_terminal() -> bool:
    if os.environ.get("TERM") == "dumb":
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False
