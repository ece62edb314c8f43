"""The positioned JSON parser (`scriptc.frontend.jsonpos`)."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.frontend.jsonpos import JsonError, parse_json, string_offsets
from scriptc.source import Span


def test_values_and_spans() -> None:
    text = '{"a": [1, -2.5e3, "x\\u00e9"], "b": {"c": null, "d": true, "e": false}}'
    root = parse_json(text)
    assert root.to_python() == json.loads(text)
    assert root.span == Span(0, len(text))
    a = root.member("a")
    assert a is not None and text[a.key_span.start:a.key_span.end] == '"a"'
    array = a.value
    assert text[array.start:array.end] == '[1, -2.5e3, "x\\u00e9"]'
    one, big, s = array.items
    assert (one.kind, one.value, one.raw) == ("number", 1, "1")
    assert (big.kind, big.value, big.raw) == ("number", -2500.0, "-2.5e3")
    assert (s.kind, s.value) == ("string", "xé")
    assert text[s.content_span.start:s.content_span.end] == "x\\u00e9"
    assert root.get("b").get("c").kind == "null"
    assert root.get("b").get("d").value is True
    assert root.child("a").child(2) is s
    assert root.child("zz") is None and array.child(7) is None


def test_members_keep_document_order() -> None:
    root = parse_json('{"z": 1, "a": 2, "m": 3}')
    assert [m.key for m in root.members] == ["z", "a", "m"]


def test_byte_order_mark_is_skipped() -> None:
    assert parse_json('\ufeff{"a": 1}').to_python() == {"a": 1}


@pytest.mark.parametrize("text, message, line, column", [
    ("", "expected a value, found the end of the file", 1, 1),
    ("{", "the file ends inside an object", 1, 2),
    ("[1,]", "a comma before `]`: JSON allows no trailing comma", 1, 3),
    ('{"a": 1,\n}', "a comma before `}`: JSON allows no trailing comma", 1, 8),
    ('{"a" 1}', "expected `:` after the key `a`, found `1`", 1, 6),
    ('{"a": 1 "b": 2}', "expected `,` or `}` after an object member, found `\"`", 1, 9),
    ("[NaN]", "`NaN` is not a JSON number: JSON numbers are finite", 1, 2),
    ("[Infinity]", "`Infinity` is not a JSON number: JSON numbers are finite", 1, 2),
    ("[-Infinity]", "`-Infinity` is not a JSON number: JSON numbers are finite", 1, 2),
    ('{"a": 1,\n "a": 2}', "duplicate key `a` (first at line 1, column 2)", 2, 2),
    ("[01]", "invalid number `01`: JSON numbers have no leading zeros", 1, 2),
    ("[1.]", "invalid number `1.`: write a digit on both sides of the decimal point", 1, 2),
    ("[+1]", "invalid number `+1`: JSON numbers have no `+` sign", 1, 2),
    ("{'a': 1}", "JSON keys are strings in double quotes, not single quotes", 1, 2),
    ("['a']", "JSON strings use double quotes, not single quotes", 1, 2),
    ("{a: 1}", "expected a key in double quotes, found `a`", 1, 2),
    ("[1] x", "unexpected `x` after the end of the JSON value", 1, 5),
    ('"ab', "unterminated string", 1, 1),
    ('["a\nb"]', "a line break inside a string: write it as `\\n`", 1, 4),
    ('["\\x"]', ("invalid escape `\\x` in a string: JSON knows `\\\"`, `\\\\`, `\\/`, `\\b`, "
                 "`\\f`, `\\n`, `\\r`, `\\t` and `\\uXXXX`"), 1, 3),
    ('["\\ud800"]', ("the escape `\\ud800` is the first half of a surrogate pair without its "
                     "second half"), 1, 3),
    ('["\\udc00"]', ("the escape `\\udc00` is the second half of a surrogate pair without its "
                     "first half"), 1, 3),
    ('["\\u12"]', "`\\u` must be followed by four hexadecimal digits", 1, 3),
    ("[True]", "`True` is not JSON: write `true`", 1, 2),
    ("[1 2]", "expected `,` or `]` after an array element, found `2`", 1, 4),
    ('{"a": 1]', "expected `,` or `}` after an object member, found `]`", 1, 8),
    ("[\n  1,\n  2", "the file ends inside an array", 3, 4),
    ("[1e999]", ("the number `1e999` is too large: numbers must be finite and within ±1.8e+308 "
                 "(a double)"), 1, 2),
    ("[-1e400]", ("the number `-1e400` is too large: numbers must be finite and within "
                  "±1.8e+308 (a double)"), 1, 2),
    ("{\n \"a\": " + "9" * 5000 + "}", ("the number `9999999999...999999` (5000 digits) is too "
                                      "large: numbers must be finite and within ±1.8e+308 "
                                      "(a double)"), 2, 7),
    ("[" + "9" * 309 + ".0]", ("the number `9999999999...9999.0` (310 digits) is too large: "
                               "numbers must be finite and within ±1.8e+308 (a double)"), 1, 2),
    ("// c\n{}", "JSON has no comments", 1, 1),
    ('{"a": 1 /* c */}', "JSON has no comments", 1, 9),
])
def test_errors(text: str, message: str, line: int, column: int) -> None:
    with pytest.raises(JsonError) as caught:
        parse_json(text)
    error = caught.value
    assert error.message == message
    assert (error.line, error.column) == (line, column)
    assert str(error) == f"line {line}, column {column}: {message}"


def test_error_labels() -> None:
    with pytest.raises(JsonError) as caught:
        parse_json('{"a": [1, 2}')
    assert caught.value.labels == ((Span(6, 7), "this array is never closed"),)
    with pytest.raises(JsonError) as caught:
        parse_json('{"k": 1, "k": 2}')
    assert caught.value.span == Span(9, 12)
    assert caught.value.labels == ((Span(1, 4), "first defined here"),)


@pytest.mark.slow
def test_deep_nesting_does_not_recurse() -> None:
    depth = 20_000
    root = parse_json("[" * depth + "]" * depth)
    value = root.to_python()
    for _ in range(depth - 1):
        assert len(value) == 1
        value = value[0]
    assert value == []
    root = parse_json('{"a":' * depth + "1" + "}" * depth)
    assert root.to_python() is not None


def test_a_reader_may_bound_the_depth() -> None:
    assert parse_json("[[1], {\"a\": 2}, []]", max_depth=2).to_python() == [[1], {"a": 2}, []]
    with pytest.raises(JsonError) as caught:
        parse_json('{"a": [[1]]}', max_depth=2)
    assert caught.value.message == "arrays and objects nested more than 2 levels deep"
    assert caught.value.span == Span(7, 8)
    with pytest.raises(JsonError, match="more than 100 levels"):
        parse_json("[" * 200_000 + "]" * 200_000, max_depth=100)


def test_deep_nesting_error_is_reported() -> None:
    with pytest.raises(JsonError, match="the file ends where a value was expected") as caught:
        parse_json("[" * 50_000)
    assert caught.value.labels == ((Span(49_999, 50_000), "this array is never closed"),)


def test_string_offsets_map_value_to_source() -> None:
    text = '["a\\"b\\u00e9\\ud83d\\ude00c"]'
    node = parse_json(text).items[0]
    assert node.value == 'a"bé😀c'
    offsets = string_offsets(text, node)
    assert [text[o] for o in offsets[:-1]] == ["a", "\\", "b", "\\", "\\", "c"]
    assert offsets[-1] == node.end - 1


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children,
                                                                      max_size=4),
    max_leaves=30,
)


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(JSON_VALUES, st.booleans(), st.booleans())
def test_agrees_with_the_json_module(value, ascii_only: bool, indent: bool) -> None:
    text = json.dumps(value, ensure_ascii=ascii_only, indent=2 if indent else None)
    root = parse_json(text)
    assert root.to_python() == json.loads(text)
    assert text[root.start:root.end] == text.strip()


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet='{}[],:"0123456789-+.eE tfalsenu\\\n', max_size=30))
def test_never_crashes(text: str) -> None:
    """Whatever the text, either a value or a JsonError; and it agrees with `json` on which."""
    try:
        expected = json.loads(text)
    except (ValueError, RecursionError):
        expected = JsonError
    try:
        got = parse_json(text).to_python()
    except JsonError:
        got = JsonError
    if expected is JsonError or got is JsonError:
        # json accepts duplicate keys and numbers too large for a double (`1e999` is
        # infinity), which this parser refuses on purpose.
        if got is JsonError and expected is not JsonError:
            with pytest.raises(JsonError, match=r"duplicate key|too large"):
                parse_json(text)
        else:
            assert got is expected
    else:
        assert got == expected
