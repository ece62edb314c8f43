"""Editor features as plain data: the API under the language server.

Everything here speaks in offsets into one text (code points, as `scriptc.source` does),
strings and small dataclasses; nothing knows LSP, JSON-RPC or UTF-16 (`scriptc.server.convert`
translates). The modules, in the order a document flows through them:

- `document`     a document's text and version, edited by offsets (`Document`)
- `incremental`  analysis that re-parses only the items an edit touched (`Analyzer`)
- `layout`       the pads of spaces that keep the other items in place while one is typed
                 into, and the conversion between a snapshot's offsets and the document's
- `shift`        moving lowered IR and diagnostics by an offset (used by `incremental`)
- `snapshot`     one analysed version of a document (`Snapshot`): what features read
- `index`        what is where: blocks and their paths, labels, aliases, rule ids, names
- `model`        the dataclasses features return (`Hover`, `CompletionItem`, `Symbol`...)
- `hover`, `completion`, `navigation` (definition, references, rename), `outline` (symbols
  and folding), `tokens` (semantic tokens), `actions` (quick fixes), `hints` (inlay hints),
  `formatting` (through `scriptc.formatter`): one feature each, functions of a snapshot and an
  offset returning plain data.

Offsets given to and returned by the feature functions are the snapshot's (its `text`);
`Document.replace` takes offsets of the document's own text. The two are the same for a
snapshot made with `Snapshot.of_text`, and differ by the pads for a document being edited
(`Snapshot.layout` converts).

    snapshot = Snapshot.of_text(text)
    hover(snapshot, offset)            # -> Hover(markdown, span) | None
    complete(snapshot, offset)         # -> [CompletionItem]
    definition(snapshot, offset)       # -> [Span]; references(...), rename(..., new_name)
    document_symbols(snapshot)         # -> [Symbol] (activity > goals > actions > blocks)
    code_actions(snapshot, span)       # -> [CodeAction] (the diagnostics' fixes)
    inlay_hints(snapshot, span)        # -> [InlayHint] (paths and durations)
"""
