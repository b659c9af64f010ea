"""The `gpp` command line: one typer app, one function per command.

Exit codes (DESIGN.md): 0 success, 1 problems in the program, 2 usage errors (bad options,
unreadable files), 3 an internal error in gpp itself. No traceback reaches the user unless
GPP_DEBUG=1 is set.

Start-up time matters for `gpp check` in editors and CI, so this module imports only typer
at the top; each command imports what it needs (the parser, the renderers, rich) when it runs.

Adding a command (`run`, `test`, `lsp`, ...): write a function decorated with
`@app.command()` below `check`, import its machinery inside the function, report problems
through `_emit_diagnostics`, user mistakes through `_usage_error`, and end with
`raise typer.Exit(code)`.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Sequence
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NoReturn

import typer

from gpp import __version__
from gpp.resources import InstallationError
from gpp.runtime.errors import Terminated

if TYPE_CHECKING:
    from gpp.diagnostics import Diagnostic

EXIT_OK = 0
EXIT_PROBLEMS = 1
EXIT_USAGE = 2
EXIT_INTERNAL = 3


class OutputFormat(StrEnum):
    """How diagnostics are written: rustc-style text, gpp's JSON report, or SARIF 2.1.0."""

    TEXT = "text"
    JSON = "json"
    SARIF = "sarif"


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
        list[Path] | None,
        typer.Argument(metavar="FILE", help="The .gpp files to check (their includes are checked too)."),
    ] = None,
    output_format: Annotated[
        OutputFormat, typer.Option("--format", help="Write diagnostics as text, one JSON document, or SARIF 2.1.0.")
    ] = OutputFormat.TEXT,
    color: Annotated[
        ColorMode, typer.Option("--color", help="Colour the text output: auto (when a terminal), always, never.")
    ] = ColorMode.AUTO,
    no_lint: Annotated[bool, typer.Option("--no-lint", help="Report errors only, no lint warnings.")] = False,
    allow: Annotated[
        list[str] | None,
        typer.Option("--allow", metavar="LINT", help="Do not report this lint (a code such as W0101, or its name)."),
    ] = None,
    deny_warnings: Annotated[
        bool, typer.Option("--deny-warnings", help="Exit with status 1 when there are warnings, too.")
    ] = False,
    list_lints: Annotated[bool, typer.Option("--list-lints", help="List the lints and exit.")] = False,
    max_diagnostics: Annotated[
        int | None,
        typer.Option(
            "--max-diagnostics",
            metavar="N",
            min=0,
            help="Text output: show at most N diagnostics of one code in one file and count the rest"
            " in one line (default 50); 0 shows all.",
        ),
    ] = None,
) -> None:
    """Parse FILES and everything they include, and report the problems found."""
    if list_lints:
        _print_lints()
        raise typer.Exit(EXIT_OK)
    if not files:
        _usage_error("no files to check (give one or more .gpp files, or --list-lints)")
    if max_diagnostics is not None and output_format is not OutputFormat.TEXT:
        _usage_error(f"--max-diagnostics applies to the text output only ({output_format} holds every diagnostic)")
    allowed = [_lint_code(a) for a in allow or ()]
    for path in files:
        _require_readable(path)
    from gpp.check import check_paths, merged_diagnostics

    try:
        results = check_paths(files, lint=not no_lint, allow=allowed)
    except OSError as e:  # a root file that vanished after the check above
        _usage_error(f"cannot read '{e.filename or files[0]}': {e.strerror or e}")
    diagnostics = merged_diagnostics(results)
    _emit_diagnostics(diagnostics, output_format, color, max_per_code=max_diagnostics)
    failed = any(d.is_error or deny_warnings for d in diagnostics)
    raise typer.Exit(EXIT_PROBLEMS if failed else EXIT_OK)


def _lint_code(code_or_name: str) -> str:
    """The code of a lint given by code or name, or a usage error."""
    from gpp import codes

    info = codes.lookup(code_or_name)
    if info is None:
        _usage_error(f"unknown lint `{code_or_name}`" + _did_you_mean(codes.close_matches(code_or_name, lints=True)))
    if not info.is_lint:
        _usage_error(f"`{info.code}` is an error, not a lint: only lints can be allowed")
    return info.code


def _print_lints() -> None:
    from gpp import codes

    rows = [(c.code, c.name, c.summary) for c in codes.lints()]
    width = max(len(name) for _, name, _ in rows)
    print(f"{'code':<7}{'name':<{width + 2}}summary")
    for code, name, summary in rows:
        print(f"{code:<7}{name:<{width + 2}}{summary}")


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


def _did_you_mean(candidates: Sequence[str]) -> str:
    if not candidates:
        return ""
    shown = [f"`{c}`" for c in candidates]
    return "; did you mean " + (shown[0] if len(shown) == 1 else ", ".join(shown[:-1]) + " or " + shown[-1]) + "?"


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


def _emit_diagnostics(
    diagnostics: Sequence[Diagnostic],
    output_format: OutputFormat,
    color: ColorMode,
    *,
    summary: bool = True,
    max_per_code: int | None = None,
) -> None:
    """Write diagnostics to stdout in the chosen format; text ends with the summary line
    (unless `summary` is false: `gpp run` prints its own summary). Text shows at most
    `max_per_code` diagnostics of one code in one file (None: the default; 0: all)."""
    from gpp import render

    limit = render.DEFAULT_MAX_DIAGNOSTICS if max_per_code is None else max_per_code
    if output_format is OutputFormat.JSON:
        sys.stdout.write(render.render_json(diagnostics))
    elif output_format is OutputFormat.SARIF:
        from gpp.sarif import render_sarif

        sys.stdout.write(render_sarif(diagnostics))
    elif use_color(color):
        from rich.console import Console

        # "standard" colours: our theme needs no more, and they work even where TERM is unknown.
        console = Console(file=sys.stdout, force_terminal=True, no_color=False, color_system="standard")
        render.print_diagnostics(console, diagnostics, summary=summary, max_per_code=limit)
    else:
        sys.stdout.write(render.render_text(diagnostics, summary=summary, max_per_code=limit))
    sys.stdout.flush()


# `gpp run` and `gpp test` live in their own module, and so does `gpp trace`.
from gpp.cli_run import register  # noqa: E402 - registered after the shared helpers above exist
from gpp.cli_trace import register as register_trace  # noqa: E402

register(app)
register_trace(app)

# ---------------------------------------------------------------- entry point


def main(argv: Sequence[str] | None = None) -> None:
    """The console script `gpp`: run the app and turn any internal failure into exit code 3."""
    # Programs nest deeply; Python 3.11 runs Python-to-Python calls without the C stack.
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    signal.signal(signal.SIGTERM, _terminate)
    try:
        app(args=None if argv is None else list(argv), prog_name="gpp")
    except Terminated:
        print("terminated", file=sys.stderr)
        sys.exit(143)
    except InstallationError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(EXIT_USAGE)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        sys.exit(130)
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


def _terminate(signum: int, frame: object) -> None:
    """SIGTERM is handled like Ctrl-C: a run cancels its activities and finishes its trace."""
    raise Terminated


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
