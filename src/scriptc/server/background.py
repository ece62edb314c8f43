"""`scriptc verify` in the language server's background: the duration range of each open
script and its goals' reachability, shown as inlay hints (docs/editors.md, docs/verify.md).

A verification explores the script and replays runs: it may take a second or more, so it never
runs in the server's own process, where it would hold the interpreter while the user types.
When a script has not changed for VERIFY_IDLE_SECONDS, its text goes to one worker process
(`scriptc.ops.verify.overview`); when the answer comes back for the version still open, it is
kept and the client is asked to fetch its inlay hints again (`workspace/inlayHint/refresh`,
when it supports it; otherwise the next request gets them). An edit cancels the wait, and an
answer for an older version is dropped. Diagnostics never wait for any of it.
"""

from __future__ import annotations

import asyncio
import logging
import multiprocessing
from concurrent.futures import Future, ProcessPoolExecutor
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Callable

    from scriptc.ide.answers import VerifyOverview

log = logging.getLogger(__name__)

# A pause in typing this long starts a verification of the script.
VERIFY_IDLE_SECONDS = 1.0


def _overview(path: str, text: str) -> VerifyOverview | None:
    """The worker's job (a module-level function: the worker imports it by name)."""
    from scriptc.ops.verify import overview

    return overview(path, text)


class Background:
    """The verifications of the open scripts (see the module's docstring). `refresh()` is
    called when a new answer is kept."""

    def __init__(self, refresh: Callable[[], None]) -> None:
        self.refresh = refresh
        self.enabled = True
        self._pool: ProcessPoolExecutor | None = None
        self._timers: dict[str, asyncio.TimerHandle] = {}
        self._results: dict[str, tuple[int | None, VerifyOverview]] = {}
        self._running: dict[str, Future[VerifyOverview | None]] = {}

    def changed(self, uri: str, path: str, text: Callable[[], str],
                version: Callable[[], int | None]) -> None:
        """The document `uri` changed (or opened): verify it once it has been still for a
        while. `text()` and `version()` read the document when that time comes."""
        if not self.enabled:
            return
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no event loop (handlers called directly)
            return
        timer = self._timers.pop(uri, None)
        if timer is not None:
            timer.cancel()
        self._timers[uri] = loop.call_later(VERIFY_IDLE_SECONDS, self._start, loop, uri, path,
                                            text, version)

    def closed(self, uri: str) -> None:
        timer = self._timers.pop(uri, None)
        if timer is not None:
            timer.cancel()
        self._results.pop(uri, None)
        running = self._running.pop(uri, None)
        if running is not None:
            running.cancel()

    def overview(self, uri: str, version: int | None) -> VerifyOverview | None:
        """The verification of `uri` at `version`, if one came back for it."""
        found = self._results.get(uri)
        return found[1] if found is not None and found[0] == version else None

    def _start(self, loop: asyncio.AbstractEventLoop, uri: str, path: str,
               text: Callable[[], str], version: Callable[[], int | None]) -> None:
        self._timers.pop(uri, None)
        at = version()
        if self._results.get(uri, (object(),))[0] == at:
            return  # verified already
        previous = self._running.pop(uri, None)
        if previous is not None:
            previous.cancel()
        if self._pool is None:
            # A fresh interpreter (not a fork of this one: its reader thread and its state
            # stay here), started once.
            self._pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        future = self._pool.submit(_overview, path, text())
        self._running[uri] = future
        future.add_done_callback(
            lambda done: loop.call_soon_threadsafe(self._done, uri, at, done))

    def _done(self, uri: str, version: int | None,
              future: Future[VerifyOverview | None]) -> None:
        if self._running.get(uri) is future:
            del self._running[uri]
        if future.cancelled():
            return
        error = future.exception()
        if error is not None:
            log.warning("verifying %s failed: %s", uri, error)
            return
        result = future.result()
        if result is None:
            self._results.pop(uri, None)
            return
        self._results[uri] = (version, result)
        self.refresh()

    def shutdown(self) -> None:
        """No more verifications: the worker stops (what it was doing is dropped)."""
        self.enabled = False
        for timer in self._timers.values():
            timer.cancel()
        self._timers.clear()
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = None
