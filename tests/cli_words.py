"""`scriptc` command lines written in files that are not Python (shell blocks of the docs, the
workflow `scriptc init` writes, the repository's `action.yml`), checked against the real CLI:
`scriptc_commands` finds them in a shell text, `parse` parses one as click would (the verb, its
options, the values of choices such as `--format github`) without running it, so a renamed verb,
option or choice fails the test that reads the file."""

from __future__ import annotations

import re
import shlex

import click

from scriptc.cli.main import VERBS, cli


def scriptc_commands(shell: str) -> list[list[str]]:
    """The words after `scriptc` of every `scriptc ...` command of a shell text: one per
    command of a line (split at `&&`, `||`, `;` and `|`), without comments and redirections."""
    found = []
    for raw in shell.splitlines():
        line = raw.split(" #", 1)[0].strip()
        for command in re.split(r"\s*(?:&&|\|\||;|\|)\s*", line):
            words = shlex.split(command.split(" <", 1)[0].split(" >", 1)[0])
            if words and words[0].endswith("scriptc"):
                found.append(words[1:])
    return found


def parse(words: list[str]) -> click.Context:
    """Parse `scriptc WORDS...` as the CLI does, without running it: a verb that does not
    exist, an option it does not have or a value outside an option's choices raise click's
    UsageError (or a subclass) saying which."""
    if not words or words[0] not in VERBS:
        raise click.UsageError(f"no verb `{' '.join(words[:1])}`")
    command = cli.get_command(click.Context(cli), words[0])
    assert command is not None
    return command.make_context(words[0], list(words[1:]), resilient_parsing=False)
