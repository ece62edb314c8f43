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
        "docs/diagnostics.md is stale: "
        "python -m scriptc.diagnostics.catalogue > docs/diagnostics.md"
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
# (`[s]` so that this file does not match itself.)
_SPEC_CITATION = re.compile(r"\b(?:LANGUAGE|RUNTIME|JSON|TESTING)\.md\b|/work/[s]hared\b")


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
    assert text.startswith("MIT License\n")
    assert "Permission is hereby granted, free of charge" in text


# -- links and file names in the documentation ------------------------------------------------

DOCUMENTS = [ROOT / "README.md", ROOT / "examples" / "README.md",
             *sorted((ROOT / "docs").glob("*.md"))]
_FENCE = re.compile(r"^```.*?^```", re.MULTILINE | re.DOTALL)
_LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")


def _prose(path: Path) -> str:
    """A document's text without its fenced blocks (code, not references)."""
    return _FENCE.sub("", path.read_text(encoding="utf-8"))


def _anchors(path: Path) -> set[str]:
    """The anchors of a Markdown file's headings, as GitHub makes them."""
    seen: dict[str, int] = {}
    anchors = set()
    for m in re.finditer(r"^#{1,6} (.+)$", _prose(path), re.MULTILINE):
        slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        anchors.add(slug if n == 0 else f"{slug}-{n}")
    return anchors


def broken_links(documents) -> list[str]:
    """The relative links of `documents` to a file, or a heading, that does not exist."""
    broken = []
    for document in documents:
        for m in _LINK.finditer(_prose(document)):
            target = m.group(1)
            if re.match(r"[a-z][a-z0-9+.-]*:", target):
                continue  # https:, mailto:
            path, _, anchor = target.partition("#")
            resolved = (document.parent / path) if path else document
            if not resolved.exists():
                broken.append(f"{document.name}: {target} (no such file)")
            elif anchor and (resolved.suffix != ".md" or anchor not in _anchors(resolved)):
                broken.append(f"{document.name}: {target} (no such heading)")
    return broken


def test_every_relative_link_of_the_documentation_exists() -> None:
    assert broken_links(DOCUMENTS) == []


def test_a_broken_link_is_found(tmp_path: Path) -> None:
    (tmp_path / "there.md").write_text("# A heading: `here` (too)\n", encoding="utf-8")
    document = tmp_path / "doc.md"
    document.write_text("[ok](there.md) [ok](there.md#a-heading-here-too) [ok](#local)\n"
                        "# Local\n[gone](nowhere.md) [wrong](there.md#nothing)\n"
                        "```\n[in code](ignored.md)\n```\n[web](https://example.org/x)\n",
                        encoding="utf-8")
    assert broken_links([document]) == ["doc.md: nowhere.md (no such file)",
                                        "doc.md: there.md#nothing (no such heading)"]


# Where a file name in the documentation is looked for: the repository, the package (module
# names such as `runtime/plot.py`), the runtime (its `robots/`), the VS Code extension (its own
# `syntaxes/`, `tests/`), the runtime cases (their `lib/`), and the document's own folder.
_BASES = ["", "src", "src/scriptc", "src/scriptc/runtime", "lsp/vscode", "tests/cases/runtime"]
# Files that are the user's, not the repository's: what `scriptc init` and the tutorial create
# in an activity repository, and examples of paths and patterns.
_USERS_FILES = {
    "activities/greeting.script", "activities/greeting.json", "scenarios/greeting.json",
    "activities/greeting.test.toml",
    "activities/", "audio/", "songs/hello.wav", "songs/...", "plugins/audio_control/songs/...",
    "out/dance_example.json", "out/dance_8.json", "./activities/x.script", "a/x.script",
    "/home/me/robot/activities/x.script", "/top.script", "dir/", ".vscode/settings.json",
    ".helix/languages.toml", "node_modules/",
    # made by the tools, ignored by git: absent from a fresh clone
    ".scriptc_cache/", "scriptc-verify/",
}
# Folders the tools write into (ignored by git): what the documentation names in them.
_MADE_BY_TOOLS = ("scriptc-verify/",)
# A named path: in backquotes, with a `/` and a file's suffix (or a folder's final `/`).
_PATH = re.compile(r"`(\.{0,2}/?[A-Za-z0-9_.-]+(?:/[A-Za-z0-9_.-]+)*/?)`")


def missing_files(documents) -> list[str]:
    """The files `documents` name (in backquotes) that the repository does not have."""
    from scriptc.cli.init import FILES

    scaffold = {name for name, _ in FILES} | {name.split("/")[0] + "/" for name, _ in FILES}
    missing = []
    for document in documents:
        for m in _PATH.finditer(_prose(document)):
            name = m.group(1)
            last = name.rstrip("/").rsplit("/", 1)[-1]
            if "/" not in name or not (name.endswith("/") or "." in last.strip(".")):
                continue
            if re.search(r"\b(NAME|CODE)\b|\.\.\.", name) and name not in _USERS_FILES:
                continue  # a pattern: `tests/cases/fmt/NAME.script`
            if name in _USERS_FILES or name in scaffold or name.startswith(_MADE_BY_TOOLS):
                continue
            places = [ROOT / base / name for base in _BASES] + [document.parent / name]
            if not any(place.exists() for place in places):
                missing.append(f"{document.name}: {name}")
    return missing


def test_every_file_the_documentation_names_exists() -> None:
    assert missing_files(DOCUMENTS) == []


def test_a_missing_file_is_found(tmp_path: Path) -> None:
    document = tmp_path / "doc.md"
    document.write_text(
        "`src/scriptc/formatter.py`, `runtime/plot.py`, `examples/`, `songs/hello.wav`,\n"
        "`.github/workflows/scriptc.yml`, `tests/cases/fmt/NAME.script`, `a/b`,\n"
        "`src/scriptc/fmt2.py` and `docs/gone/`\n```\n`src/in_code.py`\n```\n",
        encoding="utf-8")
    assert missing_files([document]) == ["doc.md: src/scriptc/fmt2.py", "doc.md: docs/gone/"]


def test_no_two_files_differ_only_in_case() -> None:
    """A checkout on a case-insensitive file system (macOS, Windows) keeps every file: no
    `README.md` beside a `readme.md`."""
    seen: dict[str, str] = {}
    clashes = []
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in _NOT_OURS and not d.startswith(".venv")]
        for name in [*dirs, *files]:
            path = (Path(folder) / name).relative_to(ROOT).as_posix()
            if path.lower() in seen:
                clashes.append((seen[path.lower()], path))
            seen[path.lower()] = path
    assert clashes == []


# `pip install scriptc`, `pip install 'scriptc[plot]'`, `pip install "scriptc==0.1.0"`: a name
# on a package index, where scriptc is not published (anyone could publish that name). Install
# lines name the source (`scriptc @ git+URL@COMMIT`, a checkout) instead.
_INDEX_INSTALL = re.compile(
    r"pip install\s+(?:-\S+\s+)*[\"']?scriptc(?:\[[^\]]*\])?(?!\s*@)(?=[\s\"'=<>~!,]|$)")


def test_no_install_line_asks_a_package_index_for_scriptc() -> None:
    found = [f"{path}: {m.group()}" for path, text in repository_text_files()
             if path != "tests/test_docs.py"  # the examples below
             for m in _INDEX_INSTALL.finditer(text)]
    assert found == []
    for line in ("pip install scriptc", "pip install 'scriptc[plot]'",
                 'python -m pip install "scriptc==0.1.0"', "pip install -U scriptc"):
        assert _INDEX_INSTALL.search(line), line
    for line in ("pip install 'scriptc @ git+https://h/o/scriptc@abc'", "pip install -e '.[plot]'",
                 "pip install 'scriptc[plot] @ git+https://h/o/scriptc@abc'",
                 "pip install scriptc-tools"):
        assert not _INDEX_INSTALL.search(line), line
