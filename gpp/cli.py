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
    from gpp.codes import CodeInfo
    from gpp.diagnostics import Diagnostic

EXIT_OK = 0
EXIT_PROBLEMS = 1
EXIT_USAGE = 2
EXIT_INTERNAL = 3


class OutputFormat(StrEnum):
    """How diagnostics are written: rustc-style text, a line each (concise), GitHub workflow
    annotations, gpp's JSON report, or SARIF 2.1.0."""

    TEXT = "text"
    CONCISE = "concise"
    GITHUB = "github"
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
        typer.Argument(
            metavar="[PATH]...",
            help="The .gpp files or folders (searched for *.gpp) to check, with their includes "
            "(default: the project's `paths`, else the working directory).",
        ),
    ] = None,
    output_format: Annotated[
        OutputFormat,
        typer.Option(
            "--format",
            help="Write diagnostics as text, a line each (concise), GitHub annotations, JSON or SARIF 2.1.0.",
        ),
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
    fix: Annotated[
        bool, typer.Option("--fix", help="Apply every safe fix to the files, then report what remains.")
    ] = False,
    diff: Annotated[
        bool, typer.Option("--diff", help="Show the safe fixes as a unified diff without writing (exit 1 if any).")
    ] = False,
) -> None:
    """Parse PATHs and everything they include, and report the problems found.

    Settings come from the nearest gpp.toml or pyproject.toml [tool.gpp] (see `gpp config`)."""
    if list_lints:
        _print_lints()
        raise typer.Exit(EXIT_OK)
    from gpp.cli_check import run_check

    allowed = [_lint_code(a) for a in allow or ()]
    run_check(
        files or [],
        output_format,
        color,
        lint=not no_lint,
        allowed=allowed,
        deny_warnings=deny_warnings,
        fix=fix,
        diff=diff,
    )


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
    code: Annotated[
        str | None, typer.Argument(metavar="CODE", help="A diagnostic code (E0011, W0101) or its name (unused).")
    ] = None,
    list_codes: Annotated[bool, typer.Option("--list", help="List every code: code, severity, name, summary.")] = False,
) -> None:
    """Explain a diagnostic code, with an example of the problem and its fix."""
    from gpp import codes

    if list_codes:
        if code is not None:
            _usage_error("give a CODE or --list, not both")
        _print_codes()
        raise typer.Exit(EXIT_OK)
    if code is None:
        _usage_error("give a CODE to explain (or --list for all of them)")

    info = codes.lookup(code)
    if info is None:
        _usage_error(f"unknown code `{code}`" + _did_you_mean(codes.close_matches(code)))
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
    diagnostics: Sequence[Diagnostic], output_format: OutputFormat, color: ColorMode, *, summary: bool = True
) -> None:
    """Write diagnostics to stdout in the chosen format; text ends with the summary line
    (unless `summary` is false: `gpp run` prints its own summary)."""
    from gpp import render

    if output_format is OutputFormat.JSON:
        sys.stdout.write(render.render_json(diagnostics))
    elif output_format in (OutputFormat.CONCISE, OutputFormat.GITHUB):
        from gpp import formats

        concise = output_format is OutputFormat.CONCISE
        sys.stdout.write((formats.render_concise if concise else formats.render_github)(diagnostics))
    elif output_format is OutputFormat.SARIF:
        from gpp.sarif import render_sarif

        sys.stdout.write(render_sarif(diagnostics))
    elif use_color(color):
        from rich.console import Console

        # "standard" colours: our theme needs no more, and they work even where TERM is unknown.
        console = Console(file=sys.stdout, force_terminal=True, no_color=False, color_system="standard")
        render.print_diagnostics(console, diagnostics, summary=summary)
    else:
        sys.stdout.write(render.render_text(diagnostics, summary=summary))
    sys.stdout.flush()


# `gpp run` and `gpp test` live in their own module, and so do `gpp trace`, `gpp fmt`,
# `gpp config` and `gpp new`.
from gpp.cli_fmt import register as register_fmt  # noqa: E402
from gpp.cli_project import register as register_project  # noqa: E402
from gpp.cli_run import register  # noqa: E402 - registered after the shared helpers above exist
from gpp.cli_trace import register as register_trace  # noqa: E402

register(app)
register_trace(app)
register_project(app)
register_fmt(app)

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
