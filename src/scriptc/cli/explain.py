"""`scriptc explain CODE` and `scriptc explain --all`: the registry of diagnostic codes.

One code prints its heading and its explanation (markdown, rendered by rich on a terminal);
`--all` lists every code as text or as JSON (`code`, `name`, `severity`, `summary`).
"""

from __future__ import annotations

import sys

import click

from scriptc.cli.common import CliError, use_color, write, write_bytes


@click.command("explain")
@click.argument("code", required=False)
@click.option("--all", "all_", is_flag=True, help="List every code.")
@click.option("--format", "format_", type=click.Choice(["text", "json"]), default="text",
              show_default=True, help="Output format of --all.")
def command(code: str | None, all_: bool, format_: str) -> None:
    """Explain a diagnostic code (L003) or name (unknown-label)."""
    from scriptc.diagnostics import codes

    if all_ == (code is not None):
        raise click.UsageError("give either a CODE or --all")
    if code is None:  # --all
        entries = codes.all_codes()
        if format_ == "json":
            import json

            records = [{"code": c.code, "name": c.name, "severity": c.severity.value,
                        "summary": c.summary} for c in entries]
            write_bytes((json.dumps(records, indent=2, ensure_ascii=False) + "\n").encode())
        else:
            width = max(len(c.name) for c in entries)
            write("".join(f"{c.code}  {c.severity.value:<7}  {c.name:<{width}}  {c.summary}"
                          f"{' (retired)' if c.retired else ''}\n" for c in entries))
        return
    try:
        entry = codes.lookup(code)
    except KeyError:
        hint = codes.suggest_codes(code)
        message = f"unknown code `{code}`"
        if hint:
            named = [f"`{h}` ({codes.lookup(h).name})" for h in hint]
            message += f"; did you mean {' or '.join(named)}?"
        raise CliError(message + " (`scriptc explain --all` lists them)") from None
    heading = f"{entry.code} ({entry.name}): {entry.summary}"
    if entry.retired:
        heading += " (retired)"
    # A run-time code is not lint's: no severity to configure, a run that stops or goes on.
    severity = (f"at run time, in the trace: {entry.severity.value} "
                f"({'the run stops' if entry.severity.value == 'error' else 'the run goes on'})"
                if entry.at_run_time else f"default severity: {entry.severity.value}")
    body = (entry.explanation or "(no explanation has been written for this code yet)").rstrip()
    if use_color(sys.stdout):
        from rich.console import Console
        from rich.markdown import Markdown

        console = Console(force_terminal=True, no_color=False, highlight=False)
        console.print(heading, style="bold", markup=False)
        console.print(severity, markup=False)
        console.print()
        console.print(Markdown(body))
        return
    write(f"{heading}\n{severity}\n\n{body}\n")
