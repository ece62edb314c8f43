"""The checks' shared tables (`check.context`). The instruction blocks read into numbers
(`read_tracks`, `Context.tracks`): read once, inline for the common texts, it says what the
general readers (`number`, `whole_ms`, the definition of a block's duration) say for any text,
and the passes that take their fast path from it (ranges, safety) find what they find from the
text. A table a pass builds for others (`Context.table`) is built once per script."""

from __future__ import annotations

import random

from hypothesis import example, given
from hypothesis import strategies as st

from scriptc.check.context import (
    CommandRead,
    Context,
    Tracks,
    number,
    read_tracks,
    whole_ms,
)
from scriptc.check.ranges import MAX_TIME, check_values
from scriptc.ir.nodes import (
    Action,
    AudioCommand,
    Goal,
    InstructionBlock,
    LedCommand,
    MoveCommand,
    Name,
    Number,
    Script,
    Text,
)
from scriptc.numbers import MAX_DIGITS, whole_number
from scriptc.source import SourceFile, Span

# Number texts as hand-built IR may hold them (the front end reports most of the odd ones, but
# the checks read whatever they are given): digits around float's exact range and the time
# limit, signs, fractions and exponents, non-ASCII digits, non-finite and non-numbers, hundreds
# of digits, colours around [0, 1].
_NUMBER_TEXTS = st.one_of(
    st.sampled_from(["0", "1", "7", "1000", "007", "+5", "-5", "-0", "+-5", "1e3", "1000.0",
                     "0.5", "1.5", "-0.25", "255", "1e999", "-1e999", "3.5e38", "nan", "inf",
                     "x", "", " 1 ", "\u00b2", "\uff11\uff12", str(MAX_TIME),
                     str(MAX_TIME + 1), "0000000001", "999999999999999", "9999999999999999",
                     "12345678901234567", "1" * 20, "1" * (MAX_DIGITS + 1), "0" * 30 + "1"]),
    st.integers(0, 10**20).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
)
_AT = Span(0, 0)


def _block(moves: list[tuple[str, ...]], leds: list[tuple[str, ...]],
           audios: list[tuple[str, ...]]) -> InstructionBlock:
    def n(text: str) -> Number:
        return Number(text, _AT)

    return InstructionBlock(
        None, tuple(MoveCommand(*map(n, m), _AT) for m in moves),
        tuple(LedCommand(*map(n, led), _AT) for led in leds),
        tuple(AudioCommand(Text("a.wav", _AT), *map(n, a), _AT) for a in audios), _AT)


def _reference_duration(block: InstructionBlock) -> int | None:
    """How long a block runs, from its definition: the longest track, each the sum of its
    commands' `wait_t` and `duration`; None when a time is not written as a whole number."""
    longest = 0
    for track in (block.moves, block.leds, block.audios):
        total = 0
        for command in track:
            times = (command.wait_t, command.duration)
            if not all(t.is_integer_text for t in times):
                return None
            wait, duration = (whole_number(t.text) for t in times)
            if wait is None or duration is None:
                return None
            total += wait + duration
        longest = max(longest, total)
    return longest


def _floats(numbers: tuple[Number, ...]) -> tuple[float, ...] | None:
    try:
        return tuple(float(n.text) for n in numbers)
    except ValueError:
        return None


BLOCKS = st.builds(_block, st.lists(st.tuples(*[_NUMBER_TEXTS] * 5), max_size=3),
                   st.lists(st.tuples(*[_NUMBER_TEXTS] * 6), max_size=3),
                   st.lists(st.tuples(*[_NUMBER_TEXTS] * 2), max_size=2))


@given(BLOCKS)
@example(_block([("1", "0", "0", "\uff11", "\uff12")], [("inf", "0", "0", "1", "0", "5"),
                                                       ("0", "-1", "inf", "1", "0", "5")], []))
@example(_block([("0", "0", "0", "12345678901234567", "0")],
                [("0", "nan", "0.5", " 1", "0", "5"), ("x", "0", "1", "1", "0", "5")],
                [("0", "-5")]))
def test_a_block_s_tracks_are_read_as_each_number_reads(block: InstructionBlock) -> None:
    tracks = read_tracks(block)
    assert tracks.block is block
    assert tracks.duration == _reference_duration(block)
    times = [t for track in (block.moves, block.leds, block.audios) for c in track
             for t in (c.wait_t.text, c.duration.text)]
    assert tracks.plain == all(t.isascii() and t.isdigit() and len(t) < 16 for t in times)
    velocities = [tuple(number(v) for v in (m.v_x, m.v_y, m.v_theta)) for m in block.moves]
    assert tracks.moves == [(None if None in v else v, whole_ms(m.wait_t), whole_ms(m.duration))
                            for v, m in zip(velocities, block.moves, strict=True)]
    leds = [(_floats((led.r, led.g, led.b)),
             led.turnas.text.strip() == "1" and any((number(c) or 0) > 0
                                                    for c in (led.r, led.g, led.b)),
             whole_ms(led.wait_t), whole_ms(led.duration)) for led in block.leds]
    assert repr(tracks.leds) == repr(leds)  # (a colour may hold a NaN, unequal to itself)


def _one_field_apart() -> list[InstructionBlock]:
    """A block, then a block for each field of each command with that field alone changed."""
    move, led, audio = ["0", "0", "0", "0", "5"], ["1", "0", "0", "0", "0", "5"], ["0", "50"]
    blocks = [_block([tuple(move)], [tuple(led)], [tuple(audio)])]
    for fields, at in ((move, 0), (led, 1), (audio, 2)):
        for i in range(len(fields)):
            changed = [*fields[:i], "1" if fields[i] != "1" else "0", *fields[i + 1:]]
            tracks = [[tuple(move)], [tuple(led)], [tuple(audio)]]
            tracks[at] = [tuple(changed)]
            blocks.append(_block(*tracks))
    return blocks


@given(st.lists(BLOCKS, min_size=1, max_size=4), st.randoms(use_true_random=False))
@example(_one_field_apart(), random.Random(0))
def test_commands_read_once_per_script_read_as_each_alone(blocks: list[InstructionBlock],
                                                           rng: random.Random) -> None:
    """`Context.tracks` reads each distinct command once (`read_tracks`' `seen`): blocks that
    repeat commands, in any order, read as each block read on its own."""
    blocks = blocks + [rng.choice(blocks) for _ in blocks]  # repeated commands
    seen: dict[tuple[str, ...], CommandRead] = {}
    shared = [read_tracks(block, seen) for block in blocks]
    alone = [read_tracks(block) for block in blocks]
    assert repr([(t.moves, t.leds, t.duration, t.plain) for t in shared]) == \
        repr([(t.moves, t.leds, t.duration, t.plain) for t in alone])


def _slow(tracks: Tracks | None) -> Tracks | None:
    """The same block as if none of its numbers had been read: every check reads the text."""
    if tracks is None:
        return None
    return Tracks(tracks.block, [(None, None, None) for _ in tracks.moves],
                  [(None, False, None, None) for _ in tracks.leds], None, False)


@given(st.lists(BLOCKS, min_size=1, max_size=3))
@example([_block([("1e999", "3.5e38", "0", str(MAX_TIME + 1), "-5")],
                 [("1.5", "255", "-0.25", "2", "1e3", "1000.0")], [("0000000001", "+5")])])
@example([_block([("0", "0", "3.5e38", str(MAX_TIME + 1), "0")], [], []),  # plain, too long
          _block([("0", "0", "0", "-5", "10")], [("0", "1.5", "0", "1", "0", "5")], []),
          _block([], [("0", "0", "-1", "1", "0", "5")], [("+5", "5")])])
def test_the_values_pass_finds_from_the_table_what_it_finds_from_the_text(
        blocks: list[InstructionBlock]) -> None:
    """V003-V006 of instruction blocks: the values pass skips a command whose numbers the
    table read as within range, and a block whose times are all plain and short: it finds
    what it finds reading every number's text."""
    script = Script(Name("s", _AT), (), (),
                    (Goal(Name("g", _AT), (Action(tuple(blocks), _AT),), _AT),), _AT)
    source = SourceFile("s.script", "")
    fast = Context(script, source)
    slow = Context(script, source)
    slow.tracks = [_slow(t) for t in fast.tracks]  # (`tracks` is computed once, then kept)
    assert check_values(fast) == check_values(slow)


def test_a_table_is_built_once_per_script_by_its_builder() -> None:
    script = Script(Name("s", _AT), (), (), (), _AT)
    ctx, other = Context(script, SourceFile("s.script", "")), Context(script, SourceFile("t", ""))
    built: list[Context] = []

    def build(c: Context) -> list[Context]:
        built.append(c)
        return [c]

    def nothing(c: Context) -> None:
        built.append(c)

    assert ctx.table(build) is ctx.table(build) == [ctx] and built == [ctx]
    assert other.table(build) == [other] and built == [ctx, other]
    assert ctx.table(nothing) is None and ctx.table(nothing) is None  # (None is a table too)
    assert built == [ctx, other, ctx]
