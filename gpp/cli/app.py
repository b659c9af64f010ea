"""The typer app of `gpp`: the root options (`--version`, `--help`) and one module per command,
each registering itself (`register(app)`); COMMANDS names them.

`make_app(command)` registers only the command a process runs (gpp.cli.main passes the first
word of the command line), so that a process imports and builds that command alone; with
None, or a word that names no command (typer then lists the commands or suggests one), it
registers all of them. `app` is the app with every command (for in-process tests).
"""

from __future__ import annotations

from importlib import import_module
from typing import Annotated

import typer

from gpp import __version__
from gpp.cli import coercion
from gpp.cli.common import APP_SETTINGS, EXIT_OK

# Command -> the module that defines it, in the order `gpp --help` lists them.
COMMANDS: dict[str, str] = {
    "check": "gpp.cli.check",
    "explain": "gpp.cli.explain",
    "lsp": "gpp.cli.lsp",
    "dap": "gpp.cli.dap",
    "run": "gpp.cli.run",
    "console": "gpp.cli.console",
    "test": "gpp.cli.run",
    "trace": "gpp.cli.trace",
    "config": "gpp.cli.project",
    "new": "gpp.cli.project",
    "fmt": "gpp.cli.fmt",
}

coercion.install()


def _value_types_where_they_say_something() -> None:
    """Show a value type in `--help` only beside an option that takes a value: typer prints
    `<bool>` beside a flag such as `--quiet`, which takes none, and `<list[Path]>` beside an
    argument whose name (PATH, FILE) and help already say what it is."""
    from typer.core import TyperArgument, TyperOption

    shown = TyperOption.display_type_rich
    if getattr(shown, "only_where_they_say_something", False):
        return

    def option_type(self: TyperOption, ctx: typer.Context) -> str | None:
        return None if self.is_flag and self.metavar is None else shown(self, ctx)

    def argument_type(self: TyperArgument, ctx: typer.Context) -> str | None:
        return None

    option_type.only_where_they_say_something = True  # type: ignore[attr-defined]
    setattr(TyperOption, "display_type_rich", option_type)  # noqa: B010
    setattr(TyperArgument, "display_type_rich", argument_type)  # noqa: B010


_value_types_where_they_say_something()


def _print_version(value: bool) -> None:
    if value:
        print(f"gpp {__version__}")
        raise typer.Exit(EXIT_OK)


def _root(
    version: Annotated[
        bool,
        typer.Option("--version", help="Print the version and exit.", callback=_print_version, is_eager=True),
    ] = False,
) -> None:
    """A toolchain for the golog++ agent language."""


def make_app(command: str | None = None) -> typer.Typer:
    """The app with the given command, or with every command."""
    app = typer.Typer(name="gpp", help="A toolchain for the golog++ agent language.", **APP_SETTINGS)
    app.callback()(_root)
    modules = [COMMANDS[command]] if command in COMMANDS else list(dict.fromkeys(COMMANDS.values()))
    for name in modules:
        import_module(name).register(app)
    return app


_full: typer.Typer | None = None


def __getattr__(name: str) -> typer.Typer:
    """`app`, built when first asked for."""
    global _full
    if name != "app":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    if _full is None:
        _full = make_app()
    return _full
