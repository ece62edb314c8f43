"""`scriptc show-settings PATH [--json]`: the configuration a file (or folder) gets, as
`scriptc lint` applies it, and where each setting comes from: the configuration file and the
line of its key, or the default (`scriptc.project.config.describe`).

The text form is TOML (it could be pasted into a `scriptc.toml`) with the origin of each value
as a comment, then what the policy does to the codes; `--json` gives the same as one object.
The configuration's own problems go to stderr. Exit status: 0, 1 (the configuration has
errors: the settings shown are those in force, the defaults in place of the wrong values), 2
(a path that does not exist).
"""

from __future__ import annotations

import json
import os
import re

import click

from scriptc.cli.common import CliError, write, write_bytes

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def toml_value(value) -> str:
    """A setting's value (a boolean, number, string, list or dict) as TOML writes it inline
    (strings as JSON writes them: TOML reads that)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if not value:  # what is left is a table (a dict), written inline
        return "{}"
    items = (f"{k if _BARE_KEY.fullmatch(k) else json.dumps(k)} = {toml_value(v)}"
             for k, v in value.items() if v is not None)
    return "{ " + ", ".join(items) + " }"


def _origin(setting) -> str:
    if setting.origin is None:
        return "default"
    if setting.rejected:
        return f"{setting.origin}, rejected (see the problems above): the default applies"
    return str(setting.origin)


def render_text(report) -> str:
    out = [f"# the settings of `{report.file}`\n",
           f"# configuration: {report.configuration or 'none (every setting is the default)'}\n",
           f"# project root: {report.root}\n",
           f"# cache: {report.cache_dir}\n"]
    table = None
    tables: list[tuple[str, list[tuple[str, str]]]] = [("", [])]
    for setting in report.settings:
        if setting.key in ("functions", "rules"):
            continue
        head, _, key = setting.key.rpartition(".")
        if head != table:
            table = head
            tables.append((head, []))
        tables[-1][1].append((f"{key} = {toml_value(setting.value)}", _origin(setting)))
    for head, rows in tables:
        if not rows:
            continue
        out.append(f"\n[{head}]\n" if head else "\n")
        width = max(len(line) for line, _ in rows)
        out += [f"{line:<{width}}  # {origin}\n" for line, origin in rows]
    for setting in report.settings:
        if setting.key not in ("functions", "rules"):
            continue
        for entry in setting.value:
            out.append(f"\n[[{setting.key}]]  # {_origin(setting)}\n")
            out += [f"{k} = {toml_value(v)}\n" for k, v in entry.items() if v is not None]
    silenced = [code for code, (reported, _s) in report.codes.items() if not reported]
    from scriptc.diagnostics.codes import lookup

    changed = [(code, severity) for code, (reported, severity) in report.codes.items()
               if reported and severity is not lookup(code).severity]
    out.append("\n# what the policy does to the codes (errors are always reported)\n")
    out.append(f"# not reported: {', '.join(silenced) or 'none'}\n")
    out.append("# severity changed: " + (", ".join(f"{c} -> {s.value}" for c, s in changed)
                                         or "none") + "\n")
    out.append(f"# per-file-ignores for this file: {', '.join(report.ignored_here) or 'none'}\n")
    return "".join(out)


def render_json(report) -> str:
    record = {
        "file": report.file,
        "configuration": report.configuration,
        "root": report.root,
        "cache_dir": report.cache_dir,
        "settings": {s.key: {"value": s.value,
                             "origin": None if s.origin is None else
                             {"file": s.origin.file, "line": s.origin.line,
                              "column": s.origin.column},
                             "rejected": s.rejected} for s in report.settings},
        "codes": {code: {"reported": reported, "severity": severity.value}
                  for code, (reported, severity) in report.codes.items()},
        "per_file_ignores_here": list(report.ignored_here),
    }
    return json.dumps(record, indent=2, ensure_ascii=False) + "\n"


@click.command("show-settings")
@click.argument("path", type=click.Path())
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--config", "config", metavar="FILE",
              type=click.Path(exists=True, dir_okay=False),
              help="As `lint --config`: this configuration file instead of searching.")
@click.option("--isolated", is_flag=True, help="As `lint --isolated`: no configuration.")
@click.pass_context
def command(ctx: click.Context, path: str, as_json: bool, config: str | None,
            isolated: bool) -> None:
    """Show the configuration PATH gets and where each setting comes from (a configuration
    file and line, or the default)."""
    from scriptc.cli.common import show
    from scriptc.diagnostics.model import has_errors
    from scriptc.project.config.describe import describe

    if config and isolated:
        raise click.UsageError("--config and --isolated contradict each other")
    if not os.path.lexists(path):
        raise CliError(f"`{path}` does not exist")
    report = describe(path, config=config, isolated=isolated)
    if report.problems:
        show([(report.source, report.problems)], err=True)
    if as_json:
        write_bytes(render_json(report).encode("utf-8"))
    else:
        write(render_text(report))
    ctx.exit(1 if has_errors(report.problems) else 0)
