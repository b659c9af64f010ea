"""The `gpp` command line: one typer app, one function per command.

Exit codes (DESIGN.md): 0 success, 1 problems in the program, 2 usage errors (bad options,
unreadable files), 3 an internal error in gpp itself. No traceback reaches the user unless
GPP_DEBUG=1 is set.

Start-up time matters for `gpp check` in editors and CI, so this module imports only typer
at the top; each command imports what it needs (the parser, the renderers, rich) when it runs.

Adding a command (`run`, `test`, `lsp`, `explain`, ...): write a function decorated with
`@app.command()` below `check`, import its machinery inside the function, report problems
through `_emit_diagnostics`, user mistakes through `_usage_error`, and end with
`raise typer.Exit(code)`.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NoReturn

import typer

from gpp import __version__

if TYPE_CHECKING:
    from gpp.diagnostics import Diagnostic

EXIT_OK = 0
EXIT_PROBLEMS = 1
EXIT_USAGE = 2
EXIT_INTERNAL = 3


class OutputFormat(StrEnum):
    """How diagnostics are written (`sarif` is planned beside these)."""

    TEXT = "text"
    JSON = "json"


class ColorMode(StrEnum):
    AUTO = "auto"
    ALWAYS = "always"
    NEVER = "never"


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


# ---------------------------------------------------------------- gpp check


@app.command()
def check(
    files: Annotated[
        list[Path], typer.Argument(metavar="FILE", help="The .gpp files to check (their includes are checked too).")
    ],
    output_format: Annotated[
        OutputFormat, typer.Option("--format", help="Write diagnostics as text or as one JSON document.")
    ] = OutputFormat.TEXT,
    color: Annotated[
        ColorMode, typer.Option("--color", help="Colour the text output: auto (when a terminal), always, never.")
    ] = ColorMode.AUTO,
) -> None:
    """Parse FILES and everything they include, and report the problems found."""
    for path in files:
        _require_readable(path)
    from gpp.check import check_paths, merged_diagnostics

    try:
        results = check_paths(files)
    except OSError as e:  # a root file that vanished after the check above
        _usage_error(f"cannot read '{e.filename or files[0]}': {e.strerror or e}")
    diagnostics = merged_diagnostics(results)
    _emit_diagnostics(diagnostics, output_format, color)
    raise typer.Exit(EXIT_PROBLEMS if any(d.is_error for d in diagnostics) else EXIT_OK)


# ---------------------------------------------------------------- shared by the commands


def _require_readable(path: Path) -> None:
    try:
        with path.open("rb"):
            pass
    except OSError as e:
        _usage_error(f"cannot read '{path}': {e.strerror or e}")


def _usage_error(message: str) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    raise typer.Exit(EXIT_USAGE)


def use_color(mode: ColorMode, stream: object = None) -> bool:
    """Whether text output gets colour: `always`/`never` decide, `auto` asks the environment
    (NO_COLOR and TERM=dumb turn colour off, FORCE_COLOR on) and then whether `stream` is a TTY."""
    if mode is ColorMode.ALWAYS:
        return True
    if mode is ColorMode.NEVER or os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR"):
        return True
    if os.environ.get("TERM") == "dumb":
        return False
    isatty = getattr(stream if stream is not None else sys.stdout, "isatty", None)
    return bool(isatty and isatty())


def _emit_diagnostics(diagnostics: Sequence[Diagnostic], output_format: OutputFormat, color: ColorMode) -> None:
    """Write diagnostics to stdout in the chosen format; text ends with the summary line."""
    from gpp import render

    if output_format is OutputFormat.JSON:
        sys.stdout.write(render.render_json(diagnostics))
    elif use_color(color):
        from rich.console import Console

        # "standard" colours: our theme needs no more, and they work even where TERM is unknown.
        console = Console(file=sys.stdout, force_terminal=True, no_color=False, color_system="standard")
        render.print_diagnostics(console, diagnostics)
    else:
        sys.stdout.write(render.render_text(diagnostics))
    sys.stdout.flush()


# ---------------------------------------------------------------- entry point


def main(argv: Sequence[str] | None = None) -> None:
    """The console script `gpp`: run the app and turn any internal failure into exit code 3."""
    try:
        app(args=None if argv is None else list(argv), prog_name="gpp")
    except BrokenPipeError:
        # The reader went away (`gpp check ... | head`); silence the final flush too.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        sys.exit(EXIT_PROBLEMS)
    except Exception as e:
        if os.environ.get("GPP_DEBUG") == "1":
            raise
        _report_internal_error(e)
        sys.exit(EXIT_INTERNAL)


def _report_internal_error(e: Exception) -> None:
    detail = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
    print(f"internal error: {detail}", file=sys.stderr)
    print(
        f"note: this is a bug in gpp {__version__}; please report it with the input that caused it\n"
        "      (run again with GPP_DEBUG=1 to see the traceback)",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
