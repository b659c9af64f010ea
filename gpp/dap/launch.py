"""`launch`: a backend for the launch request's arguments. With `"program"` a live run
(gpp.dap.live); with `"trace"`, a recorded run to replay (the trace backend, when present).

Arguments of a live run: `program` (a .gpp file), `platform` (dummy, sim, ros2; the program's
directives choose when it is left out), `platformOptions` (name -> value, as `-o name=value`),
`args` (the entry procedure's parameters, name -> value), `stopOnEntry`, `timeLimit`
(seconds of platform time), `timeout` (wall-clock seconds), `traceFile` (the run's trace, as
`gpp run --trace`), `cwd` (relative paths start there)."""

from __future__ import annotations

import json
from importlib import import_module
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gpp.dap.protocol import DapError, Message

if TYPE_CHECKING:
    from gpp.dap.backend import Host, SessionBackend

# Arguments a live run takes (others an editor adds, such as `type`, `request`, `name`, `__*`,
# are left alone; unknown ones that look like ours are refused).
LIVE_ARGUMENTS = {
    "program",
    "platform",
    "platformOptions",
    "args",
    "stopOnEntry",
    "timeLimit",
    "timeout",
    "traceFile",
    "cwd",
    "noDebug",
}
EDITOR_ARGUMENTS = {"type", "request", "name", "console", "internalConsoleOptions", "presentation"}

# The module of the trace backend (replaying a recorded run): `make_trace_backend(args, server)`.
TRACE_BACKEND = "gpp.dap.replay"


def make_backend(args: Message, server: Host) -> SessionBackend:
    if "trace" in args and "program" not in args:
        try:
            module = import_module(TRACE_BACKEND)
        except ImportError:
            raise DapError("launching a recorded run (`trace`) is not supported by this gpp") from None
        backend: SessionBackend = module.make_trace_backend(args, server)
        return backend
    if "trace" in args:
        raise DapError("launch takes either `program` (a live run) or `trace` (a recorded run), not both")
    return make_live_backend(args, server)


def _unknown(args: Message, known: set[str]) -> None:
    for name in args:
        if name in known or name in EDITOR_ARGUMENTS or name.startswith("__"):
            continue
        from gpp.base.suggest import did_you_mean

        hint = did_you_mean(name, sorted(known))
        raise DapError(f"launch has no argument `{name}`" + (f"; {hint}" if hint else ""))


def _path(args: Message, name: str, cwd: Path) -> Path | None:
    value = args.get(name)
    if value is None:
        return None
    if not isinstance(value, str) or not value.strip():
        raise DapError(f"launch's `{name}` is a file path, not {json.dumps(value)}")
    path = Path(value).expanduser()
    return path if path.is_absolute() else cwd / path


def _number(args: Message, name: str) -> float | None:
    value = args.get(name)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
        raise DapError(f"launch's `{name}` is a number of seconds above 0, not {json.dumps(value)}")
    return float(value)


def _mapping(args: Message, name: str) -> dict[str, Any]:
    value = args.get(name, {})
    if not isinstance(value, dict):
        raise DapError(f"launch's `{name}` is an object of names and values, not {json.dumps(value)}")
    return value


def make_live_backend(args: Message, server: Host) -> SessionBackend:
    from gpp.check import check_program
    from gpp.dap.live import LiveBackend, check_errors
    from gpp.platform import available
    from gpp.platform.base import PlatformError
    from gpp.run.runner import RunOptions, RunSetupError, run_program

    _unknown(args, LIVE_ARGUMENTS)
    cwd_text = args.get("cwd")
    cwd = Path(cwd_text) if isinstance(cwd_text, str) and cwd_text else Path.cwd()
    program = _path(args, "program", cwd)
    if program is None:
        raise DapError("launch needs `program` (the .gpp file to run) or `trace` (a recorded run)")
    if not program.is_file():
        raise DapError(f"launch's `program`: no such file {program}")
    platform = args.get("platform")
    if platform is not None and (not isinstance(platform, str) or platform not in available()):
        from gpp.base.suggest import did_you_mean

        hint = did_you_mean(str(platform), available())
        raise DapError(
            f"launch's `platform`: unknown platform `{platform}`"
            + (f"; {hint}" if hint else f" (there are {', '.join(available())})")
        )
    options: dict[str, Any] = {}
    for key, value in _mapping(args, "platformOptions").items():
        if not isinstance(value, str | int | float | bool):
            raise DapError(f"launch's `platformOptions.{key}` is a string, number or true/false")
        # A file an option names is found from `cwd`, as `gpp run -o` finds it from the shell's.
        named = cwd / value if isinstance(value, str) and value and not Path(value).is_absolute() else None
        options[key] = str(named) if named is not None and named.exists() else value
    try:
        check = check_program(program)
    except OSError as e:
        raise DapError(f"cannot read {program}: {e.strerror}") from None
    if check.errors:
        raise DapError(check_errors(check.diagnostics))
    if check.model.main is None:
        raise DapError("the program has no `procedure main()` to run")
    trace = _path(args, "traceFile", cwd)
    run_options = RunOptions(
        platform=platform,
        platform_options=options,
        args=_mapping(args, "args"),
        time_limit=_number(args, "timeLimit"),
        timeout=_number(args, "timeout"),
        trace=trace,
        # A session's trace replays statement by statement (gpp.dap.replay).
        trace_steps=trace is not None,
    )
    from gpp.run.runner import entry_arguments

    try:
        entry_arguments(check.model.globals[run_options.entry], run_options.args)
    except RunSetupError as e:
        raise DapError(f"launch's `args`: {e}") from None

    def run() -> int:
        try:
            outcome = run_program(program, run_options, checked=check)
        except (RunSetupError, PlatformError) as e:
            backend.setup_error = str(e)
            return 2
        except OSError as e:
            backend.setup_error = f"cannot read {program}: {e.strerror}"
            return 2
        for d in outcome.diagnostics:
            if d.is_error:
                where = f"{d.span}: " if d.span is not None else ""
                server.output(f"{where}{d.message}\n", "stderr", d.span)
        status = outcome.result.status.value if outcome.result is not None else "not run"
        server.output(f"{program.name}: {status}\n", "console")
        return outcome.exit_code

    backend = LiveBackend(server, server.breakpoints, check, run)
    run_options.control = backend
    no_debug = args.get("noDebug", False)
    if not isinstance(no_debug, bool):
        raise DapError(f"launch's `noDebug` is true or false, not {json.dumps(no_debug)}")
    backend.no_debug = no_debug
    backend.launch()
    if backend.setup_error is not None and backend.executor is None:
        raise DapError(f"the run cannot start: {backend.setup_error}")
    if backend.executor is None:
        raise DapError("the run ended before its first step (see the output)")
    return backend
