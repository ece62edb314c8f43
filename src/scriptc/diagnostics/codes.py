"""THE registry of diagnostic codes.

Every diagnostic any stage reports has its code here, with a kebab-case name, a default
severity and a one-line summary. The long explanation (what it means, why it matters, an
example, the fix) lives in `explanations/CODE.md` beside this file: it is what
`scriptc explain CODE` prints, what docs/diagnostics.md shows and what editors hover.

Codes are forever: a retired code stays listed with `retired=True` so old suppressions and
links keep working. Families:

- P  syntax (the parser)            - S  structure of the item list (lowering)
- M  rule messages and the mutex    - L  labels and goal ids
- F  control flow between blocks    - V  values inside commands and messages
- R  the rule grammar (conditions)  - A  audio tracks
- J  thesis JSON input (`scriptc check`, `scriptc decompile`)
- C  configuration (`scriptc.toml`, `[tool.scriptc]`) and suppression comments
- K  safety against the robot profile (speeds, flashing LEDs)
- T  test files (`*.test.toml`) and the expectations their runs do not meet (`scriptc test`)
- Y  verification: what `scriptc verify` proves or refutes of every run (verify/)
- X  run time: the `error` events of a run's trace (`scriptc run`, docs/runtime.md), which
     carry the code's name (`"code": "mutex-misuse"`); an error stops the run, a warning does
     not. `at_run_time` codes are never reported by lint (`lint_codes()` leaves them out).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

from scriptc.diagnostics.model import Diagnostic, Fix, Label, Severity
from scriptc.source import Span

# The severity column of the table below (`INFO` in full: a lone `I` reads as `l` or `1`).
E, W, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO


@dataclass(frozen=True, slots=True)
class Code:
    """A code of the registry: its name, default severity and one-line summary."""

    code: str
    name: str
    severity: Severity
    summary: str
    retired: bool = False
    at_run_time: bool = False

    @property
    def explanation(self) -> str:
        return explanation(self.code)


_CODES = (
    # P: syntax
    Code("P001", "unexpected-token", E, "the parser found a token where another was expected"),
    Code("P002", "unclosed-delimiter", E, "a bracket, parenthesis or brace is never closed"),
    Code("P003", "unterminated-string", E, "a string is not closed before the end of its line"),
    Code("P004", "unterminated-comment", E, "a `%` comment is never closed"),
    Code("P005", "invalid-character", E, "a character that cannot start any token"),
    Code("P006", "invalid-escape", E, "a backslash escape other than `\\\\` or `\\\"` in a string"),
    Code("P007", "unreadable-file", E, "the file is not UTF-8 text"),
    Code("P008", "stray-text", E, "text outside any bracketed item"),
    # S: structure
    Code("S001", "missing-activity-name", E, "a script must start with `[activityname]`"),
    Code("S002", "item-order", E, "an item stands where the script's order does not allow it"),
    Code("S003", "unknown-item", E, "a bracketed name that is not an item of the language"),
    Code("S004", "missing-goal", E, "a script has no goal"),
    Code("S005", "empty-goal", E, "a goal has no action"),
    Code("S006", "empty-action", E, "an action has no block"),
    Code("S007", "missing-goal-id", E, "a goal item has no id"),
    Code("S008", "track-order", E,
         "an instruction block must list `MV()`, `LD()` and `AO()` once each, in this order"),
    Code("S009", "rule-message-fields", E, "a rule message does not have its six fields"),
    # M: rule messages and the mutex
    Code("M001", "alfa-mutex-order", E, "alfa messages must all be `M` but the last, which is `U`"),
    Code("M002", "omega-mutex-order", E, "omega messages must start with `L`, then all `M`"),
    Code("M003", "unbalanced-mutex", E,
         "a script with rule messages must both unlock (alfa) and lock (omega)"),
    Code("M004", "omega-leak", W, "the omega list does not undo what the alfa list did"),
    Code("M005", "invalid-rule-letter", E, "a rule action or mutex letter that does not exist"),
    # L: labels
    Code("L001", "duplicate-label", E, "two blocks carry the same label"),
    Code("L002", "duplicate-goal-id", E, "two goals carry the same id"),
    Code("L003", "unknown-label", E, "a jump names a label no block carries"),
    # F: control flow
    Code("F001", "unreachable-block", W, "no path from the script's start reaches this block"),
    Code("F002", "jump-cycle", E, "a cycle of jumps passes no instruction block and never ends"),
    Code("F003", "no-terminus", INFO, "the script ends by running past its last block"),
    # V: values
    Code("V001", "command-fields", E, "a command string has the wrong number of fields"),
    Code("V002", "not-a-number", E, "a field that must be a number is not one"),
    Code("V003", "non-finite-number", E,
         "a number is infinite, not a number, or too large to represent"),
    Code("V004", "colour-range", E, "a colour channel outside [0, 1]"),
    Code("V005", "turnas-value", E, "`turnas` must be 0 or 1"),
    Code("V006", "invalid-time", E, "a time that is not a whole number of milliseconds in range"),
    Code("V007", "rulecode-range", E, "a rulecode that is not an unsigned 32-bit integer"),
    # R: the rule grammar
    Code("R001", "unknown-class", E, "a CLASS assignment names a class the map does not have"),
    Code("R002", "unknown-field", E, "a field that entities of that class do not have"),
    Code("R003", "unknown-function", E, "a function that is not in the function registry"),
    Code("R004", "function-kind", E, "a function of one kind (B, F, E) used as another"),
    Code("R005", "function-arity", E, "a function called with the wrong number of arguments"),
    Code("R006", "unbound-alias", E, "an alias used before any assignment binds it"),
    Code("R007", "invalid-scope", E, "a scope other than `U`, `L` or `T`"),
    Code("R008", "rebound-alias", W, "an alias bound twice in one condition"),
    Code("R009", "this-outside-test", E, "`?THIS` used outside the tests of a CLASS assignment"),
    # A: audio
    Code("A001", "absolute-audio-path", W,
         "an audio path that is absolute, so it only works on one machine"),
    Code("A002", "audio-path-escapes", W, "an audio path that leaves the activity repository"),
    Code("A003", "empty-audio-path", E, "an audio command without a track path"),
    # J: thesis JSON input
    Code("J001", "invalid-json", E, "the file is not valid JSON"),
    Code("J002", "schema-violation", E, "the JSON does not have the shape of a thesis script"),
    Code("J003", "invalid-jump-path", E,
         "a jump path that is not `goalG/actA/blkB` of an existing block"),
    # C: configuration and suppressions
    Code("C001", "unknown-config-key", E, "a key the configuration does not have"),
    Code("C002", "invalid-config-value", E,
         "a configuration value of the wrong type or out of range"),
    Code("C003", "unused-suppression", W, "a suppression comment that suppresses nothing"),
    Code("C004", "invalid-code", W,
         "a code that does not exist, an error code or a run-time code, in a suppression or the "
         "configuration"),
    Code("C005", "invalid-config-file", E, "a configuration file that is not valid TOML"),
    Code("C006", "invalid-suppression", W,
         "a `scriptc:` comment that is not a suppression scriptc understands"),
    # K: safety against the robot profile (check/safety.py, docs/robot.md)
    Code("K001", "speed-beyond-profile", W,
         "a move faster than the robot profile allows (the governor slows it down)"),
    Code("K002", "led-flashing", E,
         "LEDs flashing faster than the profile allows (3 Hz: a seizure risk, WCAG 2.3.1)"),
    Code("K003", "ramps-change-pose", W,
         "moves whose acceleration ramps leave the robot away from where the script puts it"),
    # T: test files and their expectations (`scriptc test`, testing/, docs/testing.md)
    Code("T001", "invalid-test-file", E, "a test file that is not valid TOML (or not UTF-8 text)"),
    Code("T002", "unknown-test-key", E, "a key a test file or its `[[expect]]` does not have"),
    Code("T003", "invalid-test-value", E,
         "a value of a test file of the wrong type, out of range or that says nothing"),
    Code("T004", "test-file-not-found", E,
         "a script or world file a test names does not exist or cannot be read"),
    Code("T005", "invalid-test-world", E,
         "the world of a test (its scenario file or `[world]` table) has a problem"),
    Code("T006", "expectation-failed", E, "the run of a test did not do what an `[[expect]]` says"),
    Code("T007", "snapshot-differs", E,
         "the trace of a test with `snapshot = true` is not its snapshot file, or there is none"),
    # Y: what `scriptc verify` proves or refutes over every world (verify/, docs/verify.md)
    Code("Y001", "waits-forever", E,
         "a world can keep the robot in a loop forever: the activity may never end"),
    Code("Y002", "goal-never-reached", E, "no world reaches a goal of the activity"),
    Code("Y003", "block-never-read", E, "no world leads the block reader to a block"),
    Code("Y004", "needs-governor", E,
         "a run reads a block that the safety governor must correct (speed, ramps, flashing)"),
    Code("Y005", "not-decided", W,
         "verify could not decide a property: a bound was reached, or a run it found could not "
         "be replayed"),
    # X: run time (the trace's `error` events carry the name; runtime/status.py)
    Code("X001", "mutex-misuse", W,
         "rule messages misuse the map's mutex at run time (a script that was not checked)",
         at_run_time=True),
    Code("X002", "unknown-rulecode", W,
         "a rule message names a rulecode the rule library does not have: the rule does nothing",
         at_run_time=True),
    Code("X003", "rule", W,
         "a rule cannot be made from its message, or its body raised: the chain goes on",
         at_run_time=True),
    Code("X004", "function", W,
         "a function failed or is unknown at run time: it counts as false (no value for an F "
         "function)", at_run_time=True),
    Code("X005", "override", W,
         "a compulsory switch names a script, goal or block that does not exist: nothing switches",
         at_run_time=True),
    Code("X006", "script_vect", W,
         "a `Script/script_vect` update names a script that cannot be found or loaded: it is left "
         "out", at_run_time=True),
    Code("X007", "update", W,
         "a rule posted a map update the map cannot take: it is dropped", at_run_time=True),
    Code("X008", "no-progress", E,
         "the session looped at one instant without letting time pass: the run stops",
         at_run_time=True),
    Code("X009", "read", E,
         "reading the script's blocks failed (a jump to no block, a read that never ends, a VM "
         "trap): the run stops", at_run_time=True),
    Code("X010", "robot-unstable", E,
         "the robot's physics failed (the simulation diverged): the run stops", at_run_time=True),
)

REGISTRY: dict[str, Code] = {c.code: c for c in _CODES}
BY_NAME: dict[str, Code] = {c.name: c for c in _CODES}


def lookup(code: str) -> Code:
    """The registry entry of `code` (a code such as `L003`, or its name `unknown-label`)."""
    entry = REGISTRY.get(code.upper()) or BY_NAME.get(code.lower())
    if entry is None:
        raise KeyError(code)
    return entry


def diagnostic(
    code: str,
    message: str,
    span: Span,
    *,
    labels: tuple[Label, ...] | list[Label] = (),
    notes: tuple[str, ...] | list[str] = (),
    help: str | None = None,
    fix: Fix | None = None,
    path: str | None = None,
    severity: Severity | None = None,
) -> Diagnostic:
    """Build a diagnostic with the registry's default severity for `code`."""
    entry = lookup(code)
    return Diagnostic(
        code=code,
        severity=severity or entry.severity,
        message=message,
        span=span,
        labels=tuple(labels),
        notes=tuple(notes),
        help=help,
        fix=fix,
        path=path,
    )


def all_codes() -> tuple[Code, ...]:
    return _CODES


def lint_codes() -> tuple[Code, ...]:
    """The codes lint may report: every code but the run-time ones (family X)."""
    return _LINT_CODES


_LINT_CODES = tuple(c for c in _CODES if not c.at_run_time)


def run_time_name(name: str) -> str:
    """`name` itself, once checked to be a run-time code's name: what the runtime writes as
    an `error` event's `code` (runtime/status.py), so none escapes the registry."""
    entry = BY_NAME.get(name)
    if entry is None or not entry.at_run_time:
        raise KeyError(f"`{name}` is not the name of a run-time code of the registry")
    return name


def suggest_codes(query: str, limit: int = 3, *, lint_only: bool = False) -> list[str]:
    """Codes close to a mistyped code or name, best first (`scriptc explain`; `--select`
    with `lint_only`: the codes lint may report)."""
    import difflib

    entries = lint_codes() if lint_only else _CODES
    codes = [c.code for c in entries]
    names = {c.name: c.code for c in entries}
    hits = difflib.get_close_matches(query.upper(), codes, n=limit, cutoff=0.5)
    hits += [names[n] for n in difflib.get_close_matches(query.lower(), list(names),
                                                         n=limit, cutoff=0.6)]
    return list(dict.fromkeys(hits))[:limit]


def explanation_uri(code: str) -> str | None:
    """A `file:` URI of the explanation of `code`, shipped inside the package: the link an
    editor opens from a diagnostic's code (there is no public page to link to)."""
    from importlib import resources  # here: it imports tempfile and shutil, which lint needs not

    path = resources.files("scriptc.diagnostics") / "explanations" / f"{code}.md"
    try:
        return Path(str(path)).resolve(strict=True).as_uri()
    except (OSError, ValueError):
        return None


@cache
def explanation(code: str) -> str:
    """The markdown explanation shipped in `explanations/CODE.md`."""
    from importlib import resources

    try:
        return (resources.files("scriptc.diagnostics") / "explanations" / f"{code}.md").read_text(
            encoding="utf-8"
        )
    except FileNotFoundError:
        return ""
