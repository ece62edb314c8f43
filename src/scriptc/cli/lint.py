"""`scriptc lint PATH...`: the diagnostics of script files, folders of them, or stdin (`-`).

Folders are searched recursively for `*.script` files, sorted, hidden folders skipped; a file
named explicitly is read whatever its suffix. Diagnostics go to stdout in the chosen format.
Exit status: 0 no errors (warnings alone pass), 1 errors, 2 a path that does not exist or a
file that cannot be read (the readable files are still reported).
"""

from __future__ import annotations

import click

from scriptc.cli._shell import format_option, report_paths, stdin_name_option


@click.command("lint")
@click.argument("paths", nargs=-1, required=True)
@format_option
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], format_: str, stdin_name: str) -> None:
    """Report the diagnostics of scripts: files, folders (every *.script inside,
    recursively) or - for stdin."""
    report_paths(ctx, paths, "script", format_, stdin_name)
