"""`scriptc graph` as library calls (docs/views.md "The flow graph"): the formats and the
suffixes of their files, the format an output's name asks for, a checked script's graph in a
format (`graph_of`), and a folder's scripts drawn into a folder of graphs with the same
structure (`graph_folder`).

A script with errors has no graph (its diagnostics are reported as `scriptc compile` reports
them); neither has a script whose configuration has an error. No graph is written over a
script being read.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field

from scriptc.analysis.analyze import Analysis
from scriptc.analysis.read import ReadError
from scriptc.ir.nodes import Script
from scriptc.ops.build import read_configured
from scriptc.paths import same_file, shown_path
from scriptc.project.files import discover
from scriptc.project.setup import Setup, setup_for
from scriptc.source import SourceFile, SourceKind
from scriptc.writing import WriteError, write_file

__all__ = ["FORMATS", "GraphFile", "GraphRun", "format_for", "graph_folder", "graph_of",
           "output_path"]

# The formats of `scriptc graph --format` and the suffix of the files each writes.
FORMATS: dict[str, str] = {"dot": ".dot", "mermaid": ".mmd", "svg": ".svg"}
# The format an output file's suffix asks for when `--format` is not given.
_BY_SUFFIX = {".dot": "dot", ".gv": "dot", ".mmd": "mermaid", ".mermaid": "mermaid",
              ".svg": "svg"}
DEFAULT_FORMAT = "dot"


def format_for(output: str | None, given: str | None) -> str:
    """The format asked: `given` (`--format`), else the one the output's suffix names
    (`flow.svg`: svg; `.dot` or `.gv`: dot; `.mmd` or `.mermaid`: mermaid), else dot."""
    if given is not None:
        return given
    if output is not None and output != "-":
        return _BY_SUFFIX.get(os.path.splitext(output)[1].lower(), DEFAULT_FORMAT)
    return DEFAULT_FORMAT


def graph_of(script: Script, source: SourceFile | None, format_: str) -> str | bytes:
    """The flow graph of a checked script in a format: DOT or Mermaid text, or SVG bytes
    (raises `scriptc.views.graph.GraphvizError` when Graphviz cannot draw it)."""
    from scriptc.views.graph import flow_graph, to_dot, to_mermaid, to_svg

    graph = flow_graph(script, source)
    if format_ == "svg":
        return to_svg(graph)
    if format_ == "mermaid":
        return to_mermaid(graph)
    if format_ != "dot":
        raise ValueError(f"unknown graph format {format_!r}")
    return to_dot(graph)


def output_path(path: str, folder: str, outdir: str, format_: str) -> str:
    """Where the graph of the script `path`, found in `folder`, goes in `outdir`: the same
    place relative to it, the suffix the format's (`a/b.script` -> `OUTDIR/a/b.svg`)."""
    relative = os.path.relpath(path, folder)
    root, _ext = os.path.splitext(relative)
    return os.path.join(outdir, root + FORMATS[format_])


@dataclass
class GraphFile:
    """One script of a folder: its graph's file (`output`), its analysis (None when it was
    not read), its setup, why no graph was written (`problem`, empty when one was) and the
    status that gives (1: errors in the script or its configuration; 2: it could not be read
    or its graph written)."""

    path: str
    output: str
    analysis: Analysis | None = None
    setup: Setup | None = None
    problem: str = ""
    status: int = 0

    @property
    def written(self) -> bool:
        return not self.problem


@dataclass
class GraphRun:
    """The graphs of a folder: each script's, and the problems met finding them."""

    files: list[GraphFile] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        """2: a path or file could not be read or written; 1: a script (or its
        configuration) has errors; else 0."""
        statuses = [f.status for f in self.files] + [2 for _ in self.problems]
        return max(statuses, default=0)


def graph_folder(folder: str, outdir: str, format_: str,
                 on_file: Callable[[GraphFile], None] | None = None) -> GraphRun:
    """Draw every script under `folder` (found as `scriptc lint` finds them: hidden files,
    .gitignore and the configuration's `exclude` skipped) into `outdir`, each at
    `output_path`, the folders made as needed. `on_file` is told of each file when it is
    done. Raises `scriptc.views.graph.GraphvizMissing` before any work when `format_` is svg
    and Graphviz is not installed."""
    if format_ == "svg":
        from scriptc.views.graph import dot_program

        dot_program()
    paths, problems = discover([folder])
    run = GraphRun(problems=problems)
    for path in paths:
        done = _graph_one(path, output_path(path, folder, outdir, format_), format_, paths)
        run.files.append(done)
        if on_file is not None:
            on_file(done)
    return run


def _graph_one(path: str, output: str, format_: str, inputs: list[str]) -> GraphFile:
    from scriptc.views.graph import GraphvizError

    out = GraphFile(path, output)
    if any(same_file(output, p) for p in inputs):
        out.problem = (f"the graph `{shown_path(output)}` would overwrite a script being read: "
                       "refusing (choose another -o folder)")
        out.status = 2
        return out
    setup = out.setup = setup_for(path)
    if setup.failed:
        out.problem = f"`{shown_path(path)}`: its configuration has errors: no graph"
        out.status = 1
        return out
    try:
        analysis = out.analysis = read_configured(path, SourceKind.SCRIPT, setup)
    except ReadError as exc:
        out.problem, out.status = str(exc), 2
        return out
    if not analysis.ok or analysis.script is None:
        out.problem, out.status = f"`{analysis.source.path}` has errors: no graph", 1
        return out
    try:
        data = graph_of(analysis.script, analysis.source, format_)
        os.makedirs(os.path.dirname(output) or ".", exist_ok=True)
        write_file(output, data)
    except (GraphvizError, WriteError) as exc:
        out.problem, out.status = str(exc), 2
    except OSError as exc:  # the folder could not be made
        out.problem = f"cannot write `{shown_path(output)}`: {(exc.strerror or str(exc)).lower()}"
        out.status = 2
    return out
