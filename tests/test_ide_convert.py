"""scriptc.server.convert, without a server: offsets <-> positions in each position encoding
(UTF-8, UTF-16, UTF-32; emoji, accents, line breaks of every kind, lone surrogates), edits
that split a surrogate pair or land after non-ASCII text, the layout of an analysis text with
pads, and the JSON forms sent as they are."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from scriptc.ide import answers
from scriptc.ide.document import Document
from scriptc.ide.pads import Layout
from scriptc.server import convert
from scriptc.source import SourceFile, Span

TEXT = "[a]\r\n% é😀x %\n\ud83d[b]\r[c]😀"


# The encodings' codecs and the bytes of one code unit: the tests count with Python's codecs.
CODECS = {"utf-8": ("utf-8", 1), "utf-16": ("utf-16-le", 2), "utf-32": ("utf-32-le", 4)}


def units_before(text: str, offset: int, encoding: str = "utf-16") -> tuple[int, int]:
    """(line, column in the encoding's units) of an offset, counted here the slow, obvious
    way."""
    line_start, line = 0, 0
    i = 0
    while i < offset:
        if text[i] == "\r" and i + 1 < len(text) and text[i + 1] == "\n" and i + 1 < offset:
            i += 2
            line += 1
            line_start = i
            continue
        if text[i] in "\r\n":
            line += 1
            line_start = i + 1
        i += 1
    codec, size = CODECS[encoding]
    return line, len(text[line_start:offset].encode(codec, "surrogatepass")) // size


def test_the_encodings_are_the_protocols():
    assert set(convert.ENCODINGS) == {str(k.value) for k in lsp.PositionEncodingKind} == set(CODECS)


@pytest.mark.parametrize("encoding", convert.ENCODINGS)
@pytest.mark.parametrize("offset", range(len(TEXT) + 1))
def test_positions_count_the_units_of_the_encoding(offset, encoding):
    p = convert.text_positions(TEXT, encoding)
    if offset > 0 and TEXT[offset - 1] == "\r" and offset < len(TEXT) and TEXT[offset] == "\n":
        return  # between the \r and \n of one line break: not a position of the protocol
    position = p.position(offset)
    assert (position.line, position.character) == units_before(TEXT, offset, encoding)
    assert p.offset(position) == offset
    codec, size = CODECS[encoding]
    assert p.units(TEXT[:offset]) == len(TEXT[:offset].encode(codec, "surrogatepass")) // size


def test_an_unknown_encoding_is_refused():
    with pytest.raises(ValueError, match="utf-7"):
        convert.text_positions(TEXT, "utf-7")


def test_a_position_inside_a_utf8_sequence_is_the_start_of_its_character():
    p = convert.text_positions(TEXT, "utf-8")
    second = TEXT.index("%")  # line 1: `% é😀x %`, é two bytes, 😀 four
    assert p.locate(lsp.Position(1, 3)) == (second + 2, False)  # inside é
    assert p.locate(lsp.Position(1, 4)) == (second + 3, False)  # after é
    for inside in (5, 6, 7):
        assert p.locate(lsp.Position(1, inside)) == (second + 3, False)  # inside 😀
    assert p.locate(lsp.Position(1, 8)) == (second + 4, False)
    assert p.locate(lsp.Position(1, 99)) == (TEXT.index("\n", second), False)


@pytest.mark.parametrize("encoding", convert.ENCODINGS)
def test_edits_after_non_ascii_text_land_where_the_client_made_them(encoding):
    """An insertion after `é😀` and a deletion of the `x` after them, with the client's
    positions counted in each encoding: the document is the client's text each time."""
    doc = Document("x", "[a] é😀x\n[b] 😀")
    column = units_before(doc.text, doc.text.index("x"), encoding)[1]
    at = lsp.Position(0, column)
    doc.replace(*convert.change_to_edit(doc.text, lsp.Range(at, at), "ü", encoding))
    assert doc.text == "[a] é😀üx\n[b] 😀"
    after = lsp.Position(0, column + units_before("ü", 1, encoding)[1])
    x = lsp.Range(after, lsp.Position(after.line, after.character + 1))
    doc.replace(*convert.change_to_edit(doc.text, x, "", encoding))
    assert doc.text == "[a] é😀ü\n[b] 😀"
    end = lsp.Position(1, units_before(doc.text, len(doc.text), encoding)[1])
    doc.replace(*convert.change_to_edit(doc.text, lsp.Range(end, end), "!", encoding))
    assert doc.text == "[a] é😀ü\n[b] 😀!"


def test_positions_past_the_end_are_clamped():
    p = convert.text_positions(TEXT)
    assert p.offset(lsp.Position(0, 99)) == 3  # the end of `[a]`, before \r\n
    assert p.offset(lsp.Position(99, 0)) == len(TEXT)
    second = TEXT.index("%")
    assert p.locate(lsp.Position(1, 4)) == (second + 3, True)  # between the halves of 😀


def test_an_edit_between_surrogate_halves_keeps_both_halves():
    doc = Document("x", "[a] 😀")
    start, end, new = convert.change_to_edit(
        doc.text, lsp.Range(lsp.Position(0, 5), lsp.Position(0, 5)), "X")
    doc.replace(start, end, new)
    assert doc.text == "[a] \ud83dX\ude00"
    # Deleting the X joins the pair again, as in the client's UTF-16 text.
    start, end, new = convert.change_to_edit(doc.text,
                                             lsp.Range(lsp.Position(0, 5), lsp.Position(0, 6)), "")
    doc.replace(start, end, new)
    assert doc.text == "[a] 😀"


def test_a_range_from_the_middle_of_one_emoji_to_the_middle_of_another():
    doc = Document("x", "😀ab🎵")
    start, end, new = convert.change_to_edit(doc.text,
                                             lsp.Range(lsp.Position(0, 3), lsp.Position(0, 1)), "")
    doc.replace(start, end, new)  # the range given backwards: units 1..3 go
    assert doc.text.encode("utf-16-le", "surrogatepass") == \
        "😀ab🎵".encode("utf-16-le", "surrogatepass")[:2] + "b🎵".encode("utf-16-le")


def test_positions_through_a_layout():
    # Analysis text `[a]   \n[b]` (3 pad spaces after `[a]`); the document is `[a]\n[b]`.
    p = convert.Positions(SourceFile("x", "[a]\n[b]"), Layout(((3, 3),)))
    assert p.position(7) == lsp.Position(1, 0)
    assert p.position(4) == lsp.Position(0, 3)  # inside the pad: the end of the item
    assert p.offset(lsp.Position(1, 1)) == 8
    assert p.offset(lsp.Position(0, 3)) == 3  # the cursor after `]` is on the item
    assert p.range(Span(7, 10)) == lsp.Range(lsp.Position(1, 0), lsp.Position(1, 3))


def test_diagnostic_conversion():
    from scriptc.analysis.analyze import analyze_script

    text = "[a]\n[goal:g]\n[action]\n[b#x#blk_inst: MV() LD() AO()]\n[b#x#blk_terminus]\n"
    source = SourceFile("x", text)
    (d,) = analyze_script(source).diagnostics
    out = convert.diagnostic(convert.text_positions(source.text), "file:///x", d)
    assert (out.code, out.message, out.source) == ("L001", d.message, "scriptc")
    assert out.range == lsp.Range(lsp.Position(4, 3), lsp.Position(4, 4))
    assert out.code_description.href.endswith("/explanations/L001.md")
    assert [r.message.split(":")[0] for r in out.related_information][1:] == ["note", "help"]


def test_semantic_tokens_cut_at_line_ends_and_count_units():
    source = SourceFile("x", "% 😀\nab %[a]")
    tokens = [answers.SemanticToken(Span(0, 8), "comment"),
              answers.SemanticToken(Span(9, 10), "namespace")]
    data = convert.semantic_tokens(convert.text_positions(source.text), tokens).value["data"]
    comment, namespace = convert._TYPE_INDEX["comment"], convert._TYPE_INDEX["namespace"]
    assert data == [0, 0, 4, comment, 0,   # `% 😀` is 4 units
                    1, 0, 4, comment, 0,   # `ab %`
                    0, 5, 1, namespace, 0]


def test_completion_json():
    source = SourceFile("x", "[a] é")
    items = [answers.CompletionItem("goal:", "item", Span(5, 5), snippet="goal:${1:id}",
                                    insert_text="goal:")]
    with_snippets = convert.completion_list(convert.text_positions(source.text), items, True).value
    without = convert.completion_list(convert.text_positions(source.text), items, False).value
    assert with_snippets["items"][0]["textEdit"] == {
        "range": {"start": {"line": 0, "character": 5}, "end": {"line": 0, "character": 5}},
        "newText": "goal:${1:id}"}
    assert with_snippets["items"][0]["insertTextFormat"] == 2
    assert without["items"][0]["textEdit"]["newText"] == "goal:"
    assert "insertTextFormat" not in without["items"][0]


@pytest.mark.slow
def test_the_editor_api_does_not_import_the_protocol():
    import subprocess
    import sys

    code = ("import sys, scriptc.ide.hover, scriptc.ide.completion, scriptc.ide.navigation, "
            "scriptc.ide.outline, scriptc.ide.tokens, scriptc.ide.actions, scriptc.ide.hints, "
            "scriptc.ide.document, scriptc.ide.formatting; "
            "print(sorted({m.split('.')[0] for m in sys.modules}"
            " & {'pygls', 'lsprotocol', 'cattrs'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_diagnostics_are_pushed_unless_the_client_pulls_and_can_be_asked_to_again():
    from scriptc.server.main import diagnostic_modes

    plain = lsp.ClientCapabilities(text_document=lsp.TextDocumentClientCapabilities())
    pulling = lsp.ClientCapabilities(text_document=lsp.TextDocumentClientCapabilities(
        diagnostic=lsp.DiagnosticClientCapabilities()),
        workspace=lsp.WorkspaceClientCapabilities(
            diagnostics=lsp.DiagnosticWorkspaceClientCapabilities(refresh_support=True)))
    # Neovim 0.10 and newer: pulls, takes no refresh (a change of configuration could not
    # reach it): pushed.
    neovim = lsp.ClientCapabilities(text_document=lsp.TextDocumentClientCapabilities(
        diagnostic=lsp.DiagnosticClientCapabilities()))
    assert diagnostic_modes(plain, None) == (True, False)
    assert diagnostic_modes(None, None) == (True, False)
    assert diagnostic_modes(pulling, None) == (False, True)
    assert diagnostic_modes(neovim, None) == (True, False)
    assert diagnostic_modes(neovim, {"diagnostics": "pull"}) == (False, True)
    assert diagnostic_modes(pulling, {"diagnostics": "both"}) == (True, True)
    assert diagnostic_modes(plain, {"diagnostics": "pull"}) == (False, True)
    assert diagnostic_modes(plain, {"diagnostics": "nonsense"}) == (True, False)


def test_completion_documentation_follows_the_client_format() -> None:
    """Markdown for a client that reads it (`documentationFormat`), plain text otherwise."""
    p = convert.Positions(SourceFile("x.script", "[a]\n"))
    item = answers.CompletionItem(label="now", kind="function", span=Span(0, 0),
                                documentation="The map's time in ms, as text.")
    as_markdown = convert.completion_list(p, [item], snippets=False, markdown=True)
    as_text = convert.completion_list(p, [item], snippets=False, markdown=False)
    assert as_markdown.value["items"][0]["documentation"] == {"kind": "markdown",
                                                        "value": "The map's time in ms, as text."}
    assert as_text.value["items"][0]["documentation"] == "The map's time in ms, as text."
