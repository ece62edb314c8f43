"""The robot profile: the limits the activities must respect (docs/robot.md). The static safety
pass (`check/safety.py`, K codes), the run-time governor (`runtime/governor.py`) and what both
predict of the robot's ramps (`robot/motion.py`) read it.

Each limit, its default and its range are stated once, in `robot/limits.py`; a `Profile` is
those limits as typed values. A repository overrides them in its configuration (`[robot]` of
`scriptc.toml`, docs/configuration.md): the configuration's loader builds its profile with
`Profile.given`, and a key it does not give keeps the default (`limits.MISSING_LIMIT_RULE`:
the robot is never unlimited).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields, replace

from scriptc.robot.limits import BY_FIELD, BY_KEY

_DEFAULT = {name: limit.default for name, limit in BY_FIELD.items()}


@dataclass(frozen=True, slots=True)
class Profile:
    """The limits, by the profile's names of the keys of `[robot]` (robot/limits.py)."""

    max_linear_speed: float = _DEFAULT["max_linear_speed"]  # m/s, the base in the plane
    max_angular_speed: float = _DEFAULT["max_angular_speed"]  # rad/s
    max_linear_acceleration: float = _DEFAULT["max_linear_acceleration"]  # m/s²
    max_angular_acceleration: float = _DEFAULT["max_angular_acceleration"]  # rad/s²
    min_human_distance: float = _DEFAULT["min_human_distance"]  # m
    max_led_flash_rate: float = _DEFAULT["max_led_flash_rate"]  # Hz: K002 and the governor
    max_volume: float = _DEFAULT["max_volume"]  # a fraction of full volume (the governor)
    source: str = "defaults"  # where the values came from (a configuration file's path)

    def as_dict(self) -> dict[str, float | str]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def limits(self) -> dict[str, float]:
        """The limits alone (without where they came from), as a governed trace records them."""
        return {name: getattr(self, name) for name in BY_FIELD}

    @staticmethod
    def given(values: Mapping[str, float], source: str) -> Profile:
        """The profile with `values` (by key of `[robot]`, each in its limit's range: the
        configuration's loader keeps only those) over the defaults; `DEFAULT_PROFILE` when no
        value is given."""
        if not values:
            return DEFAULT_PROFILE
        unknown = set(values) - set(BY_KEY)
        if unknown:
            raise ValueError(f"no robot limit is named {', '.join(sorted(unknown))}")
        return replace(DEFAULT_PROFILE, source=source,
                       **{BY_KEY[key].field: float(value) for key, value in values.items()})


if tuple(f.name for f in fields(Profile))[:-1] != tuple(BY_FIELD):  # the table grew a limit
    raise RuntimeError("robot/profile.py's Profile does not have the limits of robot/limits.py")

DEFAULT_PROFILE = Profile()
