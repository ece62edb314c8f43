"""Documentation generated from code must match the code."""

from __future__ import annotations

import re
from pathlib import Path

from scriptc.diagnostics.catalogue import render_catalogue
from scriptc.diagnostics.codes import all_codes

ROOT = Path(__file__).parent.parent


def test_diagnostics_catalogue_is_current() -> None:
    path = ROOT / "docs" / "diagnostics.md"
    assert path.read_text(encoding="utf-8") == render_catalogue(), (
        "docs/diagnostics.md is stale: python -m scriptc.diagnostics.catalogue > docs/diagnostics.md"
    )


def test_every_code_has_a_complete_explanation() -> None:
    for code in all_codes():
        text = code.explanation
        for section in ("## What it means", "## Why it matters", "## Example", "## How to fix"):
            assert section in text, f"{code.code}: explanation lacks {section!r}"


def test_explanation_examples_are_fenced_scriptc() -> None:
    for code in all_codes():
        assert re.search(r"```(scriptc|json|toml)\n", code.explanation), code.code
