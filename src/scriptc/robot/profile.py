"""The robot profile: the limits the activities must respect, with safe defaults
(docs/robot.md). The static safety pass (`check/safety.py`, K codes), the run-time governor
(`runtime/governor.py`) and what both predict of the robot's ramps (`robot/motion.py`) read it.

The defaults are conservative for a robot among small children: a walking child moves at about
1 m/s, Teo/Oimi's base drove at a few tenths of a metre per second in the thesis's sessions.
A repository overrides them in its configuration (`[robot]` of `scriptc.toml`,
docs/configuration.md); a key it does not give keeps the default here (the configuration's
"not checked" becomes "the safe default": the robot is never unlimited).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any


@dataclass(frozen=True, slots=True)
class Profile:
    max_linear_speed: float = 0.5  # m/s, the speed of the base in the plane
    max_angular_speed: float = 1.5  # rad/s
    max_linear_acceleration: float = 1.0  # m/s²: the governor ramps v_x and v_y at this rate
    max_angular_acceleration: float = 3.0  # rad/s²: the governor ramps v_theta at this rate
    min_human_distance: float = 0.4  # m: the governor holds the wheels closer than this
    max_led_flash_rate: float = 3.0  # Hz: WCAG 2.3.1 (three flashes); K002 and the governor
    max_volume: float = 0.8  # the speaker's level, a fraction of full volume (the governor)
    source: str = "defaults"  # where the values came from (a configuration file's path)

    def as_dict(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def limits(self) -> dict[str, float]:
        """The limits alone (without where they came from), as a governed trace records them."""
        return {k: getattr(self, k) for k in _KEYS}


DEFAULT_PROFILE = Profile()

_KEYS = tuple(f.name for f in fields(Profile) if f.name != "source")


def profile_from_settings(settings: Any) -> Profile:
    """The profile of a configuration (`scriptc.project.config.Settings`, whose `robot` is a
    `RobotProfile` of optional values): the given values over the defaults."""
    robot = getattr(settings, "robot", None)
    if robot is None:
        return DEFAULT_PROFILE
    given = {k: float(getattr(robot, k)) for k in _KEYS if getattr(robot, k, None) is not None}
    if not given:
        return DEFAULT_PROFILE
    return replace(DEFAULT_PROFILE, **given, source=getattr(settings, "path", None) or "config")
