"""`scriptc verify FILE... [--json] [--format F] [--counterexamples DIR] [--witness NAME]`:
explore every run of each script that the world allows and prove or refute its properties
(docs/verify.md): `terminates`, `goals`, `blocks`, `duration`, `no-stall`, `no-progress`,
`safety`, each proved, violated or unknown.

For each file, one line per property, then each violation as a diagnostic in the compiler's
style (family Y) whose help is the `scriptc run` command that replays it, and each undecided
property as a warning (Y005). The scenario file of each confirmed violation, and of each
witness asked with `--witness` (`fastest`, `slowest` or a goal id), is written to
`--counterexamples DIR` (default `scriptc-verify/`). `--json` prints one JSON object per file
(JSON lines); `--format sarif` and `github` give the diagnostics for CI; `--stats` adds what
was explored and how fast. On a terminal a status line shows the exploration's progress.

Exit status: 0 nothing violated (`unknown` is a warning), 1 a property is violated, 2 a file
could not be verified (unreadable, errors, a broken configuration) or a path was not found,
130 interrupted (Ctrl-C stops the exploration at once; what was decided is printed). The work
is `scriptc.ops.verify.verify_paths`'s; this module prints it.
"""

from __future__ import annotations

import sys
import time
from typing import TYPE_CHECKING

import click

from scriptc import interrupt
from scriptc.cli.common import show, use_color, write
from scriptc.ops.verify import DEFAULT_FOLDER

if TYPE_CHECKING:
    from scriptc.diagnostics.model import Diagnostic
    from scriptc.ops.verify import FileVerification, VerifyRun
    from scriptc.source import SourceFile

FORMATS = ("text", "json", "sarif", "github")


@click.command("verify")
@click.argument("paths", nargs=-1, required=True)
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON object per file (the same as --format json).")
@click.option("--format", "format_", type=click.Choice(FORMATS), default="text",
              show_default=True,
              help="text; json (one object per file); sarif or github (the diagnostics, for "
                   "CI).")
@click.option("--counterexamples", "folder", default=DEFAULT_FOLDER, show_default=True,
              metavar="DIR", help="Where the scenario files of violations and witnesses go.")
@click.option("--witness", "witnesses", multiple=True, metavar="NAME",
              help="Also write a run that shows NAME: fastest, slowest (the least and the "
                   "greatest session time) or a goal id (a run that reaches it). Repeatable.")
@click.option("--max-states", "max_states", type=click.IntRange(min=1), metavar="N",
              help="Stop exploring after N sets of instants (default 2,000,000): what is not "
                   "decided then is unknown.")
@click.option("--stats", is_flag=True, help="Print what was explored and how fast.")
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], as_json: bool, format_: str,
            folder: str, witnesses: tuple[str, ...], max_states: int | None,
            stats: bool) -> None:
    """Prove or refute what every run of the scripts does, for every world.

    The robot's side (time, blocks, jumps on the elapsed time) is exact; the world's (people,
    objects, their answers) is free: every way it can go is explored.
    """
    from scriptc.ops.verify import VerifyOptions, verify_paths

    if as_json:
        format_ = "json"
    status = _Status(enabled=format_ == "text")
    options = VerifyOptions(witnesses=witnesses, counterexamples=folder,
                            max_states=max_states, on_file=status.file,
                            on_progress=status.progress)
    try:
        with interrupt.catching():
            run = verify_paths(paths, options)
    finally:
        status.close()
    _print(run, format_, stats)
    ctx.exit(run.exit_code)


class _Status:
    """A one-line status on stderr while a file is explored (a terminal only; rich is
    imported then): the file and the sets of instants explored so far."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled and sys.stderr.isatty()
        self.name = ""
        self.started = time.perf_counter()
        self._live: object | None = None

    def file(self, path: str) -> None:
        from scriptc.paths import shown_path

        self.name = shown_path(path)
        self.started = time.perf_counter()

    def progress(self, count: int) -> None:
        if not self.enabled or time.perf_counter() - self.started < 0.5:
            return
        from rich.console import Console
        from rich.status import Status

        if self._live is None:
            self._live = Status("", console=Console(stderr=True))
            self._live.start()
        assert isinstance(self._live, Status)
        self._live.update(f"verifying {self.name}: {count:,} sets of instants explored")

    def close(self) -> None:
        if self._live is not None:
            from rich.status import Status

            assert isinstance(self._live, Status)
            self._live.stop()
            self._live = None


def _print(run: VerifyRun, format_: str, stats: bool) -> None:
    from scriptc.diagnostics.render import render
    from scriptc.numbers import json_dumps
    from scriptc.ops.verify import replay_command
    from scriptc.paths import shown_path
    from scriptc.verify.report import as_data, diagnostics, property_lines, stats_line

    for problem in run.problems:
        write(f"error: {problem}\n", err=True)
    color = use_color(sys.stdout)
    reports: list[tuple[SourceFile, list[Diagnostic]]] = []
    for file in run.files:
        verification = file.verification
        if verification is None:
            if file.analysis is not None and file.analysis.diagnostics:
                show([(file.analysis.source, file.analysis.diagnostics)], err=True)
            if file.setup is not None and file.setup.problems:
                show([(p.source, p.diagnostics) for p in file.setup.problems], err=True)
            write(f"error: {file.problem}: not verified\n", err=True)
            continue
        replays = {name: replay_command(file.path, path, _until(file, name))
                   for name, path in file.written.items()}
        found = diagnostics(verification, replays)
        assert file.analysis is not None
        reports.append((file.analysis.source, found))
        if format_ == "json":
            write(json_dumps(as_data(shown_path(file.path), verification, file.written,
                                     file.assumptions), ensure_ascii=False) + "\n")
            continue
        if format_ != "text":
            continue
        write(f"verify {shown_path(file.path)}\n" + property_lines(verification, color=color))
        for assumption in file.assumptions:
            write(f"  assumed: {assumption}\n")
        if stats:
            write(stats_line(verification))
        if found:
            write("\n" + render("text", [(file.analysis.source, found)], color=color))
        for name, path in file.written.items():
            write(f"wrote {shown_path(path)} ({name}, confirmed by a replay): "
                  f"{replays[name]}\n")
        for witness in verification.witnesses:
            if not witness.confirmed:
                write(f"no run written for `--witness {witness.name.removeprefix('goal:')}`: "
                      f"{witness.why}\n")
        write("\n" if run.files.index(file) < len(run.files) - 1 else "")
    if format_ in ("sarif", "github"):
        write(render(format_, reports, color=False))
    if run.interrupted:
        count = len(run.files)
        write(f"error: interrupted (Ctrl-C): {count} file{'' if count == 1 else 's'} "
              "looked at; what was not decided is unknown\n", err=True)


def _until(file: FileVerification, name: str) -> int | None:
    """The time limit of a witness's replay (a run that must not end by then)."""
    verification = file.verification
    assert verification is not None
    for w in [f.witness for f in verification.findings if f.witness is not None] \
            + verification.witnesses:
        if w is not None and w.name == name:
            return w.until if name == "no-stall" else None
    return None
