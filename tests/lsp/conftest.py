"""The shared server of each test module of tests/lsp/ (see lsptest.py)."""

from __future__ import annotations

import pytest_lsp
from lsptest import CONFIG, start
from pytest_lsp import LanguageClient


@pytest_lsp.fixture(scope="module", config=CONFIG)
async def client(lsp_client: LanguageClient):
    await start(lsp_client)
    yield
    await lsp_client.shutdown_session()
