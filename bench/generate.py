"""Generators of large, valid scripts for the benchmarks (deterministic: no randomness)."""

from __future__ import annotations

_INST = (
    '    [b#blk{i}#blk_inst: MV("0.{m}, 0, 0.5, 0, 1000", "0, 0.1, 0, 0, 500") '
    'LD("1, 0, 0, 1, 0, 500", "0, 1, 0, 1, 0, 500") AO("songs/track{m}.wav, 0, 1000")]\n'
)
_JUMP = (
    "    [b#jmp{i}#blk_jump: CND({{CLASS #Human U ?kid{i} (?THIS>&positionrho OP< 1.{m}, "
    "B: near(2))}} ! {{E: gt(?kid{i}>&permanencetime, {t})}}) TRJMP(blk{t_i}) FLSJMP()]\n"
)


def big_script(blocks: int) -> str:
    """A script of about `blocks` blocks: instruction blocks and jumps with conditions
    (every jump goes forward, so the script is free of diagnostics), 50 blocks per action and
    10 actions per goal. 10,000 blocks are about 1.6 MB."""
    out = [
        "[big_activity]\n",
        '[alfa:0, kick_starter, "", "", C, U]\n',
        '[omega:0, kick_starter, "", "", R, L]\n',
    ]
    for i in range(0, blocks, 2):
        if i % 500 == 0:
            out.append(f"[goal:goal{i // 500}]\n")
        if i % 50 == 0:
            out.append("  [action]\n")
        m = i % 10
        out.append(_INST.format(i=i, m=m))
        out.append(_JUMP.format(i=i, m=m, t=1000 + i, t_i=i + 2 if i + 2 < blocks else i))
    out.append(f"    [b#blk{blocks}#blk_terminus]\n")
    return "".join(out)


def script_of_size(megabytes: float) -> str:
    """A script of about the given size."""
    per_block = len(big_script(100)) / 100
    return big_script(int(megabytes * 1_000_000 / per_block) // 2 * 2)
