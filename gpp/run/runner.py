"""Running one program end to end: check it, prepare it, start a platform, execute `main()`,
evaluate `postcond()`. `gpp run` and `gpp test` are both thin layers over `run_program`."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING

from gpp import __version__
from gpp.base import diagnostics as diag
from gpp.base import signals
from gpp.base.source import Span
from gpp.base.suggest import did_you_mean
from gpp.check import CheckResult, check_program
from gpp.codes import R0008
from gpp.model.symbols import Symbol
from gpp.model.types import BOOL, NUMBER, STRING, SYMBOL, DomainType, Type
from gpp.platform import choose_platform, platform_class
from gpp.platform.base import OptionValue, Platform, PlatformConfig, PlatformError, Problem
from gpp.platform.values import ConversionError, to_value
from gpp.runtime.contract import program_interface, unfit_error
from gpp.runtime.control import RunControl
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.events import TRACE_SCHEMA_VERSION, ErrorEvent, FinishEvent, HeaderEvent, TraceEvent
from gpp.runtime.executor import Executor, RunResult, RunStatus
from gpp.runtime.trace import Recording, Trace, TraceSplit
from gpp.runtime.values import Value
from gpp.syntax.directives import directives

if TYPE_CHECKING:
    from gpp.planner.dp import Progress


class RunSetupError(Exception):
    """The run cannot start: unknown platform, a bad option, scenario or world file (a usage error)."""


@dataclass
class RunOptions:
    # The platform's name; None: chosen by the program's directives (`// world:` selects the sim).
    platform: str | None = None
    # The platform's options (`--platform-opt key=value`), validated by the platform.
    platform_options: Mapping[str, OptionValue] = field(default_factory=dict)
    # The run's bounds (SEMANTICS §4): `timeout` in wall-clock seconds (`--timeout`),
    # `time_limit` in seconds of platform time (`--time-limit`, no default).
    timeout: float | None = None
    time_limit: float | None = None
    # Values of the entry procedure's parameters (`--arg name=value`), as text or as values.
    args: Mapping[str, object] = field(default_factory=dict)
    # The platform's own command-line arguments (`--ros-args ...` for ros2; its parameters can
    # give the entry procedure's).
    platform_arguments: tuple[str, ...] | None = None
    trace: Path | None = None
    # When the trace file goes on in a new part (`--trace-max-size`, `--trace-max-time`).
    trace_split: TraceSplit | None = None
    # A `step` record before each transition (`--trace-steps`): the trace replays step by step.
    trace_steps: bool = False
    # Keep every event of the run in `RunOutcome.recording` (for tests and tools: its memory
    # grows with the run; `gpp run` keeps none).
    record: bool = False
    entry: str = "main"
    # The project's settings for checking the program: include folders, lints turned off.
    include_dirs: Sequence[Path] = ()
    allow: Sequence[str] = ()
    # How `search` looks for an execution: gpp.planner.search.STRATEGIES.
    search_strategy: str = "depth-first"
    # Told now and then how a long `solve` is getting on (the run view shows it).
    progress: Callable[[Progress], None] | None = None
    # Told the platform's clock once the platform exists (the live view shows it between events).
    clock: Callable[[Callable[[], float]], None] | None = None
    # A debugger or the operator console: holds, steps and stops the run (gpp.runtime.control).
    control: RunControl | None = None


@dataclass
class RunOutcome:
    path: Path
    check: CheckResult
    result: RunResult | None = None
    trace: Trace | None = None
    # Every event of the run, when RunOptions.record asked for them.
    recording: Recording | None = None
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    platform: str = ""

    @property
    def postcond(self) -> bool | None:
        return self.result.postcond if self.result else None

    @property
    def ok(self) -> bool:
        """The program checked, ran to its end, and its `postcond()` (if any) holds."""
        if self.check.errors or self.result is None:
            return False
        return self.result.status is RunStatus.FINISHED and self.result.postcond is not False

    @property
    def exit_code(self) -> int:
        return 0 if self.ok else 1


def program_directives(check: CheckResult, path: Path) -> dict[str, str]:
    """The `// key: value` directives of the checked program (from the text that was checked)."""
    root = check.loaded.file(path.resolve()) or (check.loaded.files[-1] if check.loaded.files else None)
    return directives(root.source.text) if root is not None else {}


def platform_for(name: str | None, check: CheckResult, path: Path) -> str:
    """The platform a checked program runs on: `name` when given, else the one its directives
    choose (`// world:` selects the sim)."""
    return name if name is not None else choose_platform(program_directives(check, path))


def make_platform(options: RunOptions, check: CheckResult, path: Path) -> Platform:
    """The platform for a run of the checked program at `path`; RunSetupError when it cannot be
    created (unknown platform or option, unusable scenario or world file)."""
    try:
        cls = platform_class(platform_for(options.platform, check, path))
        config = PlatformConfig(
            path, program_directives(check, path), options.platform_options, options.platform_arguments or ()
        )
        return cls.create(config)
    except PlatformError as e:
        raise RunSetupError(str(e)) from None


def run_program(
    path: Path,
    options: RunOptions,
    listeners: list[Callable[[TraceEvent], None]] | None = None,
    checked: CheckResult | None = None,
) -> RunOutcome:
    """Check and run one program (`checked`: the result of checking it already). Raises OSError
    for an unreadable file and RunSetupError when the platform cannot be set up; everything
    about the program itself is in the outcome."""
    if checked is None:
        checked = check_program(path, allow=options.allow, include_dirs=options.include_dirs)
    check = checked
    outcome = RunOutcome(path, check, diagnostics=list(check.diagnostics))
    if check.errors:
        return outcome
    if check.model.main is None:
        outcome.diagnostics.append(diag.error(R0008.no_main(), check.loaded.files[-1].program.span))
        return outcome
    procedure = check.model.globals[options.entry]
    if options.platform_arguments is None:
        entry_args = entry_arguments(procedure, options.args)  # before the platform starts
    platform = make_platform(options, check, path)
    outcome.platform = platform.name
    if options.clock is not None:
        options.clock(platform.now)
    trace: Trace | None = None
    try:
        if options.platform_arguments is not None:
            entry_args = entry_arguments(procedure, options.args, platform.entry_arguments())
        header = _header(path, platform)
        if options.record:
            outcome.recording = Recording()
            listeners = [outcome.recording, *(listeners or [])]
        platform_listener = platform.trace_listener()
        if platform_listener is not None:
            listeners = [*(listeners or []), platform_listener]
        trace = outcome.trace = Trace(options.trace, listeners, options.trace_split)
        trace.emit(header)
        from gpp.planner.policy import PolicyPlanner
        from gpp.runtime.compiled import CompiledProgram

        program = CompiledProgram(check.model)
        executor = Executor(
            program,
            platform,
            trace,
            options.time_limit,
            options.entry,
            planner=PolicyPlanner(options.search_strategy, options.progress),
            timeout=options.timeout,
            entry_args=entry_args,
            control=options.control,
            trace_steps=options.trace_steps,
        )
        problems = platform.attach(program_interface(program))
        if problems:
            fallback = check.model.main.span or check.loaded.files[-1].program.span
            unfit = [_unfit(p, platform.name, fallback) for p in problems]
            outcome.diagnostics.extend(unfit)
            for problem in unfit:
                trace.emit(
                    ErrorEvent(t=platform.now(), code=problem.code, message=problem.message, at=str(problem.span))
                )
            trace.emit(
                FinishEvent(t=platform.now(), status=RunStatus.ERROR.value, actions=0, failures=0, exog_events=0)
            )
            return outcome
        result = executor.run()
        outcome.result = result
        outcome.diagnostics.extend(result.diagnostics)
        if result.status is RunStatus.FINISHED:
            try:
                executor.evaluate_postcond()
            except GppRuntimeError as e:
                postcond = check.model.globals.get("postcond")
                d = e.diagnostic(postcond.span if postcond is not None else None)
                if d is not None:
                    outcome.diagnostics.append(d)
                result.postcond = False
        return outcome
    except KeyboardInterrupt as e:  # outside the executor's loop, which finishes the trace itself
        if trace is not None:
            _finish_interrupted(trace, header, platform, e)
        raise
    finally:
        platform.close()
        if trace is not None:
            trace.close()


def _finish_interrupted(trace: Trace, header: HeaderEvent, platform: Platform, e: KeyboardInterrupt) -> None:
    """End the trace of a run interrupted before or after the executor ran: the header if it is
    missing, then an `error` and the one `finish` record, unless the executor wrote them."""
    if trace.finished:
        return
    if not trace.written:
        trace.emit(header)
    now = platform.now()
    trace.emit(ErrorEvent(t=now, message=signals.message(e)))
    trace.emit(FinishEvent(t=now, status=RunStatus.INTERRUPTED.value, actions=0, failures=0, exog_events=0))


def entry_arguments(
    procedure: Symbol, given: Mapping[str, object], from_platform: Mapping[str, tuple[object, str]] | None = None
) -> tuple[Value, ...]:
    """The values of `procedure`'s parameters from `--arg name=value` pairs and those the
    platform was given (`from_platform`: name -> (value, how it was given), e.g. ROS
    parameters): text is read as a golog++ literal of the parameter's type (a number,
    `true`/`false`, a symbol, a string as it is, a list or compound as JSON). RunSetupError
    for a missing, unknown, ill-typed one, or one given both ways."""
    params = {p.name: p for p in procedure.params}
    how = {name: f"--arg {name}" for name in given}
    merged = dict(given)
    for name, (value, said) in (from_platform or {}).items():
        if name in merged:
            raise RunSetupError(f"`{name}` of `{procedure.name}` is given twice: by --arg {name}=... and by {said}")
        merged[name], how[name] = value, said
    given = merged
    for name in given:
        if name not in params:
            hint = did_you_mean(name, params)
            takes = ", ".join(params) if params else "no parameters"
            said = "" if how[name].startswith("--arg") else f"{how[name]}: "
            raise RunSetupError(
                f"{said}`{procedure.name}` has no parameter `{name}`"
                + (f"; {hint}" if hint else "")
                + f" (it takes {takes})"
            )
    values: list[Value] = []
    for name, param in params.items():
        if name not in given:
            shown = ", ".join(f"{p.type} {p.name}" for p in procedure.params)
            raise RunSetupError(
                f"`{procedure.name}({shown})` needs a value for `{name}`: give it with --arg {name}=VALUE"
                + (f" or with -p {name}:=VALUE after --ros-args" if from_platform is not None else "")
            )
        raw = given[name]
        assert param.type is not None
        try:
            values.append(to_value(_literal(raw, param.type) if isinstance(raw, str) else raw, param.type))
        except ConversionError as e:
            raise RunSetupError(f"{how[name]}: {e}") from None
    return tuple(values)


def value_from_text(text: str, t: Type) -> Value:
    """Text a user typed (`--arg`, a form of the operator console) as a value of type `t`
    (ConversionError when it is not one)."""
    return to_value(_literal(text, t), t)


def _literal(text: str, t: Type) -> object:
    """Text from the command line as plain data for `to_value`."""
    element = t.element if isinstance(t, DomainType) else t
    if element is STRING:
        return text
    if element is SYMBOL:
        return text.strip()
    if element is NUMBER:
        try:
            number = float(text)
        except ValueError:
            return text
        return int(number) if number.is_integer() and "." not in text and "e" not in text.lower() else number
    if element is BOOL:
        return {"true": True, "false": False}.get(text.strip(), text)
    try:
        return json.loads(text)
    except ValueError:
        return text


def _header(path: Path, platform: Platform) -> HeaderEvent:
    """The first record of the trace: what was run, on what, when."""
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        digest = ""
    facts = platform.facts()
    return HeaderEvent(
        t=platform.now(),
        schema_version=TRACE_SCHEMA_VERSION,
        gpp_version=__version__,
        program=str(path),
        program_sha256=digest,
        platform=platform.name,
        world=facts.world,
        scenario=facts.scenario,
        seed=facts.seed,
        node=facts.node,
        started=datetime.now(UTC).astimezone().isoformat(timespec="seconds"),
    )


def _unfit(problem: Problem, platform: str, fallback: Span) -> diag.Diagnostic:
    """A problem found when the platform attached, as an error at the mapping (or data file
    entry) it is about."""
    found = unfit_error(problem, platform, fallback).diagnostic()
    assert found is not None  # it has a span: the fallback's at least
    return found
