"""`scriptc lint PATH...`: the diagnostics of script files, folders of them, or stdin (`-`).

Folders are searched recursively for `*.script` files, sorted, skipping hidden files and
folders, what .gitignore files ignore and what the configuration excludes; a file named
explicitly is read whatever its suffix. Each file is linted with its configuration (the
nearest `scriptc.toml` or `[tool.scriptc]`, under the command line's `--select`,
`--extend-select` and `--ignore`), its result cached in the project's `.scriptc_cache/`, and
several files are linted in parallel. Diagnostics go to stdout (or `--output-file`) in the
chosen format, or their counts (`--statistics`), or what the fixes would change (`--diff`); a
summary (and, on a terminal, a progress bar) goes to stderr when several files are read.
`--watch` lints again on every change (`scriptc.cli.watch`).

Exit status: 0 no errors (warnings alone pass; `--exit-zero`: errors too), 1 errors (after
`--fix`, the errors left; with `--diff`, something to fix), 2 a path that does not exist or a
file that cannot be read or written (the readable files are still reported), or a usage
problem; 130 when `--watch` is stopped with Ctrl-C.
"""

from __future__ import annotations

import os

import click

from scriptc.cli.common import (
    CliError,
    check_output,
    lint_format_option,
    lint_report,
    stdin_name_option,
)
from scriptc.paths import same_file
from scriptc.source import SourceKind


def _selectors(option: str, *, ignoring: bool = False):
    """A click callback: the selectors of a repeatable, comma-separated option (`--select
    F001,M --select A`), each checked to name at least one code (with the closest codes
    suggested); `--ignore` may not name only errors, which are always reported."""

    def convert(_ctx: click.Context, _param: click.Parameter, values: tuple[str, ...]):
        from scriptc.diagnostics.codes import REGISTRY
        from scriptc.project.config.settings import run_time_refusal, selected_codes

        selectors = []
        for value in values:
            for selector in (part.strip() for part in value.split(",")):
                if not selector:
                    continue
                codes = selected_codes(selector)
                refusal = None if codes else run_time_refusal(selector)
                if refusal is not None:
                    raise click.BadParameter(refusal, param_hint=f"'{option}'")
                if not codes:
                    from scriptc.diagnostics.codes import suggest_codes

                    hint = suggest_codes(selector, lint_only=True)
                    message = f"`{selector}` names no diagnostic code"
                    if hint:
                        message += f"; did you mean {' or '.join(f'`{h}`' for h in hint)}?"
                    raise click.BadParameter(message + " (`scriptc explain --all` lists them)",
                                             param_hint=f"'{option}'")
                if ignoring and all(REGISTRY[c].severity.value == "error" for c in codes):
                    raise click.BadParameter(
                        f"`{selector}` names only errors: errors cannot be ignored (a script "
                        "with an error does not work on the robot)", param_hint=f"'{option}'")
                selectors.append(selector)
        return tuple(selectors)

    return convert


def _refuse_overwriting_scripts(output_file: str, paths: tuple[str, ...]) -> None:
    """`--output-file` never replaces a script lint reads: one named on the command line, or
    an existing `*.script` file inside a folder it lints."""
    if output_file == "-" or not os.path.exists(output_file):
        return
    target = os.path.realpath(output_file)
    for path in paths:
        if path == "-":
            continue
        inside = os.path.isdir(path) and target.endswith(".script") and \
            target.startswith(os.path.realpath(path).rstrip(os.sep) + os.sep)
        if inside or same_file(path, output_file):
            raise CliError(f"the output file `{output_file}` is a script being linted: refusing "
                           "to overwrite it (choose another file with --output-file)")


@click.command("lint")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@lint_format_option
@stdin_name_option
@click.option("--fix", is_flag=True,
              help="Apply the safe fixes, rewriting the files, and report what is left.")
@click.option("--unsafe-fixes/--no-unsafe-fixes", default=False,
              help="Take the unsafe fixes too (they may change what the script does): "
                   "--fix applies them, --diff shows them, [*] marks them.")
@click.option("--diff", is_flag=True,
              help="Write nothing; print a unified diff of what --fix would change, instead "
                   "of the diagnostics, and exit 1 if there is one.")
@click.option("--select", "select", multiple=True, metavar="CODES",
              callback=_selectors("--select"),
              help="Report only these codes, names or prefixes (comma-separated, repeatable), "
                   "instead of the configuration's select and ignore.")
@click.option("--extend-select", "extend_select", multiple=True, metavar="CODES",
              callback=_selectors("--extend-select"),
              help="Report these codes too, over the configuration (or --select).")
@click.option("--ignore", "ignore", multiple=True, metavar="CODES",
              callback=_selectors("--ignore", ignoring=True),
              help="Do not report these codes (warnings and info only: errors are always "
                   "reported), over the configuration.")
@click.option("--statistics", is_flag=True,
              help="Print how many diagnostics of each code were found instead of the "
                   "diagnostics (text, or JSON with --format json).")
@click.option("-o", "--output-file", metavar="FILE", type=click.Path(dir_okay=False),
              help="Write the output (diagnostics, statistics or diff) to FILE instead of "
                   "stdout; the summary stays on stderr.")
@click.option("-e", "--exit-zero", is_flag=True,
              help="Exit with status 0 even when errors are found (2 still means a file "
                   "could not be read).")
@click.option("-w", "--watch", is_flag=True,
              help="Lint again whenever a script or a configuration changes, until Ctrl-C.")
@click.option("--no-cache", is_flag=True,
              help="Analyse every file again, and do not write the cache.")
@click.option("--cache-dir", metavar="DIR", envvar="SCRIPTC_CACHE_DIR",
              type=click.Path(file_okay=False),
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
            fix: bool, unsafe_fixes: bool, diff: bool, select: tuple[str, ...],
            extend_select: tuple[str, ...], ignore: tuple[str, ...], statistics: bool,
            output_file: str | None, exit_zero: bool, watch: bool, no_cache: bool,
            cache_dir: str | None, config: str | None, isolated: bool, force_exclude: bool,
            jobs: int | None, quiet: bool) -> None:
    """Report the diagnostics of scripts: files, folders (every *.script inside,
    recursively, skipping what .gitignore ignores) or - for stdin."""
    if fix and not diff and "-" in paths:
        raise CliError("--fix cannot rewrite stdin: name the files to fix (or use --diff)")
    if watch and "-" in paths:
        raise click.UsageError("--watch cannot watch stdin: name the files or folders")
    if config and isolated:
        raise click.UsageError("--config and --isolated contradict each other")
    if statistics and diff:
        raise click.UsageError("--statistics and --diff contradict each other: choose one")
    if statistics and format_ not in ("text", "grouped", "json"):
        raise click.UsageError(f"--statistics prints text or json, not {format_}")
    if output_file is not None:
        check_output(output_file)
        _refuse_overwriting_scripts(output_file, paths)
    selection = None
    if select or extend_select or ignore:
        from scriptc.project.config import RuleSelection

        selection = RuleSelection(select or None, extend_select, ignore)
    from scriptc.ops.lint import LintOptions

    options = LintOptions(cache=not no_cache, cache_dir=cache_dir, jobs=jobs,
                          fix=fix and not diff, config=config, isolated=isolated,
                          force_exclude=force_exclude, diff=diff, unsafe_fixes=unsafe_fixes,
                          selection=selection)

    def report() -> int:
        return lint_report(paths, SourceKind.SCRIPT, format_, stdin_name, options, quiet=quiet,
                           statistics=statistics, output_file=output_file, exit_zero=exit_zero)

    if not watch:
        ctx.exit(report())
    from scriptc.cli.watch import watch as watch_paths

    ctx.exit(watch_paths(paths, report, clear=output_file is None))
