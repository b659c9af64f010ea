"""The typer app behind every `gpp` command but `check` (gpp.cli.check, which gpp.cli calls
directly so that a check does not pay for typer): `explain` here, `run` and `test` in
gpp.cli.run, `trace` in gpp.cli.trace, `fmt` in gpp.cli.fmt, `config` and `new` in
gpp.cli.project."""

from __future__ import annotations

import signal
from typing import TYPE_CHECKING, Annotated

import typer

from gpp import __version__
from gpp.cli.check import DESCRIPTION
from gpp.cli.common import EXIT_OK, did_you_mean, usage_error
from gpp.cli.fmt import register as register_fmt
from gpp.cli.project import register as register_project
from gpp.cli.run import register
from gpp.cli.trace import register as register_trace

if TYPE_CHECKING:
    from gpp.codes import CodeInfo

app = typer.Typer(
    name="gpp",
    help="A toolchain for the golog++ agent language.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _print_version(value: bool) -> None:
    if value:
        print(f"gpp {__version__}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option("--version", help="Print the version and exit.", callback=_print_version, is_eager=True),
    ] = False,
) -> None:
    """A toolchain for the golog++ agent language."""


@app.command(
    help=DESCRIPTION,
    add_help_option=False,
    context_settings={"allow_extra_args": True, "ignore_unknown_options": True},
)
def check(ctx: typer.Context) -> None:
    # Listed here for `gpp --help`; gpp.cli.main runs `gpp check` without typer.
    from gpp.cli.check import check as run_check

    raise typer.Exit(run_check(ctx.args))


# ---------------------------------------------------------------- gpp explain


@app.command()
def explain(
    code: Annotated[
        str | None, typer.Argument(metavar="CODE", help="A diagnostic code (E0011, W0101) or its name (unused).")
    ] = None,
    list_codes: Annotated[bool, typer.Option("--list", help="List every code: code, severity, name, summary.")] = False,
) -> None:
    """Explain a diagnostic code, with an example of the problem and its fix."""
    from gpp import codes

    if list_codes:
        if code is not None:
            usage_error("give a CODE or --list, not both")
        _print_codes()
        raise typer.Exit(EXIT_OK)
    if code is None:
        usage_error("give a CODE to explain (or --list for all of them)")

    info = codes.lookup(code)
    if info is None:
        usage_error(f"unknown code `{code}`" + did_you_mean(codes.close_matches(code)))
    print(f"{info.code} ({_kind(info)} `{info.name}`): {info.summary}")
    if info.explanation:
        print()
        print(info.explanation)
    raise typer.Exit(EXIT_OK)


def _print_codes() -> None:
    from gpp import codes

    rows = [(c.code, _kind(c), c.name, c.summary) for c in codes.CODES.values()]
    name_width = max(len(r[2]) for r in rows)
    print(f"{'code':<7}{'severity':<10}{'name':<{name_width + 2}}summary")
    for code, kind, name, summary in rows:
        print(f"{code:<7}{kind:<10}{name:<{name_width + 2}}{summary}")


def _kind(info: CodeInfo) -> str:
    return "lint" if info.is_lint else "warning" if info.is_warning else "error"


# ---------------------------------------------------------------- gpp lsp


@app.command()
def lsp(
    stdio: Annotated[bool, typer.Option("--stdio", help="Talk over stdin/stdout (the default).")] = False,
    tcp: Annotated[
        str | None,
        typer.Option("--tcp", metavar="HOST:PORT", help="Listen on a loopback TCP port instead (for debugging)."),
    ] = None,
) -> None:
    """Run the golog++ language server for editors (diagnostics as you type, quick fixes, ...)."""
    if stdio and tcp is not None:
        usage_error("give either --stdio or --tcp, not both")
    address = _loopback_address(tcp) if tcp is not None else None
    # A server has nothing to finish: SIGTERM (an editor stopping it) ends it at once.
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
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


register(app)
register_trace(app)
register_project(app)
register_fmt(app)
