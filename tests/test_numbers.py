"""The one number policy (src/scriptc/numbers.py): what every reader refuses, and the JSON
writer that never writes NaN or Infinity."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scriptc.numbers import (
    LARGEST,
    MAX_DIGITS,
    NonFiniteOutput,
    NumberError,
    json_dumps,
    json_number,
    number_problem,
    shown,
    whole_number,
)


def test_the_largest_integer_a_double_holds_has_max_digits() -> None:
    assert MAX_DIGITS == 309 and len(str(int(LARGEST))) == MAX_DIGITS


@pytest.mark.parametrize("raw, is_integer, value", [
    ("0", True, 0), ("-12", True, -12), ("1.5", False, 1.5), ("1e308", False, 1e308),
    ("1e-400", False, 0.0), ("9" * 300, True, int("9" * 300)), (str(int(LARGEST)), True,
                                                                  int(LARGEST)),
])
def test_numbers_the_policy_takes(raw: str, is_integer: bool, value) -> None:
    got = json_number(raw, is_integer)
    assert got == value and type(got) is type(value)


@pytest.mark.parametrize("raw, is_integer, message", [
    ("1e999", False, "the number `1e999` is too large"),
    ("-1e400", False, "the number `-1e400` is too large"),
    (str(int(LARGEST) + 1), True, "(309 digits) is too large"),
    ("1" * 5000, True, "the number `1111111111...111111` (5000 digits) is too large"),
    ("-" + "1" * 5000, True, "(5000 digits) is too large"),
])
def test_numbers_the_policy_refuses(raw: str, is_integer: bool, message: str) -> None:
    with pytest.raises(NumberError) as caught:
        json_number(raw, is_integer)
    assert message in caught.value.message
    assert "finite and within ±1.8e+308 (a double)" in caught.value.message


def test_parsed_values() -> None:
    """What TOML and Python hand over: nan, inf, integers beyond a double."""
    assert number_problem(1.0) is None and number_problem(10**300) is None
    assert number_problem(True) is None and number_problem("text") is None
    assert number_problem(math.nan) == "`nan` is not a number: numbers must be finite"
    assert number_problem(-math.inf, "-inf") == "`-inf` is infinite: numbers must be finite"
    assert number_problem(math.inf, "1e999").startswith("the number `1e999` is too large")
    assert number_problem(-(10**400)).startswith("an integer of about 401 digits is too large")


def test_whole_numbers_are_never_converted_beyond_the_policy() -> None:
    assert whole_number("-42") == -42 and whole_number("+7") == 7
    assert whole_number("9" * MAX_DIGITS) == int("9" * MAX_DIGITS)
    assert whole_number("9" * (MAX_DIGITS + 1)) is None
    assert whole_number("1" * 100_000) is None  # int() would raise: 4,300 digits at most


@pytest.mark.parametrize("text", ["0", "7", "0007", "500", "9" * 18, "9" * 19, "0" * 30 + "5",
                                  "-0", "+12", "-0012"])
def test_whole_numbers_of_any_length_read_as_int_does(text: str) -> None:
    assert whole_number(text) == int(text)


def test_shown_cuts_long_numbers() -> None:
    assert shown("12.5") == "`12.5`"
    assert shown("1" * 50) == "`1111111111...111111` (50 digits)"


def test_the_writer_never_writes_nan_or_infinity() -> None:
    assert json_dumps({"a": [1, 2.5]}, separators=(",", ":")) == '{"a":[1,2.5]}'
    with pytest.raises(NonFiniteOutput) as caught:
        json_dumps({"pose": {"x": 1.0, "y": math.nan}})
    assert caught.value.where == "pose.y"
    assert str(caught.value) == ("the JSON output would hold nan at `pose.y`, which JSON "
                                 "cannot represent")
    with pytest.raises(NonFiniteOutput) as caught:
        json_dumps([{"a": [0.0, -math.inf]}])
    assert caught.value.where == "[0].a[1]"
    with pytest.raises(ValueError, match="Circular"):  # other errors are json's own
        cycle: list = []
        cycle.append(cycle)
        json_dumps(cycle)


def test_traces_and_summaries_go_through_the_writer() -> None:
    from scriptc.runtime.trace import dumps

    assert (dumps({"t": 0, "event": "velocity", "v_x": 0.5})
            == '{"t":0,"event":"velocity","v_x":0.5}')
    with pytest.raises(NonFiniteOutput, match="v_x"):
        dumps({"t": 0, "event": "velocity", "v_x": math.inf})


@settings(max_examples=200, deadline=None)
@given(st.integers(-(10**400), 10**400) | st.floats(allow_nan=True, allow_infinity=True))
def test_writer_and_readers_agree(value) -> None:
    """What the policy accepts, the writer writes and the reader reads back; what it refuses,
    the writer refuses too."""
    problem = number_problem(value)
    if problem is None:
        text = json_dumps(value)
        assert json_number(text, isinstance(value, int)) == value
        assert json.loads(text) == value
    elif isinstance(value, float):
        with pytest.raises(NonFiniteOutput):
            json_dumps(value)
