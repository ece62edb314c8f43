"""Checking a configuration: the JSON Schema (`schemas/config.schema.json`, with `jsonschema`)
for its shape, then what a schema cannot say (codes that exist, patterns that compile, names
declared once). Every problem is a diagnostic in the configuration file, at the key or value
it is about (`tomlpos.locate` finds them: tomllib gives no positions).

This module imports `jsonschema` (about 100 ms); the loader calls it only when a configuration
file changed (the result is cached by the file's content, `scriptc.project.cache`).
"""

from __future__ import annotations

import difflib
import json
import os
from collections.abc import Mapping
from functools import cache
from typing import TYPE_CHECKING, Any

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.numbers import number_problem
from scriptc.project.config.settings import run_time_refusal, selected_codes
from scriptc.project.config.tomlpos import KeyPath, KeySpans, TOMLTable, TOMLValue, locate
from scriptc.source import SourceFile

if TYPE_CHECKING:  # jsonschema is imported when a document is checked
    from jsonschema import ValidationError


# A JSON Schema document (schemas/*.schema.json) as `json` reads it: its values are any JSON.
JSONSchema = dict[str, Any]


@cache
def schema() -> JSONSchema:
    from scriptc.resources import schema_path

    loaded: JSONSchema = json.loads(schema_path("config.schema.json").read_text(
        encoding="utf-8"))
    return loaded


def _toml_type(value: TOMLValue) -> str:
    import datetime

    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, (datetime.date, datetime.time)):
        return "a date or time"
    return type(value).__name__


_JSON_TYPE = {"string": "a string", "array": "an array", "object": "a table",
              "number": "a number", "integer": "an integer", "boolean": "a boolean"}


def dotted(path: KeyPath) -> str:
    """`lint.select[2]`, `functions[0].kind`; keys that are not bare are quoted."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            bare = part and all(c.isalnum() or c in "_-" for c in part) and part.isascii()
            text = part if bare else json.dumps(part, ensure_ascii=False)
            out += f".{text}" if out else text
    return out


class TomlChecker:
    """The checks of a TOML document of scriptc against its JSON Schema (the configuration, a
    test file): each finding of the schema in words, at the key or value it is about, an
    unknown key (code `unknown`) with the known key it is close to, and the number policy over
    every number (`nan`, `inf`); the other findings have the code `invalid`. `what` names the
    document ("the configuration"), `reference` is the page that lists its keys. A subclass
    adds what the schema cannot say (`report` at a key path, `name` of one)."""

    def __init__(self, source: SourceFile, prefix: KeyPath = (), *,
                 schema: JSONSchema | None = None, unknown: str = "C001",
                 invalid: str = "C002", what: str = "the configuration",
                 reference: str = "docs/configuration.md") -> None:
        self.source = source
        self.prefix = prefix
        self.schema = schema
        self.unknown = unknown
        self.invalid = invalid
        self.what = what
        self.reference = reference
        self._positions: KeySpans | None = None
        self.out: list[Diagnostic] = []

    @property
    def positions(self) -> KeySpans:
        if self._positions is None:
            self._positions = locate(self.source.text)
        return self._positions

    def report(self, code: str, message: str, path: KeyPath, *, at: str = "value",
               help: str | None = None, notes: tuple[str, ...] = ()) -> None:
        span = self.positions.find(self.prefix + tuple(path), prefer=at)
        self.out.append(diagnostic(code, message, span, help=help, notes=notes))

    def name(self, path: KeyPath) -> str:
        return dotted(self.prefix + tuple(path))

    def table_name(self, path: KeyPath) -> str:
        """`[lint]` for a table, `functions[0]` for an element of an array of tables."""
        full = self.prefix + tuple(path)
        if full and isinstance(full[-1], int):
            return f"`{dotted(full)}`"
        return f"`[{dotted(full)}]`" if full else self.what

    # -- the schema ---------------------------------------------------------------------------

    def check_schema(self, data: TOMLTable) -> None:
        import jsonschema

        validator = jsonschema.Draft202012Validator(self.schema or schema())
        errors = sorted(validator.iter_errors(data), key=lambda e: list(map(str, e.absolute_path)))
        for error in errors:
            self.schema_error(error)

    def schema_error(self, error: ValidationError) -> None:
        path = tuple(error.absolute_path)
        kind = error.validator
        value: TOMLValue = error.instance  # the value the finding is about
        if number_problem(value) is not None:
            return  # `nan`, `inf`, beyond a double: the number policy reports it (`numbers`)
        # the (sub)schema whose keyword `kind` failed; a boolean schema has no keyword
        sub: Mapping[str, Any] = error.schema if isinstance(error.schema, Mapping) else {}
        what = f"`{self.name(path)}`"
        if kind == "additionalProperties" and sub.get("additionalProperties") is False:
            known = sorted(sub.get("properties", {}))
            for key in value:
                if key in known:
                    continue
                close = difflib.get_close_matches(key, known, n=1, cutoff=0.6)
                help_ = (f"did you mean `{close[0]}`?" if close else
                         f"the keys of {self.table_name(path)} are "
                         + ", ".join(f"`{k}`" for k in known))
                where = f" in {self.table_name(path)}" if self.prefix + path else ""
                self.report(self.unknown, f"unknown key `{key}`{where}",
                            path + (key,), at="key", help=help_,
                            notes=(f"see {self.reference} for every key",))
            return
        if kind == "type":
            types: list[str] = sub["type"] if isinstance(sub["type"], list) else [sub["type"]]
            expected = " or ".join(_JSON_TYPE.get(t, t) for t in types)
            message = f"{what} must be {expected}, not {_toml_type(value)}"
        elif kind == "enum":
            choices = ", ".join(f"`{c}`" for c in sub["enum"])
            message = f"{what} must be one of {choices}, not `{value}`"
        elif kind == "exclusiveMinimum":
            message = f"{what} must be greater than {sub['exclusiveMinimum']}, not {value}"
        elif kind == "minimum":
            message = f"{what} must be at least {sub['minimum']}, not {value}"
        elif kind == "maximum":
            message = f"{what} must be at most {sub['maximum']}, not {value}"
        elif kind == "minLength":
            message = f"{what} must not be empty"
        elif kind == "maxItems":
            message = f"{what} has more than {sub['maxItems']} items"
        elif kind == "minItems":
            message = f"{what} must not be empty" if sub["minItems"] == 1 else \
                f"{what} has fewer than {sub['minItems']} items"
        elif kind == "pattern":
            if ":" in sub["pattern"]:
                message = f"{what} must be a Python object as `module:attribute`, not `{value}`"
            else:
                message = (f"{what} must be a name (letters, digits, `_` and `-`, not starting "
                           f"with a digit), not `{value}`")
        elif kind == "required":
            missing = [k for k in sub["required"] if k not in value]
            message = f"{self.table_name(path)} lacks the required key `{missing[0]}`"
            self.report(self.invalid, message, path, at="key")
            return
        elif kind == "anyOf" and "params" in sub.get("properties", {}):
            message = f"{self.table_name(path)} needs `arity` (or `params`)"
            self.report(self.invalid, message, path, at="key")
            return
        elif kind in ("additionalProperties", "propertyNames"):
            return  # the per-key errors are reported on their own
        else:
            message = f"{what}: {error.message}"
        self.report(self.invalid, message, path)

    # -- what a schema cannot say -------------------------------------------------------------

    def numbers(self, data: TOMLTable) -> None:
        """The number policy (scriptc.numbers) over every number of the table: TOML reads
        `nan`, `inf` and `1e999` (infinity), and a JSON Schema's ranges let them through."""
        stack: list[tuple[KeyPath, TOMLValue]] = [((), data)]
        while stack:
            path, value = stack.pop()
            if isinstance(value, dict):
                stack.extend((path + (k,), v) for k, v in value.items())
            elif isinstance(value, list):
                stack.extend((path + (i,), v) for i, v in enumerate(value))
            elif number_problem(value) is not None:
                span = self.positions.find(self.prefix + path, prefer="value")
                written = self.source.text[span.start:span.end].strip()
                self.report(self.invalid, f"`{self.name(path)}`: "
                            f"{number_problem(value, written or None)}", path,
                            help="write a finite number in the key's range")


class _Checker(TomlChecker):
    """The configuration's checks: the schema's, then what a schema cannot say."""

    def check_meaning(self, data: TOMLTable) -> None:
        self.numbers(data)
        lint = data.get("lint")
        if isinstance(lint, dict):
            for key in ("select", "ignore"):
                for i, selector in _strings(lint.get(key)):
                    self.selector(selector, ("lint", key, i), may_be_error=key == "select",
                                  purpose="ignored")
            pfi = lint.get("per-file-ignores")
            if isinstance(pfi, dict):
                for pattern, selectors in pfi.items():
                    self.pattern(pattern, ("lint", "per-file-ignores", pattern), at="key")
                    for i, selector in _strings(selectors):
                        self.selector(selector, ("lint", "per-file-ignores", pattern, i),
                                      purpose="ignored")
            severity = lint.get("severity")
            if isinstance(severity, dict):
                for selector in severity:
                    self.selector(selector, ("lint", "severity", selector), at="key",
                                  purpose="given another severity")
        for i, pattern in _strings(data.get("exclude")):
            self.pattern(pattern, ("exclude", i))
        audio = data.get("audio-root")
        if isinstance(audio, str) and audio:
            normal = os.path.normpath(audio.replace("\\", "/")).replace("\\", "/")
            if os.path.isabs(audio) or audio.startswith(("/", "\\", "~")) or \
                    normal == ".." or normal.startswith("../"):
                self.report("C002", "`audio-root` must be a folder inside the repository, "
                            f"relative to the configuration's folder, not `{audio}`",
                            ("audio-root",),
                            help="write the folder relative to this file (`audio`)")
        self.declarations(data.get("functions"), "functions", "function")
        self.declarations(data.get("rules"), "rules", "rule")

    def selector(self, selector: str, path: KeyPath, *, at: str = "value",
                 may_be_error: bool = False, purpose: str = "ignored") -> None:
        from scriptc.diagnostics.codes import REGISTRY, lint_codes

        codes = selected_codes(selector)
        refusal = None if codes else run_time_refusal(selector)
        if refusal is not None:
            self.report("C004", refusal, path, at=at,
                        help="name lint's codes here (`scriptc explain --all` lists both)")
            return
        if not codes:
            known = [c.code for c in lint_codes()] + [c.name for c in lint_codes()]
            close = difflib.get_close_matches(selector, known, n=1, cutoff=0.6)
            self.report("C004", f"`{selector}` names no diagnostic code", path, at=at,
                        help=f"did you mean `{close[0]}`?" if close else
                        "`scriptc explain --all` lists the codes and their names")
            return
        if may_be_error:
            return
        if all(REGISTRY[c].severity.value == "error" for c in codes):
            shown = codes[0] if len(codes) == 1 else f"{codes[0]}..{codes[-1]}"
            self.report("C004", f"`{selector}` names only errors ({shown}): errors cannot be "
                        f"{purpose}", path, at=at,
                        notes=(("a script with an error does not work on the robot, so errors "
                                "are always reported"),),
                        help="fix the error in the script instead")

    def pattern(self, pattern: str, path: KeyPath, *, at: str = "value") -> None:
        import pathspec

        try:
            pathspec.GitIgnoreSpec.from_lines([pattern])
        except Exception as exc:  # pathspec raises several kinds
            self.report("C002", f"`{pattern}` is not a valid .gitignore pattern: {exc}", path,
                        at=at)

    def declarations(self, items: TOMLValue, key: str, what: str) -> None:
        if not isinstance(items, list):
            return
        from scriptc.ir.builtins import STANDARD

        seen: dict[str, int] = {}
        for i, item in enumerate(items):
            if not isinstance(item, dict):
                continue
            name = item.get("name")
            if isinstance(name, str):
                if name in seen:
                    self.report("C002", f"the {what} `{name}` is declared twice", (key, i, "name"),
                                notes=(f"first declared as `{self.name((key, seen[name]))}`",))
                else:
                    seen[name] = i
                if what == "function" and STANDARD.get(name) is not None:
                    self.report("C002", f"`{name}` is a standard function: a declaration cannot "
                                "replace it", (key, i, "name"),
                                help="give the repository's function another name")
            params, arity = item.get("params"), item.get("arity")
            if isinstance(params, list) and isinstance(arity, int) and \
                    not isinstance(arity, bool) and len(params) != arity:
                self.report("C002", f"`{self.name((key, i, 'params'))}` names {len(params)} "
                            f"parameters but `arity` is {arity}", (key, i, "params"))


def _strings(value: TOMLValue) -> list[tuple[int, str]]:
    if not isinstance(value, list):
        return []
    return [(i, v) for i, v in enumerate(value) if isinstance(v, str)]


def check_config(data: TOMLTable, source: SourceFile, prefix: KeyPath = ()
                 ) -> list[Diagnostic]:
    """Every problem of a parsed configuration table (`data`, found at `prefix` in the
    document `source`: `("tool", "scriptc")` in pyproject.toml), sorted by position."""
    checker = _Checker(source, prefix)
    checker.check_schema(data)
    checker.check_meaning(data)
    checker.out.sort(key=Diagnostic.sort_key)
    return checker.out

