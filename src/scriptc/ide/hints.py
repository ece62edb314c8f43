"""Inlay hints: after each block, the path `goalG/actA/blkB` the thesis JSON gives it (what a
jump to its label becomes) and, for an instruction block, how long it takes; and, once
`scriptc verify` has looked at the script in the background, the session's duration range
after the activity's name and each goal's reachability after its `[goal:ID]`
(`verify_hints`)."""

from __future__ import annotations

from scriptc.ide.answers import InlayHint, VerifyOverview
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.nodes import InstructionBlock
from scriptc.source import Span

__all__ = ["inlay_hints", "short_duration", "verify_hints"]


def short_duration(ms: float | None) -> str:
    """`250 ms`, `1.5 s`, `2 min 5 s`; `? ms` when a time is unreadable."""
    if ms is None:
        return "? ms"
    if ms < 1000:
        return f"{ms:g} ms"
    seconds = ms / 1000
    if seconds < 60:
        return f"{seconds:.3g} s" if seconds < 10 else f"{seconds:.4g} s"
    minutes, rest = divmod(seconds, 60)
    return f"{int(minutes)} min {rest:.0f} s"


def inlay_hints(snapshot: Snapshot, span: Span | None = None) -> list[InlayHint]:
    out: list[InlayHint] = []
    for info in snapshot.index.block_list:
        block = info.block
        if span is not None and (block.span.end < span.start or block.span.start > span.end):
            continue
        out.append(InlayHint(block.span.end, info.path, "path",
                             "the block's path in the thesis JSON (where jumps to it go)"))
        if isinstance(block, InstructionBlock):
            out.append(InlayHint(block.span.end, short_duration(info.duration_ms), "duration",
                                 "how long the block runs: its longest track"))
    return out


_GOAL_WORDS = {"reached": "reachable", "unreached": "unreachable", "unknown": "reachable?"}
_GOAL_TIPS = {"reached": "scriptc verify: a world leads the activity to this goal (replayed)",
              "unreached": "scriptc verify: no world reaches this goal",
              "unknown": "scriptc verify: not decided (see `scriptc verify`)"}


def verify_hints(snapshot: Snapshot, overview: VerifyOverview,
                 span: Span | None = None) -> list[InlayHint]:
    """The hints of a verification (see the module's docstring), placed on the snapshot's
    script: after `[NAME]` the duration range, after each `[goal:ID]` its verdict (goals are
    matched by id, so a verification of a slightly older text still lands where it
    belongs)."""
    script = snapshot.script
    if script is None:
        return []
    out: list[InlayHint] = []

    def wanted(offset: int) -> bool:
        return span is None or span.start <= offset <= span.end

    close = snapshot.text.find("]", script.name.span.end)
    end = close + 1 if close >= 0 else script.name.span.end  # after the `]` of `[NAME]`
    if wanted(end) and overview.shortest is not None:
        shortest = short_duration(overview.shortest)
        if overview.unbounded:
            label = f"session: {shortest} or more, may never end"
        elif overview.longest is None:
            label = f"session: at least {shortest}"
        elif overview.longest == overview.shortest:
            label = f"session: {shortest}"
        else:
            label = f"session: {shortest} to {short_duration(overview.longest)}"
        out.append(InlayHint(end, label, "verify",
                             "scriptc verify: the session's least and greatest time, over every "
                             "world"))
    verdicts = {goalid: (verdict, why) for goalid, verdict, why in overview.goals}
    for goal in script.goals:
        found = verdicts.get(goal.id.text)
        if found is None or not wanted(goal.span.end):
            continue
        verdict, why = found
        tip = _GOAL_TIPS[verdict] + (f": {why}" if why else "")
        out.append(InlayHint(goal.span.end, _GOAL_WORDS[verdict], "verify", tip))
    return out
