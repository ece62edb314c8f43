"""The diagnostic model shared by every stage, renderer, the CLI and the language server.

The model knows no code: a diagnostic built with its code's default severity is
`scriptc.diagnostics.codes.diagnostic`, over the registry (the registry imports this module,
never the reverse).

A diagnostic belongs to one source file (the caller keeps them together); its spans are
offsets into that file's text. Messages follow rustc: lowercase, no trailing period, code
spans in backticks.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from scriptc.source import Span


class Severity(enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 0, "warning": 1, "info": 2}[self.value]


@dataclass(frozen=True, slots=True)
class Label:
    """A secondary span with a short message ("first defined here")."""

    span: Span
    message: str


@dataclass(frozen=True, slots=True)
class TextEdit:
    """Replace the text of `span` with `new_text` (an insertion has an empty span)."""

    span: Span
    new_text: str


@dataclass(frozen=True, slots=True)
class Fix:
    """A suggested change. `safe` fixes keep the script's meaning and may be applied by
    `--fix`; unsafe ones are offered to editors only."""

    message: str
    edits: tuple[TextEdit, ...]
    safe: bool = True


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One problem found in a source: its code, severity, message and where it is."""

    code: str
    severity: Severity
    message: str
    span: Span
    labels: tuple[Label, ...] = ()
    notes: tuple[str, ...] = ()
    help: str | None = None
    fix: Fix | None = None
    # Where the diagnostic comes from, when that is not the script text itself (a JSON path
    # for `scriptc check FILE.json`, say). Renderers show it as a note.
    path: str | None = field(default=None)

    def sort_key(self) -> tuple[int, int, str]:
        return (self.span.start, self.span.end, self.code)


def has_errors(diagnostics: list[Diagnostic] | tuple[Diagnostic, ...]) -> bool:
    return any(d.severity is Severity.ERROR for d in diagnostics)
