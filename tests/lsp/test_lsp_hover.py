"""Hover over stdio: blocks (duration, tracks, targets), labels (where and which path),
functions (signature and documentation), diagnostic codes (their explanation)."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from lsptest import Doc

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
[greet]
[alfa:0, kick_starter, "", "", R, U]
[omega:0, kick_starter, "", "", C, L]
[goal:wave]
  [action]
    [b#start#blk_inst: MV("0.25, 0, 0, 0, 1500") LD("1, 0, 0, 1, 500, 2000") AO()]
    [b##blk_jump: CND({CLASS #Human U ?kid (B: near(2))} ! {E: gt(?kid>&permanencetime, 10)})
                  TRJMP(start) FLSJMP(end)]
    [b#end#blk_terminus]   % scriptc: ignore[F003] %
"""


async def hover(doc: Doc, marker: str, delta: int = 1) -> lsp.Hover | None:
    return await doc.client.text_document_hover_async(
        lsp.HoverParams(doc.id, doc.at(marker, delta)))


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def doc(client):
    return await Doc.open(client, "hover.script", TEXT)


async def test_block_duration_and_tracks(doc):
    h = await hover(doc, "blk_inst")
    text = h.contents.value
    assert h.contents.kind == lsp.MarkupKind.Markdown
    assert "`goal0/act0/blk0`" in text and "2500 ms (2.5 s)" in text
    assert "`MV`: 1 move, 1500 ms" in text and "LEDs rgb(1, 0, 0)" in text
    assert doc.range_text(h.range).startswith("[b#start#blk_inst")


async def test_jump_block_targets(doc):
    text = (await hover(doc, "TRJMP(start)")).contents.value
    assert "if true: `start` → `goal0/act0/blk0`" in text
    assert "if false: `end` → `goal0/act0/blk2`" in text


async def test_label_where_and_path(doc):
    h = await hover(doc, "TRJMP(start)", len("TRJMP(s"))
    assert doc.range_text(h.range) == "start"
    assert "`start` → `goal0/act0/blk0`" in h.contents.value
    assert "line 6" in h.contents.value


async def test_function_signature_and_documentation(doc):
    h = await hover(doc, "near(", 2)
    assert doc.range_text(h.range) == "near"
    assert "B: near(distance)" in h.contents.value and "`distance`: metres" in h.contents.value


async def test_code_in_a_suppression_comment(doc):
    h = await hover(doc, "F003", 2)
    assert doc.range_text(h.range) == "F003"
    assert h.contents.value.startswith("**F003** `no-terminus`")
    assert "## What it means" in h.contents.value


async def test_activity_and_nothing_between_items(doc):
    h = await hover(doc, "greet", 2)
    assert h.contents.value == "**activity** `greet`: 1 goal, 3 blocks"
    blank = lsp.HoverParams(doc.id, lsp.Position(8, 26))  # the spaces before the comment
    assert await doc.client.text_document_hover_async(blank) is None
