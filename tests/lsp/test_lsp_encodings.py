"""Position encodings, as three clients negotiate them: one that offers UTF-8 first (Neovim
0.10 and newer offer `["utf-8", "utf-16", "utf-32"]`), one that knows only UTF-16 (VS Code),
one that offers UTF-32 first. The server counts in the encoding it answered, both ways: after
inserts and deletes behind accented letters and emoji, its copy of the document is the
client's (its diagnostics, semantic tokens, symbols, inlay hints and hovers are those of a
fresh open of the client's text), and what it sends lands on the right characters, counted in
that encoding (`Doc` counts positions independently of the server)."""

from __future__ import annotations

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from lsptest import CASES, CONFIG, Doc, apply_edits, decode, start
from pytest_lsp import LanguageClient

pytestmark = pytest.mark.asyncio(loop_scope="module")

OFFERS = {
    "utf-8 first": ("utf-8", "utf-16", "utf-32"),
    "utf-16 only": ("utf-16",),
    "utf-32 first": ("utf-32", "utf-8", "utf-16"),
}


@pytest_lsp.fixture(scope="module", config=CONFIG, params=list(OFFERS), ids=list(OFFERS))
async def client(lsp_client: LanguageClient, request):
    await start(lsp_client, encodings=OFFERS[request.param])
    lsp_client.offer = OFFERS[request.param]
    yield
    await lsp_client.shutdown_session()


# Italian comments, an accented file name and emoji (also the sample of tests/editors/).
TEXT = (CASES / "checks" / "labels_after_non_ascii.script").read_text(encoding="utf-8")

# The edits, as (what to find, where in it, how many characters to delete, what to insert):
# each lands right after non-ASCII text on its line, and each, put a few characters off,
# would change what the server reports (a label, an item, a string, a line).
EDITS = [
    ("TRJMP(strat)", len("TRJMP(st"), 1, ""),  # strat -> stat
    ("TRJMP(stat)", len("TRJMP(sta"), 0, "r"),  # stat -> start: L003 gone
    ("bello 😀 %", len("bello 😀 %"), 0, " [b#più#blk_terminus]"),  # an item after the comment
    ("#più#", len("#pi"), 1, "u"),  # a label that is not a name, then one that is
    ("canzone_è", len("canzone_è"), 0, "_😀🎵"),  # inside the string, after è
    ("canzone_è_😀🎵", len("canzone_è_"), 2, "ò"),  # delete both emoji: canzone_è_ò
    ("perché sì", len("perché "), 2, "no %\n    % così"),  # a line break, two comments
    ("così % [b##", len("così % "), 0, "[b#dopo#blk_inst: MV() LD() AO()] "),
    ("perché no %\n", len("perché no"), len(" %\n    % così"), ""),  # the lines joined again
]


async def test_the_server_counts_in_the_first_encoding_offered(client):
    assert client.init_result.capabilities.position_encoding == client.offer[0]
    assert client.encoding == client.offer[0]


async def same_as_a_fresh_open(client, doc: Doc, name: str) -> None:
    """Everything the server says of the edited document equals what it says of a document
    opened afresh with the client's text (so the two texts are the same)."""
    fresh = await Doc.open(client, name, doc.text)
    try:
        assert [(d.range, d.code, d.message) for d in await doc.diagnostics()] == \
            [(d.range, d.code, d.message) for d in await fresh.diagnostics()]
        legend = client.init_result.capabilities.semantic_tokens_provider.legend
        tokens = [decode(legend, d, list((await client.text_document_semantic_tokens_full_async(
            lsp.SemanticTokensParams(d.id))).data)) for d in (doc, fresh)]
        assert tokens[0] == tokens[1]
        symbols = [await client.text_document_document_symbol_async(
            lsp.DocumentSymbolParams(d.id)) for d in (doc, fresh)]
        assert symbols[0] == symbols[1]
        whole = lsp.Range(lsp.Position(0, 0), doc.position(len(doc.text)))
        hints = [await client.text_document_inlay_hint_async(lsp.InlayHintParams(d.id, whole))
                 for d in (doc, fresh)]
        assert ([(h.position, h.label) for h in hints[0]]
                == [(h.position, h.label) for h in hints[1]])
        at = doc.text.index("blk_inst")
        hovers = [await client.text_document_hover_async(lsp.HoverParams(d.id, d.position(at)))
                  for d in (doc, fresh)]
        assert hovers[0].contents.value == hovers[1].contents.value
    finally:
        fresh.close()


async def test_edits_after_non_ascii_text_keep_the_server_s_text_the_client_s(client):
    doc = await Doc.open(client, "edited.script", TEXT)
    (l003,) = [d for d in await doc.diagnostics() if d.code == "L003"]
    assert doc.range_text(l003.range) == "strat"
    for n, (find, into, delete, insert) in enumerate(EDITS):
        at = doc.text.index(find) + into
        await doc.replace(at, at + delete, insert)
        await same_as_a_fresh_open(client, doc, f"fresh-{n}.script")
    assert doc.text == (TEXT.replace("strat", "start")
                        .replace("😀 %\n", "😀 % [b#piu#blk_terminus]\n")
                        .replace("canzone_è", "canzone_è_ò")
                        .replace("perché sì %", "perché no % [b#dopo#blk_inst: MV() LD() AO()]"))
    assert "play `canzone_è_ò.wav`" in (await client.text_document_hover_async(lsp.HoverParams(
        doc.id, doc.position(doc.text.index("blk_inst"))))).contents.value
    doc.close()


async def test_what_the_server_sends_lands_on_the_characters(client):
    """Diagnostics, semantic tokens, symbols, inlay hints and rename edits, counted in the
    session's encoding, name the characters they are about."""
    doc = await Doc.open(client, "outgoing.script", TEXT)
    (l003,) = [d for d in await doc.diagnostics() if d.code == "L003"]
    assert doc.range_text(l003.range) == "strat"
    legend = client.init_result.capabilities.semantic_tokens_provider.legend
    tokens = decode(legend, doc, list((await client.text_document_semantic_tokens_full_async(
        lsp.SemanticTokensParams(doc.id))).data))
    assert tokens[0] == ("% Un'attività: saluta, poi canta 🎵 %", "comment", [])
    assert ("% è più bello 😀 %", "comment", []) in tokens
    assert ('"canzone_è.wav, 0, 100"', "string", []) in tokens
    assert tokens[-6:-2] == [("TRJMP", "keyword", []), ("strat", "label", []),
                             ("FLSJMP", "keyword", []), ("start", "label", [])]
    (activity,) = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(doc.id))
    assert doc.range_text(activity.selection_range) == "saluto"
    blocks = activity.children[0].children[0].children
    assert doc.range_text(blocks[1].range).startswith("[b##blk_jump") and \
        doc.range_text(blocks[1].range).endswith("FLSJMP(start)]")
    whole = lsp.Range(lsp.Position(0, 0), doc.position(len(doc.text)))
    hints = await client.text_document_inlay_hint_async(lsp.InlayHintParams(doc.id, whole))
    assert hints[0].position == doc.position(doc.text.index('100")]') + len('100")]'))
    position = doc.at("FLSJMP(start)", len("FLSJMP(st"))
    edit = await client.text_document_rename_async(lsp.RenameParams(doc.id, position, "via"))
    renamed = apply_edits(doc.text, doc, list(edit.changes[doc.uri]))
    assert renamed == TEXT.replace("#start#", "#via#").replace("FLSJMP(start)", "FLSJMP(via)")
    doc.close()
