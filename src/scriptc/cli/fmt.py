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
was refused, 2 a path that does not exist, a file that cannot be read or written.
"""

from __future__ import annotations

import re

import click

from scriptc import driver, writing
from scriptc.cli.common import read_stdin, show, stdin_name_option, write, write_bytes

_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+$")


def unified_diff(old: str, new: str, name: str) -> str:
    """A unified diff of two texts, line endings kept, `\\ No newline at end of file` marked."""
    import difflib

    out = []
    for line in difflib.unified_diff(_LINES.findall(old), _LINES.findall(new),
                                     fromfile=name, tofile=name):
        if not line.endswith(("\n", "\r")):
            line += "\n\\ No newline at end of file\n"
        out.append(line)
    return "".join(out)


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
    from scriptc.formatter import format_text

    from scriptc.project.config import Resolver
    from scriptc.paths import shown_path

    # The same walk as `scriptc lint`: .gitignore and the configuration's exclusions; a path
    # that does not exist or a folder that cannot be read is named, and the others go on.
    files, missing = driver.discover(paths, resolver=Resolver())
    for problem in missing:
        write(f"error: {problem}\n", err=True)
    if not files and not missing:
        write("warning: no script files found under the given paths\n", err=True)
    dry = check or show_diff
    changed = refused = 0
    problems = len(missing)
    for path in files:
        name = shown_path(stdin_name if path == "-" else path)
        try:
            data = read_stdin() if path == "-" else driver.read_bytes(path)
        except driver.ReadError as exc:
            write(f"error: {exc}\n", err=True)
            problems += 1
            continue
        source, problem = driver.decode_source(name, data)
        result = None if problem is not None else format_text(source.text)
        if result is None or result.refused:
            diagnostics = [problem] if problem is not None else result.diagnostics
            if path == "-" and not dry:
                write_bytes(data)  # the input, unchanged: a pipe never loses its text
            if skip_invalid:
                write(f"warning: skipped `{name}`: it has syntax errors\n", err=True)
            else:
                show([driver.Analysis(source, None, diagnostics)], err=True)
                write(f"error: `{name}` was not formatted: fix its syntax errors first\n",
                      err=True)
                refused += 1
            continue
        new = writing.encode_like(result.text, data)
        if new == data:
            if path == "-" and not dry:
                write_bytes(data)
            continue
        changed += 1
        if show_diff:
            write_bytes(unified_diff(source.text, result.text, name).encode("utf-8"))
        if check and not show_diff:
            write(f"would reformat {name}\n")
        if dry:
            continue
        if path == "-":
            write_bytes(new)
            continue
        try:
            writing.write_file(path, new)
        except writing.WriteError as exc:
            write(f"error: {exc}: it was not reformatted\n", err=True)
            problems += 1
            continue
        write(f"reformatted {name}\n", err=True)
    if problems:
        ctx.exit(2)
    if refused or (dry and changed):
        ctx.exit(1)
