"""The explanations of the diagnostic codes: the four sections, and for every code whose
example is in script syntax, an example that triggers its code (the example is what
`scriptc explain CODE` shows, so it must not lie)."""

from __future__ import annotations

import re

import pytest

from scriptc.analysis.analyze import analyze_script
from scriptc.diagnostics.codes import all_codes, explanation, lookup
from scriptc.source import SourceFile

SECTIONS = ["## What it means", "## Why it matters", "## Example", "## How to fix"]
ALL_CODES = [c.code for c in all_codes()]
# Codes whose script-syntax example cannot trigger them as text, and why.
NOT_FROM_TEXT = {"P007": "an encoding error: the example shows the text, the error is in its bytes"}


def has_script_example(code: str) -> bool:
    text = explanation(code)
    return "## Example" in text and "```scriptc\n" in text.split("## Example", 1)[1]


# Run-time codes (family X) are reported by a run, not by lint: their examples are run
# (tests/test_runtime_codes.py).
RUN_TIME_CODES = [c.code for c in all_codes() if c.at_run_time]
# Test files' codes (family T) show a test file, with the script it runs, and verify's (family
# Y) a script that `scriptc verify` refutes: both checked below.
CHECK_CODES = [c for c in ALL_CODES if has_script_example(c) and c not in NOT_FROM_TEXT
               and c not in RUN_TIME_CODES and not c.startswith(("T", "Y"))]
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


def test_the_examples_checked_cover_the_codes_of_scripts() -> None:
    """Every code but those of JSON, configuration and test files shows a script (J, C, T:
    other formats), and all of those are checked below (T's examples too)."""
    assert len(CHECK_CODES) >= 45
    assert all(has_script_example(c) for c in VERIFY_CODES) and len(VERIFY_CODES) == 5
    others = {c for c in ALL_CODES if not has_script_example(c)}
    assert all(c[0] in "JCT" for c in others), others


@pytest.mark.parametrize("code", ALL_CODES)
def test_explanation_has_the_four_sections(code: str) -> None:
    text = explanation(code)
    assert text, f"explanations/{code}.md is missing"
    headings = [line for line in text.splitlines() if line.startswith("#")]
    assert headings == SECTIONS


@pytest.mark.parametrize("code", CHECK_CODES)
def test_explanation_example_triggers_its_code(code: str) -> None:
    """The example as written (a whole script, for the codes of a script's structure), or
    completed into one (a snippet of messages or blocks)."""
    text = explanation(code)
    written = text.split("## Example", 1)[1].split("```scriptc\n", 1)[1].split("```", 1)[0]
    tried = []
    for script in (written, example_script(text)):
        analysis = analyze_script(SourceFile(f"{code}.md", script))
        found = [d for d in analysis.diagnostics if d.code == code]
        if found:
            assert lookup(code).severity is found[0].severity
            return
        tried.append(f"{[d.code for d in analysis.diagnostics]}:\n{script}")
    pytest.fail(f"{code}'s example gives " + "\nor ".join(tried))


VERIFY_CODES = [c for c in ALL_CODES if c.startswith("Y")]


@pytest.mark.parametrize("code", VERIFY_CODES)
def test_verify_example_gives_its_code(code: str, tmp_path) -> None:
    """A verification's example (a whole script, or completed into one), verified as `scriptc
    verify` verifies it, gives its code among the diagnostics it prints."""
    from scriptc.ops.verify import VerifyOptions, verify_file
    from scriptc.verify.report import diagnostics

    text = explanation(code)
    written = text.split("## Example", 1)[1].split("```scriptc\n", 1)[1].split("```", 1)[0]
    tried = []
    for script in (written, example_script(text)):
        path = tmp_path / "example.script"
        path.write_text(script, encoding="utf-8")
        result = verify_file(str(path), VerifyOptions(counterexamples=None))
        if result.verification is None:
            tried.append(f"not verified ({result.problem}):\n{script}")
            continue
        found = [d for d in diagnostics(result.verification, {}) if d.code == code]
        if found:
            assert lookup(code).severity is found[0].severity
            return
        tried.append(f"{[d.code for d in diagnostics(result.verification, {})]}:\n{script}")
    pytest.fail(f"{code}'s example gives " + "\nor ".join(tried))


TEST_CODES = [c for c in ALL_CODES if c.startswith("T")]


@pytest.mark.parametrize("code", TEST_CODES)
def test_test_file_example_triggers_its_code(code: str, tmp_path, monkeypatch) -> None:
    """A test file's example (its ```toml block, with the script of a ```scriptc block beside
    it as `example.script`) gives its code when `scriptc test` reads it, or runs it (T006)."""
    from scriptc.ops.test import run_one
    from scriptc.testing.read import read_test

    section = explanation(code).split("## Example", 1)[1]
    blocks = re.findall(r"```(toml|scriptc)\n(.*?)```", section, re.DOTALL)
    kinds = dict(blocks)
    assert "toml" in kinds, f"{code}'s example has no test file"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "example.test.toml").write_text(kinds["toml"], encoding="utf-8")
    (tmp_path / "example.script").write_text(kinds.get("scriptc", (
        "[example]\n[goal:g]\n  [action]\n    [b##blk_terminus]\n")), encoding="utf-8")
    read = read_test("example.test.toml")
    codes = [d.code for d in read.diagnostics]
    if read.test is not None:
        from scriptc.testing.report import failures

        codes = [d.code for d in failures(read.test, run_one(read.test))]
    assert code in codes, codes
