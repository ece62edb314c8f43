"""The repository's configuration in the language server: the server asks a client that can
watch files to watch `scriptc.toml` and `pyproject.toml`, and looks at them itself for a
client that cannot (Neovim on Linux); when one changes, every open document reads its
configuration again and gets new diagnostics: pushed again, or pulled again at the server's
request (`workspace/diagnostic/refresh`)."""

from __future__ import annotations

import asyncio

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from lsptest import SERVER_COMMAND, TIMEOUT, Doc, capabilities, make_client
from pytest_lsp import ClientServerConfig, LanguageClient

pytestmark = pytest.mark.asyncio(loop_scope="module")

# An instruction block after the terminus: F001 (unreachable), a warning.
TEXT = ("[greet]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n"
        "    [b##blk_inst: MV() LD() AO()]\n")


def watching_client() -> LanguageClient:
    """The tests' client, which also answers `client/registerCapability` and keeps what the
    server registered."""
    client = make_client()
    client.registrations = []

    @client.feature(lsp.CLIENT_REGISTER_CAPABILITY)
    def register(client: LanguageClient, params: lsp.RegistrationParams) -> None:
        client.registrations.extend(params.registrations)

    return client


@pytest_lsp.fixture(scope="module", config=ClientServerConfig(
    server_command=SERVER_COMMAND, client_factory=watching_client))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(capabilities=capabilities(watch=True)))
    yield
    await lsp_client.shutdown_session()


async def registered(client: LanguageClient) -> list[lsp.Registration]:
    async def wait():
        while not client.registrations:
            await asyncio.sleep(0.01)
        return client.registrations

    return await asyncio.wait_for(wait(), TIMEOUT)


async def test_the_server_asks_to_watch_the_configuration_files(client):
    (registration,) = await registered(client)
    assert registration.method == lsp.WORKSPACE_DID_CHANGE_WATCHED_FILES
    globs = [w["globPattern"] for w in registration.register_options["watchers"]]
    assert globs == ["**/scriptc.toml", "**/pyproject.toml"]


async def opened(client: LanguageClient, folder, config: str, name: str, text: str):
    """A document of a repository in `folder` whose scriptc.toml says `config`, opened, with
    its first diagnostics: (the document, the configuration's path, the diagnostics)."""
    path = folder / "scriptc.toml"
    path.write_text(config, encoding="utf-8")
    doc = Doc(client, (folder / name).as_uri(), text)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(doc.uri, "scriptc", doc.version, text)))
    return doc, path, await doc.diagnostics()


async def renewed(client: LanguageClient, doc: Doc, change: lsp.FileEvent):
    """The diagnostics the server publishes after `change`."""
    client.published.pop(doc.uri, None)
    client.workspace_did_change_watched_files(lsp.DidChangeWatchedFilesParams([change]))
    return await doc.diagnostics()


async def test_a_changed_configuration_renews_the_diagnostics(client, tmp_path):
    doc, config, first = await opened(client, tmp_path, '[lint]\nignore = ["F001"]\n',
                                      "activity.script", TEXT)
    assert first == []  # ignored by the configuration

    config.write_text('[lint]\nselect = ["F"]\n', encoding="utf-8")
    got = await renewed(client, doc, lsp.FileEvent(config.as_uri(), lsp.FileChangeType.Changed))
    assert [d.code for d in got] == ["F001"]

    config.write_text('[lint]\nignore = ["F001"]\n', encoding="utf-8")
    got = await renewed(client, doc, lsp.FileEvent(config.as_uri(), lsp.FileChangeType.Changed))
    assert [d.code for d in got] == []

    config.unlink()  # no configuration: the defaults report F001
    got = await renewed(client, doc, lsp.FileEvent(config.as_uri(), lsp.FileChangeType.Deleted))
    assert [d.code for d in got] == ["F001"]
    doc.close()


async def test_only_a_configuration_file_s_event_renews_the_configuration():
    """Events about other files (the editor may report more than was asked) change nothing;
    an event about either configuration file renews every document's configuration."""
    from scriptc.server.main import did_change_watched_files

    class Server:
        renewed = 0

        def reconfigure(self) -> None:
            self.renewed += 1

    server = Server()
    for name in ("notes.txt", "scriptc.toml.bak", "pyproject.toml~", "scriptc.toml",
                 "pyproject.toml"):
        did_change_watched_files(server, lsp.DidChangeWatchedFilesParams(
            [lsp.FileEvent(f"file:///repo/sub/{name}", lsp.FileChangeType.Changed)]))
    assert server.renewed == 2


async def test_the_robot_profile_of_the_configuration_applies(client, tmp_path):
    """K001 against the repository's `[robot]` limits, as `scriptc lint` checks them; and
    again when they change."""
    fast = ("[greet]\n[goal:g]\n  [action]\n"
            "    [b##blk_inst: MV(\"0.8, 0, 0, 0, 1000\") LD() AO()]\n"
            "    [b##blk_terminus]\n")
    doc, config, first = await opened(client, tmp_path, "[robot]\nmax-linear-speed = 1.0\n",
                                      "fast.script", fast)
    assert first == []  # 0.8 m/s is within 1.0
    config.write_text("[robot]\nmax-linear-speed = 0.5\n", encoding="utf-8")
    got = await renewed(client, doc, lsp.FileEvent(config.as_uri(), lsp.FileChangeType.Changed))
    assert [d.code for d in got] == ["K001"]
    assert "above the robot profile's 0.5 m/s" in got[0].message
    doc.close()


# Clients that watch no files, by how they get diagnostics.
UNWATCHING = {
    "push": {},  # Emacs's eglot, Helix
    "pull, no refresh": {"pull": True, "refresh": False},  # Neovim 0.10 and newer, on Linux
    "pull and refresh": {"pull": True},
}


@pytest_lsp.fixture(scope="module", config=ClientServerConfig(
    server_command=SERVER_COMMAND, client_factory=watching_client),
    params=list(UNWATCHING), ids=list(UNWATCHING))
async def unwatching(lsp_client: LanguageClient, request):
    lsp_client.kind = request.param
    lsp_client.init_result = await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=capabilities(**UNWATCHING[request.param])))
    yield
    await lsp_client.shutdown_session()


async def current(client: LanguageClient, doc: Doc, pulls: bool, refreshed: int) -> list[str]:
    """The codes of the document's diagnostics once the server has renewed them on its own:
    pushed anew, or pulled after the server's request to pull again."""
    async def wait():
        if pulls:
            while client.refreshes == refreshed:
                await asyncio.sleep(0.05)
            report = await client.text_document_diagnostic_async(
                lsp.DocumentDiagnosticParams(doc.id))
            return [d.code for d in report.items]
        return [d.code for d in await doc.diagnostics()]

    return await asyncio.wait_for(wait(), TIMEOUT)


async def test_a_client_that_watches_nothing_gets_the_changes_all_the_same(unwatching, tmp_path):
    """No file events: the server sees the configuration change by itself. A client that
    pulls but takes no request to pull again (Neovim) is pushed to instead, and is not
    offered pull diagnostics (it would show them twice)."""
    client = unwatching
    pulls = client.kind == "pull and refresh"
    assert (client.init_result.capabilities.diagnostic_provider is not None) == pulls
    assert client.registrations == []  # nothing to watch asked of a client that cannot
    config = tmp_path / "scriptc.toml"
    config.write_text('[lint]\nignore = ["F001"]\n', encoding="utf-8")
    doc = Doc(client, (tmp_path / "activity.script").as_uri(), TEXT)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(doc.uri, "scriptc", doc.version, TEXT)))
    refreshed = client.refreshes
    if pulls:
        report = await client.text_document_diagnostic_async(lsp.DocumentDiagnosticParams(doc.id))
        assert list(report.items) == []
    else:
        assert await doc.diagnostics() == []
    client.published.pop(doc.uri, None)
    config.write_text('[lint]\nselect = ["F"]\n', encoding="utf-8")
    assert await current(client, doc, pulls, refreshed) == ["F001"]
    client.published.pop(doc.uri, None)
    refreshed = client.refreshes
    config.unlink()
    (tmp_path / "pyproject.toml").write_text('[tool.scriptc.lint]\nignore = ["F"]\n',
                                             encoding="utf-8")
    assert await current(client, doc, pulls, refreshed) == []
    doc.close()
