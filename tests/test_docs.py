"""Documentation generated from code must match the code."""

from __future__ import annotations

import os
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


# -- what the repository cites and carries ------------------------------------------------------

# Folders that are not the repository's own text: tools' caches, environments, packages.
_NOT_OURS = {".git", "node_modules", "__pycache__", ".hypothesis", ".pytest_cache",
             ".scriptc_cache", ".mypy_cache", ".ruff_cache", "build", "dist"}


def repository_text_files():
    """(path relative to the root, text) of every text file of the repository."""
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = sorted(d for d in dirs
                         if d not in _NOT_OURS and not d.startswith(".venv")
                         and not d.endswith(".egg-info"))
        for name in sorted(files):
            path = Path(folder) / name
            try:
                text = path.read_text(encoding="utf-8")
            except (UnicodeDecodeError, OSError):
                continue  # not text
            yield path.relative_to(ROOT).as_posix(), text


# The project's internal specification files are not part of the repository: users cannot
# open them, so nothing may send them there (docs/*.md and the thesis by section instead).
# (The literal is split so that this file does not match itself.)
_SPEC_CITATION = re.compile(r"\b(?:LANGUAGE|RUNTIME|JSON|TESTING)\.md\b|/work/" r"shared\b")


def test_nothing_cites_files_the_repository_does_not_have() -> None:
    found = [f"{path}:{text.count(chr(10), 0, m.start()) + 1}: {m.group()}"
             for path, text in repository_text_files()
             for m in _SPEC_CITATION.finditer(text)]
    assert found == []


def test_the_license_is_the_one_the_package_declares() -> None:
    import tomllib

    declared = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert declared["project"]["license"] == "MIT"
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License\n") and "Permission is hereby granted, free of charge" in text
