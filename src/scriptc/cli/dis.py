"""`scriptc dis FILE.scb`: the readable listing of a bytecode file (docs/bytecode.md).

The file is decoded and verified first, as a runtime would: a malformed or invalid file is
refused with the reason on stderr and exit 1; a file that cannot be read at all exits 2.
"""

from __future__ import annotations

import click

from scriptc.analysis.read import ReadError, read_bytes
from scriptc.cli.common import CliError, read_stdin, write


@click.command("dis")
@click.argument("file")
@click.pass_context
def command(ctx: click.Context, file: str) -> None:
    """Print the listing of a bytecode file (- for stdin), after verifying it.

    Exit status: 0 listed, 1 the file is not a valid program, 2 the file cannot be read.
    """
    from scriptc.bytecode import BytecodeError, disassemble, load

    try:
        data = read_stdin() if file == "-" else read_bytes(file)
    except ReadError as exc:
        raise CliError(str(exc)) from None
    try:
        program = load(data).program
    except BytecodeError as exc:
        write(f"error: {'<stdin>' if file == '-' else file}: {exc}\n", err=True)
        ctx.exit(1)
    write(disassemble(program))
