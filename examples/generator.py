"""An example script generator built on `scriptc.api` (docs/api.md).

The thesis's `DanceExample.cpp` wrote its JSON line by line by hand. This generator builds the
same activity in code, gets it checked with the diagnostics of `scriptc lint`, and writes the
thesis JSON; then it writes a parametrised dance of N steps.

    python examples/generator.py OUT_FOLDER [--steps N] [--bytecode]

writes `OUT_FOLDER/dance_example.json` (equal, once loaded, to the thesis's own file) and
`OUT_FOLDER/dance_N.json` (and `.scb` files with `--bytecode`). It prints the diagnostics
and exits with status 1 when a script has errors (nothing is written for it), 2 when the
command line is wrong (`--steps` is 1 to 1000) or a file cannot be written.
"""

from __future__ import annotations

import argparse
import os
import sys

from scriptc.api import Activity, Built, audio, led, move

SONG = "plugins/audio_control/songs/polka_del_gatto.wav"
# A dance of more steps than this is not a dance for a child (and would take minutes to build).
MAX_STEPS = 1000


def dance_example() -> Activity:
    """The thesis's DanceExample: one instruction block playing a song for 5 s. Like the
    thesis's file it reuses the activity name `test_act` and has no terminus (F003, info)."""
    act = Activity("test_act")
    act.alfa(0, "kick_starter", action="C", mutex="U")
    act.omega(0, "kick_starter", action="R", mutex="L")
    act.goal("test_act_goal").action().instruction(audios=[audio(SONG, wait=0, duration=5000)])
    return act


def dance(steps: int, *, speed: float = 0.2, step_ms: int = 1000) -> Activity:
    """A dance of `steps` steps: forward and back in turn with the light changing colour, the
    song playing over the whole dance, then a terminus."""
    if steps < 1:
        raise ValueError("a dance has at least one step")
    colours = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    act = Activity(f"dance_{steps}")
    act.alfa(0, "kick_starter", action="C", mutex="U")
    act.omega(0, "kick_starter", action="R", mutex="L")
    action = act.goal("dance").action()
    moves = [move(speed if i % 2 == 0 else -speed, 0, 0, wait=0, duration=step_ms)
             for i in range(steps)]
    leds = [led(*colours[i % len(colours)], wait=0, duration=step_ms) for i in range(steps)]
    action.instruction(moves, leds, [audio(SONG, wait=0, duration=steps * step_ms)],
                       label="steps")
    action.terminus(label="end")
    return act


def write(built: Built, folder: str, name: str, bytecode: bool) -> bool:
    if built.diagnostics:
        print(built.report(), file=sys.stderr)
    if not built.ok:
        return False
    with open(os.path.join(folder, name + ".json"), "w", encoding="utf-8", newline="") as f:
        f.write(built.json())
    if bytecode:
        with open(os.path.join(folder, name + ".scb"), "wb") as f:
            f.write(built.bytecode())
    return True


def steps_count(text: str) -> int:
    """`--steps`: a whole number of steps, 1 to MAX_STEPS (argparse reports anything else)."""
    try:
        steps = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if not 1 <= steps <= MAX_STEPS:
        raise argparse.ArgumentTypeError(f"a dance has 1 to {MAX_STEPS} steps, not {steps}")
    return steps


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="where to write the JSON files (created if needed)")
    parser.add_argument("--steps", type=steps_count, default=4,
                        help=f"steps of the dance, 1 to {MAX_STEPS} (default 4)")
    parser.add_argument("--bytecode", action="store_true", help="also write .scb bytecode")
    args = parser.parse_args(argv)
    try:
        os.makedirs(args.folder, exist_ok=True)
        ok = write(dance_example().build(), args.folder, "dance_example", args.bytecode)
        ok &= write(dance(args.steps).build(), args.folder, f"dance_{args.steps}", args.bytecode)
    except OSError as exc:
        print(f"error: cannot write in `{args.folder}`: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
