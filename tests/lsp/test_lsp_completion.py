"""Completion over stdio: item kinds after `[`, labels in jumps (with their paths), classes
after `#`, fields of the alias's class after `>&`, functions of the right kind after
`B:`/`F:`/`E:`, scopes, rule ids; snippets only for clients that take them."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from lsptest import Doc

pytestmark = pytest.mark.asyncio(loop_scope="module")

BASE = """\
[greet]
[alfa:0, kick_starter, "", "", R, U]
[goal:wave]
  [action]
    [b#start#blk_inst: MV() LD() AO()]
    [b#wait#blk_jump: CND({CLASS #Obstacle U ?box ()} ! {TRUE}) TRJMP() FLSJMP()]
    [b#end#blk_terminus]
"""


async def complete_after(client, name: str, typed: str) -> tuple[Doc, list[lsp.CompletionItem]]:
    """Open BASE with `typed` on a new last line and complete at its end."""
    doc = await Doc.open(client, name, BASE + typed)
    result = await client.text_document_completion_async(
        lsp.CompletionParams(doc.id, doc.position(len(doc.text))))
    items = result.items if isinstance(result, lsp.CompletionList) else result
    return doc, list(items)


async def test_items_after_bracket(client):
    _doc, items = await complete_after(client, "c-items.script", "    [")
    labels = [i.label for i in items]
    assert labels[:4] == ["goal:", "action", "alfa:", "omega:"]
    assert "b##blk_jump" in labels
    goal = items[0]
    assert goal.insert_text_format == lsp.InsertTextFormat.Snippet
    assert goal.text_edit.new_text == "goal:${1:id}"


async def test_labels_in_jumps_with_paths(client):
    doc, items = await complete_after(client, "c-labels.script",
                                      "    [b##blk_jump: CND(! {TRUE}) TRJMP(st")
    assert [(i.label, i.detail) for i in items] == [
        ("start", "goal0/act0/blk0 · blk_inst"), ("wait", "goal0/act0/blk1 · blk_jump"),
        ("end", "goal0/act0/blk2 · blk_terminus")]
    edit = items[0].text_edit
    assert doc.range_text(edit.range) == "st"
    assert items[0].kind == lsp.CompletionItemKind.Reference


async def test_classes_after_hash(client):
    _, items = await complete_after(client, "c-classes.script", "    [b##blk_jump: CND({CLASS #")
    assert [i.label for i in items] == ["Human", "Obstacle", "Object", "Activity"]
    assert {i.kind for i in items} == {lsp.CompletionItemKind.Class}


async def test_fields_of_the_alias_class(client):
    _, items = await complete_after(client, "c-fields.script",
                                    "    [b##blk_jump: CND(! {E: gt(?box>&")
    labels = [i.label for i in items]
    assert "isfixed" in labels and "istarget" not in labels


async def test_functions_of_the_kind(client):
    _, items = await complete_after(client, "c-functions.script",
                                    "    [b##blk_jump: CND({VAR @t U F: ")
    assert sorted(i.label for i in items) == ["now", "str"]
    _, items = await complete_after(client, "c-functions-b.script",
                                    "    [b##blk_jump: CND({CLASS #Human U ?k (B: ")
    assert [i.label for i in items] == ["near"]


async def test_documentation_is_plain_text_for_a_client_without_markdown(client):
    """This client declares no `documentationFormat`: the server sends plain text."""
    _, items = await complete_after(client, "c-docs.script", "    [b##blk_jump: CND({VAR @t U F: ")
    documented = [i for i in items if i.documentation]
    assert documented and all(isinstance(i.documentation, str) for i in documented)


async def test_scopes_and_rule_ids(client):
    _, items = await complete_after(client, "c-scopes.script",
                                    "    [b##blk_jump: CND({CLASS #Human ")
    assert [i.label for i in items] == ["U", "L", "T"]
    doc = await Doc.open(client, "c-rules.script",
                         BASE.replace("[goal:wave]", "[omega:0, k\n[goal:wave]"))
    at = doc.text.index("[omega:0, k") + len("[omega:0, k")
    result = await client.text_document_completion_async(
        lsp.CompletionParams(doc.id, doc.position(at)))
    assert [i.label for i in result.items] == ["kick_starter"]


async def test_nothing_inside_strings(client):
    _, items = await complete_after(client, "c-string.script", '    [b##blk_inst: MV() LD() AO("so')
    assert items == []
