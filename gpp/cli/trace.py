"""`gpp trace summary|html|perfetto|mcap`: look at a run's trace (written by `gpp run --trace`).
Registered on the app by gpp.cli.app.

Exit codes as for every command: 0 done, 1 the file is not a valid trace (not JSON lines, a
record that does not decode, no records), 2 usage errors (a missing or unreadable file, an
output path that cannot be written, a bad option). Everything heavy (rich, the viewer) is
imported inside the commands.
"""

from __future__ import annotations

import sys
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NoReturn

import typer

from gpp.cli.common import APP_SETTINGS

if TYPE_CHECKING:
    from gpp.runtime.events import TraceEvent
    from gpp.traceview.model import RunModel

MIN_WIDTH = 60
MAX_AUTO_WIDTH = 120
PIPE_WIDTH = 100

trace_app = typer.Typer(
    name="trace",
    help="Look at a run's trace (`gpp run --trace run.jsonl`): a terminal summary, an HTML page, Perfetto JSON, "
    "an MCAP file for Foxglove.",
    **APP_SETTINGS,
)


class Color(StrEnum):
    AUTO = "auto"
    ALWAYS = "always"
    NEVER = "never"


TraceFile = Annotated[
    Path,
    typer.Argument(
        metavar="TRACE",
        help="A trace written by `gpp run --trace`: the file, or the first part (or the folder) of a split trace.",
    ),
]


def register(app: typer.Typer) -> None:
    app.add_typer(trace_app, name="trace")


def _fail(message: str, code: int) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    raise typer.Exit(code)


def _load(path: Path) -> RunModel:
    """The run in a trace (all the parts of a split one), or a one-line error (exit 2 when the file cannot be read, 1
    when it is not a valid trace)."""
    from gpp.traceview.model import build_run_model

    return build_run_model(_records(path))


def _records(path: Path) -> list[TraceEvent]:
    """The records of the run in a trace (all the parts of a split one), or a one-line error as for `_load`."""
    from gpp.base.paths import input_problem
    from gpp.cli.common import EXIT_PROBLEMS, EXIT_USAGE
    from gpp.traceview.model import TraceReadError, load_trace

    problem = input_problem(path, folder=True)
    if problem is not None:
        _fail(problem, EXIT_USAGE)
    try:
        loaded = load_trace(path)
    except TraceReadError as e:
        _fail(str(e), EXIT_USAGE if e.usage else EXIT_PROBLEMS)
    for warning in loaded.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return loaded.events


def _output_path(trace: Path, output: Path | None, suffix: str) -> Path | None:
    """Where to write (None: stdout for `-o -`). The default is next to the trace. Writing
    over the trace itself, or into a folder that does not exist, is a usage error."""
    from gpp.cli.common import usage_error

    if output is not None and str(output) == "-":
        return None
    target = output if output is not None else trace.with_name(trace.name.removesuffix(".jsonl") + suffix)
    if target.is_dir():
        usage_error(f"cannot write '{target}': it is a directory (give a file name with -o)")
    if not target.parent.is_dir():
        usage_error(f"cannot write '{target}': the folder '{target.parent}' does not exist")
    try:
        if target.exists() and target.resolve() == trace.resolve():
            usage_error(f"'{target}' is the trace itself; give another file with -o")
    except OSError:
        pass
    return target


def _write(target: Path | None, text: str) -> None:
    from gpp.cli.common import usage_error

    if target is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    try:
        target.write_text(text, encoding="utf-8")
    except OSError as e:
        usage_error(f"cannot write '{target}': {e.strerror or e}")


@trace_app.command("summary")
def summary(
    file: TraceFile,
    width: Annotated[
        int | None,
        typer.Option(
            "--width",
            help=f"Columns to use (at least {MIN_WIDTH}; default: the terminal's, at most {MAX_AUTO_WIDTH}, "
            f"or {PIPE_WIDTH} off a terminal).",
        ),
    ] = None,
    color: Annotated[
        Color, typer.Option("--color", help="Colour: auto (on a terminal, unless NO_COLOR is set), always, never.")
    ] = Color.AUTO,
) -> None:
    """The run as a timeline on the terminal.

    Activities as bars, one row per action; rows of exogenous events, plans, waits and
    numeric values over time; then the plans, the exogenous events, what failed, and how the
    run ended. Plain text when not on a terminal or NO_COLOR is set."""
    import shutil

    from rich.console import Console

    from gpp.cli.common import EXIT_OK, ColorMode, usage_error, use_color
    from gpp.traceview.summary import render_summary

    if width is not None and width < MIN_WIDTH:
        usage_error(f"--width must be at least {MIN_WIDTH}, not {width}")
    model = _load(file)
    colored = use_color(ColorMode(color.value))
    if width is None:
        width = (
            min(shutil.get_terminal_size((PIPE_WIDTH, 24)).columns, MAX_AUTO_WIDTH)
            if sys.stdout.isatty()
            else PIPE_WIDTH
        )
        width = max(width, MIN_WIDTH)
    console = Console(
        file=sys.stdout,
        width=width,
        force_terminal=colored,
        no_color=not colored,
        color_system="standard" if colored else None,
        highlight=False,
        emoji=False,
        markup=False,
    )
    render_summary(model, console)
    raise typer.Exit(EXIT_OK)


@trace_app.command("html")
def html(
    file: TraceFile,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="The page to write (default: the trace's name with .html; - for stdout)."),
    ] = None,
    source_root: Annotated[
        list[Path] | None,
        typer.Option(
            "--source-root",
            metavar="DIR",
            help="Where to find the program files the trace names (repeatable; default: the current folder, "
            "then the trace's folder).",
        ),
    ] = None,
) -> None:
    """The run as one self-contained, interactive HTML page.

    Activities per lane, exogenous events, plans with their values, numeric values over
    time, and the source line of each step on hover; zoom and pan. The page needs no network
    access to open."""
    from gpp.cli.common import EXIT_OK, usage_error
    from gpp.traceview.html import html_page

    for root in source_root or []:
        if not root.is_dir():
            usage_error(f"--source-root '{root}' is not a folder")
    model = _load(file)
    target = _output_path(file, output, ".html")
    search = [*(source_root or []), Path.cwd(), file.parent]
    page, sources = html_page(model, trace_name=file.name, search=search)
    _write(target, page)
    if sources.missing:
        print(
            f"note: source lines not embedded: {', '.join(sources.missing)} not found "
            "(run from the folder the program was run in, or give --source-root)",
            file=sys.stderr,
        )
    if target is not None:
        print(f"wrote {target} ({_counts(model)})")
    raise typer.Exit(EXIT_OK)


@trace_app.command("perfetto")
def perfetto(
    file: TraceFile,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output", "-o", help="The JSON to write (default: the trace's name with .perfetto.json; - for stdout)."
        ),
    ] = None,
) -> None:
    """The run as Chrome trace-event JSON, for ui.perfetto.dev or chrome://tracing.

    Activities on one track per action, exogenous events, plans and errors as instants,
    numeric values as counters; times are platform time in microseconds."""
    from gpp.cli.common import EXIT_OK
    from gpp.traceview.perfetto import render_chrome_trace

    model = _load(file)
    target = _output_path(file, output, ".perfetto.json")
    _write(target, render_chrome_trace(model, trace_name=file.name))
    if target is not None:
        print(f"wrote {target} ({_counts(model)}); open it in ui.perfetto.dev or chrome://tracing")
    raise typer.Exit(EXIT_OK)


@trace_app.command("mcap")
def mcap(
    file: TraceFile,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="The MCAP file to write (default: the trace's name with .mcap)."),
    ] = None,
    prefix: Annotated[
        str,
        typer.Option(
            "--prefix",
            metavar="TOPIC",
            help="What each channel's topic starts with: TOPIC/start, TOPIC/end, ... (default: /gpp).",
        ),
    ] = "/gpp",
) -> None:
    """The run as an MCAP file, to open in Foxglove beside a robot's recording.

    One channel per record kind (/gpp/start, /gpp/end, ...) with its JSON Schema, each
    message one record as JSON, logged at the run's start plus the record's time."""
    import io
    import re

    from gpp.base.paths import write_atomically
    from gpp.cli.common import EXIT_OK, usage_error
    from gpp.traceview.mcapfile import write_mcap

    if not re.fullmatch(r"(/[A-Za-z_][A-Za-z0-9_]*)+", prefix):
        usage_error(f'--prefix must be a topic name such as /gpp or /robot1/gpp, not "{prefix}"')
    if output is not None and str(output) == "-":
        usage_error("--output: an MCAP file is binary; give a file name")
    events = _records(file)
    target = _output_path(file, output, ".mcap")
    assert target is not None
    buffer = io.BytesIO()
    counts = write_mcap(events, buffer, prefix)
    try:
        write_atomically(target, buffer.getvalue())
    except OSError as e:
        usage_error(f"cannot write '{target}': {e.strerror or e}")
    records = sum(counts.values())
    print(
        f"wrote {target} ({records} record{'s' if records != 1 else ''} on {len(counts)} channel"
        f"{'s' if len(counts) != 1 else ''}); open it in Foxglove"
    )
    raise typer.Exit(EXIT_OK)


def _counts(model: RunModel) -> str:
    def count(n: int, one: str, many: str) -> str:
        return f"{n} {one if n == 1 else many}"

    return ", ".join(
        (
            count(len(model.activities), "activity", "activities"),
            count(len(model.exog), "exogenous event", "exogenous events"),
            count(len(model.plans), "plan", "plans"),
        )
    )


__all__ = ["register", "trace_app"]
