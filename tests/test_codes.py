"""The registry of diagnostic codes (`scriptc.diagnostics.codes`) and the first step of adding a
diagnostic (CONTRIBUTING.md, "Adding a diagnostic"): every code the code reports has an entry,
and every entry is well formed. Each failure names what is missing and where."""

from __future__ import annotations

import re
from pathlib import Path

from scriptc.diagnostics import codes

SRC = Path(codes.__file__).parent.parent
CODE = re.compile(r"[A-Z][0-9]{3}")
NAME = re.compile(r"[a-z][a-z0-9]*(?:[-_][a-z0-9]+)*")


def _families() -> set[str]:
    """The letters of the families the registry's docstring lists (`- P  syntax (the parser)`,
    two to a line)."""
    return set(re.findall(r"(?:^|\s)- ([A-Z])  ", codes.__doc__ or "", re.MULTILINE))


def lowercase_start(text: str) -> bool:
    """Whether `text` starts as scriptc's messages do: lowercase, unless its first word is an
    acronym (`JSON`, `LEDs`)."""
    return not text[:1].isupper() or text[:2].isupper()


# A code as a string of its own in Python source: `"L003"` or `'L003'`.
QUOTED_CODE = re.compile(r"""(?<![\w"'])(["'])([A-Z][0-9]{3})\1""")


def test_every_code_the_code_reports_is_registered() -> None:
    """A code written anywhere in the package (`diagnostic("L009", ...)`) has its entry."""
    missing = {}
    for path in sorted(SRC.rglob("*.py")):
        for m in QUOTED_CODE.finditer(path.read_text(encoding="utf-8")):
            if m.group(2) not in codes.REGISTRY:
                missing.setdefault(m.group(2), []).append(str(path.relative_to(SRC.parent)))
    assert not missing, (f"codes used but not in the registry (add an entry to "
                         f"src/scriptc/diagnostics/codes.py): {missing}")


def test_the_families_are_documented() -> None:
    families = _families()
    assert set("PSMLFVRAJCKX") <= families, families
    undocumented = sorted({c.code[0] for c in codes.all_codes()} - families)
    assert not undocumented, f"families not listed in the docstring of codes.py: {undocumented}"


def test_registry_entries_are_well_formed() -> None:
    """A code is its family's letter and three digits; its name is kebab-case (a run-time
    code's may be the trace's word, `script_vect`); codes and names are unique; the summary is
    one lowercase line without a final period; the run-time codes are exactly family X."""
    problems = []
    seen_codes: set[str] = set()
    seen_names: set[str] = set()
    for c in codes.all_codes():
        if not CODE.fullmatch(c.code) or c.code[0] not in _families():
            problems.append(f"{c.code}: not a family letter and three digits")
        if not NAME.fullmatch(c.name) or ("_" in c.name and not c.at_run_time):
            problems.append(f"{c.code}: name `{c.name}` is not kebab-case")
        if c.code in seen_codes or c.name in seen_names:
            problems.append(f"{c.code}: code or name `{c.name}` used twice")
        seen_codes.add(c.code)
        seen_names.add(c.name)
        if not c.summary or c.summary.endswith(".") or "\n" in c.summary \
                or not lowercase_start(c.summary):
            problems.append(f"{c.code}: summary `{c.summary}` is not one lowercase line "
                            f"without a final period")
        if c.at_run_time != (c.code[0] == "X"):
            problems.append(f"{c.code}: only family X holds the run-time codes")
    assert not problems, problems
