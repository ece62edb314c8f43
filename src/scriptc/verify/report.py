"""What `scriptc verify` says of a script: each violated property as diagnostics in the
compiler's style (family Y, pointing at the loop, the goal, the block), each undecided one as a
warning, one line per property, and the result as data (`--json`).
"""

from __future__ import annotations

from collections.abc import Mapping

from scriptc.diagnostics.codes import diagnostic
from scriptc.diagnostics.model import Diagnostic
from scriptc.numbers import JSONObject
from scriptc.source import Span
from scriptc.verify.verdicts import PROVED, UNKNOWN, VIOLATED, Finding, Verification

__all__ = ["CODES", "as_data", "diagnostics", "property_lines", "stats_line"]

# The code of each property's violation. A cycle that lets no time pass is lint's F002: a
# script with one has an error and is not explored (verify reads checked scripts only), so
# `no-progress` is violated only for a model made without the checks (the Python API).
CODES = {"no-stall": "Y001", "no-progress": "F002", "goals": "Y002", "blocks": "Y003",
         "safety": "Y004"}

_GREEN, _RED, _YELLOW, _RESET = "\x1b[32m", "\x1b[31m", "\x1b[33m", "\x1b[0m"
_COLOURS = {PROVED: _GREEN, VIOLATED: _RED, UNKNOWN: _YELLOW}


def diagnostics(verification: Verification, replays: Mapping[str, str]) -> list[Diagnostic]:
    """The diagnostics of a verification: a Y001-Y004 (F002) for each thing a violated
    property is about (the help replays the run that shows it: `replays` maps a witness's
    name to its `scriptc run` command), a Y005 for each property not decided."""
    whole = verification.model.program.script.name.span
    out: list[Diagnostic] = []
    for finding in verification.findings:
        if finding.property in ("terminates", "duration"):
            if finding.status == UNKNOWN and finding.property == "duration":
                out.append(_undecided(finding, whole))
            continue  # said by no-stall and no-progress
        if finding.status == VIOLATED:
            code = CODES[finding.property]
            replay = replays.get(finding.witness.name) if finding.witness is not None else None
            help_ = f"replay it: {replay}" if replay else None
            for item in finding.items:
                out.append(diagnostic(code, item.message, item.span, notes=item.notes,
                                      help=help_))
        elif finding.status == UNKNOWN:
            out.append(_undecided(finding, whole))
    out.sort(key=Diagnostic.sort_key)
    return out


def _undecided(finding: Finding, whole: Span) -> Diagnostic:
    return diagnostic("Y005", f"`{finding.property}` is not decided: {finding.detail}",
                      finding.span or whole, notes=tuple(finding.notes))


def property_lines(verification: Verification, *, color: bool = False) -> str:
    """One line per property: its name, its status, what it says."""
    lines = []
    for f in verification.findings:
        status = f.status
        shown = f"{_COLOURS[status]}{status:<9}{_RESET}" if color else f"{status:<9}"
        lines.append(f"  {f.property:<12} {shown} {f.detail}\n")
    return "".join(lines)


def stats_line(verification: Verification) -> str:
    """What was explored and how fast (`--stats`)."""
    found = verification.exploration
    rate = found.count / found.seconds if found.seconds > 0 else 0.0
    return (f"  {found.count:,} sets of instants explored in {found.seconds:.3f} s "
            f"({rate:,.0f} per second; {found.accelerated} loops taken whole), "
            f"{verification.replays} replays, {verification.seconds:.3f} s in all\n")


def as_data(path: str, verification: Verification, written: Mapping[str, str],
            assumptions: list[str]) -> JSONObject:
    """The result of one file as `--json` prints it (docs/verify.md)."""
    properties = []
    for f in verification.findings:
        witness = f.witness
        properties.append({
            "property": f.property,
            "status": f.status,
            "detail": f.detail,
            "counterexample": (written.get(witness.name) if witness is not None
                               and f.status == VIOLATED else None),
            "confirmed": witness.confirmed if witness is not None else None,
            "notes": list(f.notes),
        })
    return {
        "file": path,
        "properties": properties,
        "duration_ms": {"min": verification.duration_min, "max": verification.duration_max},
        "witnesses": {w.name: {"confirmed": w.confirmed, "scenario": written.get(w.name),
                               "why": w.why or None} for w in verification.witnesses},
        "assumptions": list(assumptions),
        "states": verification.states,
        "replays": verification.replays,
        "seconds": round(verification.seconds, 3),
    }
