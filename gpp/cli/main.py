"""The console script `gpp` and `python -m gpp`: install the signal handlers, dispatch to a
command, and turn what goes wrong into an exit code (DESIGN.md): 0 success, 1 problems in the
program, 2 usage errors (bad options, unreadable files), 3 an internal error in gpp itself,
130/143 on SIGINT/SIGTERM (gpp.base.signals). No traceback reaches the user unless
GPP_DEBUG=1 is set.

The handlers are installed before anything else is imported, the CLI library included, so a
signal during start-up ends the process as one later does. Then the typer app is built with
the one command the command line names (gpp.cli.app.make_app), which imports what it needs
when it runs: `gpp check` pays for neither the interpreter nor the platforms (bench/startup.py).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import NoReturn

from gpp.base import signals


def main(argv: Sequence[str] | None = None) -> NoReturn:
    """The console script `gpp`: run the command and exit with its code."""
    signals.install()
    # Programs nest deeply; Python 3.11 runs Python-to-Python calls without the C stack.
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    args = sys.argv[1:] if argv is None else list(argv)
    interruption: KeyboardInterrupt | None = None
    try:
        code = _run(args)
    except KeyboardInterrupt as e:
        interruption, code = e, 0
    # By the recorded signal too, not by the exception alone: the CLI library turns an
    # interruption it sees into exit code 130, whichever signal it was.
    if interruption is not None or signals.received() is not None:
        signals.ignore()
        print(signals.message(interruption), file=sys.stderr)
        code = signals.exit_code(interruption)
    sys.exit(code)


def _run(args: list[str]) -> int:
    """Run the command; its exit code."""
    from gpp.base.resources import InstallationError
    from gpp.cli.common import EXIT_INTERNAL, EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE

    try:
        from gpp.cli.app import make_app
        from gpp.cli.common import split_ros_arguments, with_console_address

        # The CLI library would refuse rcl's `-r`/`-p`: the ROS arguments go to the platform.
        args, ros_arguments = split_ros_arguments(args)
        if args[:1] == ["run"]:
            args = with_console_address(args)
        if ros_arguments is not None and args[:1] != ["run"]:
            print("error: --ros-args: only `gpp run` (on platform ros2) takes ROS arguments", file=sys.stderr)
            return EXIT_USAGE
        make_app(args[0] if args else None)(args=args, prog_name="gpp", obj=ros_arguments)
        return EXIT_OK
    except SystemExit as e:
        return _exit_code(e)
    except InstallationError as e:
        print(f"error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:
        # The reader went away (`gpp check ... | head`); silence the final flush too.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_PROBLEMS
    except Exception as e:
        if os.environ.get("GPP_DEBUG") == "1":
            raise
        _report_internal_error(e)
        return EXIT_INTERNAL


def _exit_code(e: SystemExit) -> int:
    if e.code is None or isinstance(e.code, int):
        return e.code or 0
    print(e.code, file=sys.stderr)
    return 1


def _report_internal_error(e: Exception) -> None:
    from gpp import __version__

    detail = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
    print(f"internal error: {detail}", file=sys.stderr)
    print(
        f"note: this is a bug in gpp {__version__}; please report it with the input that caused it\n"
        "      (run again with GPP_DEBUG=1 to see the traceback)",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
