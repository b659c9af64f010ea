"""The `gpp` command line: the entry point, exit codes and what the commands share.

Exit codes (DESIGN.md): 0 success, 1 problems in the program, 2 usage errors (bad options,
unreadable files), 3 an internal error in gpp itself. No traceback reaches the user unless
GPP_DEBUG=1 is set.

Start-up time matters for `gpp check` in editors and CI (bench/startup.py): `main` hands
`gpp check` straight to gpp.cli_check (argparse from the standard library), so a check imports
neither typer (which brings pydantic) nor rich, the interpreter or the platforms. Every other
command goes through the typer app of gpp.cli_app. Each command imports what it needs (the
parser, the renderers, rich) when it runs.

Adding a command (`run`, `test`, `lsp`, ...): write a function decorated with
`@app.command()` in gpp.cli_app (or register it from a module of its own, as gpp.cli_run
does), import its machinery inside the function, report problems through `_emit_diagnostics`,
user mistakes through `_usage_error`, and end with `raise typer.Exit(code)`.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Sequence
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

from gpp import __version__
from gpp.resources import InstallationError

if TYPE_CHECKING:
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


# ---------------------------------------------------------------- shared by the commands


def _did_you_mean(candidates: Sequence[str]) -> str:
    """`; did you mean `a` or `b`?` to end a usage error, or "" without candidates."""
    if not candidates:
        return ""
    from gpp.suggest import Suggestion

    return "; " + Suggestion(tuple(candidates)).help


def _require_readable(path: Path) -> None:
    try:
        with path.open("rb"):
            pass
    except OSError as e:
        _usage_error(f"cannot read '{path}': {e.strerror or e}")


def _usage_error(message: str) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    raise SystemExit(EXIT_USAGE)


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
        render.print_diagnostics(console, diagnostics, summary=summary, max_per_code=limit)
    else:
        sys.stdout.write(render.render_text(diagnostics, summary=summary, max_per_code=limit))
    sys.stdout.flush()


# ---------------------------------------------------------------- entry point


def main(argv: Sequence[str] | None = None) -> None:
    """The console script `gpp`: run the app and turn any internal failure into exit code 3."""
    # Programs nest deeply; Python 3.11 runs Python-to-Python calls without the C stack.
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    signal.signal(signal.SIGTERM, _terminate)
    args = sys.argv[1:] if argv is None else list(argv)
    try:
        if args[:1] == ["check"]:
            from gpp.cli_check import check

            sys.exit(check(args[1:]))
        from gpp.cli_app import app

        app(args=args, prog_name="gpp")
    except InstallationError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(EXIT_USAGE)
    except KeyboardInterrupt as e:
        print("terminated" if _is_terminated(e) else "interrupted", file=sys.stderr)
        sys.exit(143 if _is_terminated(e) else 130)
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
    from gpp.runtime.errors import Terminated

    raise Terminated


def _is_terminated(e: KeyboardInterrupt) -> bool:
    """Whether the interruption came from SIGTERM (only `_terminate` raises Terminated, so
    the class is imported only when there is one to recognise)."""
    errors = sys.modules.get("gpp.runtime.errors")
    return errors is not None and isinstance(e, errors.Terminated)


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
