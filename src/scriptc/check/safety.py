"""Pass 7, safety against the robot profile (docs/robot.md; `scriptc.robot.profile`):

- K001: a move command faster than the profile allows (planar speed |(v_x, v_y)| above
  `max_linear_speed`, or |v_theta| above `max_angular_speed`). A warning: the script is not
  refused, the run-time governor slows it down, but the author should know the robot will not
  do what the script says.
- K002: LEDs that flash faster than `max_led_flash_rate` (3 Hz by default: WCAG 2.3.1, "Three
  Flashes or Below Threshold", a seizure risk for photosensitive children; epilepsy is far more
  common among autistic children than in the general population). The LED track of each
  instruction block is laid out in time (each command waits `wait_t`, is on for `duration`
  when `turnas` is 1 and the colour is not black; the LEDs are off when a block starts and
  between commands, and a light that stays on while its colour changes is not a flash), and
  the timeline goes on along the control flow: blocks run one after the other, a jump takes no
  time and may take either branch (the checker does not know the world), a terminus ends it.
  The light stays on across the seam of two blocks only when the first is lit to its very end
  and the second lights at once. From every onset (off to on) the one second that starts there
  is followed along every path; more onsets than the rate in it (k = floor(rate) + 1 within
  one second) is reported, at the command making the k-th, with the first flash of that second
  and the jump (or block) that chains the blocks. One report per block at most, and a block
  that is part of a second already reported starts no other report.

Work (`_Timeline`): the shortest time to the k-th flash, over every path, memoised per (block,
flashes left, entered lit): at most 2k states per block with a flash, a DAG evaluated
iteratively; blocks without a flash in between are crossed by a shortest-path search bounded
to one second and `_REACH` blocks, memoised per entry block, under a budget of work linear in
the size of the script. A cycle of blocks that take no time stops the search (F002 reports
it).

- K003 (`check/ramps.py`): moves the governor's acceleration ramps would leave away from where
  the script puts the robot.

The profile is `ctx.profile`: the configuration's `[robot]` over the defaults when the driver
passes one, else `scriptc.robot.profile.DEFAULT_PROFILE`.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterator
from dataclasses import dataclass

from scriptc.check.context import Context, Tracks
from scriptc.check.ramps import NextTimed, check_ramps
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Label
from scriptc.gcpause import gc_paused
from scriptc.ir.nodes import JumpBlock, LedCommand, MoveCommand, block_path
from scriptc.robot.motion import Velocity
from scriptc.robot.profile import Profile

WINDOW_MS = 1000
# Bounds of the K002 timeline (those of the search for the next instruction block are
# `ramps.NextTimed`'s): blocks without a flash visited per search for the next flash, and a
# budget of such work per script (a base plus so much per block) past which searches stop
# at `_REACH_SPENT` blocks.
_REACH = 512
_REACH_SPENT = 16
_WORK_BASE = 50_000
_WORK_PER_BLOCK = 8


def _fmt(v: float) -> str:
    return f"{v:g}"


def check_safety(ctx: Context) -> list[Diagnostic]:
    profile: Profile = ctx.profile
    out: list[Diagnostic] = []
    lights = False
    max_linear, max_angular = profile.max_linear_speed, profile.max_angular_speed
    limits = _Limits(profile)
    for tracks in ctx.tracks:
        if tracks is None:
            continue
        for mv, (velocity, _, _) in zip(tracks.block.moves, tracks.moves, strict=True):
            if velocity is not None and (math.hypot(velocity[0], velocity[1]) > max_linear
                                         or abs(velocity[2]) > max_angular):
                _speed(mv, velocity, limits, out)
        lights = lights or bool(tracks.leds)
    if lights:
        with gc_paused():  # many small acyclic objects (scriptc/gcpause.py)
            _Timeline(ctx, profile).check(out)
    check_ramps(ctx, profile, out)
    return out


class _Limits:
    """The profile's speeds and their words in K001, written once per check (a script may
    have thousands of moves above them)."""

    __slots__ = ("angular", "angular_text", "linear", "linear_text", "source")

    def __init__(self, profile: Profile) -> None:
        self.linear, self.angular = profile.max_linear_speed, profile.max_angular_speed
        self.linear_text, self.angular_text = _fmt(self.linear), _fmt(self.angular)
        self.source = "" if profile.source == "defaults" else f" (from {profile.source})"


def _speed(mv: MoveCommand, velocity: Velocity, limits: _Limits,
           out: list[Diagnostic]) -> None:
    """K001 for a move whose velocity (finite: V002/V003 report the others) is above the
    profile's."""
    v_x, v_y, w = velocity
    speed = math.hypot(v_x, v_y)
    linear, angular = limits.linear_text, limits.angular_text
    if speed > limits.linear:
        span = mv.v_x.span if abs(v_x) >= abs(v_y) else mv.v_y.span
        out.append(diagnostic(
            "K001", f"this move goes at {_fmt(speed)} m/s, above the robot profile's "
                    f"{linear} m/s", span,
            notes=((f"the run-time governor slows it to {linear} m/s: "
                    f"it goes {_fmt(limits.linear / speed * 100)}% as far as written"),
                   f"profile{limits.source}: max-linear-speed = {linear}"),
            help="lower the speed and lengthen the duration to keep the distance"))
    if abs(w) > limits.angular:
        out.append(diagnostic(
            "K001", f"this move turns at {_fmt(abs(w))} rad/s, above the robot profile's "
                    f"{angular} rad/s", mv.v_theta.span,
            notes=((f"the run-time governor slows it to {angular} "
                    "rad/s: it turns less far than written"),
                   f"profile{limits.source}: max-angular-speed = {angular}"),
            help="lower the turning speed and lengthen the duration to keep the angle"))


# -- K002: the LED timeline along the control flow -------------------------------------------


@dataclass(slots=True)
class _Track:
    """The LED track of an instruction block that takes time, entered with the LEDs off."""

    duration: int | None  # None: not whole milliseconds (V006): the timeline stops there
    times: list[int]  # the onsets (off to on), in ms from the block's start
    leds: list[LedCommand]  # the command lighting each onset
    ends_lit: bool  # lit up to the block's very end

    @property
    def starts_lit(self) -> bool:
        return bool(self.times) and self.times[0] == 0


def _track(tracks: Tracks) -> _Track | None:
    """The LED track of an instruction block (its tracks read), or None when the block
    takes no time (control passes through it in the same millisecond, as through a jump)."""
    duration = tracks.duration
    if duration == 0:
        return None
    if duration is not None and duration < 0:
        duration = None
    times: list[int] = []
    leds: list[LedCommand] = []
    t = 0
    lit = False  # the LEDs are off when a block starts and between commands
    for led, (_, lights, wait, length) in zip(tracks.block.leds, tracks.leds, strict=True):
        if wait is None or length is None:
            return _Track(duration, [], [], False)  # V006
        t += wait
        if wait > 0:
            lit = False
        on = lights and length > 0
        if on and not lit:
            times.append(t)
            leds.append(led)
        lit = on
        t += length
        # a command's stop turns the LEDs off: the next command lights them again only if it
        # starts later; with no wait the change is instantaneous (no dark interval)
    return _Track(duration, times, leds, lit and t == duration)


@dataclass(slots=True)
class _Run:
    """One pass of an instruction block on the path of a reported second."""

    block: int
    start: int  # ms from the first flash (negative for the block holding it)
    via: int  # the last jump passed to get here, or -1


class _Timeline:
    """The LED timeline of a script along its control flow (module docstring, K002).

    Time passes only in instruction blocks; every other block (and an instruction block that
    takes no time) passes control on in the same millisecond, so the next blocks that take time
    are found through them (`exits`, `ramps.NextTimed`: a bounded search; a cycle of them
    just stops the search, F002 reports it). A window is too bright when some path has
    `k = floor(rate) + 1` flashes within one second of its first flash, so what is computed
    is the shortest time to the k-th flash: `first(c, k, lit)`, from the start of block `c`
    (entered lit or dark), over every path, capped at one second. Blocks without a flash of
    their own are skipped by a bounded shortest-path search (`targets`: within one second, at
    most `_REACH` blocks, memoised per entry block, under the script's budget of work); every
    other step uses at least one flash, so the memo of (block, flashes left, lit) is a DAG of
    at most 2k states per block with a flash, evaluated iteratively. A block that every way in
    enters lit loses its onset at 0 first (`_drop_seamless_onsets`): a steadily lit stretch is
    then crossed like a dark one.

    `tracks[i]` is None for a block that takes no time; the searches reach, and the counting
    reads, only blocks that take time (`timed`), which `_timed` states."""

    def __init__(self, ctx: Context, profile: Profile) -> None:
        self.ctx = ctx
        self.blocks = ctx.blocks
        self.tracks = [None if t is None else _track(t) for t in ctx.tracks]
        self.limit = profile.max_led_flash_rate
        self._targets: dict[int, list[tuple[int, int, bool]]] = {}
        self._reached: dict[tuple[int, bool], list[tuple[int, int, bool]]] = {}
        self.work = 0  # blocks settled and targets merged by the searches
        self.budget = _WORK_BASE + _WORK_PER_BLOCK * len(self.blocks)
        self._entered: tuple[set[int], set[int]] | None = None
        self.memo: dict[tuple[int, int, bool], int] = {}

    # -- the graph of blocks that take time ------------------------------------------------

    @property
    def flow(self) -> NextTimed:
        """The script's blocks that take time, along the control flow (a block that takes time
        has a track), built when a second reaches past a block (`ctx.table`: K003 reads the
        same)."""
        return self.ctx.table(NextTimed)

    @property
    def resolved(self) -> bool:
        """Whether every jump target is a label of the script (L003)."""
        return self.flow.resolved

    def _timed(self, i: int) -> _Track:
        """The track of block `i`, which takes time (reached by a search, or has a flash)."""
        track = self.tracks[i]
        assert track is not None, i
        return track

    def exits(self, i: int) -> list[tuple[int, int]]:
        """Where control may go when block `i` ends: (next block that takes time, via)."""
        return self.flow.after(i)

    def entered_lit_only(self, i: int) -> bool:
        """Whether every way into block `i` comes from a block lit to its very end: its first
        command lighting at once is then no flash. Unknown targets (L003) or no way in at
        all count as entering dark."""
        if self._entered is None:
            dark = {v for v, _ in self.flow.search((0,))} if self.blocks else set()
            lit: set[int] = set()
            for j, track in enumerate(self.tracks):
                if track is not None:
                    (lit if track.ends_lit else dark).update(v for v, _ in self.exits(j))
            self._entered = (dark, lit)
        dark, lit = self._entered
        return self.resolved and i in lit and i not in dark

    def _walk(self, starts: list[tuple[int, bool, int]], cap: int | None = None,
              ) -> Iterator[tuple[int, int, bool, tuple[int, bool], int]]:
        """Shortest times from `starts` ((block, entered lit, via) at 0 ms) through blocks
        without a flash, within one second: yields (ms, block, entered lit, previous node,
        via) as blocks are settled; a block with a flash ends its branch. At most `_REACH`
        blocks, and only `_REACH_SPENT` once the script's budget is spent."""
        tracks = self.tracks
        heap = [(0, e, lit, -1, False, via) for e, lit, via in starts]
        heapq.heapify(heap)
        done: set[tuple[int, bool]] = set()
        if cap is None:
            cap = _REACH if self.work < self.budget else _REACH_SPENT
        while heap and len(done) < cap:
            t, e, lit, prev, prev_lit, via = heapq.heappop(heap)
            if (e, lit) in done:
                continue
            done.add((e, lit))
            self.work += 1
            yield t, e, lit, (prev, prev_lit), via
            track = tracks[e]
            assert track is not None  # exits() reach blocks that take time
            if len(track.times) > lit or track.duration is None:
                continue  # a flash: a target; or an unknown duration: the timeline stops
            t += track.duration
            if t >= WINDOW_MS:
                continue
            for f, via in self.exits(e):
                lit_f = track.ends_lit and self._timed(f).starts_lit
                if (f, lit_f) not in done:
                    heapq.heappush(heap, (t, f, lit_f, e, lit, via))

    def _reach(self, e: int, lit: bool) -> list[tuple[int, int, bool]]:
        """The blocks with a flash reached from the start of block `e` (entered lit or dark)
        through blocks without one, within a second: (ms, block, entered lit), nearest first.
        Memoised per entry: blocks that jump into one waiting loop share its search."""
        if len(self._timed(e).times) > lit:
            return [(0, e, lit)]
        found = self._reached.get((e, lit))
        if found is None:
            found = self._reached[(e, lit)] = [
                (t, f, lit_f) for t, f, lit_f, _, _ in self._walk([(e, lit, -1)])
                if len(self._timed(f).times) > lit_f]
        return found

    def _entries(self, c: int) -> list[tuple[int, bool, int]]:
        """The blocks that take time control may go to when block `c` ends: (block, entered
        lit, via)."""
        ends = self._timed(c).ends_lit
        return [(e, ends and self._timed(e).starts_lit, via) for e, via in self.exits(c)]

    def targets(self, c: int) -> list[tuple[int, int, bool]]:
        """The blocks with a flash that may come next after block `c` (through blocks
        without one) within a second: (ms from the end of `c` to its start, block, entered
        lit), the shortest time for each."""
        found = self._targets.get(c)
        if found is None:
            entries = self._entries(c)
            if len(entries) == 1 and self.work < self.budget:  # nothing to merge
                found = self._targets[c] = self._reach(entries[0][0], entries[0][1])
                return found
            best: dict[tuple[int, bool], int] = {}
            for e, lit, _ in entries:
                reached = self._reach(e, lit)
                if self.work >= self.budget:
                    reached = reached[:_REACH_SPENT]
                self.work += len(reached)
                for t, f, lit_f in reached:
                    if best.get((f, lit_f), WINDOW_MS) > t:
                        best[(f, lit_f)] = t
            found = self._targets[c] = [(t, f, lit) for (f, lit), t in best.items()]
        return found

    # -- counting ----------------------------------------------------------------------------

    def first(self, c: int, k: int, lit: bool) -> int:
        """The shortest time (ms, `WINDOW_MS` or more: none within a second) from the start of
        block `c`, entered lit or dark, to its `k`-th flash, over every path. `c` has a flash
        (entered so). Iterative, memoised."""
        memo = self.memo
        root = (c, k, lit)
        found = memo.get(root)
        if found is not None:
            return found
        stack = [root]
        while stack:
            key = stack[-1]
            if key in memo:
                stack.pop()
                continue
            c, k, lit = key
            track = self._timed(c)
            m = len(track.times) - lit
            best = WINDOW_MS
            if k <= m:
                best = track.times[lit + k - 1]
            elif track.duration is not None and track.duration < WINDOW_MS:
                missing = False
                for t, e, lit_e in self.targets(c):
                    child = (e, k - m, lit_e)
                    v = memo.get(child)
                    if v is None:
                        stack.append(child)
                        missing = True
                    elif track.duration + t + v < best:
                        best = track.duration + t + v
                if missing:
                    continue
            stack.pop()
            memo[key] = min(best, WINDOW_MS)
        return memo[root]

    def span(self, b: int, j: int, k: int) -> int:
        """The shortest time from the `j`-th flash of block `b` to the `k`-th counting it, over
        every path (`WINDOW_MS` or more: not within a second)."""
        track = self._timed(b)
        x = track.times[j]
        after = len(track.times) - j
        if after >= k:
            return track.times[j + k - 1] - x
        if track.duration is None or track.duration - x >= WINDOW_MS:
            return WINDOW_MS
        rest = track.duration - x
        return min((rest + t + self.first(e, k - after, lit) for t, e, lit in self.targets(b)),
                   default=WINDOW_MS)

    def path(self, b: int, j: int, k: int) -> tuple[list[_Run], list[tuple[int, LedCommand]]]:
        """The fastest path from the `j`-th flash of block `b` to the `k`-th flash: its runs
        of blocks and its flashes (index of the run, command)."""
        track = self._timed(b)
        x = track.times[j]
        runs = [_Run(b, -x, -1)]
        flashes = [(0, led) for led in track.leds[j : j + k]]
        end = None if track.duration is None else track.duration - x
        c = b
        while len(flashes) < k and end is not None:
            left = k - len(flashes)
            t, e, lit = min(self.targets(c), key=lambda o: o[0] + self.first(o[1], left, o[2]))
            # the search that found it again, keeping the way (it settles in the same order)
            entry = next(entry for entry in self._entries(c)
                         if (t, e, lit) in self._reach(entry[0], entry[1]))
            settled: dict[tuple[int, bool], tuple[int, tuple[int, bool], int]] = {}
            for when, f, lit_f, prev, via in self._walk([entry], _REACH):
                settled[(f, lit_f)] = (when, prev, via)
                if (f, lit_f) == (e, lit):
                    break
            chain: list[_Run] = []
            node = (e, lit)
            if node not in settled:  # past the search's bound: the blocks between are left out
                settled[node] = (t, (-1, False), entry[2])
            while node[0] >= 0:
                when, prev, via = settled[node]
                chain.append(_Run(node[0], end + when, via))
                node = prev
            runs.extend(reversed(chain))
            target = self._timed(e)
            flashes += [(len(runs) - 1, led) for led in target.leds[lit : lit + left]]
            c = e
            end = None if target.duration is None else runs[-1].start + target.duration
        return runs, flashes

    # -- reporting ---------------------------------------------------------------------------

    def check(self, out: list[Diagnostic]) -> None:
        limit = self.limit
        if math.isnan(limit) or limit == math.inf:
            return
        k = 1 if limit < 0 else math.floor(limit) + 1  # k flashes within a second are too many
        if k > WINDOW_MS:
            return
        if k > 1 and any(track is not None and track.times and track.duration is not None
                         and track.duration - track.times[-1] < WINDOW_MS
                         for track in self.tracks):
            self._drop_seamless_onsets()  # some second reaches past its block
        covered: set[int] = set()  # blocks already part of a reported second
        reported: set[int] = set()  # the LED commands reported (ids)
        for b, track in enumerate(self.tracks):
            if track is None or not track.times or b in covered:
                continue
            for j, x in enumerate(track.times):
                span = self.span(b, j, k)
                if span >= WINDOW_MS or (x == 0 and self.entered_lit_only(b)):
                    continue  # (the light goes on in the block before: no flash at 0)
                runs, flashes = self.path(b, j, k)
                if id(flashes[-1][1]) not in reported:  # one report per command
                    reported.add(id(flashes[-1][1]))
                    covered.update(self._second(runs))
                    out.append(self._diagnostic(runs, flashes, span, limit))
                break  # one report per block

    def _drop_seamless_onsets(self) -> None:
        """A block that every way in enters lit, and that lights at once, never flashes at
        its start: that onset is dropped before any search, so a long steadily lit stretch
        is crossed as one without a flash (and needs no search of its own)."""
        for i, track in enumerate(self.tracks):
            if track is not None and track.starts_lit and self.entered_lit_only(i):
                del track.times[0], track.leds[0]

    def _second(self, runs: list[_Run]) -> Iterator[int]:
        """The blocks of the reported second: its path, then on along first exits."""
        yield from (run.block for run in runs)
        c = runs[-1].block
        track = self._timed(c)
        end = None if track.duration is None else runs[-1].start + track.duration
        while end is not None and end < WINDOW_MS and self.exits(c):
            c = self.exits(c)[0][0]
            yield c
            duration = self._timed(c).duration
            end = None if duration is None else end + duration

    def _jump(self, i: int) -> JumpBlock:
        jump = self.blocks[i]
        assert isinstance(jump, JumpBlock)  # a run's `via` is the last jump passed
        return jump

    def _name(self, i: int) -> str | None:
        if not self.ctx.is_script_syntax:
            return f"`{block_path(self.ctx.addressed_blocks[i][0])}`"
        label = self.blocks[i].label
        return f"`{label.text}`" if label is not None and label.text else None

    def _link(self, runs: list[_Run], repeats: bool) -> Label:
        """The label on what chains the blocks: the jump going back, else the first jump,
        else the block the flashing goes on in."""
        jumps = [run for run in runs[1:] if run.via >= 0]
        back = [run for run in jumps if run.block <= run.via]
        if back or jumps:
            run = (back or jumps)[0]
            jump = self._jump(run.via)
            if repeats:
                return Label(jump.span, "this jump repeats the block")
            may = "" if jump.condition.is_constant_true else "may "
            where = "back" if back else "on"
            name = self._name(run.block) or "the next block"
            return Label(jump.span, f"this jump {may}go{'es' if not may else ''} {where} to {name}")
        return Label(self.ctx.block_head(self.blocks[runs[1].block]),
                     "the flashing goes on in this block")

    def _diagnostic(self, runs: list[_Run], flashes: list[tuple[int, LedCommand]], span: int,
                    limit: float) -> Diagnostic:
        count = len(flashes)
        led = flashes[-1][1]
        runs = runs[: flashes[-1][0] + 1]
        labels = []
        first = flashes[0][1]
        if first is not led:
            labels.append(Label(first.span, "the first flash of that second"))
        blocks = list(dict.fromkeys(run.block for run in runs))
        where = ""
        if len(runs) > 1:
            labels.append(self._link(runs, len(blocks) == 1))
            if len(blocks) == 1:
                where = " as the block repeats"
            else:
                names = [self._name(i) for i in blocks]
                named = [name for name in names if name is not None]
                where = (" across blocks " + _and(named)
                         if len(named) == len(names) and len(names) <= 4
                         else f" across {len(blocks)} blocks")
        notes = [("flashing faster than 3 times a second can trigger seizures in "
                  "photosensitive children (WCAG 2.3.1)")]
        if count > 1 and span > 0:
            notes.append(f"these {count} flashes come within {span} ms: about "
                         f"{_fmt(round((count - 1) * WINDOW_MS / span, 1))} a second")
        if any(run.via >= 0 and not self._jump(run.via).condition.is_constant_true
               for run in runs):
            notes.append("a jump may go either way: the check follows every path the jumps "
                         "allow")
        notes.append(f"profile: max-led-flash-rate = {_fmt(limit)}")
        help = ("keep each on/off cycle at least a third of a second long (for example on 200 ms, "
                "off 150 ms), or keep the light on and change its colour slowly")
        if len(blocks) > 1:
            help = ("keep each on/off cycle at least a third of a second long across the blocks "
                    "too (for example a dark block of 250 ms after a block lit 100 ms), or keep "
                    "the light on and change its colour slowly")
        return diagnostic(
            "K002", f"the LEDs flash {count} times within one second{where}, above the robot "
                    f"profile's {_fmt(limit)} per second", led.span,
            labels=tuple(labels), notes=tuple(notes), help=help)


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
