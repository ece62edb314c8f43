"""`scriptc decompile FILE.json [-o OUT]`: thesis JSON back to script syntax.

The script text goes to stdout, or to OUT (atomically, never over the input). It is written
whenever the JSON reads into a script, even when the checks then find errors: turning a faulty
thesis file into script syntax is how one fixes it. Diagnostics go to stderr; the exit status
is 1 when any is an error.
"""

from __future__ import annotations

import click

from scriptc.cli.common import (
    check_output,
    load,
    refuse_overwriting_input,
    show,
    stdin_name_option,
    write_output,
)
from scriptc.ops.build import decompile
from scriptc.source import SourceKind


@click.command("decompile")
@click.argument("file")
@click.option("-o", "--output", metavar="OUT", default="-", help="Output file (default: stdout).")
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, file: str, output: str, stdin_name: str) -> None:
    """Turn a thesis JSON file (- for stdin) back into script syntax.

    The script goes to stdout, or to OUT. It is written whenever the JSON reads into a script,
    even when the checks find errors in it (the exit status is then 1). Diagnostics go to
    stderr.
    """
    refuse_overwriting_input(file, output)
    check_output(output)
    analysis = load(file, SourceKind.JSON, stdin_name)
    show([analysis], err=True)
    if analysis.script is None:
        ctx.exit(1)
    write_output(output, decompile(analysis.script))
    ctx.exit(0 if analysis.ok else 1)
