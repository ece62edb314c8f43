"""One test run, and its result as data (docs/testing.md).

`run_test` runs the session a test describes on programs its caller loaded (`scriptc.ops.test`
loads them as `scriptc run` does, with the repository's functions, rules and robot profile),
asks the session to observe the instants the expectations read, and judges every expectation
(`scriptc.testing.expect`). The result (`TestResult`) is plain data a worker process sends
back whole: the verdicts, the trace, how the session ended, and the `scriptc run` command that
replays the run. Renderers (`scriptc.testing.report`, the CLI) read it; nothing here prints.
"""

from __future__ import annotations

import os
import shlex
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from scriptc.diagnostics.model import Diagnostic
from scriptc.paths import shown_path
from scriptc.robot.profile import Profile
from scriptc.runtime.executor import Loadable
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS, Implementations
from scriptc.runtime.loading import Loader
from scriptc.runtime.robots import Robot
from scriptc.runtime.rules import STANDARD_RULES, RuleLibrary
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Event, Trace
from scriptc.source import SourceFile
from scriptc.testing.expect import Run, Verdict, judge
from scriptc.testing.model import TestFile

__all__ = ["ERROR", "FAILED", "PASSED", "TestResult", "replay_command", "run_test"]

PASSED, FAILED, ERROR = "passed", "failed", "error"


@dataclass(frozen=True, slots=True)
class TestResult:
    """What a test gave: `status` is `passed` (every verdict holds), `failed` (one does not)
    or `error` (it could not run: `reason`, and the diagnostics of the files that stopped it
    in `problems`, each with its source). `time_ms` is the simulated time at the session's
    end, `wall_s` the seconds the test took (its loading included), `events` the trace."""

    __test__ = False  # not a pytest class, despite its name

    path: str
    description: str
    status: str
    replay: str
    time_ms: int | None = None
    outcome: str | None = None
    verdicts: tuple[Verdict, ...] = ()
    events: tuple[Event, ...] = ()
    reason: str = ""
    problems: tuple[tuple[SourceFile, tuple[Diagnostic, ...]], ...] = ()
    wall_s: float = field(default=0.0, compare=False)
    written: tuple[str, ...] = ()  # the files the test wrote (`--update`: its snapshot)

    @property
    def failures(self) -> list[Verdict]:
        return [v for v in self.verdicts if not v.passed]

    def as_dict(self) -> dict[str, Any]:
        """The result as JSON data, without the wall time (the same test gives the same
        data every time) and without the trace (`events`)."""
        data: dict[str, Any] = {"path": self.path, "description": self.description,
                                "status": self.status}
        if self.status == ERROR:
            data["reason"] = self.reason
            data["problems"] = [{"path": source.path, "code": d.code, "message": d.message}
                                for source, diagnostics in self.problems for d in diagnostics]
        else:
            data.update(time_ms=self.time_ms, outcome=self.outcome,
                        verdicts=[v.as_dict() for v in self.verdicts])
        data["replay"] = self.replay
        return data


def replay_command(test: TestFile, governor: bool) -> str:
    """The `scriptc run` command that runs the session of `test` again, from the working
    folder: its scripts, its world (the test file itself for a `[world]` table: `scriptc run
    --world` takes a test file's world), its robot, governor and time limit."""
    words = ["scriptc", "run", *(shown_path(s) for s in test.scripts)]
    if test.world_arg is not None:
        words += ["--world", shown_path(test.world_arg)]
    words += ["--robot", test.robot, "--governor" if governor else "--no-governor",
              "--until", str(test.until)]
    return shlex.join(_posix(w) for w in words)


def _posix(word: str) -> str:
    return word.replace(os.sep, "/") if os.sep != "/" else word


def run_test(test: TestFile, programs: Sequence[Loadable], robot: Robot, *,
             profile: Profile | None = None, loader: Loader | None = None,
             functions: Implementations = STANDARD_IMPLEMENTATIONS,
             rules: RuleLibrary = STANDARD_RULES) -> TestResult:
    """Run the session of `test` over `programs` (the loaded `scripts`, in order) on `robot`,
    governed by `profile` when one is given, and judge its expectations."""
    trace = Trace()
    session = Session(tuple(programs), scenario=test.world, robot=robot, trace=trace, loader=loader,
                      profile=profile, functions=functions, rules=rules)
    result = session.run(test.until, test.instants)
    observed = {state.t: state for state in result.observations}
    run = Run(trace.events, observed, result.final, result.outcome, result.time_ms)
    verdicts = tuple(judge(test.expectations, run))
    return TestResult(test.source.path, test.description,
                      PASSED if all(v.passed for v in verdicts) else FAILED,
                      replay_command(test, profile is not None), result.time_ms,
                      result.outcome, verdicts, tuple(trace.events))
