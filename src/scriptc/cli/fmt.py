"""`scriptc fmt PATH... [--check] [--diff] [--skip-invalid]`: rewrite scripts in the
canonical layout (`scriptc.formatter`; the decisions are in docs/editors.md, "Formatting").

Files are rewritten in place, atomically, and only when they change; folders are searched for
`*.script` files as `lint` does; `-` formats stdin to stdout. `--check` lists the files that
would change, `--diff` shows how; neither writes anything. A file with syntax errors (or that
is not UTF-8 text) is never rewritten: its diagnostics go to stderr and it counts as a
failure, unless `--skip-invalid`, which names it as skipped and lets the run pass. Read from
stdin, such a file is written back to stdout unchanged, so an editor that pipes its buffer
through `scriptc fmt -` never loses it.

Exit status: 0 done (or nothing to change), 1 a file would change (`--check`, `--diff`) or
was refused, 2 a path that does not exist, a file that cannot be read or written. The work is
`scriptc.ops.format.FormatRun`'s; this module reports each file's outcome.
"""

from __future__ import annotations

import click

from scriptc.cli.common import read_stdin, show, stdin_name_option, write, write_bytes


@click.command("fmt")
@click.argument("paths", nargs=-1, required=True)
@click.option("--check", is_flag=True,
              help="Write nothing; list the files that would change and exit 1 if any.")
@click.option("--diff", "show_diff", is_flag=True,
              help="Write nothing; print a unified diff of each file that would change and "
                   "exit 1 if any.")
@click.option("--skip-invalid", is_flag=True,
              help="Skip files with syntax errors (named on stderr) instead of failing; they "
                   "are never rewritten either way.")
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], check: bool, show_diff: bool,
            skip_invalid: bool, stdin_name: str) -> None:
    """Format scripts in the canonical layout: files, folders (every *.script inside,
    recursively) or - (stdin to stdout).

    Comments are kept where they were and the compiled JSON does not change. Files with
    syntax errors are never rewritten.
    """
    from scriptc.ops.format import FileFormat, FormatRun, unified_diff

    run = FormatRun(paths, stdin=read_stdin, stdin_name=stdin_name, dry=check or show_diff,
                    skip_invalid=skip_invalid)
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    if not run.files and not run.problems:
        write("warning: no script files found under the given paths\n", err=True)
    for done in run:
        if done.stdout is not None:
            write_bytes(done.stdout)  # stdin's text, formatted or as it came
        if done.status == FileFormat.UNREADABLE:
            write(f"error: {done.error}\n", err=True)
        elif done.status == FileFormat.REFUSED and skip_invalid:
            write(f"warning: skipped `{done.name}`: it has syntax errors\n", err=True)
        elif done.status == FileFormat.REFUSED:
            show([done.analysis], err=True)
            write(f"error: `{done.name}` was not formatted: fix its syntax errors first\n",
                  err=True)
        elif done.status == FileFormat.CHANGED:
            if show_diff:
                write_bytes(unified_diff(done.old, done.new, done.name).encode("utf-8"))
            else:
                write(f"would reformat {done.name}\n")
        elif done.status == FileFormat.UNWRITTEN:
            write(f"error: {done.error}: it was not reformatted\n", err=True)
        elif done.status == FileFormat.REFORMATTED and done.path != "-":
            write(f"reformatted {done.name}\n", err=True)
    ctx.exit(run.exit_code)
