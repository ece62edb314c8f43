"""All conversion between the editor API (`scriptc.ide`: offsets, plain data) and the protocol
(`lsprotocol` types: lines, and columns in the negotiated position encoding). Nothing else in
scriptc computes an LSP position or builds an LSP type; the handlers of `scriptc.server.main`
call these functions.

Positions: scriptc counts code points in the whole text; the protocol counts lines, and
columns in the code units of the position encoding that client and server agreed on at
`initialize` (`positionEncoding`): UTF-16 code units unless the client offered another
(`utf-8`: bytes, `utf-32`: code points). An accented letter is one UTF-16 unit and two UTF-8
bytes; a character outside the Basic Multilingual Plane (an emoji) is one code point, two
UTF-16 units and four bytes. Every position in and out goes through `Positions`, which
counts in its encoding, so the server's copy of a document stays the client's whatever it
negotiated.

Incoming positions are clamped as the protocol says (a character past the end of its line
means the end of the line; a line past the last means the end of the text). A position
inside a character (between the two halves of a UTF-16 surrogate pair, or among the bytes of
one UTF-8 sequence) names no character: in UTF-16 it is kept exact when it comes with an edit
(`change_to_edit`: the client's UTF-16 text really is split there), and otherwise rounded down
to the start of the character; in UTF-8 it is always rounded down (a client's UTF-8 text
cannot hold half a character).
"""

from __future__ import annotations

from functools import cache

from lsprotocol import types as lsp

from scriptc.diagnostics.codes import explanation_uri
from scriptc.diagnostics.model import Diagnostic, Severity, TextEdit
from scriptc.ide import answers
from scriptc.ide.pads import IDENTITY, Layout
from scriptc.ide.tokens import MODIFIERS, TYPES
from scriptc.numbers import JSONObject
from scriptc.source import SourceFile, Span

SOURCE = "scriptc"

_SEVERITY = {
    Severity.ERROR: lsp.DiagnosticSeverity.Error,
    Severity.WARNING: lsp.DiagnosticSeverity.Warning,
    Severity.INFO: lsp.DiagnosticSeverity.Information,
}
# Codes whose span is code that never runs: editors fade it.
_UNNECESSARY = {"F001"}

_COMPLETION_KIND = {
    "keyword": lsp.CompletionItemKind.Keyword,
    "item": lsp.CompletionItemKind.Keyword,
    "label": lsp.CompletionItemKind.Reference,
    "class": lsp.CompletionItemKind.Class,
    "field": lsp.CompletionItemKind.Field,
    "function": lsp.CompletionItemKind.Function,
    "scope": lsp.CompletionItemKind.EnumMember,
    "rule": lsp.CompletionItemKind.Event,
    "operator": lsp.CompletionItemKind.Operator,
    "letter": lsp.CompletionItemKind.EnumMember,
    "snippet": lsp.CompletionItemKind.Snippet,
    "variable": lsp.CompletionItemKind.Variable,
}
_SYMBOL_KIND = {
    "activity": lsp.SymbolKind.Module,
    "message": lsp.SymbolKind.Event,
    "goal": lsp.SymbolKind.Namespace,
    "action": lsp.SymbolKind.Method,
    "block": lsp.SymbolKind.Function,
}
_FOLD_KIND = {"region": lsp.FoldingRangeKind.Region, "comment": lsp.FoldingRangeKind.Comment}
_TYPE_INDEX = {name: i for i, name in enumerate(TYPES)}
_MODIFIER_BIT = {name: 1 << i for i, name in enumerate(MODIFIERS)}



class Json:
    """A result already in the protocol's JSON form (dicts, lists, numbers, strings): the
    server sends it as it is (see `scriptc.server.main.ScriptcProtocol`)."""

    __slots__ = ("value",)

    def __init__(self, value) -> None:
        self.value = value


LEGEND = lsp.SemanticTokensLegend(token_types=list(TYPES), token_modifiers=list(MODIFIERS))


# -- positions ------------------------------------------------------------------------------------

UTF8 = lsp.PositionEncodingKind.Utf8.value
UTF16 = lsp.PositionEncodingKind.Utf16.value
UTF32 = lsp.PositionEncodingKind.Utf32.value
ENCODINGS = (UTF8, UTF16, UTF32)


def units(text: str, encoding: str = UTF16) -> int:
    """The length of `text` in code units of a position encoding. Lone surrogates (a client's
    UTF-16 text split inside an emoji) count one UTF-16 unit each."""
    if encoding == UTF32 or text.isascii():
        return len(text)
    if encoding == UTF16:
        return len(text.encode("utf-16-le", "surrogatepass")) >> 1
    return len(text.encode("utf-8", "surrogatepass"))


def _width(ch: str, encoding: str) -> int:
    """The code units of one character."""
    code = ord(ch)
    if encoding == UTF16:
        return 2 if code > 0xFFFF else 1
    if encoding == UTF8:
        return 1 if code < 0x80 else 2 if code < 0x800 else 3 if code < 0x10000 else 4
    return 1


class Positions:
    """Offsets <-> protocol positions for one document, counted in one position encoding.
    Offsets are those of a snapshot (its analysis text, see `scriptc.ide.pads`), converted
    through `layout` to offsets of the document's text, whose lines and columns the protocol
    counts. Lines of ASCII text (the usual case) need no counting: in every encoding, their
    column is the distance from the line's start."""

    __slots__ = ("ascii", "encoding", "layout", "source", "text")

    def __init__(self, source: SourceFile, layout: Layout = IDENTITY,
                 encoding: str = UTF16) -> None:
        if encoding not in ENCODINGS:
            raise ValueError(f"unknown position encoding {encoding!r}")
        self.source = source  # the document's text
        self.layout = layout
        self.text = source.text
        self.encoding = encoding
        # Code points are UTF-32's units: every text counts as plain.
        self.ascii = encoding == UTF32 or self.text.isascii()

    def units(self, text: str) -> int:
        """The length of a piece of the text in this encoding's code units."""
        return len(text) if self.ascii else units(text, self.encoding)

    def position(self, offset: int) -> lsp.Position:
        return self._position(self.layout.to_real(offset))

    def _position(self, offset: int) -> lsp.Position:
        source = self.source
        offset = max(0, min(offset, len(self.text)))
        line = source.line_of(offset)
        start = source.line_starts[line]
        if self.ascii:
            return lsp.Position(line, offset - start)
        return lsp.Position(line, units(self.text[start:offset], self.encoding))

    def range(self, span: Span) -> lsp.Range:
        return lsp.Range(self.position(span.start), self.position(span.end))

    def locate(self, position: lsp.Position) -> tuple[int, bool]:
        """The document offset of a protocol position, and whether it falls between the two
        halves of a UTF-16 surrogate pair (then the offset is that of the character it
        splits). A position among the bytes of a UTF-8 sequence is that character's start."""
        source = self.source
        starts = source.line_starts
        line, character = position.line, position.character
        if line < 0:
            return 0, False
        if line >= len(starts):
            return len(self.text), False
        start = starts[line]
        end = source.line_end(line)
        if self.ascii:
            return min(start + max(character, 0), end), False
        text = self.text
        encoding = self.encoding
        count = 0
        offset = start
        while offset < end and count < character:
            count += _width(text[offset], encoding)
            offset += 1
        if count > character:
            return offset - 1, encoding == UTF16
        return offset, False

    def offset(self, position: lsp.Position) -> int:
        """The snapshot offset of a protocol position."""
        return self.layout.to_analysis(self.locate(position)[0])

    def span(self, range_: lsp.Range) -> Span:
        a, b = self.offset(range_.start), self.offset(range_.end)
        return Span(min(a, b), max(a, b))


def positions(snapshot, encoding: str = UTF16) -> Positions:
    """The converter of a snapshot's offsets, made once per snapshot (and encoding)."""
    found = snapshot.__dict__.get("_lsp_positions")
    if found is None or found.encoding != encoding:
        found = snapshot.__dict__["_lsp_positions"] = Positions(snapshot.real_source,
                                                                snapshot.layout, encoding)
    return found


def text_positions(text: str, encoding: str = UTF16) -> Positions:
    """The converter of a plain text (no layout): for edits to a document's text. Made anew
    each time (a converter kept on its own text would make a reference cycle, which the
    server, running with the collector off, would keep until it is idle)."""
    return Positions(SourceFile("", text), IDENTITY, encoding)


def change_to_edit(text: str, range_: lsp.Range, new_text: str,
                   encoding: str = UTF16) -> tuple[int, int, str]:
    """An incremental change of the document `text` as `(start, end, new_text)` in code
    points. In UTF-16, an end of the range between the halves of a surrogate pair widens the
    edit to the whole character and keeps the half that stays, so the result is what the
    client's UTF-16 text becomes."""
    p = text_positions(text, encoding)
    start, start_split = p.locate(range_.start)
    end, end_split = p.locate(range_.end)
    if (end, end_split) < (start, start_split):
        start, start_split, end, end_split = end, end_split, start, start_split
    prefix = suffix = ""
    if start_split:
        prefix = _halves(text[start])[0]
    if end_split:
        suffix = _halves(text[end])[1]
        end += 1
    return start, end, prefix + new_text + suffix


def _halves(ch: str) -> tuple[str, str]:
    units = ch.encode("utf-16-le", "surrogatepass")
    return (units[:2].decode("utf-16-le", "surrogatepass"),
            units[2:].decode("utf-16-le", "surrogatepass"))


# -- diagnostics --------------------------------------------------------------------------------


def diagnostic(p: Positions, uri: str, d: Diagnostic) -> lsp.Diagnostic:
    """The protocol's diagnostic: the code and message the CLI prints; labels as related
    locations; notes and help as related information at the diagnostic itself (editors list
    them under the message). The code links (`codeDescription`) to its explanation, a file
    shipped inside the package (the codes have no public page); a hover on a code, or the
    `scriptc.explain` command, gives the same text."""
    primary = p.range(d.span)
    related = [lsp.DiagnosticRelatedInformation(lsp.Location(uri, p.range(label.span)),
                                                label.message)
               for label in d.labels]
    related += [lsp.DiagnosticRelatedInformation(lsp.Location(uri, primary), f"note: {note}")
                for note in d.notes]
    if d.help:
        related.append(lsp.DiagnosticRelatedInformation(lsp.Location(uri, primary),
                                                        f"help: {d.help}"))
    return lsp.Diagnostic(
        range=primary,
        message=d.message,
        severity=_SEVERITY[d.severity],
        code=d.code,
        code_description=_code_link(d.code),
        source=SOURCE,
        related_information=related or None,
        tags=[lsp.DiagnosticTag.Unnecessary] if d.code in _UNNECESSARY else None,
    )


@cache
def _code_link(code: str) -> lsp.CodeDescription | None:
    uri = explanation_uri(code)
    return lsp.CodeDescription(href=uri) if uri else None


def diagnostics(p: Positions, uri: str, items: list[Diagnostic]) -> list[lsp.Diagnostic]:
    return [diagnostic(p, uri, d) for d in items]


# -- edits ----------------------------------------------------------------------------------------


def text_edits(p: Positions, edits) -> list[lsp.TextEdit]:
    return [lsp.TextEdit(p.range(e.span), e.new_text) for e in edits]


def workspace_edit(p: Positions, uri: str, edits) -> lsp.WorkspaceEdit:
    return lsp.WorkspaceEdit(changes={uri: text_edits(p, edits)})


# -- features -----------------------------------------------------------------------------------


def hover(p: Positions, h: answers.Hover | None) -> lsp.Hover | None:
    if h is None:
        return None
    return lsp.Hover(lsp.MarkupContent(lsp.MarkupKind.Markdown, h.markdown), p.range(h.span))


def _json_range(r: lsp.Range) -> JSONObject:
    return {"start": {"line": r.start.line, "character": r.start.character},
            "end": {"line": r.end.line, "character": r.end.character}}


def completion_list(p: Positions, items: list[answers.CompletionItem], snippets: bool,
                    markdown: bool = True) -> Json:
    """A CompletionList, in JSON form (a large script has hundreds of labels to propose).
    Documentation is markdown when the client says it reads markdown, else plain text."""
    out = []
    ranges: dict[Span, JSONObject] = {}
    for item in items:
        r = ranges.get(item.span)
        if r is None:
            r = ranges[item.span] = _json_range(p.range(item.span))
        use_snippet = snippets and item.snippet is not None
        entry: JSONObject = {"label": item.label,
                             "textEdit": {"range": r, "newText": item.snippet if use_snippet
                                          else (item.insert_text or item.label)}}
        kind = _COMPLETION_KIND.get(item.kind)
        if kind is not None:
            entry["kind"] = int(kind)
        if item.detail:
            entry["detail"] = item.detail
        if item.documentation:
            entry["documentation"] = ({"kind": "markdown", "value": item.documentation}
                                      if markdown else item.documentation)
        if item.sort_text is not None:
            entry["sortText"] = item.sort_text
        if use_snippet:
            entry["insertTextFormat"] = int(lsp.InsertTextFormat.Snippet)
        out.append(entry)
    return Json({"isIncomplete": False, "items": out})


def locations(p: Positions, uri: str, spans: list[Span]) -> list[lsp.Location]:
    return [lsp.Location(uri, p.range(s)) for s in spans]


def document_symbols(p: Positions, symbols: list[answers.Symbol]) -> list[lsp.DocumentSymbol]:

    def one(s: answers.Symbol) -> lsp.DocumentSymbol:
        return lsp.DocumentSymbol(
            name=s.name or "?",
            kind=_SYMBOL_KIND.get(s.kind, lsp.SymbolKind.Object),
            range=p.range(s.span),
            selection_range=p.range(s.selection),
            detail=s.detail or None,
            children=[one(c) for c in s.children] or None,
        )

    return [one(s) for s in symbols]


def folding_ranges(p: Positions, folds: list[answers.Fold]) -> list[lsp.FoldingRange]:
    out = []
    seen: set[int] = set()
    for f in folds:
        start = p.position(f.span.start).line
        end = p.position(max(f.span.start, f.span.end - 1)).line
        if end <= start or start in seen:
            continue
        seen.add(start)
        out.append(lsp.FoldingRange(start_line=start, end_line=end, kind=_FOLD_KIND.get(f.kind)))
    return out


def semantic_tokens(p: Positions, tokens: list[answers.SemanticToken]) -> Json:
    """The protocol's relative encoding: per token, the line delta, the start delta (in the
    position encoding's units, from the previous token on the same line), the length, the
    type and the modifier bits.
    Tokens over several lines (comments) are cut at line ends. Tokens come in text order, so
    the line is found by walking forward, not searched for each token."""
    source = p.source
    text = source.text
    starts = source.line_starts
    lines = len(starts)
    to_real = p.layout.to_real
    identity = p.layout.identity
    ascii_ = p.ascii
    count = p.units
    data: list[int] = []
    last_line = last_col = 0
    line = 0
    bits_of: dict[tuple[str, ...], int] = {}
    for token in tokens:
        type_index = _TYPE_INDEX.get(token.type)
        if type_index is None:
            continue
        bits = bits_of.get(token.modifiers)
        if bits is None:
            bits = 0
            for m in token.modifiers:
                bits |= _MODIFIER_BIT.get(m, 0)
            bits_of[token.modifiers] = bits
        start, end = token.span
        if not identity:
            start, end = to_real(start), to_real(end)
        while line + 1 < lines and starts[line + 1] <= start:
            line += 1
        if line + 1 >= lines or end < starts[line + 1]:  # on one line (the usual case)
            if ascii_:
                col, length = start - starts[line], end - start
            else:
                col, length = count(text[starts[line]:start]), count(text[start:end])
            data += (line - last_line, col - last_col if line == last_line else col, length,
                     type_index, bits)
            last_line, last_col = line, col
            continue
        piece_line = line
        while start < end:
            piece_end = min(end, source.line_end(piece_line))
            if piece_end > start:
                col = count(text[starts[piece_line]:start])
                data += (piece_line - last_line, col - last_col if piece_line == last_line else col,
                         count(text[start:piece_end]), type_index, bits)
                last_line, last_col = piece_line, col
            piece_line += 1
            if piece_line >= lines:
                break
            start = max(start, starts[piece_line])
    return Json({"data": data})


_CODE_ACTION_KIND = {"quickfix": lsp.CodeActionKind.QuickFix,
                     "source.fixAll": lsp.CodeActionKind.SourceFixAll}


def code_actions(p: Positions, uri: str, actions: list[answers.CodeAction]) -> list[lsp.CodeAction]:
    return [lsp.CodeAction(
        title=a.title,
        kind=_CODE_ACTION_KIND.get(a.kind, a.kind),
        diagnostics=diagnostics(p, uri, list(a.diagnostics)) or None,
        is_preferred=a.preferred or None,
        edit=workspace_edit(p, uri, a.edits),
    ) for a in actions]


def inlay_hints(p: Positions, hints: list[answers.InlayHint]) -> list[lsp.InlayHint]:
    return [lsp.InlayHint(position=p.position(h.offset), label=h.label, padding_left=True,
                          tooltip=h.tooltip or None) for h in hints]


def text_edit_list(p: Positions, edits: list[TextEdit] | None) -> list[lsp.TextEdit] | None:
    return None if edits is None else text_edits(p, edits)
