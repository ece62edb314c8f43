"""The outline of a script (activity > goals > actions > blocks) and its foldable regions.

A goal's span runs from its `[goal:ID]` item to the end of its last block (or of its last
`[action]` item, when it has no block), and likewise for an action; blocks are named by
their label, or by their kind when they have none, with their path and duration beside.
Rule messages sit under the activity, before the goals.
"""

from __future__ import annotations

from scriptc.ide.answers import Fold, Symbol
from scriptc.ide.hover import format_ms
from scriptc.ide.index import BlockInfo
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.nodes import InstructionBlock, JumpBlock, SensorBlock, TerminusBlock
from scriptc.source import Span

__all__ = ["document_symbols", "folding_ranges"]

_KIND_WORD = {InstructionBlock: "blk_inst", JumpBlock: "blk_jump", TerminusBlock: "blk_terminus",
              SensorBlock: "blk_sens"}


def _block_symbol(info: BlockInfo) -> Symbol:
    block = info.block
    word = _KIND_WORD[type(block)]
    label = block.label
    if label is not None and label.text:
        name, selection, detail = label.text, label.span, f"{word} · {info.path}"
    else:
        name, selection, detail = word, block.span, info.path
    if isinstance(block, InstructionBlock):
        detail += f" · {format_ms(info.duration_ms)}"
    return Symbol(name, "block", block.span, selection, detail)


def document_symbols(snapshot: Snapshot) -> list[Symbol]:
    script = snapshot.script
    if script is None:
        return []
    index = snapshot.index
    children: list[Symbol] = []
    for message in (*script.alfa, *script.omega):
        children.append(Symbol(f"{message.kind} {message.id.text}", "message", message.span,
                               message.id.span, f"{message.action.text}, {message.mutex.text}"))
    for g, goal in enumerate(script.goals):
        actions = []
        for a, action in enumerate(goal.actions):
            blocks = tuple(_block_symbol(index.blocks[b.span.start]) for b in action.blocks)
            end = action.blocks[-1].span.end if action.blocks else action.span.end
            actions.append(Symbol(f"act{a}", "action", Span(action.span.start, end), action.span,
                                  f"goal{g}/act{a} · {len(action.blocks)} block"
                                  + "s" * (len(action.blocks) != 1), blocks))
        end = actions[-1].span.end if actions else goal.span.end
        name = goal.id.text or f"goal{g}"
        selection = goal.id.span if goal.id.text else goal.span
        children.append(Symbol(name, "goal", Span(goal.span.start, end), selection, f"goal{g}",
                               tuple(actions)))
    items = snapshot.items
    start = items[0].span.start if items else 0
    end = max([items[-1].span.end if items else 0] + [c.span.end for c in children])
    name = script.name.text or "(no activity name)"
    selection = script.name.span if script.name.text else Span(start, start)
    return [Symbol(name, "activity", Span(start, end), selection, "activity", tuple(children))]


def folding_ranges(snapshot: Snapshot) -> list[Fold]:
    """Goals, actions, items written over several lines, comments over several lines, and
    the run of rule messages. Regions on one line are dropped by the protocol layer."""
    folds: list[Fold] = []

    def walk(symbols) -> None:
        for s in symbols:
            if s.kind in ("goal", "action", "block"):
                folds.append(Fold(s.span))
            walk(s.children)

    symbols = document_symbols(snapshot)
    walk(symbols)
    if symbols:
        messages = [s for s in symbols[0].children if s.kind == "message"]
        if len(messages) > 1:
            folds.append(Fold(Span(messages[0].span.start, messages[-1].span.end)))
    folds.extend(Fold(c, "comment") for c in snapshot.comments)
    folds.sort(key=lambda f: (f.span.start, -f.span.end))
    return folds
