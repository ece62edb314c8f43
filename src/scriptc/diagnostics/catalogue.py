"""The diagnostics catalogue (docs/diagnostics.md), generated from the registry and the
explanation files, so the documentation cannot drift from what scriptc reports.

`python -m scriptc.diagnostics.catalogue > docs/diagnostics.md` regenerates it;
tests/test_docs.py fails when the file is stale.
"""

from __future__ import annotations

from scriptc.diagnostics.codes import all_codes

_FAMILIES = {
    "P": "Syntax",
    "S": "Structure of the item list",
    "M": "Rule messages and the mutex",
    "L": "Labels and goal ids",
    "F": "Control flow",
    "V": "Values",
    "R": "The rule grammar",
    "A": "Audio",
    "J": "Thesis JSON input",
    "C": "Configuration and suppressions",
    "K": "Safety against the robot profile",
    "X": "Run time (the `error` events of a run's trace)",
}


def _demote(markdown: str) -> str:
    """Explanations use `##` headings; inside the catalogue they sit under `###` codes."""
    return "\n".join("##" + line if line.startswith("## ") else line
                     for line in markdown.splitlines())


def render_catalogue() -> str:
    codes = all_codes()
    out = [
        "# Diagnostics",
        "",
        "Every diagnostic scriptc reports, generated from the registry",
        ("(`src/scriptc/diagnostics/codes.py`) and the explanations beside it; "
         "`scriptc explain CODE`"),
        "prints the same text. Do not edit by hand: run",
        "`python -m scriptc.diagnostics.catalogue > docs/diagnostics.md`.",
        "",
        "| code | name | default severity | summary |",
        "|---|---|---|---|",
    ]
    for c in codes:
        summary = c.summary.replace("|", "\\|")
        out.append(f"| [{c.code}](#{c.code.lower()}) | `{c.name}` | {c.severity.value} "
                   f"| {summary} |")
    family = None
    for c in codes:
        if c.code[0] != family:
            family = c.code[0]
            out += ["", f"## {_FAMILIES.get(family, family)}"]
        out += ["", f"### {c.code}", "", f"`{c.name}` ({c.severity.value}): {c.summary}", ""]
        text = c.explanation.strip()
        out.append(_demote(text) if text else "_No explanation yet._")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    import sys

    sys.stdout.write(render_catalogue())
