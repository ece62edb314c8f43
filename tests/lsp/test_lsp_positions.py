"""Positions in UTF-16, as the protocol counts: on lines with emoji (two units each) and
accented letters (one), diagnostics, hover, completion, references and rename land on the
right characters, and edits that split an emoji keep the server's text equal to the
client's."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from lsptest import Doc, apply_edits
from pygls.exceptions import JsonRpcException

from scriptc.analysis.analyze import analyze_script
from scriptc.source import SourceFile

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
[cafe]
[goal:g]
  [action]
    [b#start#blk_inst: MV() LD() AO("chanson d'été 😀🎵.wav, 0, 100")] % 😀 %
    % 🎵🎵 é % [b##blk_jump: CND(! {TRUE}) TRJMP(strat) FLSJMP(start)]
    [b##blk_terminus]
"""


async def test_diagnostic_after_emoji(client):
    doc = await Doc.open(client, "utf16.script", TEXT)
    (l003,) = [d for d in await doc.diagnostics() if d.code == "L003"]
    assert l003.range.start.line == 4
    # Before `strat` on line 4 stand two emoji: two code points more in UTF-16 units.
    assert l003.range.start.character == TEXT.splitlines()[4].index("strat") + 2
    assert doc.range_text(l003.range) == "strat"


async def test_hover_after_emoji(client):
    doc = await Doc.open(client, "utf16-hover.script", TEXT)
    position = doc.at("FLSJMP(start)", len("FLSJMP(st"))
    h = await client.text_document_hover_async(lsp.HoverParams(doc.id, position))
    assert doc.range_text(h.range) == "start"
    assert "line 4" in h.contents.value
    with pytest.raises(JsonRpcException, match="not a valid label"):
        await client.text_document_rename_async(lsp.RenameParams(doc.id, position, "début"))


async def test_rename_lands_on_the_names(client):
    doc = await Doc.open(client, "utf16-rename2.script", TEXT)
    position = doc.at("FLSJMP(start)", len("FLSJMP(st"))
    edit = await client.text_document_rename_async(lsp.RenameParams(doc.id, position, "go"))
    renamed = apply_edits(doc.text, doc, list(edit.changes[doc.uri]))
    assert renamed == TEXT.replace("#start#", "#go#").replace("FLSJMP(start)", "FLSJMP(go)")


async def test_completion_range_after_emoji(client):
    doc = await Doc.open(client, "utf16-complete.script", TEXT)
    at = doc.text.index("TRJMP(strat") + len("TRJMP(str")
    result = await client.text_document_completion_async(
        lsp.CompletionParams(doc.id, doc.position(at)))
    (first, *_) = result.items
    assert doc.range_text(first.text_edit.range) == "str"


async def test_edits_with_emoji_and_split_pairs(client):
    doc = await Doc.open(client, "utf16-edit.script", TEXT)
    # Type after the emoji of the comment on line 3.
    after = doc.text.index("% 😀 %") + 3
    await doc.replace(after, after, "é")
    # Split 🎵 between its halves: insert text at the middle unit, then remove it again.
    client = doc.client
    first = doc.text.index("🎵")
    mid = doc.position(first)
    mid = lsp.Position(mid.line, mid.character + 1)  # between the surrogates
    doc.version += 1
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        text_document=lsp.VersionedTextDocumentIdentifier(uri=doc.uri, version=doc.version),
        content_changes=[lsp.TextDocumentContentChangePartial(range=lsp.Range(mid, mid),
                                                              text="X")]))
    units = doc.text.encode("utf-16-le", "surrogatepass")
    cut = (len(doc.text[:first].encode("utf-16-le", "surrogatepass")) // 2 + 1) * 2
    split = units[:cut] + "X".encode("utf-16-le") + units[cut:]
    doc.text = split.decode("utf-16-le", "surrogatepass")
    got = await doc.diagnostics()
    expected = [(d.code, d.message) for d in analyze_script(SourceFile("x", doc.text)).diagnostics]
    assert [(d.code, d.message) for d in got] == expected
    # Remove the X: the pair joins again, as in the client.
    x = lsp.Range(lsp.Position(mid.line, mid.character), lsp.Position(mid.line, mid.character + 1))
    doc.version += 1
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        text_document=lsp.VersionedTextDocumentIdentifier(uri=doc.uri, version=doc.version),
        content_changes=[lsp.TextDocumentContentChangePartial(range=x, text="")]))
    doc.text = doc.text.replace("\ud83cX\udfb5", "🎵")
    assert doc.text.count("🎵") == 3
    got = await doc.diagnostics()
    expected = [(d.code, d.message) for d in analyze_script(SourceFile("x", doc.text)).diagnostics]
    assert [(d.code, d.message) for d in got] == expected
    # The server's text is the client's: a rename's edits apply cleanly to it.
    position = doc.at("FLSJMP(start)", len("FLSJMP(st"))
    edit = await client.text_document_rename_async(lsp.RenameParams(doc.id, position, "go"))
    renamed = apply_edits(doc.text, doc, list(edit.changes[doc.uri]))
    assert "FLSJMP(go)" in renamed and "#go#" in renamed and "🎵🎵" in renamed
