"""verify/timeset.py: sets of times as unions of arithmetic progressions.

Every operation is compared with Python sets over a window [0, W) that holds every finite
part of the sets drawn and several periods of their infinite parts, so that two sets equal
in the window are equal; the canonical form is checked on every result; worked examples
hold the merging rules, the texts and the bound `MAX_PIECES`.
"""

from __future__ import annotations

import pickle
from itertools import pairwise
from math import lcm

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scriptc.verify.timeset import MAX_PIECES, Piece, TimeSet, TooComplex

LAWS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# The sets drawn: starts < 30, steps <= 6, at most 8 elements a finite piece; every finite
# part ends below 72 and every period divides 60, so a window of W holds them and eight
# periods of what follows them.
W = 600
RAW_PIECES = st.tuples(st.integers(0, 30), st.integers(1, 6),
                       st.one_of(st.integers(1, 8), st.integers(1, 8), st.none()))
RAWS = st.lists(RAW_PIECES, max_size=4)


def elements_of(pieces: list[Piece] | tuple[Piece, ...], window: int = W) -> set[int]:
    """The elements of pieces below `window`, read from the pieces alone."""
    out: set[int] = set()
    for start, step, count in pieces:
        stop = window if count is None else min(window, start + step * count)
        out.update(range(start, stop, step))
    return out


def build(raw: list[Piece]) -> TimeSet:
    """The union of the raw pieces, one `progression` after another."""
    ts = TimeSet.empty()
    for start, step, count in raw:
        ts = ts | TimeSet.progression(start, step, count)
    return ts


def check_canonical(ts: TimeSet) -> None:
    """The rules of the canonical form that every result keeps."""
    pieces = ts.pieces
    assert len(pieces) <= MAX_PIECES
    assert list(pieces) == sorted(pieces)
    assert len({(p[0], p[1]) for p in pieces}) == len(pieces)
    for start, step, count in pieces:
        assert start >= 0 and step >= 1
        assert count is None or count >= 1
        if count == 1:
            assert step == 1
        if step > 1:
            assert count is None or count >= 3
    intervals = [p for p in pieces if p[1] == 1 and p[2] != 1]
    points = [p[0] for p in pieces if p[2] == 1]
    progressions = [p for p in pieces if p[1] > 1]
    ones = sorted(p for p in pieces if p[1] == 1)
    for p, q in pairwise(ones):
        end = p[0] + p[2] - 1 if p[2] is not None else None
        assert end is not None and q[0] > end + 1, (p, q)
    for i, p in enumerate(progressions):
        for q in progressions[i + 1:]:
            if p[1] == q[1] and (p[0] - q[0]) % p[1] == 0:
                first, second = sorted([p, q], key=lambda x: x[0])
                assert first[2] is not None
                assert second[0] > first[0] + first[1] * first[2], (p, q)
        for t in points:
            end = None if p[2] is None else p[0] + p[1] * (p[2] - 1)
            near = p[0] - p[1] <= t and (end is None or t <= end + p[1])
            assert not (near and (t - p[0]) % p[1] == 0), (p, t)
        for iv in intervals:
            iv_end = None if iv[2] is None else iv[0] + iv[2] - 1
            p_end = None if p[2] is None else p[0] + p[1] * (p[2] - 1)
            inside = iv[0] <= p[0] and (iv_end is None or (p_end is not None and p_end <= iv_end))
            assert not inside, (p, iv)


def window(ts: TimeSet, size: int = W) -> set[int]:
    check_canonical(ts)
    return elements_of(ts.pieces, size)


# Building and querying


@LAWS
@given(RAWS)
def test_a_set_holds_what_it_was_built_from(raw: list[Piece]) -> None:
    ts = build(raw)
    model = elements_of(raw)
    assert window(ts) == model
    assert TimeSet(raw) == ts
    assert window(TimeSet(raw)) == model
    assert [t for t in range(-3, W) if t in ts] == sorted(model)
    assert bool(ts) == bool(raw)
    infinite = any(count is None for _, _, count in raw)
    assert ts.is_infinite == infinite
    if not raw:
        for query in (ts.min, ts.max):
            with pytest.raises(ValueError):
                query()
        assert ts.size() == 0
        assert ts.first(3) == []
        return
    assert ts.min() == min(model)
    assert ts.max() == (None if infinite else max(model))
    assert ts.size() == (None if infinite else len(model))
    assert ts.first(12) == sorted(model)[:12]


@LAWS
@given(RAWS, st.lists(st.integers(-5, W - 100), max_size=6))
def test_nearest_elements(raw: list[Piece], probes: list[int]) -> None:
    ts = build(raw)
    model = elements_of(raw)
    for t in probes:
        below = [x for x in model if x <= t]
        above = [x for x in model if x >= t]
        assert ts.last_at_most(t) == (max(below) if below else None)
        assert ts.first_at_least(t) == (min(above) if above else None)


@LAWS
@given(RAWS, st.integers(0, 80))
def test_elements_of_a_finite_set(raw: list[Piece], limit: int) -> None:
    ts = build(raw)
    if ts.is_infinite:
        with pytest.raises(ValueError):
            ts.elements(10_000)
        return
    model = sorted(elements_of(raw))
    if len(model) > limit:
        with pytest.raises(ValueError):
            ts.elements(limit)
    else:
        assert ts.elements(limit) == model
        assert TimeSet.of(model) == ts
        assert window(TimeSet.of(model)) == set(model)


# Equality


@LAWS
@given(RAWS, RAWS)
def test_equality_is_equality_of_sets(raw_a: list[Piece], raw_b: list[Piece]) -> None:
    a = build(raw_a)
    b = build(raw_b)
    same = elements_of(raw_a) == elements_of(raw_b)
    assert (a == b) == same
    assert (a != b) == (not same)
    if same:
        assert hash(a) == hash(b)
    assert a.issubset(b) == (elements_of(raw_a) <= elements_of(raw_b))


@LAWS
@given(RAWS, st.permutations(range(4)))
def test_the_order_of_building_does_not_matter(raw: list[Piece], order: list[int]) -> None:
    reordered = [raw[i] for i in order if i < len(raw)]
    a = build(raw)
    b = build(reordered)
    assert a == b
    assert hash(a) == hash(b)


# Algebra


@LAWS
@given(RAWS, RAWS)
def test_union_intersection_difference(raw_a: list[Piece], raw_b: list[Piece]) -> None:
    a = build(raw_a)
    b = build(raw_b)
    ma = elements_of(raw_a)
    mb = elements_of(raw_b)
    assert window(a | b) == ma | mb
    assert window(a & b) == ma & mb
    assert window(a - b) == ma - mb
    assert window(b - a) == mb - ma
    assert a.union(b) == b | a
    assert a.intersection(b) == b & a
    assert (a - b) | (a & b) == a
    assert (a - b) | b == a | b
    assert not (a - b) & b
    assert a - a == TimeSet.empty()
    assert a | a == a
    assert a & a == a
    assert (a | b).is_infinite == (a.is_infinite or b.is_infinite)


@LAWS
@given(RAWS, RAWS, RAWS)
def test_distributive_laws(raw_a: list[Piece], raw_b: list[Piece], raw_c: list[Piece]) -> None:
    a, b, c = build(raw_a), build(raw_b), build(raw_c)
    assert a & (b | c) == (a & b) | (a & c)
    assert a - (b | c) == (a - b) - c
    assert (a | b) | c == a | (b | c)


@LAWS
@given(RAWS, st.integers(-40, 60))
def test_shift(raw: list[Piece], d: int) -> None:
    a = build(raw)
    if a and a.min() + d < 0:
        with pytest.raises(ValueError):
            a.shift(d)
        return
    shifted = a.shift(d)
    model = {x + d for x in elements_of(raw, W + 40)}
    assert window(shifted) == {x for x in model if x < W}
    assert shifted.shift(-d) == a
    assert shifted.pieces == a.shift(d).pieces


@LAWS
@given(RAWS, st.integers(-5, 90), st.one_of(st.none(), st.integers(-5, 90)), st.integers(-5, 90))
def test_clip_below_above(raw: list[Piece], lo: int, hi: int | None, c: int) -> None:
    a = build(raw)
    model = elements_of(raw)
    assert window(a.clip(lo, hi)) == {x for x in model if x >= lo and (hi is None or x <= hi)}
    assert window(a.below(c)) == {x for x in model if x < c}
    assert window(a.above(c)) == {x for x in model if x > c}
    assert a.below(c) | a.above(c) | (a & TimeSet.point(c) if c >= 0 else TimeSet.empty()) == a


@LAWS
@given(RAWS, st.integers(1, 10), st.one_of(st.none(), st.integers(0, 5)))
def test_repeat_is_the_union_of_shifted_copies(raw: list[Piece], d: int,
                                               times: int | None) -> None:
    a = build(raw)
    size = 1000
    repeated = a.repeat(d, times)
    model = elements_of(raw, size)
    if times is None:
        expected: set[int] = set()
        for t in range(size):
            if t in model or t - d in expected:
                expected.add(t)
    else:
        expected = {x + j * d for x in model for j in range(times + 1) if x + j * d < size}
    assert window(repeated, size) == expected
    if times is not None:
        brute = TimeSet.empty()
        for j in range(times + 1):
            brute = brute | a.shift(j * d)
        assert repeated == brute
    else:
        assert repeated.is_infinite == bool(a)
        assert repeated.repeat(d, None) == repeated


@LAWS
@given(RAW_PIECES, RAW_PIECES)
def test_the_union_of_two_pieces_is_the_general_canonical_form(p: Piece, q: Piece) -> None:
    # `|` of two single pieces takes a short way (`_union2`): the same pieces as the long one.
    a = TimeSet([p])
    b = TimeSet([q])
    if len(a.pieces) == 1 and len(b.pieces) == 1:
        assert (a | b).pieces == TimeSet([*a.pieces, *b.pieces]).pieces


# The canonical form

CANONICAL = [
    # A point extending a progression at either end is merged into it.
    (TimeSet.progression(0, 500, 3) | TimeSet.point(1500), ((0, 500, 4),)),
    (TimeSet.point(0) | TimeSet.progression(500, 500, None), ((0, 500, None),)),
    # A point on a progression is inside it; one off its residue stays.
    (TimeSet.progression(0, 500, 4) | TimeSet.point(1000), ((0, 500, 4),)),
    (TimeSet.progression(0, 500, 4) | TimeSet.point(1001), ((0, 500, 4), (1001, 1, 1))),
    # A point between two aligned progressions joins them.
    (TimeSet.progression(0, 500, 3) | TimeSet.progression(2000, 500, 3) | TimeSet.point(1500),
     ((0, 500, 7),)),
    # Points in a row, one step apart, extend a progression one after the other.
    (TimeSet.progression(3000, 500, 3) | TimeSet.of([1500, 2000, 2500]), ((1500, 500, 6),)),
    # Intervals that touch or overlap become one; points next to an interval join it.
    (TimeSet.interval(0, 9) | TimeSet.interval(10, 20), ((0, 1, 21),)),
    (TimeSet.interval(0, 9) | TimeSet.interval(5, None), ((0, 1, None),)),
    (TimeSet.point(4) | TimeSet.point(5) | TimeSet.point(6), ((4, 1, 3),)),
    # Aligned progressions that overlap or follow each other become one.
    (TimeSet.progression(0, 5, 10) | TimeSet.progression(25, 5, None), ((0, 5, None),)),
    (TimeSet.progression(0, 5, 3) | TimeSet.progression(15, 5, 3), ((0, 5, 6),)),
    (TimeSet.progression(1200, 500, None) | TimeSet.progression(1700, 500, None),
     ((1200, 500, None),)),
    # Not aligned, or apart: they stay.
    (TimeSet.progression(0, 5, 3) | TimeSet.progression(20, 5, 3), ((0, 5, 3), (20, 5, 3))),
    (TimeSet.progression(0, 5, 3) | TimeSet.progression(1, 5, 3), ((0, 5, 3), (1, 5, 3))),
    # Three equally spaced points are a progression; two are two points.
    (TimeSet.point(0) | TimeSet.point(500) | TimeSet.point(1000), ((0, 500, 3),)),
    (TimeSet.progression(0, 500, 2), ((0, 1, 1), (500, 1, 1))),
    (TimeSet.of(range(0, 35001, 500)), ((0, 500, 71),)),
    # A progression inside an interval, or inside a coarser progression, is dropped.
    (TimeSet.interval(0, 100) | TimeSet.progression(10, 7, 5), ((0, 1, 101),)),
    (TimeSet.progression(0, 2, None) | TimeSet.progression(4, 6, 9), ((0, 2, None),)),
    # Progressions of one step that take turns become one of a smaller step.
    (TimeSet.progression(0, 4, None) | TimeSet.progression(2, 4, None), ((0, 2, None),)),
    (TimeSet.progression(49, 6, 12) | TimeSet.progression(52, 6, 11), ((49, 3, 23),)),
    (TimeSet.progression(0, 6, None) | TimeSet.progression(2, 6, None)
     | TimeSet.progression(4, 6, None) | TimeSet.progression(1, 2, None), ((0, 1, None),)),
    # A set cut by another and put together again: (a & x) | (a - x) is a.
    ((TimeSet.progression(0, 3, None) & TimeSet.progression(30, 4, None))
     | (TimeSet.progression(0, 3, None) - TimeSet.progression(30, 4, None)), ((0, 3, None),)),
    # Not when their counts do not take turns.
    (TimeSet.progression(49, 6, 12) | TimeSet.progression(52, 6, 9),
     ((49, 6, 12), (52, 6, 9))),
    # Repetitions are single progressions where they can be.
    (TimeSet.point(0).repeat(500, 70), ((0, 500, 71),)),
    (TimeSet.interval(0, 499).repeat(500, None), ((0, 1, None),)),
    (TimeSet.interval(0, 99).repeat(500, 2), ((0, 1, 100), (500, 1, 100), (1000, 1, 100))),
    (TimeSet.progression(0, 2, None).repeat(1, None), ((0, 1, None),)),
    (TimeSet.of([0, 300]).repeat(500, None), ((0, 500, None), (300, 500, None))),
    (TimeSet.progression(0, 3, 10).repeat(2, 3), ((0, 2, 16), (3, 2, 16))),
    # Differences and clips that leave pieces next to each other.
    (TimeSet.all() - TimeSet.progression(5, 3, 2), ((0, 1, 5), (6, 1, 2), (9, 1, None))),
    (TimeSet.all() - TimeSet.progression(0, 2, None), ((1, 2, None),)),
    ((TimeSet.progression(0, 2, 3) | TimeSet.interval(5, 7)).clip(4, 7), ((4, 1, 4),)),
]


@pytest.mark.parametrize(("ts", "pieces"), CANONICAL)
def test_canonical_form(ts: TimeSet, pieces: tuple[Piece, ...]) -> None:
    assert ts.pieces == pieces
    assert ts == TimeSet(pieces)
    check_canonical(ts)


EQUAL = [
    (TimeSet.progression(0, 500, 71), TimeSet.point(0).repeat(500, 70)),
    (TimeSet.progression(0, 2, 500) | TimeSet.progression(1, 2, 500), TimeSet.interval(0, 999)),
    (TimeSet.progression(0, 2, None) | TimeSet.progression(1, 2, None), TimeSet.all()),
    # A covering system (Erdos): every integer is 0 mod 2, 0 mod 3, 1 mod 4, 5 mod 6 or 7 mod 12.
    (TimeSet.progression(0, 2, None) | TimeSet.progression(0, 3, None)
     | TimeSet.progression(1, 4, None) | TimeSet.progression(5, 6, None)
     | TimeSet.progression(7, 12, None), TimeSet.all()),
    (TimeSet.progression(0, 4, None) | TimeSet.progression(2, 4, None),
     TimeSet.progression(0, 2, None)),
    (TimeSet.interval(0, 10) - TimeSet.interval(3, 5), TimeSet.of([0, 1, 2, 6, 7, 8, 9, 10])),
]


@pytest.mark.parametrize(("a", "b"), EQUAL)
def test_equal_sets_built_different_ways(a: TimeSet, b: TimeSet) -> None:
    assert a == b
    assert b == a
    assert hash(a) == hash(b)
    assert a.size() == b.size()
    assert a.first(50) == b.first(50)
    assert a != b - TimeSet.point(b.min())
    assert {a: 1}[b] == 1


def test_size_of_overlapping_pieces() -> None:
    ts = TimeSet.progression(0, 2, 50) | TimeSet.progression(0, 3, 40)
    assert ts.size() == len(set(range(0, 100, 2)) | set(range(0, 120, 3)))
    assert ts.elements(200) == sorted(set(range(0, 100, 2)) | set(range(0, 120, 3)))


# Exactness and the bound


def test_too_complex_instead_of_an_approximation() -> None:
    with pytest.raises(TooComplex, match="more than"):
        TimeSet.all() - TimeSet.progression(0, 1000, None)
    with pytest.raises(TooComplex):
        TimeSet.of(i * i for i in range(600))
    with pytest.raises(TooComplex):
        TimeSet.progression(0, 1000, None).repeat(1001, None)
    with pytest.raises(TooComplex):
        TimeSet.of(range(3, 3 * 600, 3)).repeat(10_000, None)
    residues = TimeSet.of(range(0, 2 * 300, 2)).repeat(10_000, None)
    with pytest.raises(TooComplex):
        residues | residues.shift(1)
    # Every time but the multiples of a prime p is p - 1 progressions of step p: exact
    # under the bound (509), refused over it (521).
    ts = TimeSet.all() - TimeSet.progression(0, 509, None)
    assert len(ts.pieces) == 508
    assert 0 not in ts and 509 * 7 not in ts and 509 * 7 + 1 in ts
    with pytest.raises(TooComplex):
        TimeSet.all() - TimeSet.progression(0, 521, None)
    # Where the progressions interleave, the bound is far: 9 pieces, not 511.
    ts = TimeSet.all() - TimeSet.progression(0, MAX_PIECES, None)
    assert ts.pieces == tuple((2**i, 2 ** (i + 1), None) for i in range(9))


def test_huge_steps_stay_exact() -> None:
    # The intersection of two progressions is one progression, however large the lcm.
    a = TimeSet.progression(0, 999_983, None)
    b = TimeSet.progression(5, 1_000_003, None)
    both = a & b
    assert len(both.pieces) == 1
    first = both.min()
    assert first % 999_983 == 0 and first % 1_000_003 == 5
    assert both.first(2)[1] - first == 999_983 * 1_000_003
    assert both.issubset(a) and both.issubset(b)
    # A difference that removes a few elements of a long progression keeps the rest in runs.
    long = TimeSet.interval(0, 10**9)
    holes = long - TimeSet.progression(0, 10**8, None)
    assert holes.size() == 10**9 + 1 - 11
    assert 10**8 not in holes and 10**8 + 1 in holes


# Arguments


def test_arguments_are_checked() -> None:
    for make in (lambda: TimeSet.point(-1), lambda: TimeSet.interval(-1, 3),
                 lambda: TimeSet.progression(0, 0, 3), lambda: TimeSet.progression(0, 1, -1),
                 lambda: TimeSet.of([3, -1]), lambda: TimeSet.point(3).shift(-4),
                 lambda: TimeSet.point(3).repeat(0, 2), lambda: TimeSet.point(3).repeat(1, -1)):
        with pytest.raises(ValueError):
            make()
    assert TimeSet.interval(5, 4) == TimeSet.empty()
    assert TimeSet.progression(5, 3, 0) == TimeSet.empty()
    assert TimeSet() == TimeSet.empty()
    assert TimeSet.all() == TimeSet.interval(0, None)
    assert TimeSet.point(3).shift(-3) == TimeSet.point(0)


def test_immutable_hashable_picklable() -> None:
    ts = TimeSet.progression(0, 500, 71) | TimeSet.interval(40_000, None)
    with pytest.raises(AttributeError):
        ts._pieces = ()  # type: ignore[misc]  # the point of the test
    with pytest.raises(AttributeError):
        ts.extra = 1  # type: ignore[attr-defined]  # the point of the test
    assert pickle.loads(pickle.dumps(ts)) == ts
    assert len({ts, TimeSet.of(range(0, 35001, 500)) | TimeSet.interval(40_000, None)}) == 1
    assert TimeSet.point(1) != (1,)


# Text

TEXTS = [
    (TimeSet.empty(), "TimeSet({})", "never"),
    (TimeSet.point(1200), "TimeSet({1200})", "1200 ms"),
    (TimeSet.interval(1000, 2000), "TimeSet({1000..2000})", "1000 to 2000 ms"),
    (TimeSet.interval(1200, None), "TimeSet({1200..})", "from 1200 ms on"),
    (TimeSet.progression(0, 500, 71), "TimeSet({0..35000 step 500})",
     "0 to 35000 ms every 500 ms"),
    (TimeSet.progression(1200, 500, None), "TimeSet({1200.. step 500})",
     "from 1200 ms every 500 ms"),
    (TimeSet.progression(0, 500, 71) | TimeSet.point(36000) | TimeSet.interval(40000, None),
     "TimeSet({0..35000 step 500, 36000, 40000..})",
     "0 to 35000 ms every 500 ms, 36000 ms or from 40000 ms on"),
    (TimeSet.of([0, 500]), "TimeSet({0, 500})", "0 ms or 500 ms"),
    (TimeSet.of([0, 10, 30, 70, 150, 310, 630, 1270]),
     "TimeSet({0, 10, 30, 70, 150, 310, 630, 1270})",
     "0 ms, 10 ms, 30 ms, 70 ms, 150 ms or 3 more, up to 1270 ms"),
]


@pytest.mark.parametrize(("ts", "shown", "described"), TEXTS)
def test_repr_and_describe(ts: TimeSet, shown: str, described: str) -> None:
    assert repr(ts) == shown
    assert ts.describe() == described


def test_periods_in_the_window() -> None:
    # The window of the laws holds the finite parts and eight periods of the drawn sets.
    assert 30 + 6 * 7 + 8 * lcm(1, 2, 3, 4, 5, 6) <= W
