"""`scriptc lsp`: run the language server, speaking LSP over stdin and stdout.

Editors start it as a subprocess (`scriptc lsp`, or `scriptc lsp --stdio`, which many clients
pass). Logs go to stderr; stdout carries the protocol only. pygls is imported here, when the
verb runs, never by the other verbs.
"""

from __future__ import annotations

import click


@click.command("lsp")
@click.option("--stdio", is_flag=True, help="Talk over stdin/stdout (the default; accepted "
              "because clients pass it).")
@click.option("--log-level", type=click.Choice(["debug", "info", "warning", "error"]),
              default="warning", show_default=True, help="What to log to stderr.")
def command(stdio: bool, log_level: str) -> None:
    """Run the language server (LSP over stdin/stdout)."""
    from scriptc.server.main import serve

    serve(log_level)
