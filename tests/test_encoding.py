"""scriptc.encoding: how every reader turns a file's bytes into text (the byte order mark
dropped, the first bad byte found) and every rewrite keeps the mark."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from scriptc.encoding import UTF8_BOM, decode, encode_like, without_bom

texts = st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"))


@given(texts, st.booleans())
def test_a_rewrite_reads_back_and_keeps_the_mark(text: str, bom: bool) -> None:
    original = (UTF8_BOM if bom else b"") + b"old"
    data = encode_like(text, original)
    assert data.startswith(UTF8_BOM) == bom
    assert without_bom(data) == text.encode("utf-8")
    assert decode(data).text == text
    assert decode(data).bad is None


@given(texts, st.sampled_from([b"\xff", b"\xc3", b"\xe9", b"\x80", b"\xed\xa0\x80"]), texts,
       st.booleans())
def test_the_first_bad_byte_is_found_where_it_is(before: str, bad: bytes, after: str,
                                                 bom: bool) -> None:
    mark = UTF8_BOM if bom else b""
    data = mark + before.encode("utf-8") + bad + after.encode("utf-8")
    decoded = decode(data)
    assert decoded.bad == len(before)
    assert decoded.byte == len(mark) + len(before.encode("utf-8"))
    assert decoded.text.startswith(before)
    assert decoded.text[len(before)] == "\ufffd"
    assert decoded.problem == (f"the file is not UTF-8 text: byte 0x{bad[0]:02x} is not "
                               "valid UTF-8")
    assert not decoded.utf16


@given(texts, texts)
def test_a_nul_byte_makes_a_binary_file(before: str, after: str) -> None:
    data = before.encode("utf-8") + b"\x00" + after.encode("utf-8") + b"\xff"
    decoded = decode(data)
    assert decoded.bad == len(before)
    assert decoded.problem == "the file is not text: it holds a NUL byte (is it a binary file?)"


def test_a_bad_byte_before_a_nul_is_the_first() -> None:
    decoded = decode(b"ab\xffc\x00")
    assert (decoded.bad, decoded.byte) == (2, 2)
    assert "not UTF-8" in decoded.problem


def test_utf16_is_named() -> None:
    assert decode("ciao".encode("utf-16")).utf16
    assert decode(b"\xfe\xff\x00c\x00i\x00a\x00o").utf16
    assert not decode(b"\xffciao").utf16


def test_only_a_leading_mark_is_dropped() -> None:
    assert without_bom(UTF8_BOM + UTF8_BOM + b"x") == UTF8_BOM + b"x"
    assert without_bom(b"x" + UTF8_BOM) == b"x" + UTF8_BOM
    assert decode(b"x" + UTF8_BOM).text == "x\ufeff"
