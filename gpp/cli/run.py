"""`gpp run` and `gpp test`: the commands users run most. Registered on the app by gpp.cli.app.

The flags of the platforms' options (`--world`, `--scenario`, ...) are not named here: they
are built from the declarations in gpp.platform.options, and a flag that the chosen platform
does not take is a usage error. Everything heavy (the interpreter, rich, the platforms) is
imported inside the commands.
"""

from __future__ import annotations

import dataclasses
import inspect
import sys
import typing
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from gpp.cli.common import console_access, usage_error

if TYPE_CHECKING:
    from gpp.check import CheckResult
    from gpp.console.access import Access
    from gpp.console.server import ConsoleServer
    from gpp.run.runner import RunOptions
    from gpp.run.testing import TestCase
    from gpp.run.view import RunView
    from gpp.runtime.trace import TraceListener, TraceSplit

PlatformOption = Annotated[
    str | None,
    typer.Option(
        "--platform",
        "-p",
        help="Where to run: dummy (virtual time), sim (physics), or a plugin "
        "(default: sim for programs with a `// world:` line, else dummy).",
    ),
]
PlatformOptOption = Annotated[
    list[str] | None,
    typer.Option(
        "--platform-opt",
        "-o",
        metavar="KEY=VALUE",
        help="An option of the platform (repeatable); an unknown key is an error that lists the platform's options.",
    ),
]
TimeoutOption = Annotated[
    float | None,
    typer.Option(
        "--timeout",
        metavar="SECONDS",
        help="Stop a run after this many seconds of wall-clock time, however far its platform's clock got "
        "(default: the project's `timeout`, else none).",
    ),
]
TimeLimitOption = Annotated[
    float | None,
    typer.Option(
        "--time-limit",
        metavar="SECONDS",
        help="Stop a run when its platform's clock reaches this many seconds (virtual or real; "
        "default: the project's `time_limit`, else none).",
    ),
]

Command = TypeVar("Command", bound=Callable[..., None])


def platform_flags(*, single_run: bool) -> list[inspect.Parameter]:
    """The flags of the built-in platforms' options that have one (gpp.platform.options), as
    keyword parameters of a typer command: one per option name, with the help of each platform
    that takes it. `single_run`: also those only `gpp run` offers."""
    from gpp.platform.options import BUILTIN, flag_of

    found: dict[str, tuple[object, list[str]]] = {}
    for platform, declared in BUILTIN.items():
        hints = typing.get_type_hints(declared.options)
        for f in dataclasses.fields(declared.options):
            flag = flag_of(f)
            if flag is None or (flag.single_run and not single_run):
                continue
            kind, helps = found.setdefault(f.name, (hints[f.name], []))
            if kind != hints[f.name]:
                raise TypeError(f"option `{f.name}` has two types: {kind} and {hints[f.name]}")
            helps.append(f"{platform.capitalize()} platform: {f.metadata['help']}.")
    return [
        inspect.Parameter(
            name,
            inspect.Parameter.KEYWORD_ONLY,
            default=False if kind is bool else None,
            annotation=Annotated[
                kind,
                typer.Option(f"--{name}", help=" ".join(helps), show_default=False, rich_help_panel="Platform flags"),
            ],
        )
        for name, (kind, helps) in found.items()
    ]


_OWN_SIGNATURES: dict[Callable[..., Any], inspect.Signature] = {}


def with_platform_flags(*, single_run: bool) -> Callable[[Command], Command]:
    """A command whose `**flags` are the platform flags (`platform_flags`) for typer."""

    def add(command: Command) -> Command:
        # The command's own signature, also when an app was built before in this process.
        signature = _OWN_SIGNATURES.setdefault(command, inspect.signature(command, eval_str=True))
        fixed = [p for p in signature.parameters.values() if p.kind is not inspect.Parameter.VAR_KEYWORD]
        flags = platform_flags(single_run=single_run)
        clash = {p.name for p in fixed} & {p.name for p in flags}
        if clash:
            raise TypeError(f"{command.__name__}: platform flags named like its own options: {sorted(clash)}")
        command.__signature__ = signature.replace(parameters=[*fixed, *flags])  # type: ignore[attr-defined]
        return command

    return add


def refuse_overwriting_inputs(
    trace: Path | None,
    platform: str,
    options: dict[str, str | int | float | bool | Path],
    checked: CheckResult,
    program: Path,
) -> None:
    """A file the run would write (the trace, a platform's outputs such as `--record`) that is
    one the run reads (the program, a file it includes, a file a directive or an option names)
    is a usage error: a typo must not overwrite the program with its trace."""
    from gpp.base.paths import overwritten_input
    from gpp.platform import options_of
    from gpp.platform.base import PlatformError
    from gpp.platform.options import is_output
    from gpp.run.runner import program_directives

    try:
        outputs = {f.name for f in dataclasses.fields(options_of(platform)) if is_output(f)}
    except PlatformError:
        outputs = set()  # an unknown platform: the run says so
    inputs: list[tuple[Path, str]] = [(program, "the program")]
    inputs += [(f.path, "a file the program includes") for f in checked.loaded.files]
    inputs += [
        (program.parent / value, f"the file of its `// {key}:` line")
        for key, value in program_directives(checked, program).items()
    ]
    inputs += [
        (Path(str(value)), f"the file of option `{name}`")
        for name, value in options.items()
        if name not in outputs and isinstance(value, str | Path)
    ]
    written = [("--trace", trace)] if trace is not None else []
    written += [(f"option `{name}`", Path(str(options[name]))) for name in sorted(outputs & options.keys())]
    for what, path in written:
        problem = overwritten_input(path, inputs)
        if problem is not None:
            usage_error(f"{what}: {problem}; writing there would overwrite it")


def given_flags(flags: dict[str, Any]) -> dict[str, str | int | float | bool | Path]:
    """The platform flags given on the command line (not None, not False)."""
    return {name: value for name, value in flags.items() if value is not None and value is not False}


def check_flags(given: dict[str, Any], platform: str) -> None:
    """A flag for an option that `platform` does not take is a usage error (never ignored)."""
    from gpp.platform import options_of
    from gpp.platform.base import PlatformError
    from gpp.platform.options import BUILTIN

    try:
        takes = {f.name for f in dataclasses.fields(options_of(platform))}
    except PlatformError:
        return  # an unknown or missing platform: the run says so
    for name in given:
        if name not in takes:
            owners = [p for p, d in BUILTIN.items() if name in {f.name for f in dataclasses.fields(d.options)}]
            usage_error(f"--{name} is an option of platform {' and '.join(owners)}, not of `{platform}`")


def key_values(pairs: list[str] | None, option: str) -> dict[str, str]:
    """`KEY=VALUE` pairs of a repeatable option; a malformed pair or a key given twice is a
    usage error."""
    found: dict[str, str] = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        key = key.strip()
        if not sep or not key:
            usage_error(f"{option} takes KEY=VALUE, not {pair!r}")
        if key in found:
            usage_error(f"{option} `{key}` is given twice")
        found[key] = value.strip()
    return found


def platform_options(
    pairs: list[str] | None, flags: dict[str, str | int | float | bool | Path]
) -> dict[str, str | int | float | bool | Path]:
    """The platform options from `--platform-opt KEY=VALUE` pairs and the flags given. A
    malformed pair, or a key given twice, is a usage error."""
    options: dict[str, str | int | float | bool | Path] = dict(key_values(pairs, "--platform-opt"))
    for name, value in flags.items():
        if name in options:
            usage_error(f"platform option `{name}` is given twice (--{name} and --platform-opt {name}=...)")
        options[name] = value
    return options


# `gpp test` bounds each program's wall-clock time by this many seconds unless --timeout is given,
# so that a suite with an endless loop finishes.
DEFAULT_TEST_TIMEOUT = 120.0


def check_timeout(timeout: float | None, flag: str = "--timeout") -> None:
    """A bound (`--timeout`, `--time-limit`) must be a positive number of seconds (a usage error
    otherwise)."""
    import math

    if timeout is not None and not (timeout > 0 and math.isfinite(timeout)):
        usage_error(f"{flag} must be a number of seconds greater than 0, not {timeout:g}")


_SIZE_UNITS: dict[str, float] = {
    "": 1,
    "B": 1,
    "KB": 10**3,
    "MB": 10**6,
    "GB": 10**9,
    "KIB": 2**10,
    "MIB": 2**20,
    "GIB": 2**30,
}
_TIME_UNITS: dict[str, float] = {"": 1.0, "S": 1.0, "M": 60.0, "MIN": 60.0, "H": 3600.0, "D": 86400.0}


def trace_split(trace: Path | None, max_size: str | None, max_time: str | None) -> TraceSplit | None:
    """The `--trace-max-size`/`--trace-max-time` split (a usage error without --trace, or for
    a size or time that is not one)."""
    from gpp.runtime.trace import TraceSplit

    if max_size is None and max_time is None:
        return None
    if trace is None:
        given = "--trace-max-size" if max_size is not None else "--trace-max-time"
        usage_error(f"{given} splits the trace file: it needs --trace FILE")
    size = _amount(max_size, _SIZE_UNITS, "--trace-max-size", "a size such as 10MB, 500KB or 4096")
    seconds = _amount(max_time, _TIME_UNITS, "--trace-max-time", "a time such as 90s, 30m or 2h")
    return TraceSplit(int(size) if size is not None else None, seconds)


def _amount(text: str | None, units: dict[str, float], option: str, expected: str) -> float | None:
    """`text` as a number times its unit (a usage error unless it is a positive one)."""
    import math
    import re

    if text is None:
        return None
    found = re.fullmatch(r"\s*([0-9]+(?:\.[0-9]*)?|\.[0-9]+)\s*([A-Za-z]*)\s*", text)
    unit = units.get(found.group(2).upper()) if found else None
    value = float(found.group(1)) * unit if found and unit is not None else math.nan
    if not (value > 0 and math.isfinite(value)):
        usage_error(f"{option} takes {expected}, not {text!r}")
    return value


def register(app: typer.Typer) -> None:
    app.command(name="run")(with_platform_flags(single_run=True)(run))
    app.command(name="test")(with_platform_flags(single_run=False)(test_command))


def run(
    ctx: typer.Context,
    file: Annotated[Path, typer.Argument(metavar="FILE", help="The agent to run; its `main()` is executed.")],
    platform: PlatformOption = None,
    platform_opt: PlatformOptOption = None,
    arg: Annotated[
        list[str] | None,
        typer.Option(
            "--arg",
            metavar="NAME=VALUE",
            help="A value for a parameter of `main` (repeatable): a number, true/false, a symbol, text, "
            "or a list or compound as JSON.",
        ),
    ] = None,
    trace: Annotated[Path | None, typer.Option("--trace", help="Write the run's trace (JSON lines) here.")] = None,
    trace_max_size: Annotated[
        str | None,
        typer.Option(
            "--trace-max-size",
            metavar="SIZE",
            help="Go on in a new part of the trace (run.1.jsonl, ...) once a part holds SIZE (10MB, 500KB, bytes).",
        ),
    ] = None,
    trace_max_time: Annotated[
        str | None,
        typer.Option(
            "--trace-max-time",
            metavar="TIME",
            help="Go on in a new part of the trace once a part covers TIME of platform time (90s, 30m, 2h).",
        ),
    ] = None,
    trace_steps: Annotated[
        bool,
        typer.Option(
            "--trace-steps",
            help="Write a `step` record before each transition of the program, so that `gpp dap` replays "
            "the trace statement by statement.",
        ),
    ] = False,
    timeout: TimeoutOption = None,
    time_limit: TimeLimitOption = None,
    profile: Annotated[bool, typer.Option("--profile", help="Print a table of every `solve`/`search`.")] = False,
    search_strategy: Annotated[
        str,
        typer.Option(
            "--search-strategy",
            metavar="STRATEGY",
            help="How `search` looks for an execution: depth-first (the first in textual order) or "
            "iterative-deepening (a shortest one).",
        ),
    ] = "depth-first",
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No live view or event lines; only the summary.")
    ] = False,
    console: Annotated[
        str | None,
        typer.Option(
            "--console",
            metavar="[HOST:PORT]",
            help="Serve the operator console, a live page of the run with Start, Pause, Stop and events to "
            "send (default 127.0.0.1:8765; any other address than loopback needs a token).",
            rich_help_panel="Operator console",
        ),
    ] = None,
    console_wait: Annotated[
        bool,
        typer.Option(
            "--console-wait",
            help="Wait for Start on the console page before `main` begins (actions and events can be "
            "triggered before).",
            rich_help_panel="Operator console",
        ),
    ] = False,
    console_join: Annotated[
        str | None,
        typer.Option(
            "--console-join",
            metavar="URL",
            help="Show this run on the page of `gpp console` at URL too (several agents on one page).",
            rich_help_panel="Operator console",
        ),
    ] = None,
    console_token: Annotated[
        str | None,
        typer.Option(
            "--console-token",
            metavar="TOKEN",
            help="The token the console asks for (default: none on loopback, else a new one, printed).",
            rich_help_panel="Operator console",
        ),
    ] = None,
    **flags: Any,
) -> None:
    """Check FILE, run its `main()` on a platform, and evaluate `postcond()` if it has one.

    On platform ros2, the ROS arguments follow `--ros-args` (up to `--` or the end), as for any
    ROS node: `--ros-args -r __ns:=/robot1 -r navigate:=move_base -p n:=3 --params-file p.yaml`.

    Exit code 0 when the run finished (and `postcond()` holds), 1 otherwise, 130 on Ctrl-C,
    143 on SIGTERM."""
    from gpp.base import signals
    from gpp.cli.common import (
        EXIT_OK,
        EXIT_PROBLEMS,
        ColorMode,
        OutputFormat,
        emit_diagnostics,
        load_config,
        require_readable,
        use_color,
    )
    from gpp.run.runner import RunOptions, RunSetupError, platform_for, run_program

    require_readable(file)
    check_timeout(timeout)
    check_timeout(time_limit, "--time-limit")
    access = console_access(console, console_wait, console_token)
    if console_join is not None and access is None:
        usage_error("--console-join shows the run's console on another page: it needs --console")
    from gpp.planner.search import STRATEGIES

    if search_strategy not in STRATEGIES:
        usage_error(f"--search-strategy must be one of {', '.join(STRATEGIES)}, not `{search_strategy}`")
    config = load_config(file)
    if timeout is None:
        timeout = config.run_timeout
    if time_limit is None:
        time_limit = config.run_time_limit
    split = trace_split(trace, trace_max_size, trace_max_time)
    if trace_steps and trace is None:
        usage_error("--trace-steps adds records to the trace file: it needs --trace FILE")
    if trace is not None:
        from gpp.base.paths import output_problem

        problem = output_problem(trace)
        if problem is not None:
            usage_error(f"--trace: {problem}")
    from gpp.check import check_program

    allow = config.disabled_lints()
    checked = check_program(file, allow=allow, include_dirs=config.include)
    shown = list(checked.diagnostics)
    if shown:
        emit_diagnostics(shown, OutputFormat.TEXT, ColorMode.AUTO, summary=bool(checked.errors))
    if checked.errors:
        raise typer.Exit(EXIT_PROBLEMS)
    chosen = platform_for(platform or config.run_platform, checked, file)
    ros_arguments = ctx.obj if isinstance(ctx.obj, tuple) else None  # gpp.cli.main took them out
    if ros_arguments is not None and chosen != "ros2":
        usage_error(f"--ros-args: ROS arguments are for platform ros2, and this run is on `{chosen}`")
    given = given_flags(flags)
    check_flags(given, chosen)
    if "world" not in given:
        world = _configured_world(config.run_world, chosen, platform_opt, checked, file)
        given.update({"world": world} if world is not None else {})
    chosen_options = platform_options(platform_opt, given)
    refuse_overwriting_inputs(trace, chosen, chosen_options, checked, file)
    options = RunOptions(
        platform=chosen,
        platform_options=chosen_options,
        timeout=timeout,
        time_limit=time_limit,
        trace=trace,
        trace_split=split,
        trace_steps=trace_steps,
        args=key_values(arg, "--arg"),
        platform_arguments=ros_arguments,
        include_dirs=config.include,
        allow=allow,
        search_strategy=search_strategy,
    )
    view = _view(file, chosen, quiet, use_color(ColorMode.AUTO))
    options.progress = view.progress
    options.clock = view.watch_clock
    from gpp.runtime.events import ErrorEvent, PlanEvent, ReplanEvent
    from gpp.runtime.trace import Recording, TraceWriteError

    # The planner profile needs the plans and the errors that stopped planning, nothing else.
    plans = Recording(kinds=(PlanEvent, ReplanEvent, ErrorEvent)) if profile else None
    listeners: list[TraceListener] = [*([view] if view.shows else []), *([plans] if plans is not None else [])]
    served = open_console(access, checked, console_wait, options, listeners) if access is not None else None
    if served is not None and console_join is not None:
        from gpp.console.hub import join

        problem = join(console_join, served.url)
        if problem is not None:
            served.close()
            usage_error(f"--console-join: {problem}")
    try:
        with view:
            outcome = run_program(file, options, listeners or None, checked=checked)
    except RunSetupError as e:
        usage_error(str(e))
    except TraceWriteError as e:  # the run stopped, its activities cancelled
        print(f"error: {e}", file=sys.stderr)
        raise typer.Exit(EXIT_PROBLEMS) from None
    finally:
        if served is not None:
            served.close()
    runtime = [d for d in outcome.diagnostics if d not in shown]
    if runtime:
        emit_diagnostics(runtime, OutputFormat.TEXT, ColorMode.AUTO, summary=False)
    if plans is not None and outcome.trace is not None:
        from rich.console import Console

        from gpp.planner.profile import render_profile

        # Off a terminal rich would assume 80 columns; the table needs more.
        width = None if sys.stdout.isatty() else 140
        render_profile(plans.records, Console(file=sys.stdout, highlight=False, width=width))
    from gpp.run.view import summary_lines

    print("\n".join(summary_lines(outcome)))
    if outcome.result is not None and outcome.result.status.value == "interrupted":
        raise typer.Exit(signals.EXIT_TERMINATED if outcome.result.terminated else signals.EXIT_INTERRUPTED)
    raise typer.Exit(EXIT_OK if outcome.ok else EXIT_PROBLEMS)


def open_console(
    access: Access, checked: CheckResult, wait: bool, options: RunOptions, listeners: list[TraceListener]
) -> ConsoleServer:
    """Serve the console for this run (its state a listener of the run, its control the
    run's), and say where."""
    from gpp.console.access import AccessError
    from gpp.console.control import ConsoleControl
    from gpp.console.server import serve
    from gpp.console.state import ConsoleState

    state = ConsoleState()
    control = ConsoleControl(state, checked.model, wait)
    try:
        server = serve(state, control, access)
    except AccessError as e:
        usage_error(f"--console: {e}")
    options.control = control
    listeners.extend(state.listeners())
    print(f"console: {server.url}", file=sys.stderr, flush=True)
    if not access.address.loopback:
        print(
            f"warning: the console listens on {access.address.host}, beyond this machine, without TLS: its token "
            "and everything it shows cross the network in plain text (use a network you trust, or a TLS proxy)",
            file=sys.stderr,
            flush=True,
        )
    if wait:
        print("console: the run waits for Start on the page", file=sys.stderr, flush=True)
    return server


def test_command(
    paths: Annotated[
        list[Path] | None,
        typer.Argument(
            metavar="PATH",
            help="Programs or folders to run (default: the project's test paths, or tests/programs).",
        ),
    ] = None,
    platform: PlatformOption = None,
    platform_opt: PlatformOptOption = None,
    timeout: Annotated[
        float | None,
        typer.Option(
            "--timeout",
            metavar="SECONDS",
            help="Stop each program after this many seconds of wall-clock time "
            f"(default: the project's test `timeout`, else {DEFAULT_TEST_TIMEOUT:g} s).",
        ),
    ] = None,
    time_limit: Annotated[
        float | None,
        typer.Option(
            "--time-limit",
            metavar="SECONDS",
            help="Stop each program when its platform's clock reaches this many seconds "
            "(default: the project's test `time_limit`, else none).",
        ),
    ] = None,
    keyword: Annotated[
        str | None,
        typer.Option(
            "-k", metavar="EXPRESSION", help="Run only programs whose path matches: words, `and`, `or`, `not`, (...)."
        ),
    ] = None,
    exitfirst: Annotated[bool, typer.Option("-x", "--exitfirst", help="Stop at the first program that fails.")] = False,
    junitxml: Annotated[
        Path | None, typer.Option("--junitxml", metavar="FILE", help="Write the results as JUnit XML.")
    ] = None,
    jobs: Annotated[int, typer.Option("-j", "--jobs", metavar="N", help="Run N programs at once, in processes.")] = 1,
    **flags: Any,
) -> None:
    """Run every program's `main()` and check its `postcond()`; a table of the results.

    Exit code 0 when every program passes, 1 when one fails, 2 when misused, 5 when no program
    was selected (as pytest), 130 on Ctrl-C, 143 on SIGTERM."""
    from gpp.cli.common import EXIT_OK, EXIT_PROBLEMS, load_config
    from gpp.run.runner import RunOptions
    from gpp.run.testing import SelectionError, discover, run_all, selector

    check_timeout(timeout)
    check_timeout(time_limit, "--time-limit")
    given = given_flags(flags)
    if platform is not None:
        check_flags(given, platform)
    if jobs < 1:
        usage_error(f"-j takes a number of processes of at least 1, not {jobs}")
    from gpp.base.paths import input_problem

    config = load_config(paths[0] if paths else Path.cwd())
    targets = paths or list(config.test_paths)
    for p in targets:
        problem = input_problem(p, folder=True)
        if problem is not None:
            usage_error(problem)
    if junitxml is not None:
        from gpp.base.paths import output_problem

        problem = output_problem(junitxml)
        if problem is not None:
            usage_error(f"--junitxml: {problem}")
    files = discover([_shown(p) for p in targets])
    if keyword is not None:
        try:
            matches = selector(keyword)
        except SelectionError as e:
            usage_error(str(e))
        files = [f for f in files if matches(str(f))]
    if not files:
        where = ", ".join(f"'{p}'" for p in targets)
        print(f"no program in {where} matches -k `{keyword}`" if keyword else f"no programs to run in {where}")
        raise typer.Exit(EXIT_NO_TESTS)
    timeout = timeout if timeout is not None else config.test_timeout
    time_limit = time_limit if time_limit is not None else config.test_time_limit
    options = RunOptions(
        platform=platform,
        platform_options=platform_options(platform_opt, given),
        timeout=timeout if timeout is not None else DEFAULT_TEST_TIMEOUT,
        time_limit=time_limit,
        include_dirs=config.include,
        allow=config.disabled_lints(),
    )
    named = [_shown(p) for p in targets if not p.is_dir()]
    cases = run_all(files, options, jobs=jobs, stop_at_first_failure=exitfirst, named=named)
    _print_results(cases, platform)
    if junitxml is not None:
        from gpp.run.testing import junit_xml

        junitxml.write_text(junit_xml(cases), encoding="utf-8")
    raise typer.Exit(EXIT_PROBLEMS if any(c.failed for c in cases) else EXIT_OK)


# As pytest: no test was collected (none found, or none matches -k).
EXIT_NO_TESTS = 5


def _shown(path: Path) -> Path:
    """A path as the results show it: relative to the working directory when below it."""
    try:
        return path.resolve().relative_to(Path.cwd().resolve()) if path.is_absolute() else path
    except ValueError:
        return path


def _print_results(cases: list[TestCase], platform: str | None) -> None:
    from rich.console import Console
    from rich.table import Table

    from gpp.cli.common import ColorMode, OutputFormat, emit_diagnostics, use_color
    from gpp.run.testing import Verdict

    console = Console(file=sys.stdout, highlight=False, no_color=not use_color(ColorMode.AUTO), width=120)
    table = Table(title=f"gpp test ({platform or 'dummy, or sim for programs with a world'})", title_justify="left")
    table.add_column("program")
    table.add_column("result")
    table.add_column("time", justify="right")
    table.add_column("detail", overflow="fold")
    style = {Verdict.PASS: "green", Verdict.FAIL: "red", Verdict.ERROR: "red", Verdict.SKIP: "yellow"}
    for case in cases:
        table.add_row(
            str(case.path),
            f"[{style[case.verdict]}]{case.verdict.value}[/]",
            f"{case.seconds:.2f} s",
            case.detail,
        )
    console.print(table)
    for case in cases:
        if case.failed and case.errors:
            emit_diagnostics(list(case.errors), OutputFormat.TEXT, ColorMode.AUTO, summary=False)
    counts = {v: sum(1 for c in cases if c.verdict is v) for v in Verdict}
    print(
        f"{counts[Verdict.PASS]} passed, {counts[Verdict.FAIL] + counts[Verdict.ERROR]} failed"
        + (f", {counts[Verdict.SKIP]} skipped" if counts[Verdict.SKIP] else "")
    )


def _configured_world(
    world: str | None, platform: str, platform_opt: list[str] | None, checked: CheckResult, file: Path
) -> str | None:
    """The configuration's `run.world` for a run on the sim, unless `-o world=...` or the
    program's `// world:` line names one (the program's own choice comes first)."""
    from gpp.run.runner import program_directives

    if world is None or platform != "sim" or "world" in key_values(platform_opt, "--platform-opt"):
        return None
    return None if "world" in program_directives(checked, file) else world


def _view(file: Path, platform: str, quiet: bool, color: bool) -> RunView:
    from gpp.run.view import LiveView, NoView, PlainView

    if quiet:
        return NoView()
    if color and sys.stdout.isatty():
        from rich.console import Console

        return LiveView(Console(file=sys.stdout), f"{file} on {platform}")
    return PlainView(sys.stdout)
