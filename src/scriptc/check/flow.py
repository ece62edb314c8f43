"""Pass 3, control flow between blocks: unreachable blocks (F001), cycles of jump and sensor
blocks that pass no instruction block (F002), and scripts without a terminus (F003).

The control-flow graph has one node per block, in execution order (goal by goal, action by
action, block by block; docs/runtime.md "The block reader"):
- an instruction or sensor block goes on to the next block;
- a jump goes to its true target and to its false target, an empty target meaning the next
  block (docs/language.md); a jump whose condition cannot be false takes the true branch
  only (`Condition.is_constant_true`);
- a terminus goes nowhere; past the last block the script ends.
Everything here is iterative (no recursion): scripts may have 10,000 blocks and more.
"""

from __future__ import annotations

from collections.abc import Sequence

from scriptc.check.context import Context
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, Label, TextEdit
from scriptc.ir.nodes import (
    Block,
    InstructionBlock,
    JumpBlock,
    Name,
    TerminusBlock,
    block_path,
)
from scriptc.source import Span

# A cycle's report labels at most this many of its other blocks; a note gives the rest.
_MAX_CYCLE_LABELS = 8


def successors(ctx: Context) -> tuple[list[tuple[int, ...]], bool]:
    """The successors of every block (indices in execution order; `len(blocks)` stands for
    "the script ends" and is left out), and whether every jump target was resolved. An
    unknown target (L003) adds no edge."""
    blocks = ctx.blocks
    n = len(blocks)
    index = ctx.labels.index
    resolved = True

    def target(name: Name | None, i: int) -> int | None:
        nonlocal resolved
        if name is None or not name.text:
            return i + 1
        j = index.get(name.text)
        if j is None:
            resolved = False
        return j

    succ: list[tuple[int, ...]] = []
    for i, block in enumerate(blocks):
        if isinstance(block, TerminusBlock):
            succ.append(())
        elif isinstance(block, JumpBlock):
            ts = [target(block.true_target, i)]
            if not block.condition.is_constant_true:
                ts.append(target(block.false_target, i))
            succ.append(tuple(sorted({t for t in ts if t is not None and t < n})))
        else:
            succ.append((i + 1,) if i + 1 < n else ())
    return succ, resolved


def next_timed(blocks: Sequence[Block], succ: list[tuple[int, ...]], timed: Sequence[bool],
               starts: tuple[int, ...], limit: int) -> list[tuple[int, int]]:
    """The blocks that take time (`timed[i]`) control reaches from `starts` through blocks
    that take none (jumps, sensor blocks, empty instruction blocks: all in the same
    millisecond), each with the last jump passed (-1: none), depth first in the order of the
    successors; at most `limit` blocks are visited (a cycle of blocks that take no time, F002,
    just ends the search)."""
    found: list[tuple[int, int]] = []
    seen: set[int] = set()
    todo = [(w, -1) for w in reversed(starts)]
    while todo and len(seen) < limit:
        v, via = todo.pop()
        if v in seen:
            continue
        seen.add(v)
        if timed[v]:
            found.append((v, via))
            continue
        if isinstance(blocks[v], JumpBlock):
            via = v
        todo.extend((w, via) for w in reversed(succ[v]) if w not in seen)
    return found


def check_flow(ctx: Context) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    blocks = ctx.blocks
    if not blocks:
        return out
    succ, resolved = ctx.table(successors)  # (built once: the safety pass reads it too)
    # With an unknown jump target (L003) nobody knows where that jump goes, so reachability
    # would blame blocks for the typo; F001 waits until the labels are right.
    if resolved:
        _unreachable(ctx, succ, out)
    _cycles(ctx, succ, out)
    _terminus(ctx, out)
    return out


def _unreachable(ctx: Context, succ: list[tuple[int, ...]], out: list[Diagnostic]) -> None:
    blocks = ctx.blocks
    n = len(blocks)
    reached = [False] * n
    reached[0] = True
    todo = [0]
    while todo:
        v = todo.pop()
        for w in succ[v]:
            if not reached[w]:
                reached[w] = True
                todo.append(w)
    addresses = [a for a, _ in ctx.addressed_blocks]
    i = 1  # the script starts at block 0
    while i < n:
        if reached[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and not reached[j + 1]:
            j += 1
        count = j - i + 1
        notes = []
        if count > 1:
            after = "the next one" if count == 2 else f"the {count - 1} after it"
            notes.append(f"this block and {after} are never reached "
                         f"({block_path(addresses[i])} to {block_path(addresses[j])})")
        # The block before the run was reached (block 0 always is) and does not go on to the
        # next one: it is a terminus or a jump that goes elsewhere.
        labels = []
        before = blocks[i - 1]
        if isinstance(before, TerminusBlock):
            labels.append(Label(ctx.block_head(before), "the script ends here"))
        elif isinstance(before, JumpBlock):
            target = before.true_target.text if before.true_target else ""
            if before.condition.is_constant_true and target in ctx.labels.index:
                if not ctx.is_script_syntax:  # labels were made up from JSON paths
                    target = block_path(addresses[ctx.labels.index[target]])
                why = f"this jump always goes to `{target}`"
            else:
                why = "neither branch of this jump goes on to the next block"
            labels.append(Label(ctx.block_head(before), why))
        out.append(
            diagnostic(
                "F001",
                "unreachable block" if count == 1 else f"{count} unreachable blocks",
                ctx.block_head(blocks[i]),
                labels=labels,
                notes=notes,
                help="remove the blocks no path reaches, or label the first one and jump to it",
            )
        )
        i = j + 1


def strongly_connected(nodes: list[int], succ: list[tuple[int, ...]],
                       keep: list[bool]) -> list[list[int]]:
    """Tarjan's strongly connected components of the subgraph of nodes with `keep[v]`,
    iteratively. Components come out in reverse topological order."""
    n = len(succ)
    index = [-1] * n
    low = [0] * n
    on_stack = [False] * n
    stack: list[int] = []
    components: list[list[int]] = []
    counter = 0
    for root in nodes:
        if index[root] >= 0:
            continue
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack[root] = True
        work = [(root, iter(succ[root]))]
        while work:
            v, it = work[-1]
            descended = False
            for w in it:
                if not keep[w]:
                    continue
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack[w] = True
                    work.append((w, iter(succ[w])))
                    descended = True
                    break
                if on_stack[w] and index[w] < low[v]:
                    low[v] = index[w]
            if descended:
                continue
            work.pop()
            if work:
                u = work[-1][0]
                if low[v] < low[u]:
                    low[u] = low[v]
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    component.append(w)
                    if w == v:
                        break
                components.append(component)
    return components


def _cycles(ctx: Context, succ: list[tuple[int, ...]], out: list[Diagnostic]) -> None:
    blocks = ctx.blocks
    # Reading blocks stops only at an instruction block (the next tick) or a terminus; the map
    # does not change in between (thesis 4.2), so a cycle without an instruction block, once
    # entered, repeats the same decisions forever. An instruction block that takes no time
    # (`MV() LD() AO()`, or only zero waits and durations) is consumed in the same millisecond
    # it is issued, so it does not let time pass either.
    keep = [duration == 0 for duration in ctx.durations]
    nodes = [i for i, k in enumerate(keep) if k]
    for component in strongly_connected(nodes, succ, keep):
        if len(component) == 1:
            v = component[0]
            if v not in succ[v]:
                continue
        component.sort()
        head = component[0]
        others = component[1:]
        labels = [Label(ctx.block_head(blocks[v]), "part of the cycle")
                  for v in others[:_MAX_CYCLE_LABELS]]
        notes = [("the map does not change while blocks are read, so once the robot enters this "
                  "cycle it repeats the same jumps forever inside one tick")]
        if len(others) > _MAX_CYCLE_LABELS:
            notes.append(f"{len(others) - _MAX_CYCLE_LABELS} more blocks are part of the cycle")
        timeless = [v for v in component if isinstance(blocks[v], InstructionBlock)]
        if timeless:
            notes.append(f"{len(timeless)} instruction block{'s' if len(timeless) > 1 else ''} "
                         "in the cycle take no time: every wait and duration is 0")
        message = (
            "this jump block jumps to itself without passing an instruction block"
            if not others
            else f"{len(component)} blocks form a cycle that passes no instruction block"
            + (" that takes time" if timeless else "")
        )
        out.append(
            diagnostic(
                "F002",
                message,
                ctx.block_head(blocks[head]),
                labels=labels,
                notes=notes,
                help="put an instruction block in the cycle (even one that only waits, such as "
                     '`[b##blk_inst: MV() LD() AO("Silence, 0, 100")]`) so the map can change',
            )
        )


def _terminus(ctx: Context, out: list[Diagnostic]) -> None:
    blocks = ctx.blocks
    if any(isinstance(b, TerminusBlock) for b in blocks):
        return
    last = blocks[-1]
    fix = None
    if ctx.is_script_syntax:
        at = Span(last.span.end, last.span.end)
        fix = Fix("end the script with a terminus block",
                  (TextEdit(at, ctx.newline + ctx.indent_at(last.span.start)
                            + "[b##blk_terminus]"),))
    out.append(
        diagnostic(
            "F003",
            "the script has no terminus block",
            ctx.block_head(last),
            notes=(("the script ends by running past its last block (valid: the thesis's "
                    "`dance_example.json` does so)"),),
            help="end the script explicitly with "
                 + ("`[b##blk_terminus]`" if ctx.is_script_syntax else '`{"type": "terminus"}`'),
            fix=fix,
        )
    )
