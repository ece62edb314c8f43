"""What every job of a session shares: the instant under way, whether the session is over and
how, and the problems it reports.

Problems are `error` events in the trace (`code`, `message`, `fatal`). Their codes are the
run-time codes of the one registry (`scriptc.diagnostics.codes`, family X: `scriptc explain
mutex-misuse` explains each); the trace carries the code's name, and the names below are
checked against the registry when this module is imported, so the runtime cannot write a code
`explain` does not know. A fatal problem ends the session (`RunStatus.fatal`): whatever the
actuators run stops at once (`on_fatal`), the outcome is `error`.
"""

from __future__ import annotations

from collections.abc import Callable

from scriptc.diagnostics.codes import run_time_name
from scriptc.runtime.trace import Trace

# The run-time codes, by the name the trace writes (docs/diagnostics.md, family X).
MUTEX_MISUSE = run_time_name("mutex-misuse")
UNKNOWN_RULECODE = run_time_name("unknown-rulecode")
RULE = run_time_name("rule")
FUNCTION = run_time_name("function")
OVERRIDE = run_time_name("override")
SCRIPT_VECT = run_time_name("script_vect")
UPDATE = run_time_name("update")
NO_PROGRESS = run_time_name("no-progress")
READ = run_time_name("read")
ROBOT_UNSTABLE = run_time_name("robot-unstable")


class RunStatus:
    """The session's clock hand (`now`: the instant under way, in ms), its end (`done`, and
    `outcome`: `completed`, `until`, `stalled`, `error` or `interrupted`), and its problems."""

    __slots__ = ("done", "now", "on_fatal", "outcome", "trace")

    def __init__(self, trace: Trace, on_fatal: Callable[[int], None] | None = None) -> None:
        self.trace = trace
        self.now = 0
        self.done = False
        self.outcome = ""
        self.on_fatal = on_fatal  # called at a fatal problem, before the session ends

    def report(self, now: int, code: str, message: str) -> None:
        """A problem the run goes on after (a warning in `scriptc run`'s summary)."""
        self.trace.emit(now, "error", code=code, message=message, fatal=False)

    def fatal(self, now: int, code: str, message: str) -> None:
        """A problem that ends the session: reported, the actuators stopped, outcome `error`."""
        self.trace.emit(now, "error", code=code, message=message, fatal=True)
        if self.on_fatal is not None:
            self.on_fatal(now)
        self.finish("error")

    def finish(self, outcome: str) -> None:
        """The session is over (no other instant will run)."""
        self.done = True
        self.outcome = outcome
