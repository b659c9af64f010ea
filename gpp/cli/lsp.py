"""`gpp lsp`: the golog++ language server for editors (the `lsp` package)."""

from __future__ import annotations

from typing import Annotated

import typer

from gpp.cli.common import EXIT_OK, usage_error


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
    address = _loopback_address(tcp) if tcp is not None else None
    # A server has nothing to finish: SIGTERM (an editor stopping it) ends it at once.
    signals.end_at_once_on_sigterm()
    # pygls and lsprotocol take half a second to import: only this command pays for them.
    from lsp.main import serve_stdio, serve_tcp

    if address is None:
        serve_stdio()
    else:
        serve_tcp(*address)
    raise typer.Exit(EXIT_OK)


def _loopback_address(text: str) -> tuple[str, int]:
    """HOST:PORT for --tcp; only loopback hosts: the server has no authentication."""
    import ipaddress

    host, sep, port = text.rpartition(":")
    host = host.strip("[]")
    if not sep or not port.isdigit() or not 0 < int(port) < 65536:
        usage_error(f"--tcp wants HOST:PORT with a port from 1 to 65535, not `{text}`")
    try:
        loopback = host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = False
    if not loopback:
        usage_error(f"--tcp listens on loopback addresses only (127.0.0.1, ::1, localhost), not `{host}`")
    return host, int(port)
