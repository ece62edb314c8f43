"""`scriptc compile FILE [-o OUT] [--emit json|bytecode]`: a script to thesis JSON (the
default) or to bytecode (`.scb`, with the source's lines in its span table).

Without `-o` the output goes beside the input with the back end's suffix (`dance.script` ->
`dance.json`); input from stdin (`-`) goes to stdout; `-o -` writes to stdout. The output is
written only when the script has no error, atomically (a temporary file renamed over the
target), and never over the input file itself. Diagnostics go to stderr as text. A `.json`
input is thesis JSON, which `check` and `decompile` read: compile refuses it and says so.
"""

from __future__ import annotations

import click

from scriptc.cli.common import (
    CliError,
    check_output,
    load,
    refuse_overwriting_input,
    show,
    stdin_name_option,
    write_output,
)
from scriptc.ops.build import EMITTERS, default_output, emit
from scriptc.source import SourceKind


@click.command("compile")
@click.argument("file")
@click.option("-o", "--output", metavar="OUT",
              help="Output file (- for stdout). Default: FILE with the back end's suffix.")
@click.option("--emit", "back_end", type=click.Choice(list(EMITTERS)), default="json",
              show_default=True, help="Back end.")
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, file: str, output: str | None, back_end: str,
            stdin_name: str) -> None:
    """Compile a script (- for stdin) to thesis JSON or bytecode (--emit bytecode).

    Without -o the output goes beside FILE with the back end's suffix (dance.script ->
    dance.json, dance.scb), or to stdout when FILE is -. Nothing is written when the script has
    errors, and never over FILE itself. Diagnostics go to stderr.
    """
    named = stdin_name if file == "-" else file
    if named.lower().endswith(".json"):
        raise CliError(f"`{named}` is thesis JSON, not script syntax: `scriptc check {named}` "
                       f"checks it, `scriptc decompile {named}` turns it into a script")
    output = output or default_output(file, back_end)
    refuse_overwriting_input(file, output)
    check_output(output)
    analysis = load(file, SourceKind.SCRIPT, stdin_name)
    show([analysis], err=True)
    if not analysis.ok:
        ctx.exit(1)
    assert analysis.script is not None  # `ok`: the script was read
    write_output(output, emit(analysis.script, back_end, analysis.source))
