"""Diagnostics over stdio: pushed on open and on every change, with the CLI's codes and
messages; labels as related locations, notes and help as related information; cleared on
close."""

from __future__ import annotations

import pytest
from harness.diagnostics import parsed
from lsprotocol import types as lsp
from lsptest import CASES, Doc

from scriptc.analysis.analyze import analyze_script
from scriptc.source import SourceFile

pytestmark = pytest.mark.asyncio(loop_scope="module")

CLEAN = ("[greet]\n[goal:g]\n  [action]\n    [b#start#blk_inst: MV() LD() AO()]\n"
         "    [b##blk_terminus]\n")


def cli(text: str) -> list[tuple[str, str]]:
    return [(d.code, d.message) for d in analyze_script(SourceFile("x", text)).diagnostics]


@pytest.mark.parametrize("name", ["checks/duplicate_label", "checks/unknown_label",
                                  "checks/jump_cycle", "syntax/unterminated_string",
                                  "checks/omega_leak", "checks/unreachable"])
async def test_open_pushes_what_lint_reports(client, name):
    path = CASES / f"{name}.script"
    text = path.read_text(encoding="utf-8")
    doc = await Doc.open(client, f"diag-{name.replace('/', '-')}.script", text)
    got = await doc.diagnostics()
    assert [(d.code, d.message) for d in got] == cli(text)
    assert all(d.source == "scriptc" for d in got)
    doc.close()


async def test_labels_notes_and_help_are_related_information(client):
    text = (CASES / "checks" / "duplicate_label.script").read_text(encoding="utf-8")
    doc = await Doc.open(client, "related.script", text)
    first = (await doc.diagnostics())[0]
    assert first.code == "L001" and first.severity == lsp.DiagnosticSeverity.Error
    related = first.related_information
    label, *rest = related
    assert label.location.uri == doc.uri
    assert doc.range_text(label.location.range) == doc.range_text(first.range)  # same label text
    assert label.location.range != first.range
    assert [r.message.split(":")[0] for r in rest] == ["note", "help"]
    assert all(r.location.range == first.range for r in rest)


async def test_the_code_links_to_its_explanation(client):
    """`codeDescription.href` is the explanation shipped in the package: a file that exists
    and is what `scriptc explain` prints."""
    from pathlib import Path
    from urllib.parse import urlparse
    from urllib.request import url2pathname

    from scriptc.diagnostics.codes import explanation

    text = (CASES / "checks" / "duplicate_label.script").read_text(encoding="utf-8")
    doc = await Doc.open(client, "links.script", text)
    first = (await doc.diagnostics())[0]
    href = first.code_description.href
    assert href.startswith("file:") and href.endswith("/L001.md")
    path = Path(url2pathname(urlparse(href).path))
    assert path.read_text(encoding="utf-8") == explanation("L001")


async def test_severities_and_unreachable_code_is_faded(client):
    text = (CASES / "checks" / "unreachable.script").read_text(encoding="utf-8")
    doc = await Doc.open(client, "faded.script", text)
    f001 = [d for d in await doc.diagnostics() if d.code == "F001"]
    assert f001 and f001[0].severity == lsp.DiagnosticSeverity.Warning
    assert list(f001[0].tags) == [lsp.DiagnosticTag.Unnecessary]


async def test_change_pushes_new_diagnostics(client):
    doc = await Doc.open(client, "change.script", CLEAN)
    assert await doc.diagnostics() == []
    at = doc.text.index("blk_terminus")
    got = await doc.replace(at, at + len("blk_terminus"), "blk_terminos")
    assert [d.code for d in got] == [c for c, _ in cli(doc.text)]
    assert got and got[0].code.startswith("P")
    assert await doc.replace(at, at + len("blk_terminos"), "blk_terminus") == []


async def test_every_version_gets_its_own_diagnostics(client):
    doc = await Doc.open(client, "versions.script", CLEAN)
    at = doc.text.index("start")
    for ch in "abc":
        await doc.replace(at, at, ch)
        assert client.published[doc.uri].version == doc.version
    assert await doc.replace(at, at + 3, "") == []


async def test_close_clears_the_diagnostics(client):
    doc = await Doc.open(client, "closing.script", "[x]\n[b##blk_terminus]\n")
    assert await doc.diagnostics()
    doc.close()
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert list(client.published[doc.uri].diagnostics) == []


async def test_suppressed_codes_are_not_pushed(client):
    text = ("[greet]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n"
            "    [b##blk_inst: MV() LD() AO()]  % scriptc: ignore[F001] %\n")
    doc = await Doc.open(client, "suppressed.script", text)
    got = await doc.diagnostics()
    assert [(d.code, d.message) for d in got] == cli(text)
    assert "F001" not in [d.code for d in got]


@pytest.mark.parametrize("name", ["calls", "activity"])
async def test_the_repository_configuration_applies(client, name):
    """A file in a repository with a scriptc.toml gets what `scriptc lint` reports there:
    the declared functions are known, the policy drops and re-grades warnings
    (tests/cases/config/repo/NAME.lint holds lint's report)."""
    path = CASES / "config" / "repo" / f"{name}.script"
    text = path.read_text(encoding="utf-8")
    doc = Doc(client, path.resolve().as_uri(), text)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(doc.uri, "scriptc", doc.version, text)))
    got = await doc.diagnostics()
    severity = {lsp.DiagnosticSeverity.Error: "error", lsp.DiagnosticSeverity.Warning: "warning",
                lsp.DiagnosticSeverity.Information: "info"}
    found = [((f"{d.range.start.line + 1}:{d.range.start.character + 1}-"
               f"{d.range.end.line + 1}:{d.range.end.character + 1}"),
              severity[d.severity], d.code, d.message) for d in got]
    assert found == parsed(path.with_suffix(".lint").read_text(encoding="utf-8"))
    doc.close()


async def test_pull_gives_what_is_pushed(client):
    """textDocument/diagnostic answers with the same diagnostics. (A client that can pull
    gets no pushes: `diagnostic_modes`, tests/test_ide_convert.py.)"""
    text = ("[greet]\n[goal:g]\n  [action]\n"
            "    [b##blk_jump: CND(! {TRUE}) TRJMP(nowhere) FLSJMP()]\n")
    doc = await Doc.open(client, "pull.script", text)
    pushed = await doc.diagnostics()
    report = await client.text_document_diagnostic_async(lsp.DocumentDiagnosticParams(doc.id))
    assert report.kind == "full"
    assert [(d.code, d.range) for d in report.items] == [(d.code, d.range) for d in pushed]
    assert [d.code for d in report.items] == ["F003", "L003"]
    await doc.replace(doc.text.index("nowhere"), doc.text.index("nowhere") + 7, "")
    report = await client.text_document_diagnostic_async(lsp.DocumentDiagnosticParams(doc.id))
    assert [d.code for d in report.items] == ["F003"]
    unknown = lsp.TextDocumentIdentifier("file:///not/open.script")
    report = await client.text_document_diagnostic_async(lsp.DocumentDiagnosticParams(unknown))
    assert list(report.items) == []
