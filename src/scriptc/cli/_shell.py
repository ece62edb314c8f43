"""What the verbs share: the CLI's error type, input loading, colour choice and writing to
stdout/stderr, the run summary and progress bar of `lint`, and the grouped text format. Thin
glue over `scriptc.driver`; nothing here decides what a script means."""

from __future__ import annotations

import os
import sys
from typing import IO

import click

from scriptc import driver
from scriptc.profile import profile_from_settings
from scriptc.diagnostics.render import FORMATS, render


class CliError(click.ClickException):
    """A problem with the command or its files (not with the script): exit 2."""

    exit_code = 2

    def show(self, file: IO[str] | None = None) -> None:
        click.echo(f"error: {self.format_message()}", err=True)


def format_option(function):
    return click.option("--format", "format_", type=click.Choice(FORMATS), default="text",
                        show_default=True, help="Output format of the diagnostics.")(function)


# `lint` and `check` also have `grouped`: one line per diagnostic under each file (ruff's).
LINT_FORMATS = (*FORMATS, "grouped")


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


def load(path: str, kind: str, stdin_name: str = "<stdin>") -> driver.Analysis:
    """Analyse one file (or stdin for `-`) with its configuration (the repository's functions,
    the lint policy); the configuration's own problems are shown on stderr, and when one is an
    error the command stops there with status 1: nothing is compiled or run under a
    configuration that does not say what was meant (docs/configuration.md). An unreadable
    file is a CliError."""
    settings, config_reports = driver.settings_for(path if path != "-" else stdin_name)
    if config_reports:
        show(config_reports, err=True)
        if driver.configuration_failed(config_reports):
            click.echo("error: fix the configuration first: nothing was done", err=True)
            click.get_current_context().exit(1)
    try:
        if path == "-":
            analysis = driver.analyze_bytes(stdin_name, read_stdin(), kind, settings.registry,
                                            profile_from_settings(settings))
        else:
            analysis = driver.analyze_file(path, kind, functions=settings.registry,
                                           profile=profile_from_settings(settings))
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    analysis.diagnostics = settings.apply(analysis.diagnostics,
                                          None if path == "-" and stdin_name == "<stdin>"
                                          else analysis.source.path)
    return analysis


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


def show(results: list[driver.Analysis], format_: str = "text", *, err: bool = False) -> None:
    """Render diagnostics (text to a terminal in colour when `--color` allows it)."""
    stream = sys.stderr if err else sys.stdout
    if format_ == "grouped":
        write(render_grouped(results), err=err)
        return
    output = render(format_, results, color=format_ == "text" and use_color(stream))
    if format_ == "text":
        write(output, err=err)
    else:
        write_bytes(output.encode("utf-8"))


def write_output(path: str, text: str | bytes) -> None:
    """An output file written atomically (`-` is stdout); a failure is a CliError. Text is
    written as UTF-8; bytes (bytecode) as they are."""
    if path == "-":
        write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
        return
    try:
        driver.write_atomic(path, text)
    except OSError as exc:
        raise CliError(f"cannot write `{path}`: {exc.strerror or exc}") from None


def refuse_overwriting_input(input_path: str, output_path: str) -> None:
    if driver.same_file(input_path, output_path):
        raise CliError(f"the output `{output_path}` is the input file itself: refusing to "
                       "overwrite it (choose another file with -o)")


def report_paths(ctx: click.Context, paths: tuple[str, ...], kind: str, format_: str,
                 stdin_name: str, options: driver.LintOptions | None = None, *,
                 quiet: bool = False) -> None:
    """`lint` and `check`: analyse the paths (with their configuration, the cache and worker
    processes: `driver.lint_paths`), show the diagnostics on stdout, a summary on stderr when
    several files were read, and exit with the run's status (a file that cannot be read is
    named on stderr and makes it 2)."""
    options = options or driver.LintOptions()
    progress = Progress(quiet)
    options.progress = progress
    try:
        run = driver.lint_paths(paths, kind, stdin=read_stdin, stdin_name=stdin_name,
                                options=options)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    finally:
        progress.close()
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if not run.files and not run.problems:
        write("warning: no script files found under the given paths\n", err=True)
    show(run.results, format_)
    several = run.files > 1 or any(p != "-" and os.path.isdir(p) for p in paths)
    if not quiet and (run.fixed or (several and run.files)):
        write(run_summary(run, several), err=True)
    ctx.exit(run.exit_code)


def _plural(n: int, word: str, words: str | None = None) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {words or word + 's'}"


def run_summary(run: driver.LintRun, several: bool = True) -> str:
    """The lines `scriptc lint` ends with on stderr: what --fix did, and what was found."""
    from scriptc.diagnostics.model import Severity

    lines = []
    if run.fixed:
        lines.append(f"fixed {_plural(run.fixed, 'problem')} in "
                     f"{_plural(run.fixed_files, 'file')}")
    if several:
        counts = {s: 0 for s in Severity}
        for result in run.results:
            for d in result.diagnostics:
                counts[d.severity] += 1
        found = [_plural(counts[Severity.ERROR], "error"),
                 _plural(counts[Severity.WARNING], "warning"),
                 _plural(counts[Severity.INFO], "info message")]
        found = [f for f, s in zip(found, Severity) if counts[s]] or ["no problems"]
        cached = f" ({run.cached} unchanged, from the cache)" if run.cached else ""
        line = f"checked {_plural(run.files, 'file')}{cached}: {', '.join(found)}"
        if run.fixable:
            line += (f"; {_plural(run.fixable, 'fix', 'fixes')} available "
                     f"(`scriptc lint --fix` applies {'it' if run.fixable == 1 else 'them'})")
        lines.append(line)
    return "".join(line + "\n" for line in lines)


# Below this many files no progress bar is shown: the run is over before one would help.
PROGRESS_MIN_FILES = 50


class Progress:
    """A rich progress bar on stderr, only on a terminal and only for many files (rich is
    imported then, and only then)."""

    def __init__(self, quiet: bool = False) -> None:
        self.enabled = not quiet and _stderr_is_terminal()
        self._bar = None
        self._task = None

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled or total < PROGRESS_MIN_FILES or done >= total and self._bar is None:
            return
        if self._bar is None:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, TextColumn, \
                TimeRemainingColumn
            from rich.progress import Progress as Bar

            # No refresh thread (auto_refresh off, refreshed on each update): worker
            # processes are forked while the bar runs, and a fork must not copy a thread
            # that may hold a lock.
            self._bar = Bar(TextColumn("linting"), BarColumn(), MofNCompleteColumn(),
                            TimeRemainingColumn(), console=Console(stderr=True), transient=True,
                            auto_refresh=False)
            self._bar.start()
            self._task = self._bar.add_task("lint", total=total)
        self._bar.update(self._task, completed=done, total=total)
        self._bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None


def _stderr_is_terminal() -> bool:
    if os.environ.get("TERM") == "dumb":
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


# ---------------------------------------------------------------------------------------------
# grouped text: one line per diagnostic, under its file (as ruff's `--output-format grouped`)


def _printable(text: str) -> str:
    return text if text.isprintable() else "".join(c if c.isprintable() else "\ufffd"
                                                   for c in text)


def render_grouped(results: list) -> str:
    """Each file with diagnostics, then one line per diagnostic: `  LINE:COL CODE [*] severity:
    message` (`[*]`: `--fix` can fix it), a blank line between files, and the summary."""
    from scriptc.diagnostics.render import summary

    out = []
    for result in results:
        if not result.diagnostics:
            continue
        source = result.source
        rows = []
        for d in result.diagnostics:
            pos = source.position(d.span.start)
            mark = "[*] " if d.fix is not None and d.fix.safe else ""
            rows.append((f"{pos.line}:{pos.column}", f"{d.code} {mark}{d.severity.value}: "
                                                     f"{_printable(d.message)}"))
        width = max(len(where) for where, _ in rows)
        out.append(f"{_printable(source.path)}:\n")
        out += [f"  {where:<{width}} {rest}\n" for where, rest in rows]
        out.append("\n")
    if out:
        out.append(summary(results) + "\n")
    return "".join(out)
