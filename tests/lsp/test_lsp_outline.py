"""Document symbols (activity > goals > actions > blocks) and folding ranges over stdio."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from lsptest import Doc

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
% two
  lines %
[greet]
[alfa:0, kick_starter, "", "", R, U]
[omega:0, kick_starter, "", "", C, L]
[goal:wave]
  [action]
    [b#start#blk_inst: MV("0, 0, 0.5, 0, 1000")
                       LD() AO()]
    [b##blk_terminus]
[goal:rest]
  [action]
    [b##blk_sens]
"""


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def doc(client):
    return await Doc.open(client, "outline.script", TEXT)


async def test_outline(doc):
    symbols = await doc.client.text_document_document_symbol_async(lsp.DocumentSymbolParams(doc.id))
    (activity,) = symbols
    assert activity.name == "greet" and activity.kind == lsp.SymbolKind.Module

    def tree(s):
        return (s.name, [tree(c) for c in s.children or ()])

    assert tree(activity)[1] == [
        ("alfa kick_starter", []), ("omega kick_starter", []),
        ("wave", [("act0", [("start", []), ("blk_terminus", [])])]),
        ("rest", [("act0", [("blk_sens", [])])]),
    ]
    wave = activity.children[2]
    assert wave.kind == lsp.SymbolKind.Namespace
    assert doc.range_text(wave.selection_range) == "wave"
    assert (wave.range.start.line, wave.range.end.line) == (5, 9)
    start = wave.children[0].children[0]
    assert start.detail == "blk_inst · goal0/act0/blk0 · 1000 ms (1 s)"


async def test_folding(doc):
    folds = await doc.client.text_document_folding_range_async(lsp.FoldingRangeParams(doc.id))
    got = sorted((f.start_line, f.end_line, f.kind) for f in folds)
    assert got == [(0, 1, lsp.FoldingRangeKind.Comment), (3, 4, lsp.FoldingRangeKind.Region),
                   (5, 9, lsp.FoldingRangeKind.Region), (6, 9, lsp.FoldingRangeKind.Region),
                   (7, 8, lsp.FoldingRangeKind.Region), (10, 12, lsp.FoldingRangeKind.Region),
                   (11, 12, lsp.FoldingRangeKind.Region)]
