"""F002 against a brute-force reference: random small jump graphs, written as scripts, whose
cycles that let no time pass are enumerated one simple cycle at a time; and the search for the
blocks that take time next (`next_timed`) on the same graphs.

The reference knows nothing of check/flow.py's graph or of Tarjan's algorithm. It takes the
block-reader's rules from the graph the strategy drew (docs/runtime.md "The block reader"): a
jump goes to its true target and, unless its condition cannot be false, to its false target,
an empty target meaning the next block; an instruction block or a sensor block goes on to
the next block; a terminus, and the end of the script, go nowhere; an instruction block stops
reading only when it takes time. Every simple cycle of the blocks that take no time is found
by walking every path; cycles that share a block make one report, led by its first block,
naming every other block of it, once.
"""

from __future__ import annotations

from dataclasses import dataclass

from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.check.context import Context
from scriptc.check.flow import _MAX_CYCLE_LABELS, check_flow, next_timed, successors
from scriptc.frontend.script import lower_script
from scriptc.ir.nodes import JumpBlock
from scriptc.source import SourceFile

# A condition that cannot be false, and one that can (the checks know no more of it).
ALWAYS = "{TRUE}"
MAYBE = "! {E: gt(@n, 1)}"


@dataclass(frozen=True)
class Block:
    kind: str                    # "jump", "sensor", "still" (takes no time), "timed", "terminus"
    true: int | None = None      # jumps: the target block, None for the next block
    false: int | None = None
    constant: bool = False       # jumps: the condition cannot be false


@st.composite
def graphs(draw, most: int = 10) -> list[Block]:
    n = draw(st.integers(1, most))
    target = st.one_of(st.none(), st.integers(0, n - 1))
    blocks = []
    for _ in range(n):
        kind = draw(st.sampled_from(["jump", "jump", "jump", "sensor", "still", "timed",
                                     "terminus"]))
        if kind == "jump":
            blocks.append(Block(kind, draw(target), draw(target), draw(st.booleans())))
        else:
            blocks.append(Block(kind))
    return blocks


def script_text(blocks: list[Block], goals: list[int]) -> str:
    """The graph as a script, block i labelled `b{i}`, a new goal before each index in
    `goals` (execution order runs on across goals: the graph does not see them)."""
    lines = ["[act]", "[goal:g]", "[action]"]
    for i, block in enumerate(blocks):
        if i in goals:
            lines += [f"[goal:g{i}]", "[action]"]
        head = f"[b#b{i}#"
        if block.kind == "jump":
            true = "" if block.true is None else f"b{block.true}"
            false = "" if block.false is None else f"b{block.false}"
            condition = ALWAYS if block.constant else MAYBE
            lines.append(f"{head}blk_jump: CND({condition}) TRJMP({true}) FLSJMP({false})]")
        elif block.kind == "sensor":
            lines.append(f"{head}blk_sens]")
        elif block.kind == "still":
            lines.append(f'{head}blk_inst: MV("0, 0, 0, 0, 0") LD() AO()]')
        elif block.kind == "timed":
            lines.append(f'{head}blk_inst: MV() LD() AO("Silence, 0, 100")]')
        else:
            lines.append(f"{head}blk_terminus]")
    return "\n".join(lines) + "\n"


def next_blocks(blocks: list[Block], i: int) -> set[int]:
    """Where reading goes after block i (the script's end left out)."""
    block = blocks[i]
    if block.kind == "terminus":
        found = set()
    elif block.kind == "jump":
        found = {i + 1 if block.true is None else block.true}
        if not block.constant:
            found.add(i + 1 if block.false is None else block.false)
    else:
        found = {i + 1}
    return {j for j in found if j < len(blocks)}


def simple_cycles(blocks: list[Block]) -> list[tuple[int, ...]]:
    """Every simple cycle through blocks that take no time, each once: walked from its
    smallest block through larger ones only."""
    still = [b.kind != "timed" for b in blocks]
    cycles = []
    for start in range(len(blocks)):
        if not still[start]:
            continue
        paths = [(start,)]
        while paths:
            path = paths.pop()
            for j in next_blocks(blocks, path[-1]):
                if j == start:
                    cycles.append(path)
                elif j > start and still[j] and j not in path:
                    paths.append(path + (j,))
    return cycles


def expected_reports(blocks: list[Block]) -> list[tuple[int, tuple[int, ...], str, tuple]]:
    """(first block, the others, message, notes) for each group of cycles sharing blocks."""
    groups: list[set[int]] = []
    for cycle in simple_cycles(blocks):
        joined = set(cycle)
        for group in [g for g in groups if g & joined]:
            joined |= group
            groups.remove(group)
        groups.append(joined)
    reports = []
    for group in groups:
        first, *others = sorted(group)
        still = sum(1 for i in group if blocks[i].kind == "still")
        if not others:
            message = "this jump block jumps to itself without passing an instruction block"
        else:
            message = (f"{len(group)} blocks form a cycle that passes no instruction block"
                       + (" that takes time" if still else ""))
        notes = [("the map does not change while blocks are read, so once the robot enters "
                  "this cycle it repeats the same jumps forever inside one tick")]
        if len(others) > _MAX_CYCLE_LABELS:
            notes.append(f"{len(others) - _MAX_CYCLE_LABELS} more blocks are part of the cycle")
        if still:
            notes.append(f"{still} instruction block{'s' if still > 1 else ''} in the cycle "
                         "take no time: every wait and duration is 0")
        reports.append((first, tuple(others[:_MAX_CYCLE_LABELS]), message, tuple(notes)))
    return sorted(reports)


def reported(blocks: list[Block], goals: list[int]):
    text = script_text(blocks, goals)
    source = SourceFile("t.script", text)
    script, problems = lower_script(source)
    assert script is not None and not problems, problems
    heads = {text.index(f"[b#b{i}#"): i for i in range(len(blocks))}
    found = []
    for d in check_flow(Context(script, source)):
        if d.code != "F002":
            continue
        others = tuple(heads[label.span.start] for label in d.labels)
        assert all(label.message == "part of the cycle" for label in d.labels)
        found.append((heads[d.span.start], others, d.message, tuple(d.notes)))
    return sorted(found)


@settings(max_examples=400, deadline=None)
@given(graphs(), st.lists(st.integers(1, 9), max_size=2))
def test_f002_reports_each_group_of_cycles_once(blocks, goals):
    assert reported(blocks, goals) == expected_reports(blocks)


# The shapes the random graphs must not miss, each written out.

def test_a_jump_to_itself_is_one_cycle():
    blocks = [Block("jump", 0, None), Block("timed"), Block("terminus")]
    assert reported(blocks, []) == expected_reports(blocks) != []


def test_two_jumps_to_each_other_are_one_cycle_reported_once():
    blocks = [Block("jump", 1, None), Block("jump", 0, None), Block("terminus")]
    assert reported(blocks, []) == expected_reports(blocks)
    assert [(first, others) for first, others, *_ in reported(blocks, [])] == [(0, (1,))]


def test_two_jumps_one_way_are_no_cycle():
    # 0 -> 1 and 1 -> 2: a two-block path, no way back.
    blocks = [Block("jump", 1, None), Block("jump", 2, None), Block("terminus")]
    assert reported(blocks, []) == []


def test_a_timed_block_breaks_the_cycle_and_a_still_one_does_not():
    timed = [Block("jump", None, None), Block("timed"), Block("jump", 0, 0, True)]
    assert reported(timed, []) == []
    still = [Block("jump", None, None), Block("still"), Block("jump", 0, 0, True)]
    assert reported(still, []) == expected_reports(still)
    assert "that takes time" in reported(still, [])[0][2]


def test_a_constant_jump_does_not_take_its_false_branch():
    blocks = [Block("jump", 1, 0, True), Block("terminus")]
    assert reported(blocks, []) == []


def test_two_cycles_apart_are_two_reports_and_a_self_jump_inside_a_cycle_is_not_a_third():
    blocks = [Block("jump", 1, 0), Block("jump", 0, None), Block("timed"),
              Block("jump", 4, None), Block("jump", 3, 3), Block("terminus")]
    got = reported(blocks, [])
    assert got == expected_reports(blocks)
    assert [(first, others) for first, others, *_ in got] == [(0, (1,)), (3, (4,))]


def test_a_long_cycle_names_eight_blocks_and_counts_the_rest():
    blocks = [Block("jump", (i + 1) % 11, None, True) for i in range(11)] + [Block("terminus")]
    ((first, others, _message, notes),) = reported(blocks, [])
    assert (first, others) == (0, tuple(range(1, 9)))
    assert notes[1] == "2 more blocks are part of the cycle"


# -- next_timed: the blocks that take time control reaches without time passing ------------------
# (the safety and ramp passes' search for what runs next), against a breadth-first reference.


def spread(succ, froms, expand) -> set[int]:
    """Every block reached from `froms`, going on from a block only when `expand(block)`."""
    seen, todo = set(froms), list(froms)
    while todo:
        v = todo.pop()
        if expand(v):
            for w in succ[v]:
                if w not in seen:
                    seen.add(w)
                    todo.append(w)
    return seen


@settings(max_examples=300, deadline=None)
@given(graphs(), st.data())
def test_next_timed_finds_each_timed_block_reached_once_with_its_last_jump(blocks, data):
    n = len(blocks)
    text = script_text(blocks, [])
    source = SourceFile("t.script", text)
    script, _problems = lower_script(source)
    ctx = Context(script, source)
    succ, _resolved = successors(ctx)
    timed = data.draw(st.lists(st.booleans(), min_size=n, max_size=n))
    starts = tuple(data.draw(st.lists(st.integers(0, n - 1), max_size=3)))
    found = next_timed(ctx.blocks, succ, timed, starts, n + 1)
    reached = spread(succ, starts, lambda v: not timed[v])
    assert sorted(v for v, _via in found) == sorted(v for v in reached if timed[v])
    is_jump = [isinstance(b, JumpBlock) for b in ctx.blocks]
    plain = spread(succ, starts, lambda v: not timed[v] and not is_jump[v])
    for v, via in found:
        if via == -1:
            assert v in plain  # no jump on the way
        else:
            assert via >= 0 and is_jump[via] and not timed[via] and via in reached
            assert v in spread(succ, succ[via], lambda u: not timed[u] and not is_jump[u])
    # A limit stops the same search earlier: what it found is the start of the whole answer.
    for limit in range(n + 1):
        some = next_timed(ctx.blocks, succ, timed, starts, limit)
        assert len(some) <= limit and some == found[:len(some)]
