"""What every semantic pass reads: the script, its source, the function registry, and tables
built once per script (blocks in execution order, the label table, each instruction block's
tracks read into numbers and how long the block runs) so that no pass loops over the script
more than a few times, nor reads a number's text twice (a 10,000-block script must check in
well under 0.3 s).

Also small helpers the passes share: the span of a block's head, a line's indentation (for
fixes that insert a line) and did-you-mean suggestions.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import cached_property
from typing import Any, TypeVar

from scriptc.diagnostics.model import Fix, TextEdit
from scriptc.ir.builtins import STANDARD, FunctionRegistry
from scriptc.ir.nodes import (
    Block,
    Command,
    InstructionBlock,
    JumpBlock,
    LedCommand,
    MoveCommand,
    Name,
    Number,
    Script,
)
from scriptc.numbers import whole_number
from scriptc.robot.motion import Velocity
from scriptc.robot.profile import DEFAULT_PROFILE, Profile
from scriptc.source import SourceFile, SourceKind, Span

_Table = TypeVar("_Table")


@dataclass(frozen=True, slots=True)
class LabelTable:
    """Non-empty labels of a script. `index` maps a label to the position (in execution
    order) of the FIRST block carrying it: a jump to a duplicated label (L001) goes there,
    which is what a reader scanning the script top-down would assume."""

    index: dict[str, int]
    names: dict[str, Name]  # the first definition of each label
    duplicates: tuple[tuple[Name, Name], ...]  # (later definition, first definition)


def number(n: Number) -> float | None:
    """The number, or None when it is not a finite one (V002/V003 report those)."""
    try:
        v = float(n.text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def whole_ms(n: Number) -> int | None:
    """A time as whole milliseconds, or None (V006 reports the others)."""
    v = number(n)
    return int(v) if v is not None and v >= 0 and v == int(v) else None


# A move command read (`Tracks.moves`): its velocity (v_x, v_y, v_theta), None unless all three
# are finite numbers, then its `wait_t` and `duration` as whole milliseconds (`whole_ms`).
MoveRead = tuple[Velocity | None, int | None, int | None]
# An LED command read (`Tracks.leds`): its colour (r, g, b) as `float` reads each channel,
# None when one is not a number at all; whether it lights (`turnas` 1 and some channel a finite
# number above 0, whatever its duration); its `wait_t` and `duration` as whole milliseconds.
LedRead = tuple[tuple[float, float, float] | None, bool, int | None, int | None]


class Tracks:
    """An instruction block's tracks read into numbers (`Context.tracks`): `moves[i]` and
    `leds[i]` are the i-th move and LED commands of `block` read; `duration` is how long the
    block runs: its three tracks start together and each runs its commands one after the
    other, `wait_t` then `duration` (docs/runtime.md), so the block lasts as long as its
    longest track; None when a time is not a whole number written as one (digits and a sign,
    no fraction or exponent: V006 says how to write it), or has hundreds of digits (V003).
    `plain` is True when every time of the block is a few ASCII digits (under 16: no sign,
    fraction or exponent), as nearly every time is."""

    __slots__ = ("block", "duration", "leds", "moves", "plain")

    def __init__(self, block: InstructionBlock, moves: list[MoveRead], leds: list[LedRead],
                 duration: int | None, plain: bool) -> None:
        self.block, self.moves, self.leds = block, moves, leds
        self.duration, self.plain = duration, plain


# A command read (`read_command`): its MoveRead or LedRead (None for an audio command), the
# sum of its `wait_t` and `duration` when both are written as whole numbers (else None), and
# whether both are plain (a few ASCII digits: `Tracks.plain`).
CommandRead = tuple[MoveRead | LedRead | None, int | None, bool]


def read_command(command: Command) -> CommandRead:
    """One command read into numbers (`CommandRead`): the common texts (a few ASCII digits; a
    finite decimal) inline, the others by `whole_ms`, `number` and `whole_number`."""
    w, d = command.wait_t.text, command.duration.text
    wait: int | None
    duration: int | None
    exact: int | None
    # (under 16 digits, float() is exact: `whole_ms` and `whole_number` agree)
    plain = (w.isdigit() and d.isdigit() and len(w) < 16 and len(d) < 16 and w.isascii()
             and d.isascii())
    if plain:
        wait, duration = int(w), int(d)
        exact = wait + duration
    else:
        wait, duration = whole_ms(command.wait_t), whole_ms(command.duration)
        whole = (whole_number(w), whole_number(d)) if (
            command.wait_t.is_integer_text and command.duration.is_integer_text) else None
        exact = None if whole is None or whole[0] is None or whole[1] is None \
            else whole[0] + whole[1]
    if isinstance(command, MoveCommand):
        velocity: Velocity | None
        try:
            velocity = (float(command.v_x.text), float(command.v_y.text),
                        float(command.v_theta.text))
        except ValueError:
            velocity = None
        if velocity is not None and not (math.isfinite(velocity[0])
                                         and math.isfinite(velocity[1])
                                         and math.isfinite(velocity[2])):
            velocity = None
        return (velocity, wait, duration), exact, plain
    if isinstance(command, LedCommand):
        colour: tuple[float, float, float] | None
        try:
            colour = (float(command.r.text), float(command.g.text), float(command.b.text))
        except ValueError:
            colour = None
        lights = command.turnas.text.strip() == "1" and (
            any((number(c) or 0) > 0 for c in (command.r, command.g, command.b))
            if colour is None else  # (finite and above 0: `number`)
            0.0 < colour[0] < math.inf or 0.0 < colour[1] < math.inf
            or 0.0 < colour[2] < math.inf)
        return (colour, lights, wait, duration), exact, plain
    return None, exact, plain


def read_tracks(block: InstructionBlock,
                seen: dict[tuple[str, ...], CommandRead] | None = None) -> Tracks:
    """The block's tracks read (`Tracks`), each command by `read_command`. `seen` holds the
    commands read so far, by their texts (`MoveCommand.texts`): a script repeats its commands
    (a still move, the LEDs off, the same times), and a 1 MB script holds some 100,000
    numbers."""
    if seen is None:
        seen = {}
    moves: list[MoveRead] = []
    leds: list[LedRead] = []
    longest: int | None = 0
    plain = True
    for track in (block.moves, block.leds, block.audios):
        total: int | None = 0
        for command in track:
            texts = command.texts
            found = seen.get(texts)
            if found is None:
                found = seen[texts] = read_command(command)
            read, exact, plain_times = found
            plain = plain and plain_times
            total = None if total is None or exact is None else total + exact
            if read is None:
                continue  # an audio command: its times only
            if len(read) == 3:  # (a move reads as three values, an LED command as four)
                moves.append(read)
            else:
                leds.append(read)
        if total is None:
            longest = None
        elif longest is not None and total > longest:
            longest = total
    return Tracks(block, moves, leds, longest, plain)


class Context:
    """The input of every pass. Cheap to build; tables are computed on first use."""

    def __init__(
        self, script: Script, source: SourceFile, functions: FunctionRegistry = STANDARD,
        profile: Profile | None = None, kind: SourceKind = SourceKind.SCRIPT,
    ) -> None:
        self.script = script
        self.source = source
        self.functions = functions
        # "script" or "json": fixes are text edits in script syntax, so JSON sources get none.
        self.is_script_syntax = kind == SourceKind.SCRIPT
        self.profile = profile if profile is not None else DEFAULT_PROFILE
        self._tables: dict[Callable[[Context], Any], Any] = {}

    def table(self, build: Callable[[Context], _Table]) -> _Table:
        """`build(self)`, built once per script: a table that a pass builds and other passes
        read too (the control flow's successors, `flow.successors`; the next blocks that take
        time, `ramps.NextTimed`). One entry per builder."""
        found: _Table
        if build in self._tables:
            found = self._tables[build]
        else:
            found = self._tables[build] = build(self)
        return found

    @cached_property
    def addressed_blocks(self) -> list[tuple[tuple[int, int, int], Block]]:
        """Every block with its (goal, action, block) address, in execution order."""
        return self.script.blocks()

    @cached_property
    def blocks(self) -> list[Block]:
        return [block for _, block in self.addressed_blocks]

    @cached_property
    def labels(self) -> LabelTable:
        index: dict[str, int] = {}
        names: dict[str, Name] = {}
        duplicates: list[tuple[Name, Name]] = []
        for i, block in enumerate(self.blocks):
            label = block.label
            if label is None or not label.text:
                continue
            first = names.get(label.text)
            if first is None:
                index[label.text] = i
                names[label.text] = label
            else:
                duplicates.append((label, first))
        return LabelTable(index, names, tuple(duplicates))

    @cached_property
    def tracks(self) -> list[Tracks | None]:
        """Each block's tracks read into numbers, in execution order (`read_tracks`; None for
        a block that is not an instruction block). Read once: safety (K001, K002), its ramps
        (K003) and `durations` read them."""
        seen: dict[tuple[str, ...], CommandRead] = {}  # (bounded by the script)
        return [read_tracks(b, seen) if isinstance(b, InstructionBlock) else None
                for b in self.blocks]

    @cached_property
    def durations(self) -> list[int | None]:
        """How long each block runs, in execution order: an instruction block's
        `Tracks.duration` (None when a time is not a whole number), 0 for the other blocks,
        which take no time. Flow (F002) and safety (K002, K003) read it."""
        return [0 if t is None else t.duration for t in self.tracks]

    @cached_property
    def jumps(self) -> list[tuple[int, JumpBlock]]:
        return [(i, b) for i, b in enumerate(self.blocks) if isinstance(b, JumpBlock)]

    # -- presentation helpers -----------------------------------------------------------

    def block_head(self, block: Block) -> Span:
        """The span of `[b#LABEL#blk_KIND`: short, and names the block. Falls back to the
        whole block when the text there is not script syntax (IR read from thesis JSON)."""
        text = self.source.text
        start, end = block.span.start, block.span.end
        if not text.startswith("[", start):
            # Thesis JSON: the block's span starts at its key (`"blk3"`), which names it.
            if text.startswith('"', start):
                close = text.find('"', start + 1, end)
                if close != -1:
                    return Span(start, close + 1)
            return block.span
        # Search after the label, which may itself contain `blk_`.
        after = block.label.span.end if block.label is not None else start
        i = text.find("blk_", after, end)
        if i < 0:
            return block.span
        j = i + 4
        while j < end and (text[j].isalnum() or text[j] == "_"):
            j += 1
        return Span(start, j)

    def indent_at(self, offset: int) -> str:
        """The indentation of the line holding `offset`."""
        line = self.source.line_starts[self.source.line_of(offset)]
        text = self.source.text
        j = line
        while j < len(text) and text[j] in " \t":
            j += 1
        return text[line:j]

    @cached_property
    def newline(self) -> str:
        """The line break inserted lines use: the file's own (CRLF files stay CRLF)."""
        return "\r\n" if "\r\n" in self.source.text else "\n"

    def text_of(self, span: Span) -> str:
        return self.source.text[span.start : span.end]


def suggestion(ctx: Context, best: str | None, what: str, span: Span, replacement: str | None,
               verb: str, otherwise: str) -> tuple[str, Fix | None]:
    """The help line and (for script syntax) the fix of a did-you-mean: `best` is the closest
    candidate or None, `what` names it ("a label"), `replacement` is the text that replaces
    `span` (None: `best` itself), `verb` words the fix ("jump to"), `otherwise` is the help
    when nothing is close."""
    if best is None:
        return otherwise, None
    help = f"{what} with a similar name exists: `{best}`"
    if not ctx.is_script_syntax:
        return help, None
    new = best if replacement is None else replacement
    return help, Fix(f"{verb} `{best}`", (TextEdit(span, new),), safe=False)


def closest(word: str, candidates: Iterable[str], *, cutoff: float = 0.6) -> str | None:
    """The candidate most like `word`: an exact match ignoring case first, then difflib's
    best ratio above `cutoff`. difflib is imported here so `import scriptc.check` stays cheap."""
    lowered = word.lower()
    pool = list(candidates)
    for c in pool:
        if c.lower() == lowered:
            return c
    import difflib

    matches = difflib.get_close_matches(word, pool, n=1, cutoff=cutoff)
    return matches[0] if matches else None


def code_list(items: Iterable[object]) -> str:
    """`a`, `b` and `c`."""
    quoted = [f"`{i}`" for i in items]
    if not quoted:
        return "none"
    if len(quoted) == 1:
        return quoted[0]
    return ", ".join(quoted[:-1]) + " and " + quoted[-1]
