"""Pausing the cyclic garbage collector while a stage builds many objects (scriptc/gcpause.py)."""

from __future__ import annotations

import gc
import weakref

import pytest

from scriptc.gcpause import PROMOTE_AT, gc_paused


class _Node:
    def __init__(self) -> None:
        self.other: _Node | None = None


@pytest.fixture(autouse=True)
def collector_on():
    was = gc.isenabled()
    gc.enable()
    yield
    if not was:
        gc.disable()


def test_the_collector_is_off_during_the_pause_and_as_it_was_after() -> None:
    with gc_paused():
        assert not gc.isenabled()
    assert gc.isenabled()
    gc.disable()
    with gc_paused():
        assert not gc.isenabled()
    assert not gc.isenabled()  # a pause inside a pause (or a disabled collector) keeps it off


@pytest.mark.slow
def test_what_a_long_pause_built_goes_to_the_oldest_generation_without_a_scan() -> None:
    gc.collect()
    with gc_paused():
        kept = [[i] for i in range(2 * PROMOTE_AT)]  # lists are tracked by the collector
    oldest = {id(o) for o in gc.get_objects(generation=2)}
    assert id(kept) in oldest and id(kept[0]) in oldest and id(kept[-1]) in oldest
    assert gc.get_freeze_count() == 0  # nothing is left frozen


def test_a_short_pause_leaves_the_generations_alone() -> None:
    gc.collect()
    with gc_paused():
        kept = [[i] for i in range(10)]
    assert id(kept[0]) not in {id(o) for o in gc.get_objects(generation=2)}


def test_a_garbage_cycle_made_in_a_long_pause_is_still_collected() -> None:
    with gc_paused():
        a, b = _Node(), _Node()
        a.other, b.other = b, a
        gone = weakref.ref(a)
        kept = [[i] for i in range(2 * PROMOTE_AT)]
        del a, b
    assert gone() is not None  # only a cycle holds it: reference counting cannot free it
    gc.collect()
    assert gone() is None and len(kept) == 2 * PROMOTE_AT
