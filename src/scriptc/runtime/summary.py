"""What `scriptc run` prints: a readable summary of a `RunResult`, or one JSON object."""

from __future__ import annotations

from scriptc.numbers import json_dumps
from scriptc.runtime.loop import RunResult

_OUTCOMES = {
    "completed": "every script ended",
    "until": "stopped at the time limit",
    "stalled": "nothing more could happen (nothing is scheduled and the wheels are still: the "
               "operator froze the block)",
    "error": "stopped by an error",
    "interrupted": "stopped by Ctrl-C",
}


def _running(result: RunResult) -> str:
    """What an interrupted run was running: the script loaded last, unless it had ended."""
    if result.loads and result.loads[-1].ended_by is None:
        load = result.loads[-1]
        return f" while `{load.script}` ({load.path}) was running"
    return ""


_CAPPED = ("the scripts did not end within the default limit of one hour of simulated time "
           "(pass --until to run longer)")


def summary_json(result: RunResult, trace_path: str | None = None, capped: bool = False) -> str:
    data = result.as_dict()
    data["trace"] = trace_path
    if capped:
        data["note"] = _CAPPED
    return json_dumps(data, ensure_ascii=False, indent=2) + "\n"


def _goals(goals: dict[str, str]) -> str:
    if not goals:
        return "no goal recorded"
    return ", ".join(f"{g} {record}" for g, record in goals.items())


def _fixed(value: float) -> str:
    """Four decimals, without the sign of a value that rounds to zero (`-0.0000`)."""
    text = f"{value:.4f}"
    return text[1:] if text == "-0.0000" else text


def summary_text(result: RunResult, trace_path: str | None = None, capped: bool = False) -> str:
    interrupted = result.outcome == "interrupted"
    lines = [(f"{result.outcome} at {result.time_ms} ms ({result.time_ms / 1000:.3f} s "
              f"simulated): {_OUTCOMES.get(result.outcome, result.outcome)}"
              f"{_running(result) if interrupted else ''}")]
    if capped:
        lines.append(f"  note: {_CAPPED}")
    for load in result.loads:
        end = (f"ended by {load.ended_by.replace('_', ' ')} at {load.ended_ms} ms"
               if load.ended_by else "still running")
        lines.append(f"  {load.script}: loaded at {load.loaded_ms} ms ({load.reason}), {end}; "
                     f"{_goals(load.goals)}")
    p = result.pose
    rest = result.at_rest_ms
    braking = (f" (where it came to rest at {rest} ms, braking after the end)"
               if rest is not None and rest > result.time_ms else "")
    lines.append(f"  pose: x = {_fixed(p.x)} m, y = {_fixed(p.y)} m, theta = {_fixed(p.theta)} "
                 f"rad{braking}")
    if result.governor and result.governor["clamps"]:
        said = ", ".join(f"{reason} {n}" for reason, n in result.governor["reasons"].items())
        lines.append(f"  governor: kept the run within the robot profile "
                     f"{result.governor['clamps']} times ({said}; the trace's `governor` events "
                     "say when and how)")
    for error in result.errors:
        lines.append(f"  {'error' if error.get('fatal') else 'warning'} at {error['t']} ms "
                     f"[{error['code']}]: {error['message']}")
    if trace_path:
        upto = ", up to the interruption" if interrupted else ""
        lines.append(f"  trace: {trace_path} ({len(result.trace.events)} events{upto})")
    return "\n".join(lines) + "\n"
