"""Hostile documents and refused requests: every request on a document that cannot be read
into a script (a NUL in its only item) or whose times are not finite (`1e999`) is answered,
never with an internal error; a refused rename is answered as the protocol's RequestFailed
with its reason, and the server's log stays quiet; a bug in a handler is answered as an
internal error that names it, without the server's traceback in the answer.

The sessions are driven in one go (`run_session`), so that the server's stderr can be read
whole once it has exited; as they send `shutdown` and `exit` right after the document's
change, they also check that the server leaves quietly then (it used to write the due
diagnostics to the closed stream, and log that at ERROR, over and over)."""

from __future__ import annotations

from concurrent.futures import Future

from lsptest import run_session

URI = "file:///scriptc-tests/hostile.script"
NOT_A_SCRIPT = "[\x00]\n"
INFINITE = """\
[greet]
[goal:g]
  [action]
    [b#long#blk_inst: MV("0, 0, 0.5, 0, 1e999") LD("0, 0, 1, 1, 1e308, 1e308") AO()]
    [b##blk_terminus]
"""
RENAMES = """\
[greet]
[goal:g]
  [action]
    [b#start#blk_inst: MV() LD() AO()]
    [b#other#blk_jump: CND(! {TRUE}) TRJMP(start) FLSJMP(other)]
    [b##blk_terminus]
"""


def open_(text: str) -> dict:
    return {"method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": URI, "languageId": "scriptc", "version": 1, "text": text}}}


def requests(text: str) -> list[dict]:
    """Every reading request of the server, at the start, the middle and the end of every
    line (and past them), numbered from 1."""
    doc = {"textDocument": {"uri": URI}}
    lines = text.split("\n")
    whole = {"start": {"line": 0, "character": 0}, "end": {"line": len(lines), "character": 0}}
    out: list[dict] = [
        {"method": "textDocument/documentSymbol", "params": doc},
        {"method": "textDocument/foldingRange", "params": doc},
        {"method": "textDocument/semanticTokens/full", "params": doc},
        {"method": "textDocument/semanticTokens/range", "params": {**doc, "range": whole}},
        {"method": "textDocument/inlayHint", "params": {**doc, "range": whole}},
        {"method": "textDocument/codeAction", "params": {**doc, "range": whole,
                                                         "context": {"diagnostics": []}}},
        {"method": "textDocument/diagnostic", "params": doc},
        {"method": "textDocument/formatting", "params": {**doc, "options": {
            "tabSize": 2, "insertSpaces": True}}},
    ]
    for line, content in enumerate(lines):
        for character in sorted({0, 1, len(content) // 2, len(content), len(content) + 3}):
            at = {**doc, "position": {"line": line, "character": character}}
            out += [
                {"method": "textDocument/hover", "params": at},
                {"method": "textDocument/definition", "params": at},
                {"method": "textDocument/references", "params": {
                    **at, "context": {"includeDeclaration": True}}},
                {"method": "textDocument/completion", "params": at},
                {"method": "textDocument/prepareRename", "params": at},
                {"method": "textDocument/rename", "params": {**at, "newName": "renamed"}},
            ]
    return [{"id": n, **message} for n, message in enumerate(out, 1)]


def answered_without_failing(text: str) -> dict[str, list]:
    """Every request's result by method; none answered with an error other than a refused
    rename, and nothing logged at ERROR."""
    sent = requests(text)
    responses, stderr = run_session([open_(text), *sent])
    results: dict[str, list] = {}
    for message in sent:
        response = responses[message["id"]]
        error = response.get("error")
        if error is not None:
            assert message["method"].endswith("ename"), (message, error)
            assert error["code"] == -32803 and "data" not in error, error
        results.setdefault(message["method"], []).append(response.get("result"))
    assert "ERROR" not in stderr and "Traceback" not in stderr, stderr[-3000:]
    return results


def test_a_document_with_no_script_answers_every_request():
    results = answered_without_failing(NOT_A_SCRIPT)
    assert results["textDocument/documentSymbol"] == [[]]
    assert all(r is None for r in results["textDocument/hover"])
    assert all(r is None for r in results["textDocument/definition"])


def test_times_that_are_not_finite_read_as_unknown():
    results = answered_without_failing(INFINITE)
    (symbols,) = results["textDocument/documentSymbol"]
    block = symbols[0]["children"][0]["children"][0]["children"][0]
    assert block["name"] == "long" and block["detail"].endswith("· ?")
    (hints,) = results["textDocument/inlayHint"]
    assert [h["label"] for h in hints] == ["goal0/act0/blk0", "? ms", "goal0/act0/blk1"]
    hovers = [r["contents"]["value"] for r in results["textDocument/hover"] if r is not None]
    assert any("**instruction block** `long`" in h for h in hovers)


REFUSED = [  # (method, where, new name, what the reason says)
    ("textDocument/rename", "start#", "other", "already"),  # a name in use
    ("textDocument/rename", "start#", "d\u00e9but", "not a valid label"),
    ("textDocument/prepareRename", "MV()", None, "only labels, aliases and rule ids"),
    ("textDocument/rename", "blk_terminus", "x", "only labels, aliases and rule ids"),
]


def test_a_refused_rename_is_answered_with_its_reason_and_not_logged():
    lines = RENAMES.split("\n")
    sent = []
    for n, (method, at, new_name, _reason) in enumerate(REFUSED, 1):
        line = next(i for i, content in enumerate(lines) if at in content)
        params = {"textDocument": {"uri": URI}, "position": {
            "line": line, "character": lines[line].index(at) + 1}}
        if new_name is not None:
            params["newName"] = new_name
        sent.append({"id": n, "method": method, "params": params})
    responses, stderr = run_session([open_(RENAMES), *sent])
    for n, (_method, _at, _new_name, reason) in enumerate(REFUSED, 1):
        error = responses[n]["error"]
        assert error["code"] == -32803 and reason in error["message"], error
        assert "data" not in error
    assert stderr.strip() == "", stderr


def test_a_bug_is_answered_as_an_internal_error_without_the_traceback():
    """A handler that raises (here a stand-in future with a ValueError): the answer names
    the failure; the traceback goes to the log only."""
    import logging

    from scriptc.server.main import ScriptcServer

    server = ScriptcServer()
    sent: list = []
    server.protocol._send_response = lambda msg_id, result=None, error=None: sent.append(
        (msg_id, result, error))
    failed: Future = Future()
    try:
        raise ValueError("a bug")
    except ValueError as bug:
        failed.set_exception(bug)
    records: list[logging.LogRecord] = []
    handler = logging.Handler()
    handler.emit = records.append
    logging.getLogger("scriptc.server").addHandler(handler)
    try:
        server.protocol._send_handler_result(failed, msg_id=7)
    finally:
        logging.getLogger("scriptc.server").removeHandler(handler)
    ((msg_id, result, error),) = sent
    assert msg_id == 7 and result is None
    assert error.code == -32603 and error.data is None
    assert "ValueError: a bug" in error.message
    (record,) = records
    assert record.levelno == logging.ERROR and record.exc_info[1] is failed.exception()
