"""The console script `gpp` and `python -m gpp`: dispatch to a command, and turn what goes wrong
into an exit code (DESIGN.md): 0 success, 1 problems in the program, 2 usage errors (bad
options, unreadable files), 3 an internal error in gpp itself, 130/143 on SIGINT/SIGTERM. No
traceback reaches the user unless GPP_DEBUG=1 is set.

Start-up time matters for `gpp check` in editors and CI (bench/startup.py): `main` hands
`gpp check` straight to gpp.cli.check, so a check imports neither typer (which brings pydantic)
nor rich, the interpreter or the platforms. Every other command goes through the typer app of
gpp.cli.app. Each command imports what it needs when it runs.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Sequence

from gpp import __version__
from gpp.base.resources import InstallationError
from gpp.cli.common import EXIT_INTERNAL, EXIT_PROBLEMS, EXIT_USAGE


def main(argv: Sequence[str] | None = None) -> None:
    """The console script `gpp`: run the app and turn any internal failure into exit code 3."""
    # Programs nest deeply; Python 3.11 runs Python-to-Python calls without the C stack.
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    signal.signal(signal.SIGTERM, _terminate)
    args = sys.argv[1:] if argv is None else list(argv)
    try:
        if args[:1] == ["check"]:
            from gpp.cli.check import check

            sys.exit(check(args[1:]))
        from gpp.cli.app import app

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
