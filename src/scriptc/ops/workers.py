"""Worker processes for the verbs that spread work over the cores (`lint`, `test`): how many
cores there are, and chunks of work run in a process pool that Ctrl-C stops at once.

The workers are forked where the platform can (they start with scriptc already imported) and
ignore Ctrl-C: a terminal sends it to every process of the command, and the parent, which
takes it (a `KeyboardInterrupt` wherever it falls), stops them with SIGTERM, at once, not after
their chunks (`stop_workers`). They are started with Ctrl-C and SIGTERM held back
(`scriptc.interrupt.deferred`), so that none is started before it ignores Ctrl-C.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, TypeVar

from scriptc import interrupt

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

__all__ = ["PoolFailed", "available_cores", "map_chunks", "start_worker", "stop_workers"]

Item = TypeVar("Item")
Result = TypeVar("Result")


class PoolFailed(Exception):
    """No worker process can be started here (a sandbox): the caller does the work itself."""


def available_cores() -> int:
    """The cores this process may run on (its affinity), at least one."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def map_chunks(work: Callable[[list[Item]], list[Result]], chunks: Sequence[list[Item]],
               jobs: int, done: Callable[[int, int, Result], None]) -> None:
    """Run `work` over each chunk in at most `jobs` worker processes; as a chunk finishes, call
    `done(chunk, position in the chunk, result)` here, for each of its items. Raises PoolFailed
    when no pool can start; when a worker dies (`BrokenProcessPool`) or anything else stops the
    parent (Ctrl-C), the workers are stopped and the exception goes on: the caller knows from
    `done` which items are finished."""
    import multiprocessing
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else None)
    try:
        pool = ProcessPoolExecutor(max_workers=max(1, min(jobs, len(chunks))),
                                   mp_context=context, initializer=start_worker)
    except (OSError, ValueError, NotImplementedError) as exc:
        raise PoolFailed from exc
    try:
        # The workers are started by the first submissions; Ctrl-C is held back meanwhile.
        with interrupt.deferred():
            pending = {pool.submit(work, chunk): c for c, chunk in enumerate(chunks)}
        while pending:
            ready, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in ready:
                c = pending.pop(future)
                for k, result in enumerate(future.result()):
                    done(c, k, result)
    except BaseException:
        stop_workers(pool)
        raise
    else:
        pool.shutdown(wait=True)


def start_worker() -> None:
    """The start of a worker process: Ctrl-C is the parent's to handle. The worker was forked
    with Ctrl-C and SIGTERM held back (`interrupt.deferred`: blocked, and their handlers the
    one that only records them): SIGTERM, by which the parent stops it, must end it again."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})


def stop_workers(pool: ProcessPoolExecutor) -> None:
    """Stop a process pool at once: pending work cancelled, the workers terminated and
    waited for (none is left behind). `shutdown` alone would wait for the chunks already
    running; the pool has no public way to terminate its workers before Python 3.14
    (`terminate_workers`), so they are taken from its `_processes`."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout=5)
        if process.is_alive():
            process.kill()
            process.join()
    pool.shutdown(wait=True)
