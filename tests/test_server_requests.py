"""The language server's requests about a document all take one path (`server.main._request`):
every handler registered for such a request is the path's own code, a request about a document
that is not open is answered None by every one of them, and a hostile document (no script,
bad characters, positions and ranges outside it) is answered by every one of them with
something the protocol can carry. The handlers are found from the server's registry, not
from a list, so a new one that bypasses the path fails here. In process (no stdio session)."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from scriptc.server import convert, main

# Requests about a document that are not features of its content: text synchronisation, and
# pull diagnostics (answered with an empty report, as the protocol asks, for any document).
NOT_FEATURES = {lsp.TEXT_DOCUMENT_DID_OPEN, lsp.TEXT_DOCUMENT_DID_CHANGE,
                lsp.TEXT_DOCUMENT_DID_CLOSE, lsp.TEXT_DOCUMENT_DIAGNOSTIC}

URI = "untitled:hostile.script"
# No script can be read from it (a NUL in an item), a lone surrogate (half an emoji from a
# UTF-16 client), a whole emoji, line breaks of every kind, an unterminated item and string.
HOSTILE = "[\x00]\r[b#\ud83d#blk_inst: MV(\"0, 0, 0, 0, 1e999\") \U0001F600\r\n[goal:\"g\n"


def features() -> dict[str, object]:
    """method -> the handler the server runs (pygls wraps each in a partial)."""
    out = {}
    for method, handler in main.SERVER.protocol.fm.features.items():
        if method.startswith("textDocument/") and method not in NOT_FEATURES:
            out[method] = getattr(handler, "func", handler)
    return out


def params(method: str, uri: str, position: dict, range_: dict):
    """The params of `method` about `uri`, from every field a document request may have
    (each request's type takes the ones it knows)."""
    params_type = lsp.METHOD_TO_TYPES[method][2]
    data = {"textDocument": {"uri": uri}, "position": position, "range": range_,
            "context": {"diagnostics": [], "includeDeclaration": True, "triggerKind": 1},
            "newName": "renamed", "options": {"tabSize": 2, "insertSpaces": True}}
    return main.SERVER.protocol._converter.structure(data, params_type)


def test_every_request_about_a_document_takes_the_one_path() -> None:
    found = features()
    assert len(found) == 14, sorted(found)
    # Each handler `_request` registers is its closure `handle`: one code object for all.
    one_path = main.on_hover.__code__
    assert one_path.co_name == "handle"
    bypassing = [method for method, handler in found.items()
                 if getattr(handler, "__code__", None) is not one_path]
    assert bypassing == []


def test_a_document_that_is_not_open_is_answered_none_by_every_handler() -> None:
    server = main.ScriptcServer()
    at = {"line": 0, "character": 0}
    for method, handler in features().items():
        request = params(method, "file:///nowhere/closed.script", at, {"start": at, "end": at})
        assert handler(server, request) is None, method


@pytest.mark.parametrize("encoding", [convert.UTF8, convert.UTF16, convert.UTF32])
@pytest.mark.parametrize("position, range_", [
    ({"line": 0, "character": 0}, {"start": {"line": 0, "character": 0},
                                   "end": {"line": 9, "character": 0}}),
    ({"line": 1, "character": 4}, {"start": {"line": 1, "character": 5},  # inside the pair
                                   "end": {"line": 1, "character": 3}}),  # reversed
    ({"line": 99, "character": 99}, {"start": {"line": 50, "character": 7},  # past the end
                                     "end": {"line": 99, "character": 0}}),
])
def test_a_hostile_document_is_answered_by_every_handler(encoding, position, range_) -> None:
    server = main.ScriptcServer()
    server.encoding = encoding
    server.documents[URI] = main._configured(URI, HOSTILE, 1)
    converter = main.SERVER.protocol._converter
    for method, handler in features().items():
        try:
            answer = handler(server, params(method, URI, position, range_))
        except main.Refusal:
            assert method.endswith("ename"), method  # a refused rename, with its reason
            continue
        # Whatever it is, the protocol can carry it.
        if isinstance(answer, convert.Json):
            continue
        converter.unstructure(answer)
