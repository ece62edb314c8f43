"""Each internal of pygls that the language server relies on, named by a test of its own
(server/pyglsshim.py is the only module that reads them): a pygls release that changes one
fails here, under the internal's name; `pyproject.toml` pins pygls to the versions that pass
this file and tests/lsp/. The tests drive a small server in process, message by message."""

from __future__ import annotations

import asyncio
import json
import subprocess
import sys
from typing import ClassVar

import pytest
from lsprotocol import types as lsp

from scriptc.server import pyglsshim
from scriptc.server.pyglsshim import JsonRpcException, LanguageServer


class Raw:
    """A result already in JSON form (as `convert.Json`)."""

    def __init__(self, value) -> None:
        self.value = value


class Failed(JsonRpcException):
    CODE = -32803


class Protocol(pyglsshim.Protocol):
    raw_results = Raw
    seen_initialize: ClassVar[list] = []

    def error_answer(self, error, msg_id):
        if isinstance(error, KeyError):
            return Failed(message=f"request {msg_id}: no key {error}")
        return None

    def initialize_result(self, result) -> None:
        Protocol.seen_initialize.append(self.server)
        result.capabilities.hover_provider = False


class Writer:
    def __init__(self) -> None:
        self.sent: list[dict] = []

    def write(self, data) -> None:
        self.sent.append(json.loads(data))

    def close(self) -> None:
        pass


def make_server():
    server = LanguageServer("shim-test", "1", protocol_cls=Protocol)
    events: list = []

    @server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls, params):
        events.append(("open", params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls, params):
        events.append(("change", params.text_document.version))

    @server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls, params):
        events.append(("close", params.text_document.uri))

    @server.feature(lsp.TEXT_DOCUMENT_HOVER)
    def hover(ls, params):
        if params.position.line == 1:
            raise KeyError("kid")
        if params.position.line == 2:
            raise ValueError("a bug")
        return Raw({"contents": {"kind": "plaintext", "value": "as is"}, "extra": [1, 2]})

    writer = Writer()
    server.protocol.set_writer(writer, include_headers=False)
    return server, writer, events


def run(server, *messages) -> None:
    """Hand the messages to the protocol inside an event loop and let their handlers finish."""
    async def go() -> None:
        for message in messages:
            server.protocol.handle_message(server.protocol.structure_message(message))
            await asyncio.sleep(0)
        await asyncio.sleep(0.01)

    asyncio.run(go())


def initialize(id_: int = 1) -> dict:
    return {"jsonrpc": "2.0", "id": id_, "method": "initialize", "params": {"capabilities": {}}}


def hover(id_: int, line: int) -> dict:
    return {"jsonrpc": "2.0", "id": id_, "method": "textDocument/hover",
            "params": {"textDocument": {"uri": "file:///a.script"},
                       "position": {"line": line, "character": 0}}}


DOC = {"uri": "file:///a.script", "languageId": "scriptc", "version": 1, "text": "[a]\n"}


def test_lsp_initialize_is_a_generator_and_the_protocol_knows_its_server() -> None:
    """`LanguageServerProtocol.lsp_initialize` (overridden as a generator with `lsp_method`),
    the protocol's `_server`."""
    server, writer, _ = make_server()
    Protocol.seen_initialize.clear()
    run(server, initialize())
    assert Protocol.seen_initialize == [server]
    (answer,) = writer.sent
    assert answer["id"] == 1 and answer["result"]["capabilities"]["hoverProvider"] is False


def test_text_synchronisation_is_left_to_the_server() -> None:
    """`lsp_text_document__did_open/__did_change/__did_close` and `fm.features`: the handlers
    get every change, pygls's workspace keeps no copy."""
    server, _, events = make_server()
    run(server, initialize(),
        {"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": DOC}},
        {"jsonrpc": "2.0", "method": "textDocument/didChange",
         "params": {"textDocument": {"uri": DOC["uri"], "version": 2},
                    "contentChanges": [{"text": "[b]\n"}]}},
        {"jsonrpc": "2.0", "method": "textDocument/didClose",
         "params": {"textDocument": {"uri": DOC["uri"]}}})
    assert events == [("open", DOC["uri"]), ("change", 2), ("close", DOC["uri"])]
    assert not server.workspace.text_documents


def test_handle_notification_leaves_no_request_future() -> None:
    """`JsonRPCProtocol._handle_notification` and `_request_futures`: a notification handled
    by a generator leaves nothing among the futures of requests."""
    server, _, events = make_server()
    changes = [{"jsonrpc": "2.0", "method": "textDocument/didChange",
                "params": {"textDocument": {"uri": DOC["uri"], "version": v},
                           "contentChanges": [{"text": f"[v{v}]\n"}]}} for v in range(2, 50)]
    run(server, initialize(),
        {"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": DOC}},
        *changes)
    assert len(events) == 49
    assert isinstance(server.protocol._request_futures, dict)
    assert server.protocol._request_futures == {}


def test_send_handler_result_answers_as_error_answer_says() -> None:
    """`JsonRPCProtocol._send_handler_result(future, msg_id=)` and `_send_response(msg_id,
    error=)`: the policy's error is the answer; without one, pygls answers."""
    server, writer, _ = make_server()
    run(server, initialize(), hover(2, 1), hover(3, 2))
    refused, bug = writer.sent[1:]
    assert refused["id"] == 2 and refused["error"]["code"] == -32803
    assert refused["error"]["message"] == "request 2: no key 'kid'"
    assert bug["id"] == 3 and bug["error"]["code"] != -32803 and "result" not in bug
    assert server.protocol._request_futures == {}


def test_serialize_message_sends_raw_results_as_they_are() -> None:
    """`JsonRPCProtocol._serialize_message(data)` and `JsonRPCResponseMessage`: a result in
    JSON form skips cattrs (a key a Hover does not have survives)."""
    server, writer, _ = make_server()
    run(server, initialize(), hover(2, 0))
    answer = writer.sent[-1]
    assert answer == {"id": 2, "jsonrpc": "2.0",
                      "result": {"contents": {"kind": "plaintext", "value": "as is"},
                                 "extra": [1, 2]}}


STDIO_CHILD = """
import asyncio, logging, sys
from scriptc.server import pyglsshim
server = pyglsshim.LanguageServer("shim-test", "1", protocol_cls=pyglsshim.Protocol)
try:
    asyncio.run(pyglsshim.serve_stdio(server, sys.stdin.buffer, sys.stdout.buffer,
                                      logging.getLogger()))
except SystemExit:
    pass
"""


@pytest.mark.slow
def test_the_stdio_loop_over_a_pipe() -> None:
    """`pygls.io_` (`StdoutWriter`, `run_async`), `LanguageServer._stop_event`,
    `protocol.set_writer`, `thread_pool`, `report_server_error`: a session over a pipe, from
    `initialize` to `exit`, in a process of its own (`exit` ends it)."""
    def framed(message: dict) -> bytes:
        body = json.dumps(message).encode()
        return b"Content-Length: %d\r\n\r\n" % len(body) + body

    session = (framed(initialize()) + framed({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
               + framed({"jsonrpc": "2.0", "method": "exit"}))
    done = subprocess.run([sys.executable, "-c", STDIO_CHILD], input=session,
                          capture_output=True, timeout=60, check=False)
    answers = [json.loads(part.split(b"\r\n\r\n", 1)[1])
               for part in done.stdout.split(b"Content-Length: ")[1:]]
    assert [a["id"] for a in answers] == [1, 2], done.stderr.decode()
    assert "capabilities" in answers[0]["result"] and answers[1]["result"] is None
