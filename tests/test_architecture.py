"""docs/architecture.md tells the same story as the tree: every package of src/scriptc has its
heading, every module is named in its package's section (and a name there is a module that
exists), and the layers it draws are the ones import-linter checks."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "src" / "scriptc"
DOC = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
MODULE = re.compile(r"`([a-z_]+(?:/[a-z_]+)*(?:\.py|/))`")


def sections() -> dict[str, str]:
    """Each `### ` heading of the code map with the text under it. A module is named as
    `name.py` (or, for a feature module, `name`) in its package's section; a path with a
    slash is from src/scriptc or from the repository's root."""
    code_map = DOC.split("## Code map", 1)[1].split("\n## ", 1)[0]
    parts = re.split(r"^### (.*)$", code_map, flags=re.MULTILINE)
    return dict(zip(parts[1::2], parts[2::2], strict=True))


def top_packages() -> list[str]:
    return sorted(p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file())


def test_every_package_has_its_heading() -> None:
    headings = set(sections())
    assert [p for p in top_packages() if f"`{p}/`" not in headings] == []


def test_every_module_is_named_in_its_section() -> None:
    named = sections()
    missing = []
    for package in top_packages():
        text = named[f"`{package}/`"]
        for module in sorted((PACKAGE / package).rglob("*.py")):
            if module.name == "__init__.py":
                folder = module.parent.relative_to(PACKAGE).as_posix() + "/"
                if module.parent != PACKAGE / package and f"`{folder}`" not in text:
                    missing.append(folder)
                continue
            if f"`{module.name}`" not in text and f"`{module.stem}`" not in text:
                missing.append(str(module.relative_to(PACKAGE)))
    top_level = "\n".join(heading for heading in named if "/" not in heading)
    for module in sorted(PACKAGE.glob("*.py")):
        if module.name in ("__init__.py", "__main__.py"):
            continue
        if f"`{module.name}`" not in top_level:
            missing.append(module.name)
    assert missing == []


def test_every_module_named_exists() -> None:
    stale = []
    for heading, text in sections().items():
        folder = re.fullmatch(r"`([a-z_]+)/`", heading)
        for name in MODULE.findall(heading + text):
            candidates = [PACKAGE / name, ROOT / name]
            if folder and "/" not in name.rstrip("/"):
                candidates += list((PACKAGE / folder.group(1)).rglob(name.rstrip("/")))
            if not any(c.exists() for c in candidates):
                stale.append(f"{heading}: {name}")
    assert stale == []


def test_the_layers_are_the_import_contract() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    contracts = config["tool"]["importlinter"]["contracts"]
    (layers,) = [c["layers"] for c in contracts if c["name"] == "layers, top to bottom"]
    drawn = DOC.split("## The layers", 1)[1].split("```")[1].strip().splitlines()
    assert drawn == [layer.replace("scriptc.", "") for layer in layers]
