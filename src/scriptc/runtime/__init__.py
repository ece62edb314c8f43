"""The runtime: scripts running in simulated time (docs/runtime.md; thesis 4.2).

Shared by every executor (what a bytecode VM reuses as it is):

- `clock`       the event queue (simulated ms, heapq; no wall clock)
- `commands`    plain run-time values (commands, positions, rule messages), number/text compare
- `world`       the map: entities, robot status, script info; MapUpdate with R/A policies
- `bindings`    aliases (one per entity), VARs, ATTs and their scopes U/T/L
- `functions`   B/F/E implementations and the registration API for an activity's own
- `evaluate`    condition evaluation: `EvalContext` primitives, and the IR evaluator
- `rules`       the chain's actions (A R D B C), the rule library by rulecode, `RuleContext`
                (what a body may do, through a `RuleHost`)
- `actuators`   track timing, outputs, the operator's joystick
- `robots/`     robot backends (`kinematic`, `mujoco`)
- `scenario`    world files: timed MapUpdates and operator events
- `trace`       JSON-lines traces
- `session`     the wiring of the jobs below into one run (`Session`)
- `loop`        the event loop: the instants and the order of each (thesis 4.2); `RunResult`
- `scripts`     the LIFO, `idle_activity` (`idle`), loading, unloading and block reading
- `sink`        what an executor reports while reading (the `ReadSink`)
- `goals`       goal records and `goalreached`
- `mutex`       the chain of rules: alfa/omega hand-over, the lock, the chain pass
- `overrides`   compulsory script switches and `Script/script_vect`
- `updates`     map updates posted and applied
- `operator`    the operator's joystick (thesis 5.3)
- `status`      the instant under way, the end, the problems (the registry's run-time codes)
- `loading`     `Loader`, the protocol by which a session loads a script met by path
- `idle`        `idle_activity`, built as IR
- `configured`  a repository's own functions and rules, registered beside the standard ones
- `governor`    the safety governor between the actuators and the robot
- `sensing`     simulated perception of the scenario's people, objects and obstacles
- `summary`     what `scriptc run` prints; `plot` its `--plot` picture (matplotlib)

Executor-specific (one per way of reading a script's blocks; `executor.py` is the contract):

- `interp`      the reference interpreter over the IR (the executable spec)
- `vm`          the bytecode VM over a verified program (what `scriptc run` uses)

Nothing here imports `scriptc.ops` or the CLI: `scriptc run` (`scriptc.ops.programs`, cli/run.py)
builds the programs and hands the session a loader (`loading.Loader`) for scripts met by path.
"""

from __future__ import annotations

_EXPORTS = {
    "Session": "scriptc.runtime.session",
    "RunResult": "scriptc.runtime.loop",
    "LoadError": "scriptc.runtime.loading",
    "Loader": "scriptc.runtime.loading",
    "IRProgram": "scriptc.runtime.interp",
    "Trace": "scriptc.runtime.trace",
    "load_scenario": "scriptc.runtime.scenario",
    "scenario_from_data": "scriptc.runtime.scenario",
    "scenario_from_text": "scriptc.runtime.scenario",
    "ScenarioError": "scriptc.runtime.scenario",
    "Implementations": "scriptc.runtime.functions",
    "STANDARD_IMPLEMENTATIONS": "scriptc.runtime.functions",
    "RuleLibrary": "scriptc.runtime.rules",
    "STANDARD_RULES": "scriptc.runtime.rules",
    "Rule": "scriptc.runtime.rules",
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> object:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'scriptc.runtime' has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(module), name)
