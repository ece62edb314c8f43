"""A run as an MCAP file for Foxglove, Lichtblick and PlotJuggler (`scriptc run --trace
FILE.mcap`, docs/views.md "The run in Foxglove").

Every message is JSON (message encoding `json`) under a JSON Schema (schema encoding
`jsonschema`); the four kinds the panels know carry Foxglove's schema names and fields
(`foxglove.FrameTransform`, `foxglove.PoseInFrame`, `foxglove.SceneUpdate`, `foxglove.Log`),
the plottable channels a small schema of scriptc's own (`scriptc.Led`, `scriptc.Velocity`,
`scriptc.Distance`). The topics, in the order the file registers them:

- `/tf` (`foxglove.FrameTransform`): the robot's pose, `world` -> `base_link`, at 10 Hz
  while it moves (`POSE_EVERY_MS`);
- `/robot/pose` (`foxglove.PoseInFrame`): the same pose in `world`;
- `/robot/body` (`foxglove.SceneUpdate`): the robot's footprint, a cylinder locked to
  `base_link` (once, at 0);
- `/scene` (`foxglove.SceneUpdate`): every person (a cylinder), object (a cube) and obstacle
  the map placed, with its name, each time one moves: the whole scene each time;
- `/scene/paths` (`foxglove.SceneUpdate`): the path of each of them and the robot's, whole
  (once, at 0);
- `/log` (`foxglove.Log`): every trace event, one line each, at its `t`;
- `/robot/led` (`scriptc.Led`): the colour the LED track asks for (`r`, `g`, `b`, `on`);
- `/robot/velocity` (`scriptc.Velocity`): the wheels' velocity (`v_x`, `v_y`, `v_theta`);
- `/people/ID/distance` (`scriptc.Distance`): how far the map puts each person from the robot.

Times are simulated: a message of the instant `t` ms has `log_time = publish_time = t * 10**6`
ns, and the `timestamp` in it says the same. `/robot/led` and `/robot/velocity` hold a value
until the next, so a change at `t` is two messages at `t` (the old value, then the new one):
a plot draws a step, not a slope. The robot's pose is its recorded path (`samples`, recorded by
`runtime.recorded.PathRecorder` as for `--plot`); people and objects are where the map's `poses`
updates put them (`runtime.recorded.map_positions`, as in the picture of `--plot`).

The file is the same bytes for the same events: nothing comes from the clock (the writer's
header names `scriptc`, not the library's version), the channels and schemas are registered in
a fixed order, and the chunks are compressed with zstd, whose output depends only on its
input. The `mcap` package is imported only here, and only when a file is written.
"""

from __future__ import annotations

import io
import json
import math
import re
from collections.abc import Sequence
from typing import Any, ClassVar

from scriptc.numbers import JSONObject, json_dumps
from scriptc.runtime.recorded import Sample, footprint_radius, map_positions
from scriptc.runtime.trace import Event

# -- Foxglove's schemas (the fields of foxglove-sdk's JSON Schemas) -----------------------------

# A JSON Schema, as data.
Schema = dict[str, Any]


def _object(title: str, description: str, properties: dict[str, Schema],
            required: bool = True) -> Schema:
    schema: Schema = {"title": title, "description": description, "type": "object",
                      "properties": properties}
    if required:
        schema["required"] = list(properties)
    return schema


def _number(description: str) -> Schema:
    return {"type": "number", "description": description}


def _array(items: Schema, description: str) -> Schema:
    return {"type": "array", "items": items, "description": description}


def _time(description: str) -> Schema:
    return {"type": "object", "title": "time", "description": description,
            "properties": {"sec": {"type": "integer", "minimum": 0},
                           "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}


def _duration(description: str) -> Schema:
    return {"type": "object", "title": "duration", "description": description,
            "properties": {"sec": {"type": "integer"},
                           "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}


def _vector3(description: str) -> Schema:
    return _object("foxglove.Vector3", description,
                   {axis: _number(f"{axis} coordinate length") for axis in "xyz"})


def _point3(description: str) -> Schema:
    return _object("foxglove.Point3", description,
                   {axis: _number(f"{axis} coordinate position") for axis in "xyz"})


def _quaternion(description: str) -> Schema:
    return _object("foxglove.Quaternion", description,
                   {axis: _number(f"{axis} value") for axis in "xyzw"})


def _pose(description: str) -> Schema:
    return _object("foxglove.Pose", description, {
        "position": _vector3("Point denoting position in 3D space"),
        "orientation": _quaternion("Quaternion denoting orientation in 3D space")})


def _color(description: str) -> Schema:
    return _object("foxglove.Color", description, {
        "r": _number("Red value between 0 and 1"), "g": _number("Green value between 0 and 1"),
        "b": _number("Blue value between 0 and 1"), "a": _number("Alpha value between 0 and 1")})


def _enum(title: str, description: str, names: Sequence[str]) -> Schema:
    return {"title": title, "description": description,
            "oneOf": [{"title": name, "const": i} for i, name in enumerate(names)]}


def _indices() -> Schema:
    return _array({"type": "integer", "minimum": 0},
                  "Indices into the `points` and `colors` attribute arrays")


def _scene_entity() -> Schema:
    pose, color = _pose("Pose of the primitive"), _color("Color of the primitive")
    boolean, string = {"type": "boolean"}, {"type": "string"}
    primitives = {
        "arrows": _object("foxglove.ArrowPrimitive", "A primitive representing an arrow", {
            "pose": pose, "shaft_length": _number("Length of the arrow shaft"),
            "shaft_diameter": _number("Diameter of the arrow shaft"),
            "head_length": _number("Length of the arrow head"),
            "head_diameter": _number("Diameter of the arrow head"), "color": color}),
        "cubes": _object("foxglove.CubePrimitive",
                         "A primitive representing a cube or rectangular prism", {
                             "pose": pose, "size": _vector3("Size of the cube along each axis"),
                             "color": color}),
        "spheres": _object("foxglove.SpherePrimitive",
                           "A primitive representing a sphere or ellipsoid", {
                               "pose": pose,
                               "size": _vector3("Size (diameter) of the sphere along each axis"),
                               "color": color}),
        "cylinders": _object(
            "foxglove.CylinderPrimitive",
            "A primitive representing a cylinder, elliptic cylinder, or truncated cone", {
                "pose": pose, "size": _vector3("Size of the cylinder's bounding box"),
                "bottom_scale": _number("0-1, ratio of the diameter of the cylinder's bottom "
                                        "face (min z) to the bottom of the bounding box"),
                "top_scale": _number("0-1, ratio of the diameter of the cylinder's top face "
                                     "(max z) to the top of the bounding box"),
                "color": color}),
        "lines": _object("foxglove.LinePrimitive",
                         "A primitive representing a series of points connected by lines", {
                             "type": _enum("foxglove.LineType",
                                           "Drawing primitive to use for lines",
                                           ("LINE_STRIP", "LINE_LOOP", "LINE_LIST")),
                             "pose": pose, "thickness": _number("Line thickness"),
                             "scale_invariant": boolean,
                             "points": _array(_point3("A point"), "Points along the line"),
                             "color": color, "colors": _array(color, "Per-point colors"),
                             "indices": _indices()}),
        "triangles": _object("foxglove.TriangleListPrimitive",
                             "A primitive representing a set of triangles", {
                                 "pose": pose,
                                 "points": _array(_point3("A point"), "Vertices of triangles"),
                                 "color": color, "colors": _array(color, "Per-vertex colors"),
                                 "indices": _indices()}),
        "texts": _object("foxglove.TextPrimitive", "A primitive representing a text label", {
            "pose": pose, "billboard": boolean, "font_size": _number("Font size"),
            "scale_invariant": boolean, "color": color, "text": string}),
        "models": _object("foxglove.ModelPrimitive",
                          "A primitive representing a 3D model file", {
                              "pose": pose, "scale": _vector3("Scale factor along each axis"),
                              "color": color, "override_color": boolean, "url": string,
                              "media_type": string,
                              "data": {"type": "string", "contentEncoding": "base64"}}),
    }
    key_value = _object("foxglove.KeyValuePair", "A key with its associated value",
                        {"key": string, "value": string})
    return _object("foxglove.SceneEntity", "A visual element in a 3D scene", {
        "timestamp": _time("Timestamp of the entity"),
        "frame_id": {"type": "string", "description": "Frame of reference"},
        "id": {"type": "string", "description": "Identifier for the entity"},
        "lifetime": _duration("Length of time after which the entity is removed (0: never)"),
        "frame_locked": boolean,
        "metadata": _array(key_value, "Additional user-provided metadata"),
        **{name: _array(item, f"{name.capitalize()} primitives")
           for name, item in primitives.items()}})


def foxglove_schemas() -> dict[str, Schema]:
    """Foxglove's four schemas this file uses, by name, as JSON Schemas (the fields and
    required fields of Foxglove's published JSON Schemas)."""
    log_level = _enum("foxglove.LogLevel", "Log level",
                      ("UNKNOWN", "DEBUG", "INFO", "WARNING", "ERROR", "FATAL"))
    return {
        "foxglove.FrameTransform": _object(
            "foxglove.FrameTransform", "A transform between two reference frames in 3D space", {
                "timestamp": _time("Timestamp of transform"),
                "parent_frame_id": {"type": "string", "description": "Name of the parent frame"},
                "child_frame_id": {"type": "string", "description": "Name of the child frame"},
                "translation": _vector3("Translation component of the transform"),
                "rotation": _quaternion("Rotation component of the transform")}),
        "foxglove.PoseInFrame": _object(
            "foxglove.PoseInFrame", "A timestamped pose for an object or reference frame", {
                "timestamp": _time("Timestamp of pose"),
                "frame_id": {"type": "string", "description": "Frame of reference for pose"},
                "pose": _pose("Pose in 3D space")}),
        "foxglove.SceneUpdate": _object(
            "foxglove.SceneUpdate", "An update to the entities displayed in a 3D scene", {
                "deletions": _array(_object(
                    "foxglove.SceneEntityDeletion", "Command to remove previously published "
                    "entities", {
                        "timestamp": _time("Timestamp of the deletion"),
                        "type": _enum("foxglove.SceneEntityDeletionType",
                                      "Type of deletion action to perform",
                                      ("MATCHING_ID", "ALL")),
                        "id": {"type": "string", "description": "Identifier of the entity"}}),
                    "Scene entities to delete"),
                "entities": _array(_scene_entity(), "Scene entities to add or replace")}),
        "foxglove.Log": _object("foxglove.Log", "A log message", {
            "timestamp": _time("Timestamp of log message"), "level": log_level,
            "message": {"type": "string", "description": "Log message"},
            "name": {"type": "string", "description": "Process or node name"},
            "file": {"type": "string", "description": "Filename"},
            "line": {"type": "integer", "minimum": 0, "description": "Line number in the file"}}),
    }


def _numbers(title: str, description: str, fields: dict[str, str]) -> Schema:
    return _object(title, description, {name: _number(text) for name, text in fields.items()})


# scriptc's own schemas, for the plottable channels: numbers only.
OWN_SCHEMAS: dict[str, Schema] = {
    "scriptc.Led": _numbers("scriptc.Led", "The colour the LED track asks for (0 to 1 each; "
                            "all 0 and `on` 0 when off)",
                            {"r": "red", "g": "green", "b": "blue", "on": "1 lit, 0 off"}),
    "scriptc.Velocity": _numbers("scriptc.Velocity", "The wheels' velocity in the body frame", {
        "v_x": "forward, m/s", "v_y": "to the left, m/s", "v_theta": "turning, rad/s"}),
    "scriptc.Distance": _numbers("scriptc.Distance", "How far the map puts a person from the "
                                 "robot", {"distance": "metres"}),
}

# Foxglove's log levels.
DEBUG, INFO, WARNING, ERROR = 1, 2, 3, 4

# The level of a trace event in the log: what the run did as INFO, what each track and the map
# did second by second as DEBUG, what went wrong as WARNING or ERROR.
_DEBUG_KINDS = frozenset(("cmd_start", "cmd_stop", "block_done", "update", "velocity", "rule",
                          "mutex", "sensor"))

_ROBOT_COLOUR = (0.12, 0.47, 0.71)
# The look of each positioned class: the shape, its size (x, y, z in metres) and colour; the
# colours are those of `--plot`.
_LOOKS: dict[str, tuple[str, tuple[float, float, float], tuple[float, float, float]]] = {
    "Human": ("cylinders", (0.3, 0.3, 1.1), (0.84, 0.15, 0.16)),
    "Object": ("cubes", (0.2, 0.2, 0.2), (0.17, 0.63, 0.17)),
    "Obstacle": ("cubes", (0.4, 0.4, 0.5), (0.33, 0.33, 0.33)),
}
_OTHER_LOOK = ("cubes", (0.2, 0.2, 0.2), (0.58, 0.4, 0.74))


def level(event: Event) -> int:
    """The log level of a trace event: errors ERROR; a governor's clamp, an operator's command
    ignored, a goal interrupted or failed, a run interrupted WARNING; a track's commands, the
    map's updates, the rules' messages and the wheels DEBUG; the rest INFO."""
    kind = event["event"]
    if kind == "error" or (kind == "session_end" and event.get("outcome") == "error"):
        return ERROR
    if (kind == "governor" or (kind == "operator" and event.get("ignored"))
            or (kind == "goal" and event.get("record") != "reached")
            or (kind == "session_end" and event.get("outcome") == "interrupted")):
        return WARNING
    return DEBUG if kind in _DEBUG_KINDS else INFO


def _stamp(t_ms: int) -> JSONObject:
    return {"sec": t_ms // 1000, "nsec": (t_ms % 1000) * 1_000_000}


def _rotation(theta: float) -> JSONObject:
    return {"x": 0.0, "y": 0.0, "z": math.sin(theta / 2), "w": math.cos(theta / 2)}


def _pose_json(x: float, y: float, z: float, theta: float = 0.0) -> JSONObject:
    return {"position": {"x": x, "y": y, "z": z}, "orientation": _rotation(theta)}


def _rgba(colour: tuple[float, float, float], a: float = 1.0) -> JSONObject:
    return {"r": colour[0], "g": colour[1], "b": colour[2], "a": a}


def _entity(t_ms: int, frame: str, entity_id: str, **primitives: list[JSONObject]) -> JSONObject:
    entity: JSONObject = {
        "timestamp": _stamp(t_ms), "frame_id": frame, "id": entity_id,
        "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": frame != "world", "metadata": []}
    for name in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts",
                 "models"):
        entity[name] = primitives.get(name, [])
    return entity


def _shape(kind: str, size: tuple[float, float, float], colour: tuple[float, float, float],
           x: float, y: float) -> JSONObject:
    shape: JSONObject = {"pose": _pose_json(x, y, size[2] / 2),
                         "size": {"x": size[0], "y": size[1], "z": size[2]},
                         "color": _rgba(colour)}
    if kind == "cylinders":
        shape["bottom_scale"] = shape["top_scale"] = 1.0
    return shape


def _label(text: str, x: float, y: float, z: float) -> JSONObject:
    return {"pose": _pose_json(x, y, z), "billboard": True, "font_size": 14.0,
            "scale_invariant": True, "color": _rgba((0.1, 0.1, 0.1)), "text": text}


def _line(points: Sequence[tuple[float, float]], colour: tuple[float, float, float]
          ) -> JSONObject:
    return {"type": 0, "pose": _pose_json(0.0, 0.0, 0.0), "thickness": 0.02,
            "scale_invariant": False,
            "points": [{"x": x, "y": y, "z": 0.01} for x, y in points],
            "color": _rgba(colour, 0.8), "colors": [], "indices": []}


def _thing(t_ms: int, objectid: str, x: float, y: float) -> JSONObject:
    """A person, object or obstacle at (x, y): its shape and its name above it."""
    kind, size, colour = _LOOKS.get(objectid.partition("/")[0], _OTHER_LOOK)
    return _entity(t_ms, "world", objectid, texts=[_label(objectid, x, y, size[2] + 0.15)],
                   **{kind: [_shape(kind, size, colour, x, y)]})


class _Things:
    """The scene's entities as JSON text, from one template per entity (its look and name do
    not change, only where it is and when): a scene of 10 messages a second for ten minutes
    is mostly these."""

    # Where the template has each value: a string no message holds ("\0x": a control
    # character is always escaped in JSON).
    _SLOTS: ClassVar[dict[str, str]] = {
        "x": '"\\u0000x"', "y": '"\\u0000y"', "sec": '"\\u0000s"', "nsec": '"\\u0000n"'}

    def __init__(self) -> None:
        self.templates: dict[str, str] = {}

    def text(self, t_ms: int, objectid: str, x: float, y: float) -> str:
        template = self.templates.get(objectid)
        if template is None:
            entity = _thing(0, objectid, "\0x", "\0y")  # type: ignore[arg-type]  # slots
            entity["timestamp"] = {"sec": "\0s", "nsec": "\0n"}
            template = self.templates[objectid] = _dumps(entity)
        slots = self._SLOTS
        return (template.replace(slots["x"], _real(x)).replace(slots["y"], _real(y))
                .replace(slots["sec"], str(t_ms // 1000))
                .replace(slots["nsec"], str((t_ms % 1000) * 1_000_000)))


_TOPIC_NAME = re.compile(r"[^A-Za-z0-9_-]")


def person_topic(objectid: str) -> str:
    """The topic of a person's distance: `Human/kid1` -> `/people/kid1/distance` (a character
    a topic name should not hold becomes `_`)."""
    return f"/people/{_TOPIC_NAME.sub('_', objectid.partition('/')[2])}/distance"


class _File:
    """The messages of the file, gathered before they are written: (t, channel, data)."""

    def __init__(self) -> None:
        self.channels: list[tuple[str, str]] = []  # (topic, schema name), in order
        self.messages: list[tuple[int, int, bytes]] = []

    def channel(self, topic: str, schema: str) -> int:
        self.channels.append((topic, schema))
        return len(self.channels) - 1

    def add(self, t_ms: int, channel: int, message: JSONObject) -> None:
        self.add_text(t_ms, channel, _dumps(message))

    def add_text(self, t_ms: int, channel: int, text: str) -> None:
        """A message already written as JSON text (the many of the pose and the log)."""
        self.messages.append((t_ms, channel, text.encode("utf-8")))


# One encoder for the file's 100,000 messages (json.dumps would make one per message).
_ENCODER = json.JSONEncoder(ensure_ascii=False, separators=(",", ":"), allow_nan=False)
_string = json.encoder.encode_basestring  # a text as a JSON string, non-ASCII kept


def _dumps(value: object) -> str:
    try:
        return _ENCODER.encode(value)
    except ValueError:  # a number that is not finite: the number policy's error names it
        return json_dumps(value)


def _real(x: float) -> str:
    """A coordinate as JSON writes it (Python's shortest repr), never NaN or an infinity."""
    return repr(float(x)) if math.isfinite(x) else json_dumps(x)


def _steps(out: _File, channel: int, changes: list[tuple[int, JSONObject]]) -> None:
    """A value held until the next: each change as the old value and the new at its time (a
    step in a plot); the value of an instant is its last (a LED command stopped and the next
    started at the same millisecond is no change)."""
    last: JSONObject | None = None
    by_instant: dict[int, JSONObject] = {}
    for t, value in changes:
        by_instant[t] = value
    for t, value in by_instant.items():
        if value == last:
            continue
        if last is not None:
            out.add(t, channel, last)
        out.add(t, channel, value)
        last = value


def _led_changes(events: Sequence[Event]) -> list[tuple[int, JSONObject]]:
    off: JSONObject = {"r": 0.0, "g": 0.0, "b": 0.0, "on": 0}
    changes = [(0, off)]
    for e in events:
        if e["event"] == "cmd_start" and e.get("track") == "led":
            command = e["command"]
            lit = command.get("turnas") == 1
            changes.append((e["t"], {"r": float(command["r"]), "g": float(command["g"]),
                                     "b": float(command["b"]), "on": 1} if lit else off))
        elif e["event"] == "cmd_stop" and e.get("track") == "led":
            changes.append((e["t"], off))
    return changes


def _velocity_changes(events: Sequence[Event]) -> list[tuple[int, JSONObject]]:
    changes: list[tuple[int, JSONObject]] = [(0, {"v_x": 0.0, "v_y": 0.0, "v_theta": 0.0})]
    changes += [(e["t"], {"v_x": float(e["v_x"]), "v_y": float(e["v_y"]),
                          "v_theta": float(e["v_theta"])})
                for e in events if e["event"] == "velocity"]
    return changes


# The robot's pose in the file: a sample every 100 ms (10 Hz, the simulated sensor's default
# rate, at which the people move in the scene) of the recorded path (every 20 ms) while it
# moves; a still robot is its first and last sample still (nothing between them for a plot or
# the 3D panel to move it through). The end of the run is always a sample.
POSE_EVERY_MS = 100


def _poses(samples: Sequence[Sample]) -> list[Sample]:
    """The samples of the file's pose: those at a multiple of `POSE_EVERY_MS` and the last,
    less those where the robot was still between two still ones."""
    grid = [s for i, s in enumerate(samples)
            if s[0] % POSE_EVERY_MS == 0 or i == len(samples) - 1]
    return [s for i, s in enumerate(grid)
            if i in (0, len(grid) - 1) or s[1:] != grid[i - 1][1:] or s[1:] != grid[i + 1][1:]]


def _log(event: Event, scripts: dict[str, str]) -> str:
    """A trace event as a log line (JSON text): the kind as its name, the other fields as the
    message (the event's JSON without `t` and `event`), the script's file when the event names
    a script."""
    t = event["t"]
    fields = _dumps({key: value for key, value in event.items() if key not in ("t", "event")})
    script = event.get("script")
    file = scripts.get(script, "") if isinstance(script, str) else ""
    return (f'{{"timestamp":{{"sec":{t // 1000},"nsec":{(t % 1000) * 1_000_000}}},'
            f'"level":{level(event)},"message":{_string(fields)},'
            f'"name":{_string(str(event["event"]))},"file":{_string(file)},"line":0}}')


def _pose_texts(t: int, x: float, y: float, theta: float) -> tuple[str, str]:
    """The robot's pose at `t` as a `foxglove.FrameTransform` and a `foxglove.PoseInFrame`
    (JSON text: they are most of the file's messages)."""
    stamp = f'{{"sec":{t // 1000},"nsec":{(t % 1000) * 1_000_000}}}'
    position = f'{{"x":{_real(x)},"y":{_real(y)},"z":0.0}}'
    z, w = _real(math.sin(theta / 2)), _real(math.cos(theta / 2))
    rotation = f'{{"x":0.0,"y":0.0,"z":{z},"w":{w}}}'
    transform = (f'{{"timestamp":{stamp},"parent_frame_id":"world",'
                 f'"child_frame_id":"base_link","translation":{position},"rotation":{rotation}}}')
    in_frame = (f'{{"timestamp":{stamp},"frame_id":"world","pose":{{"position":{position},'
                f'"orientation":{rotation}}}}}')
    return transform, in_frame


def messages(events: Sequence[Event], samples: Sequence[Sample]
             ) -> tuple[list[tuple[str, str]], list[tuple[int, int, bytes]]]:
    """The channels of the file ((topic, schema name) by channel index) and its messages ((t
    ms, channel index, JSON bytes)), in time order (a stable sort: at one time, in the order
    of the channels, then as they were made)."""
    out = _File()
    tf = out.channel("/tf", "foxglove.FrameTransform")
    pose = out.channel("/robot/pose", "foxglove.PoseInFrame")
    body = out.channel("/robot/body", "foxglove.SceneUpdate")
    scene = out.channel("/scene", "foxglove.SceneUpdate")
    paths = out.channel("/scene/paths", "foxglove.SceneUpdate")
    log = out.channel("/log", "foxglove.Log")
    led = out.channel("/robot/led", "scriptc.Led")
    velocity = out.channel("/robot/velocity", "scriptc.Velocity")

    for t, x, y, theta in _poses(samples):
        transform, in_frame = _pose_texts(t, x, y, theta)
        out.add_text(t, tf, transform)
        out.add_text(t, pose, in_frame)

    radius = footprint_radius()
    size = (2 * radius, 2 * radius, 0.3)
    out.add(0, body, {"deletions": [], "entities": [_entity(
        0, "base_link", "robot", cylinders=[_shape("cylinders", size, _ROBOT_COLOUR, 0.0, 0.0)],
        arrows=[{"pose": _pose_json(0.0, 0.0, 0.32), "shaft_length": radius,
                 "shaft_diameter": 0.03, "head_length": 0.08, "head_diameter": 0.07,
                 "color": _rgba((1.0, 1.0, 1.0))}])]})

    placed, _no_position = map_positions(events, samples)
    where: dict[str, tuple[float, float]] = {}
    things = _Things()
    moves = sorted((t, i, j, objectid, x, y) for i, (objectid, path) in enumerate(placed.items())
                   for j, (t, x, y) in enumerate(path))
    for i, (t, _i, _j, objectid, x, y) in enumerate(moves):
        where[objectid] = (x, y)
        if i + 1 == len(moves) or moves[i + 1][0] != t:
            out.add_text(t, scene, '{"deletions":[],"entities":[' + ",".join(
                things.text(t, name, *xy) for name, xy in where.items()) + "]}")
    lines = [_entity(0, "world", f"path:{objectid}", lines=[_line(
        [(x, y) for _t, x, y in path], _LOOKS.get(objectid.partition("/")[0], _OTHER_LOOK)[2])])
        for objectid, path in placed.items()]
    lines.append(_entity(0, "world", "path:robot",
                         lines=[_line([(s[1], s[2]) for s in _poses(samples)], _ROBOT_COLOUR)]))
    out.add(0, paths, {"deletions": [], "entities": lines})

    scripts = {e["script"]: e["path"] for e in events if e["event"] == "script_load"}
    for event in events:
        out.add_text(event["t"], log, _log(event, scripts))
    _steps(out, led, _led_changes(events))
    _steps(out, velocity, _velocity_changes(events))

    people: dict[str, int] = {}
    for e in events:
        value = e.get("value")
        if (e["event"] == "update" and e.get("status") == "applied"
                and e.get("attributename") == "poses" and isinstance(value, dict)
                and e.get("objectid", "").startswith("Human/")
                and isinstance(value.get("positionrho"), (int, float))):
            objectid = e["objectid"]
            if objectid not in people:
                people[objectid] = out.channel(person_topic(objectid), "scriptc.Distance")
            out.add(e["t"], people[objectid], {"distance": float(value["positionrho"])})

    out.messages.sort(key=lambda m: m[0])
    return out.channels, out.messages


def write_mcap(events: Sequence[Event], samples: Sequence[Sample]) -> bytes:
    """The MCAP file of a run, as bytes: its trace's `events` and the robot's path (`samples`,
    `(t, x, y, theta)` as `runtime.recorded.PathRecorder` records them)."""
    from mcap.writer import CompressionType, Writer

    channels, timed = messages(events, samples)
    schemas: dict[str, Schema] = {**foxglove_schemas(), **OWN_SCHEMAS}
    stream = io.BytesIO()
    writer = Writer(stream, compression=CompressionType.ZSTD)
    # The library's name and version would otherwise go into the header: the bytes would
    # change with the version of `mcap` installed.
    writer.start(profile="", library="scriptc")
    schema_ids: dict[str, int] = {}
    for _topic, name in channels:
        if name not in schema_ids:
            data = json_dumps(schemas[name], separators=(",", ":")).encode("utf-8")
            schema_ids[name] = writer.register_schema(name=name, encoding="jsonschema",
                                                      data=data)
    ids = [writer.register_channel(topic=topic, message_encoding="json",
                                   schema_id=schema_ids[name]) for topic, name in channels]
    for t, channel, data in timed:
        ns = t * 1_000_000
        writer.add_message(channel_id=ids[channel], log_time=ns, data=data, publish_time=ns)
    writer.finish()  # type: ignore[no-untyped-call]  # mcap's finish() has no annotations
    return stream.getvalue()
