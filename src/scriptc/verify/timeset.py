"""Sets of times for the explorer of `scriptc verify`: exact, compact, fast.

Time is whole milliseconds and every delay of the language is a fixed integer, so the times at
which the robot can be at one point of a script form a set of integers >= 0: {0, 500, ...,
35000} for a loop that waits 500 ms and is left on a timeout, {1200, 1700, 2200, ...} without
end for a loop that never ends. `TimeSet` holds such a set exactly, as a finite union of
arithmetic progressions ("pieces"), each `(start, step, count)`: the elements start + step*k
for 0 <= k < count, or for every k >= 0 when count is None. Nothing is ever approximated: an
exact result that would need more than `MAX_PIECES` pieces raises `TooComplex`, which the
explorer reports as "unknown: the bound was reached".

The pieces are kept in a canonical form as far as that is cheap (`_canonical`):

- the pieces are sorted by start (then step); none is empty;
- a piece of one element is a point, `(t, 1, 1)`; a piece of step 1 is an interval;
- a progression of step > 1 has at least three elements: two elements are two points;
- intervals that overlap or touch are merged into one;
- progressions of one step and one residue modulo the step that overlap or follow each other
  (the gap is the step) are merged into one;
- three or more points in a row, equally spaced, become one progression (greedily, from the
  smallest), before the progressions are merged;
- a point that lies on a progression (same residue, inside its range) or extends it by one
  step at either end is merged into it, repeatedly;
- progressions of one step s that take turns (k of them for a prime factor k of s, starting
  s/k apart, their counts as those of one progression dealt out in turn) become one
  progression of step s/k, which may merge further: (0, 4, None) and (2, 4, None) are
  (0, 2, None);
- a progression inside an interval is dropped; so is a progression inside another one of a
  step that divides its own, when there are at most `_FEW` progressions.

Equal sets built in different ways usually have the same pieces, but not always: pieces of
different steps may overlap, and points join progressions greedily. So equality does not
depend on it: `==` compares the pieces first and, when they differ, checks that each set is a
subset of the other, exactly.

Speed: the explorer calls these operations hundreds of thousands of times. A set is a slotted
object around a tuple of tuples; the union of two single pieces (`_union2`), the shift (which
keeps the canonical form), a clip that changes nothing and the queries take short ways;
everything else goes through `_canonical` once.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Callable, Iterable
from functools import lru_cache
from heapq import heappop, heapreplace
from math import gcd
from operator import itemgetter
from typing import TypeAlias

__all__ = ["MAX_PIECES", "Piece", "TimeSet", "TooComplex"]

# The most pieces a result may have; an exact result that needs more raises `TooComplex`.
MAX_PIECES = 512

# `(start, step, count)`: start + step*k for 0 <= k < count; count None: for every k >= 0.
Piece: TypeAlias = tuple[int, int, int | None]

# The number of progressions up to which `_canonical` drops a progression that another one
# holds (a check of every pair).
_FEW = 16
# The pieces a subset test or a size may go through before it gives up with `TooComplex`.
_WORK = 100_000

_START = itemgetter(0)


class TooComplex(Exception):
    """An exact result would need more pieces than `MAX_PIECES` (or more work than a check
    may do); the message says what grew too large."""


def _piece(start: int, step: int, count: int | None) -> Piece:
    """The piece of `count` elements from `start` every `step`; a point when it has one."""
    if count == 1:
        return (start, 1, 1)
    return (start, step, count)


def _end(p: Piece) -> int | None:
    """The last element of a piece; None when it has no end."""
    n = p[2]
    return None if n is None else p[0] + p[1] * (n - 1)


def _count(p: Piece) -> int:
    """The number of elements of a finite piece."""
    assert p[2] is not None
    return p[2]


def _max(pieces: tuple[Piece, ...]) -> int | None:
    """The greatest element of a non-empty set; None when it is infinite."""
    top = -1
    for start, step, count in pieces:
        if count is None:
            return None
        end = start + step * (count - 1)
        if end > top:
            top = end
    return top


def _single(p: Piece) -> tuple[Piece, ...]:
    """The canonical pieces of one piece: two points for a progression of two elements."""
    start, step, count = p
    if count == 2 and step > 1:
        return ((start, 1, 1), (start + step, 1, 1))
    if count == 1 and step != 1:
        return ((start, 1, 1),)
    return (p,)


def _merge_aligned(members: list[Piece], step: int) -> list[Piece]:
    """Pieces of one step and one residue, those that overlap or follow each other merged."""
    members.sort(key=_START)
    out: list[Piece] = []
    start, _, count = members[0]
    end = None if count is None else start + step * (count - 1)
    for p in members:
        if end is None:
            break  # every later member starts inside the run, which has no end
        s, _, c = p
        if s <= end + step:
            if c is None:
                end = None
            else:
                e = s + step * (c - 1)
                if e > end:
                    end = e
        else:
            out.append(_piece(start, step, (end - start) // step + 1))
            start = s
            end = None if c is None else s + step * (c - 1)
    out.append(_piece(start, step, None if end is None else (end - start) // step + 1))
    return out


def _merge_group(members: list[Piece], step: int, points: list[int], point_set: set[int],
                 consumed: set[int]) -> list[Piece]:
    """The progressions of one step and one residue merged, with the points that lie on them
    or extend them (those points are added to `consumed`)."""
    if len(members) > 1:
        members.sort(key=_START)
    first = members[0][0]
    low = bisect_left(points, first - step)
    near: list[int] = []
    if low < len(points):
        top = -1
        for start, _, count in members:
            if count is None:
                top = -1
                break
            last = start + step * (count - 1)
            if last > top:
                top = last
        high = len(points) if top < 0 else bisect_right(points, top + step, low)
        residue = first % step
        near = [t for t in points[low:high] if t % step == residue]
    if not near:
        return _merge_aligned(members, step) if len(members) > 1 else members
    entries = [(p[0], _end(p), True) for p in members] + [(t, t, False) for t in near]
    entries.sort(key=_START)
    out: list[Piece] = []
    run_start, run_end, run_prog = entries[0]
    run_points = [] if run_prog else [run_start]

    def close() -> None:
        if not run_prog:
            return  # points alone: they stay points
        start, end = run_start, run_end
        while start - step in point_set:
            start -= step
            run_points.append(start)
        if end is not None:
            while end + step in point_set:
                end += step
                run_points.append(end)
        consumed.update(run_points)
        out.append((start, step, None if end is None else (end - start) // step + 1))

    for start, end, is_prog in entries[1:]:
        if run_end is None or start <= run_end + step:
            if run_end is not None and (end is None or end > run_end):
                run_end = end
            if is_prog:
                run_prog = True
            else:
                run_points.append(start)
        else:
            close()
            run_start, run_end, run_prog = start, end, is_prog
            run_points = [] if is_prog else [start]
    close()
    return out


def _inside(p: Piece, q: Piece) -> bool:
    """Whether progression `p` is a subset of progression `q`."""
    a, s, n = p
    b, t, m = q
    if a < b or s % t or (a - b) % t:
        return False
    if m is None:
        return True
    return n is not None and a + s * (n - 1) <= b + t * (m - 1)


def _point_runs(points: list[int]) -> list[Piece]:
    """Points (sorted, none adjacent) as pieces: three or more equally spaced, from the
    smallest on, become a progression."""
    out: list[Piece] = []
    i = 0
    n = len(points)
    while i < n:
        if i + 2 < n:
            gap = points[i + 1] - points[i]
            if points[i + 2] - points[i + 1] == gap:
                j = i + 2
                while j + 1 < n and points[j + 1] - points[j] == gap:
                    j += 1
                out.append((points[i], gap, j - i + 1))
                i = j + 1
                continue
        out.append((points[i], 1, 1))
        i += 1
    return out


@lru_cache(maxsize=256)
def _prime_factors(n: int) -> tuple[int, ...]:
    """The distinct prime factors of `n` >= 1, increasing."""
    out: list[int] = []
    f = 2
    while f * f <= n:
        if n % f == 0:
            out.append(f)
            while n % f == 0:
                n //= f
        f += 1
    if n > 1:
        out.append(n)
    return tuple(out)


def _interleave(progressions: list[Piece]) -> list[Piece] | None:
    """The progressions with each family of k of one step s (k a prime factor of s) that
    interleave into one progression of step s/k replaced by it: starts a, a + s/k, ...,
    a + (k-1)*s/k and counts that take turns (infinite all, or c_i = ceil((N - i)/k) for
    N their sum); None when there is no such family."""
    by_step: dict[int, list[Piece]] = {}
    for p in progressions:
        members = by_step.get(p[1])
        if members is None:
            by_step[p[1]] = [p]
        else:
            members.append(p)
    out: list[Piece] = []
    changed = False
    for step, of_step in by_step.items():
        members = of_step
        for k in _prime_factors(step) if len(members) > 1 else ():
            if k > len(members):
                break
            e = step // k
            at = {p[0]: p for p in members}
            for start in at:
                if start + e in at:
                    break
            else:
                continue  # no two start s/k apart: no family
            used: set[int] = set()
            for p in sorted(members):
                if p[0] in used:
                    continue
                family = [p]
                for i in range(1, k):
                    q = at.get(p[0] + i * e)
                    if q is None or q[0] in used:
                        break
                    family.append(q)
                else:
                    counts = [q[2] for q in family]
                    if all(c is None for c in counts):
                        total: int | None = None
                    elif None in counts:
                        continue
                    else:
                        total = sum(c for c in counts if c is not None)
                        if any(c != (total - i + k - 1) // k for i, c in enumerate(counts)):
                            continue
                    used.update(q[0] for q in family)
                    out.append((p[0], e, total))
            if used:
                changed = True
                members = [p for p in members if p[0] not in used]
        out.extend(members)
    return out if changed else None


def _canonical(raw: list[Piece]) -> tuple[Piece, ...]:
    """The canonical pieces of the union of `raw` (pieces of at least one element, in any
    order, overlapping or not); the module's docstring lists the rules."""
    if len(raw) <= 1:
        return _single(raw[0]) if raw else ()
    ones: list[Piece] = []
    groups: dict[tuple[int, int], list[Piece]] = {}
    for p in raw:
        start, step, count = p
        if step == 1:
            ones.append(p)
        elif count == 2:
            ones.append((start, 1, 1))
            ones.append((start + step, 1, 1))
        else:
            key = (step, start % step)
            group = groups.get(key)
            if group is None:
                groups[key] = [p]
            else:
                group.append(p)
    if len(ones) > 1:
        ones = _merge_aligned(ones, 1)
    points = [p[0] for p in ones if p[2] == 1]
    intervals = [p for p in ones if p[2] != 1] if points else ones
    if len(points) > 2:
        # Equally spaced points become progressions first, which then merge as the others do.
        runs = _point_runs(points)
        if len(runs) < len(points):
            points = []
            for p in runs:
                start, step, count = p
                if count == 1:
                    points.append(start)
                    continue
                key = (step, start % step)
                group = groups.get(key)
                if group is None:
                    groups[key] = [p]
                else:
                    group.append(p)
    progressions: list[Piece] = []
    if groups:
        if points:
            point_set = set(points)
            consumed: set[int] = set()
            for (step, _), members in groups.items():
                if len(members) == 1:  # alone: as it is, unless a point is near it
                    start, _, count = p = members[0]
                    i = bisect_left(points, start - step)
                    if i == len(points) or (
                            count is not None and points[i] > start + step * count):
                        progressions.append(p)
                        continue
                progressions.extend(_merge_group(members, step, points, point_set, consumed))
            if consumed:
                points = [t for t in points if t not in consumed]
        else:
            for (step, _), members in groups.items():
                if len(members) > 1:
                    progressions.extend(_merge_aligned(members, step))
                else:
                    progressions.append(members[0])
        # The steps of the progressions, when there are two or more (else none).
        steps = {p[1] for p in progressions} if len(progressions) > 1 else set()
        if steps and len(steps) < len(progressions):  # one step twice: they may interleave
            woven = _interleave(progressions)
            if woven is not None:  # fewer pieces: once more, as they may merge further
                return _canonical(intervals + woven + [(t, 1, 1) for t in points])
        if intervals:
            starts = [p[0] for p in intervals]
            kept = []
            for p in progressions:
                i = bisect_right(starts, p[0]) - 1
                if i >= 0:
                    end = _end(intervals[i])
                    if end is None or (p[2] is not None and p[0] + p[1] * (p[2] - 1) <= end):
                        continue
                kept.append(p)
            progressions = kept
        if len(steps) > 1 and len(progressions) <= _FEW:
            # One progression inside another has a greater step (a multiple of the other's).
            kept = []
            for p in progressions:
                for q in progressions:
                    if q[1] < p[1] and _inside(p, q):
                        break
                else:
                    kept.append(p)
            progressions = kept
    result = intervals + progressions
    result += [(t, 1, 1) for t in points]
    result.sort()  # (start, step) is unique among canonical pieces: counts are never compared
    return tuple(result)


def _union2(p: Piece, q: Piece) -> tuple[Piece, ...]:
    """The canonical pieces of the union of two canonical single pieces: what `_canonical`
    gives for the two, without its general machinery."""
    if q[0] < p[0] or (q[0] == p[0] and q[1] < p[1]):
        p, q = q, p  # p first, as they are sorted
    a, s, n = p
    b, t, m = q
    if s == t and (s == 1 or (b - a) % s == 0):  # one group: one piece if they touch
        if n is None:
            return (p,)
        end = a + s * (n - 1)
        if b > end + s:
            return (p, q)
        if m is None:
            return ((a, s, None),)
        q_end = b + s * (m - 1)
        return ((a, s, (max(end, q_end) - a) // s + 1),)
    if n == 1:  # a point before a progression (or on its start): on it, or one step before
        if m == 1 or (b - a) % t or a < b - t:
            return (p, q)
        return ((a, t, None if m is None else m + (b - a) // t),)
    if m == 1:  # a progression, then a point: on it, or one step after its end
        if (b - a) % s:
            return (p, q)
        if n is None:
            return (p,)
        if b > a + s * n:
            return (p, q)
        return ((a, s, max(n, (b - a) // s + 1)),)
    if s == 1 or t == 1:  # an interval and a progression: the progression inside or not
        interval, other = (p, q) if s == 1 else (q, p)
        if other[0] >= interval[0]:
            iv_end = _end(interval)
            o_end = _end(other)
            if iv_end is None or (o_end is not None and o_end <= iv_end):
                return (interval,)
        return (p, q)
    if s == t:  # different residues: two that take turns are one of half the step
        if not s % 2 and b - a == s // 2 and ((n is None and m is None) or (
                n is not None and m is not None and n - 1 <= m <= n)):
            return ((a, s // 2, None if n is None or m is None else n + m),)
        return (p, q)
    if t < s and _inside(p, q):
        return (q,)
    if s < t and _inside(q, p):
        return (p,)
    return (p, q)


def _meet(p: Piece, q: Piece) -> Piece | None:
    """The intersection of two pieces: one piece (its step the lcm of theirs), or None."""
    a, s, n = p
    b, t, m = q
    lo = a if a > b else b
    hi = None if n is None else a + s * (n - 1)
    if m is not None:
        qe = b + t * (m - 1)
        if hi is None or qe < hi:
            hi = qe
    if hi is not None and hi < lo:
        return None
    if s == t:
        if s > 1 and (b - a) % s:
            return None
        base, step = a, s
    elif t == 1:
        base, step = a, s
    elif s == 1:
        base, step = b, t
    else:
        g = gcd(s, t)
        diff = b - a
        if diff % g:
            return None
        tg = t // g
        base = a + s * (diff // g * pow(s // g, -1, tg) % tg)  # = a mod s, = b mod t
        step = s // g * t
    first = lo + (base - lo) % step
    if hi is None:
        return (first, step, None)
    if first > hi:
        return None
    return _piece(first, step, (hi - first) // step + 1)


def _minus(p: Piece, q: Piece, out: list[Piece], limit: int) -> None:
    """Appends to `out` pieces whose union is `p` minus `q`; `TooComplex` when the part of `p`
    within `q`'s range splits into more than `limit` pieces."""
    a, s, n = p
    b, t, m = q
    lo = a if a > b else b
    hi = None if n is None else a + s * (n - 1)
    if m is not None:
        qe = b + t * (m - 1)
        if hi is None or qe < hi:
            hi = qe
    if hi is not None and hi < lo:
        out.append(p)
        return
    i0 = 0 if lo <= a else -((a - lo) // s)  # the first index of p at or after lo
    i1 = None if hi is None else (hi - a) // s  # the last index of p at or before hi
    if i1 is not None and i1 < i0:
        out.append(p)
        return
    if i0 > 0:
        out.append(_piece(a, s, i0))
    if i1 is not None and (n is None or i1 + 1 < n):
        out.append(_piece(a + s * (i1 + 1), s, None if n is None else n - i1 - 1))
    # The middle, a2 + s*i for 0 <= i < c, lies within q's range: an element of it is in q
    # exactly when it is in q's lattice.
    if t == 1:
        return
    a2 = a + s * i0
    c = None if i1 is None else i1 - i0 + 1
    g = gcd(s, t)
    if (b - a2) % g:
        out.append(_piece(a2, s, c))
        return
    k = t // g  # the middle's indices in q's lattice: those of one residue j0 modulo k
    if k == 1:
        return
    j0 = (b - a2) // g * pow(s // g, -1, k) % k
    if c is not None and c <= j0:
        out.append(_piece(a2, s, c))
        return
    if c is None:
        by_residue = True
        pieces = k - 1
    else:
        runs = (c - 1 - j0) // k + 2
        residues = min(k, c) - 1
        by_residue = residues <= runs
        pieces = residues if by_residue else runs
    if pieces > limit:
        raise TooComplex(f"a difference of sets of times needs {pieces} pieces or more, "
                         f"more than {limit}")
    if by_residue:
        big = s * k
        for j in range(k if c is None else min(k, c)):
            if j != j0:
                out.append(_piece(a2 + s * j, big, None if c is None else (c - j + k - 1) // k))
    else:
        assert c is not None
        prev = 0
        for gap in range(j0, c, k):
            if gap > prev:
                out.append(_piece(a2 + s * prev, s, gap - prev))
            prev = gap + 1
        if prev < c:
            out.append(_piece(a2 + s * prev, s, c - prev))


def _repeat_piece(p: Piece, d: int, times: int | None, out: list[Piece]) -> None:
    """Appends to `out` pieces whose union is the union of `p` shifted by j*d for 0 <= j <=
    `times` (every j >= 0 when None; times >= 1); `TooComplex` beyond `MAX_PIECES` pieces."""
    a, s, n = p
    if n == 1:
        out.append((a, d, None if times is None else times + 1))
        return
    # The elements are a + s*i + d*j. With g = gcd(s, d), s*(d/g) = d*(s/g): the indices i of
    # one residue modulo d/g give one progression of step d when j covers s/g consecutive
    # values (way "i"), the indices j of one residue modulo s/g give one of step s when i
    # covers d/g consecutive values (way "j"); else one progression for each i (way "each
    # i", step d) or for each j (way "each j", step s). The way of the fewest pieces is taken.
    g = gcd(s, d)
    sg = s // g
    dg = d // g
    ways: list[tuple[int, str]] = []
    if times is None or times + 1 >= sg:
        ways.append((dg if n is None else min(n, dg), "i"))
    if n is None or n >= dg:
        ways.append((sg if times is None else min(times + 1, sg), "j"))
    if n is not None:
        ways.append((n, "each i"))
    if times is not None:
        ways.append((times + 1, "each j"))
    pieces, way = min(ways)
    _check_pieces(pieces, "a repetition")
    if way == "i":
        for c in range(pieces):
            count = None if n is None or times is None else sg * ((n - c - 1) // dg) + times + 1
            out.append((a + s * c, d, count))
    elif way == "j":
        for c in range(pieces):
            count = None if n is None or times is None else dg * ((times - c) // sg) + n
            out.append((a + d * c, s, count))
    elif way == "each i":
        out.extend((a + s * i, d, None if times is None else times + 1) for i in range(pieces))
    else:
        out.extend((a + d * j, s, n) for j in range(pieces))


def _check_pieces(count: int, what: str) -> None:
    """`TooComplex` when `what` needs more than `MAX_PIECES` pieces."""
    if count > MAX_PIECES:
        raise TooComplex(f"{what} of sets of times needs {count} pieces, "
                         f"more than {MAX_PIECES}")


def _covered(p: Piece, qs: list[Piece], budget: list[int]) -> bool:
    """Whether piece `p` is a subset of the union of `qs`: `p` minus each of `qs` in turn,
    depth first, until a part is left over (no) or nothing is (yes). `budget[0]` is the
    number of parts it may still go through."""
    stack = [(p, 0)]
    last = len(qs)
    while stack:
        x, i = stack.pop()
        while i < last:
            parts: list[Piece] = []
            _minus(x, qs[i], parts, budget[0])
            i += 1
            if len(parts) != 1 or parts[0] != x:
                break
        else:
            return False
        budget[0] -= len(parts)
        if budget[0] < 0:
            raise TooComplex(f"comparing sets of times went through more than {_WORK} parts")
        stack.extend((part, i) for part in parts)
    return True


def _subset(a: tuple[Piece, ...], b: tuple[Piece, ...], budget: list[int]) -> bool:
    """Whether the set of pieces `a` is a subset of the set of pieces `b`."""
    if not a:
        return True
    if not b:
        return False
    qs = sorted(b, key=itemgetter(1))  # intervals first: they remove whole ranges
    return all(_covered(p, qs, budget) for p in a)


def _ms(t: int) -> str:
    return f"{t} ms"


def _describe_piece(p: Piece) -> list[str]:
    start, step, count = p
    if count == 1:
        return [_ms(start)]
    if count == 2 and step > 1:
        return [_ms(start), _ms(start + step)]
    if count is None:
        if step == 1:
            return [f"from {start} ms on"]
        return [f"from {start} ms every {step} ms"]
    end = start + step * (count - 1)
    if step == 1:
        return [f"{start} to {end} ms"]
    return [f"{start} to {end} ms every {step} ms"]


def _show_piece(p: Piece) -> str:
    start, step, count = p
    if count == 1:
        return str(start)
    every = "" if step == 1 else f" step {step}"
    if count is None:
        return f"{start}..{every}"
    return f"{start}..{start + step * (count - 1)}{every}"


class TimeSet:
    """An immutable set of integers >= 0 (times in milliseconds), held exactly as a finite
    union of arithmetic progressions in the canonical form of the module's docstring.

    Build one with `empty`, `point`, `interval`, `progression`, `of` or `all`; `TimeSet()` is
    the empty set and `TimeSet(pieces)` the union of raw `(start, step, count)` pieces. There
    is no iteration (a set may be infinite): `first`, `elements` and the queries take its
    place. Every operation is exact and returns a new set, or raises `TooComplex` when the
    result would need more than `MAX_PIECES` pieces. Comparing sets whose pieces differ
    (`==`, `issubset`) and counting overlapping pieces (`size`) are exact too; they raise
    `TooComplex` only past `_WORK` parts, which pieces of steps with a huge lcm could need.
    """

    __slots__ = ("_pieces",)
    _pieces: tuple[Piece, ...]

    def __init__(self, pieces: Iterable[Piece] = ()) -> None:
        raw: list[Piece] = []
        for start, step, count in pieces:
            _check_piece(start, step, count)
            if count != 0:
                raw.append(_piece(start, step, count))
        pieces = _canonical(raw)
        _check_pieces(len(pieces), "a set")
        _SET_PIECES(self, pieces)

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"a TimeSet is immutable: cannot set {name!r}")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"a TimeSet is immutable: cannot delete {name!r}")

    def __reduce__(self) -> tuple[type[TimeSet], tuple[tuple[Piece, ...]]]:
        return (TimeSet, (self._pieces,))

    # Construction

    @classmethod
    def empty(cls) -> TimeSet:
        """The empty set."""
        return _EMPTY

    @classmethod
    def point(cls, t: int) -> TimeSet:
        """The set of `t` alone."""
        if t < 0:
            raise ValueError(f"a time is >= 0, not {t}")
        return _wrap(((t, 1, 1),))

    @classmethod
    def interval(cls, lo: int, hi: int | None) -> TimeSet:
        """Every time from `lo` to `hi` inclusive (without end when `hi` is None); empty when
        `hi` < `lo`."""
        if lo < 0:
            raise ValueError(f"a time is >= 0, not {lo}")
        if hi is None:
            return _wrap(((lo, 1, None),))
        if hi < lo:
            return _EMPTY
        return _wrap(((lo, 1, hi - lo + 1),))

    @classmethod
    def progression(cls, start: int, step: int, count: int | None) -> TimeSet:
        """start + step*k for 0 <= k < `count` (for every k >= 0 when `count` is None)."""
        _check_piece(start, step, count)
        if count == 0:
            return _EMPTY
        return _wrap(_single((start, step, count)))

    @classmethod
    def of(cls, values: Iterable[int]) -> TimeSet:
        """The finite set of `values`; runs of three or more equally spaced values become
        progressions."""
        ordered = sorted(set(values))
        if not ordered:
            return _EMPTY
        if ordered[0] < 0:
            raise ValueError(f"a time is >= 0, not {ordered[0]}")
        return _make(_canonical([(t, 1, 1) for t in ordered]), "a set")

    @classmethod
    def all(cls) -> TimeSet:
        """Every time >= 0."""
        return _ALL

    # Queries

    @property
    def pieces(self) -> tuple[Piece, ...]:
        """The canonical pieces, `(start, step, count)` each, sorted by start."""
        return self._pieces

    def __bool__(self) -> bool:
        return bool(self._pieces)

    def __contains__(self, t: int) -> bool:
        for start, step, count in self._pieces:
            if start > t:
                return False
            if (t - start) % step == 0 and (count is None or t - start < step * count):
                return True
        return False

    def min(self) -> int:
        """The least element; `ValueError` when the set is empty."""
        if not self._pieces:
            raise ValueError("the empty set of times has no least element")
        return self._pieces[0][0]

    def max(self) -> int | None:
        """The greatest element, None when the set is infinite; `ValueError` when empty."""
        if not self._pieces:
            raise ValueError("the empty set of times has no greatest element")
        return _max(self._pieces)

    @property
    def is_infinite(self) -> bool:
        """Whether the set has no greatest element."""
        return any(p[2] is None for p in self._pieces)

    def size(self) -> int | None:
        """The number of elements, None when the set is infinite."""
        pieces = self._pieces
        if any(p[2] is None for p in pieces):
            return None
        total = 0
        reach = -1
        for start, step, count in pieces:
            if count is None or start <= reach:
                break
            reach = start + step * (count - 1)
            total += count
        else:
            return total  # no two pieces overlap
        # Pieces of different steps overlap: count what each adds to those before it.
        total = 0
        work = _WORK
        for i, p in enumerate(pieces):
            parts = [p]
            for q in pieces[:i]:
                rest: list[Piece] = []
                for x in parts:
                    _minus(x, q, rest, work)
                parts = rest
                work -= len(parts)
                if work < 0:
                    raise TooComplex(f"counting a set of times went through more than "
                                     f"{_WORK} parts")
            total += sum(_count(x) for x in parts)
        return total

    def first(self, n: int) -> list[int]:
        """The `n` least elements in increasing order (all of them when there are fewer)."""
        pieces = self._pieces
        if n <= 0 or not pieces:
            return []
        if len(pieces) == 1:
            start, step, count = pieces[0]
            if count is not None and count < n:
                n = count
            return list(range(start, start + step * n, step))
        out: list[int] = []
        heap = [(p[0], i, 0) for i, p in enumerate(pieces)]  # sorted, so a heap already
        last = -1
        while heap:
            value, i, k = heap[0]
            if value != last:
                out.append(value)
                if len(out) == n:
                    break
                last = value
            start, step, count = pieces[i]
            k += 1
            if count is None or k < count:
                heapreplace(heap, (start + step * k, i, k))
            else:
                heappop(heap)
        return out

    def elements(self, limit: int) -> list[int]:
        """Every element in increasing order; `ValueError` when the set is infinite or has
        more than `limit` elements."""
        if self.is_infinite:
            raise ValueError("an infinite set of times has no list of elements")
        bound = sum(_count(p) for p in self._pieces)
        if bound > limit:
            size = self.size()
            assert size is not None
            if size > limit:
                raise ValueError(f"the set of times has {size} elements, more than {limit}")
            bound = size
        return self.first(bound)

    def last_at_most(self, t: int) -> int | None:
        """The greatest element <= `t`; None when there is none."""
        best: int | None = None
        for start, step, count in self._pieces:
            if start > t:
                break
            k = (t - start) // step
            if count is not None and k >= count:
                k = count - 1
            value = start + step * k
            if best is None or value > best:
                best = value
        return best

    def first_at_least(self, t: int) -> int | None:
        """The least element >= `t`; None when there is none."""
        best: int | None = None
        for start, step, count in self._pieces:
            if best is not None and start >= best:
                break
            if start >= t:
                value = start
            else:
                k = -((start - t) // step)
                if count is not None and k >= count:
                    continue
                value = start + step * k
            if best is None or value < best:
                best = value
        return best

    def issubset(self, other: TimeSet) -> bool:
        """Whether every element of this set is in `other`."""
        a = self._pieces
        b = other._pieces
        if a == b or not a:
            return True
        if not b or a[0][0] < b[0][0]:
            return False
        top = _max(b)
        if top is not None:
            mine = _max(a)
            if mine is None or mine > top:
                return False
        return _subset(a, b, [_WORK])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TimeSet):
            return NotImplemented
        a = self._pieces
        b = other._pieces
        if a == b:
            return True
        if not a or not b or a[0][0] != b[0][0] or _max(a) != _max(b):
            return False
        budget = [_WORK]
        return _subset(a, b, budget) and _subset(b, a, budget)

    def __hash__(self) -> int:
        a = self._pieces
        if not a:
            return hash(())
        return hash((a[0][0], _max(a)))

    # Algebra

    def union(self, other: TimeSet) -> TimeSet:
        """The elements of either set."""
        a = self._pieces
        b = other._pieces
        if not a or a == b:
            return other
        if not b:
            return self
        if len(a) == 1 and len(b) == 1:
            return _wrap(_union2(a[0], b[0]))
        return _make(_canonical([*a, *b]), "a union")

    __or__ = union

    def intersection(self, other: TimeSet) -> TimeSet:
        """The elements of both sets."""
        a = self._pieces
        b = other._pieces
        if not a or not b:
            return _EMPTY
        if a == b:
            return self
        if len(a) == 1 and len(b) == 1:
            r = _meet(a[0], b[0])
            return _EMPTY if r is None else _wrap(_single(r))
        out: list[Piece] = []
        for p in a:
            end = _end(p)
            for q in b:
                if end is not None and q[0] > end:
                    break
                r = _meet(p, q)
                if r is not None:
                    out.append(r)
        return _make(_canonical(out), "an intersection")

    __and__ = intersection

    def difference(self, other: TimeSet) -> TimeSet:
        """The elements of this set that are not in `other`."""
        a = self._pieces
        b = other._pieces
        if not a or not b:
            return self
        if a == b:
            return _EMPTY
        out: list[Piece] = []
        for p in a:
            parts = [p]
            end = _end(p)
            for q in b:
                if end is not None and q[0] > end:
                    break
                rest: list[Piece] = []
                for x in parts:
                    _minus(x, q, rest, MAX_PIECES)
                parts = rest
                if not parts:
                    break
                _check_pieces(len(parts), "a difference")
            out.extend(parts)
        if len(out) == len(a) and tuple(out) == a:
            return self
        return _make(_canonical(out), "a difference")

    __sub__ = difference

    def shift(self, d: int) -> TimeSet:
        """Every element plus `d`; `ValueError` when that would make one negative."""
        a = self._pieces
        if not d or not a:
            return self
        if a[0][0] + d < 0:
            raise ValueError(f"shifting by {d} makes {a[0][0]} negative")
        if len(a) == 1:
            start, step, count = a[0]
            return _wrap(((start + d, step, count),))
        return _wrap(tuple([(start + d, step, count) for start, step, count in a]))

    def clip(self, lo: int, hi: int | None) -> TimeSet:
        """The elements from `lo` to `hi` inclusive (no upper bound when `hi` is None)."""
        a = self._pieces
        if lo < 0:
            lo = 0
        if not a or (hi is not None and hi < lo):
            return _EMPTY
        out: list[Piece] = []
        changed = False
        for p in a:
            start, step, count = p
            if hi is not None and start > hi:
                changed = True
                break
            k0 = 0 if start >= lo else -((start - lo) // step)
            if count is not None and k0 >= count:
                changed = True
                continue
            k1 = count if hi is None else (hi - start) // step + 1  # one past the last index
            if count is not None and k1 is not None and k1 > count:
                k1 = count
            if k1 is not None and k1 <= k0:
                changed = True  # no element between lo and hi
                continue
            if k0 == 0 and k1 == count:
                out.append(p)
            else:
                changed = True
                out.append(_piece(start + step * k0, step, None if k1 is None else k1 - k0))
        if not changed:
            return self
        if len(out) <= 1:
            return _wrap(_single(out[0])) if out else _EMPTY
        return _wrap(_canonical(out))

    def below(self, c: int) -> TimeSet:
        """The elements < `c`."""
        if c <= 0:
            return _EMPTY
        return self.clip(0, c - 1)

    def above(self, c: int) -> TimeSet:
        """The elements > `c`."""
        if c < 0:
            return self
        return self.clip(c + 1, None)

    def repeat(self, d: int, times: int | None) -> TimeSet:
        """The union of `self.shift(j*d)` for 0 <= j <= `times` (for every j >= 0 when
        `times` is None); `d` >= 1."""
        if d < 1:
            raise ValueError(f"a repetition's period is >= 1, not {d}")
        if times is not None and times < 0:
            raise ValueError(f"a repetition's count is >= 0, not {times}")
        a = self._pieces
        if not a or times == 0:
            return self
        out: list[Piece] = []
        for p in a:
            _repeat_piece(p, d, times, out)
        return _make(_canonical(out), "a repetition")

    # Text

    def __repr__(self) -> str:
        return "TimeSet({" + ", ".join(_show_piece(p) for p in self._pieces) + "})"

    def describe(self) -> str:
        """The set in words, for messages: "0 to 35000 ms every 500 ms", "1200 ms", "from
        1200 ms every 500 ms", several joined with commas and "or"; past six, the first five
        and how many more."""
        pieces = self._pieces
        if not pieces:
            return "never"
        parts = [text for p in pieces for text in _describe_piece(p)]
        if len(parts) > 6:
            top = _max(pieces)
            tail = "without end" if top is None else f"up to {top} ms"
            return ", ".join(parts[:5]) + f" or {len(parts) - 5} more, {tail}"
        if len(parts) == 1:
            return parts[0]
        return ", ".join(parts[:-1]) + " or " + parts[-1]


# The setter of the `_pieces` slot (its member descriptor's `__set__`): `__setattr__` refuses.
_SET_PIECES: Callable[[TimeSet, tuple[Piece, ...]], None] = TimeSet.__dict__["_pieces"].__set__


def _wrap(pieces: tuple[Piece, ...]) -> TimeSet:
    """A TimeSet of canonical pieces, built without a check."""
    ts = object.__new__(TimeSet)
    _SET_PIECES(ts, pieces)
    return ts


def _make(pieces: tuple[Piece, ...], what: str) -> TimeSet:
    """A TimeSet of canonical pieces, or `TooComplex` when there are more than `MAX_PIECES`
    (`what` names the operation in the message)."""
    _check_pieces(len(pieces), what)
    return _wrap(pieces)


def _check_piece(start: int, step: int, count: int | None) -> None:
    """`ValueError` unless start >= 0, step >= 1 and count is None or >= 0."""
    if start < 0:
        raise ValueError(f"a time is >= 0, not {start}")
    if step < 1:
        raise ValueError(f"a progression's step is >= 1, not {step}")
    if count is not None and count < 0:
        raise ValueError(f"a progression's count is >= 0, not {count}")


_EMPTY = _wrap(())
_ALL = _wrap(((0, 1, None),))
