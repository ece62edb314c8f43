"""The configuration of an activity repository (docs/configuration.md).

`scriptc.toml`, or `[tool.scriptc]` in `pyproject.toml`, found by walking up from each file:
which diagnostics are reported and how severe they are, the robot profile, the repository's
own functions and rules (with their Python implementations, imported only when asked), the
audio root, and what `scriptc lint DIR` skips.

- `settings.py`  `Settings` and its parts; the policy applied to a file's diagnostics
- `load.py`      finding, reading and building configurations (`Resolver` for many files)
- `validate.py`  the checks: JSON Schema (`schemas/config.schema.json`) and the rest
- `tomlpos.py`   positions of keys and values in TOML text (tomllib gives none)

Importing this package costs nothing beyond the standard library: `tomllib` is imported when
a configuration file is read, `jsonschema` only when one is checked (it changed since the
cached check), `pathspec` only for per-file ignores and exclusions.
"""

from __future__ import annotations

from scriptc.project.config.load import (
    ConfigFile,
    Resolver,
    build_settings,
    find_config,
    load_config,
    project_root,
)
from scriptc.project.config.settings import (
    ImplementationError,
    RuleSelection,
    Settings,
    UserFunction,
    UserRule,
    import_implementation,
)

__all__ = [
    "ConfigFile", "ImplementationError", "Resolver", "RuleSelection", "Settings",
    "UserFunction", "UserRule", "build_settings", "find_config", "import_implementation",
    "load_config", "project_root",
]
