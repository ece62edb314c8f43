"""The `graph` aspect of case files: the flow graph `scriptc graph` draws of a script.

Under tests/cases/graph/, `NAME.script` is a case (it has its lint `.diagnostics` too, as
every script of the cases, and no errors: a script with errors has no graph); beside it
`NAME.dot` and `NAME.mmd`, what `scriptc graph --format dot` and `--format mermaid` write.
Each graph is drawn twice: the two must be the same bytes. (The SVG is Graphviz's drawing of
the DOT, and its bytes depend on Graphviz's version: tests/test_views_graph.py draws it.)
"""

from __future__ import annotations

from pathlib import Path

from harness import Check, beside, expect, files
from harness.aspects import analysis


def outputs(path: Path) -> dict[str, str]:
    """The DOT and the Mermaid text of the case `path`, by suffix."""
    from scriptc.ops.graph import graph_of

    found = analysis(path)
    assert found.ok and found.script is not None, "a graph case must have no error"
    drawn = {}
    for suffix, format_ in ((".dot", "dot"), (".mmd", "mermaid")):
        first = graph_of(found.script, found.source, format_)
        assert first == graph_of(found.script, found.source, format_), "two drawings differ"
        assert isinstance(first, str)
        drawn[suffix] = first
    return drawn


def _case(path: Path) -> None:
    for suffix, text in outputs(path).items():
        expect(beside(path, suffix), text)


def checks() -> list[Check]:
    return [Check("graph", p, (beside(p, ".dot"), beside(p, ".mmd")), lambda p=p: _case(p))
            for p in files("graph", "*.script")]
