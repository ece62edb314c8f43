"""`scriptc graph FILE [--format dot|mermaid|svg] [-o OUT]`: the flow of a script, drawn
(docs/views.md "The flow graph"): goals as clusters, blocks as nodes, each jump's two outcomes
as edges labelled with its condition.

FILE's graph goes to stdout, or to OUT; `--format` is dot (Graphviz), mermaid (GitHub
Markdown) or svg (drawn by Graphviz's `dot`, which must be installed); without it, OUT's
suffix chooses (`flow.svg`), else dot. `scriptc graph DIR -o OUTDIR` draws every script
under DIR into OUTDIR, keeping the folders. A script with errors has no graph: its
diagnostics go to stderr, as `scriptc compile` shows them, and the status is 1. The work is
`scriptc.ops.graph`'s.
"""

from __future__ import annotations

import os

import click

from scriptc.cli.common import (
    CliError,
    check_output,
    load,
    refuse_overwriting_input,
    show,
    stdin_name_option,
    write,
    write_output,
)
from scriptc.ops.graph import FORMATS
from scriptc.source import SourceKind


@click.command("graph")
@click.argument("path", metavar="FILE|DIR")
@click.option("--format", "format_", type=click.Choice(list(FORMATS)), default=None,
              help="dot (Graphviz's language), mermaid (a flowchart GitHub renders) or svg "
                   "(drawn by Graphviz's dot). Default: OUT's suffix, else dot.")
@click.option("-o", "--output", metavar="OUT",
              help="Output file (- for stdout, the default); for a folder DIR, the folder "
                   "the graphs go to (needed).")
@stdin_name_option
@click.pass_context
def command(ctx: click.Context, path: str, format_: str | None, output: str | None,
            stdin_name: str) -> None:
    """Draw the flow of a script (- for stdin): goals, blocks, jumps and their conditions.

    The graph goes to stdout, or to OUT. With a folder DIR, every script under it is drawn
    into the folder OUTDIR (-o, needed), one file per script, the folders kept. A script with
    errors is not drawn (its diagnostics go to stderr; status 1). SVG needs Graphviz.
    """
    from scriptc.ops.graph import format_for

    if path != "-" and os.path.isdir(path):
        _folder(ctx, path, output, format_ or "dot")
        return
    format_ = format_for(output, format_)
    output = output or "-"
    if format_ == "svg":
        _need_graphviz()
    kind = SourceKind.of_path(stdin_name if path == "-" else path)
    if kind is SourceKind.BYTECODE:
        raise CliError(f"`{path}` is bytecode, which keeps no goals or labels to draw: "
                       "graph the script it was compiled from")
    refuse_overwriting_input(path, output)
    check_output(output)
    analysis = load(path, kind, stdin_name)
    show([analysis], err=True)
    if not analysis.ok:
        ctx.exit(1)
    assert analysis.script is not None  # `ok`: the script was read
    write_output(output, _drawn(analysis, format_))


def _need_graphviz() -> None:
    from scriptc.views.graph import GraphvizMissing, dot_program

    try:
        dot_program()
    except GraphvizMissing as exc:
        raise CliError(str(exc)) from None


def _drawn(analysis, format_: str) -> str | bytes:
    from scriptc.ops.graph import graph_of
    from scriptc.views.graph import GraphvizError

    try:
        return graph_of(analysis.script, analysis.source, format_)
    except GraphvizError as exc:
        raise CliError(str(exc)) from None


def _folder(ctx: click.Context, folder: str, outdir: str | None, format_: str) -> None:
    from scriptc.ops.graph import graph_folder
    from scriptc.paths import shown_path

    if outdir is None or outdir == "-":
        raise CliError(f"`{shown_path(folder)}` is a folder: its graphs go to a folder, "
                       "named with -o OUTDIR (one file per script, the folders kept)")
    if os.path.exists(outdir) and not os.path.isdir(outdir):
        raise CliError(f"`{shown_path(outdir)}` is not a folder: with a folder DIR, -o names "
                       "the folder the graphs go to")
    if format_ == "svg":
        _need_graphviz()
    shown_configs: set[str] = set()

    def report(done) -> None:
        if done.setup is not None:
            fresh = [p for p in done.setup.problems if p.source.path not in shown_configs]
            shown_configs.update(p.source.path for p in fresh)
            if fresh:
                show([(p.source, p.diagnostics) for p in fresh], err=True)
        if done.analysis is not None and done.analysis.diagnostics:
            show([done.analysis], err=True)
        if done.problem:
            write(f"error: {done.problem}\n", err=True)

    run = graph_folder(folder, outdir, format_, on_file=report)
    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    written = sum(1 for f in run.files if f.written)
    failed = len(run.files) - written
    if not run.files and not run.problems:
        write(f"warning: no script files found under `{shown_path(folder)}`\n", err=True)
    else:
        graphs = "graph" if written == 1 else "graphs"
        skipped = f" ({failed} not drawn)" if failed else ""
        write(f"wrote {written} {graphs} to `{shown_path(outdir)}`{skipped}\n", err=True)
    ctx.exit(run.exit_code)
