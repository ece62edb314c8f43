"""Inlay hints over stdio: each block's path and each instruction block's duration, after
the block, for the blocks in the requested range."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from lsptest import Doc

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
[greet]
[goal:wave]
  [action]
    [b#start#blk_inst: MV("0.25, 0, 0, 0, 1500") LD() AO("Silence, 250, 2000")]
    [b##blk_jump: CND(! {TRUE}) TRJMP(start) FLSJMP()]
  [action]
    [b##blk_terminus]
"""


async def test_paths_and_durations(client):
    doc = await Doc.open(client, "hints.script", TEXT)
    whole = lsp.Range(lsp.Position(0, 0), doc.position(len(TEXT)))
    hints = await client.text_document_inlay_hint_async(lsp.InlayHintParams(doc.id, whole))
    got = [(h.position.line, h.label) for h in hints]
    assert got == [(3, "goal0/act0/blk0"), (3, "2.25 s"), (4, "goal0/act0/blk1"),
                   (6, "goal0/act1/blk0")]
    first = hints[0]
    assert first.position == doc.position(doc.text.index("]\n    [b##blk_jump") + 1)
    assert first.padding_left


async def test_only_the_range(client):
    doc = await Doc.open(client, "hints-range.script", TEXT)
    line = lsp.Range(lsp.Position(6, 0), lsp.Position(6, 10))
    hints = await client.text_document_inlay_hint_async(lsp.InlayHintParams(doc.id, line))
    assert [h.label for h in hints] == ["goal0/act1/blk0"]
