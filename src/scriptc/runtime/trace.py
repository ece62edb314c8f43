"""The trace of a run: JSON lines, one event each, every event with `t` (simulated ms) and
`event` (its kind) first. Shared by every executor; `schemas/trace.schema.json` describes each
kind and docs/runtime.md says when each is written.

Events are dicts in the order they happen; the text of a trace depends only on them (keys in
insertion order, compact separators, floats as Python's shortest repr), so two runs of the
same inputs write identical bytes.
"""

from __future__ import annotations

from typing import Any

from scriptc.numbers import JSONObject, json_dumps

# One event of the trace: `t`, `event` and the kind's fields. The values are JSON data (texts,
# numbers, booleans, None, and lists and dicts of them: a jsonmsg's record, bindings, a
# command), so they are typed at this boundary as JSON is, not per kind.
Event = JSONObject

# Every kind of event, in the order docs/runtime.md presents them.
EVENT_KINDS = (
    "session_start", "script_load", "script_unload", "rule", "rule_fire", "mutex", "block",
    "cmd_start", "cmd_stop", "block_done", "jump", "sensor", "terminus", "goal", "update",
    "operator", "velocity", "rule_note", "override", "governor", "error", "session_end",
)


def dumps(event: Event) -> str:
    return json_dumps(event, ensure_ascii=False, separators=(",", ":"))


class Trace:
    """Collects events. With `enabled=False` nothing is kept (benchmarks, or runs without
    `--trace`) but errors, which the summary reports."""

    def __init__(self, enabled: bool = True) -> None:
        self.enabled = enabled
        self.events: list[Event] = []
        self.errors: list[Event] = []
        self.count = 0

    def emit(self, t: int, event: str, **fields: Any) -> None:
        self.count += 1
        if event == "error":
            self.errors.append({"t": t, "event": event, **fields})
        if self.enabled:
            self.events.append({"t": t, "event": event, **fields})

    def of_kind(self, *kinds: str) -> list[Event]:
        return [e for e in self.events if e["event"] in kinds]

    def text(self) -> str:
        """The JSON lines text of the trace (each line ends with a newline)."""
        return "".join(dumps(e) + "\n" for e in self.events)
