"""The import contracts of pyproject.toml (`[tool.importlinter]`: the layers of
docs/architecture.md, the layers inside packages, and the rooms of third-party packages) are
kept: import-linter's `lint-imports` reads the code's imports, lazy ones inside functions
included, and fails on any import a contract forbids."""

from __future__ import annotations

import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def lint_imports(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    beside = Path(sys.executable).with_name("lint-imports")
    command = str(beside) if beside.exists() else shutil.which("lint-imports")
    assert command, "lint-imports is not installed (pip install -e '.[test]')"
    return subprocess.run([command, "--no-cache", "--no-logo", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120, check=False)


@pytest.mark.slow
def test_every_import_contract_is_kept() -> None:
    done = lint_imports()
    assert done.returncode == 0, done.stdout + done.stderr
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))[
        "tool"]["importlinter"]["contracts"]
    for contract in contracts:
        assert f"{contract['name']} KEPT" in done.stdout, contract["name"]


@pytest.mark.slow
def test_a_broken_contract_fails(tmp_path: Path) -> None:
    """The check can fail: a contract the code breaks (syntax/ itself imports lark, through
    its shim) is reported, by name, with the import that breaks it."""
    (tmp_path / ".importlinter").write_text(
        "[importlinter]\nroot_package = scriptc\ninclude_external_packages = True\n\n"
        "[importlinter:contract:no-lark]\nname = no lark at all\ntype = forbidden\n"
        "source_modules =\n    scriptc.syntax\nforbidden_modules =\n    lark\n",
        encoding="utf-8")
    done = lint_imports(cwd=tmp_path)
    assert done.returncode != 0
    assert "no lark at all BROKEN" in done.stdout
    assert "scriptc.syntax.larkshim -> lark" in done.stdout
