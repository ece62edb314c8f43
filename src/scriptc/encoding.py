"""How a file's bytes become text and back, the same for every file scriptc reads or rewrites
(scripts, thesis JSON, configurations, scenarios).

- Text is UTF-8. A leading UTF-8 byte order mark (some Windows editors write one) is dropped
  when a file is read (`without_bom`, `decode`) and kept when the file is rewritten
  (`encode_like`).
- Content that is not UTF-8 text, or that holds a NUL byte (a binary file), is found at its
  first bad byte (`decode`): each reader turns that into its own error (a P007 diagnostic for
  sources, C005 for the configuration, a scenario error), at the place `decode` gives.

Only the standard library: anything may use it.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["UTF8_BOM", "Decoded", "decode", "encode_like", "without_bom"]

UTF8_BOM = b"\xef\xbb\xbf"


def without_bom(data: bytes) -> bytes:
    """A file's bytes without the UTF-8 byte order mark it may start with."""
    return data[len(UTF8_BOM):] if data.startswith(UTF8_BOM) else data


def encode_like(text: str, original: bytes) -> bytes:
    """`text` as UTF-8, with a byte order mark when the file it replaces (`original`) had one."""
    return (UTF8_BOM if original.startswith(UTF8_BOM) else b"") + text.encode("utf-8")


@dataclass(frozen=True, slots=True)
class Decoded:
    """A file's content as text. When it is not all UTF-8 text, `bad` is the offset in `text`
    of the first bad byte (each bad byte is U+FFFD in `text`, so the offsets before it are
    exact and the offending line can be shown), `byte` that byte's offset in the file (the
    byte order mark counted), `problem` what is wrong with it, and `utf16` whether the file
    starts with a UTF-16 byte order mark (it is UTF-16 text, not UTF-8)."""

    text: str
    bad: int | None = None
    byte: int | None = None
    problem: str = ""
    utf16: bool = False


def decode(data: bytes) -> Decoded:
    """The bytes of a file as text, the byte order mark dropped; see `Decoded`."""
    body = without_bom(data)
    skipped = len(data) - len(body)
    bad: int | None = None
    problem = ""
    try:
        text = body.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad = exc.start
        problem = f"the file is not UTF-8 text: byte 0x{body[bad]:02x} is not valid UTF-8"
        text = body.decode("utf-8", errors="replace")
    nul = body.find(b"\x00", 0, bad)
    if nul != -1:
        bad = nul
        problem = "the file is not text: it holds a NUL byte (is it a binary file?)"
    if bad is None:
        return Decoded(text)
    # The bytes before the first bad one are valid UTF-8, so their length in code points is
    # the bad byte's offset in `text` (the replacement leaves them as they are).
    return Decoded(text, len(body[:bad].decode("utf-8")), bad + skipped, problem,
                   data.startswith((b"\xff\xfe", b"\xfe\xff")))
