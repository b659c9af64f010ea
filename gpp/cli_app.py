"""The typer app behind every `gpp` command but `check` (gpp.cli_check, which gpp.cli calls
directly so that a check does not pay for typer): `explain` here, `run` and `test` in
gpp.cli_run, `trace` in gpp.cli_trace."""

from __future__ import annotations

from typing import Annotated

import typer

from gpp import __version__
from gpp.cli import EXIT_OK, _did_you_mean, _usage_error
from gpp.cli_check import DESCRIPTION
from gpp.cli_run import register
from gpp.cli_trace import register as register_trace

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
    from gpp.cli_check import check as run_check

    raise typer.Exit(run_check(ctx.args))


# ---------------------------------------------------------------- gpp explain


@app.command()
def explain(
    code: Annotated[str, typer.Argument(metavar="CODE", help="A diagnostic code (E0011, W0101) or its name (unused).")],
) -> None:
    """Explain a diagnostic code, with an example of the problem and its fix."""
    from gpp import codes

    info = codes.lookup(code)
    if info is None:
        _usage_error(f"unknown code `{code}`" + _did_you_mean(codes.close_matches(code)))
    kind = "lint" if info.is_lint else "warning" if info.is_warning else "error"
    print(f"{info.code} ({kind} `{info.name}`): {info.summary}")
    if info.explanation:
        print()
        print(info.explanation)
    raise typer.Exit(EXIT_OK)


register(app)
register_trace(app)
