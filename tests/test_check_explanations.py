"""The explanations of the check codes: the four sections, and an example that triggers its
code (the example is what `scriptc explain CODE` shows, so it must not lie)."""

from __future__ import annotations

import re

import pytest

from scriptc.diagnostics.codes import explanation, lookup
from scriptc.driver import analyze_script
from scriptc.source import SourceFile

CHECK_CODES = (
    [f"M00{i}" for i in range(1, 6)]
    + [f"L00{i}" for i in range(1, 4)]
    + [f"F00{i}" for i in range(1, 4)]
    + [f"V00{i}" for i in range(3, 8)]
    + [f"R00{i}" for i in range(1, 10)]
    + [f"A00{i}" for i in range(1, 4)]
)
SECTIONS = ["## What it means", "## Why it matters", "## Example", "## How to fix"]
_NAME_ITEM = re.compile(r"\[[A-Za-z_][A-Za-z0-9_-]*\]$")


def example_script(text: str) -> str:
    """The example of an explanation as a whole script: a snippet of messages or blocks gets
    the items around it that a script needs."""
    section = text.split("## Example", 1)[1]
    snippet = section.split("```scriptc\n", 1)[1].split("```", 1)[0]
    lines = [line for line in snippet.strip().splitlines() if line.strip()]
    name = []
    if lines and _NAME_ITEM.match(lines[0]) and lines[0] != "[action]":
        name, lines = [lines[0]], lines[1:]
    messages = [line for line in lines if line.startswith(("[alfa", "[omega"))]
    body = [line for line in lines if line not in messages]
    if not any(line.startswith("[goal:") for line in body):
        body = ["[goal:g]", "[action]", *body]
    if not any(line.startswith("[b#") for line in body):
        body.append("[b##blk_terminus]")
    return "\n".join((name or ["[example]"]) + messages + body) + "\n"


@pytest.mark.parametrize("code", CHECK_CODES)
def test_explanation_has_the_four_sections(code: str) -> None:
    text = explanation(code)
    assert text, f"explanations/{code}.md is missing"
    headings = [line for line in text.splitlines() if line.startswith("#")]
    assert headings == SECTIONS


@pytest.mark.parametrize("code", CHECK_CODES)
def test_explanation_example_triggers_its_code(code: str) -> None:
    script = example_script(explanation(code))
    analysis = analyze_script(SourceFile(f"{code}.md", script))
    codes = [d.code for d in analysis.diagnostics]
    assert code in codes, f"{code}'s example gives {codes}:\n{script}"
    assert lookup(code).severity is next(d.severity for d in analysis.diagnostics if d.code == code)
