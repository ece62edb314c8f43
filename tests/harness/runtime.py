"""The `trace` aspect of case files: a script, an optional scenario, the expected trace.

Under tests/cases/runtime/:

- `NAME.script` (or `NAME.json`, thesis JSON) is a case. It runs through the library, as
  `scriptc run` runs it, and its trace must equal `NAME.trace.jsonl`. With `NAME.world` the run
  has that scenario; each `NAME.VARIANT.world` is one more run of the same script, expected in
  `NAME.VARIANT.trace.jsonl`.
- A line `run: ARGS` in the script's first comment gives more options: `--until MS`, `--also
  FILE` (queue one more script after it; repeatable), `--catalogue FILE` (a script an
  override or a `script_vect` update may name; repeatable), `--stay-idle` (do not end when the
  queue is empty: run `idle_activity`), `--unchecked` (run although the checker reports
  errors: for the cases of run-time misuse), `--max-loops N` (loops at one instant before the
  session gives up; keeps the trace of a no-progress case short), `--governed` (with the safety
  governor and the default robot profile, as `scriptc run` runs: its `governor` events and
  where the robot comes to rest are in the trace), `--robot NAME` (the robot backend:
  `kinematic` unless it says `mujoco`). FILE is relative to the case's folder.
- Helper scripts live in `lib/`.
- Every case is checked and run with its repository's setup, as `scriptc run` does: the
  functions and rules its configuration declares with their Python implementations. The
  cases of `repo/` have one (`repo/scriptc.toml`, the code in `repo/runtime_case_code.py`);
  the others have none (the standard functions and rules).

Every trace is also validated against `schemas/trace.schema.json`, and each case runs twice:
the two traces must be identical, byte for byte. Each case runs through every executor of
`EXECUTORS` (the IR interpreter and the bytecode VM) against the same expected trace.
"""

from __future__ import annotations

import json
import re
import shlex
from functools import cache
from pathlib import Path

from harness import CASES, Check, expect
from scriptc.analysis.analyze import analyze_file
from scriptc.project.setup import setup_for
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.runtime.configured import implementations_for, rules_for
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.scenario import load_scenario
from scriptc.runtime.session import LoadError, Session
from scriptc.runtime.trace import Trace

RUNTIME = CASES / "runtime"


# The executors every case runs through; each must write the same trace, byte for byte. Only
# the executor changes; the session, map, rules, actuators and trace are shared
# (docs/runtime.md). The VM runs the analysis compiled to bytecode in memory and loaded (decoded
# and verified) as `scriptc run` does.
def _vm_program(analysis, shown: str):
    from scriptc import bytecode
    from scriptc.ops.build import emit
    from scriptc.runtime.vm import program_from_bytecode

    data = emit(analysis.script, "bytecode", analysis.source)
    return program_from_bytecode(bytecode.load(data), shown)


# Cases bytecode cannot express: a script run --unchecked that jumps to a label no block
# carries. Code generation refuses it (test_bytecode_refuses_what_no_vm_could_run), so they run
# through the interpreter only.
NOT_IN_BYTECODE = {"unchecked_jump"}


EXECUTORS = {
    "ir": lambda analysis, shown: IRProgram(analysis.script, shown),
    "vm": _vm_program,
}


def _program(path: Path, executor: str, unchecked: bool = False):
    analysis = analyze_file(path, "json" if path.suffix == ".json" else "script",
                            name=str(path.relative_to(CASES)),
                            functions=setup_for(str(path), cache=False).functions)
    assert analysis.script is not None, analysis.diagnostics
    if not unchecked:
        assert analysis.ok, [d.message for d in analysis.diagnostics]
    return EXECUTORS[executor](analysis, str(path.relative_to(CASES)))


def _options(path: Path) -> dict:
    text = path.read_text(encoding="utf-8")
    m = re.search(r"^\s*run:(.*)$", text, re.MULTILINE) if path.suffix == ".script" else None
    args = shlex.split(m.group(1).rstrip().rstrip("%")) if m else []
    options = {"until": None, "also": [], "catalogue": [], "stay_idle": False, "unchecked": False,
               "max_loops": 10_000, "governed": False, "robot": "kinematic"}
    it = iter(args)
    for arg in it:
        if arg == "--until":
            options["until"] = int(next(it))
        elif arg in ("--also", "--catalogue"):
            options[arg[2:]].append(next(it))
        elif arg == "--max-loops":
            options["max_loops"] = int(next(it))
        elif arg == "--stay-idle":
            options["stay_idle"] = True
        elif arg == "--unchecked":
            options["unchecked"] = True
        elif arg == "--governed":
            options["governed"] = True
        elif arg == "--robot":
            options["robot"] = next(it)
        else:
            raise AssertionError(f"{path.name}: unknown run option {arg}")
    return options


def _loader(executor: str):
    def load(path: str):
        p = Path(path)
        if not p.exists():
            raise LoadError(f"`{p.name}` does not exist")
        return _program(p, executor)

    return load


def run_case(path: Path, world: Path | None, executor: str = "ir") -> Trace:
    options = _options(path)
    folder = path.parent
    unchecked = options["unchecked"]
    programs = [_program(path, executor, unchecked)] + [
        _program(folder / f, executor, unchecked) for f in options["also"]]
    catalogue = [_program(folder / f, executor) for f in options["catalogue"]]
    scenario = load_scenario(str(world)) if world is not None else None
    if scenario is not None:
        scenario.path = str(world.relative_to(CASES))  # the same text on every machine
    trace = Trace()
    settings = setup_for(str(path), cache=False).settings
    Session(programs, scenario=scenario, trace=trace, catalogue=catalogue,
            stop_when_done=not options["stay_idle"], loader=_loader(executor),
            max_loops_per_instant=options["max_loops"], robot=options["robot"],
            functions=implementations_for(settings), rules=rules_for(settings),
            profile=DEFAULT_PROFILE if options["governed"] else None).run(options["until"])
    return trace


def _runs() -> list[tuple[Path, Path | None, Path]]:
    runs = []
    for path in sorted([*RUNTIME.glob("*.script"), *RUNTIME.glob("*.json"),
                        *RUNTIME.glob("repo/*.script")]):
        stem, folder = path.name[: -len(path.suffix)], path.parent
        default = folder / f"{stem}.world"
        variants = sorted(p for p in folder.glob(f"{stem}.*.world"))
        runs.append((path, default if default.exists() else None, folder / f"{stem}.trace.jsonl"))
        for v in variants:
            variant = v.name[len(stem) + 1: -len(".world")]
            runs.append((path, v, folder / f"{stem}.{variant}.trace.jsonl"))
    return runs


@cache
def _trace_validator():
    """schemas/trace.schema.json compiled to Python code (fastjsonschema: a tenth of
    jsonschema's time over the cases' thousands of events)."""
    import fastjsonschema

    from scriptc.resources import schema_path

    schema = json.loads(schema_path("trace.schema.json").read_text(encoding="utf-8"))
    return fastjsonschema.compile(schema)


@cache
def _valid_trace(text: str) -> None:
    """Every event of a trace satisfies the trace schema (each distinct trace once: the
    executors write the same one)."""
    from fastjsonschema import JsonSchemaException

    for line in text.splitlines():
        event = json.loads(line)
        try:
            _trace_validator()(event)
        except JsonSchemaException as error:
            raise AssertionError(f"{event}: {error.message}") from None


def _check(path: Path, world: Path | None, expected: Path, executor: str) -> None:
    text = run_case(path, world, executor).text()
    assert run_case(path, world, executor).text() == text, "two runs of the same inputs differ"
    _valid_trace(text)
    expect(expected, text)


def checks() -> list[Check]:
    out = []
    for path, world, expected in _runs():
        variant = expected.name[len(path.stem) + 1: -len(".trace.jsonl")]
        for executor in EXECUTORS:
            if executor == "vm" and path.stem in NOT_IN_BYTECODE:
                continue
            out.append(Check("trace", path, (expected,),
                             lambda p=path, w=world, e=expected, x=executor: _check(p, w, e, x),
                             variant=f"{variant}.{executor}" if variant else executor,
                             reads=(world,) if world is not None else ()))
    return out
