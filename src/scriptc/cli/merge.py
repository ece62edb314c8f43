"""`scriptc merge OUTPUT INPUT...`: the outputs of a sharded test run's jobs merged into one
(docs/testing.md, "Merging the shards' outputs"): JUnit reports into one report (OUTPUT
`*.xml`), coverage data into one (OUTPUT `*.json`) or into an LCOV tracefile (OUTPUT `*.info`,
`*.lcov`). What OUTPUT is to be is said by its name, or by the inputs' contents
(`scriptc.testing.merge.KINDS`); OUTPUT `-` is stdout.

Exit status: 0 merged (notes, such as a test in several inputs, on stderr), 2 an input
missing, unreadable or of another kind, an OUTPUT whose kind is unknown or that is one of the
inputs (nothing is written then). The work is `scriptc.testing.merge.merge_files`'s.
"""

from __future__ import annotations

import click

from scriptc.cli.common import CliError, check_output, write, write_output
from scriptc.paths import same_file


@click.command("merge")
@click.argument("output", metavar="OUTPUT")
@click.argument("inputs", nargs=-1, required=True, metavar="INPUT...")
def command(output: str, inputs: tuple[str, ...]) -> None:
    """Merge the shards' outputs INPUT... into OUTPUT: JUnit XML reports (OUTPUT.xml), or
    coverage data (scriptc test --coverage-data) into OUTPUT.json or an LCOV OUTPUT.info.

    What OUTPUT is to be is said by its name, or by what the inputs hold; `-` writes to
    stdout.
    """
    from scriptc.testing.merge import MergeError, merge_files

    for path in inputs:
        if same_file(path, output):
            raise CliError(f"the output `{output}` is one of the inputs: refusing to "
                           "overwrite it (name a new file)")
    check_output(output)
    try:
        _kind, text, notes = merge_files(output, inputs)
    except MergeError as exc:
        raise CliError(str(exc)) from None
    write_output(output, text)
    for note in notes:
        write(f"note: {note}\n", err=True)
