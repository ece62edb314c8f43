"""The language server's background verification (server/background.py), driven directly on
an event loop: a document still for a while is verified in a worker process, the answer is
kept for the version it was made for and announced, an edit or a close drops what is under
way, and `enabled = False` (`initializationOptions: {"verify": false}`) does nothing."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest

from scriptc.server import background
from scriptc.server.background import Background

pytestmark = pytest.mark.slow

EXAMPLE = Path(__file__).parent.parent / "examples" / "greeting.script"


class Doc:
    def __init__(self, text: str, version: int = 1) -> None:
        self.text, self.version = text, version


async def settle(bg: Background, refreshed: list[int], count: int, timeout: float = 60) -> None:
    async def wait() -> None:
        while len(refreshed) < count:
            await asyncio.sleep(0.05)

    await asyncio.wait_for(wait(), timeout)


def test_a_still_document_is_verified_and_announced(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "VERIFY_IDLE_SECONDS", 0.05)

    async def main() -> None:
        refreshed: list[int] = []
        bg = Background(lambda: refreshed.append(1))
        doc = Doc(EXAMPLE.read_text(encoding="utf-8"))
        bg.changed("file:///g", str(EXAMPLE), lambda: doc.text, lambda: doc.version)
        await settle(bg, refreshed, 1)
        found = bg.overview("file:///g", 1)
        assert found is not None and (found.shortest, found.longest) == (4000, 34000)
        assert [v for _, v, _ in found.goals] == ["reached"] * 3
        assert bg.overview("file:///g", 2) is None  # another version: not this answer
        # An edit: the next answer is for the new version; the old one is not shown for it.
        doc.text, doc.version = doc.text.replace("1.5)", "0.5)"), 2
        bg.changed("file:///g", str(EXAMPLE), lambda: doc.text, lambda: doc.version)
        await settle(bg, refreshed, 2)
        assert bg.overview("file:///g", 2) is not None
        bg.closed("file:///g")
        assert bg.overview("file:///g", 2) is None
        bg.shutdown()

    asyncio.run(main())


def test_a_script_with_errors_gives_no_hints(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "VERIFY_IDLE_SECONDS", 0.05)

    async def main() -> None:
        bg = Background(lambda: None)
        doc = Doc("[broken]\n[goal:g]\n")
        bg.changed("file:///b", str(EXAMPLE), lambda: doc.text, lambda: doc.version)
        await asyncio.sleep(0.2)
        for _ in range(600):
            if not bg._running and not bg._timers:
                break
            await asyncio.sleep(0.05)
        assert bg.overview("file:///b", 1) is None
        bg.shutdown()

    asyncio.run(main())


def test_disabled_or_without_a_loop_nothing_is_scheduled() -> None:
    bg = Background(lambda: None)
    bg.changed("file:///x", "x.script", lambda: "", lambda: 1)  # no running loop: nothing
    assert not bg._timers

    async def main() -> None:
        bg.enabled = False
        bg.changed("file:///x", "x.script", lambda: "", lambda: 1)
        assert not bg._timers

    asyncio.run(main())
