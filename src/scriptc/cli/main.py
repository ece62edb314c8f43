"""The `scriptc` click group, the top-level error handling and the entry point
(`scriptc.cli.main:main`, also `python -m scriptc`).

Verbs are listed here with their one-line help and imported only when invoked (`LazyGroup`):
importing every verb module, and through them rich or jsonschema, would cost `scriptc lint`
its cold-start budget (docs/performance.md). The group's options are accepted after the verb
too (`scriptc lint --color always .`), a mistyped verb gets the closest one suggested, and
shell completion (`_SCRIPTC_COMPLETE`, or `scriptc completion SHELL`) lists the verbs from
here without importing them.
"""

from __future__ import annotations

import importlib
import os
import sys

import click

from scriptc import __version__

# name -> (module holding `command`, one-line help shown by `scriptc --help`)
VERBS: dict[str, tuple[str, str]] = {
    "compile": ("scriptc.cli.compile", "Compile a script to thesis JSON."),
    "lint": ("scriptc.cli.lint", "Report the diagnostics of scripts and folders of scripts."),
    "check": ("scriptc.cli.check", "Check thesis JSON files."),
    "decompile": ("scriptc.cli.decompile", "Turn thesis JSON back into script syntax."),
    "explain": ("scriptc.cli.explain", "Explain a diagnostic code."),
    "init": ("scriptc.cli.init", "Scaffold an activity repository (configuration, example, CI)."),
    "lsp": ("scriptc.cli.lsp", "Run the language server (LSP over stdin/stdout)."),
    "run": ("scriptc.cli.run", "Run scripts in simulated time (with a scenario, a trace)."),
    "test": ("scriptc.cli.test", "Run the tests of an activity (*.test.toml) in simulated time."),
    "verify": ("scriptc.cli.verify",
               "Prove or refute what every run of a script does, for every world."),
    "merge": ("scriptc.cli.merge", "Merge the outputs of test shards (JUnit XML) into one."),
    "graph": ("scriptc.cli.graph", "Draw the flow of a script: DOT, Mermaid or SVG."),
    "report": ("scriptc.cli.report", "Write the report of a run (one HTML page) from its trace."),
    "dis": ("scriptc.cli.dis", "Print the listing of a bytecode (.scb) file."),
    "fmt": ("scriptc.cli.fmt", "Format scripts in the canonical layout, comments kept."),
    "show-settings": ("scriptc.cli.show_settings",
                      "Show the configuration a file gets, and where each setting comes from."),
    "clean": ("scriptc.cli.clean", "Remove the cache folder of the project."),
    "completion": ("scriptc.cli.completion",
                   "Print the shell completion script (bash, zsh, fish)."),
}

COLOR_CHOICES = ("auto", "always", "never")
COLOR_HELP = ("Colour the text output: auto means on a terminal, unless NO_COLOR is set "
              "(FORCE_COLOR forces it).")

INTERNAL_ERROR_HINT = (
    "this is a bug in scriptc: please report it with the command line and the input file "
    "(set SCRIPTC_DEBUG=1 to see the traceback)"
)


class LazyGroup(click.Group):
    """A group whose verbs are imported on first use, with the top-level error policy:
    anything that escapes a verb is an internal error (exit 2), never a traceback."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(VERBS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in VERBS:
            return None
        command = importlib.import_module(VERBS[name][0]).command
        _add_group_options(command)
        return command

    def resolve_command(self, ctx: click.Context, args: list[str]):
        name = args[0] if args else ""
        if name and name not in VERBS and not name.startswith("-"):
            import difflib

            close = difflib.get_close_matches(name, list(VERBS), n=1, cutoff=0.6)
            hint = f"; did you mean `{close[0]}`?" if close else ""
            ctx.fail(f"no such command `{name}`{hint} (`scriptc --help` lists them)")
        return super().resolve_command(ctx, args)

    def shell_complete(self, ctx: click.Context, incomplete: str) -> list:
        """The verbs (from `VERBS`, nothing imported) and the group's options."""
        from click.shell_completion import CompletionItem

        verbs = [CompletionItem(name, help=help) for name, (_module, help) in VERBS.items()
                 if name.startswith(incomplete)]
        return verbs + click.Command.shell_complete(self, ctx, incomplete)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        with formatter.section("Commands"):
            formatter.write_dl([(name, help) for name, (_module, help) in VERBS.items()])

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise
        except BrokenPipeError:
            raise  # click's main quietens a closed pipe (`scriptc explain --all | head`)
        except KeyboardInterrupt:
            click.echo("error: interrupted", err=True)
            ctx.exit(130)
        except Exception as exc:  # the one place that catches everything
            report_internal_error(exc)
            ctx.exit(2)


def _set_color(ctx: click.Context, _param: click.Parameter, value: str | None) -> None:
    """`--color` given after the verb: it wins over the one before (the later one)."""
    if value is not None:
        ctx.find_root().ensure_object(dict)["color"] = value


def _add_group_options(command: click.Command) -> None:
    """The group's `--color` and `--version` on a verb too, as ruff takes `--color` after
    `check`: `scriptc lint --color always .` is `scriptc --color always lint .`."""
    taken = {opt for param in command.params for opt in param.opts}
    if "--color" not in taken:
        command.params.append(click.Option(
            ["--color", "--colour", "color"], type=click.Choice(COLOR_CHOICES), default=None,
            expose_value=False, callback=_set_color, help=COLOR_HELP))
    if "--version" not in taken:
        click.version_option(__version__, "-V", "--version", prog_name="scriptc",
                             message="%(prog)s %(version)s")(command)


def report_internal_error(exc: BaseException) -> None:
    if os.environ.get("SCRIPTC_DEBUG"):
        import traceback

        traceback.print_exception(exc)
    detail = str(exc)
    click.echo(f"error: internal error: {type(exc).__name__}{': ' + detail if detail else ''}",
               err=True)
    click.echo(f"  = help: {INTERNAL_ERROR_HINT}", err=True)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "-V", "--version", prog_name="scriptc",
                      message="%(prog)s %(version)s")
@click.option("--color", "--colour", "color", type=click.Choice(COLOR_CHOICES),
              default="auto", show_default=True, help=COLOR_HELP)
@click.pass_context
def cli(ctx: click.Context, color: str) -> None:
    """scriptc: the compiler toolchain of the robot activity language.

    Exit status: 0 no errors (warnings alone pass), 1 errors found, 2 usage problem,
    unreadable file or internal error, 130 interrupted.
    """
    ctx.ensure_object(dict).setdefault("color", color)


def main(argv: list[str] | None = None) -> None:
    """The `scriptc` command."""
    try:
        cli.main(args=argv, prog_name="scriptc")
    except SystemExit:
        raise
    except Exception as exc:  # outside any verb (argument parsing, say)
        report_internal_error(exc)
        sys.exit(2)
