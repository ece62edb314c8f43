"""`scriptc run` as library calls: the programs a run runs, and its defaults.

A file's kind is its suffix's (`SourceKind.of_path`). `.script` and `.json` files are read
and checked as `compile` and `check` read them, under their repository's setup (functions,
robot profile, policy); a checked script is compiled to bytecode in memory, verified (as a
`.scb` file is once decoded) and run by the VM, or, with the `ir` executor, read from
the IR by the reference interpreter. `.scb` files are decoded and verified, then run by the
VM. `load_programs` does this for the command line's files; `ProgramLoader` for the scripts a
session meets by path while it runs (the runtime's `scriptc.runtime.loading.Loader`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from scriptc.analysis.analyze import Analysis
from scriptc.analysis.read import ReadError, read_bytes
from scriptc.gcpause import gc_paused
from scriptc.ops.build import read_configured
from scriptc.project.setup import Setup, setup_for
from scriptc.runtime.loading import LoadError
from scriptc.source import SourceKind

if TYPE_CHECKING:  # the executors are imported when a program is made
    from scriptc.runtime.executor import Loadable

__all__ = [
    "DEFAULT_LIMIT_MS",
    "EXECUTORS",
    "ConfigurationFailed",
    "Loaded",
    "ProgramLoader",
    "Refused",
    "bytecode_program",
    "checked_program",
    "governed_by_default",
    "load_programs",
]

# How `.script` and `.json` files run: compiled to bytecode for the VM, or read from the IR
# by the reference interpreter (for comparison). `.scb` files always run on the VM.
EXECUTORS = ("vm", "ir")

# Scripts may loop forever: without a limit, a run stops after an hour of simulated time.
DEFAULT_LIMIT_MS = 3_600_000


class Refused(Exception):
    """A file that is read but cannot run: bytecode that is malformed or invalid, a script
    the bytecode cannot hold. The message names the file and says why."""


class ConfigurationFailed(Exception):
    """The configuration of a file has an error: nothing runs under a configuration that does
    not say what was meant (docs/configuration.md). `setup.problems` say what is wrong."""

    def __init__(self, setup: Setup) -> None:
        super().__init__(f"the configuration `{setup.settings.path}` has errors")
        self.setup = setup


def governed_by_default(robot: str) -> bool:
    """Whether a run on the robot backend `robot` is kept within the robot profile when the
    command line does not say: yes on the physical model (mujoco), no on the kinematic robot,
    the ideal robot that does exactly what the script says."""
    return robot != "kinematic"


def bytecode_program(path: str) -> Loadable:
    """The runtime program of a `.scb` file: decoded and verified, then run by the VM. Raises
    ReadError (the file cannot be read) or Refused (it is not a valid program)."""
    data = read_bytes(path)
    from scriptc.bytecode import BytecodeError, load
    from scriptc.runtime import vm

    try:
        program = load(data)
    except BytecodeError as exc:
        raise Refused(f"`{path}`: {exc}") from None
    # The VM's entry point: a runtime program (executor.py) over a verified bytecode program.
    return vm.program_from_bytecode(program, path)


def checked_program(analysis: Analysis, path: str, executor: str = "vm") -> Loadable:
    """The runtime program of a checked script: compiled to bytecode in memory, verified (as
    a `.scb` file is once decoded) and run by the VM; or, with the `ir`
    executor, read from the IR by the reference interpreter. Raises Refused when the script
    cannot be compiled to bytecode (or was not read at all)."""
    script = analysis.script
    if script is None:
        raise Refused(f"`{path}` could not be read into a script")
    if executor == "ir":
        from scriptc.runtime.interp import IRProgram

        return IRProgram(script, path)
    from scriptc.bytecode import InvalidError, verify
    from scriptc.emit.codegen import CodegenError, codegen
    from scriptc.runtime import vm

    # Codegen's program is verified as it is, in memory: the bytes of a `.scb` file would only
    # be decoded back into the same program (tests/test_bytecode.py holds the round trip).
    try:
        with gc_paused():
            verified = verify(codegen(script, analysis.source))
    except (CodegenError, InvalidError) as exc:  # only for what the checks let through
        raise Refused(f"`{path}` cannot be compiled to bytecode: {exc} (`--executor ir` "
                      "runs it)") from None
    return vm.program_from_bytecode(verified, path)


class Loaded:
    """The files of a run, loaded: `analyses` of the scripts read (each with its diagnostics,
    to show), `programs` in the order of the files (None for a script with errors), and
    `setup`, the setup of the first file, whose repository gives the run its functions, its
    rules and the governor's profile."""

    __slots__ = ("analyses", "programs", "setup")

    def __init__(self, analyses: list[Analysis], programs: list[Loadable | None],
                 setup: Setup) -> None:
        self.analyses = analyses
        self.programs = programs
        self.setup = setup

    @property
    def ok(self) -> bool:
        """Whether every file gave a program (no script has errors)."""
        return all(p is not None for p in self.programs)

    def runnable(self) -> list[Loadable]:
        """The programs, to run: only when every file gave one (`ok`), else ValueError."""
        found = [p for p in self.programs if p is not None]
        if len(found) != len(self.programs):
            raise ValueError("a script has errors: it gave no program to run")
        return found


def load_programs(paths: list[str] | tuple[str, ...], executor: str = "vm", *,
                  configured: Callable[[str], Setup] = setup_for) -> Loaded:
    """The programs of the files of `scriptc run`, in order. `configured(path)` gives the
    setup of a script (`setup_for`; the CLI's also shows the configuration's problems); a
    setup whose configuration has an error raises ConfigurationFailed, a file that cannot
    be read ReadError, a `.scb` file that is not a valid program or a script that cannot be
    compiled Refused. A script with errors gives no program (None) and its analysis says why."""
    analyses: list[Analysis] = []
    programs: list[Loadable | None] = []
    setups: list[Setup | None] = []
    for path in paths:
        kind = SourceKind.of_path(path)
        if kind is SourceKind.BYTECODE:
            programs.append(bytecode_program(path))
            setups.append(None)
            continue
        setup = configured(path)
        if setup.failed:
            raise ConfigurationFailed(setup)
        setups.append(setup)
        analysis = read_configured(path, kind, setup)
        analyses.append(analysis)
        programs.append(checked_program(analysis, path, executor) if analysis.ok else None)
    # One session, one robot: the first file's repository (read once) gives the run its
    # functions, rules and profile.
    first = setups[0] if setups and setups[0] is not None else setup_for(paths[0])
    return Loaded(analyses, programs, first)


class ProgramLoader:
    """The loader of a session (`scriptc.runtime.loading.Loader`): a script met by path during
    the run is loaded as `load_programs` loads the command line's, and any reason it cannot
    run (unreadable, a broken configuration, errors, invalid bytecode) is a LoadError, which
    the session reports."""

    def __init__(self, executor: str = "vm") -> None:
        self.executor = executor

    def __call__(self, path: str) -> Loadable:
        try:
            if SourceKind.of_path(path) is SourceKind.BYTECODE:
                return bytecode_program(path)
            setup = setup_for(path)
            if setup.failed:
                raise LoadError(f"the configuration of `{path}` has errors (run `scriptc lint "
                                f"{path}`)")
            analysis = read_configured(path, SourceKind.of_path(path), setup)
            if not analysis.ok:
                raise LoadError(f"`{path}` has errors (run `scriptc lint {path}`)")
            return checked_program(analysis, path, self.executor)
        except (ReadError, Refused) as exc:
            raise LoadError(str(exc)) from None
