"""The world model: the map of thesis 4.1 and the MapUpdate messages of thesis 4.5.

Shared by every executor. The map holds

- the entities conditions can name: Humans, Obstacles, Objects (each with a fixed unique id,
  updatable fields such as `positionrho`, and append-only histories of their `poses` and
  `tracking` updates), and the Activities being tracked (one per script loaded);
- cameras and sonars (updatable fields only);
- the robot status (`RobotStatus`: battery, goal records, the history of what the actuators
  did) and the script info (`ScriptInfo`: where the block reader is, the block about to be
  issued, the `changed` and override flags, the LIFO of scripts).

Sensors change the map only through `MapUpdate`s (`objectid` `Class/ID`, `attributename`,
`policy`, `jsonmsg`; tables 4.1 and 4.2, `ATTRIBUTES` below). An update for an unknown id
creates the entity. Updates are *posted* when they arrive and *applied* at step 4 of the loop;
policy `R` drops the not-yet-applied updates of the same attribute of the same object posted
before it, `A` queues behind them (thesis 4.5). Updatable fields keep the latest value;
append-only attributes also go into a circular register of the last `HISTORY` values.

Candidates of a class are ordered oldest first (earliest `appearanceon`, then the earliest
created; an entity with no `appearanceon` yet counts from the map time it was created), the
order in which a CLASS assignment tries them (thesis 4.3). The order is cached per class and
rebuilt only when an entity is created or its `appearanceon` changes.
"""

from __future__ import annotations

import difflib
import json
import re
from collections import deque
from collections.abc import Collection, Iterable
from dataclasses import dataclass, field

from scriptc.frontend.jsonpos import JsonError, JsonNode, parse_json
from scriptc.numbers import JSONObject, JSONValue, number_problem, whole_number
from scriptc.runtime.commands import BlockCommands
from scriptc.source import Span

_WHOLE = re.compile(r"[+-]?[0-9]+")

# What the map holds: a jsonmsg as `_type_ok` converted it (a value of the attribute's kind, a
# record of them, or for `audioin` any JSON), read by conditions, rules and functions as the
# tables below say it is. It comes from JSON, and is typed at this boundary as JSON is.
Record = JSONObject

HISTORY = 100  # length of the circular registers of append-only attributes

ENTITY_CLASSES = ("Human", "Obstacle", "Object")
DEVICE_CLASSES = ("Camera", "Sonar")

# Record shapes: key -> type ("float", "int", "text", "char", "bool", "texts", "any").
_POSE = {"positionrho": "float", "positiontheta": "float", "positionchangetime": "int"}
_TRACKING = {"permanencetime": "int", "appearanceon": "int"}
_GOAL = {"goalid": "text", "timestamp": "int", "activity": "text"}

# class -> attribute -> (policies allowed, kind); kind is "bool", "int", "text", or a record
# shape (dict). Tables 4.1 and 4.2 of the thesis.
ATTRIBUTES: dict[str, dict[str, tuple[str, str | dict[str, str]]]] = {
    "Camera": {"isonline": ("R", "bool"), "width": ("R", "int"), "height": ("R", "int"),
               "fps": ("R", "int")},
    "Sonar": {"isonline": ("R", "bool"), "scanfrequency": ("R", "int")},
    "Human": {"poses": ("RA", _POSE), "tracking": ("RA", _TRACKING)},
    "Obstacle": {"poses": ("RA", _POSE), "tracking": ("RA", _TRACKING), "isfixed": ("R", "bool")},
    "Object": {"poses": ("RA", _POSE), "tracking": ("RA", _TRACKING), "istarget": ("R", "bool"),
               "category": ("R", "text")},
    "RobotStatus": {
        "batterytimeleft": ("R", "int"),
        "touch": ("RA", {"touchtype": "char", "duration": "int", "startingtime": "int"}),
        "led": ("RA", {"r": "float", "g": "float", "b": "float", "frequency": "int",
                       "duration": "int", "startingtime": "int"}),
        "audioout": ("RA", {"duration": "int", "startingtime": "int", "trackpath": "text"}),
        "audioin": ("RA", "any"),
        "speed": ("RA", {"xspeed": "float", "yspeed": "float", "thetaspeed": "float",
                         "duration": "int", "startingtime": "int"}),
        "elapsedtime": ("R", "int"),
        "goalreached": ("RA", _GOAL),
        "goalfailed": ("RA", _GOAL),
        "goalinterrupted": ("RA", _GOAL),
        "startingtime": ("R", "int"),
    },
    "Script": {"submove": ("R", "int"), "subled": ("R", "int"), "subaout": ("R", "int"),
               "script_vect": ("R", {"restart": "bool", "update": "texts"})},
}

# Which fields of an entity each attribute sets (the latest value).
_FIELD_OF_RECORD = {"poses": tuple(_POSE), "tracking": tuple(_TRACKING)}


class UpdateError(ValueError):
    """A MapUpdate that the map cannot take (unknown class or attribute, a policy the
    attribute does not allow, a `jsonmsg` of the wrong shape). Where the problem is, for a
    reader that knows where the update was written (a scenario file): `field` is the update's
    field it is about (`objectid`, `attributename`, `policy`, `jsonmsg`), `key` the key of the
    jsonmsg's record (`unknown_key`: the key itself is wrong, not its value), and `span` the
    offending text inside a jsonmsg given as text."""

    def __init__(self, message: str, *, field: str = "jsonmsg", key: str | None = None,
                 unknown_key: bool = False, span: Span | None = None) -> None:
        super().__init__(message)
        self.field = field
        self.key = key
        self.unknown_key = unknown_key
        self.span = span


# The nesting of a jsonmsg text: records are flat; an `audioin` value may nest, and goes on to
# the trace's JSON writer, which recurses.
JSONMSG_DEPTH = 32


def _shown(value: JSONValue) -> str:
    """A value for a message, as JSON (a number beyond the policy is said to be one)."""
    if isinstance(value, (int, float)) and number_problem(value) is not None:
        return "a number beyond a double's range" if isinstance(value, int) else repr(value)
    try:
        return json.dumps(value, ensure_ascii=False)
    except (TypeError, ValueError, RecursionError):
        return repr(type(value).__name__)


def _choices(word: str, known: Collection[str]) -> str:
    """`(did you mean `x`?)` or `(one of `a`, `b`)`: the end of a message about a name."""
    close = difflib.get_close_matches(word, list(known), n=1, cutoff=0.6)
    if close:
        return f"(did you mean `{close[0]}`?)"
    return f"(one of {', '.join(f'`{k}`' for k in known)})"


@dataclass(frozen=True, slots=True)
class MapUpdate:
    """One MapUpdate message, its `jsonmsg` already read (`value`: a dict for the record
    attributes, a str/int for the others)."""

    objectid: str
    attributename: str
    policy: str
    value: JSONValue
    cls: str
    id: str

    def as_dict(self) -> Record:
        return {"objectid": self.objectid, "attributename": self.attributename,
                "policy": self.policy, "value": self.value}


def _type_ok(kind: str, value: JSONValue) -> JSONValue:
    """The value converted to `kind`, or raises ValueError with what was expected. Numbers
    go through the number policy (scriptc.numbers) first: finite, within a double's range."""
    if kind == "any":
        return value
    if isinstance(value, (int, float)) and number_problem(value) is not None:
        raise ValueError("a finite number" if kind == "float" else "a whole number")
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError("a number")
        return float(value)
    if kind == "int":
        if isinstance(value, bool):
            raise ValueError("a whole number")
        if isinstance(value, float) and value.is_integer():
            return int(value)
        if isinstance(value, str) and _WHOLE.fullmatch(value.strip()):
            number = whole_number(value.strip())
            if number is None or number_problem(number) is not None:
                raise ValueError("a whole number within a double's range")
            return number
        if not isinstance(value, int):
            raise ValueError("a whole number")
        return value
    if kind == "text":
        if not isinstance(value, str):
            raise ValueError("a string")
        return value
    if kind == "char":
        if not isinstance(value, str) or len(value) != 1:
            raise ValueError("one character")
        return value
    if kind == "bool":
        if value is True or value == "s_true":
            return "s_true"
        if value is False or value == "s_false":
            return "s_false"
        raise ValueError('"s_true" or "s_false"')
    if kind == "texts":
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise ValueError("a list of strings")
        return list(value)
    raise AssertionError(kind)


def split_objectid(objectid: str) -> tuple[str, str]:
    """`Human/kid1` -> ("Human", "kid1"); `RobotStatus` and `Script` take no id (one given
    to `RobotStatus/...` is ignored: there is one robot)."""
    cls, sep, ident = objectid.partition("/")
    if cls in ("RobotStatus", "Script"):
        if cls == "Script" and sep:
            raise UpdateError(f"`Script` takes no id, found `{objectid}`", field="objectid")
        return cls, ""
    if cls not in ATTRIBUTES:
        raise UpdateError(f"unknown class `{cls}` in objectid `{objectid}` "
                          f"{_choices(cls, ATTRIBUTES)}", field="objectid")
    if not sep or not ident:
        raise UpdateError(f"objectid `{objectid}` must be `{cls}/ID`", field="objectid")
    if "/" in ident:
        raise UpdateError(f"objectid `{objectid}`: an id cannot contain `/`", field="objectid")
    return cls, ident


def parse_update(objectid: str, attributename: str, policy: str, jsonmsg: JSONValue
                 ) -> MapUpdate:
    """A MapUpdate checked against tables 4.1/4.2. `jsonmsg` is the message's text (JSON text
    for the record attributes, read as every JSON of scriptc is: `scriptc.frontend.jsonpos`,
    the number policy, at most JSONMSG_DEPTH levels deep) or an already-parsed JSON value.
    Raises UpdateError."""
    cls, ident = split_objectid(objectid)
    spec = ATTRIBUTES[cls].get(attributename)
    if spec is None:
        raise UpdateError(f"`{cls}` has no attribute `{attributename}` "
                          f"{_choices(attributename, ATTRIBUTES[cls])}", field="attributename")
    policies, kind = spec
    if policy not in ("R", "A"):
        raise UpdateError(f"policy must be `R` or `A`, found `{policy}`", field="policy")
    if policy not in policies:
        raise UpdateError(f"`{cls}` `{attributename}` takes policy `R` only, found `{policy}`",
                          field="policy")
    value = jsonmsg
    if isinstance(kind, dict):
        node: JsonNode | None = None
        if isinstance(value, str):
            try:
                node = parse_json(value, max_depth=JSONMSG_DEPTH)
            except JsonError as exc:
                raise UpdateError(f"jsonmsg of `{attributename}` is not JSON: {exc.message}",
                                  span=exc.span) from None
            value = node.to_python()
        if not isinstance(value, dict):
            raise UpdateError(f"jsonmsg of `{attributename}` must be an object with "
                              f"{', '.join(f'`{k}`' for k in kind)}")
        record: Record = {}
        for key, item in value.items():
            member = node.member(key) if node is not None else None
            key_kind = kind.get(key)
            if key_kind is None:
                raise UpdateError(f"jsonmsg of `{attributename}` has an unknown key `{key}` "
                                  f"{_choices(key, kind)}", key=key, unknown_key=True,
                                  span=member.key_span if member is not None else None)
            try:
                record[key] = _type_ok(key_kind, item)
            except ValueError as exc:
                raise UpdateError(f"`{key}` in the jsonmsg of `{attributename}` must be "
                                  f"{exc}, found {_shown(item)}", key=key,
                                  span=member.value.span if member is not None else None
                                  ) from None
        if attributename.startswith("goal") and "goalid" not in record:
            raise UpdateError(f"jsonmsg of `{attributename}` needs a `goalid`")
        if attributename == "script_vect" and "update" not in record:
            raise UpdateError("jsonmsg of `script_vect` needs an `update` list")
        value = record
    else:
        try:
            value = _type_ok(kind, value)
        except ValueError as exc:
            raise UpdateError(f"jsonmsg of `{attributename}` must be {exc}, "
                              f"found {_shown(value)}") from None
    return MapUpdate(objectid, attributename, policy, value, cls, ident)


class Entity:
    """A Human, Obstacle, Object, Camera, Sonar or Activity of the map. `fields` holds the
    latest value of each field (`id` is fixed at creation); `history` the append-only
    registers."""

    __slots__ = ("cls", "created_at", "fields", "history", "id", "key", "seq")

    def __init__(self, cls: str, ident: str, seq: int, created_at: int) -> None:
        self.cls = cls
        self.id = ident
        self.key = f"{cls}/{ident}"
        self.seq = seq
        self.created_at = created_at
        self.fields: Record = {"id": ident}
        self.history: dict[str, deque[Record]] = {}

    @property
    def age_key(self) -> tuple[int, int]:
        """Oldest first: earliest `appearanceon` (the creation time when not known), then the
        earliest created."""
        appearance = self.fields.get("appearanceon")
        return (self.created_at if appearance is None else appearance, self.seq)

    def __repr__(self) -> str:
        return f"Entity({self.key})"


@dataclass
class OverrideRequest:
    """A compulsory script switch raised by a rule (thesis 4.2 step 5): load `script` at
    goal `goal` (an index or a goal id), action `action`, block `block`."""

    script: str
    goal: int | str = 0
    action: int = 0
    block: int = 0
    by: str = ""


@dataclass
class ScriptInfo:
    """The map's Script Info (thesis 4.1): where the block reader is and the block that is
    (or is about to be) with the actuators."""

    currentactivity: str = ""
    goalid: str = ""
    goal: int = -1
    action: int = -1
    blockid: int = -1
    path: str = ""
    block: BlockCommands | None = None
    changed: bool = False
    override: OverrideRequest | None = None
    submove: int = 0
    subled: int = 0
    subaout: int = 0
    script_vect: list[str] = field(default_factory=list)


class RobotStatus:
    """The robot's status: updatable fields and append-only histories (tables 4.1, 4.2)."""

    __slots__ = ("fields", "history")

    def __init__(self) -> None:
        self.fields: Record = {}
        self.history: dict[str, deque[JSONValue]] = {}

    def append(self, attribute: str, record: JSONValue) -> None:
        register = self.history.get(attribute)
        if register is None:
            register = self.history[attribute] = deque(maxlen=HISTORY)
        register.append(record)
        self.fields[attribute] = record


class World:
    """The map. `time` is its Last Update Time (ms)."""

    def __init__(self) -> None:
        self.time = 0
        self.classes: dict[str, dict[str, Entity]] = {
            c: {} for c in (*ENTITY_CLASSES, *DEVICE_CLASSES, "Activity")}
        self.robot = RobotStatus()
        self.script = ScriptInfo()
        self.pending: list[MapUpdate] = []
        self._seq = 0
        self._order: dict[str, tuple[Entity, ...]] = {}

    # -- entities ---------------------------------------------------------------------------

    def entity(self, cls: str, ident: str) -> Entity | None:
        return self.classes[cls].get(ident)

    def create(self, cls: str, ident: str, now: int) -> Entity:
        """The entity `cls/ident`, created (at map time `now`) when it does not exist."""
        table = self.classes[cls]
        entity = table.get(ident)
        if entity is None:
            self._seq += 1
            entity = table[ident] = Entity(cls, ident, self._seq, now)
            self._order.pop(cls, None)
        return entity

    def candidates(self, cls: str) -> tuple[Entity, ...]:
        """Every entity of a class, oldest first (see the module's docstring)."""
        order = self._order.get(cls)
        if order is None:
            order = self._order[cls] = tuple(sorted(self.classes[cls].values(),
                                                    key=lambda e: e.age_key))
        return order

    def set_field(self, entity: Entity, name: str, value: JSONValue) -> None:
        if name == "appearanceon" and entity.fields.get(name) != value:
            self._order.pop(entity.cls, None)
        entity.fields[name] = value

    # -- activities (one Activity entity per script name) ------------------------------------

    def start_activity(self, name: str, now: int) -> Entity:
        activity = self.create("Activity", name, now)
        activity.created_at = now  # restarted: it "appears" again, for the age order
        self._order.pop("Activity", None)
        activity.fields.update(activityid=name, startingtime=now, elapsedtime=0)
        return activity

    # -- updates ----------------------------------------------------------------------------

    def post(self, update: MapUpdate) -> list[MapUpdate]:
        """Queue an update until the next step 4; an `R` update drops (and returns) the
        pending updates of the same object's attribute posted before it."""
        dropped: list[MapUpdate] = []
        if update.policy == "R" and self.pending:
            keep = []
            for u in self.pending:
                if u.objectid == update.objectid and u.attributename == update.attributename:
                    dropped.append(u)
                else:
                    keep.append(u)
            self.pending = keep
        self.pending.append(update)
        return dropped

    def take_pending(self) -> list[MapUpdate]:
        pending, self.pending = self.pending, []
        return pending

    def apply(self, update: MapUpdate, now: int) -> None:
        """Merge one update into the map (step 4). `Script/script_vect` is only stored here;
        the session acts on it."""
        self.time = now
        cls, attr, value = update.cls, update.attributename, update.value
        if cls == "RobotStatus":
            if isinstance(ATTRIBUTES[cls][attr][1], dict) or attr == "audioin":
                self.robot.append(attr, value)
            else:
                self.robot.fields[attr] = value
            return
        if cls == "Script":
            info = self.script
            if attr == "script_vect":
                info.script_vect = list(value["update"])
            else:
                setattr(info, attr, value)
            return
        entity = self.create(cls, update.id, now)
        if attr in _FIELD_OF_RECORD:
            register = entity.history.get(attr)
            if register is None:
                register = entity.history[attr] = deque(maxlen=HISTORY)
            register.append(value)
            for key in _FIELD_OF_RECORD[attr]:
                if key in value:
                    self.set_field(entity, key, value[key])
            if attr == "poses" and "positionchangetime" not in value:
                entity.fields["positionchangetime"] = now
        else:
            entity.fields[attr] = value

    # -- what rules and functions read --------------------------------------------------------

    def goal_records(self, kind: str) -> Iterable[Record]:
        """The register of `goalreached`, `goalinterrupted` or `goalfailed` records."""
        return self.robot.history.get(kind, ())

    def snapshot(self) -> dict[str, dict[str, JSONValue]]:
        """A plain summary of the map (for `--json` and debugging): entities and their fields."""
        out: dict[str, dict[str, JSONValue]] = {}
        for cls, table in self.classes.items():
            if table:
                out[cls] = {e.id: dict(e.fields) for e in self.candidates(cls)}
        out["RobotStatus"] = dict(self.robot.fields)
        return out

