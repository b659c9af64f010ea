"""`gpp explain`: what a diagnostic code means, with an example of the problem and its fix;
`--list` for every code."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

import typer

from gpp.cli.common import EXIT_OK, did_you_mean, usage_error

if TYPE_CHECKING:
    from gpp.codes import CodeInfo


def register(app: typer.Typer) -> None:
    app.command(name="explain")(explain)


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
