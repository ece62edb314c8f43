"""`scriptc lint PATH...`: the diagnostics of script files, folders of them, or stdin (`-`).

Folders are searched recursively for `*.script` files, sorted, hidden folders skipped; a file
named explicitly is read whatever its suffix. Diagnostics go to stdout in the chosen format.
Exit status: 0 no errors (warnings alone pass), 1 errors, 2 a path that does not exist or a
file that cannot be read (the readable files are still reported).
"""

from __future__ import annotations

import click

from scriptc import driver
from scriptc.cli._shell import CliError, format_option, read_stdin, show, stdin_name_option, write


@click.command("lint")
@click.argument("paths", nargs=-1, required=True)
@format_option
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], format_: str, stdin_name: str) -> None:
    """Report the diagnostics of scripts: files, folders (every *.script inside, recursively)
    or - for stdin."""
    try:
        run = driver.analyze_paths(paths, "script", stdin=read_stdin, stdin_name=stdin_name)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if not run.results and not run.problems:
        write("warning: no script files found under the given paths\n", err=True)
    show(run.results, format_)
    ctx.exit(run.exit_code)
