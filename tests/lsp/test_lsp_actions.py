"""Code actions over stdio: the diagnostics' fixes as quick fixes (mutex order, unknown
label, `<` for `OP<`, missing terminus, missing tracks) and one fix-all action."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from lsptest import Doc, apply_edits

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def actions_at(doc: Doc, marker: str, delta: int = 0, only=None) -> list[lsp.CodeAction]:
    position = doc.at(marker, delta)
    found = await doc.client.text_document_code_action_async(lsp.CodeActionParams(
        doc.id, lsp.Range(position, position),
        lsp.CodeActionContext(diagnostics=list(await doc.diagnostics()), only=only)))
    return list(found or ())


def applied(doc: Doc, action: lsp.CodeAction) -> str:
    return apply_edits(doc.text, doc, list(action.edit.changes[doc.uri]))


CASES = [
    ("mutex", ('[a]\n[alfa:0, k, "", "", R, M]\n[omega:0, k, "", "", C, L]\n[goal:g]\n[action]\n'
               '[b##blk_terminus]\n'),
     "R, M", 3, "M001", '[alfa:0, k, "", "", R, U]'),
    ("label", ("[a]\n[goal:g]\n[action]\n[b#start#blk_inst: MV() LD() AO()]\n"
               "[b##blk_jump: CND(! {TRUE}) TRJMP(strat) FLSJMP()]\n[b##blk_terminus]\n"),
     "strat", 1, "L003", "TRJMP(start)"),
    ("operator", ("[a]\n[goal:g]\n[action]\n"
                  "[b##blk_jump: CND({CLASS #Human U ?k (?THIS>&positionrho < 1)} ! {TRUE}) "
                  "TRJMP() FLSJMP()]\n[b##blk_terminus]\n"),
     "< 1", 0, "P001", "positionrho OP< 1"),
    ("terminus", "[a]\n[goal:g]\n  [action]\n    [b##blk_inst: MV() LD() AO()]\n",
     "[b##", 1, "F003", "    [b##blk_inst: MV() LD() AO()]\n    [b##blk_terminus]"),
    ("tracks", "[a]\n[goal:g]\n[action]\n[b##blk_inst: MV()]\n[b##blk_terminus]\n",
     "MV()]", 4, "S008", "[b##blk_inst: MV() LD() AO()]"),
]


@pytest.mark.parametrize("name, text, marker, delta, code, expected", CASES,
                         ids=[c[0] for c in CASES])
async def test_quick_fix(client, name, text, marker, delta, code, expected):
    doc = await Doc.open(client, f"actions-{name}.script", text)
    found = [a for a in await actions_at(doc, marker, delta)
             if a.kind == lsp.CodeActionKind.QuickFix]
    assert found, f"no quick fix at {marker!r}"
    action = found[0]
    assert [d.code for d in action.diagnostics] == [code]
    assert expected in applied(doc, action)
    # Applying the fix leaves no diagnostic of that code.
    await doc.set_text(applied(doc, action))
    assert code not in [d.code for d in await doc.diagnostics()]


async def test_fix_all_applies_the_safe_fixes(client):
    text = ('[a]\n[alfa:0, k, "", "", R, M]\n[omega:0, k, "", "", C, M]\n[goal:g]\n[action]\n'
            '[b##blk_jump: CND({CLASS #Human u ?kid ()} ! {TRUE}) TRJMP() FLSJMP()]\n'
            '[b##blk_terminus]\n')
    doc = await Doc.open(client, "actions-all.script", text)
    (action,) = await actions_at(doc, "[a]", only=[lsp.CodeActionKind.SourceFixAll])
    assert action.kind == lsp.CodeActionKind.SourceFixAll
    assert sorted(d.code for d in action.diagnostics) == ["M001", "M002", "R007"]
    await doc.set_text(applied(doc, action))
    assert await doc.diagnostics() == []


async def test_no_action_where_nothing_is_wrong(client):
    doc = await Doc.open(client, "actions-none.script",
                         "[a]\n[goal:g]\n[action]\n[b##blk_terminus]\n")
    assert await actions_at(doc, "goal") == []
