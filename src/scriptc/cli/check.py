"""`scriptc check PATH...`: read thesis JSON and run the same checks as for scripts.

PATH is a JSON file (read whatever its suffix), `-` for stdin, or a folder: every `.json` file
under it that is a thesis script (`scriptc.project.files.is_thesis_json`: not a scenario), walked as
`lint` walks folders. Diagnostics go to stdout in the chosen format; positions are in the JSON
file. Exit status as for `lint`.
"""

from __future__ import annotations

import click

from scriptc.cli.common import format_option, report_paths, stdin_name_option
from scriptc.source import SourceKind


@click.command("check")
@click.argument("files", nargs=-1, required=True)
@format_option
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, files: tuple[str, ...], format_: str, stdin_name: str) -> None:
    """Check thesis JSON files: files, folders (every JSON script inside, recursively) or -
    for stdin."""
    report_paths(ctx, files, SourceKind.JSON, format_, stdin_name)
