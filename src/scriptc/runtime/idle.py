"""The built-in `idle_activity` (thesis 3.2): what the robot does when no script is queued.

A passive loop that never ends on its own: the wheels stay still (an idle robot must never
move by itself near a child), the LEDs breathe a dim blue (2 s on, 1 s off) so the robot does
not look switched off, and the speaker is silent. It has no rule messages, so loading it
completes a hand-over (see docs/runtime.md "The mutex"). The session leaves it as soon as a
real script is queued (loop step 6), stopping its block wherever it is. A file can replace it
(`Session(idle=...)`).
"""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING

from scriptc.ir import nodes as ir
from scriptc.source import Span

if TYPE_CHECKING:
    from scriptc.runtime.interp import IRProgram

IDLE_NAME = "idle_activity"

# The idle activity is built here as IR, not read from script text: the run time runs programs
# and reads no script (a bytecode file runs without the syntax stage). Its script text, which
# `scriptc.emit.script.format_script(idle_script())` prints, is what tests lint:
#
#     [idle_activity]
#     [goal:idle]
#       [action]
#         [b#breathe#blk_inst: MV() LD("0, 0, 0.3, 1, 0, 2000", "0, 0, 0, 0, 1000, 0") AO()]
#         [b##blk_jump: CND(! {TRUE}) TRJMP(breathe) FLSJMP()]
#
# It has no source: every span is the empty span at 0.
_NOWHERE = Span(0, 0)
# The LEDs' commands, (r, g, b, turnas, wait_t, duration): dim blue for 2 s, then off for 1 s.
_BREATH = (("0", "0", "0.3", "1", "0", "2000"), ("0", "0", "0", "0", "1000", "0"))


def _name(text: str) -> ir.Name:
    return ir.Name(text, _NOWHERE)


def _led(fields: tuple[str, str, str, str, str, str]) -> ir.LedCommand:
    r, g, b, turnas, wait_t, duration = (ir.Number(text, _NOWHERE) for text in fields)
    return ir.LedCommand(r, g, b, turnas, wait_t, duration, _NOWHERE)


@cache
def idle_script() -> ir.Script:
    """The IR of `idle_activity`: one instruction block that breathes, and a jump back to it."""
    breathe = ir.InstructionBlock(_name("breathe"), (), tuple(_led(f) for f in _BREATH), (),
                                  _NOWHERE)
    always = ir.Condition((), (ir.TrueEvaluation(_NOWHERE),), _NOWHERE)
    back = ir.JumpBlock(None, always, _name("breathe"), None, _NOWHERE, "! {TRUE}")
    action = ir.Action((breathe, back), _NOWHERE)
    goal = ir.Goal(_name("idle"), (action,), _NOWHERE)
    return ir.Script(_name(IDLE_NAME), (), (), (goal,), _NOWHERE)


@cache
def idle_program() -> IRProgram:
    """The built-in idle program (an `IRProgram`; its path is empty)."""
    from scriptc.runtime.interp import IRProgram

    return IRProgram(idle_script(), "")
