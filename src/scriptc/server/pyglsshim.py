"""The one door to pygls's internals: what the language server changes in pygls, and nothing else.

`server/main.py` uses pygls's public API (`LanguageServer`, `@server.feature`, lsprotocol's
types) and this module's `Protocol` and `serve_stdio`. Every private name of pygls scriptc
relies on is read here, and tests/test_pyglsshim.py names each in a test of its own, so that a
pygls release that changes one fails there, by name; `pyproject.toml` pins pygls to the
versions that pass it. The internals:

- `JsonRPCProtocol._handle_notification` and `_request_futures`: pygls 2.1 files the future of
  a notification whose handler is a generator among the futures of requests, under an id of
  its own, and never removes it (1.4 KiB per keystroke); `Protocol` drops it once handled.
- `JsonRPCProtocol._send_handler_result(future, msg_id=)` and `_send_response(msg_id,
  error=)`: how a failed request is answered (`Protocol.error_answer` decides).
- `JsonRPCProtocol._serialize_message(data)` and `JsonRPCResponseMessage`: results already in
  JSON form are sent as they are, without pygls's cattrs pass (`Protocol.raw_results`).
- `LanguageServerProtocol.lsp_initialize` as a generator (`yield from`), `lsp_method`, the
  protocol's `_server`, and the text-synchronisation methods
  `lsp_text_document__did_open/__did_change/__did_close` with `fm.features`: text
  synchronisation is left to the server's own documents.
- `pygls.io_` (`StdinAsyncReader`, `StdoutWriter`, `run_async`), `LanguageServer._stop_event`,
  `protocol.set_writer`, `thread_pool` and `report_server_error`: the stdio loop, reading stdin
  through an asyncio pipe rather than a thread per read.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import typing
from typing import Any

from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcException, JsonRpcInternalError
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol, lsp_method
from pygls.protocol.json_rpc import JsonRPCResponseMessage

__all__ = ["JsonRpcException", "JsonRpcInternalError", "LanguageServer", "Protocol",
           "RawResult", "serve_stdio"]


class RawResult(typing.Protocol):
    """A result already in the protocol's JSON form, held in `value`."""

    # JSON data (dicts, lists, numbers, strings), written out as it is.
    value: Any


class Protocol(LanguageServerProtocol):
    """pygls's protocol, with text synchronisation left to the server's own documents, results
    already in JSON form sent as they are, notifications that leave nothing behind, and failed
    requests answered as `error_answer` says. A subclass sets the policies: `raw_results`,
    `error_answer` and `initialize_result`."""

    # Results of this type are sent as their `value` (JSON already): pygls would otherwise walk
    # them with cattrs, which costs more than computing them.
    raw_results: type[RawResult] | tuple[type[RawResult], ...] = ()

    @property
    def server(self) -> LanguageServer:
        """The server this protocol serves."""
        return self._server

    def error_answer(self, error: BaseException, msg_id) -> JsonRpcException | None:
        """The error that answers request `msg_id`, whose handler raised `error`; or None to
        let pygls answer it (its own wording, and its log of the traceback at ERROR)."""
        return None

    def initialize_result(self, result: lsp.InitializeResult) -> None:
        """Adjust pygls's answer to `initialize` (the capabilities) in place."""

    # -- pygls's internals ----------------------------------------------------------------

    def _handle_notification(self, method_name, params):
        filed = self._request_futures
        before = set(filed)  # the requests under way: a few at most
        super()._handle_notification(method_name, params)
        for key in [key for key in filed if key not in before]:
            filed.pop(key, None)

    def _send_handler_result(self, future, *, msg_id):
        error = None if future.cancelled() else future.exception()
        answer = None if error is None else self.error_answer(error, msg_id)
        if answer is None:
            return super()._send_handler_result(future, msg_id=msg_id)
        self._request_futures.pop(msg_id, None)
        self._send_response(msg_id, error=answer.to_response_error())

    def _serialize_message(self, data):
        if isinstance(data, JsonRPCResponseMessage) and isinstance(data.result, self.raw_results):
            return {"id": data.id, "jsonrpc": data.jsonrpc, "result": data.result.value}
        return super()._serialize_message(data)

    @lsp_method(lsp.INITIALIZE)
    def lsp_initialize(self, params):
        result = yield from super().lsp_initialize(params)
        self.initialize_result(result)
        return result

    @lsp_method(lsp.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params):
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params):
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params):
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None


async def serve_stdio(server: LanguageServer, stdin: Any, stdout: Any,
                      log: logging.Logger) -> None:
    """pygls's stdio loop for `server`, reading `stdin` through an asyncio pipe rather than a
    thread per read (pygls's default): three thread hand-offs per message cost milliseconds
    on a busy machine. A file, /dev/null or a terminal (which epoll cannot watch) is read in
    pygls's thread."""
    from pygls.io_ import StdinAsyncReader, StdoutWriter, run_async

    server._stop_event = threading.Event()
    server.protocol.set_writer(StdoutWriter(stdout))
    if _is_pipe(stdin):
        reader: Any = asyncio.StreamReader(limit=2**30)
        await asyncio.get_running_loop().connect_read_pipe(
            lambda: asyncio.StreamReaderProtocol(reader), stdin)
    else:
        reader = StdinAsyncReader(stdin, server.thread_pool)
    await run_async(stop_event=server._stop_event, reader=reader, protocol=server.protocol,
                    logger=log, error_handler=server.report_server_error)


def _is_pipe(stream) -> bool:
    import os
    import stat

    try:
        mode = os.fstat(stream.fileno()).st_mode
    except (OSError, ValueError, AttributeError):
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode)
