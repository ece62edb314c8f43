"""Pausing Python's cyclic garbage collector while a stage builds many objects.

Lowering a 1 MB script creates about a million small objects (tokens, trees, IR nodes), none
of them in reference cycles. The collector's generational passes, triggered by allocation
counts, then rescan everything built so far again and again: measured here, they doubled the
time of parsing and lowering. Reference counting frees all of it anyway; the pause only skips
useless scans, and the previous state is restored afterwards (the language server keeps
running with the collector on).
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def gc_paused() -> Iterator[None]:
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
