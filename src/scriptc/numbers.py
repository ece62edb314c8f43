"""One number policy for every number scriptc reads from a file, and for every JSON it writes.

Readers parse numbers in several places (the thesis JSON and scenarios through
`scriptc.frontend.jsonpos`, the `jsonmsg` texts of map updates, the configuration's TOML, the
numbers of the script syntax), and Python lets each of them produce what the code after it
cannot use: `NaN` and `Infinity` (Python's `json` reads them, tomllib reads `nan` and `inf`,
and a JSON Schema's `"type": "number"` accepts them), `1e999`, which `float()` turns into
infinity, and integers of thousands of digits, which `int()` refuses beyond 4,300 digits and
`float()` cannot hold. Every reader asks here instead, so the answer is the same everywhere:

- a number is usable when it is finite and within a double's range (|x| <= LARGEST,
  about 1.8e308); an integer of more digits than that range holds is too large, and is
  refused from its length, before any conversion;
- anything else is refused where it is read, with the position of its text (the reader turns
  `NumberError` into its own diagnostic);
- each field then has its declared range (the JSON Schemas' `minimum` and `maximum`, the
  checks' limits such as `MAX_TIME`), checked by the reader of that field.

On the way out, `json_dumps` is the one JSON writer of results (traces, `--json` summaries,
diagnostics): it never writes `NaN` or `Infinity`, which no strict JSON reader accepts; a
non-finite number reaching it is a bug of scriptc, reported as such with where it was.
`JSONValue` and `JSONObject` name JSON data wherever it crosses into the code (parsed
documents, map records, trace events, cache entries, protocol answers).
"""

from __future__ import annotations

import json
import math
import sys
from typing import Any, TypeAlias

__all__ = [
    "LARGEST",
    "MAX_DIGITS",
    "JSONObject",
    "JSONValue",
    "NonFiniteOutput",
    "NumberError",
    "json_dumps",
    "json_number",
    "number_problem",
    "shown",
    "whole_number",
]

LARGEST = sys.float_info.max
# Digits of the largest integer a double holds (LARGEST is 309 digits long): an integer
# written with more digits is beyond it, whatever they are.
MAX_DIGITS = len(str(int(LARGEST)))


class NumberError(ValueError):
    """A number the policy refuses; `message` says why, for a diagnostic at its text."""

    def __init__(self, message: str) -> None:
        self.message = message
        super().__init__(message)


def shown(text: str) -> str:
    """A number's text in backticks for a message, cut in the middle when long (a 5,000-digit
    number is one line)."""
    digits = sum(c.isdigit() for c in text)
    if len(text) <= 24:
        return f"`{text}`"
    return f"`{text[:10]}...{text[-6:]}` ({digits} digits)"


def _too_large(subject: str) -> str:
    return (f"{subject} is too large: numbers must be finite and within ±{LARGEST:.1e} "
            "(a double)")


def number_problem(value: Any, text: str | None = None) -> str | None:
    """Why the parsed number `value` (an int or a float, as a TOML or JSON reader returned it)
    cannot be used, or None when it can. `text` is how the file wrote it, for the message."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    if isinstance(value, float):
        if math.isfinite(value):
            return None
        written = shown(text) if text is not None else f"`{value}`"
        if text is not None and text.lstrip("+-").lower() not in ("inf", "infinity", "nan"):
            return _too_large(f"the number {written}")  # `1e999`: a finite text that overflows
        what = "not a number" if math.isnan(value) else "infinite"
        return f"{written} is {what}: numbers must be finite"
    if value > LARGEST or value < -LARGEST:
        # str() of the integer may be refused (more than 4,300 digits): count its digits.
        digits = int(abs(value).bit_length() * math.log10(2)) + 1
        return _too_large(f"the number {shown(text)}" if text is not None
                          else f"an integer of about {digits} digits")
    return None


def json_number(raw: str, is_integer: bool) -> int | float:
    """The value of the text of a JSON number (RFC 8259 syntax, already matched), under the
    policy: an int when written without fraction or exponent (`is_integer`), else a float.
    Raises NumberError."""
    if is_integer:
        if len(raw) - raw.startswith("-") > MAX_DIGITS:
            raise NumberError(_too_large(f"the number {shown(raw)}"))
        value: int | float = int(raw)
    else:
        value = float(raw)  # float() reads any number of digits; too large becomes inf
    problem = number_problem(value, raw)
    if problem is not None:
        raise NumberError(problem)
    return value


def whole_number(text: str) -> int | None:
    """The value of a whole number's text (ASCII digits, an optional sign), or None when it
    has more digits than any number the policy accepts (so no caller converts a 5,000-digit
    text: Python refuses beyond 4,300 digits, leading zeros included, which are dropped
    here: `000...0001` of a million digits is 1)."""
    if len(text) < 19 and text.isdigit() and text.isascii():
        return int(text)  # the common case: a few digits, no sign
    sign = "-" if text.startswith("-") else ""
    digits = text.lstrip("+-").lstrip("0") or "0"
    if len(digits) > MAX_DIGITS:
        return None
    return int(sign + digits)


class NonFiniteOutput(ValueError):
    """A NaN or an infinity reached a JSON writer: a bug of scriptc (the readers refuse
    non-finite input, so a computation produced it). `where` is its path in the value."""

    def __init__(self, where: str, value: float) -> None:
        self.where = where
        super().__init__(f"the JSON output would hold {value!r} at `{where}`, which JSON cannot "
                         "represent")


def _first_non_finite(value: Any) -> tuple[str, float] | None:
    """The path and value of the first NaN or infinity in a JSON-like value (iteratively)."""
    stack: list[tuple[str, Any]] = [("", value)]
    seen: set[int] = set()  # a container met twice is a cycle (json's own error, then)
    while stack:
        path, item = stack.pop()
        if isinstance(item, float) and not math.isfinite(item):
            return path or "the top level", item
        if isinstance(item, (dict, list, tuple)):
            if id(item) in seen:
                continue
            seen.add(id(item))
        if isinstance(item, dict):
            stack.extend((f"{path}.{k}" if path else str(k), v)
                         for k, v in reversed(list(item.items())))
        elif isinstance(item, (list, tuple)):
            stack.extend((f"{path}[{i}]", v) for i, v in reversed(list(enumerate(item))))
    return None


# JSON data as Python holds it (`json.loads`, a parsed document, a trace event): dicts, lists,
# texts, numbers, booleans and None, nested. Its shape is checked where it is read (a schema,
# or `isinstance`), not by the type checker: this is the one boundary type for it.
JSONValue: TypeAlias = Any
JSONObject: TypeAlias = dict[str, JSONValue]


def json_dumps(value: Any, **options: Any) -> str:
    """`json.dumps` that never writes NaN or Infinity: raises NonFiniteOutput, naming where
    the non-finite number is, instead. `options` are json.dumps's."""
    try:
        return json.dumps(value, allow_nan=False, **options)
    except ValueError:
        found = _first_non_finite(value)
        if found is None:
            raise
        raise NonFiniteOutput(*found) from None
