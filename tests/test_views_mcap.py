"""`scriptc run --trace FILE.mcap` (views/mcap.py): the file read back with the `mcap` package's
own reader, as Foxglove, Lichtblick and PlotJuggler read it: Foxglove's schema names with
JSON Schemas, every message valid against the schema its channel embeds, one log line per
trace event at the event's time, every time simulated and in order, the same bytes for the
same run; `--trace -` and `--trace FILE.jsonl` keep JSON lines."""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import jsonschema
import pytest
from click.testing import CliRunner
from mcap.reader import make_reader

from scriptc.analysis.analyze import analyze_file
from scriptc.cli.main import cli
from scriptc.robot.profile import DEFAULT_PROFILE
from scriptc.runtime.interp import IRProgram
from scriptc.runtime.recorded import PathRecorder
from scriptc.runtime.robots import make_robot
from scriptc.runtime.scenario import load_scenario
from scriptc.runtime.session import Session
from scriptc.runtime.trace import Trace
from scriptc.views.mcap import ERROR, WARNING, level, person_topic, write_mcap

ROOT = Path(__file__).parent.parent
EXAMPLES = ROOT / "examples"
CASES = ROOT / "tests" / "cases" / "runtime"
FOXGLOVE = ("foxglove.FrameTransform", "foxglove.PoseInFrame", "foxglove.SceneUpdate",
            "foxglove.Log")


def run_example(name: str):
    """An example with its world, run as `scriptc run` runs it (the governor on) on the
    kinematic robot, its path recorded: (events, samples)."""
    shown = f"examples/{name}.script"
    analysis = analyze_file(EXAMPLES / f"{name}.script", name=shown)
    assert analysis.script is not None
    recorder = PathRecorder(make_robot("kinematic"))
    trace = Trace()
    session = Session([IRProgram(analysis.script, shown)], robot=recorder, trace=trace,
                      scenario=load_scenario(str(EXAMPLES / f"{name}.world.json")),
                      profile=DEFAULT_PROFILE)
    session.run(3_600_000)
    return trace.events, recorder.samples


def read(data: bytes):
    """(schemas by channel topic, [(topic, log_time, publish_time, decoded JSON)], summary)."""
    reader = make_reader(io.BytesIO(data))
    out = []
    for schema, channel, message in reader.iter_messages(log_time_order=False):
        assert schema is not None and schema.encoding == "jsonschema"
        assert channel.message_encoding == "json"
        out.append((channel.topic, message.log_time, message.publish_time,
                    json.loads(message.data)))
    summary = reader.get_summary()
    assert summary is not None
    schemas = {c.topic: summary.schemas[c.schema_id] for c in summary.channels.values()}
    return schemas, out, summary


@pytest.fixture(scope="module")
def approach():
    events, samples = run_example("approach")
    return events, samples, write_mcap(events, samples)


def test_the_channels_carry_foxglove_schema_names(approach) -> None:
    _events, _samples, data = approach
    schemas, _messages, _summary = read(data)
    names = {topic: schema.name for topic, schema in schemas.items()}
    assert names == {
        "/tf": "foxglove.FrameTransform", "/robot/pose": "foxglove.PoseInFrame",
        "/robot/body": "foxglove.SceneUpdate", "/scene": "foxglove.SceneUpdate",
        "/scene/paths": "foxglove.SceneUpdate", "/log": "foxglove.Log",
        "/robot/led": "scriptc.Led", "/robot/velocity": "scriptc.Velocity",
        "/people/kid1/distance": "scriptc.Distance"}
    for schema in schemas.values():
        body = json.loads(schema.data)
        assert body["type"] == "object" and body["title"] == schema.name
        jsonschema.Draft202012Validator.check_schema(body)
    # The fields the panels read, as Foxglove's schemas name them.
    transform = json.loads(schemas["/tf"].data)
    assert set(transform["properties"]) == {"timestamp", "parent_frame_id", "child_frame_id",
                                            "translation", "rotation"}
    entity = json.loads(schemas["/scene"].data)["properties"]["entities"]["items"]
    assert {"cylinders", "cubes", "lines", "texts"} <= set(entity["properties"])
    log = json.loads(schemas["/log"].data)
    assert [c["title"] for c in log["properties"]["level"]["oneOf"]] == [
        "UNKNOWN", "DEBUG", "INFO", "WARNING", "ERROR", "FATAL"]


def test_every_message_is_valid_against_its_channels_schema(approach) -> None:
    _events, _samples, data = approach
    schemas, messages, _summary = read(data)
    validators = {topic: jsonschema.Draft202012Validator(json.loads(schema.data))
                  for topic, schema in schemas.items()}
    for topic, _log_time, _publish_time, message in messages:
        validators[topic].validate(message)


def test_one_log_line_per_event_at_the_events_time(approach) -> None:
    events, _samples, data = approach
    _schemas, messages, summary = read(data)
    lines = [(log_time, publish_time, message) for topic, log_time, publish_time, message
             in messages if topic == "/log"]
    assert len(lines) == len(events)
    for event, (log_time, publish_time, message) in zip(events, lines, strict=True):
        assert log_time == publish_time == event["t"] * 1_000_000
        stamp = message["timestamp"]
        assert stamp["sec"] * 1_000_000_000 + stamp["nsec"] == log_time
        assert message["name"] == event["event"]
        assert json.loads(message["message"]) == {k: v for k, v in event.items()
                                                  if k not in ("t", "event")}
    (log_channel,) = [c.id for c in summary.channels.values() if c.topic == "/log"]
    assert summary.statistics.channel_message_counts[log_channel] == len(events)


def test_times_are_simulated_and_in_order(approach) -> None:
    events, _samples, data = approach
    _schemas, messages, summary = read(data)
    times = [log_time for _topic, log_time, _publish, _message in messages]
    assert times == sorted(times)
    assert all(log_time == publish for _t, log_time, publish, _m in messages)
    assert summary.statistics.message_start_time == 0
    end = events[-1]
    assert end["event"] == "session_end"
    assert summary.statistics.message_end_time == max(end["t"], end.get("at_rest_ms", 0)) * 10**6
    for _topic, log_time, _publish, message in messages:
        if "timestamp" in message:
            stamp = message["timestamp"]
            assert stamp["sec"] * 1_000_000_000 + stamp["nsec"] == log_time


def test_the_robots_pose_is_the_recorded_path(approach) -> None:
    events, _samples, data = approach
    _schemas, messages, _summary = read(data)
    transforms = [m for topic, _t, _p, m in messages if topic == "/tf"]
    poses = [m for topic, _t, _p, m in messages if topic == "/robot/pose"]
    assert len(transforms) == len(poses) >= 2
    assert {(m["parent_frame_id"], m["child_frame_id"]) for m in transforms} == {
        ("world", "base_link")}
    last = transforms[-1]
    end = events[-1]["pose"]
    assert last["translation"]["x"] == pytest.approx(end["x"])
    assert last["translation"]["y"] == pytest.approx(end["y"])
    rotation = last["rotation"]
    assert 2 * math.atan2(rotation["z"], rotation["w"]) == pytest.approx(end["theta"], abs=1e-9)
    # the robot stepped towards the child: its x grows
    assert last["translation"]["x"] > 0.5
    assert poses[-1]["pose"]["position"]["x"] == last["translation"]["x"]


def test_people_are_in_the_scene_with_their_paths_and_distances(approach) -> None:
    events, _samples, data = approach
    _schemas, messages, _summary = read(data)
    scenes = [m for topic, _t, _p, m in messages if topic == "/scene"]
    assert scenes
    (kid,) = scenes[-1]["entities"]
    assert kid["id"] == "Human/kid1" and kid["frame_id"] == "world"
    assert len(kid["cylinders"]) == 1 and kid["texts"][0]["text"] == "Human/kid1"
    (paths,) = [m for topic, _t, _p, m in messages if topic == "/scene/paths"]
    ids = [entity["id"] for entity in paths["entities"]]
    assert ids == ["path:Human/kid1", "path:robot"]
    assert len(paths["entities"][0]["lines"][0]["points"]) == len(scenes)
    distances = [(t, m["distance"]) for topic, t, _p, m in messages
                 if topic == "/people/kid1/distance"]
    sent = [(e["t"] * 1_000_000, e["value"]["positionrho"]) for e in events
            if e["event"] == "update" and e["objectid"] == "Human/kid1"
            and "positionrho" in e["value"] and e["status"] == "applied"]
    assert distances == sent


def test_led_and_velocity_are_steps(approach) -> None:
    events, _samples, data = approach
    _schemas, messages, _summary = read(data)
    velocity = [(t // 1_000_000, m) for topic, t, _p, m in messages if topic == "/robot/velocity"]
    assert velocity[0] == (0, {"v_x": 0.0, "v_y": 0.0, "v_theta": 0.0})
    changed = [e for e in events if e["event"] == "velocity"]
    first = changed[0]
    # at the first change: the value before it, then the new one, at the same time
    at = [m for t, m in velocity if t == first["t"]]
    assert at == [{"v_x": 0.0, "v_y": 0.0, "v_theta": 0.0},
                  {"v_x": first["v_x"], "v_y": first["v_y"], "v_theta": first["v_theta"]}]
    leds = [(t // 1_000_000, m) for topic, t, _p, m in messages if topic == "/robot/led"]
    # lit from 0 (the value of an instant is its last), dark at the end
    start = next(e["command"] for e in events if e["event"] == "cmd_start"
                 and e["track"] == "led")
    assert leds[0] == (0, {"r": start["r"], "g": start["g"], "b": start["b"], "on": 1})
    assert leds[-1][1] == {"r": 0.0, "g": 0.0, "b": 0.0, "on": 0}


def test_the_same_run_writes_the_same_bytes(approach) -> None:
    _events, _samples, data = approach
    events, samples = run_example("approach")
    assert write_mcap(events, samples) == data
    assert b"mcap-python" not in data  # no library version in the header


def test_levels_say_what_went_wrong() -> None:
    assert level({"t": 0, "event": "error", "code": "no-progress", "message": "",
                  "fatal": True}) == ERROR
    assert level({"t": 0, "event": "governor", "reasons": ["speed"]}) == WARNING
    assert level({"t": 0, "event": "operator", "command": "drive", "ignored": True}) == WARNING
    assert level({"t": 0, "event": "session_end", "outcome": "error"}) == ERROR
    assert level({"t": 0, "event": "cmd_start"}) < level({"t": 0, "event": "goal",
                                                         "record": "reached"})
    assert person_topic("Human/kid 1") == "/people/kid_1/distance"


@pytest.mark.parametrize("case", ["governed_ramps", "no_progress", "operator", "safety_stop"])
def test_traces_of_the_runtime_cases_make_valid_files(case: str) -> None:
    """Governor clamps, a fatal error, the operator, the safety stop: every message valid, the
    log's levels as the events say."""
    events = [json.loads(line) for line in
              (CASES / f"{case}.trace.jsonl").read_text(encoding="utf-8").splitlines()]
    data = write_mcap(events, [(0, 0.0, 0.0, 0.0)])
    schemas, messages, _summary = read(data)
    validators = {topic: jsonschema.Draft202012Validator(json.loads(schema.data))
                  for topic, schema in schemas.items()}
    logs = []
    for topic, _t, _p, message in messages:
        validators[topic].validate(message)
        if topic == "/log":
            logs.append(message)
    assert len(logs) == len(events)
    for event, line in zip(events, logs, strict=True):
        if event["event"] == "error":
            assert line["level"] == ERROR
        if event["event"] == "governor":
            assert line["level"] == WARNING


SCRIPT = """[wiggle]
[goal:g]
  [action]
    [b##blk_inst: MV("0.2, 0, 0.5, 0, 600") LD("0, 0, 1, 1, 0, 600") AO()]
    [b##blk_terminus]
"""


def cli_run(tmp_path: Path, trace: str):
    (tmp_path / "w.script").write_text(SCRIPT, encoding="utf-8")
    return CliRunner().invoke(cli, ["run", str(tmp_path / "w.script"), "--robot", "kinematic",
                                    "--trace", trace], catch_exceptions=False)


def test_cli_writes_mcap_when_the_file_ends_in_mcap(tmp_path: Path) -> None:
    for name in ("run.mcap", "RUN.MCAP"):
        result = cli_run(tmp_path, str(tmp_path / name))
        assert result.exit_code == 0, result.output
        data = (tmp_path / name).read_bytes()
        assert data.startswith(b"\x89MCAP0\r\n")
        assert f"trace: {tmp_path / name}" in result.output
        _schemas, messages, _summary = read(data)
        topics = {topic for topic, *_rest in messages}
        assert {"/tf", "/log", "/robot/led", "/robot/velocity"} <= topics
    assert (tmp_path / "run.mcap").read_bytes() == (tmp_path / "RUN.MCAP").read_bytes()


def test_cli_keeps_json_lines_otherwise(tmp_path: Path) -> None:
    result = cli_run(tmp_path, str(tmp_path / "run.jsonl"))
    assert result.exit_code == 0, result.output
    lines = (tmp_path / "run.jsonl").read_text(encoding="utf-8").splitlines()
    assert json.loads(lines[0])["event"] == "session_start"
    result = cli_run(tmp_path, "-")
    assert result.exit_code == 0
    assert json.loads(result.stdout.splitlines()[0])["event"] == "session_start"


def test_cli_refuses_an_mcap_file_in_a_missing_folder_before_the_run(tmp_path: Path) -> None:
    result = cli_run(tmp_path, str(tmp_path / "nowhere" / "run.mcap"))
    assert result.exit_code == 2
    assert "Traceback" not in result.output and "run.mcap" in result.output


@pytest.mark.slow
def test_mcap_is_imported_only_for_an_mcap_file(tmp_path: Path) -> None:
    import subprocess
    import sys

    (tmp_path / "w.script").write_text(SCRIPT, encoding="utf-8")
    probe = ("import sys\nfrom click.testing import CliRunner\nfrom scriptc.cli.main import cli\n"
             "for name in sys.argv[1:]:\n"
             "    CliRunner().invoke(cli, ['run', 'w.script', '--robot', 'kinematic', "
             "'--trace', name])\n"
             "    print(name, 'mcap' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", probe, "run.jsonl", "run.mcap"], cwd=tmp_path,
                          capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:2] == ["run.jsonl False", "run.mcap True"]
