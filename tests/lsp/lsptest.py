"""Helpers of the language-server tests: the client, the server command, and waiting for the
diagnostics of one version of a document.

Every test module in tests/lsp/ shares one server (starting one costs about a second): the
`client` fixture of conftest.py is module-scoped, so each module opens its own documents
(under its own URIs) and leaves the others' alone.
"""

from __future__ import annotations

import asyncio
import json
import subprocess
import sys
from pathlib import Path

from lsprotocol import types as lsp
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig, LanguageClient
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

from scriptc.diagnostics import edits as edits_module
from scriptc.diagnostics.model import TextEdit
from scriptc.source import Span

CASES = Path(__file__).parent.parent / "cases"
SERVER_COMMAND = [sys.executable, "-m", "scriptc", "lsp"]
TIMEOUT = 20.0


def make_client() -> LanguageClient:
    """pytest-lsp's client, which also keeps the version of the last diagnostics published
    for each document (`client.published[uri]`) and counts the server's requests to pull
    every document's diagnostics again (`client.refreshes`, `workspace/diagnostic/refresh`)."""
    client = LanguageClient(converter_factory=default_converter)
    client.published = {}  # uri -> PublishDiagnosticsParams
    client.refreshes = 0
    client.hint_refreshes = 0

    def publish(client: LanguageClient, params: lsp.PublishDiagnosticsParams) -> None:
        client.diagnostics[params.uri] = params.diagnostics
        client.published[params.uri] = params

    def refresh(client: LanguageClient, params: None) -> None:
        client.refreshes += 1

    def refresh_hints(client: LanguageClient, params: None) -> None:
        client.hint_refreshes += 1

    features = dict(DEFAULT_CLIENT_FEATURES)
    features[lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = publish
    features[lsp.WORKSPACE_DIAGNOSTIC_REFRESH] = refresh
    features[lsp.WORKSPACE_INLAY_HINT_REFRESH] = refresh_hints
    register_lsp_features(client, features)
    return client


CONFIG = ClientServerConfig(server_command=SERVER_COMMAND, client_factory=make_client)


def capabilities(*, pull: bool = False, refresh: bool = True, watch: bool = False,
                 snippets: bool = True,
                 encodings: tuple[str, ...] = ("utf-16",)) -> lsp.ClientCapabilities:
    """The tests' client capabilities. `pull`: the client can pull diagnostics, and with
    `refresh` be asked to pull them again (as VS Code; Neovim pulls without `refresh`), and
    be asked to fetch inlay hints again (as VS Code);
    `watch`: it watches the files the server asks it to; `encodings`: the position
    encodings offered, in order of preference."""
    return lsp.ClientCapabilities(
        workspace=lsp.WorkspaceClientCapabilities(
            did_change_watched_files=lsp.DidChangeWatchedFilesClientCapabilities(
                dynamic_registration=True) if watch else None,
            diagnostics=lsp.DiagnosticWorkspaceClientCapabilities(refresh_support=True)
            if pull and refresh else None,
            inlay_hint=lsp.InlayHintWorkspaceClientCapabilities(refresh_support=refresh)),
        text_document=lsp.TextDocumentClientCapabilities(
            completion=lsp.CompletionClientCapabilities(
                completion_item=lsp.ClientCompletionItemOptions(snippet_support=snippets)),
            hover=lsp.HoverClientCapabilities(content_format=[lsp.MarkupKind.Markdown]),
            diagnostic=lsp.DiagnosticClientCapabilities() if pull else None,
            publish_diagnostics=lsp.PublishDiagnosticsClientCapabilities(related_information=True),
        ),
        general=lsp.GeneralClientCapabilities(
            position_encodings=[lsp.PositionEncodingKind(e) for e in encodings]),
    )


async def start(client: LanguageClient, *, pull: bool = False,
                encodings: tuple[str, ...] = ("utf-16",),
                verify: bool = False) -> lsp.InitializeResult:
    """Initialize the session; the result is kept as `client.init_result`, and the position
    encoding the server chose as `client.encoding` (the tests' documents count in it). The
    background verification of scripts (server/background.py) is off unless `verify`: it
    would only load the machine in the other modules."""
    client.init_result = await client.initialize_session(
        lsp.InitializeParams(capabilities=capabilities(pull=pull, encodings=encodings),
                             initialization_options=None if verify else {"verify": False}))
    client.encoding = str(getattr(client.init_result.capabilities.position_encoding, "value",
                                  client.init_result.capabilities.position_encoding))
    return client.init_result


# The position encodings' codecs, and the bytes of one code unit.
CODECS = {"utf-8": ("utf-8", 1), "utf-16": ("utf-16-le", 2), "utf-32": ("utf-32-le", 4)}


async def diagnostics_of(client: LanguageClient, uri: str, version: int | None,
                         timeout: float = TIMEOUT) -> list[lsp.Diagnostic]:
    """The diagnostics the server published for `version` of the document."""

    async def wait() -> list[lsp.Diagnostic]:
        while True:
            published = client.published.get(uri)
            if published is not None and published.version == version:
                return list(published.diagnostics)
            await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)

    return await asyncio.wait_for(wait(), timeout)


class Doc:
    """A document opened in the server, edited through the client, whose positions count in
    the client's position encoding (`client.encoding`, UTF-16 unless the test's session
    chose another)."""

    def __init__(self, client: LanguageClient, uri: str, text: str) -> None:
        self.client = client
        self.uri = uri
        self.text = text
        self.version = 1
        self.codec, self.unit = CODECS[getattr(client, "encoding", "utf-16")]

    @classmethod
    async def open(cls, client: LanguageClient, name: str, text: str) -> Doc:
        doc = cls(client, f"file:///scriptc-tests/{name}", text)
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(
            lsp.TextDocumentItem(doc.uri, "scriptc", doc.version, text)))
        await doc.diagnostics()
        return doc

    @property
    def id(self) -> lsp.TextDocumentIdentifier:
        return lsp.TextDocumentIdentifier(self.uri)

    async def diagnostics(self) -> list[lsp.Diagnostic]:
        return await diagnostics_of(self.client, self.uri, self.version)

    def position(self, offset: int) -> lsp.Position:
        """The protocol position of a code-point offset (computed here independently of the
        server's conversion: the encoding's units since the line's start)."""
        before = self.text[:offset]
        line = before.count("\n")
        column = before[before.rfind("\n") + 1:]
        return lsp.Position(line, len(column.encode(self.codec, "surrogatepass")) // self.unit)

    def at(self, marker: str, delta: int = 0) -> lsp.Position:
        """The position of the first occurrence of `marker`, moved by `delta` code points."""
        i = self.text.index(marker)
        return self.position(i + delta)

    def offset(self, position: lsp.Position) -> int:
        lines = self.text.split("\n")
        prefix = sum(len(line) + 1 for line in lines[:position.line])
        units = lines[position.line].encode(self.codec, "surrogatepass")
        before = units[:position.character * self.unit]
        return prefix + len(before.decode(self.codec, "surrogatepass"))

    def range_text(self, range_: lsp.Range) -> str:
        return self.text[self.offset(range_.start):self.offset(range_.end)]

    async def replace(self, start: int, end: int, new_text: str) -> list[lsp.Diagnostic]:
        """Edit `text[start:end]` (offsets) and wait for the new diagnostics."""
        range_ = lsp.Range(self.position(start), self.position(end))
        self.text = self.text[:start] + new_text + self.text[end:]
        self.version += 1
        self.client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=self.uri, version=self.version),
            [lsp.TextDocumentContentChangePartial(range=range_, text=new_text)]))
        return await self.diagnostics()

    async def set_text(self, text: str) -> list[lsp.Diagnostic]:
        self.text = text
        self.version += 1
        self.client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=self.uri, version=self.version),
            [lsp.TextDocumentContentChangeWholeDocument(text=text)]))
        return await self.diagnostics()

    def close(self) -> None:
        self.client.text_document_did_close(lsp.DidCloseTextDocumentParams(self.id))


def decode(legend: lsp.SemanticTokensLegend, doc: Doc,
           data: list[int]) -> list[tuple[str, str, list[str]]]:
    """Semantic tokens in the protocol's relative encoding, as (text, type, modifiers)."""
    out = []
    line = col = 0
    for i in range(0, len(data), 5):
        dline, dcol, length, type_, mods = data[i:i + 5]
        col = col + dcol if dline == 0 else dcol
        line += dline
        start = lsp.Position(line, col)
        end = lsp.Position(line, col + length)
        names = [m for bit, m in enumerate(legend.token_modifiers) if mods & (1 << bit)]
        out.append((doc.range_text(lsp.Range(start, end)), legend.token_types[type_], names))
    return out


def apply_edits(text: str, doc: Doc, edits: list[lsp.TextEdit]) -> str:
    """`text` with protocol edits applied as the protocol says (insertions at one position
    keep their order in the list): positions turned into offsets, then the one applier."""
    return edits_module.apply_edits(text, [
        TextEdit(Span(doc.offset(e.range.start), doc.offset(e.range.end)), e.new_text)
        for e in edits])


def run_session(messages: list[dict], capabilities: dict | None = None,
                timeout: float = 60) -> tuple[dict[int, dict], str]:
    """`scriptc lsp` over stdio, driven by a client that sends `initialize`, `initialized`,
    `messages` (requests have an `id`), `shutdown` and `exit` at once, then reads everything
    back: the responses by id, and all the server wrote on stderr (complete: the server has
    exited). For what only the log shows."""
    framed = []
    for message in [{"id": 0, "method": "initialize", "params": {
                        "processId": None, "rootUri": None, "capabilities": capabilities or {}}},
                    {"method": "initialized", "params": {}}, *messages,
                    {"id": -1, "method": "shutdown"}, {"method": "exit"}]:
        body = json.dumps({"jsonrpc": "2.0", **message}).encode()
        framed.append(b"Content-Length: %d\r\n\r\n%s" % (len(body), body))
    done = subprocess.run(SERVER_COMMAND, input=b"".join(framed), capture_output=True,
                          timeout=timeout, check=False)
    responses: dict[int, dict] = {}
    out = done.stdout
    while out:
        head, _, rest = out.partition(b"\r\n\r\n")
        length = next(int(line.split(b":")[1]) for line in head.split(b"\r\n")
                      if line.lower().startswith(b"content-length:"))
        message = json.loads(rest[:length])
        out = rest[length:]
        if "id" in message and "method" not in message:
            responses[message["id"]] = message
    return responses, done.stderr.decode("utf-8", "replace")
