"""Semantic tokens over stdio: the legend, the relative encoding, UTF-16 lengths, ranges."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from lsptest import Doc, decode

pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
% é 😀 %
[greet]
[goal:wave]
  [action]
    [b#ask#blk_jump: CND({CLASS #Human U ?kid (?THIS>&positionrho OP< 1.5)}
                         ! {E: gt(?kid>&permanencetime, 2)}) TRJMP(ask) FLSJMP()]
"""


@pytest_asyncio.fixture(scope="module", loop_scope="module")
async def doc(client):
    return await Doc.open(client, "tokens.script", TEXT)


def legend(client) -> lsp.SemanticTokensLegend:
    """The legend the server announced when the session started."""
    return client.init_result.capabilities.semantic_tokens_provider.legend


async def test_full(doc, client):
    result = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(doc.id))
    tokens = decode(legend(client), doc, list(result.data))
    assert tokens[0] == ("% é 😀 %", "comment", [])
    assert ("ask", "label", ["declaration"]) in tokens
    assert ("#Human", "class", []) in tokens
    assert ("positionrho", "property", []) in tokens
    assert ("gt", "function", ["defaultLibrary"]) in tokens
    assert ("OP<", "operator", []) in tokens
    assert tokens[-3:] == [("TRJMP", "keyword", []), ("ask", "label", []),
                           ("FLSJMP", "keyword", [])]


async def test_range(doc, client):
    rng = lsp.Range(lsp.Position(2, 0), lsp.Position(3, 10))
    result = await client.text_document_semantic_tokens_range_async(
        lsp.SemanticTokensRangeParams(doc.id, rng))
    decoded = decode(legend(client), doc, list(result.data))
    assert [t[0] for t in decoded] == ["goal", "wave", "action"]
