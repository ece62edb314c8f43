"""Generators of large, valid scripts for the benchmarks (deterministic: fixed patterns, or a
seeded random generator)."""

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


_CONDITIONS = (
    "! {{E: gt(@count, {n})}}",
    "{{CLASS #Human U ?kid (?THIS>&positionrho OP< {f})}} ! {{TRUE}}",
    ("{{CLASS #Human T ?kid (?THIS>&positionrho OP< {f}, B: near({n}))}} ! "
     "{{E: gt(?kid>&permanencetime, {t})}}"),
    "{{VAR @start U F: now()}} ! {{E: gt(@start, {t})}}",
    ("{{CLASS #Object U ?toy (?THIS>&positiontheta OP> {f})}} "
     "{{CLASS #Human U ?kid (?THIS>&positionrho OP< {f})}} ! {{E: lt(?kid>&positionrho, {f})}}"),
    "{{TRUE}}",
)


def varied_script(blocks: int, seed: int) -> str:
    """A valid script of about `blocks` blocks in many shapes, as people write them: 0-3 moves,
    0-3 LED commands and 0-2 tracks per instruction block, jumps on six kinds of condition,
    comments now and then, labels on some blocks only (deterministic for a seed). Each move
    waits half a second or more, lasts as long, and the move track ends with 300 ms still:
    room for the governor's ramps around each change (K003, docs/robot.md), so the script has
    no diagnostic."""
    import random

    rng = random.Random(seed)

    def number(scale: float) -> str:
        return f"{rng.random() * scale:.{rng.choice((1, 2))}f}"

    out = [f"% activity {seed}: generated, varied %\n[activity{seed}]\n",
           '[alfa:0, kick_starter, "", "", C, U]\n', '[omega:0, kick_starter, "", "", R, L]\n']
    labelled = [i % 20 != 19 and rng.random() < 0.6 for i in range(blocks)]
    for i in range(blocks):
        if i % 40 == 0:
            out.append(f"[goal:goal{i // 40}]\n")
        if i % 20 == 0:
            out.append("  [action]\n")
        label = f"b{i}" if labelled[i] else ""
        if rng.random() < 0.35 and i % 20 not in (0, 19):
            # forward, within the action: to the next labelled block, or on to the next block
            ahead = [j for j in range(i + 1, min(blocks, i - i % 20 + 20)) if labelled[j]]
            target = f"b{ahead[0]}" if ahead and rng.random() < 0.5 else ""
            condition = rng.choice(_CONDITIONS).format(n=rng.randint(0, 9), f=number(2),
                                                       t=rng.randint(0, 5000))
            if condition == "{TRUE}":
                target = ""  # an unconditional jump ahead would leave blocks unreachable
            out.append(f"    [b#{label}#blk_jump: CND({condition}) TRJMP({target}) FLSJMP()]\n")
            continue
        moves = [f'"{number(0.4)}, {number(0.2)}, {number(1)}, {rng.randint(5, 8) * 100}, '
                 f'{rng.randint(5, 20) * 100}"' for _ in range(rng.randint(0, 3))]
        moves = ", ".join(moves + ['"0, 0, 0, 0, 300"'] if moves else [])
        leds = ", ".join(f'"{number(1)}, {number(1)}, {number(1)}, 1, {rng.randint(0, 3) * 100}, '
                         f'{rng.randint(4, 10) * 100}"' for _ in range(rng.randint(0, 3)))
        audio = ", ".join(f'"songs/track{rng.randint(0, 99)}.wav, 0, {rng.randint(1, 10) * 500}"'
                          for _ in range(rng.randint(0, 2)))
        comment = f"  % step {i} %" if rng.random() < 0.1 else ""
        out.append(f"    [b#{label}#blk_inst: MV({moves}) LD({leds}) AO({audio})]{comment}\n")
    out.append("    [b#end#blk_terminus]\n")
    return "".join(out)


def waiting_script(actions: int, *, period: int = 500, timeout: int = 30_000) -> str:
    """An activity of `actions` actions of 10 blocks each, 10 actions to a goal (the script
    of `bench_verify.py`): each action prompts, then waits in a loop for a child to come near,
    left when the activity's elapsed time passes the action's deadline (`timeout` ms per
    action, cumulative: the k-th action's is (k + 1) * timeout), then branches forward on
    where the child stands (to the left or in front) before the next action. Every block is
    read in some world and every goal reached; the session ends by a terminus."""
    out = ["[waiting_activity]\n",
           '[alfa:1, guard, "distance=0.5", "", A, U]\n',
           '[omega:1, guard, "", "", R, L]\n']
    for k in range(actions):
        if k % 10 == 0:
            out.append(f"[goal:round{k // 10}]\n")
        deadline = (k + 1) * timeout
        near = "{CLASS #Human U ?kid (B: near(1.0))} ! {TRUE}"
        late = f"{{CLASS #Activity T ?me (?THIS>&elapsedtime OP> {deadline})}} ! {{TRUE}}"
        left = "{CLASS #Human U ?kid (?THIS>&positiontheta OP> 0.3)} ! {TRUE}"
        out += [
            "  [action]\n",
            f'    [b#a{k}#blk_inst: MV() LD("0.2, 0.4, 0.9, 1, 0, {period}") AO()]\n',
            f'    [b#w{k}#blk_inst: MV() LD("0.9, 0.6, 0.3, 1, 0, {period}") AO()]\n',
            f"    [b##blk_jump: CND({near}) TRJMP(c{k}) FLSJMP()]\n",
            f"    [b##blk_jump: CND({late}) TRJMP(t{k}) FLSJMP(w{k})]\n",
            f"    [b#c{k}#blk_jump: CND({left}) TRJMP(l{k}) FLSJMP()]\n",
            '    [b##blk_inst: MV() LD("0.2, 0.8, 0.3, 1, 0, 1000") AO()]\n',
            f"    [b##blk_jump: CND({{TRUE}}) TRJMP(n{k}) FLSJMP()]\n",
            f'    [b#l{k}#blk_inst: MV() LD("0.3, 0.8, 0.2, 1, 0, 700") AO()]\n',
            f'    [b#t{k}#blk_inst: MV() LD("0.1, 0.2, 0.4, 1, 0, {period}") AO()]\n',
            f'    [b#n{k}#blk_sens: "next"]\n',
        ]
    out.append("[goal:closing]\n  [action]\n    [b#end#blk_terminus]\n")
    return "".join(out)
