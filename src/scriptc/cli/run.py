"""`scriptc run FILE... [--world FILE] [--until MS] [--trace FILE[.mcap]] [--robot NAME]
[--governor/--no-governor] [--plot FILE] [--report FILE.html] [--executor vm|ir] [--json]`:
run scripts as one session in simulated time (docs/runtime.md) on the MuJoCo robot (the
default; `--robot kinematic` is the ideal robot), governed by the robot profile
(docs/robot.md); `--report` writes the run's report, one HTML page (docs/views.md).

The files are queued in the order given and run one after the other; the run ends when every
one has ended (it does not sit in `idle_activity`) or at `--until` (without it, after one hour
of simulated time: a script may loop forever). `.script` and `.json`
(thesis JSON) files are read and checked like `compile`/`check` do: a file with errors is
refused with its diagnostics (exit 1) and nothing runs; the others are compiled to bytecode in
memory and run through the VM (`--executor ir` runs them through the reference interpreter over
the IR instead, for comparison). `.scb` (bytecode) is decoded, verified and runs through the
VM. Exit status: 0 when the run completed, reached `--until` or stalled, 1 for a script with
errors or a run stopped by a run-time error, 2 for a usage problem (a file that cannot be read,
a bad scenario), 130 when Ctrl-C stopped it (the trace is written up to there; a second Ctrl-C
stops at once, without it).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import click

from scriptc import interrupt
from scriptc.cli.common import (
    CliError,
    check_output,
    configured,
    show,
    stop_for_configuration,
    write,
    write_bytes,
    write_output,
)
from scriptc.ops.programs import EXECUTORS

if TYPE_CHECKING:
    from scriptc.runtime.scenario import Scenario


class ProgramRefused(CliError):
    """`ops.programs.Refused` as the CLI shows it: a file that is read but refused (bytecode
    that is malformed or invalid, a script the bytecode cannot hold): exit 1, as for a script
    with errors."""

    exit_code = 1


@click.command("run")
@click.argument("files", nargs=-1, required=True)
@click.option("--world", "world", metavar="FILE",
              help="Scenario: timed map updates and operator events (JSON), or a test file "
                   "(*.test.toml) whose world to use.")
@click.option("--until", "until", type=click.IntRange(min=0), metavar="MS",
              help="Stop at this simulated time (ms).")
@click.option("--trace", "trace_path", metavar="FILE",
              help="Write the trace as JSON lines (- for stdout), or as MCAP for Foxglove, "
                   "Lichtblick and PlotJuggler when FILE ends in .mcap.")
@click.option("--robot", "robot", default="mujoco", show_default=True, metavar="NAME",
              help="Robot backend: mujoco (the physics of the Teo/Oimi model) or kinematic "
                   "(exact integration).")
@click.option("--governor/--no-governor", "governor", default=None,
              help="Keep the run within the robot profile: speeds clamped, accelerations "
                   "ramped, people kept at a distance, LED flashing held (default: on with "
                   "mujoco, off with kinematic, the ideal robot that does exactly what the "
                   "script says).")
@click.option("--plot", "plot_path", metavar="FILE",
              help="Draw the run (trajectory from above, timeline of the tracks) to FILE.png "
                   "or FILE.svg (needs matplotlib, scriptc's plot extra).")
@click.option("--report", "report_path", metavar="FILE",
              help="Write the report of the run to FILE (one HTML page: the room, the tracks, "
                   "the events and the flow of each script, with one cursor).")
@click.option("--executor", "executor", type=click.Choice(EXECUTORS), default="vm",
              show_default=True,
              help="How .script and .json files run: vm (compiled to bytecode, run by the VM) "
                   "or ir (the reference interpreter over the IR, for comparison). .scb files "
                   "always run on the VM.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object.")
@click.pass_context
def command(ctx: click.Context, files: tuple[str, ...], world: str | None, until: int | None,
            trace_path: str | None, robot: str, governor: bool | None, plot_path: str | None,
            report_path: str | None, executor: str, as_json: bool) -> None:
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
    if plot_path is not None and os.path.splitext(plot_path)[1].lower() not in (".png", ".svg"):
        raise CliError(f"--plot `{plot_path}`: the file must end in .png or .svg")
    if plot_path is not None:
        import importlib.util

        if importlib.util.find_spec("matplotlib") is None:
            from scriptc.project.provenance import extra_install_command

            raise CliError("--plot needs matplotlib, which is not installed here; install it "
                           "into scriptc's environment with\n  "
                           + extra_install_command("plot", ["matplotlib"]))
    # `--trace FILE.mcap` writes MCAP (the suffix chooses); `mcap` is a dependency of scriptc,
    # but an environment made before it was may not have it.
    as_mcap = trace_path is not None and trace_path.lower().endswith(".mcap")
    if as_mcap:
        import importlib.util

        if importlib.util.find_spec("mcap") is None:
            import shlex
            import sys

            raise CliError(f"--trace `{trace_path}`: writing MCAP needs the `mcap` package, "
                           "which is not installed here; install it into scriptc's environment "
                           f"with\n  {shlex.quote(sys.executable)} -m pip install 'mcap>=1.2,<2'")
    # Where the trace and the picture go is checked before the run, not after it.
    for output in (trace_path, plot_path, report_path):
        if output is not None:
            check_output(output)
    scenario = None
    if world is not None and world.endswith(".test.toml"):
        scenario = _test_world(ctx, world)
    elif world is not None:
        try:
            scenario = load_scenario(world)
        except ScenarioError as exc:
            write("".join(f"error: {line}\n" for line in exc.lines()), err=True)
            ctx.exit(2)
    from scriptc.analysis.read import ReadError
    from scriptc.ops import programs

    try:
        loaded = programs.load_programs(files, executor, configured=configured)
    except programs.ConfigurationFailed:
        stop_for_configuration()
    except ReadError as exc:
        raise CliError(str(exc)) from None
    except programs.Refused as exc:
        raise ProgramRefused(str(exc)) from None
    if any(a.diagnostics for a in loaded.analyses):
        show([a for a in loaded.analyses if a.diagnostics], err=True)
    if not loaded.ok:
        ctx.exit(1)
    from scriptc.runtime.configured import (
        ConfiguredError,
        implementations_for,
        rules_for,
    )

    # One session, one robot: the repository of the first file gives the functions and rules
    # that run (imported now: linting never imports them) and the safety governor's profile.
    settings = loaded.setup.settings
    try:
        functions, rules = implementations_for(settings), rules_for(settings)
    except ConfiguredError as exc:
        raise CliError(str(exc)) from None
    trace = Trace(enabled=trace_path is not None or plot_path is not None
                  or report_path is not None)
    if governor is None:
        governor = programs.governed_by_default(robot)
    profile = loaded.setup.profile if governor else None
    try:
        robot_backend = make_robot(robot)
    except Exception as exc:  # a backend that cannot start (mujoco missing)
        raise CliError(f"robot `{robot}` cannot start: {exc}") from None
    recorder = None
    # The MCAP file and the report show the robot where it was: its path is recorded as for
    # the picture.
    if plot_path is not None or as_mcap or report_path is not None:
        from scriptc.runtime.recorded import PathRecorder

        robot_backend = recorder = PathRecorder(robot_backend)
    session = Session(loaded.runnable(), scenario=scenario, robot=robot_backend, trace=trace,
                      loader=programs.ProgramLoader(executor), profile=profile,
                      functions=functions, rules=rules)
    # Scripts may loop forever: without --until, a run stops after an hour of simulated time.
    # Ctrl-C stops the session between two instants (or two chunks of physics): it ends
    # `interrupted`, its trace is written up to there, and the exit status is 130.
    with interrupt.catching():
        result = session.run(until if until is not None else programs.DEFAULT_LIMIT_MS)
    interrupted = result.outcome == "interrupted"
    capped = until is None and result.outcome == "until"
    # A file that cannot be written at the end (a full disk) is reported after the summary,
    # which is never lost (exit 2).
    unwritten: list[str] = []
    shown_path = None if trace_path in (None, "-") else trace_path
    if trace_path is not None:
        try:
            if as_mcap:
                from scriptc.views.mcap import write_mcap

                assert recorder is not None  # made for an .mcap trace
                write_output(trace_path, write_mcap(trace.events, recorder.samples))
            else:
                write_output(trace_path, trace.text())
        except CliError as exc:
            unwritten.append(exc.format_message())
            shown_path = None
    if plot_path is not None and interrupted:
        write(f"note: interrupted: the picture `{plot_path}` was not drawn\n", err=True)
    elif plot_path is not None:
        from scriptc.runtime.plot import plot_run
        from scriptc.writing import WriteError

        assert recorder is not None  # made with `--plot`
        try:
            plot_run(trace.events, plot_path, recorder.samples, scenario)
        except WriteError as exc:
            unwritten.append(str(exc))
    if report_path is not None:  # written when interrupted too, as the trace is
        from scriptc.ops.report import run_report

        assert recorder is not None  # made with `--report`
        page, warnings = run_report(trace.events, files, loaded.analyses, recorder.samples)
        write("".join(f"warning: {w}\n" for w in warnings), err=True)
        try:
            write_output(report_path, page)
        except CliError as exc:
            unwritten.append(exc.format_message())
    to_stderr = trace_path == "-"
    if as_json:
        text = summary_json(result, shown_path, capped)
        if to_stderr:
            write(text, err=True)
        else:
            write_bytes(text.encode("utf-8"))
    else:
        write(summary_text(result, shown_path, capped), err=to_stderr)
    if unwritten:
        write("".join(f"error: {message}\n" for message in unwritten), err=True)
        ctx.exit(2)
    if interrupted:
        ctx.exit(interrupt.EXIT_STATUS)
    ctx.exit(1 if result.outcome == "error" else 0)


def _test_world(ctx: click.Context, path: str) -> Scenario | None:
    """The world of a test file (`--world NAME.test.toml`: its `[world]` table, or the world
    file it names), so that `scriptc test`'s replay command runs the test's session. A test
    file with problems is reported as `scriptc test` reports it (exit 2)."""
    from scriptc.analysis.read import ReadError
    from scriptc.testing.read import read_test

    try:
        read = read_test(path)
    except ReadError as exc:
        raise CliError(str(exc)) from None
    if read.test is None:
        show([(read.source, read.diagnostics)], err=True)
        ctx.exit(2)
    return read.test.world
