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

IDLE_NAME = "idle_activity"

IDLE_TEXT = """\
[idle_activity]
[goal:idle]
  [action]
    [b#breathe#blk_inst: MV() LD("0, 0, 0.3, 1, 0, 2000", "0, 0, 0, 0, 1000, 0") AO()]
    [b##blk_jump: CND(! {TRUE}) TRJMP(breathe) FLSJMP()]
"""


@cache
def idle_program():
    """The built-in idle program (an `IRProgram`; its path is empty)."""
    from scriptc.frontend.script import lower_script
    from scriptc.runtime.interp import IRProgram
    from scriptc.source import SourceFile

    script, problems = lower_script(SourceFile("<idle_activity>", IDLE_TEXT))
    assert script is not None and not problems, problems
    return IRProgram(script, "")
