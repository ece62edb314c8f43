"""`scriptc lsp`: the language server, a thin pygls shell over `scriptc.ide`.

Every request about a document takes one path (`_request`): the document (a request about a
document that is not open is answered None), analysed or not as the feature needs, its
positions in the negotiated encoding, and the offset of the request's position; the handler
then calls one function of the editor API with offsets and converts the answer back
(`scriptc.server.convert`). None holds logic of its own.

Decisions:

- **Documents are scriptc's own** (`scriptc.ide.document.Document`), not pygls's workspace:
  the builtin open/change/close handlers are replaced (`pyglsshim`) so that an edit is applied
  once, with the protocol's line breaks (pygls splits lines on `\\f`, `\\v`, U+2028... too)
  and with ranges that the protocol allows but pygls mishandles (past the end, between the
  halves of a surrogate pair) clamped or kept exact.
- **Positions** are counted in the encoding negotiated at `initialize`: the client's first
  offer among UTF-8, UTF-16 and UTF-32 (pygls chooses it and answers `positionEncoding`),
  UTF-16 when it offers none. `ScriptcServer.encoding` holds it; every conversion, incoming
  edits and ranges as well as everything sent, goes through `scriptc.server.convert` with it.
- **Diagnostics** are analysed right after the changes received so far, without debounce
  (a keystroke in a 90 KB script costs 15-25 ms, see bench/bench_lsp.py: a timer would only
  add latency), and pushed; a burst of changes already waiting is analysed once, at its end
  (`ScriptcServer.publish`). A client that can pull diagnostics (`textDocument/diagnostic`)
  pulls them instead, so that no editor shows them twice;
  `initializationOptions: {"diagnostics": "push" | "pull" | "both"}` overrides this. Pull
  requests are answered in every mode.
- **The repository's configuration** applies as in `scriptc lint`: the functions a
  `scriptc.toml` declares, its robot profile and its policy (selection, per-file ignores,
  severities), read when the document is opened and again when a configuration file is
  created, changed or deleted: the server asks the client to watch `scriptc.toml` and
  `pyproject.toml` files, and looks at them itself once a second as well (`initialized`).
- **Test files** (`*.test.toml`, docs/testing.md) are documents too: their diagnostics are
  the problems `scriptc test` finds in them (T001-T005, the test file's reader over the
  editor's text, `scriptc.ide.checked`), pushed and pulled as a script's are, in the same
  position encoding; the features of scripts (hover, completion, formatting...) answer None
  for them. A test file's document is told apart by its path, whatever the client calls its
  language.
- **Codes link to their explanation**: a diagnostic's `codeDescription` is the explanation
  file shipped in the package (the codes have no public page). A hover on a code (in a
  suppression comment, say) shows it too, and the command `scriptc.explain CODE` returns it
  as markdown.
- **The garbage collector** is off while the server runs: the trees and IR of a large
  document are acyclic, and collections rescanning them after every keystroke cost 10-30 ms.
  Each analysis's survivors are frozen (`gc.freeze`), and a full collection runs when the
  server has been idle for a few seconds. So an edit must leave no reference cycle behind
  (reference counting frees everything it replaced), and nothing may be kept per edit or per
  version: memory stays flat over a long session of quick edits
  (tests/lsp/test_lsp_memory.py; `bench/bench_lsp.py --memory` measures the server's RSS).
- **stdin is read through an asyncio pipe** (pygls reads it in a thread, three hand-offs per
  message), and results already in JSON form (`convert.Json`) skip pygls's cattrs pass.
- **Nothing goes to stdout** but the protocol: `serve` points `sys.stdout` at stderr before
  anything runs; logging goes to stderr.
"""

from __future__ import annotations

import asyncio
import gc
import logging
import os
import sys

from lsprotocol import types as lsp

from scriptc import __version__
from scriptc.ide import (
    actions,
    completion,
    formatting,
    hints,
    hover,
    navigation,
    outline,
    tokens,
)
from scriptc.ide.answers import RenameError
from scriptc.ide.checked import CheckedDocument
from scriptc.ide.document import Document, TextDocument, configured_document
from scriptc.project.config.load import CONFIG_FILES
from scriptc.server import convert
from scriptc.server.background import Background
from scriptc.server.pyglsshim import (
    JsonRpcException,
    JsonRpcInternalError,
    LanguageServer,
    serve_stdio,
)
from scriptc.server.pyglsshim import Protocol as PyglsProtocol
from scriptc.testing import is_test_file

log = logging.getLogger("scriptc.server")

# How long the server waits without a change before running a full garbage collection.
IDLE_COLLECT_SECONDS = 5.0
REQUEST_FAILED = -32803  # the protocol's RequestFailed: the request was valid but failed


class Refusal(JsonRpcException):
    """A request the server declines for a reason the user should read (a rename to a name
    in use, of something that is not a name): answered as the protocol's RequestFailed with
    that reason, which editors show, and not logged as a failure of the server."""

    CODE = REQUEST_FAILED


class ScriptcProtocol(PyglsProtocol):
    """pygls's protocol (adjusted in `pyglsshim.py`) with the server's policies: completion
    lists and semantic tokens (`convert.Json`) sent as they are, how a failed request is
    answered, and pull diagnostics offered only to a client that will pull them."""

    raw_results = convert.Json

    @property
    def server(self) -> ScriptcServer:
        """The scriptc server this protocol serves (`ScriptcServer` makes it its protocol)."""
        server = super().server
        assert isinstance(server, ScriptcServer), server
        return server

    def error_answer(self, error: BaseException, msg_id) -> JsonRpcException | None:
        """A `Refusal` is answered as it is, without the traceback pygls logs at ERROR for
        every error response; a bug (any other exception) is logged with its traceback on
        stderr and answered as an internal error that says what failed, without the traceback
        pygls puts in the answer's data. pygls answers its own errors."""
        if isinstance(error, JsonRpcException) and not isinstance(error, Refusal):
            return None
        if isinstance(error, Refusal):
            return error
        log.error("request %s failed", msg_id, exc_info=error)
        return JsonRpcInternalError(
            message=f"scriptc could not answer: {type(error).__name__}: {error} "
                    "(the server's log on stderr has the details; please report it)")

    def initialize_result(self, result: lsp.InitializeResult) -> None:
        """A client that can pull diagnostics pulls whenever the server offers it, and would
        show pushed diagnostics a second time: pull is offered only to a client that will
        pull (`diagnostic_modes`)."""
        if not self.server.pull:
            result.capabilities.diagnostic_provider = None


class ScriptcServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("scriptc", __version__, protocol_cls=ScriptcProtocol,
                         text_document_sync_kind=lsp.TextDocumentSyncKind.Incremental)
        self.documents: dict[str, Document | CheckedDocument] = {}
        self.push = True  # push diagnostics (pull requests are answered in any case)
        self.snippets = False
        # The client's formats for completion documentation (LSP `documentationFormat`).
        self.markdown_docs = False
        self._idle: asyncio.TimerHandle | None = None
        # Documents whose diagnostics are due.
        self._dirty: dict[str, Document | CheckedDocument] = {}
        self.pull = False  # the client pulls diagnostics
        # The position encoding agreed at `initialize` (the client's first offer that
        # pygls supports, answered as `positionEncoding`): every position is counted in it.
        self.encoding = convert.UTF16
        # The configuration files each open document's configuration depends on, as
        # `os.stat` saw them when it was read (None: absent): the server's own watch.
        self._stamps: dict[str, dict[str, tuple | None]] = {}
        self._poll: asyncio.TimerHandle | None = None
        # `scriptc verify` of the open scripts, in a worker process (server/background.py).
        self.background = Background(self.refresh_hints)
        self.hint_refresh = False  # the client can be asked to fetch inlay hints again

    # -- documents ---------------------------------------------------------------------------

    def document(self, uri: str) -> Document | CheckedDocument | None:
        return self.documents.get(uri)

    def open_document(self, uri: str, text: str, version: int | None
                      ) -> Document | CheckedDocument:
        """The document of `uri`: a test file checked as `scriptc test` checks it, or a script
        with its repository's configuration (`configure`)."""
        path = _path(uri)
        if is_test_file(path):
            return CheckedDocument(uri, text, version, path=path, check=_test_file_problems)
        return self.configure(uri, text, version)

    def snapshot(self, uri: str):
        doc = self.documents.get(uri)
        return None if doc is None else self.analysed(doc)

    def analysed(self, doc: Document | CheckedDocument):
        """The document's snapshot, analysed now if it changed, with the garbage collector
        kept off the new objects (see the module docstring)."""
        if doc.analysed:
            return doc.snapshot()
        try:
            snapshot = doc.snapshot()
        except Exception:  # a bug must not cost the user the session
            log.exception("incremental analysis failed on %s; analysing afresh", doc.uri)
            doc.reset_analyzer()
            snapshot = doc.snapshot()
        gc.freeze()
        self._schedule_collect()
        return snapshot

    # -- the repository's configuration ---------------------------------------------------------

    def configure(self, uri: str, text: str, version: int | None) -> Document:
        """The document with its repository's configuration (`_configured`), noting what
        its configuration files looked like first (`watch_configuration`)."""
        if self._poll is not None and uri.startswith("file:"):
            from scriptc.project.config.load import config_candidates

            self._stamps[uri] = {path: _stamp(path) for path in config_candidates(_path(uri))}
        return _configured(uri, text, version)

    def reconfigure(self) -> None:
        """A configuration file was created, changed or deleted: every open document reads
        its configuration again (as `scriptc lint` would now) and its diagnostics are renewed:
        pushed again, or pulled again at the server's request."""
        for uri, doc in list(self.documents.items()):
            self.documents[uri] = fresh = self.open_document(uri, doc.text, doc.version)
            self.publish(fresh)
        workspace = self.client_capabilities.workspace
        refresh = workspace.diagnostics if workspace is not None else None
        if self.pull and refresh is not None and refresh.refresh_support:
            self.workspace_diagnostic_refresh(None)

    def watch_configuration(self) -> None:
        """Look at the open documents' configuration files every CONFIGURATION_POLL_SECONDS
        (see `initialized`)."""
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no event loop (handlers called directly)
            return
        self._poll = loop.call_later(CONFIGURATION_POLL_SECONDS, self._look_at_configuration)

    def _look_at_configuration(self) -> None:
        self.watch_configuration()
        for uri in [uri for uri in self._stamps if uri not in self.documents]:
            del self._stamps[uri]  # closed
        for stamps in self._stamps.values():
            if any(_stamp(path) != seen for path, seen in stamps.items()):
                log.info("a configuration file changed: reading the configuration again")
                self.reconfigure()
                return

    def _schedule_collect(self) -> None:
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return
        if self._idle is not None:
            self._idle.cancel()
        self._idle = loop.call_later(IDLE_COLLECT_SECONDS, _collect)

    def publish(self, doc: Document | CheckedDocument) -> None:
        """Push the document's diagnostics as soon as the messages already received are
        handled: a burst of changes (a paste, a fast typist, a replay) is analysed once, at
        its end, and a lone change at once (no timer, no added latency)."""
        if not self.push:
            return
        first = not self._dirty
        self._dirty[doc.uri] = doc
        if not first:
            return
        try:
            asyncio.get_running_loop().call_soon(self._flush)
        except RuntimeError:  # no event loop (handlers called directly)
            self._flush()

    def verify_later(self, doc: Document | CheckedDocument) -> None:
        """Verify the script `doc` in the background once it is still (not a test file)."""
        if isinstance(doc, Document) and doc.uri.startswith("file:"):
            uri = doc.uri

            def current() -> Document | CheckedDocument:
                return self.documents.get(uri, doc)

            self.background.changed(uri, _path(uri), lambda: current().text,
                                    lambda: current().version)

    def refresh_hints(self) -> None:
        """A verification came back: the client fetches the inlay hints again, if it can."""
        if self.hint_refresh:
            self.workspace_inlay_hint_refresh(None)

    def _flush(self) -> None:
        dirty, self._dirty = self._dirty, {}
        for uri, doc in dirty.items():
            if self.documents.get(uri) is not doc:
                continue  # closed (or reopened) since
            try:
                snapshot = self.analysed(doc)
                diagnostics = convert.diagnostics(convert.positions(snapshot, self.encoding),
                                                  uri, snapshot.diagnostics)
            except Exception:  # one document's bug must not silence the others
                log.exception("cannot analyse %s", uri)
                continue
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
                uri=uri, diagnostics=diagnostics, version=doc.version))


def _test_file_problems(text: str, path: str) -> list:
    """The problems of a test file (T001-T005) whose text is `text`, its paths relative to
    `path` (`scriptc.ide.checked.Check`)."""
    from scriptc.testing.read import test_from_text

    return test_from_text(text, path).diagnostics


def _collect() -> None:
    gc.unfreeze()
    gc.collect()
    gc.freeze()


SERVER = ScriptcServer()


def _path(uri: str) -> str:
    from urllib.parse import unquote, urlparse

    parsed = urlparse(uri)
    return unquote(parsed.path) if parsed.scheme == "file" else uri


# -- lifecycle ----------------------------------------------------------------------------------


def diagnostic_modes(capabilities: lsp.ClientCapabilities | None, options) -> tuple[bool, bool]:
    """(push, pull): the client pulls when it can pull and can be asked to pull again
    (`workspace/diagnostic/refresh`: a change of configuration changes the diagnostics of
    documents nobody edited), and then nothing is pushed, or an editor would show every
    diagnostic twice; otherwise the server pushes (Neovim pulls, but takes no refresh).
    `initializationOptions.diagnostics` ("push", "pull" or "both") overrides."""
    text = capabilities.text_document if capabilities else None
    workspace = capabilities.workspace if capabilities else None
    refresh = workspace.diagnostics if workspace is not None else None
    can_pull = (text is not None and text.diagnostic is not None
                and refresh is not None and bool(refresh.refresh_support))
    mode = options.get("diagnostics") if isinstance(options, dict) else None
    if mode not in ("push", "pull", "both"):
        mode = "pull" if can_pull else "push"
    return mode in ("push", "both"), mode in ("pull", "both")


@SERVER.feature(lsp.INITIALIZE)
def initialize(ls: ScriptcServer, params: lsp.InitializeParams) -> None:
    capabilities = params.capabilities
    ls.push, ls.pull = diagnostic_modes(capabilities, params.initialization_options)
    # pygls has chosen the encoding (and answers it); count in the same one.
    ls.encoding = str(getattr(ls.workspace.position_encoding, "value",
                              ls.workspace.position_encoding) or convert.UTF16)
    text = capabilities.text_document if capabilities else None
    completion_caps = text.completion if text is not None else None
    item_caps = completion_caps.completion_item if completion_caps is not None else None
    ls.snippets = bool(item_caps and item_caps.snippet_support)
    workspace = capabilities.workspace if capabilities else None
    inlay = workspace.inlay_hint if workspace is not None else None
    ls.hint_refresh = bool(inlay and inlay.refresh_support)
    options = params.initialization_options
    if isinstance(options, dict) and options.get("verify") is False:
        ls.background.enabled = False
    formats = (item_caps.documentation_format if item_caps is not None else None) or []
    ls.markdown_docs = lsp.MarkupKind.Markdown in formats
    # Load the grammar now rather than on the first keystroke.
    from scriptc.syntax.parser import script_parser

    script_parser()


@SERVER.feature(lsp.SHUTDOWN)
def shutdown(ls: ScriptcServer, params: None) -> None:
    """The client is leaving: diagnostics still due are not sent (a client that sends
    `shutdown` and `exit` right after a change would otherwise have them written to a closed
    stream while the server exits), and the configuration is no longer watched."""
    ls.push = False
    ls._dirty.clear()
    if ls._poll is not None:
        ls._poll.cancel()
    ls.background.shutdown()


# How often the server looks at the configuration files of the open documents itself (a few
# `os.stat` calls each time).
CONFIGURATION_POLL_SECONDS = 1.0


def _stamp(path: str) -> tuple | None:
    """What tells that a file was created, changed or deleted (None: it does not exist)."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_mtime_ns, st.st_size, st.st_ino, st.st_ctime_ns


@SERVER.feature(lsp.INITIALIZED)
def initialized(ls: ScriptcServer, params: lsp.InitializedParams) -> None:
    """Watch the configuration files: ask the client to report their changes, when it can
    (the protocol's way, and the quickest), and look at them once a second all the same:
    many editors watch no files (Neovim on Linux), and an editor's watch fails silently
    when the system's limit of watches is reached (inotify's, on Linux), or in a batch
    Emacs, which handles no file events."""
    ls.watch_configuration()
    workspace = ls.client_capabilities.workspace
    watched = workspace.did_change_watched_files if workspace is not None else None
    if watched is None or not watched.dynamic_registration:
        return
    options = lsp.DidChangeWatchedFilesRegistrationOptions(
        watchers=[lsp.FileSystemWatcher(glob_pattern=f"**/{name}") for name in CONFIG_FILES])
    ls.client_register_capability(lsp.RegistrationParams(registrations=[lsp.Registration(
        id="scriptc-configuration", method=lsp.WORKSPACE_DID_CHANGE_WATCHED_FILES,
        register_options=options)]))


@SERVER.feature(lsp.WORKSPACE_DID_CHANGE_WATCHED_FILES)
def did_change_watched_files(ls: ScriptcServer, params: lsp.DidChangeWatchedFilesParams) -> None:
    """The client reports a change to files it watches: a configuration file's renews the
    configuration of every open document (`ScriptcServer.reconfigure`)."""
    names = {_path(change.uri).replace("\\", "/").rsplit("/", 1)[-1] for change in params.changes}
    if names & set(CONFIG_FILES):
        ls.reconfigure()


def _configured(uri: str, text: str, version: int | None) -> Document:
    """The document with its repository's setup (`scriptc.ide.document.configured_document`);
    the configuration's own problems are logged (scriptc lint shows them on stderr). A
    configuration that cannot be read at all gets the defaults, logged: it must not cost the
    session."""
    path = _path(uri) if uri.startswith("file:") else None
    try:
        doc, problems = configured_document(uri, text, version, path=path)
    except Exception:  # a broken configuration must not cost the session
        log.exception("cannot read the configuration of %s", path)
        return Document(uri, text, version, path=_path(uri))
    for problem in problems:
        for d in problem.diagnostics:
            log.warning("%s: %s[%s] %s", problem.source.path, d.severity.value, d.code,
                        d.message)
    return doc


@SERVER.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: ScriptcServer, params: lsp.DidOpenTextDocumentParams) -> None:
    item = params.text_document
    doc = ls.documents[item.uri] = ls.open_document(item.uri, item.text, item.version)
    ls.publish(doc)
    ls.verify_later(doc)


@SERVER.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: ScriptcServer, params: lsp.DidChangeTextDocumentParams) -> None:
    doc = ls.document(params.text_document.uri)
    if doc is None:
        log.warning("change to a document that is not open: %s", params.text_document.uri)
        return
    for change in params.content_changes:
        if isinstance(change, lsp.TextDocumentContentChangePartial):
            start, end, text = convert.change_to_edit(doc.text, change.range, change.text,
                                                      ls.encoding)
            doc.replace(start, end, text)
        else:
            doc.set_text(change.text)
    doc.version = params.text_document.version
    ls.publish(doc)
    ls.verify_later(doc)


@SERVER.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: ScriptcServer, params: lsp.DidCloseTextDocumentParams) -> None:
    uri = params.text_document.uri
    ls.documents.pop(uri, None)
    ls._dirty.pop(uri, None)
    ls.background.closed(uri)
    if ls.push:
        ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


# -- diagnostics (pull) -------------------------------------------------------------------------


@SERVER.feature(lsp.TEXT_DOCUMENT_DIAGNOSTIC,
                lsp.DiagnosticOptions(identifier="scriptc", inter_file_dependencies=False,
                                      workspace_diagnostics=False))
def pull_diagnostics(ls: ScriptcServer, params: lsp.DocumentDiagnosticParams):
    snapshot = ls.snapshot(params.text_document.uri)
    if snapshot is None:
        return lsp.RelatedFullDocumentDiagnosticReport(items=[])
    uri = params.text_document.uri
    return lsp.RelatedFullDocumentDiagnosticReport(
        items=convert.diagnostics(convert.positions(snapshot, ls.encoding), uri,
                                  snapshot.diagnostics),
        result_id=f"{id(snapshot):x}",
    )


@SERVER.command("scriptc.explain")
def explain(ls: ScriptcServer, *args) -> str | None:
    """The explanation of a diagnostic code, as markdown (for clients that show it)."""
    if not args or not isinstance(args[0], str):
        return None
    from scriptc.diagnostics.codes import REGISTRY

    return hover.code_markdown(args[0].upper()) if args[0].upper() in REGISTRY else None


# -- requests about a document ------------------------------------------------------------------


class At:
    """Where a request is, as its handler reads it: the `document`, its `snapshot` (None
    for a feature of the text alone: formatting) and the `positions` converter of the text
    the feature works on."""

    __slots__ = ("document", "positions", "snapshot")

    def __init__(self, document: TextDocument, snapshot, positions) -> None:
        self.document = document
        self.snapshot = snapshot
        self.positions = positions


class AtPosition(At):
    """Where a request at a position is (`_request(..., position=True)`): `At`, and the
    `offset` of the request's position."""

    __slots__ = ("offset",)

    def __init__(self, document: TextDocument, snapshot, positions, offset: int) -> None:
        super().__init__(document, snapshot, positions)
        self.offset = offset


def _request(method: str, options=None, *, analysed: bool = True, position: bool = False):
    """Register the handler of a request about a document, through the one path: the
    document (None answers a request about a document that is not open, or that is not a
    script: a test file has diagnostics and none of these features), its snapshot when
    the feature reads the analysis (`analysed`; else its own text: formatting's edits are of
    the document's text), the positions in the negotiated encoding, and the offset of
    `params.position` (`position`). The handler gets `(ls, params, at)`, `at` an `At`, or an
    `AtPosition` with `position`."""

    def register(answer):
        def handle(ls: ScriptcServer, params):
            doc = ls.document(params.text_document.uri)
            if not isinstance(doc, Document):
                return None
            if analysed:
                snapshot = ls.analysed(doc)
                positions = convert.positions(snapshot, ls.encoding)
            else:
                snapshot, positions = None, convert.text_positions(doc.text, ls.encoding)
            if position:
                offset = positions.offset(params.position)
                return answer(ls, params, AtPosition(doc, snapshot, positions, offset))
            return answer(ls, params, At(doc, snapshot, positions))

        handle.__name__ = answer.__name__
        handle.__qualname__ = answer.__qualname__
        handle.__doc__ = answer.__doc__
        SERVER.feature(method, options)(handle)
        return handle

    return register


@_request(lsp.TEXT_DOCUMENT_HOVER, position=True)
def on_hover(ls: ScriptcServer, params: lsp.HoverParams, at: AtPosition):
    return convert.hover(at.positions, hover.hover(at.snapshot, at.offset))


@_request(lsp.TEXT_DOCUMENT_COMPLETION,
          lsp.CompletionOptions(trigger_characters=["[", "#", "(", ":", "&", "?", "{", ","]),
          position=True)
def on_completion(ls: ScriptcServer, params: lsp.CompletionParams, at: AtPosition):
    return convert.completion_list(at.positions, completion.complete(at.snapshot, at.offset),
                                   ls.snippets, ls.markdown_docs)


@_request(lsp.TEXT_DOCUMENT_DEFINITION, position=True)
def on_definition(ls: ScriptcServer, params: lsp.DefinitionParams, at: AtPosition):
    spans = navigation.definition(at.snapshot, at.offset)
    return convert.locations(at.positions, params.text_document.uri, spans) or None


@_request(lsp.TEXT_DOCUMENT_REFERENCES, position=True)
def on_references(ls: ScriptcServer, params: lsp.ReferenceParams, at: AtPosition):
    spans = navigation.references(at.snapshot, at.offset, params.context.include_declaration)
    return convert.locations(at.positions, params.text_document.uri, spans) or None


def _rename_failed(error: RenameError) -> Refusal:
    return Refusal(message=str(error))


@_request(lsp.TEXT_DOCUMENT_PREPARE_RENAME, position=True)
def on_prepare_rename(ls: ScriptcServer, params: lsp.PrepareRenameParams, at: AtPosition):
    try:
        span, name = navigation.prepare_rename(at.snapshot, at.offset)
    except RenameError as error:
        raise _rename_failed(error) from None
    return lsp.PrepareRenamePlaceholder(at.positions.range(span), name)


@_request(lsp.TEXT_DOCUMENT_RENAME, lsp.RenameOptions(prepare_provider=True), position=True)
def on_rename(ls: ScriptcServer, params: lsp.RenameParams, at: AtPosition):
    try:
        edits = navigation.rename(at.snapshot, at.offset, params.new_name)
    except RenameError as error:
        raise _rename_failed(error) from None
    return convert.workspace_edit(at.positions, params.text_document.uri, edits)


@_request(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def on_document_symbol(ls: ScriptcServer, params: lsp.DocumentSymbolParams, at: At):
    return convert.document_symbols(at.positions, outline.document_symbols(at.snapshot))


@_request(lsp.TEXT_DOCUMENT_FOLDING_RANGE)
def on_folding_range(ls: ScriptcServer, params: lsp.FoldingRangeParams, at: At):
    return convert.folding_ranges(at.positions, outline.folding_ranges(at.snapshot))


@_request(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, convert.LEGEND)
def on_semantic_tokens(ls: ScriptcServer, params: lsp.SemanticTokensParams, at: At):
    return convert.semantic_tokens(at.positions, tokens.semantic_tokens(at.snapshot))


@_request(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE, convert.LEGEND)
def on_semantic_tokens_range(ls: ScriptcServer, params: lsp.SemanticTokensRangeParams, at: At):
    span = at.positions.span(params.range)
    return convert.semantic_tokens(at.positions, tokens.semantic_tokens(at.snapshot, span))


@_request(lsp.TEXT_DOCUMENT_CODE_ACTION,
          lsp.CodeActionOptions(code_action_kinds=[lsp.CodeActionKind.QuickFix,
                                                   lsp.CodeActionKind.SourceFixAll]))
def on_code_action(ls: ScriptcServer, params: lsp.CodeActionParams, at: At):
    only = tuple(str(getattr(k, "value", k)) for k in params.context.only or ()) or None
    found = actions.code_actions(at.snapshot, at.positions.span(params.range), only)
    return convert.code_actions(at.positions, params.text_document.uri, found) or None


@_request(lsp.TEXT_DOCUMENT_INLAY_HINT)
def on_inlay_hint(ls: ScriptcServer, params: lsp.InlayHintParams, at: At):
    span = at.positions.span(params.range)
    found = hints.inlay_hints(at.snapshot, span)
    verified = ls.background.overview(at.document.uri, at.document.version)
    if verified is not None:
        found += hints.verify_hints(at.snapshot, verified, span)
    return convert.inlay_hints(at.positions, found)


# Formatting works on the document's own text (not the analysis text), so its edits are
# converted with the document's positions.

@_request(lsp.TEXT_DOCUMENT_FORMATTING, analysed=False)
def on_formatting(ls: ScriptcServer, params: lsp.DocumentFormattingParams, at: At):
    return convert.text_edit_list(at.positions, formatting.format_document(at.document.text))


@_request(lsp.TEXT_DOCUMENT_RANGE_FORMATTING, analysed=False)
def on_range_formatting(ls: ScriptcServer, params: lsp.DocumentRangeFormattingParams, at: At):
    span = at.positions.span(params.range)
    return convert.text_edits(at.positions,
                              formatting.format_range(at.document.text, span.start, span.end))


# -- running --------------------------------------------------------------------------------------


def serve(log_level: str = "WARNING") -> None:
    """Talk LSP over stdin and stdout until the client says exit."""
    level = getattr(logging, log_level.upper(), logging.WARNING)
    logging.basicConfig(stream=sys.stderr, level=level,
                        format="scriptc-lsp %(levelname)s %(name)s: %(message)s")
    # pygls logs every message it sends at INFO; keep it quieter than our own level.
    logging.getLogger("pygls").setLevel(max(logging.WARNING, logging.getLogger().level))
    stdin, stdout = sys.stdin.buffer, sys.stdout.buffer
    # A stray print anywhere would corrupt the protocol stream: send it to stderr instead.
    sys.stdout = sys.stderr
    gc.disable()  # collections run when idle (ScriptcServer.analysed)
    try:
        asyncio.run(serve_stdio(SERVER, stdin, stdout, log))
    except (KeyboardInterrupt, SystemExit, BrokenPipeError, ConnectionResetError):
        pass
    except asyncio.IncompleteReadError:
        log.info("the client closed the connection in the middle of a message")
    finally:
        SERVER.shutdown()
