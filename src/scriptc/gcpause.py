"""Pausing Python's cyclic garbage collector while a stage builds many objects.

Lowering a 1 MB script creates about a million small objects (tokens, trees, IR nodes), none
of them in reference cycles. The collector's generational passes, triggered by allocation
counts, then rescan everything built so far again and again: measured here, they doubled the
time of parsing and lowering. Reference counting frees all of it anyway; the pause only skips
useless scans, and the previous state is restored afterwards (the language server keeps
running with the collector on). The objects a long pause leaves behind are moved to the
oldest generation at once, rather than scanned by the next young collection.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

# The net count of objects a pause may leave in the youngest generation before they are moved
# on at once (below): a script of a few hundred lines leaves fewer.
PROMOTE_AT = 10_000


@contextmanager
def gc_paused() -> Iterator[None]:
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            if gc.get_count()[0] >= PROMOTE_AT:
                # What the pause built and kept (the IR of a large script: 640,000 objects for
                # 1.6 MB) sits in the youngest generation, whose next collection would only
                # scan it all to move it on (0.1 s, 15 % of a compile). `freeze` then
                # `unfreeze` moves every tracked object to the oldest generation without a
                # scan (two list splices); a full collection still examines them, as it does
                # any old object, so no garbage cycle escapes it.
                gc.freeze()
                gc.unfreeze()
            gc.enable()
