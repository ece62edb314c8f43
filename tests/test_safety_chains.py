"""K002 along the control flow (check/safety.py, `_Timeline`): LEDs flashing too fast across
chains of blocks and jump cycles. The case files are tests/cases/safety/chain_*.script; here:
the check against a brute-force oracle on small random block graphs (every path, every
one-second window), that it terminates on any graph, and that it stays linear on long
scripts."""

from __future__ import annotations

import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scripts

from scriptc.analysis.analyze import analyze_script
from scriptc.check.context import Context
from scriptc.check.safety import check_safety
from scriptc.source import SourceFile

FAST = settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
LIMIT = 3  # the default profile's max-led-flash-rate

# -- small random block graphs -------------------------------------------------------------

LEDS = st.tuples(
    st.sampled_from(["1, 0, 0", "1, 0, 0", "0, 1, 0", "0, 0, 0"]),  # black is off
    st.sampled_from([1, 1, 1, 0]),  # turnas
    st.sampled_from([0, 0, 50, 100, 150]),  # wait_t
    st.sampled_from([0, 50, 100, 100, 150, 300]),  # duration
)
INST = st.tuples(st.just("inst"), st.lists(LEDS, max_size=4),
                 st.sampled_from([0, 0, 100, 150, 250, 400]))  # the audio track's length
JUMP = st.tuples(st.just("jump"), st.integers(-1, 7), st.integers(-1, 7), st.booleans())
BLOCKS = st.one_of(INST, INST, INST, JUMP, JUMP, st.just(("sens",)), st.just(("terminus",)))


def render(blocks) -> str:
    n = len(blocks)
    lines = ["[g]", "[goal:g]", "[action]"]
    for i, b in enumerate(blocks):
        if b[0] == "inst":
            leds = ", ".join(f'"{c}, {t}, {w}, {d}"' for c, t, w, d in b[1])
            audio = f'"Silence, 0, {b[2]}"' if b[2] else ""
            lines.append(f"[b#l{i}#blk_inst: MV() LD({leds}) AO({audio})]")
        elif b[0] == "jump":
            t = f"l{b[1] % n}" if b[1] >= 0 else ""
            f = f"l{b[2] % n}" if b[2] >= 0 else ""
            cond = "{TRUE}" if b[3] and b[1] % 3 == 0 else "! {E: gt(1, 2)}"
            lines.append(f"[b#l{i}#blk_jump: CND({cond}) TRJMP({t}) FLSJMP({f})]")
        elif b[0] == "sens":
            lines.append(f'[b#l{i}#blk_sens: "x"]')
        else:
            lines.append(f"[b#l{i}#blk_terminus]")
    return "\n".join(lines) + "\n"


def track(leds):
    """(duration of the LED track, onsets entering dark, lit at the track's end), the rule of
    docs/robot.md written out again: dark at the start and between commands unless the next
    command lights at once."""
    t, lit, onsets = 0, False, []
    for colour, turnas, wait, duration in leds:
        t += wait
        if wait:
            lit = False
        on = turnas == 1 and duration > 0 and colour != "0, 0, 0"
        if on and not lit:
            onsets.append(t)
        lit = on
        t += duration
    return t, onsets, lit


def oracle(blocks) -> bool:
    """Whether some path flashes more than LIMIT times within one second: every path from
    every onset, walked block by block."""
    n = len(blocks)
    timed = {}
    for i, b in enumerate(blocks):
        if b[0] == "inst":
            length, onsets, lit = track(b[1])
            duration = max(length, b[2])
            if duration:
                timed[i] = (duration, onsets, lit and length == duration)

    def successors(i):
        b = blocks[i]
        if b[0] == "terminus":
            return []
        if b[0] != "jump":
            return [i + 1] if i + 1 < n else []
        out = [b[1] % n if b[1] >= 0 else i + 1]
        if not (b[3] and b[1] % 3 == 0):
            out.append(b[2] % n if b[2] >= 0 else i + 1)
        return [w for w in out if w < n]

    def next_timed(starts):
        found, seen, todo = [], set(), list(starts)
        while todo:
            v = todo.pop()
            if v in seen:
                continue
            seen.add(v)
            if v in timed:
                found.append(v)
            else:
                todo.extend(successors(v))
        return found

    # entered lit only: only lit-ended blocks lead there, and not the script's start
    dark = set(next_timed([0]))
    lit_in = set()
    for i, (_, _, ends) in timed.items():
        (lit_in if ends else dark).update(next_timed(successors(i)))

    def most(block, elapsed, entered_lit, horizon):
        """The most onsets before `horizon` from `elapsed` (the block's start) on."""
        duration, onsets, ends = timed[block]
        count = sum(1 for k, t in enumerate(onsets)
                    if elapsed + t < horizon and not (k == 0 and t == 0 and entered_lit))
        if elapsed + duration >= horizon:
            return count
        return count + max((most(e, elapsed + duration, ends and timed[e][1][:1] == [0], horizon)
                            for e in next_timed(successors(block))), default=0)

    for b, (_duration, onsets, _ends) in timed.items():
        for x in onsets:
            if x == 0 and b in lit_in and b not in dark:
                continue
            if most(b, -x, False, 1000) - sum(1 for t in onsets if t < x) > LIMIT:
                return True
    return False


def k002(text: str) -> list:
    analysis = analyze_script(SourceFile("g.script", text))
    assert analysis.script is not None, analysis.diagnostics
    return [d for d in check_safety(Context(analysis.script, analysis.source)) if d.code == "K002"]


@pytest.mark.slow
@FAST
@given(st.lists(BLOCKS, min_size=2, max_size=7))
def test_the_check_agrees_with_every_path(blocks) -> None:
    text = render(blocks)
    found = k002(text)
    assert bool(found) == oracle(blocks), text
    commands = [d.span for d in found]
    assert len(commands) == len(set(commands)), "one report per LED command at most"


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scripts())
def test_the_check_ends_on_any_script(text: str) -> None:
    analysis = analyze_script(SourceFile("gen.script", text))
    if analysis.script is not None:
        check_safety(Context(analysis.script, analysis.source))


# -- examples and sizes ----------------------------------------------------------------------


def loop(*blocks: str, back: str = "a") -> str:
    body = "\n".join(blocks)
    return (f"[s]\n[goal:g]\n[action]\n{body}\n"
            f"[b##blk_jump: CND(! {{E: gt(1, 2)}}) TRJMP(end) FLSJMP({back})]\n"
            "[b#end#blk_terminus]\n")


def test_a_lit_block_and_a_dark_block_in_a_loop() -> None:
    lit = '[b#a#blk_inst: MV() LD("1, 0, 0, 1, 0, {0}") AO()]'
    dark = '[b#b#blk_inst: MV() LD() AO("Silence, 0, {0}")]'
    # 5 Hz: reported once, at the lit block's command, with the jump that chains them
    found = k002(loop(lit.format(100), dark.format(100)))
    assert len(found) == 1 and "across blocks `a` and `b`" in found[0].message
    assert [label.message for label in found[0].labels] == ["this jump may go back to `a`"]
    assert any("about 5 a second" in note for note in found[0].notes)
    # 1 Hz, and exactly 3 Hz (4 flashes only 1000 ms apart: not within one second)
    assert k002(loop(lit.format(500), dark.format(500))) == []
    assert k002(loop(lit.format(150), dark.format(184))) == []
    assert len(k002(loop(lit.format(150), dark.format(183)))) == 1


def test_a_light_kept_on_across_blocks_does_not_flash() -> None:
    red = '[b#a#blk_inst: MV() LD("1, 0, 0, 1, 0, 100") AO()]'
    blue = '[b#b#blk_inst: MV() LD("0, 0, 1, 1, 0, 100") AO()]'
    assert k002(loop(red, blue)) == []
    # a gap of 1 ms at the seam is a flash at every pass: 5 a second
    gap = '[b#b#blk_inst: MV() LD("0, 0, 1, 1, 1, 99") AO()]'
    assert len(k002(loop(red, gap))) == 1


def test_a_cycle_of_blocks_that_take_no_time_ends() -> None:
    text = loop('[b#a#blk_inst: MV() LD("1, 0, 0, 1, 0, 0") AO()]', '[b##blk_sens: "x"]')
    assert k002(text) == []


@pytest.mark.slow
def test_a_long_flashing_chain_is_reported_once_per_second() -> None:
    """10,000 blocks of 10 ms, each lit 5 ms (100 Hz): one report per second of blocks, and
    fast."""
    blocks = ['[b##blk_inst: MV() LD("1, 0, 0, 1, 0, 5") AO("Silence, 0, 10")]'] * 10_000
    text = "[s]\n[goal:g]\n[action]\n" + "\n".join(blocks) + "\n[b##blk_terminus]\n"
    analysis = analyze_script(SourceFile("long.script", text))
    ctx = Context(analysis.script, analysis.source)
    start = time.process_time()
    found = [d for d in check_safety(ctx) if d.code == "K002"]
    elapsed = time.process_time() - start
    assert len(found) == 100
    assert elapsed < 5, elapsed  # about 0.2 s on the reference machine


@pytest.mark.slow
def test_a_branching_ladder_stays_linear() -> None:
    """Short blocks with a flash every 12th and jumps skipping up to 5 ahead: the fastest
    path is found without following every path."""
    lines = []
    n = 4000
    for i in range(n):
        leds = '"1, 0, 0, 1, 0, 10"' if i % 12 == 0 else ""
        lines.append(f'[b#i{i}#blk_inst: MV() LD({leds}) AO("Silence, 0, {20 + i % 21}")]')
        lines.append(f"[b##blk_jump: CND(! {{E: gt(1, 2)}}) TRJMP(i{min(n - 1, i + 1 + i % 5)}) "
                     "FLSJMP()]")
    text = "[s]\n[goal:g]\n[action]\n" + "\n".join(lines) + "\n[b##blk_terminus]\n"
    analysis = analyze_script(SourceFile("ladder.script", text))
    ctx = Context(analysis.script, analysis.source)
    start = time.process_time()
    found = [d for d in check_safety(ctx) if d.code == "K002"]
    assert found and time.process_time() - start < 5


def test_a_spent_budget_still_reports(monkeypatch) -> None:
    """Past the budget of work, searches stop early (16 blocks), and the reports found are
    still whole: the case files give the same diagnostics."""
    from harness import CASES

    import scriptc.check.safety as safety

    for path in sorted((CASES / "safety").glob("chain_*.script")):
        text = path.read_text(encoding="utf-8")
        expected = [(d.span, d.message) for d in k002(text)]
        monkeypatch.setattr(safety, "_WORK_BASE", 0)
        monkeypatch.setattr(safety, "_WORK_PER_BLOCK", 0)
        assert [(d.span, d.message) for d in k002(text)] == expected, path.name
        monkeypatch.undo()


# -- the check and the run-time governor agree -------------------------------------------------


@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(BLOCKS, min_size=2, max_size=7))
def test_what_k002_lets_through_the_governor_never_holds(blocks) -> None:
    """Both count onsets in one-second windows the same way, and K002 follows every path the
    run could take: a script K002 accepts runs without a held LED onset."""
    from scriptc.robot.profile import DEFAULT_PROFILE
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.session import Session
    from scriptc.runtime.trace import Trace

    text = render(blocks)
    analysis = analyze_script(SourceFile("g.script", text))
    if not analysis.ok:  # K002 or another error: nothing to run
        return
    trace = Trace()
    Session([IRProgram(analysis.script, "g.script")], robot="kinematic", trace=trace,
            profile=DEFAULT_PROFILE).run(20_000)
    held = [e for e in trace.events
            if e["event"] == "governor" and "led-flash" in e["reasons"]]
    assert held == [], text
