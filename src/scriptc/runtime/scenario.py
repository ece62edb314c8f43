"""Scenario (world) files: what happens around the robot during a run, as data. Shared by
every executor.

A scenario is JSON (`schemas/scenario.schema.json`):

    {"updates": [{"at": 500, "objectid": "Human/kid1", "attributename": "poses",
                  "policy": "R", "jsonmsg": "{\\"positionrho\\": 0.8, \\"positiontheta\\": 0}"}],
     "operator": [{"at": 1000, "command": "safety_lock", "held": true},
                  {"at": 1200, "command": "drive", "v_x": 0.2, "duration": 500},
                  {"at": 3000, "command": "interrupt"}]}

`updates` are MapUpdate messages as the thesis's Wizard-of-Oz sensors would send them (thesis
4.5, tables 4.1/4.2); `jsonmsg` is the message's text or the JSON value itself. `operator` are
the joystick's events (thesis 5.3). A file is read whole and checked before the run starts:
the shape by the JSON Schema (jsonschema is imported only here, only when a scenario is
given), then every update against the map's tables. Every problem is reported at once, with
the file and where in it (`updates[2].policy`).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from functools import cache
from typing import Any

from scriptc.runtime.world import MapUpdate, UpdateError, parse_update

SCHEMA_NAME = "scenario.schema.json"


class ScenarioError(Exception):
    """A scenario file that cannot be used: `problems` says each thing wrong."""

    def __init__(self, path: str, problems: list[str]) -> None:
        self.path = path
        self.problems = problems
        super().__init__(f"scenario `{path}`: " + "; ".join(problems))

    def lines(self) -> list[str]:
        return [f"scenario `{self.path}`: {p}" for p in self.problems]


@dataclass(frozen=True, slots=True)
class TimedUpdate:
    at: int
    update: MapUpdate
    index: int  # position in the file's `updates`


@dataclass(frozen=True, slots=True)
class OperatorEvent:
    at: int
    command: str  # "safety_lock", "drive" or "interrupt"
    params: dict
    index: int


@dataclass
class Scenario:
    path: str = ""  # as shown in traces and messages
    updates: list[TimedUpdate] = field(default_factory=list)
    operator: list[OperatorEvent] = field(default_factory=list)
    folder: str = ""  # where paths in the scenario (a `script_vect` update) are resolved from
    # Placed people, objects and obstacles, sensed by the simulation (runtime/sensing.py).
    entities: list = field(default_factory=list)  # of sensing.PlacedEntity
    sensing_rate_hz: float = 10.0
    sensing_range: float | None = None


@cache
def _validator():
    import jsonschema

    from scriptc.resources import schema_path

    schema = json.loads(schema_path(SCHEMA_NAME).read_text(encoding="utf-8"))
    return jsonschema.Draft202012Validator(schema)


def _where(steps) -> str:
    out = ""
    for step in steps:
        out += f"[{step}]" if isinstance(step, int) else (f".{step}" if out else str(step))
    return out or "the top level"


def scenario_from_data(data: Any, path: str = "<scenario>", folder: str | None = None) -> Scenario:
    """A scenario from parsed JSON; raises ScenarioError listing every problem. `folder`
    (default: the current directory) is where the scenario's paths are resolved from."""
    errors = sorted(_validator().iter_errors(data), key=lambda e: list(map(str, e.absolute_path)))
    if errors:
        problems = []
        for e in errors:
            message = e.message
            if e.validator == "false" or (e.validator is False):
                message = "not allowed here"
            problems.append(f"{_where(e.absolute_path)}: {message}")
        raise ScenarioError(path, problems)
    scenario = Scenario(path, folder=folder if folder is not None else os.getcwd())
    problems = []
    for i, item in enumerate(data.get("updates", ())):
        try:
            update = parse_update(item["objectid"], item["attributename"], item["policy"],
                                  item["jsonmsg"])
        except UpdateError as exc:
            problems.append(f"updates[{i}] (at {item['at']} ms): {exc}")
            continue
        scenario.updates.append(TimedUpdate(item["at"], update, i))
    for i, item in enumerate(data.get("operator", ())):
        params = {k: v for k, v in item.items() if k not in ("at", "command")}
        scenario.operator.append(OperatorEvent(item["at"], item["command"], params, i))
    if data.get("entities"):
        from scriptc.runtime.sensing import PlacedEntity

        for item in data["entities"]:
            scenario.entities.append(PlacedEntity.from_data(item))
    sensing = data.get("sensing", {})
    scenario.sensing_rate_hz = float(sensing.get("rate_hz", 10.0))
    scenario.sensing_range = sensing.get("range")
    if problems:
        raise ScenarioError(path, problems)
    scenario.updates.sort(key=lambda u: u.at)
    scenario.operator.sort(key=lambda o: o.at)
    return scenario


def load_scenario(path: str) -> Scenario:
    """Read and check a scenario file; raises ScenarioError (also when it cannot be read)."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except FileNotFoundError:
        raise ScenarioError(path, ["the file does not exist"]) from None
    except IsADirectoryError:
        raise ScenarioError(path, ["it is a directory, not a file"]) from None
    except OSError as exc:
        raise ScenarioError(path, [f"cannot read it: {exc.strerror or exc}"]) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError(path, [f"not UTF-8 text (byte offset {exc.start})"]) from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ScenarioError(path, [f"not JSON: {exc.msg} at line {exc.lineno}, "
                                   f"column {exc.colno}"]) from None
    return scenario_from_data(data, path, os.path.dirname(os.path.abspath(path)))
