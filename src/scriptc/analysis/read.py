"""Reading sources: a file's bytes in, a `SourceFile` out, and never an exception for what a
file holds. A file that cannot be read at all (missing, a folder, no permission) is a
`ReadError` whose message names it; content that is not UTF-8 text is a P007 diagnostic at the
first bad byte. A leading UTF-8 byte order mark is dropped (`scriptc.encoding`; a rewrite
keeps it).
"""

from __future__ import annotations

import os

from scriptc.diagnostics.model import Diagnostic
from scriptc.encoding import decode
from scriptc.paths import shown_path
from scriptc.source import SourceFile

__all__ = ["ReadError", "decode_source", "read_bytes"]


class ReadError(Exception):
    """A file that cannot be read at all (missing, a directory, no permission). The content
    of a file is never a ReadError: bad bytes are a P007 diagnostic (`decode_source`). The
    message names the file; `reason` says why without naming it, for a caller that names it
    itself."""

    def __init__(self, message: str, reason: str | None = None) -> None:
        super().__init__(message)
        self.reason = reason if reason is not None else message


def read_bytes(path: str | os.PathLike[str]) -> bytes:
    """The content of a file, or a ReadError that says why it cannot be read."""
    shown = shown_path(os.fspath(path))
    try:
        with open(path, "rb") as f:
            return f.read()
    except FileNotFoundError:
        raise ReadError(f"`{shown}` does not exist", "the file does not exist") from None
    except IsADirectoryError:
        raise ReadError(f"`{shown}` is a directory, not a file",
                        "it is a directory, not a file") from None
    except PermissionError:
        raise ReadError(f"cannot read `{shown}`: permission denied",
                        "cannot read it: permission denied") from None
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise ReadError(f"cannot read `{shown}`: {reason}", f"cannot read it: {reason}") \
            from None


def decode_source(path: str, data: bytes) -> tuple[SourceFile, Diagnostic | None]:
    """Decode the bytes of a script or JSON file as UTF-8, with a leading BOM dropped; `path`
    is the name the source is shown under.

    Invalid UTF-8 and NUL bytes (binary content) give a P007 diagnostic at the first bad
    byte; its line and column are those of the text decoded up to there. The SourceFile then
    holds the whole content with each bad byte replaced by U+FFFD, so that offsets before
    the bad byte are exact and a renderer can show the offending line.
    """
    decoded = decode(data)
    source = SourceFile(path, decoded.text)
    if decoded.bad is None:
        return source, None

    from scriptc.diagnostics.codes import diagnostic
    from scriptc.source import Span

    offset = decoded.bad
    notes = [f"at byte offset {decoded.byte} of the file"]
    if decoded.utf16:
        notes.append("the file starts with a UTF-16 byte order mark: it is UTF-16, not UTF-8")
    return source, diagnostic(
        "P007",
        decoded.problem,
        Span(offset, min(offset + 1, len(decoded.text))),
        notes=notes,
        help="save the file as UTF-8 (scripts are text; binary files cannot be read)",
    )
