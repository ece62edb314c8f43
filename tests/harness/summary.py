"""The `summary` aspect of case files: the session summary for the therapist of every expected
trace of the runtime cases (`runtime/**/NAME[.VARIANT].trace.jsonl`), written beside it:
`NAME[.VARIANT].summary.txt` in English as plain text and `NAME[.VARIANT].summary.it.md` in
Italian as Markdown, what `scriptc.views.summary.summarize` says of the trace's events (the
two other forms differ from these only by language or by layout)."""

from __future__ import annotations

import json
from pathlib import Path

from harness import Check, expect, files

SUFFIX = ".trace.jsonl"


def _summaries(trace: Path) -> tuple[Path, Path]:
    base = trace.name[: -len(SUFFIX)]
    return trace.with_name(f"{base}.summary.txt"), trace.with_name(f"{base}.summary.it.md")


def _check(trace: Path) -> None:
    from scriptc.views.summary import summarize

    events = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    english, italian = _summaries(trace)
    expect(english, summarize(events))
    expect(italian, summarize(events, lang="it", markdown=True))


def checks() -> list[Check]:
    return [Check("summary", trace, _summaries(trace), lambda trace=trace: _check(trace))
            for trace in files("runtime", "*" + SUFFIX)]
