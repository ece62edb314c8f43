"""A document open in an editor: its text, its version, and its analysis, kept current.

Edits come as offsets (code points) with the new text; `scriptc.server.convert` turns the
protocol's ranges (lines, and columns in the negotiated position encoding) into these. The
text is kept in one canonical form: a UTF-16 surrogate pair is always one code point, and a
surrogate left alone (an edit of a UTF-16 client that split an emoji, a client that sent half
of one) stays a lone surrogate code point. That is exactly the client's text read as UTF-16,
so offsets and UTF-16 columns never drift apart, whatever the edits (UTF-8 and UTF-32
clients cannot split a character).

`TextDocument` is that text and its version, edited; `Document`, a script's, adds its analysis:
`Document.snapshot()` analyses the current text if it changed (`scriptc.ide.incremental`)
and returns the `Snapshot` every editor feature reads. `configured_document` opens a file's
document under its repository's setup, as `scriptc lint` reads the file. A document of
another kind (a test file) is a `TextDocument` too (`scriptc.ide.checked`).
"""

from __future__ import annotations

import re

from scriptc.ide.incremental import Analyzer
from scriptc.ide.snapshot import Snapshot
from scriptc.ir.builtins import STANDARD, FunctionRegistry

_SURROGATE = re.compile("[\ud800-\udfff]")


def canonical(text: str) -> str:
    """`text` with every high surrogate followed by a low one joined into one code point."""
    if _SURROGATE.search(text) is None:
        return text
    return text.encode("utf-16-le", "surrogatepass").decode("utf-16-le", "surrogatepass")


class TextDocument:
    """One open document's text (in the canonical form above) and version, edited by offsets.
    Not thread-safe (the server uses it from its event loop)."""

    def __init__(self, uri: str, text: str, version: int | None = None, *,
                 path: str = "") -> None:
        self.uri = uri
        self.path = path or uri
        self.version = version
        self.text = canonical(text)

    def changed(self, edit: tuple[int, int, str] | None) -> None:
        """The text changed by `edit` (`(start, end, new_text)` of the old text), or was
        replaced whole (None): what a subclass derives from the text is stale."""

    def set_text(self, text: str, version: int | None = None) -> None:
        self.text = canonical(text)
        self.version = version
        self.changed(None)

    def replace(self, start: int, end: int, new_text: str) -> None:
        """Replace `text[start:end]` (clamped to the text, ends in either order)."""
        n = len(self.text)
        start, end = max(0, min(start, n)), max(0, min(end, n))
        if end < start:
            start, end = end, start
        old = self.text
        text = old[:start] + new_text + old[end:]
        edit = (start, end, new_text)
        # Only the edges of the edit and the new text can hold surrogates to join.
        lo, hi = max(0, start - 1), min(len(text), start + len(new_text) + 1)
        window = text[lo:hi]
        if _SURROGATE.search(window) is not None:
            joined = canonical(window)
            text = text[:lo] + joined + text[hi:]
            # As one edit of the old text: the window, from `lo` to where it ended there.
            edit = (lo, end + (hi - start - len(new_text)), joined)
        self.text = text
        self.changed(edit)


class Document(TextDocument):
    """An open script, analysed as `scriptc lint` analyses it."""

    def __init__(self, uri: str, text: str, version: int | None = None, *, path: str = "",
                 functions: FunctionRegistry = STANDARD, policy=None, profile=None) -> None:
        """`functions`: the registry the checks use (a repository's configuration extends
        the standard one); `policy`: what is reported of the diagnostics found (a
        configuration's selection and severities, `Settings.apply`), None for everything;
        `profile`: the robot profile of the safety checks (None: the defaults)."""
        super().__init__(uri, text, version, path=path)
        self.policy = policy
        self._analyzer = Analyzer(functions, slack=True, profile=profile)
        self._snapshot: Snapshot | None = None
        # The edits since the last analysis, for the analyser to follow (None: unknown).
        self._edits: list[tuple[int, int, str]] | None = None

    def changed(self, edit: tuple[int, int, str] | None) -> None:
        self._snapshot = None
        if edit is None:
            self._edits = None
        elif self._edits is not None:
            self._edits.append(edit)

    def reset_analyzer(self) -> None:
        """Forget the caches of incremental analysis (the next snapshot analyses afresh)."""
        self._analyzer = Analyzer(self._analyzer.functions, slack=True,
                                  profile=self._analyzer.profile)
        self._snapshot = None
        self._edits = None

    def snapshot(self) -> Snapshot:
        """The analysis of the current text (computed on first use after a change)."""
        if self._snapshot is None:
            edits, self._edits = self._edits, []
            result = self._analyzer.analyze(self.text, self.path, edits)
            self._snapshot = Snapshot(result, self.version, self._analyzer.functions,
                                      self.policy)
        return self._snapshot

    @property
    def analysed(self) -> bool:
        return self._snapshot is not None


def configured_document(uri: str, text: str, version: int | None = None, *,
                        path: str | None = None) -> tuple[Document, list]:
    """A document with its repository's setup (`scriptc.project.setup`), as `scriptc lint`
    reads the file `path`: the functions the configuration declares, its robot profile and
    its policy (selection, per-file ignores, severities); with no `path` (a document that is
    not a file), the defaults. Also returns the configuration's problems (each with its
    `source` and `diagnostics`), which `scriptc lint` would show on stderr."""
    if path is None:
        return Document(uri, text, version, path=uri), []
    from scriptc.project.setup import setup_for

    setup = setup_for(path)
    return Document(uri, text, version, path=path, functions=setup.functions,
                    policy=lambda diagnostics: setup.apply(diagnostics, path),
                    profile=setup.profile), setup.problems
