"""Runs every case file under tests/cases/ through the harness (see harness.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from harness import CASES, case_files, expect, short_lines
from scriptc.analysis.analyze import analyze_bytes

SCRIPTS = case_files(".script")
SCRIPTS = [p for p in SCRIPTS if not p.name.endswith(".out.script")]
JSONS = case_files(".json")


def _analyze(path: Path, kind: str):
    """Through the byte decoding of `scriptc.analysis.read`, as the CLI reads files (so P007
    has cases)."""
    return analyze_bytes(str(path.relative_to(CASES)), path.read_bytes(), kind)


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda p: str(p.relative_to(CASES)))
def test_script_case(path: Path) -> None:
    analysis = _analyze(path, "script")
    expect(path.with_suffix(".diagnostics"), short_lines(analysis.source, analysis.diagnostics))
    golden = path.with_suffix(".out.json")
    if golden.exists():
        from scriptc.emit.json import emit_json

        assert analysis.ok, "a case with a golden JSON file must compile"
        expect(golden, emit_json(analysis.script))


@pytest.mark.parametrize("path", JSONS, ids=lambda p: str(p.relative_to(CASES)))
def test_json_case(path: Path) -> None:
    analysis = _analyze(path, "json")
    expect(path.with_suffix(".diagnostics"), short_lines(analysis.source, analysis.diagnostics))
    golden = path.with_suffix(".out.script")
    if golden.exists():
        from scriptc.emit.script import format_script

        assert analysis.script is not None
        expect(golden, format_script(analysis.script))


def test_every_code_has_a_case() -> None:
    """Each code of the registry is triggered by at least one case file."""
    from scriptc.diagnostics.codes import all_codes

    seen = set()
    for path in CASES.rglob("*.diagnostics"):
        for line in path.read_text(encoding="utf-8").splitlines():
            seen.add(line.split(" ")[2])
    missing = [c.code for c in all_codes() if not c.retired and c.code not in seen]
    assert not missing, f"codes without a case file: {missing}"
