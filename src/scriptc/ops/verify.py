"""`scriptc verify` as library calls: each script read and checked as `scriptc run` reads it,
explored (`scriptc.verify`), and the runs that show what was found written as scenario files
(docs/verify.md).

A script with errors, or whose configuration has an error, is not explored (its problems are
reported as `run` reports them). The scenario files go to the folder `counterexamples`
(`scriptc-verify/` by default), one per violation and per witness asked, named
`SCRIPT.PROPERTY.world.json` (`approach.no-stall.world.json`, `approach.slowest.world.json`,
`approach.goal-child_welcomed.world.json`), written only when the replay confirmed them.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from scriptc import interrupt
from scriptc.analysis.analyze import Analysis
from scriptc.analysis.read import ReadError
from scriptc.diagnostics.model import has_errors
from scriptc.numbers import json_dumps
from scriptc.ops.build import read_configured
from scriptc.ops.programs import Refused, checked_program
from scriptc.paths import shown_path
from scriptc.project.files import discover
from scriptc.project.setup import Setup, setup_for
from scriptc.source import SourceKind
from scriptc.writing import write_file

if TYPE_CHECKING:
    from scriptc.ide.answers import VerifyOverview
    from scriptc.verify.verdicts import Verification, Witness

__all__ = ["DEFAULT_FOLDER", "FileVerification", "VerifyOptions", "VerifyRun", "overview",
           "verify_file", "verify_paths"]

DEFAULT_FOLDER = "scriptc-verify"
# The exploration's bound in the editor, where a verification runs in the background after
# each pause in typing (the command line's is verify's MAX_RECORDS).
EDITOR_MAX_STATES = 200_000


@dataclass
class VerifyOptions:
    """What `scriptc verify` is asked: the witnesses to write (`fastest`, `slowest`, goal
    ids), where scenario files go (`counterexamples`; None: nowhere), the exploration's bound
    (`max_states`), and callbacks told of each file as it starts (`on_file`) and, now and
    then, of how many sets of instants its exploration has made (`on_progress`)."""

    witnesses: tuple[str, ...] = ()
    counterexamples: str | None = DEFAULT_FOLDER
    max_states: int | None = None
    on_file: Callable[[str], None] | None = None
    on_progress: Callable[[int], None] | None = None


@dataclass
class FileVerification:
    """One file's verification: its analysis (None when it could not be read), why it was not
    explored (`problem`, with `analysis` holding the diagnostics when the script has errors),
    the verdicts, what was assumed (`assumptions`), and the scenario files written, by
    witness name."""

    path: str
    analysis: Analysis | None = None
    setup: Setup | None = None
    verification: Verification | None = None
    problem: str = ""
    assumptions: list[str] = field(default_factory=list)
    written: dict[str, str] = field(default_factory=dict)


@dataclass
class VerifyRun:
    """Every file's verification, the problems met finding them, and whether Ctrl-C stopped
    it (what was decided until then is kept)."""

    files: list[FileVerification] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    interrupted: bool = False
    seconds: float = 0.0

    @property
    def exit_code(self) -> int:
        """130 interrupted; 2 a file could not be verified (unreadable, errors, bad
        configuration) or a path was not found; 1 a property is violated; else 0."""
        if self.interrupted:
            return 130
        if self.problems or any(f.problem for f in self.files):
            return 2
        if any(f.verification is not None and f.verification.violated for f in self.files):
            return 1
        return 0


def verify_paths(paths: Sequence[str], options: VerifyOptions | None = None) -> VerifyRun:
    """Verify every script named or found under `paths` (folders contribute their
    `*.script` files, as for `scriptc lint`)."""
    options = options or VerifyOptions()
    started = time.perf_counter()
    files, problems = discover(list(paths))
    run = VerifyRun(problems=problems)
    for path in files:
        if options.on_file is not None:
            options.on_file(path)
        try:
            run.files.append(verify_file(path, options))
        except interrupt.Interrupted:
            run.interrupted = True
            break
        if run.files[-1].verification is not None and run.files[-1].verification.interrupted:
            run.interrupted = True
            break
    run.seconds = time.perf_counter() - started
    return run


def verify_file(path: str, options: VerifyOptions | None = None) -> FileVerification:
    """Read, check, explore and judge one script (see the module's docstring)."""
    options = options or VerifyOptions()
    out = FileVerification(path)
    kind = SourceKind.of_path(path)
    if kind is SourceKind.BYTECODE:
        out.problem = f"`{shown_path(path)}` is bytecode: verify reads scripts and thesis JSON"
        return out
    setup = setup_for(path)
    out.setup = setup
    if setup.failed:
        out.problem = f"the configuration `{setup.settings.path}` has errors"
        return out
    try:
        analysis = read_configured(path, kind, setup)
    except ReadError as exc:
        out.problem = str(exc)
        return out
    out.analysis = analysis
    interrupt.check()  # Ctrl-C while the file was read: nothing more is done
    if not analysis.ok or analysis.script is None or has_errors(analysis.diagnostics):
        out.problem = f"`{shown_path(path)}` has errors"
        return out
    from scriptc.runtime.configured import ConfiguredError, implementations_for, rules_for
    from scriptc.runtime.interp import IRProgram
    from scriptc.verify.model import Model
    from scriptc.verify.verdicts import verify_model
    from scriptc.verify.witness import Runner

    try:
        functions, rules = implementations_for(setup.settings), rules_for(setup.settings)
        program = checked_program(analysis, path)
    except (ConfiguredError, Refused) as exc:
        out.problem = str(exc)
        return out
    interrupt.check()
    model = Model(IRProgram(analysis.script, path), functions, rules)
    out.assumptions = list(model.assumed)
    runner = Runner(program, functions, rules, setup.profile,
                    os.path.dirname(os.path.abspath(path)))
    for name in options.witnesses:
        if name not in ("fastest", "slowest") and name not in model.goal_ids:
            out.problem = (f"`--witness {name}`: `{shown_path(path)}` has no goal `{name}` "
                           "(a witness is `fastest`, `slowest` or a goal id)")
            return out
    unsafe = _unsafe_blocks(analysis, setup, model)
    out.verification = verify_model(model, runner, witnesses=options.witnesses, unsafe=unsafe,
                                    max_records=options.max_states,
                                    interrupted=interrupt.requested,
                                    progress=options.on_progress)
    if options.counterexamples is not None:
        _write(out, options.counterexamples)
    return out


def _unsafe_blocks(analysis: Analysis, setup: Setup, model: object) -> dict[int, list[str]]:
    """The instruction blocks that need the governor (the safety checks K001-K003 against
    the robot profile, whatever the configuration makes of their severity), by index."""
    from scriptc.check.context import Context
    from scriptc.check.safety import check_safety
    from scriptc.verify.model import Model

    assert isinstance(model, Model) and analysis.script is not None
    ctx = Context(analysis.script, analysis.source, setup.functions, setup.profile,
                  SourceKind.of_path(analysis.source.path))
    out: dict[int, list[str]] = {}
    for d in check_safety(ctx):
        for step in model.steps:
            if step.span.start <= d.span.start < step.span.end:
                out.setdefault(step.index, []).append(f"{d.message} ({d.code})")
                break
    return out


def witness_file(path: str, name: str) -> str:
    """The file name of a witness's scenario: `SCRIPT.NAME.world.json`."""
    stem = os.path.splitext(os.path.basename(path))[0]
    return f"{stem}.{name.replace(':', '-').replace('/', '-')}.world.json"


def _write(out: FileVerification, folder: str) -> None:
    """The scenario file of each confirmed violation and of each witness asked."""
    verification = out.verification
    assert verification is not None
    shown: list[Witness] = [f.witness for f in verification.findings
                            if f.witness is not None and f.status == "violated"]
    shown += verification.witnesses
    for witness in shown:
        if not witness.confirmed or witness.name in out.written:
            continue
        target = os.path.join(folder, witness_file(out.path, witness.name))
        description = (f"scriptc verify: {witness.claim} ({shown_path(out.path)}). Replay: "
                       + replay_command(out.path, target, witness.until))
        os.makedirs(folder, exist_ok=True)
        text = json_dumps(witness.world.as_json(description), indent=2) + "\n"
        write_file(target, text.encode("utf-8"))
        witness.path = target
        out.written[witness.name] = target


def replay_command(script: str, scenario: str, until: int | None) -> str:
    """The `scriptc run` command that replays a witness."""
    import shlex

    words = ["scriptc", "run", shown_path(script), "--world", shown_path(scenario)]
    if until is not None:
        words += ["--until", str(until)]
    return " ".join(shlex.quote(w) for w in words)


def overview(path: str, text: str) -> VerifyOverview | None:
    """What the editor shows of a verification of `text` (the document of `path`, under its
    repository's setup): the duration range and each goal's verdict; None when the script
    has errors or its configuration does (the editor shows those), or when verify cannot
    run it. For the language server, which calls it in a worker process."""
    from scriptc.analysis.analyze import analyze_source
    from scriptc.ide.answers import VerifyOverview
    from scriptc.runtime.configured import ConfiguredError, implementations_for, rules_for
    from scriptc.runtime.interp import IRProgram
    from scriptc.source import SourceFile
    from scriptc.verify.model import Model
    from scriptc.verify.verdicts import VIOLATED, verify_model
    from scriptc.verify.witness import Runner

    setup = setup_for(path)
    if setup.failed:
        return None
    analysis = analyze_source(SourceFile(path, text), SourceKind.SCRIPT, setup.functions,
                              setup.profile)
    if analysis.script is None or has_errors(analysis.diagnostics):
        return None
    try:
        functions, rules = implementations_for(setup.settings), rules_for(setup.settings)
        program = checked_program(analysis, path)
    except (ConfiguredError, Refused):
        return None
    model = Model(IRProgram(analysis.script, path), functions, rules)
    runner = Runner(program, functions, rules, setup.profile,
                    os.path.dirname(os.path.abspath(path)))
    verification = verify_model(model, runner, max_records=EDITOR_MAX_STATES)
    goals = verification.finding("goals")
    missing = {item.key: item.notes[0] if item.notes else "" for item in goals.items}
    verdicts = []
    for goalid in model.goal_ids:
        if goalid in missing and goals.status == VIOLATED:
            verdicts.append((goalid, "unreached", missing[goalid]))
        elif goalid in verification.reached_goals:
            verdicts.append((goalid, "reached", ""))
        else:
            verdicts.append((goalid, "unknown", ""))
    return VerifyOverview(verification.duration_min, verification.duration_max,
                          verification.unbounded, tuple(verdicts))
