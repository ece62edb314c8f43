"""Definition, references and rename over stdio, for labels, aliases and rule ids."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from lsptest import Doc, apply_edits
from pygls.exceptions import JsonRpcException

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
[greet]
[alfa:0, kick_starter, "", "", R, U]
[omega:0, kick_starter, "", "", C, L]
[goal:wave]
  [action]
    [b#loop#blk_inst: MV() LD() AO("Silence, 0, 100")]
    [b##blk_jump: CND({CLASS #Human U ?kid ()} ! {E: gt(?kid>&permanencetime, 10)})
                  TRJMP(loop) FLSJMP(end)]
    [b##blk_jump: CND(! {E: lt(?kid>&positionrho, 2)}) TRJMP(end) FLSJMP(loop)]
    [b#end#blk_terminus]
"""


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def doc(client):
    return await Doc.open(client, "navigation.script", TEXT)


def texts(doc: Doc, locations) -> list[tuple[int, str]]:
    return [(loc.range.start.line, doc.range_text(loc.range)) for loc in locations or ()]


async def test_definition_of_a_label(doc):
    found = await doc.client.text_document_definition_async(
        lsp.DefinitionParams(doc.id, doc.at("FLSJMP(loop)", len("FLSJMP(l"))))
    assert texts(doc, found) == [(5, "loop")]


async def test_definition_of_an_alias_and_a_rule(doc):
    use = doc.text.index("?kid>&positionrho")
    found = await doc.client.text_document_definition_async(
        lsp.DefinitionParams(doc.id, doc.position(use + 2)))
    assert texts(doc, found) == [(6, "?kid")]
    found = await doc.client.text_document_definition_async(
        lsp.DefinitionParams(doc.id, doc.at("[omega:0, kick", len("[omega:0, ki"))))
    assert texts(doc, found) == [(1, "kick_starter")]


async def test_references(doc):
    found = await doc.client.text_document_references_async(lsp.ReferenceParams(
        text_document=doc.id, position=doc.at("b#end#", 4),
        context=lsp.ReferenceContext(include_declaration=True)))
    assert texts(doc, found) == [(7, "end"), (8, "end"), (9, "end")]
    found = await doc.client.text_document_references_async(lsp.ReferenceParams(
        text_document=doc.id, position=doc.at("b#end#", 4),
        context=lsp.ReferenceContext(include_declaration=False)))
    assert texts(doc, found) == [(7, "end"), (8, "end")]


async def test_rename_a_label(doc):
    position = doc.at("TRJMP(loop)", len("TRJMP(lo"))
    prepared = await doc.client.text_document_prepare_rename_async(
        lsp.PrepareRenameParams(doc.id, position))
    assert doc.range_text(prepared.range) == "loop" and prepared.placeholder == "loop"
    edit = await doc.client.text_document_rename_async(lsp.RenameParams(doc.id, position, "again"))
    renamed = apply_edits(doc.text, doc, list(edit.changes[doc.uri]))
    assert renamed.count("again") == 3 and "loop" not in renamed


async def test_rename_an_alias(doc):
    position = doc.at("?kid>&positionrho", 1)
    edit = await doc.client.text_document_rename_async(lsp.RenameParams(doc.id, position, "child"))
    renamed = apply_edits(doc.text, doc, list(edit.changes[doc.uri]))
    assert renamed.count("?child") == 3 and "?kid" not in renamed


async def test_rename_refusals_say_why(doc):
    with pytest.raises(JsonRpcException, match="already exists"):
        await doc.client.text_document_rename_async(
            lsp.RenameParams(doc.id, doc.at("TRJMP(loop)", 7), "end"))
    with pytest.raises(JsonRpcException, match="only labels, aliases and rule ids"):
        await doc.client.text_document_prepare_rename_async(
            lsp.PrepareRenameParams(doc.id, doc.at("gt(", 1)))
