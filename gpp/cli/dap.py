"""`gpp dap`: the Debug Adapter Protocol server for editors (the `gpp.dap` package)."""

from __future__ import annotations

from typing import Annotated

import typer

from gpp.cli.common import EXIT_OK, loopback_address, usage_error


def register(app: typer.Typer) -> None:
    app.command(name="dap")(dap)


def dap(
    stdio: Annotated[bool, typer.Option("--stdio", help="Talk over stdin/stdout (the default).")] = False,
    tcp: Annotated[
        str | None,
        typer.Option(
            "--tcp", metavar="HOST:PORT", help="Listen on a loopback TCP port for one session instead (for debugging)."
        ),
    ] = None,
) -> None:
    """Run the golog++ debugger for editors (breakpoints, stepping, fluents as variables)."""
    if stdio and tcp is not None:
        usage_error("give either --stdio or --tcp, not both")
    address = loopback_address(tcp) if tcp is not None else None
    from gpp.dap.main import serve_stdio, serve_tcp

    if address is None:
        serve_stdio()
    else:
        serve_tcp(*address)
    raise typer.Exit(EXIT_OK)
