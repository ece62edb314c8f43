"""Inlay hints: after each block, the path `goalG/actA/blkB` the thesis JSON gives it (what a
jump to its label becomes) and, for an instruction block, how long it takes."""

from __future__ import annotations

from scriptc.ide.answers import InlayHint
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.nodes import InstructionBlock
from scriptc.source import Span

__all__ = ["inlay_hints", "short_duration"]


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
