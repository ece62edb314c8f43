"""The run time of an activity repository: its configuration's functions and rules, imported
and registered beside the standard ones.

`[[functions]]` and `[[rules]]` in `scriptc.toml` (docs/configuration.md) declare what a
repository adds to the rule grammar and to the rule library, with their Python
implementations as `module:attribute`. Linting only needs the declarations (the signatures
extend the checker's registry); running needs the code, so it is imported here, when a
session is about to start, and never on the lint path.

- A function's implementation is called as `fn(call, *args)` (runtime/functions.py).
- A rule's implementation is a factory `(message, params) -> Rule`: a subclass of
  `scriptc.runtime.rules.Rule` is one. A rule declared with a `rulecode` is the body of that
  rulecode; one declared without is found by the id of the messages that name it.
"""

from __future__ import annotations

from typing import Any

from scriptc.project.config.settings import ImplementationError, Settings, import_implementation
from scriptc.runtime.functions import STANDARD_IMPLEMENTATIONS, Implementations
from scriptc.runtime.rules import STANDARD_RULES, RuleLibrary

# What a `module:attribute` implementation names: whatever the repository's code defines there,
# checked where it is used (callable, then called as a function or a rule factory).
Imported = Any


class ConfiguredError(Exception):
    """A declared function or rule whose implementation cannot be used; the message names
    the configuration file and the entry."""


def implementations_for(settings: Settings) -> Implementations:
    """The standard functions and the repository's, imported."""
    impls = STANDARD_IMPLEMENTATIONS.extended()
    for function in settings.functions:
        fn = _load(settings, "function", function.name, function.implementation, function.root)
        if not callable(fn):
            raise ConfiguredError(f"{_where(settings)}: function `{function.name}`: "
                                  f"`{function.implementation}` is not callable")
        impls.register(function.name, function.kind, function.arity, fn, doc=function.doc,
                       params=tuple(function.params), origin="config")
    return impls


def rules_for(settings: Settings) -> RuleLibrary:
    """The standard rule library and the repository's rules, imported."""
    library = STANDARD_RULES.extended()
    for rule in settings.rules:
        factory = _load(settings, "rule", rule.name, rule.implementation, rule.root)
        if not callable(factory):
            raise ConfiguredError(f"{_where(settings)}: rule `{rule.name}`: "
                                  f"`{rule.implementation}` is not callable")
        if rule.rulecode is not None:
            library.register(rule.rulecode, rule.name, factory, rule.doc, origin="config")
        else:
            library.register_named(rule.name, factory, rule.doc, origin="config")
    return library


def _where(settings: Settings) -> str:
    return settings.path or "the configuration"


def _load(settings: Settings, what: str, name: str, spec: str, root: str) -> Imported:
    try:
        return import_implementation(spec, root)
    except ImplementationError as exc:
        raise ConfiguredError(f"{_where(settings)}: {what} `{name}`: {exc}") from None
