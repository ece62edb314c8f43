"""The repository's setup of a file: its configuration's `Settings`, the function registry
the checks use (the standard functions and those the configuration declares), the robot
profile (the configuration's `[robot]` over the defaults) and the configuration's own
problems. Every verb and the language server take these from here, so a file is checked,
compiled and run under one reading of its repository (docs/configuration.md).

The registry is built one way (`function_registry`), from the declared functions'
signatures, once per process for each set of them: `scriptc lint`'s worker processes receive
the signatures (plain data) and build the same registry the parent would.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from scriptc.diagnostics.model import Diagnostic, has_errors
from scriptc.ir.builtins import STANDARD, Function, FunctionRegistry
from scriptc.robot.profile import Profile

if TYPE_CHECKING:  # the configuration is imported when a setup is made from files
    from scriptc.project.config.load import ConfigFile
    from scriptc.project.config.settings import Settings

__all__ = ["Setup", "function_registry", "setup_for"]

_registries: dict[tuple[Function, ...], FunctionRegistry] = {}


def function_registry(signatures: tuple[Function, ...]) -> FunctionRegistry:
    """The registry of the standard functions and the declared ones (`signatures`), built
    once per process for each set."""
    if not signatures:
        return STANDARD
    registry = _registries.get(signatures)
    if registry is None:
        registry = _registries[signatures] = STANDARD.extended(signatures)
    return registry


class Setup:
    """What a file's repository says about it: `settings` (`scriptc.project.config.Settings`),
    the declared functions' `signatures` and the `functions` registry they make, the robot
    `profile`, and `problems`: the configuration files that have diagnostics (each with its
    `source` and `diagnostics`, as a renderer reads them), empty when there are none."""

    __slots__ = ("functions", "problems", "profile", "settings", "signatures")

    def __init__(self, settings: Settings, problems: Sequence[ConfigFile] = ()) -> None:
        self.settings = settings
        self.signatures: tuple[Function, ...] = tuple(f.signature for f in settings.functions)
        self.functions = function_registry(self.signatures)
        self.profile: Profile = settings.robot
        self.problems = list(problems)

    def __repr__(self) -> str:
        return f"Setup({self.settings.path!r}, {len(self.problems)} configuration problems)"

    @property
    def failed(self) -> bool:
        """Whether the configuration has an error: `compile`, `decompile` and `run` do
        nothing then (docs/configuration.md); warnings do not stop them."""
        return any(has_errors(p.diagnostics) for p in self.problems)

    def apply(self, diagnostics: Sequence[Diagnostic], path: str | None) -> list[Diagnostic]:
        """The configuration's policy over a file's diagnostics (`Settings.apply`): `path`
        is the file as shown, None for stdin without a name (no per-file ignores)."""
        return self.settings.apply(diagnostics, path)


def setup_for(path: str, *, cache: bool = True) -> Setup:
    """The setup of one file (`scriptc compile FILE`, a script loaded by `scriptc run`, a
    document in the language server). `path` may be a name that does not exist
    (`--stdin-filename`): its folder is searched; `-` and `<stdin>` are the working folder's.
    With `cache`, the configuration's checks are cached in the project's cache, as `scriptc
    lint` caches them."""
    from scriptc.project.config import Resolver

    named = path if path not in ("-", "<stdin>") else "-"
    store = None
    if cache:
        from scriptc.project.cache import Cache, default_cache_dir
        from scriptc.project.config import project_root

        # The cache of the file's project, wherever scriptc runs (as `scriptc lint`'s).
        store = Cache(default_cache_dir(project_root(named if named != "-" else ".")))
    resolver = Resolver(store)
    settings = resolver.for_file(named)
    return Setup(settings, [c for c in resolver.configs if c.diagnostics])
