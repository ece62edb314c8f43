"""What the verbs share: the CLI's error type, input loading, colour choice and writing to
stdout/stderr, the run summary and progress bar of `lint`, and the grouped text format. Thin
glue over `scriptc.driver`; nothing here decides what a script means."""

from __future__ import annotations

import os
import sys
from typing import IO

import click

from scriptc import driver, interrupt, writing
from scriptc.paths import shown_path
from scriptc.diagnostics.render import FORMATS, render


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
            analysis = driver.analyze_bytes(shown_path(stdin_name), read_stdin(), kind,
                                            settings.registry, settings.robot)
        else:
            analysis = driver.analyze_file(path, kind, name=shown_path(path),
                                           functions=settings.registry,
                                           profile=settings.robot)
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


def show(results: list[driver.Analysis], *, err: bool = False) -> None:
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
    if driver.same_file(input_path, output_path):
        raise CliError(f"the output `{output_path}` is the input file itself: refusing to "
                       "overwrite it (choose another file with -o)")


def report_paths(ctx: click.Context, paths: tuple[str, ...], kind: str, format_: str,
                 stdin_name: str, options: driver.LintOptions | None = None, *,
                 quiet: bool = False, statistics: bool = False, output_file: str | None = None,
                 exit_zero: bool = False) -> None:
    """`lint` and `check`: `lint_report`, then exit with its status."""
    ctx.exit(lint_report(paths, kind, format_, stdin_name, options, quiet=quiet,
                         statistics=statistics, output_file=output_file, exit_zero=exit_zero))


def lint_report(paths: tuple[str, ...], kind: str, format_: str, stdin_name: str,
                options: driver.LintOptions | None = None, *, quiet: bool = False,
                statistics: bool = False, output_file: str | None = None,
                exit_zero: bool = False) -> int:
    """Analyse the paths (with their configuration, the cache and worker processes:
    `driver.lint_paths`), show the diagnostics on stdout (or in `output_file`), a summary on
    stderr when several files were read, and return the run's status (a file that cannot be
    read is named on stderr and makes it 2). `statistics` shows a count per code instead of
    the diagnostics; `options.diff` the unified diff of what the fixes would change instead
    (status 1 when there is one); `exit_zero` turns status 1 into 0."""
    options = options or driver.LintOptions()
    if output_file is not None:
        check_output(output_file)
    progress = Progress(quiet)
    options.progress = progress
    try:
        run = driver.lint_paths(paths, kind, stdin=read_stdin, stdin_name=stdin_name,
                                options=options)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    except KeyboardInterrupt:
        # Worker processes are stopped by then, and every file written so far (cache
        # entries, fixes) was put in place whole (`scriptc.writing`).
        progress.close()
        verb = "checking" if kind == "json" else "linting"
        how_far = (f"{progress.done} of {_plural(progress.total, 'file')} analysed"
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
        output = "".join(fix_diff(r) for r in run.results[run.configs:])
        emit_output(output, output_file)
        if not quiet:
            write(diff_summary(run), err=True)
        status = 2 if run.problems else 1 if run.fixed or driver.configuration_failed(configs) \
            else 0
    else:
        if statistics:
            output = render_statistics(run, format_)
        else:
            color = format_ == "text" and output_file is None and use_color(sys.stdout)
            output = rendered(run.results, format_, color=color, unsafe=options.unsafe_fixes)
        emit_output(output, output_file, human=format_ in ("text", "grouped"))
        if not quiet and (run.fixed or (several and run.files)):
            write(run_summary(run, several), err=True)
    return 0 if exit_zero and status == 1 else status


def rendered(results: list, format_: str, *, color: bool = False, unsafe: bool = False) -> str:
    """The diagnostics in one of the formats of `lint` (`grouped` marks with `[*]` what
    `--fix` fixes: with `unsafe`, the unsafe fixes too)."""
    if format_ == "grouped":
        return render_grouped(results, unsafe=unsafe)
    return render(format_, results, color=color)


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
    if getattr(report, "fixed_text", None) is None:
        return ""
    from scriptc.cli.fmt import unified_diff

    return unified_diff(report.source.text, report.fixed_text, report.source.path)


def diff_summary(run: driver.LintRun) -> str:
    """The line `scriptc lint --diff` ends with on stderr."""
    if run.fixed:
        line = (f"would fix {_plural(run.fixed, 'problem')} in "
                f"{_plural(run.fixed_files, 'file')}")
    else:
        line = "nothing to fix"
    if run.hidden_fixes:
        line += f" ({_plural(run.hidden_fixes, 'more fix', 'more fixes')} with `--unsafe-fixes`)"
    return line + "\n"


def render_statistics(run: driver.LintRun, format_: str) -> str:
    """`lint --statistics`: how many diagnostics of each code, most frequent first (then by
    code), with the code's name and `[*]` when `--fix` fixes every one of them (as ruff's);
    as text, or as JSON (`code`, `name`, `severity`, `count`, `fixable`) with `--format json`."""
    from scriptc.diagnostics.codes import lookup

    counts: dict[str, list] = {}
    for result in run.results:
        for d in result.diagnostics:
            applies = d.fix is not None and (run.unsafe_fixes or d.fix.safe)
            entry = counts.setdefault(d.code, [0, True, d.severity.value])
            entry[0] += 1
            entry[1] = entry[1] and applies
    rows = sorted(counts.items(), key=lambda item: (-item[1][0], item[0]))
    if format_ == "json":
        import json

        records = [{"code": code, "name": lookup(code).name, "severity": severity,
                    "count": count, "fixable": fixable}
                   for code, (count, fixable, severity) in rows]
        return json.dumps(records, indent=2, ensure_ascii=False) + "\n"
    if not rows:
        return ""
    width = max(len(str(count)) for _code, (count, _f, _s) in rows)
    any_fixable = any(fixable for _code, (_c, fixable, _s) in rows)
    lines = []
    for code, (count, fixable, _severity) in rows:
        mark = ("[*] " if fixable else "    ") if any_fixable else ""
        lines.append(f"{count:>{width}}\t{code}\t{mark}{lookup(code).name}\n")
    return "".join(lines)


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
            flags = "--fix --unsafe-fixes" if run.unsafe_fixes else "--fix"
            line += (f"; {_plural(run.fixable, 'fix', 'fixes')} available "
                     f"(`scriptc lint {flags}` applies {'it' if run.fixable == 1 else 'them'})")
        hidden = run.hidden_fixes  # unsafe fixes, left out without --unsafe-fixes
        if hidden and run.fixable:
            line += f", {hidden} more with `--unsafe-fixes`"
        elif hidden:
            line += (f"; {_plural(hidden, 'unsafe fix', 'unsafe fixes')} available (`scriptc "
                     f"lint --fix --unsafe-fixes` applies {'it' if hidden == 1 else 'them'})")
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
        self.done = self.total = 0  # the last figures, for the message of an interruption

    def __call__(self, done: int, total: int) -> None:
        self.done, self.total = done, total
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


def render_grouped(results: list, *, unsafe: bool = False) -> str:
    """Each file with diagnostics, then one line per diagnostic: `  LINE:COL CODE [*] severity:
    message` (`[*]`: `--fix` can fix it; with `unsafe`, `--fix --unsafe-fixes`), a blank line
    between files, and the summary."""
    from scriptc.diagnostics.render import summary

    out = []
    for result in results:
        if not result.diagnostics:
            continue
        source = result.source
        rows = []
        for d in result.diagnostics:
            pos = source.position(d.span.start)
            mark = "[*] " if d.fix is not None and (unsafe or d.fix.safe) else ""
            rows.append((f"{pos.line}:{pos.column}", f"{d.code} {mark}{d.severity.value}: "
                                                     f"{_printable(d.message)}"))
        width = max(len(where) for where, _ in rows)
        out.append(f"{_printable(source.path)}:\n")
        out += [f"  {where:<{width}} {rest}\n" for where, rest in rows]
        out.append("\n")
    if out:
        out.append(summary(results) + "\n")
    return "".join(out)
