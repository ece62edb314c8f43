"""What the verbs share: the CLI's error type, input loading, colour choice and writing to
stdout/stderr. Thin glue over `scriptc.driver`; nothing here decides what a script means."""

from __future__ import annotations

import os
import sys
from typing import IO

import click

from scriptc import driver
from scriptc.diagnostics.render import FORMATS, render


class CliError(click.ClickException):
    """A problem with the command or its files (not with the script): exit 2."""

    exit_code = 2

    def show(self, file: IO[str] | None = None) -> None:
        click.echo(f"error: {self.format_message()}", err=True)


def format_option(function):
    return click.option("--format", "format_", type=click.Choice(FORMATS), default="text",
                        show_default=True, help="Output format of the diagnostics.")(function)


def stdin_name_option(function):
    return click.option("--stdin-filename", "stdin_name", default="<stdin>", metavar="NAME",
                        help="The file name shown for input read from `-` (stdin).")(function)


def read_stdin() -> bytes:
    return sys.stdin.buffer.read()


def load(path: str, kind: str, stdin_name: str = "<stdin>") -> driver.Analysis:
    """Analyse one file (or stdin for `-`); an unreadable file is a CliError."""
    try:
        if path == "-":
            return driver.analyze_bytes(stdin_name, read_stdin(), kind)
        return driver.analyze_file(path, kind)
    except driver.ReadError as exc:
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


def show(results: list[driver.Analysis], format_: str = "text", *, err: bool = False) -> None:
    """Render diagnostics (text to a terminal in colour when `--color` allows it)."""
    stream = sys.stderr if err else sys.stdout
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
                 stdin_name: str) -> None:
    """`lint` and `check`: analyse the paths, show the diagnostics on stdout, exit with the
    run's status (a file that cannot be read is named on stderr and makes it 2)."""
    try:
        run = driver.analyze_paths(paths, kind, stdin=read_stdin, stdin_name=stdin_name)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if not run.results and not run.problems:
        write("warning: no script files found under the given paths\n", err=True)
    show(run.results, format_)
    ctx.exit(run.exit_code)
