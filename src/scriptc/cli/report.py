"""`scriptc report TRACE [-o FILE.html] [--summary [--lang en|it] [--markdown]]`: the report of
a run from its trace (docs/views.md, "The report of a run").

The page (`scriptc.views.report`) is one self-contained HTML file: the summary, the room from
above, the tracks, the velocity, the events and the flow of each script, with one cursor. It
is written to `-o FILE` (default: the trace's name with `.html`). The scripts the trace names
are found beside the trace or in the working folder (`scriptc.ops.report.find_sources`); one
that is not found is named in a warning, and the page shows the run without its flow.
`--summary` prints the session summary for the therapist instead
(`scriptc.views.summary.summarize`), and writes the page only when `-o` is given too.

Exit status: 0 written, 2 a trace that cannot be read or is not a trace, or a page that
cannot be written.
"""

from __future__ import annotations

import click

from scriptc.cli.common import CliError, check_output, write, write_output


@click.command("report")
@click.argument("trace")
@click.option("-o", "--output", "output", metavar="FILE",
              help="Write the page to FILE (- for stdout; default: the trace's name with "
                   ".html).")
@click.option("--summary", "summary", is_flag=True,
              help="Print the session summary in plain words (for the therapist) instead of "
                   "writing the page (both with -o).")
@click.option("--lang", "lang", type=click.Choice(("en", "it")), default="en",
              show_default=True, help="The summary's language.")
@click.option("--markdown", "markdown", is_flag=True, help="The summary as Markdown.")
def command(trace: str, output: str | None, summary: bool, lang: str, markdown: bool) -> None:
    """Write the report of a run (one HTML page) from its trace (JSON lines).

    The page needs nothing else: the scripts' flows are drawn from the scripts the trace
    names, found beside the trace or in the working folder.
    """
    from scriptc.analysis.read import ReadError
    from scriptc.ops.report import TraceError, default_output, find_sources, read_trace

    if summary and output is None:
        page = None
    else:
        page = output if output is not None else default_output(trace)
        if page == trace:
            raise CliError(f"the output `{page}` is the trace itself: choose another file "
                           "with -o")
        check_output(page)
    try:
        events = read_trace(trace)
    except (ReadError, TraceError) as exc:
        raise CliError(str(exc)) from None
    if summary:
        from scriptc.views.summary import summarize

        write(summarize(events, lang=lang, markdown=markdown))
    if page is None:
        return
    from scriptc.views.report import report_html

    sources, warnings = find_sources(events, trace)
    for warning in warnings:
        write(f"warning: {warning}\n", err=True)
    html = report_html(events, sources)
    write_output(page, html)
    if page != "-":
        size = len(html.encode("utf-8"))
        write(f"wrote {page} ({size / 1024:,.0f} KiB)\n", err=True)
