"""Test files (`*.test.toml`, docs/testing.md) in the language server: opened or changed, the
server publishes (or, to a client that pulls, answers) the problems `scriptc test` finds in
them (T001-T005: the test file's reader over the editor's text), their ranges counted in the
negotiated position encoding, their paths resolved from the test file's folder; the features
of scripts answer nothing for them. Two clients: one that is pushed to and counts in UTF-16
(eglot 1.9, Neovim 0.9), one that pulls and counts in UTF-8 (VS Code pulls; Neovim and Helix
count in UTF-8)."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from lsptest import CONFIG, TIMEOUT, Doc, start
from pytest_lsp import LanguageClient

from scriptc.testing.read import test_from_text as read_test_text

pytestmark = pytest.mark.asyncio(loop_scope="module")

EXAMPLES = Path(__file__).resolve().parent.parent.parent / "examples"

SESSIONS = {
    "push, utf-16": {"encodings": ("utf-16",)},
    "pull, utf-8": {"encodings": ("utf-8", "utf-16"), "pull": True},
}


@pytest_lsp.fixture(scope="module", config=CONFIG, params=list(SESSIONS), ids=list(SESSIONS))
async def client(lsp_client: LanguageClient, request):
    await start(lsp_client, **SESSIONS[request.param])
    lsp_client.pulls = SESSIONS[request.param].get("pull", False)
    yield
    await lsp_client.shutdown_session()


# Problems after accented letters and emoji on their lines (a `where` field block events do
# not have, an unknown key), a script beside the test and one that does not exist.
TEXT = """\
description = "Già: un saluto 😀"
scripts = ["greeting.script", "più😀.script"]
until = 60000

[[expect]]
name = "dice ciao 😀"
event = "block"
where = { label = "ciào 😀", lable = "x" }

[[expect]]
name = "è finita"
outcmoe = "completed"
"""


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "greeting.script").write_text(
        (EXAMPLES / "greeting.script").read_text(encoding="utf-8"), encoding="utf-8")
    return tmp_path


async def problems(client: LanguageClient, doc: Doc) -> list[lsp.Diagnostic]:
    """The document's diagnostics now: pulled, or the ones pushed for its version."""
    if client.pulls:
        report = await asyncio.wait_for(client.text_document_diagnostic_async(
            lsp.DocumentDiagnosticParams(doc.id)), TIMEOUT)
        return list(report.items)
    return await doc.diagnostics()


async def open_test(client: LanguageClient, path: Path, text: str) -> Doc:
    """Open the test file `path` with `text`, as VS Code's extension does (its language
    `scriptc-test`; the server goes by the path)."""
    doc = Doc(client, path.as_uri(), text)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(doc.uri, "scriptc-test", doc.version, text)))
    return doc


async def edit(client: LanguageClient, doc: Doc, start: int, end: int, new_text: str
               ) -> list[lsp.Diagnostic]:
    """Replace `doc.text[start:end]` through an incremental change; the new diagnostics."""
    range_ = lsp.Range(doc.position(start), doc.position(end))
    doc.text = doc.text[:start] + new_text + doc.text[end:]
    doc.version += 1
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=doc.uri, version=doc.version),
        [lsp.TextDocumentContentChangePartial(range=range_, text=new_text)]))
    return await problems(client, doc)


def expected(doc: Doc, path: Path) -> list[tuple]:
    """What `scriptc test` says of the text, each problem's range counted by the test's own
    `Doc` in the client's encoding."""
    found = read_test_text(doc.text, str(path)).diagnostics
    return [(d.code, d.message, lsp.Range(doc.position(d.span.start), doc.position(d.span.end)))
            for d in found]


def seen(got: list[lsp.Diagnostic]) -> list[tuple]:
    return [(d.code, d.message, d.range) for d in got]


async def test_a_test_file_gets_scriptc_tests_problems(client, folder):
    path = folder / "saluto.test.toml"
    doc = await open_test(client, path, TEXT)
    got = await problems(client, doc)
    assert seen(got) == expected(doc, path)
    assert [d.code for d in got] == ["T004", "T003", "T003", "T002"]
    missing, where, nothing, unknown = got
    # Paths are the test file's: the script beside it is found, the other is not.
    assert "più😀.script" in missing.message and "greeting.script" not in missing.message
    # Ranges land on the characters, after the accented letters and emoji of their lines.
    assert doc.range_text(missing.range) == '"più😀.script"'
    assert doc.range_text(where.range) == "lable"
    assert doc.range_text(unknown.range) == "outcmoe"
    assert doc.range_text(nothing.range) == "expect"  # the second [[expect]]: it checks nothing
    assert "did you mean `outcome`?" in str(unknown.related_information)
    assert all(d.source == "scriptc" and d.severity == lsp.DiagnosticSeverity.Error
               for d in got)
    assert unknown.code_description.href.endswith("/T002.md")
    doc.close()


async def test_changes_renew_them(client, folder):
    path = folder / "renewed.test.toml"
    doc = await open_test(client, path, TEXT)
    await problems(client, doc)
    at = doc.text.index("outcmoe")
    after = await edit(client, doc, at + len("outc"), at + len("outcmo"), "om")  # outcome
    assert seen(after) == expected(doc, path)
    assert [d.code for d in after] == ["T004", "T003"]
    at = doc.text.index(', lable = "x"')
    assert seen(await edit(client, doc, at, at + len(', lable = "x"'), "")) == \
        expected(doc, path)
    at = doc.text.index("più😀.script")
    assert await edit(client, doc, at, at + len("più😀"), "greeting") == []
    at = doc.text.index('"è finita"')
    broken = await edit(client, doc, at + len('"è finita'), at + len('"è finita"'), "")
    assert seen(broken) == expected(doc, path)
    assert [d.code for d in broken] == ["T001"]  # a string left open: not TOML
    doc.close()


async def test_a_byte_order_mark_is_a_character_before_the_problems(client, folder):
    path = folder / "bom.test.toml"
    text = '\ufeffscriptz = ["greeting.script"]\n'
    doc = await open_test(client, path, text)
    got = await problems(client, doc)
    unknown = [d for d in got if d.code == "T002"]
    assert len(unknown) == 1 and doc.range_text(unknown[0].range) == "scriptz"
    doc.close()


async def test_the_features_of_scripts_answer_nothing(client, folder):
    doc = await open_test(client, folder / "quiet.test.toml", TEXT)
    await problems(client, doc)
    at = doc.position(doc.text.index("block"))
    assert await client.text_document_hover_async(lsp.HoverParams(doc.id, at)) is None
    assert await client.text_document_completion_async(lsp.CompletionParams(doc.id, at)) is None
    assert await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        doc.id, lsp.FormattingOptions(tab_size=2, insert_spaces=True))) is None
    assert await client.text_document_semantic_tokens_full_async(
        lsp.SemanticTokensParams(doc.id)) is None
    assert await client.text_document_document_symbol_async(
        lsp.DocumentSymbolParams(doc.id)) is None
    doc.close()


async def test_closing_clears_them(client, folder):
    """Closed: an empty list is pushed, or a pull is answered with none."""
    doc = await open_test(client, folder / "closed.test.toml", TEXT)
    assert await problems(client, doc)
    doc.close()
    if client.pulls:
        assert await problems(client, doc) == []
        return

    async def cleared() -> None:
        while client.published[doc.uri].diagnostics:
            await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)

    await asyncio.wait_for(cleared(), TIMEOUT)


async def test_a_change_of_configuration_checks_them_again(client, folder):
    """Every open document is opened again when a configuration file changes: a test file's
    stays a test file's, its problems pushed again (or pulled at the server's request)."""
    path = folder / "configured.test.toml"
    doc = await open_test(client, path, TEXT)
    before = await problems(client, doc)
    client.published.pop(doc.uri, None)
    refreshed = client.refreshes
    (folder / "scriptc.toml").write_text('[lint]\nignore = ["F001"]\n', encoding="utf-8")
    client.workspace_did_change_watched_files(lsp.DidChangeWatchedFilesParams(
        [lsp.FileEvent((folder / "scriptc.toml").as_uri(), lsp.FileChangeType.Created)]))

    async def renewed() -> list[lsp.Diagnostic]:
        while client.pulls and client.refreshes == refreshed:
            await asyncio.sleep(0.05)
        return await problems(client, doc)

    after = await asyncio.wait_for(renewed(), TIMEOUT)
    assert seen(after) == seen(before) == expected(doc, path)
    doc.close()
