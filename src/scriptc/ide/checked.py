"""A document open in an editor that is not a script but whose problems the editor shows: a test
file (`*.test.toml`, docs/testing.md). Its text is kept current as a script's is
(`scriptc.ide.document.TextDocument`); its diagnostics come from a check the server hands it,
a function of the text and the file's path (the test file's reader: `scriptc.ide` sits below
`scriptc.testing` and does not read test files itself).

A `CheckedSnapshot` is one checked version: the document's text and the diagnostics, offsets
into that text, read the way a script's `Snapshot` is read for diagnostics (`real_source`,
`layout`, `diagnostics`, `version`). It has nothing else: the editor features of scripts do not
apply to it.

A text that starts with a byte order mark (a client that sends it as a character) is checked
without it, as a file is read, and the diagnostics moved past it.
"""

from __future__ import annotations

from collections.abc import Callable

from scriptc.diagnostics.model import Diagnostic
from scriptc.ide.document import TextDocument
from scriptc.ide.pads import IDENTITY, Layout
from scriptc.ir.shift import shift
from scriptc.source import SourceFile

__all__ = ["Check", "CheckedDocument", "CheckedSnapshot"]

# The check: (text, path of the file) -> its diagnostics, offsets into `text`.
Check = Callable[[str, str], list[Diagnostic]]
_BOM = "\ufeff"


class CheckedSnapshot:
    """One checked version of a `CheckedDocument`."""

    layout: Layout = IDENTITY  # no pads: offsets are the document's own

    def __init__(self, source: SourceFile, diagnostics: list[Diagnostic],
                 version: int | None) -> None:
        self.source = source
        self.diagnostics = diagnostics
        self.version = version

    @property
    def real_source(self) -> SourceFile:
        return self.source

    @property
    def text(self) -> str:
        return self.source.text


class CheckedDocument(TextDocument):
    """A document whose diagnostics are `check`'s over its text (see the module docstring)."""

    def __init__(self, uri: str, text: str, version: int | None = None, *, path: str = "",
                 check: Check) -> None:
        super().__init__(uri, text, version, path=path)
        self.check = check
        self._snapshot: CheckedSnapshot | None = None

    def changed(self, edit: tuple[int, int, str] | None) -> None:
        self._snapshot = None

    def reset_analyzer(self) -> None:
        """Check afresh on the next snapshot (as a script's document forgets its caches)."""
        self._snapshot = None

    def snapshot(self) -> CheckedSnapshot:
        """The diagnostics of the current text (checked on first use after a change)."""
        if self._snapshot is None:
            text = self.text
            bom = len(_BOM) if text.startswith(_BOM) else 0
            diagnostics = self.check(text[bom:], self.path)
            if bom:
                diagnostics = [shift(d, bom) for d in diagnostics]
            self._snapshot = CheckedSnapshot(SourceFile(self.path, text), diagnostics,
                                             self.version)
        return self._snapshot

    @property
    def analysed(self) -> bool:
        return self._snapshot is not None
