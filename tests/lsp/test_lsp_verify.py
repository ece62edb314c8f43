"""`scriptc verify` in the language server's background (server/background.py): the session's
duration range after the activity's name and each goal's reachability after its item, as
inlay hints, once the script has been still for a second; diagnostics never wait for it."""

from __future__ import annotations

import asyncio
import time

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from lsptest import CONFIG, Doc, start
from pytest_lsp import LanguageClient

pytestmark = [pytest.mark.asyncio(loop_scope="module"), pytest.mark.slow]


@pytest_lsp.fixture(scope="module", config=CONFIG)
async def client(lsp_client: LanguageClient):
    await start(lsp_client, verify=True)
    yield
    await lsp_client.shutdown_session()

TEXT = """\
[late]
[goal:g]
  [action]
    [b#w#blk_inst: MV() LD("0, 0.3, 0.8, 1, 0, 700") AO()]
    [b##blk_jump: CND({CLASS #Activity T ?me (?THIS>&elapsedtime OP< 500)} ! {TRUE})
                  TRJMP(fast) FLSJMP(end)]
    [b#end#blk_terminus]
[goal:quick]
  [action]
    [b#fast#blk_inst: MV() LD("0.2, 0.8, 0.3, 1, 0, 1000") AO()]
    [b##blk_terminus]
"""


async def verify_hints(client, doc: Doc, timeout: float = 30.0) -> list[lsp.InlayHint]:
    """The document's inlay hints once the background verification has answered."""
    whole = lsp.Range(lsp.Position(0, 0), doc.position(len(doc.text)))
    deadline = time.monotonic() + timeout
    while True:
        hints = await client.text_document_inlay_hint_async(lsp.InlayHintParams(doc.id, whole))
        found = [h for h in hints or [] if str(h.tooltip or "").startswith("scriptc verify")]
        if found:
            return found
        assert time.monotonic() < deadline, "no verification came back"
        await asyncio.sleep(0.2)


async def test_durations_and_goals_as_hints(client):
    started = time.monotonic()
    doc = await Doc.open(client, "verify-hints.script", TEXT)
    assert time.monotonic() - started < 1.0  # the diagnostics came before any verification
    hints = await verify_hints(client, doc)
    got = {(h.position.line, str(h.label)) for h in hints}
    # `w` runs 700 ms; the jump is true before 500 ms only: the session lasts 700 ms, and
    # the goal `quick` is never reached.
    assert got == {(0, "session: 700 ms"), (1, "reachable"), (7, "unreachable")}
    quick = next(h for h in hints if h.position.line == 7)
    assert "read at 700 ms" in str(quick.tooltip)
    assert hints[0].position == doc.position(len("[late]"))
    assert client.hint_refreshes >= 1  # the client was asked to fetch the hints again


async def test_an_edit_drops_the_old_answer_and_verifies_again(client):
    doc = await Doc.open(client, "verify-edit.script", TEXT)
    await verify_hints(client, doc)
    at = doc.text.index("OP< 500")
    await doc.replace(at, at + len("OP< 500"), "OP< 5000")  # now read at 700 ms, true
    hints = await verify_hints(client, doc)
    assert {str(h.label) for h in hints} == {"session: 1.7 s", "reachable"}

