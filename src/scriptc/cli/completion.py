"""`scriptc completion bash|zsh|fish`: print the shell's completion script for `scriptc`.

It is click's own script, the one `_SCRIPTC_COMPLETE=bash_source scriptc` prints: on each
<Tab> the shell runs `scriptc` again with `_SCRIPTC_COMPLETE=<shell>_complete` and the words
typed so far, and scriptc answers with the verbs, options, choices (`--format`) or files that
fit. docs/cli.md says where to put the script.
"""

from __future__ import annotations

import click

SHELLS = ("bash", "zsh", "fish")
COMPLETE_VAR = "_SCRIPTC_COMPLETE"


@click.command("completion")
@click.argument("shell", type=click.Choice(SHELLS))
def command(shell: str) -> None:
    """Print the completion script of SHELL (bash, zsh or fish) for scriptc."""
    from click.shell_completion import get_completion_class

    from scriptc.cli.main import cli

    completion_class = get_completion_class(shell)
    # click.Choice(SHELLS) lets through only shells click has a completion class for.
    assert completion_class is not None, shell
    completer = completion_class(cli, {}, "scriptc", COMPLETE_VAR)
    script = completer.source()
    click.echo(script, nl=not script.endswith("\n"))  # one newline at the end, as click's own
