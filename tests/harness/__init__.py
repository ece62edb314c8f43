"""The one harness for case files (tests are data).

A case is an input file under tests/cases/ with its expected outputs beside it:

- `NAME.script`  script syntax; `NAME.diagnostics` lists what `scriptc lint` reports, one line
  each (`LINE:COL-ENDLINE:ENDCOL SEVERITY CODE message`, 1-based, columns in code points), empty
  when the file is clean. `NAME.out.json`, when present, is the exact text `scriptc compile`
  writes (a golden file: compared byte for byte).
- `NAME.json`    thesis JSON; `NAME.diagnostics` as above for `scriptc check`, and
  `NAME.out.script`, when present, the exact text `scriptc decompile` writes.

`UPDATE_EXPECT=1 pytest tests/test_cases.py` rewrites the expected files from what the code
does now; review the diff before committing it.
"""

from __future__ import annotations

import os
from pathlib import Path

from scriptc.diagnostics.model import Diagnostic
from scriptc.source import SourceFile

CASES = Path(__file__).parent.parent / "cases"
UPDATE = os.environ.get("UPDATE_EXPECT") == "1"


def short_lines(source: SourceFile, diagnostics: list[Diagnostic]) -> str:
    out = []
    for d in diagnostics:
        a = source.position(d.span.start)
        b = source.position(d.span.end)
        out.append(f"{a.line}:{a.column}-{b.line}:{b.column} {d.severity.value} {d.code} {d.message}\n")
    return "".join(out)


def expect(path: Path, actual: str) -> None:
    """Compare `actual` with the file at `path` (or write it when updating)."""
    if UPDATE:
        if actual or path.exists() or path.suffix == ".diagnostics":
            path.write_text(actual, encoding="utf-8", newline="")
        return
    assert path.exists(), f"missing expected file {path} (run with UPDATE_EXPECT=1)"
    expected = path.read_text(encoding="utf-8")
    assert actual == expected, f"{path.name} differs from the actual output:\n{actual}"


def case_files(suffix: str) -> list[Path]:
    """The case files with this suffix: not the golden outputs, and nothing in a hidden folder
    (a `.scriptc_cache` that linting `project/config/repo` from an editor leaves at its root, as every
    project gets one)."""
    return sorted(p for p in CASES.rglob(f"*{suffix}") if not p.name.endswith((".out.json",))
                  and not any(part.startswith(".") for part in p.relative_to(CASES).parts))
