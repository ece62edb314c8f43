"""The server never dies: thousands of random edits (ranges past the end of a line or of the
text, ranges in either order, positions between the halves of a surrogate pair, garbage and
lone surrogates as text, whole-text replacements), malformed messages and unknown methods;
the server keeps answering, and its diagnostics for the text the client holds are those of a
fresh analysis of that text (which also checks the incremental analysis at every sync point).

The client's text is modelled here the way an editor holds it: UTF-16 code units, lines
broken at `\\r\\n`, `\\r` or `\\n`, positions clamped as the protocol says.
"""

from __future__ import annotations

import json
import random

import pytest
from lsprotocol import types as lsp
from lsptest import CASES, diagnostics_of
from pygls.exceptions import JsonRpcMethodNotFound

from scriptc.analysis.analyze import analyze_script
from scriptc.server import convert
from scriptc.source import SourceFile

pytestmark = pytest.mark.asyncio(loop_scope="module")

EDITS = 3000
SYNC_EVERY = 150
PIECES = ["[", "]", "#", "(", ")", "{", "}", '"', "%", ",", ":", "!", "?", ">&", " ", "\n",
          "\r\n", "\r", "\t", "a", "b", "x", "0", "1", ".5", "é", "ß", "😀", "🎵", "\ud83d",
          "\ude00", "\u2028", "\x00", "\ufeff", "blk_inst", "blk_jump", "b##", "TRJMP(",
          "FLSJMP()", "CND(! {TRUE})", "MV() LD() AO()", "[b##blk_terminus]", "[action]",
          "[goal:g]", "OP<", "<", "?THIS>&positionrho", "B: near(1)", "E: gt(1, 2)",
          "% scriptc: ignore[F001] %"]


class Utf16Text:
    """The client's side: a list of UTF-16 code units."""

    def __init__(self, text: str) -> None:
        self.units = list(memoryview(text.encode("utf-16-le", "surrogatepass")).cast("H"))

    @property
    def text(self) -> str:
        import array

        return array.array("H", self.units).tobytes().decode("utf-16-le", "surrogatepass")

    def _lines(self) -> list[tuple[int, int]]:
        """(start, end of content) of each line, in units."""
        out, start, i, n = [], 0, 0, len(self.units)
        u = self.units
        while i < n:
            if u[i] == 13 or u[i] == 10:
                end = i
                i += 2 if u[i] == 13 and i + 1 < n and u[i + 1] == 10 else 1
                out.append((start, end))
                start = i
            else:
                i += 1
        out.append((start, n))
        return out

    def index(self, position: lsp.Position, lines) -> int:
        if position.line >= len(lines):
            return len(self.units)
        start, end = lines[position.line]
        return min(start + position.character, end)

    def apply(self, change) -> None:
        new = list(memoryview(change.text.encode("utf-16-le", "surrogatepass")).cast("H"))
        if isinstance(change, lsp.TextDocumentContentChangeWholeDocument):
            self.units = new
            return
        lines = self._lines()
        a, b = self.index(change.range.start, lines), self.index(change.range.end, lines)
        a, b = min(a, b), max(a, b)
        self.units[a:b] = new

    def random_position(self, rng: random.Random) -> lsp.Position:
        lines = self._lines()
        roll = rng.random()
        if roll < 0.05:
            return lsp.Position(len(lines) + rng.randint(0, 3), rng.randint(0, 5))  # past the end
        line = rng.randrange(len(lines))
        start, end = lines[line]
        if roll < 0.15:
            return lsp.Position(line, end - start + rng.randint(1, 40))  # past the line's end
        return lsp.Position(line, rng.randint(0, end - start))  # may split a surrogate pair


SEEDS = [p.read_text(encoding="utf-8") for p in sorted((CASES / "checks").glob("*.script"))[:12]]


def random_change(model: Utf16Text, rng: random.Random):
    roll = rng.random()
    if roll < 0.004:
        return lsp.TextDocumentContentChangeWholeDocument(text=rng.choice(SEEDS) + "% 😀 %\n")
    start = model.random_position(rng)
    if roll < 0.02:
        end = model.random_position(rng)  # a large range, in either order
    elif roll < 0.5:
        end = start
    else:
        end = lsp.Position(start.line, start.character + rng.randint(0, 4))
    text = "".join(rng.choice(PIECES) for _ in range(rng.choice([0, 1, 1, 1, 2, 3])))
    return lsp.TextDocumentContentChangePartial(range=lsp.Range(start, end), text=text)


def expected(text: str) -> list[tuple]:
    source = SourceFile("x", text)
    p = convert.text_positions(text)
    return [(d.code, d.message, convert.diagnostic(p, "u", d).range)
            for d in analyze_script(source).diagnostics]


def got(diagnostics) -> list[tuple]:
    return [(d.code, d.message, d.range) for d in diagnostics]


def send_raw(client, payload: bytes) -> None:
    client._server.stdin.write(b"Content-Length: %d\r\n\r\n" % len(payload) + payload)


async def test_random_edits_and_garbage(client):
    rng = random.Random(20211105)
    seed = (CASES / "emit" / "features.script").read_text(encoding="utf-8")
    seed = "% ünïcödé 😀 and 🎵 %\n" + seed
    uri = "file:///scriptc-tests/fuzz.script"
    model = Utf16Text(seed)
    version = 1
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="scriptc", version=1, text=seed)))
    checked = 0
    sizes: list[int] = []
    for n in range(1, EDITS + 1):
        changes = [random_change(model, rng) for _ in range(1 if rng.random() < 0.9 else 3)]
        for change in changes:
            model.apply(change)
        version += 1
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=changes))
        if n % 500 == 0:
            # Malformed messages: not JSON, a change of the wrong shape, an unknown method.
            send_raw(client, b"{this is not json")
            bad = {"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
                "textDocument": {"uri": uri, "version": "x"},
                "contentChanges": [{"range": {"start": {"line": "a"}}, "text": 5}]}}
            send_raw(client, json.dumps(bad).encode())
        if n % SYNC_EVERY == 0 or n == EDITS:
            published = await diagnostics_of(client, uri, version, timeout=60)
            assert got(published) == expected(model.text), f"after {n} edits"
            sizes.append(len(model.text))
            checked += 1
    assert checked == EDITS // SYNC_EVERY
    assert sorted(sizes)[len(sizes) // 2] > 150  # the document did not wither away

    # Still answering, requests and errors alike.
    hover = await client.text_document_hover_async(lsp.HoverParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(0, 0)))
    assert hover is None or hover.contents
    symbols = await client.text_document_document_symbol_async(
        lsp.DocumentSymbolParams(lsp.TextDocumentIdentifier(uri)))
    assert symbols is None or isinstance(symbols, list)
    with pytest.raises(JsonRpcMethodNotFound):
        await client.protocol.send_request_async("scriptc/noSuchMethod", {})
    tokens = await client.text_document_semantic_tokens_full_async(
        lsp.SemanticTokensParams(lsp.TextDocumentIdentifier(uri)))
    assert len(tokens.data) % 5 == 0


async def test_requests_at_impossible_positions(client):
    uri = "file:///scriptc-tests/fuzz-positions.script"
    text = "[a]\n[goal:g]\n[action]\n[b#x😀#blk_terminus]\n"
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="scriptc", version=1, text=text)))
    await diagnostics_of(client, uri, 1)
    doc = lsp.TextDocumentIdentifier(uri)
    for position in (lsp.Position(99, 99), lsp.Position(3, 999), lsp.Position(3, 5),
                     lsp.Position(3, 6), lsp.Position(0, 0)):
        await client.text_document_hover_async(lsp.HoverParams(doc, position))
        await client.text_document_completion_async(lsp.CompletionParams(doc, position))
        await client.text_document_definition_async(lsp.DefinitionParams(doc, position))
        await client.text_document_inlay_hint_async(
            lsp.InlayHintParams(doc, lsp.Range(position, lsp.Position(0, 0))))
    # A document the server never saw.
    other = lsp.TextDocumentIdentifier("file:///never/opened.script")
    assert await client.text_document_hover_async(
        lsp.HoverParams(other, lsp.Position(0, 0))) is None


async def test_typing_in_a_large_valid_script(client):
    """Edits that keep a large script mostly valid (digits typed into and deleted from
    numbers, labels changed and restored), so that the checks run at every sync point: the
    incremental analysis, its pads and its reuse of lowered items, checked over the wire."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parents[2] / "bench"))
    from generate import big_script

    rng = random.Random(7)
    text = big_script(120)
    uri = "file:///scriptc-tests/fuzz-typing.script"
    model = Utf16Text(text)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="scriptc", version=1, text=text)))
    version = 1
    semantic = 0
    for n in range(1, 401):
        current = model.text
        lines = current.split("\n")
        line = rng.randrange(len(lines))
        row = lines[line]
        digits = [i for i, ch in enumerate(row) if ch.isdigit()]
        if not digits:
            continue
        col = rng.choice(digits)
        kind = rng.random()
        if kind < 0.45:
            change = lsp.TextDocumentContentChangePartial(
                range=lsp.Range(lsp.Position(line, col), lsp.Position(line, col)),
                text=str(rng.randint(0, 9)))
        elif kind < 0.9:
            change = lsp.TextDocumentContentChangePartial(
                range=lsp.Range(lsp.Position(line, col), lsp.Position(line, col + 1)), text="")
        else:
            change = lsp.TextDocumentContentChangePartial(
                range=lsp.Range(lsp.Position(line, 0), lsp.Position(line, 0)),
                text=rng.choice(["  ", "% c %", "\n"]))
        model.apply(change)
        version += 1
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[change]))
        if n % 40 == 0:
            published = await diagnostics_of(client, uri, version, timeout=60)
            assert got(published) == expected(model.text), f"after {n} edits"
            semantic += not any(d.code[0] in "PS" for d in published)
    assert semantic >= 3  # the checks ran at several sync points
