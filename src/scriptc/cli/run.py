"""`scriptc run FILE... [--world FILE] [--until MS] [--trace FILE] [--robot NAME] [--json]`:
run scripts as one session in simulated time (docs/runtime.md).

The files are queued in the order given and run one after the other; the run ends when every
one has ended (it does not sit in `idle_activity`) or at `--until` (without it, after one hour
of simulated time: a script may loop forever). `.script` and `.json`
(thesis JSON) files are read and checked like `compile`/`check` do: a file with errors is
refused with its diagnostics (exit 1) and nothing runs. `.scb` (bytecode) runs through the VM
when there is one. Exit status: 0 when the run completed or reached `--until`, 1 for a
script with errors or a run stopped by a run-time error, 2 for a usage problem (a file that
cannot be read, a bad scenario, bytecode that cannot run yet).
"""

from __future__ import annotations

import os

import click

from scriptc import driver
from scriptc.cli._shell import CliError, show, write, write_bytes, write_output

DEFAULT_LIMIT_MS = 3_600_000


def _kind(path: str) -> str:
    return {".json": "json", ".scb": "scb"}.get(os.path.splitext(path)[1].lower(), "script")


class Refused(CliError):
    """A file that is read but refused (bytecode that is malformed or invalid): exit 1, as for a
    script with errors."""

    exit_code = 1


def _bytecode_program(path: str):
    """A program for a `.scb` file: decoded and verified, then run through the VM."""
    import importlib.util

    try:
        data = driver.read_bytes(path)
    except driver.ReadError as exc:
        raise CliError(str(exc)) from None
    if importlib.util.find_spec("scriptc.bytecode") is None:
        raise CliError(f"`{path}`: bytecode execution is not available yet")
    from scriptc.bytecode import BytecodeError, load

    try:
        program = load(data)
    except BytecodeError as exc:
        raise Refused(f"`{path}`: {exc}") from None
    if importlib.util.find_spec("scriptc.runtime.vm") is None:
        raise CliError(f"`{path}`: bytecode execution is not available yet (the file is "
                       "valid bytecode)")
    from scriptc.runtime import vm

    # The VM's entry point: a runtime `Program` (executor.py) over a verified bytecode Program.
    return vm.program_from_bytecode(program, path)


def _analyze(paths: tuple[str, ...]):
    """Programs for the files, or exit 1 with every file's diagnostics."""
    from scriptc.runtime.interp import IRProgram

    analyses, programs = [], []
    for path in paths:
        kind = _kind(path)
        if kind == "scb":
            programs.append(_bytecode_program(path))
            continue
        try:
            analysis = driver.analyze_file(path, kind)
        except driver.ReadError as exc:
            raise CliError(str(exc)) from None
        analyses.append(analysis)
        programs.append(IRProgram(analysis.script, path) if analysis.ok else None)
    return analyses, programs


def _loader(path: str):
    """Scripts named at run time (a `script_vect` update, an override by path)."""
    from scriptc.runtime.interp import IRProgram
    from scriptc.runtime.session import LoadError

    kind = _kind(path)
    if kind == "scb":
        try:
            return _bytecode_program(path)
        except CliError as exc:
            raise LoadError(exc.format_message()) from None
    try:
        analysis = driver.analyze_file(path, kind)
    except driver.ReadError as exc:
        raise LoadError(str(exc)) from None
    if not analysis.ok:
        raise LoadError(f"`{path}` has errors (run `scriptc lint {path}`)")
    return IRProgram(analysis.script, path)


@click.command("run")
@click.argument("files", nargs=-1, required=True)
@click.option("--world", "world", metavar="FILE",
              help="Scenario: timed map updates and operator events (JSON).")
@click.option("--until", "until", type=click.IntRange(min=0), metavar="MS",
              help="Stop at this simulated time (ms).")
@click.option("--trace", "trace_path", metavar="FILE",
              help="Write the trace as JSON lines (- for stdout).")
@click.option("--robot", "robot", default="kinematic", show_default=True, metavar="NAME",
              help="Robot backend (kinematic).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object.")
@click.pass_context
def command(ctx: click.Context, files: tuple[str, ...], world: str | None, until: int | None,
            trace_path: str | None, robot: str, as_json: bool) -> None:
    """Run scripts (.script, .json, .scb) as one session in simulated time.

    The files run one after the other, in the order given; the run ends when all have
    ended, or at --until. The summary gives the outcome, the simulated time and the robot's
    pose (metres and radians, from the origin facing +x).
    """
    from scriptc.runtime.robots import ROBOTS, make_robot
    from scriptc.runtime.scenario import ScenarioError, load_scenario
    from scriptc.runtime.session import Session
    from scriptc.runtime.summary import summary_json, summary_text
    from scriptc.runtime.trace import Trace

    if robot not in ROBOTS:
        raise CliError(f"unknown robot `{robot}` (known: {', '.join(sorted(ROBOTS))})")
    scenario = None
    if world is not None:
        try:
            scenario = load_scenario(world)
        except ScenarioError as exc:
            write("".join(f"error: {line}\n" for line in exc.lines()), err=True)
            ctx.exit(2)
    analyses, programs = _analyze(files)
    if any(a.diagnostics for a in analyses):
        show([a for a in analyses if a.diagnostics], err=True)
    if any(p is None for p in programs):
        ctx.exit(1)
    trace = Trace(enabled=trace_path is not None)
    session = Session(programs, scenario=scenario, robot=make_robot(robot), trace=trace,
                      loader=_loader)
    # Scripts may loop forever: without --until, a run stops after an hour of simulated time.
    result = session.run(until if until is not None else DEFAULT_LIMIT_MS)
    capped = until is None and result.outcome == "until"
    if trace_path is not None:
        write_output(trace_path, trace.text())
    to_stderr = trace_path == "-"
    shown_path = None if trace_path in (None, "-") else trace_path
    if as_json:
        text = summary_json(result, shown_path, capped)
        if to_stderr:
            write(text, err=True)
        else:
            write_bytes(text.encode("utf-8"))
    else:
        write(summary_text(result, shown_path, capped), err=to_stderr)
    ctx.exit(1 if result.outcome == "error" else 0)
