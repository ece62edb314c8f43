"""K003 (pass 7, safety; docs/robot.md "Acceleration"): where the run-time governor's ramps
change where the robot ends up, predicted before the run with the same code the run uses
(`scriptc.robot.motion`).

The governor ramps every change of speed at the profile's acceleration. Within an instruction
block the move track is known when the block is issued, so a motion (one group's velocity
between two rests: the plane, or the turn) whose ramps all fit in the block gets them centred
on its changes, and the robot covers exactly the distance of the script. The others are ramped
late, from each change on: a motion that starts as the block starts, runs to its end, or whose
ramps would overlap; and a block entered while the robot still moves. A late motion from rest
to rest at one speed still keeps its distance (what the ramp up loses, the ramp down after the
stop gives back); other late motions (a reversal, a move shorter than its ramp, turning while
moving) do not.

For each instruction block, `motion.run_block` runs the governor's plan and ramps and the
exact kinematics from the states the robot can enter it in, and compares where the robot
comes to rest with the pose of the script (speeds within the profile: K001 reports those).
The states are found along the control flow: the script's first blocks are entered at rest,
and each block passes the state it leaves the robot in (the ramp it follows, the command it
had) to the blocks that may come next (through jumps and blocks that take no time), until
nothing new comes (at most `MAX_ENTRIES` states per block, and a budget of runs linear in the
script's size: blocks alike entered alike are run once). An error of at least
`POSITION_TOLERANCE` or `HEADING_TOLERANCE` is reported, once per block: at the move starting
the first motion the governor cannot centre (with why, and what would let it), or, when the
block is fine on its own but not after some block, at the block's first move with that block
labelled.
"""

from __future__ import annotations

import math
from collections import deque
from itertools import pairwise

from scriptc.check.context import Context, MoveRead, Tracks
from scriptc.check.flow import next_timed, successors
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Label
from scriptc.ir.nodes import InstructionBlock, JumpBlock, MoveCommand
from scriptc.robot.motion import (
    GROUPS,
    REST,
    BlockRun,
    Entry,
    EntryKey,
    Motion,
    Pose,
    Velocity,
    centred_bound,
    centred_ms,
    ideal_pose,
    limit_ms,
    limit_speed,
    rates_of,
    run_block,
    track_steps,
)
from scriptc.robot.profile import Profile

POSITION_TOLERANCE = 0.01  # m: a centimetre, where the robot ends up
HEADING_TOLERANCE = math.radians(1.0)  # a degree, which way it faces
MAX_ENTRIES = 8  # states a block is followed from (a loop of short blocks needs a few)
# Runs of blocks (`motion.run_block`, about half a millisecond each when a ramp turns while it
# moves) a script's check may take: a base plus so many per instruction block, so that the
# check stays linear; past it no more states are followed.
_RUNS_BASE = 1000
_RUNS_PER_BLOCK = 3
# A block whose centred ramps are bound to leave the robot within this share of the position
# tolerance is not run (`motion.centred_bound`; the grid's rounding is far below the rest).
_BOUND_SHARE = 0.9
_EXIT_SEARCH = 256  # blocks that take no time crossed per search for the next blocks

# Where a run leaves the robot, the governed pose minus the script's: (dx, dy, dtheta).
_Error = tuple[float, float, float]
# The block whose run adds the most to a chain's error so far: (block, its entry, how much;
# `_size`), or `_NO_BLAME` before any.
_Blame = tuple[int, EntryKey, float]
_NO_BLAME: _Blame = (-1, REST.key(), 0.0)
# A state followed along the control flow: (block, entry, error so far, the chain's first
# block, blame).
_State = tuple[int, Entry, _Error, int, _Blame]


# `_Moves.key`: blocks with the same steps and length run alike.
_MovesKey = tuple[tuple[tuple[int, Velocity], ...], int]


class _Moves:
    """An instruction block's move track, read: the steps of its velocity (within the speed
    limits), its length, and when each command starts (ms from the block's start)."""

    __slots__ = ("block", "commands", "ideal", "index", "key", "length", "starts")

    def __init__(self, index: int, block: InstructionBlock, starts: list[int],
                 key: _MovesKey) -> None:
        self.index, self.block, self.commands, self.starts = index, block, block.moves, starts
        self.length, self.key = key[1], key
        # where the steps take the robot (`motion.ideal_pose`), when needed
        self.ideal: Pose | None = None

    @property
    def steps(self) -> list[tuple[int, Velocity]]:
        """The steps of the track's velocity (`motion.track_steps`), for a run."""
        return list(self.key[0])

    def command_at(self, t: int) -> MoveCommand | None:
        """The command that starts at `t`, or the last one started before."""
        found = None
        for command, start in zip(self.commands, self.starts, strict=True):  # read together
            if start > t:
                break
            found = command
        return found


# `_read`'s work for a move track, by what it read (`Tracks.moves`) and the block's length:
# when each command starts and the `_MovesKey`, or None (not readable).
_Steps = dict[tuple[tuple[MoveRead, ...], int], tuple[list[int], _MovesKey] | None]


def _read(index: int, tracks: Tracks, profile: Profile, seen: _Steps) -> _Moves | None:
    """The move track of an instruction block (its tracks read), or None when the block
    takes no time or a number of its moves is not readable (V002, V003, V006). `seen` holds
    the tracks read so far: a script repeats its blocks."""
    length = tracks.duration
    if not length or length < 0:
        return None
    read = (tuple(tracks.moves), length)
    if read in seen:
        found = seen[read]
    else:
        found = seen[read] = _steps(tracks.moves, length, profile)
    return None if found is None else _Moves(index, tracks.block, *found)


def _steps(reads: list[MoveRead], length: int, profile: Profile,
           ) -> tuple[list[int], _MovesKey] | None:
    """When each move starts and the steps of the track's velocity (`_MovesKey`), or None
    when a number is not readable."""
    moves: list[tuple[Velocity, int, int]] = []
    starts: list[int] = []
    t = 0
    for velocity, wait, duration in reads:
        if velocity is None or wait is None or duration is None:
            return None
        t += wait
        starts.append(t)
        t += duration
        moves.append((limit_speed(velocity, profile)[0], wait, duration))
    return starts, (tuple(track_steps(moves)), length)


def _off(error: _Error) -> tuple[float, float]:
    return math.hypot(error[0], error[1]), error[2]


def _matters(error: _Error) -> bool:
    position, heading = _off(error)
    return position >= POSITION_TOLERANCE or abs(heading) >= HEADING_TOLERANCE


def _at_rest(entry: Entry) -> bool:
    return entry.ramp is None and not any(entry.target) and not any(entry.command)


class NextTimed:
    """The blocks that take time (`Context.durations`) that control may go to next, through
    the blocks that take none (`flow.next_timed`: at most `_EXIT_SEARCH` of them per search),
    each with the last jump passed (-1: none): from the script's start (`search((0,))`) and
    when each block ends (`after`, memoised). Built once per script (`ctx.table(NextTimed)`):
    K002 and K003 follow the same control flow."""

    def __init__(self, ctx: Context) -> None:
        self.blocks = ctx.blocks
        self.succ, self.resolved = ctx.table(successors)
        self.timed = [duration != 0 for duration in ctx.durations]
        self._after: dict[int, list[tuple[int, int]]] = {}

    def search(self, starts: tuple[int, ...]) -> list[tuple[int, int]]:
        """The blocks that take time reached from `starts` (`flow.next_timed`)."""
        return next_timed(self.blocks, self.succ, self.timed, starts, _EXIT_SEARCH)

    def after(self, i: int) -> list[tuple[int, int]]:
        """Where control may go when block `i` ends: (next block that takes time, via)."""
        found = self._after.get(i)
        if found is None:
            found = self._after[i] = self._near(self.succ[i]) or self.search(self.succ[i])
        return found

    def _near(self, succ: tuple[int, ...]) -> list[tuple[int, int]] | None:
        """What `search(succ)` finds, without a search, in the common cases: the one next
        block takes time; or it takes none and every block after it does (the search crosses
        it, and a jump there is the way). None otherwise (a search is needed)."""
        if len(succ) != 1:
            return None
        j = succ[0]
        if self.timed[j]:
            return [(j, -1)]
        after = self.succ[j]
        if not after or not all(self.timed[k] for k in after):
            return None
        via = j if isinstance(self.blocks[j], JumpBlock) else -1
        return [(k, via) for k in after]


def check_ramps(ctx: Context, profile: Profile, out: list[Diagnostic]) -> None:
    blocks = ctx.blocks
    read: _Steps = {}  # (bounded by the script)
    reads = [None if t is None else _read(i, t, profile, read)
             for i, t in enumerate(ctx.tracks)]
    if not blocks or not any(r is not None and r.block.moves for r in reads):
        return  # nothing moves
    rates = rates_of(profile)
    flow = ctx.table(NextTimed)
    # a run, with its size (`_size`, rounded) and whether it leaves the robot at rest
    runs: dict[tuple[int, EntryKey], tuple[BlockRun, float, bool]] = {}
    alike: dict[tuple[_MovesKey, EntryKey], tuple[BlockRun, float, bool]] = {}
    budget = _RUNS_BASE + _RUNS_PER_BLOCK * sum(r is not None for r in reads)

    # A chain: blocks from the one the robot starts to move in (entered at rest) to the one it
    # comes to rest in (or the script's end). Its error is the sum of its blocks' errors, each
    # block's run assuming the robot stops at its end: where the next block goes on moving,
    # what that stop would add is taken back by the next block's run from the state the robot
    # is really in (`motion.run_block`). It is reported at the block whose run adds the most
    # (`blame`). The states along the control flow: (block, entry, error so far, the chain's
    # first block, blame), at most MAX_ENTRIES per block.
    seen: dict[int, set[tuple[EntryKey, _Error, int, _Blame]]] = {}  # by block, once reached
    # blamed block -> (error, its entry, the chain's first block)
    found: dict[int, tuple[_Error, EntryKey, int]] = {}
    start = (REST, (0.0, 0.0, 0.0), -1, _NO_BLAME)
    todo: deque[_State] = deque((b, *start) for b, _ in flow.search((0,)))
    while todo:
        b, entry, error, first, blame = todo.popleft()
        entry_key = entry.key()
        key = (entry_key, error, first, blame)
        states = seen.get(b)
        if states is None:
            states = seen[b] = set()
        elif key in states or len(states) >= MAX_ENTRIES:
            continue
        states.add(key)
        if first < 0:
            first = b
        moves = reads[b]
        if moves is None or (not moves.commands and entry is REST):
            # times not readable (V006): start again at rest; or nothing moves here
            leaving, total, rests = REST, error, True
        else:
            ran = runs.get((b, entry_key))
            if ran is None:
                # blocks alike entered alike run alike (a script repeats its blocks)
                same = (moves.key, entry_key)
                ran = alike.get(same)
                if ran is None:
                    if len(alike) >= budget:
                        break  # the script's work is spent: what is found is reported
                    run = _run(entry, moves, rates)
                    ran = alike[same] = (run, round(_size(run.error), 9), _at_rest(run.exit))
                runs[(b, entry_key)] = ran
            run, size, rests = ran
            leaving = run.exit
            # rounded, so that a loop of blocks moving on at one speed comes back to a state
            total = (round(error[0] + run.error[0], 9), round(error[1] + run.error[1], 9),
                     round(error[2] + run.error[2], 9))
            if size > blame[2]:
                blame = (b, entry_key, size)
        exits = flow.after(b)
        if rests or not exits:
            if _matters(total) and blame[0] >= 0:
                worst = found.get(blame[0])
                if worst is None or _size(total) > _size(worst[0]):
                    found[blame[0]] = (total, blame[1], first)
            todo.extend((c, *start) for c, _ in exits)
        else:
            todo.extend((c, leaving, total, first, blame) for c, _ in exits)

    for b, (error, entry_key, first) in sorted(found.items()):
        moves = reads[b]
        assert moves is not None  # a block is blamed for its run
        out.append(_report(ctx, moves, runs[(b, entry_key)][0], error, first, rates, profile))


def _run(entry: Entry, moves: _Moves, rates: Velocity) -> BlockRun:
    """`motion.run_block`, or nothing to run: a block entered at rest whose motions are all
    centred, and ramp together too little to come near the tolerance (`centred_bound`), ends
    at rest within a fraction of it (its error is taken as none)."""
    if entry is REST:
        centred = centred_bound(moves.steps, moves.length, rates)
        if centred is not None and centred[1] < _BOUND_SHARE * POSITION_TOLERANCE:
            return BlockRun(centred[0], REST, (0.0, 0.0, 0.0))
    if moves.ideal is None:
        moves.ideal = ideal_pose(moves.steps, moves.length)
    return run_block(entry, moves.steps, moves.length, rates, exact=False, ideal=moves.ideal)


def _size(error: _Error) -> float:
    position, heading = _off(error)
    return max(position / POSITION_TOLERANCE, abs(heading) / HEADING_TOLERANCE)


# -- reporting -----------------------------------------------------------------------------------


def _fmt(v: float) -> str:
    return f"{v:g}"


def _how_far(error: _Error) -> str:
    """`3.2 cm and 12.2° (0.213 rad)`, leaving out what is within the tolerances."""
    position, heading = _off(error)
    parts: list[str] = []
    if position >= POSITION_TOLERANCE:
        parts.append(f"{position * 100:.1f} cm" if position < 1 else f"{position:.2f} m")
    if abs(heading) >= HEADING_TOLERANCE:
        parts.append(f"{abs(math.degrees(heading)):.1f}° ({abs(heading):.3f} rad)")
    return " and ".join(parts)


def _profile_note(profile: Profile) -> str:
    source = "" if profile.source == "defaults" else f" (from {profile.source})"
    return (f"profile{source}: max-linear-acceleration = "
            f"{_fmt(profile.max_linear_acceleration)} m/s², max-angular-acceleration = "
            f"{_fmt(profile.max_angular_acceleration)} rad/s²")


def _needs(motion: Motion, rates: Velocity) -> tuple[int, int, tuple[int, int, int] | None]:
    """What centring the motion needs: the wait before its first change and the time after its
    last one (ms), and the first speed too short for the ramps around it (when it starts, how
    long it lasts, how long its ramps need), if any."""
    group_rates = [rates[i] for i in GROUPS[motion.group]]
    spans: list[tuple[int, int, int]] = []
    for t, v0, v1 in motion.changes:
        m = centred_ms(limit_ms(v0, v1, group_rates))
        spans.append((t, (m - 1) // 2, (m + 1) // 2))
    short = next(((a[0], b[0] - a[0], a[2] + b[1]) for a, b in pairwise(spans)
                  if b[0] - a[0] < a[2] + b[1]), None)
    return spans[0][1], spans[-1][2], short


def _report(ctx: Context, moves: _Moves, run: BlockRun, error: _Error, first: int,
            rates: Velocity, profile: Profile) -> Diagnostic:
    """A chain of blocks from `first` leaves the robot away from the script's pose, and this
    block's run adds the most to it: reported at its first motion the governor cannot
    centre."""
    late = [m for m in run.motions if not m.centred] or run.motions
    motion = min(late, key=lambda m: m.changes[0][0])
    start = motion.changes[0][0]
    command = moves.command_at(start) or moves.commands[0]
    what = "moves" if motion.group == 0 else "turns"
    lead, tail, short = _needs(motion, rates)
    stop = motion.changes[-1][0]
    wants: list[str] = []
    if motion.late_because == "entered":
        wants.append("end the previous block's move at least half a ramp before that block "
                     "ends, or start this block with the velocity it ends with")
    else:
        if start < lead:
            wants.append(f"start it at least {lead} ms into the block (its `wait_t`)")
        if moves.length - stop < tail:
            wants.append(f"let the block go on at least {tail} ms after it stops (a longer "
                         "LED or audio track)")
        if short is not None:
            wants.append(f"keep each speed long enough for the ramps around it (the one from "
                         f"{short[0]} ms lasts {short[1]} ms, its ramps need {short[2]}), or "
                         "change it by less")
    why = {
        "start": "it starts as the block starts (or while the robot still moves), so its "
                 "first ramp cannot begin before it",
        "end": "it runs to the end of the block, and what comes next is not known before then",
        "overlap": "its changes come faster than their ramps",
        "entered": "the block starts while the robot still moves (or brakes) from the block "
                   "before",
    }[motion.late_because or "start"]
    notes = [
        "the governor ramps each change of speed at the robot profile's acceleration; ramps "
        "centred on the changes keep the distance, but " + why + ": each change is ramped "
        "from where it is, and the robot lags behind the script"]
    labels: list[Label] = []
    if first != moves.index:
        labels.append(Label(ctx.block_head(ctx.blocks[first]),
                            "the robot starts moving in this block"))
        notes.append("the motion goes on from block to block: the error is counted from where "
                     "the robot starts moving to where it comes to rest")
    notes.append(_profile_note(profile))
    help = ("so that the governor can centre the ramps, " + "; ".join(wants)
            if wants else "keep one speed from the start of the motion to its stop")
    return diagnostic(
        "K003", f"the governor's ramps leave the robot {_how_far(error)} away from where "
                f"the script {what} it", command.span,
        labels=tuple(labels), notes=tuple(notes), help=help)
