"""Pass 7, safety against the robot profile (docs/robot.md; `scriptc.profile`):

- K001: a move command faster than the profile allows (planar speed |(v_x, v_y)| above
  `max_linear_speed`, or |v_theta| above `max_angular_speed`). A warning: the script is not
  refused, the run-time governor slows it down, but the author should know the robot will not
  do what the script says.
- K002: an LED on/off pattern that flashes faster than `max_led_flash_rate` (3 Hz by default:
  WCAG 2.3.1, "Three Flashes or Below Threshold", a seizure risk for photosensitive children;
  epilepsy is far more common among autistic children than in the general population). The
  LED track of each instruction block is laid out in time (each command waits `wait_t`, is on
  for `duration` when `turnas` is 1) and every window of one second is checked: more onsets
  (off to on) than the rate in one second is reported, at the command making the excess.
  A block that the jumps right after it may send straight back to itself repeats: its pattern
  is repeated for two seconds (a blink of 100 ms on, 100 ms off in a loop is 5 Hz).

The profile is `ctx.profile`: the configuration's `[robot]` over the defaults when the driver
passes one, else `scriptc.profile.DEFAULT_PROFILE`. Linear in the number of commands.
"""

from __future__ import annotations

import math

from scriptc.check.context import Context
from scriptc.diagnostics.model import Diagnostic, Label, diagnostic
from scriptc.ir.nodes import InstructionBlock, JumpBlock, Number
from scriptc.profile import Profile

WINDOW_MS = 1000


def _num(number: Number) -> float | None:
    try:
        v = float(number.text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def _ms(number: Number) -> int | None:
    v = _num(number)
    return int(v) if v is not None and v >= 0 and v == int(v) else None


def _fmt(v: float) -> str:
    return f"{v:g}"


def check_safety(ctx: Context) -> list[Diagnostic]:
    profile: Profile = ctx.profile
    out: list[Diagnostic] = []
    blocks = ctx.blocks
    for i, block in enumerate(blocks):
        if not isinstance(block, InstructionBlock):
            continue
        for mv in block.moves:
            _speed(mv, profile, out)
        if block.leds:
            _flashes(block, _loop_back(ctx, i), profile, out)
    return out


def _loop_back(ctx: Context, i: int) -> JumpBlock | None:
    """The jump that may send execution straight back to instruction block `i` (the jumps
    right after it, before any other instruction block), if any: the block then repeats."""
    block = ctx.blocks[i]
    label = block.label.text if block.label is not None else ""
    if not label or ctx.labels.index.get(label) != i:
        return None
    for j in range(i + 1, len(ctx.blocks)):
        jump = ctx.blocks[j]
        if not isinstance(jump, JumpBlock):
            return None
        for target in (jump.true_target, jump.false_target):
            if target is not None and target.text == label:
                return jump
    return None


def _speed(mv, profile: Profile, out: list[Diagnostic]) -> None:
    v_x, v_y, w = _num(mv.v_x), _num(mv.v_y), _num(mv.v_theta)
    if v_x is None or v_y is None or w is None:
        return  # reported by V002/V003
    speed = math.hypot(v_x, v_y)
    source = "" if profile.source == "defaults" else f" (from {profile.source})"
    if speed > profile.max_linear_speed:
        span = mv.v_x.span if abs(v_x) >= abs(v_y) else mv.v_y.span
        out.append(diagnostic(
            "K001", f"this move goes at {_fmt(speed)} m/s, above the robot profile's "
                    f"{_fmt(profile.max_linear_speed)} m/s", span,
            notes=(f"the run-time governor slows it to {_fmt(profile.max_linear_speed)} m/s: "
                   f"it goes {_fmt(profile.max_linear_speed / speed * 100)}% as far as "
                   "written",
                   f"profile{source}: max-linear-speed = {_fmt(profile.max_linear_speed)}"),
            help="lower the speed and lengthen the duration to keep the distance"))
    if abs(w) > profile.max_angular_speed:
        out.append(diagnostic(
            "K001", f"this move turns at {_fmt(abs(w))} rad/s, above the robot profile's "
                    f"{_fmt(profile.max_angular_speed)} rad/s", mv.v_theta.span,
            notes=(f"the run-time governor slows it to {_fmt(profile.max_angular_speed)} "
                   "rad/s: it turns less far than written",
                   f"profile{source}: max-angular-speed = {_fmt(profile.max_angular_speed)}"),
            help="lower the turning speed and lengthen the duration to keep the angle"))


def _flashes(block: InstructionBlock, loop: JumpBlock | None, profile: Profile,
             out: list[Diagnostic]) -> None:
    """Onsets of light on the block's LED track (repeated when the block loops back to
    itself), then a sliding one-second window."""
    onsets: list[tuple[int, object]] = []  # (time ms, command) in one pass of the block
    t = 0
    lit = False  # the LEDs are off when a block starts and between commands
    for led in block.leds:
        wait, duration = _ms(led.wait_t), _ms(led.duration)
        if wait is None or duration is None:
            return  # V006
        t += wait
        if wait > 0:
            lit = False
        on = led.turnas.text.strip() == "1" and duration > 0 and any(
            (_num(c) or 0) > 0 for c in (led.r, led.g, led.b))
        if on and not lit:
            onsets.append((t, led))
        lit = on
        t += duration
        # a command's stop turns the LEDs off: the next command lights them again only if it
        # starts later; with no wait the change is instantaneous (no dark interval)
    period = block.duration_ms
    if loop is not None and onsets and period:
        # The block repeats: its onsets come back every `period` ms. The light stays on across
        # the seam only when the LED track runs to the block's end and starts lit at once.
        seamless = lit and t == period and onsets[0][0] == 0
        one_pass = onsets[1:] if seamless else onsets
        repeated = list(onsets)
        k = 1
        while one_pass and k * period < 2 * WINDOW_MS and len(repeated) < 64:
            repeated += [(when + k * period, led) for when, led in one_pass]
            k += 1
        onsets = repeated
    limit = profile.max_led_flash_rate
    first = 0
    for i, (when, led) in enumerate(onsets):
        while when - onsets[first][0] >= WINDOW_MS:
            first += 1
        count = i - first + 1
        if count > limit:
            start_led = onsets[first][1]
            labels = []
            if start_led is not led:
                labels.append(Label(start_led.span, "the first flash of that second"))
            if loop is not None and when >= (period or 0):
                labels.append(Label(loop.span, "this jump repeats the block"))
            repeats = " as the block repeats" if loop is not None and when >= (period or 0) \
                else ""
            out.append(diagnostic(
                "K002", f"the LEDs flash {count} times within one second{repeats}, above the "
                        f"robot profile's {_fmt(limit)} per second", led.span,
                labels=tuple(labels),
                notes=("flashing faster than 3 times a second can trigger seizures in "
                       "photosensitive children (WCAG 2.3.1)",
                       f"profile: max-led-flash-rate = {_fmt(limit)}"),
                help="keep each on/off cycle at least a third of a second long (for example "
                     "on 200 ms, off 150 ms), or keep the light on and change its colour "
                     "slowly"))
            return  # one report per block
