"""`scriptc check FILE.json...`: read thesis JSON and run the same checks as for scripts.

Diagnostics go to stdout in the chosen format; positions are in the JSON file. Exit status as
for `lint`.
"""

from __future__ import annotations

import click

from scriptc import driver
from scriptc.cli._shell import CliError, format_option, read_stdin, show, stdin_name_option, write


@click.command("check")
@click.argument("files", nargs=-1, required=True)
@format_option
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, files: tuple[str, ...], format_: str, stdin_name: str) -> None:
    """Check thesis JSON files (- for stdin)."""
    try:
        run = driver.analyze_paths(files, "json", stdin=read_stdin, stdin_name=stdin_name)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    show(run.results, format_)
    ctx.exit(run.exit_code)
