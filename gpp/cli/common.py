"""What the commands of `gpp` share: exit codes, output formats and colour, usage errors, the
project's settings and files, and writing diagnostics.

Adding a command: write a module gpp/cli/NAME.py with the command as a typer function and a
`register(app)` that adds it, and name the module in gpp.cli.app.COMMANDS. Import only typer,
this module and the standard library at the top; import the command's machinery inside the
function (start-up time, tests/cli/test_cli.py). Report problems through `emit_diagnostics`, user
mistakes through `usage_error`, and end with `raise typer.Exit(code)`. This module imports
neither typer nor anything of gpp at the top: the entry point imports it before the CLI
library.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

if TYPE_CHECKING:
    from gpp.base.diagnostics import Diagnostic
    from gpp.console.access import Access
    from gpp.project.config import Config, ConfigError

# The settings of every typer app of gpp (the root one and `gpp trace`'s).
APP_SETTINGS: dict[str, Any] = {
    "no_args_is_help": True,
    "add_completion": False,
    "pretty_exceptions_enable": False,
    # Help texts are Markdown: paragraphs are reflowed to the terminal's width, `code` is shown as
    # code, and square brackets (`[tool.gpp]`, `[PATH]`) are text, not Rich markup.
    "rich_markup_mode": "markdown",
    "context_settings": {"help_option_names": ["-h", "--help"]},
}

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


def did_you_mean(candidates: Sequence[str]) -> str:
    """`; did you mean `a` or `b`?` to end a usage error, or "" without candidates."""
    if not candidates:
        return ""
    from gpp.base.suggest import Suggestion

    return "; " + Suggestion(tuple(candidates)).help


def require_readable(path: Path) -> None:
    """A usage error unless `path` is a regular file this process may read."""
    from gpp.base.paths import input_problem

    problem = input_problem(path)
    if problem is not None:
        usage_error(problem)
    try:
        with path.open("rb"):
            pass
    except OSError as e:
        usage_error(f"cannot read '{path}': {e.strerror or e}")


def require_writable(paths: Sequence[Path]) -> None:
    """A usage error naming every file that could not be written, before any is (paths as the
    user should see them)."""
    from gpp.base.paths import write_problem

    problems = [problem for problem in map(write_problem, paths) if problem is not None]
    if problems:
        usage_error("; ".join(problems) + ": no file was changed")


def split_ros_arguments(args: list[str]) -> tuple[list[str], tuple[str, ...] | None]:
    """The command line without its ROS arguments, and those (None when there is no
    `--ros-args`): as for any ROS node, each `--ros-args` begins them and `--` (or the end)
    ends them, so `gpp run a.gpp --ros-args -r __ns:=/r1 -- --trace t.jsonl` runs with
    `--trace`. rcl parses them (the ros2 platform hands them on)."""
    if "--ros-args" not in args:
        return args, None
    rest: list[str] = []
    ros: list[str] = []
    inside = False
    for arg in args:
        if arg == "--ros-args":
            inside = True
        elif inside and arg == "--":
            inside = False
        else:
            (ros if inside else rest).append(arg)
    return rest, tuple(ros)


# `gpp run --console` without an address (gpp.console.access.DEFAULT_ADDRESS).
DEFAULT_CONSOLE = "127.0.0.1:8765"


def with_console_address(args: list[str]) -> list[str]:
    """The command line with the default address after a bare `--console` (one followed by
    nothing, another option or an argument that is not HOST:PORT): the CLI library has no
    option whose value may be left out."""
    import re

    shown: list[str] = []
    for i, arg in enumerate(args):
        shown.append(arg)
        if arg != "--console":
            continue
        following = args[i + 1] if i + 1 < len(args) else None
        if following is None or not re.fullmatch(r"(\[[^\]]+\]|[^\s:\[\]/]*):[0-9]{1,5}|[0-9]{1,5}", following):
            shown.append(DEFAULT_CONSOLE)
    return shown


def console_access(address: str | None, wait: bool, token: str | None) -> Access | None:
    """Who may use the console `--console` asks for (None: no console); a usage error for an
    address that is not one, or for --console-wait or --console-token without --console."""
    if address is None:
        if wait or token is not None:
            usage_error(
                f"{'--console-wait' if wait else '--console-token'} is for the operator console: it needs --console"
            )
        return None
    from gpp.console.access import Access, AccessError, new_token, parse_address

    try:
        where = parse_address(address)
    except AccessError as e:
        usage_error(str(e))
    if token is not None and not token.strip():
        usage_error("--console-token must not be empty")
    if token is None and not where.loopback:
        token = new_token()
    return Access(where, token)


def usage_error(message: str) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    raise SystemExit(EXIT_USAGE)


def config_error(e: ConfigError) -> NoReturn:
    """A bad configuration file: its diagnostic on stderr, exit status 2."""
    from gpp.report.text import render_text

    sys.stderr.write(render_text([e.diagnostic], summary=False))
    raise SystemExit(EXIT_USAGE)


def load_config(start: Path) -> Config:
    """The settings for a file or folder (a bad configuration file ends the command)."""
    from gpp.project.config import ConfigError, config_for

    try:
        return config_for(start)
    except ConfigError as e:
        config_error(e)


def files_to_check(given: Sequence[Path], hint: str = "") -> list[Path]:
    """The files `gpp check` and `gpp fmt` work on (gpp.project.config.project_files): each file given,
    the .gpp files under each folder given, or with no PATH the project's `paths`. A path that
    does not exist, a bad configuration file or no .gpp file at all end the command (exit 2;
    `hint` is added to the last message)."""
    from gpp.base.paths import input_problem
    from gpp.project.config import ConfigError, project_files

    for path in given:
        problem = input_problem(path, folder=True)
        if problem is not None:
            usage_error(problem)
    try:
        files = project_files(given)
    except ConfigError as e:
        config_error(e)
    if not files:
        where = ", ".join(f"'{p}'" for p in given) if given else "the project (the working directory)"
        usage_error(f"no .gpp files found in {where}{hint}")
    return files


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


def emit_diagnostics(
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
    from gpp.report import text as render

    limit = render.DEFAULT_MAX_DIAGNOSTICS if max_per_code is None else max_per_code
    if output_format is OutputFormat.JSON:
        sys.stdout.write(render.render_json(diagnostics))
    elif output_format in (OutputFormat.CONCISE, OutputFormat.GITHUB):
        from gpp.report import concise as formats

        concise = output_format is OutputFormat.CONCISE
        sys.stdout.write((formats.render_concise if concise else formats.render_github)(diagnostics))
    elif output_format is OutputFormat.SARIF:
        from gpp.report.sarif import render_sarif

        sys.stdout.write(render_sarif(diagnostics))
    elif use_color(color):
        from rich.console import Console

        # "standard" colours: our theme needs no more, and they work even where TERM is unknown.
        console = Console(file=sys.stdout, force_terminal=True, no_color=False, color_system="standard")
        render.print_diagnostics(console, diagnostics, summary=summary, max_per_code=limit)
    else:
        sys.stdout.write(render.render_text(diagnostics, summary=summary, max_per_code=limit))
    sys.stdout.flush()


def loopback_address(text: str) -> tuple[str, int]:
    """HOST:PORT for a server's --tcp (`gpp lsp`, `gpp dap`); only loopback hosts: the servers have
    no authentication."""
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
