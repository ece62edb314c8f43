"""Reading sources: a file's bytes in, a `SourceFile` out, and never an exception for what a
file holds. A file that cannot be read at all (missing, a folder, no permission) is a
`ReadError` whose message names it; content that is not UTF-8 text is a P007 diagnostic at the
first bad byte. A leading UTF-8 byte order mark is dropped (`scriptc.writing.without_bom`; a
rewrite keeps it, `scriptc.writing.encode_like`).
"""

from __future__ import annotations

import os

from scriptc.diagnostics.model import Diagnostic
from scriptc.paths import shown_path
from scriptc.source import SourceFile
from scriptc.writing import without_bom

__all__ = ["ReadError", "decode_source", "read_bytes"]


class ReadError(Exception):
    """A file that cannot be read at all (missing, a directory, no permission). The content
    of a file is never a ReadError: bad bytes are a P007 diagnostic (`decode_source`)."""


def read_bytes(path: str | os.PathLike[str]) -> bytes:
    """The content of a file, or a ReadError that says why it cannot be read."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except FileNotFoundError:
        raise ReadError(f"`{shown_path(os.fspath(path))}` does not exist") from None
    except IsADirectoryError:
        raise ReadError(f"`{shown_path(os.fspath(path))}` is a directory, not a file") from None
    except PermissionError:
        raise ReadError(f"cannot read `{shown_path(os.fspath(path))}`: permission denied") \
            from None
    except OSError as exc:
        raise ReadError(f"cannot read `{shown_path(os.fspath(path))}`: "
                        f"{exc.strerror or exc}") from None


def decode_source(path: str, data: bytes) -> tuple[SourceFile, Diagnostic | None]:
    """Decode the bytes of a script or JSON file as UTF-8, with a leading BOM dropped; `path`
    is the name the source is shown under.

    Invalid UTF-8 and NUL bytes (binary content) give a P007 diagnostic at the first bad
    byte; its line and column are those of the text decoded up to there. The SourceFile then
    holds the whole content with each bad byte replaced by U+FFFD, so that offsets before
    the bad byte are exact and a renderer can show the offending line.
    """
    raw = data
    data = without_bom(raw)
    skipped = len(raw) - len(data)
    bad: int | None = None
    message = ""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad = exc.start
        message = f"the file is not UTF-8 text: byte 0x{data[bad]:02x} is not valid UTF-8"
        text = data.decode("utf-8", errors="replace")
    nul = data.find(b"\x00", 0, bad)
    if nul != -1:
        bad = nul
        message = "the file is not text: it holds a NUL byte (is it a binary file?)"
    if bad is None:
        return SourceFile(path, text), None

    from scriptc.diagnostics.codes import diagnostic
    from scriptc.source import Span

    # The prefix before the first bad byte is valid UTF-8, so its length in code points is
    # the offset of the bad byte in `text` (the replacement keeps the prefix unchanged).
    offset = len(data[:bad].decode("utf-8"))
    notes = [f"at byte offset {bad + skipped} of the file"]
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        notes.append("the file starts with a UTF-16 byte order mark: it is UTF-16, not UTF-8")
    source = SourceFile(path, text)
    return source, diagnostic(
        "P007",
        message,
        Span(offset, min(offset + 1, len(text))),
        notes=notes,
        help="save the file as UTF-8 (scripts are text; binary files cannot be read)",
    )
