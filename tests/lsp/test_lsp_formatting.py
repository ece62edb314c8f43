"""Formatting over stdio, through the formatter's API (scriptc.formatter): the whole document as
one minimal edit, a range as the formatter's edits, nothing for a text that does not parse."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from lsptest import Doc, apply_edits

from scriptc.formatter import format_text

pytestmark = pytest.mark.asyncio(loop_scope="module")

MESSY = ("% keep me %\n[a]\n[goal:g]\n[action]\n[b#é😀x##blk_inst:MV()LD()AO()]\n"
         "[b##blk_inst:MV()LD()AO()]\n[b##blk_terminus]\n")
MESSY = MESSY.replace("[b#é😀x##blk_inst:MV()LD()AO()]\n", "% é 😀 %[b##blk_inst:MV()LD()AO()]\n")
OPTIONS = lsp.FormattingOptions(tab_size=4, insert_spaces=True)


async def test_format_document(client):
    doc = await Doc.open(client, "fmt.script", MESSY)
    edits = await client.text_document_formatting_async(
        lsp.DocumentFormattingParams(doc.id, OPTIONS))
    assert edits and len(edits) == 1
    assert apply_edits(doc.text, doc, list(edits)) == format_text(MESSY).text
    # Formatted text formats to nothing.
    await doc.set_text(format_text(MESSY).text)
    assert not await client.text_document_formatting_async(
        lsp.DocumentFormattingParams(doc.id, OPTIONS))


async def test_format_range(client):
    doc = await Doc.open(client, "fmt-range.script", MESSY)
    line = doc.text.splitlines().index("[b##blk_terminus]")
    rng = lsp.Range(lsp.Position(line, 0), lsp.Position(line, 3))
    edits = await client.text_document_range_formatting_async(
        lsp.DocumentRangeFormattingParams(doc.id, rng, OPTIONS))
    formatted = apply_edits(doc.text, doc, list(edits))
    assert formatted.endswith("    [b##blk_terminus]\n")
    assert "[b##blk_inst:MV()LD()AO()]" in formatted  # outside the range: untouched


async def test_no_edit_for_a_text_that_does_not_parse(client):
    doc = await Doc.open(client, "fmt-broken.script",
                         "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV( LD() AO()]\n")
    edits = await client.text_document_formatting_async(
        lsp.DocumentFormattingParams(doc.id, OPTIONS))
    assert not edits
