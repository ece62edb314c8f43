"""`scriptc lint PATH...`: the diagnostics of script files, folders of them, or stdin (`-`).

Folders are searched recursively for `*.script` files, sorted, skipping hidden files and
folders, what .gitignore files ignore and what the configuration excludes; a file named
explicitly is read whatever its suffix. Each file is linted with its configuration (the
nearest `scriptc.toml` or `[tool.scriptc]`), its result cached under `.scriptc_cache/`, and
several files are linted in parallel. Diagnostics go to stdout in the chosen format; a summary
(and, on a terminal, a progress bar) goes to stderr when several files are read.

Exit status: 0 no errors (warnings alone pass), 1 errors (after `--fix`, the errors left), 2 a
path that does not exist or a file that cannot be read or written (the readable files are
still reported), or a usage problem.
"""

from __future__ import annotations

import click

from scriptc import driver
from scriptc.cli._shell import CliError, lint_format_option, report_paths, stdin_name_option


@click.command("lint")
@click.argument("paths", nargs=-1, required=True)
@lint_format_option
@stdin_name_option
@click.option("--fix", is_flag=True,
              help="Apply the safe fixes, rewriting the files, and report what is left.")
@click.option("--no-cache", is_flag=True,
              help="Analyse every file again, and do not write the cache.")
@click.option("--cache-dir", metavar="DIR", envvar="SCRIPTC_CACHE_DIR",
              help="Where the cache lives. Default: .scriptc_cache in the project's root "
                   "(the folder of the configuration of the first PATH), else here.")
@click.option("--config", "config", metavar="FILE",
              type=click.Path(exists=True, dir_okay=False),
              help="Use this configuration file for every file, instead of searching.")
@click.option("--isolated", is_flag=True, help="Use no configuration file at all.")
@click.option("--force-exclude", is_flag=True,
              help="Apply the configuration's `exclude` to files named on the command line "
                   "too (for pre-commit).")
@click.option("-j", "--jobs", type=click.IntRange(min=1), metavar="N",
              help="Worker processes. Default: one per available core.")
@click.option("-q", "--quiet", is_flag=True, help="No summary and no progress bar.")
@click.pass_context
def command(ctx: click.Context, paths: tuple[str, ...], format_: str, stdin_name: str,
            fix: bool, no_cache: bool, cache_dir: str | None, config: str | None,
            isolated: bool, force_exclude: bool, jobs: int | None, quiet: bool) -> None:
    """Report the diagnostics of scripts: files, folders (every *.script inside,
    recursively, skipping what .gitignore ignores) or - for stdin."""
    if fix and "-" in paths:
        raise CliError("--fix cannot rewrite stdin: name the files to fix")
    if config and isolated:
        raise click.UsageError("--config and --isolated contradict each other")
    options = driver.LintOptions(cache=not no_cache, cache_dir=cache_dir, jobs=jobs, fix=fix,
                                 config=config, isolated=isolated, force_exclude=force_exclude)
    report_paths(ctx, paths, "script", format_, stdin_name, options, quiet=quiet)
