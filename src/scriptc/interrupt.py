"""Ctrl-C as a request that long work takes at a safe point: one mechanism for every verb that
may run for long (`scriptc run` uses it; docs/runtime.md, "Interrupting a run").

By default Python turns SIGINT into `KeyboardInterrupt` wherever the main thread happens to be,
which may leave work half done (a trace missing its end), and not at all while C code holds
the thread (MuJoCo's `mj_step` over an hour of physics ignores Ctrl-C until it returns). So:

- `catching()` (a context manager, around the work): the first Ctrl-C only records the request;
  a second one raises `KeyboardInterrupt` at once, the way out if the work never reaches a safe
  point. Outside it, and in threads other than the main one (which never receive signals),
  nothing changes.
- `check()`, called by the work at its safe points (between two instants of a session, between
  two bounded chunks of physics steps), raises `Interrupted` when Ctrl-C was pressed. Work that
  runs in C for long must be cut into chunks short enough for the response time wanted (half a
  second), with a `check()` between them.
- `request()` records a request without a signal (tests; a parent stopping its work).
- `deferred()` (a context manager, around a step that must not be cut: a file being put in
  place by `scriptc.writing`, worker processes being started) holds Ctrl-C and SIGTERM back
  at the system's level; one that arrives meanwhile is delivered as the block ends. Work whose
  every such step is deferred needs no safe points: `scriptc lint` lets Ctrl-C raise
  `KeyboardInterrupt` wherever it falls (it stops at once, even inside one large file), and
  nothing is left half-written.

Whoever catches `Interrupted` finishes cleanly (closes what it writes, says how far it got) and
exits with `EXIT_STATUS`, 130 (128 + SIGINT), what shells report for a command stopped by
Ctrl-C. This module imports only the standard library, so anything may use it.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

EXIT_STATUS = 130


class _Request:
    """Whether a stop was requested: set by `request()` and by the SIGINT handler, cleared by
    `catching()`, read by `check()`."""

    __slots__ = ("pending",)

    def __init__(self) -> None:
        self.pending = False


_request = _Request()


class Interrupted(Exception):
    """Ctrl-C was pressed; raised by `check()` at a safe point of the work."""


def requested() -> bool:
    """Whether Ctrl-C was pressed (inside `catching()`) or `request()` was called."""
    return _request.pending


def request() -> None:
    """Ask the work to stop at its next `check()`."""
    _request.pending = True


def check() -> None:
    """Raise `Interrupted` when a stop was requested (cheap: call it as often as needed)."""
    if _request.pending:
        raise Interrupted("interrupted (Ctrl-C)")


def _on_sigint(signum: int, frame: FrameType | None) -> None:
    if _request.pending:  # the second Ctrl-C: the user does not want to wait for a safe point
        raise KeyboardInterrupt
    _request.pending = True


@contextmanager
def catching() -> Iterator[None]:
    """Within the block, Ctrl-C is a request taken by `check()` (see the module's docstring).
    The request is cleared on entry and on exit, and the previous SIGINT handler restored."""
    _request.pending = False
    previous = None
    if threading.current_thread() is threading.main_thread():
        try:
            previous = signal.signal(signal.SIGINT, _on_sigint)
        except ValueError:  # an embedding that does not let Python handle signals
            previous = None
    try:
        yield
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        _request.pending = False


@contextmanager
def deferred() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) and SIGTERM back during the block (see the module's docstring):
    one that arrives meanwhile is delivered as the block ends. Only the main thread runs signal
    handlers; elsewhere, and where signals cannot be blocked, this does nothing. Never around a
    wait that only the user can end (opening a FIFO that has no reader): Ctrl-C could not end it.

    Two locks, because the mask is a thread's: the signals are blocked for the main thread, and
    for the block their Python handlers are replaced by one that only records them, since the
    system hands a signal sent to the process to any thread that does not block it (a worker
    pool's threads, pytest-xdist's) and Python then runs its handler in the main thread all
    the same. A handler not installed from Python cannot be put back, so it is left alone."""
    if not hasattr(signal, "pthread_sigmask") or \
            threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum: int, frame: FrameType | None) -> None:
        held.append(signum)

    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(sig) is not None:
            previous[sig] = signal.signal(sig, hold)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)  # a blocked one arrives now: `hold`
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        # Each to the handler it was meant for, once; SIGTERM first, as Ctrl-C's
        # `KeyboardInterrupt` would leave the other undelivered.
        for sig in (signal.SIGTERM, signal.SIGINT):
            if sig in held:
                signal.raise_signal(sig)
