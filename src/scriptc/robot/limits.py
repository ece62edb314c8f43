"""The robot's limits, each stated once: its key in the `[robot]` table of the configuration,
its unit, its safe default, the range a configuration may give it, what it means and who keeps
it (docs/robot.md, "The robot profile").

Everything else reads this table: the profile (`robot/profile.py`, whose defaults these are),
the configuration's loader (which keeps a value only inside its range), `show-settings`, the
`[robot]` section `scriptc init` writes, the JSON Schemas of the configuration and of the
trace's `session_start` (`python -m scriptc.generate` writes their robot parts from here) and
the tables of docs/configuration.md and docs/robot.md (generated too; tests fail when stale).

The one rule for a limit the configuration does not give (`MISSING_LIMIT_RULE`): it keeps its
safe default. No reader treats a missing limit as "not checked": the robot is never unlimited.
A value the checks reject (C002) is not given either: the key keeps its default.

The defaults are conservative for a robot among small children: a walking child moves at about
1 m/s, Teo/Oimi's base drove at a few tenths of a metre per second in the thesis's sessions.
Standard library only; on the path of `scriptc lint` (the safety checks read the profile).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

__all__ = ["BY_FIELD", "BY_KEY", "LIMITS", "MISSING_LIMIT_RULE", "Limit", "toml_section"]

MISSING_LIMIT_RULE = ("Every key is optional: a limit that is not given, or whose value is "
                      "rejected, keeps its safe default (the robot is never unlimited).")


class Limit(NamedTuple):
    """One limit of the robot profile."""

    key: str  # in `[robot]` of scriptc.toml; the profile's field is `field`
    unit: str  # as the docs and the init template write it
    default: float  # the safe default (the profile's)
    minimum: float  # the lowest value a configuration may give...
    exclusive: bool  # ...excluded (True: the value must be greater than `minimum`)
    maximum: float | None  # the highest (included), None: no maximum
    doc: str  # what it limits, a sentence without its unit
    used_by: str  # who keeps it (docs/robot.md)

    @property
    def field(self) -> str:
        """The profile's attribute (`max_linear_speed`)."""
        return self.key.replace("-", "_")

    def accepts(self, value: float) -> bool:
        """Whether a configuration may give `value` (a finite number in the range)."""
        if not math.isfinite(value):
            return False
        above = value > self.minimum if self.exclusive else value >= self.minimum
        return above and (self.maximum is None or value <= self.maximum)

    @property
    def range(self) -> str:
        """The range as the docs write it: `> 0`, `≥ 1`, `> 0 and ≤ 1`."""
        low = f"{'>' if self.exclusive else '≥'} {self.minimum}"
        return low if self.maximum is None else f"{low} and ≤ {self.maximum}"


LIMITS: tuple[Limit, ...] = (
    Limit("max-linear-speed", "m/s", 0.5, 0, True, None,
          "the highest speed of the base in the plane, |(v_x, v_y)|", "K001, the governor"),
    Limit("max-angular-speed", "rad/s", 1.5, 0, True, None,
          "the highest turning speed, |v_theta|", "K001, the governor"),
    Limit("max-linear-acceleration", "m/s²", 1.0, 0, True, None,
          "the highest acceleration of the base: the governor ramps v_x and v_y at this rate",
          "K003, the governor (ramps of `v_x`, `v_y`; its braking distance near people)"),
    Limit("max-angular-acceleration", "rad/s²", 3.0, 0, True, None,
          "the highest angular acceleration: the governor ramps v_theta at this rate",
          "K003, the governor (ramps of `v_theta`)"),
    Limit("min-human-distance", "m", 0.4, 0, False, None,
          "the closest the robot may come to a `Human` entity",
          "the governor, with simulated sensing"),
    Limit("max-led-flash-rate", "Hz", 3.0, 1, False, None,
          "the most flashes (onsets of light) the LEDs may make in any one second; "
          "photosensitivity guidance (WCAG 2.3.1) allows three",
          "K002, the governor"),
    Limit("max-volume", "fraction of full volume", 0.8, 0, True, 1,
          "the loudest the speaker may play (audio commands carry no volume, so every track "
          "plays at this one level)",
          "the governor: the speaker's level"),
)

BY_KEY: Mapping[str, Limit] = {limit.key: limit for limit in LIMITS}
BY_FIELD: Mapping[str, Limit] = {limit.field: limit for limit in LIMITS}


def toml_section(values: Mapping[str, float] | None = None) -> str:
    """The `[robot]` table with every limit (`values` by key, else the defaults), each with its
    unit: what `scriptc init` writes and the docs show."""
    rows = [(f"{limit.key} = {(values or {}).get(limit.key, limit.default)}",
             limit.unit) for limit in LIMITS]
    width = max(len(row) for row, _ in rows) + 2
    return "[robot]\n" + "".join(f"{row:<{width}}# {unit}\n" for row, unit in rows)
