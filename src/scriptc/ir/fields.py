"""Reading numbers and text the same way from script syntax and from thesis JSON.

Both front ends (lowering of the script syntax and the thesis JSON reader) turn the text of a
field into a `Number` here, so "is this a number" has one answer everywhere.
"""

from __future__ import annotations

import re

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.ir.nodes import Number
from scriptc.language import NUMBER_PATTERN
from scriptc.source import Span

# The language's number (docs/language.md): decimal, optional sign, fraction and exponent (C++'s
# stof, which read these fields on the robot, accepts it), ASCII digits only; ranges are checked
# by the checker.
NUMBER_RE = re.compile(NUMBER_PATTERN)


def fields_pattern(count: int, text_first: bool = False) -> re.Pattern[str]:
    """A command string of `count` comma-separated numbers (the first a non-empty text when
    `text_first`, which may itself hold commas, as an audio path), blanks around each: group i
    is field i, trimmed as `str.strip` trims (`\\s` is `str.isspace`). The text ends at a
    non-blank (`\\S(?:.*?\\S)?`, not `\\S.*?` before the blanks: that form retried the blanks
    at each of their characters, quadratic in a path holding a megabyte of spaces)."""
    field = rf"\s*({NUMBER_PATTERN})\s*"
    parts = [r"\s*(\S(?:.*?\S)?)\s*"] + [field] * (count - 1) if text_first else [field] * count
    return re.compile(",".join(parts), re.DOTALL)


_NON_FINITE = re.compile(r"[+-]?(nan|inf|infinity)", re.IGNORECASE)


def read_number(text: str, span: Span, what: str) -> tuple[Number, Diagnostic | None]:
    """`text` (already trimmed) as a Number; a diagnostic when it is not one. `what` names
    the field for the message ("`v_x`", "the rulecode")."""
    number = Number(text, span)
    if NUMBER_RE.fullmatch(text):
        return number, None
    if _NON_FINITE.fullmatch(text):
        return number, diagnostic(
            "V003",
            f"{what} is `{text}`, which is not a finite number",
            span,
            help="write a finite decimal number such as `0.5`",
        )
    shown = text if text else "nothing"
    return number, diagnostic(
        "V002",
        f"{what} must be a number, found `{shown}`" if text else f"{what} is missing",
        span,
        help="write a decimal number such as `0`, `1000` or `-0.25`",
    )
