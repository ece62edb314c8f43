"""Pass 4, values inside commands, rule messages and conditions (docs/language.md):
finite numbers (V003; speeds within the robot's 32-bit floats), colour channels in [0, 1]
(V004), `turnas` 0 or 1 (V005), times whole, non-negative and within a C++ `int` (V006),
rulecodes within uint32 (V007).

Numbers whose text is not a number at all (`Number.value is None`) were reported where they
were read (V002) and are skipped here; so are `inf` and `nan` written as such (V003 there).
"""

from __future__ import annotations

from scriptc.check.context import Context
from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic, Fix, TextEdit
from scriptc.ir.fields import NUMBER_RE
from scriptc.ir.nodes import (
    CallEvaluation,
    ClassAssignment,
    Condition,
    FieldTest,
    JumpBlock,
    Number,
    NumberValue,
    Value,
)
from scriptc.numbers import shown, whole_number

# Decided: the robot's software kept `wait_t` and `duration` in a C++ `int` (32 bits).
MAX_TIME = 2**31 - 1
MAX_RULECODE = 2**32 - 1
# The robot's software reads speeds and colours with C++ `stof`: a 32-bit float, which fails
# beyond its largest value (FLT_MAX).
MAX_ROBOT_FLOAT = 3.4028234663852886e38


def check_values(ctx: Context) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    fixes = ctx.is_script_syntax
    for msg in (*ctx.script.alfa, *ctx.script.omega):
        _whole(msg.rulecode, "the rulecode", 0, MAX_RULECODE, "V007", fixes, out)
    # A 1 MB script holds some 100,000 numbers: each check starts with a fast path for the
    # common, valid numbers (read once, `ctx.tracks`) and leaves the rest (and every message)
    # to the slow path, which reads the text.
    limit = MAX_ROBOT_FLOAT
    for block, tracks in zip(ctx.blocks, ctx.tracks, strict=True):
        if tracks is not None:  # an instruction block: `tracks.block`
            # every time a few digits, and the longest track within the limit: so is each time
            times = not (tracks.plain and tracks.duration is not None
                         and tracks.duration <= MAX_TIME)
            for mv, (velocity, _, _) in zip(tracks.block.moves, tracks.moves, strict=True):
                if velocity is None or not (-limit <= velocity[0] <= limit
                                            and -limit <= velocity[1] <= limit
                                            and -limit <= velocity[2] <= limit):
                    for name, number in (("v_x", mv.v_x), ("v_y", mv.v_y),
                                         ("v_theta", mv.v_theta)):
                        if not _plain_finite(number.text, limit):
                            _finite(number, f"`{name}`", out, limit)
                if times:
                    _time(mv.wait_t, "`wait_t`", fixes, out)
                    _time(mv.duration, "`duration`", fixes, out)
            for led, (colour, _, _, _) in zip(tracks.block.leds, tracks.leds, strict=True):
                if colour is None or not (0.0 <= colour[0] <= 1.0 and 0.0 <= colour[1] <= 1.0
                                          and 0.0 <= colour[2] <= 1.0):
                    for channel, number in (("r", led.r), ("g", led.g), ("b", led.b)):
                        if not _plain_unit(number.text):
                            _colour(number, channel, out)
                if led.turnas.text not in ("0", "1"):
                    _turnas(led.turnas, fixes, out)
                if times:
                    _time(led.wait_t, "`wait_t`", fixes, out)
                    _time(led.duration, "`duration`", fixes, out)
            if times:
                for ao in tracks.block.audios:
                    _time(ao.wait_t, "`wait_t`", fixes, out)
                    _time(ao.duration, "`duration`", fixes, out)
        elif isinstance(block, JumpBlock):
            for number in condition_numbers(block.condition):
                if not _plain_finite(number.text):
                    _finite(number, "the number", out)
    return out


def _plain_finite(text: str, limit: float | None = None) -> bool:
    """Fast path: a finite float, within `limit` when given (texts float() reads but the
    syntax does not were reported where they were read, so accepting them here hides
    nothing)."""
    try:
        v = float(text)
    except ValueError:
        return True
    return v - v == 0.0 and (limit is None or -limit <= v <= limit)


def _plain_unit(text: str) -> bool:
    try:
        v = float(text)
    except ValueError:
        return True
    return 0.0 <= v <= 1.0


def _read(number: Number) -> float | None:
    """The value, or None when the text was already reported where it was read."""
    if not NUMBER_RE.fullmatch(number.text):
        return None
    return number.value


def _finite(number: Number, what: str, out: list[Diagnostic],
            limit: float | None = None) -> bool:
    """Report V003 for a number too large to represent (as a double, or beyond `limit`, the
    largest value the robot reads into the field); True when the number is usable."""
    value = _read(number)
    if value is None:
        return False
    if number.is_finite and limit is not None and abs(value) > limit:
        out.append(diagnostic(
            "V003", f"{what} is {shown(number.text)}, too large for the robot", number.span,
            notes=(("the robot's software reads it as a 32-bit float (C++ `stof`), whose "
                    f"largest value is about {limit:.1e}"),),
            help="write a speed the robot can reach"))
        return False
    if number.is_finite:
        return True
    out.append(
        diagnostic(
            "V003",
            f"{what} is {shown(number.text)}, too large to represent",
            number.span,
            notes=("read as a floating-point number it becomes infinite",),
            help="write a finite number",
        )
    )
    return False


def _replace(number: Number, text: str, fixes: bool) -> Fix | None:
    return Fix(f"write `{text}`", (TextEdit(number.span, text),)) if fixes else None


def _whole(number: Number, what: str, low: int, high: int, code: str, fixes: bool,
           out: list[Diagnostic], unit: str = "") -> None:
    """A field the JSON emits as an integer: whole text, within [low, high]."""
    value = _read(number)
    if value is None:
        return
    limit = "an unsigned 32-bit integer" if code == "V007" else "a whole number of milliseconds"
    n = whole_number(number.text) if number.is_integer_text else None
    if n is not None:  # (None for a text of hundreds of digits: V003 below says so)
        if n < low:
            out.append(diagnostic(code, f"{what} must not be negative, found `{number.text}`",
                                  number.span, help=f"{what} must be {limit} from {low} to {high}"))
        elif n > high:
            out.append(diagnostic(code,
                                  f"{what} is `{number.text}`, above the limit of {high}{unit}",
                                  number.span, notes=_limit_note(code),
                                  help=f"{what} must be {limit} from {low} to {high}"))
        return
    if not _finite(number, what, out):
        return
    fix = None
    if value.is_integer() and low <= value <= high:
        fix = _replace(number, str(int(value)), fixes)
    out.append(
        diagnostic(code, f"{what} must be {limit}, found `{number.text}`", number.span,
                   notes=(("the thesis JSON stores it as an integer, written without fraction "
                           "or exponent"),),
                   help=f"write it as a whole number, from {low} to {high}",
                   fix=fix)
    )


def _limit_note(code: str) -> tuple[str, ...]:
    if code == "V006":
        return ("the robot's software keeps times in a C++ `int`: about 24.8 days at most",)
    return ("rulecodes are unsigned 32-bit integers",)


def _time(number: Number, what: str, fixes: bool, out: list[Diagnostic]) -> None:
    text = number.text
    if text.isdigit() and len(text) < 10:
        return
    _whole(number, what, 0, MAX_TIME, "V006", fixes, out, unit=" ms")


def _colour(number: Number, channel: str, out: list[Diagnostic]) -> None:
    if not _finite(number, f"the colour channel `{channel}`", out):
        return
    value = number.value
    assert value is not None
    if 0.0 <= value <= 1.0:
        return
    hint = ""
    if 1.0 < value <= 255.0:
        hint = "; for a 0-255 value divide by 255"
    out.append(
        diagnostic(
            "V004",
            f"the colour channel `{channel}` is `{number.text}`, outside [0, 1]",
            number.span,
            help=f"write a value from 0 (off) to 1 (full brightness){hint}",
        )
    )


def _turnas(number: Number, fixes: bool, out: list[Diagnostic]) -> None:
    if not _finite(number, "`turnas`", out):
        return
    value = number.value
    if number.is_integer_text and value in (0.0, 1.0):
        return
    fix = _replace(number, str(int(value)), fixes) if value in (0.0, 1.0) else None
    out.append(
        diagnostic(
            "V005",
            f"`turnas` must be 0 or 1, found `{number.text}`",
            number.span,
            help="write `1` to turn the LEDs on or `0` to keep them off",
            fix=fix,
        )
    )


def condition_numbers(condition: Condition) -> list[Number]:
    """Every number literal of a condition, left to right (a list, gathered without nested
    generators: a 1 MB script has some 5,000 conditions)."""
    groups: list[tuple[Value, ...]] = []  # the values of each test and call, in order
    for asg in condition.assignments:
        if isinstance(asg, ClassAssignment):
            for test in asg.tests:
                groups.append((test.value,) if isinstance(test, FieldTest) else test.call.args)
        else:  # a VAR or ATT assignment
            groups.append(asg.call.args)
    for ev in condition.evaluations:
        if isinstance(ev, CallEvaluation):
            groups.append(ev.call.args)
    return [v.number for values in groups for v in values if isinstance(v, NumberValue)]
