"""The plain data editor features return: offsets, strings, tuples. No protocol types.

Kinds are short strings (listed on each class), which `scriptc.server.convert` maps to the
protocol's enumerations; text edits are `scriptc.diagnostics.model.TextEdit`, the same edits
that diagnostic fixes carry.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from scriptc.diagnostics.model import Diagnostic, TextEdit
from scriptc.source import Span

__all__ = ["CodeAction", "CompletionItem", "Fold", "Hover", "InlayHint", "RenameError",
           "SemanticToken", "Symbol", "TextEdit", "VerifyOverview"]


@dataclass(frozen=True, slots=True)
class Hover:
    """Markdown about the thing at `span`."""

    markdown: str
    span: Span


@dataclass(frozen=True, slots=True)
class CompletionItem:
    """One proposal. `kind`: "keyword", "item", "label", "class", "field", "function", "scope",
    "rule", "operator", "letter" or "snippet". `span` is the text the proposal replaces (the
    word typed so far, possibly empty). `snippet`, when set, is the same insertion with
    `${1:placeholders}` for clients that take snippets; `insert_text` is for the others."""

    label: str
    kind: str
    span: Span
    detail: str = ""
    documentation: str = ""
    insert_text: str | None = None
    snippet: str | None = None
    sort_text: str | None = None


@dataclass(frozen=True, slots=True)
class Symbol:
    """An entry of the outline. `kind`: "activity", "messages", "message", "goal", "action",
    "block". `span` covers the whole thing (a goal and all its actions), `selection` its
    name."""

    name: str
    kind: str
    span: Span
    selection: Span
    detail: str = ""
    children: tuple[Symbol, ...] = ()


@dataclass(frozen=True, slots=True)
class Fold:
    """A foldable region. `kind`: "region" or "comment"."""

    span: Span
    kind: str = "region"


class SemanticToken(NamedTuple):
    """A highlighted span. `type` and `modifiers` are the protocol's names (`label`,
    `function`, `declaration`...), listed in `scriptc.ide.tokens.TYPES` and `MODIFIERS`.
    A named tuple: a large script has tens of thousands of tokens."""

    span: Span
    type: str
    modifiers: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class CodeAction:
    """A change offered to the user. `kind`: "quickfix" or "source.fixAll". `diagnostics`
    are the problems it fixes; `preferred` marks the fix to apply without asking (a safe
    fix, in the sense of `Fix.safe`)."""

    title: str
    kind: str
    edits: tuple[TextEdit, ...]
    diagnostics: tuple[Diagnostic, ...] = ()
    preferred: bool = False


@dataclass(frozen=True, slots=True)
class InlayHint:
    """Text shown at `offset` that is not in the file. `kind`: "path", "duration" or
    "verify" (what `scriptc verify` found)."""

    offset: int
    label: str
    kind: str
    tooltip: str = ""


@dataclass(frozen=True, slots=True)
class VerifyOverview:
    """What `scriptc verify` found of a script, as the editor shows it (computed in the
    background, `scriptc.ops.verify.overview`): the session's least and greatest time (ms;
    `longest` None when unbounded or not known, `unbounded` when a run may never end), and
    each goal's verdict by id: "reached" (a replayed run reaches it), "unreached" (no world
    does: `why` says why) or "unknown"."""

    shortest: int | None
    longest: int | None
    unbounded: bool
    goals: tuple[tuple[str, str, str], ...]  # (goal id, verdict, why)


class RenameError(Exception):
    """A rename that cannot be done; the message says why, to the user."""
