"""Runtime case files (tests are data): a script, an optional scenario, the expected trace.

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
  where the robot comes to rest are in the trace). FILE is relative to the case's folder.
- Helper scripts live in `lib/`.

Every trace is also validated against `schemas/trace.schema.json`, and each case runs twice:
the two traces must be identical, byte for byte. Each case runs through every executor of
`EXECUTORS` (the IR interpreter and the bytecode VM) against the same expected trace.
`UPDATE_EXPECT=1` rewrites the expected traces; review the diff.
"""

from __future__ import annotations

import json
import re
import shlex
import sys
from pathlib import Path

import pytest

from harness import CASES, expect
from scriptc.analysis.analyze import analyze_file
from scriptc.robot.profile import DEFAULT_PROFILE
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
EXECUTOR = "ir"  # the one `_program` uses; the test sets it per run


def _program(path: Path, unchecked: bool = False):
    analysis = analyze_file(path, "json" if path.suffix == ".json" else "script",
                            name=str(path.relative_to(CASES)))
    assert analysis.script is not None, analysis.diagnostics
    if not unchecked:
        assert analysis.ok, [d.message for d in analysis.diagnostics]
    return EXECUTORS[EXECUTOR](analysis, str(path.relative_to(CASES)))


def _options(path: Path) -> dict:
    text = path.read_text(encoding="utf-8")
    m = re.search(r"^\s*run:(.*)$", text, re.MULTILINE) if path.suffix == ".script" else None
    args = shlex.split(m.group(1).rstrip().rstrip("%")) if m else []
    options = {"until": None, "also": [], "catalogue": [], "stay_idle": False, "unchecked": False,
               "max_loops": 10_000, "governed": False}
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
        else:
            raise AssertionError(f"{path.name}: unknown run option {arg}")
    return options


def _loader(folder: Path):
    def load(path: str):
        p = Path(path)
        if not p.exists():
            raise LoadError(f"`{p.name}` does not exist")
        return _program(p)

    return load


def run_case(path: Path, world: Path | None) -> Trace:
    options = _options(path)
    folder = path.parent
    unchecked = options["unchecked"]
    programs = [_program(path, unchecked)] + [_program(folder / f, unchecked) for f in options["also"]]
    catalogue = [_program(folder / f) for f in options["catalogue"]]
    scenario = load_scenario(str(world)) if world is not None else None
    if scenario is not None:
        scenario.path = str(world.relative_to(CASES))  # the same text on every machine
    trace = Trace()
    Session(programs, scenario=scenario, trace=trace, catalogue=catalogue,
            stop_when_done=not options["stay_idle"], loader=_loader(folder),
            max_loops_per_instant=options["max_loops"],
            profile=DEFAULT_PROFILE if options["governed"] else None).run(options["until"])
    return trace


def _runs() -> list[tuple[Path, Path | None, Path]]:
    runs = []
    for path in sorted([*RUNTIME.glob("*.script"), *RUNTIME.glob("*.json")]):
        stem = path.name[: -len(path.suffix)]
        default = RUNTIME / f"{stem}.world"
        variants = sorted(p for p in RUNTIME.glob(f"{stem}.*.world"))
        runs.append((path, default if default.exists() else None, RUNTIME / f"{stem}.trace.jsonl"))
        for v in variants:
            variant = v.name[len(stem) + 1: -len(".world")]
            runs.append((path, v, RUNTIME / f"{stem}.{variant}.trace.jsonl"))
    return runs


RUNS = _runs()


@pytest.fixture(scope="module")
def trace_validator():
    import jsonschema

    from scriptc.resources import schema_path

    schema = json.loads(schema_path("trace.schema.json").read_text(encoding="utf-8"))
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize(
    "path, world, expected, executor",
    [(p, w, e, x) for p, w, e in RUNS for x in EXECUTORS
     if not (x == "vm" and p.stem in NOT_IN_BYTECODE)],
    ids=[f"{e.name[: -len('.trace.jsonl')]}-{x}" for p, _, e in RUNS for x in EXECUTORS
         if not (x == "vm" and p.stem in NOT_IN_BYTECODE)])
def test_runtime_case(path: Path, world: Path | None, expected: Path, executor: str,
                      trace_validator, monkeypatch) -> None:
    monkeypatch.setattr(sys.modules[__name__], "EXECUTOR", executor)
    first = run_case(path, world)
    text = first.text()
    assert run_case(path, world).text() == text, "two runs of the same inputs differ"
    for event in first.events:
        errors = [e.message for e in trace_validator.iter_errors(event)]
        assert not errors, (event, errors)
    expect(expected, text)


def test_bytecode_refuses_what_no_vm_could_run() -> None:
    """The cases left out of the VM's runs are refused by code generation, with the reason."""
    from scriptc.ops.build import emit
    from scriptc.emit.codegen import CodegenError

    for name in NOT_IN_BYTECODE:
        path = RUNTIME / f"{name}.script"
        analysis = analyze_file(path, name=str(path.relative_to(CASES)))
        with pytest.raises(CodegenError, match="no block carries"):
            emit(analysis.script, "bytecode", analysis.source)


def test_every_expected_trace_has_a_case() -> None:
    wanted = {e for _, _, e in RUNS}
    stale = [p.name for p in RUNTIME.glob("*.trace.jsonl") if p not in wanted]
    assert not stale, f"expected traces without a case: {stale}"
