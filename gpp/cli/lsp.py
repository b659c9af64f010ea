"""`gpp lsp`: the golog++ language server for editors (the `lsp` package)."""

from __future__ import annotations

from typing import Annotated

import typer

from gpp.cli.common import EXIT_OK, loopback_address, usage_error


def register(app: typer.Typer) -> None:
    app.command(name="lsp")(lsp)


def lsp(
    stdio: Annotated[bool, typer.Option("--stdio", help="Talk over stdin/stdout (the default).")] = False,
    tcp: Annotated[
        str | None,
        typer.Option("--tcp", metavar="HOST:PORT", help="Listen on a loopback TCP port instead (for debugging)."),
    ] = None,
) -> None:
    """Run the golog++ language server for editors (diagnostics as you type, quick fixes, ...)."""
    from gpp.base import signals

    if stdio and tcp is not None:
        usage_error("give either --stdio or --tcp, not both")
    address = loopback_address(tcp) if tcp is not None else None
    # A server has nothing to finish: SIGTERM (an editor stopping it) ends it at once.
    signals.end_at_once_on_sigterm()
    # pygls and lsprotocol take half a second to import: only this command pays for them.
    from lsp.main import serve_stdio, serve_tcp

    if address is None:
        serve_stdio()
    else:
        serve_tcp(*address)
    raise typer.Exit(EXIT_OK)
