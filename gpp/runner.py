"""Running one program end to end: check it, prepare it, start a platform, execute `main()`,
evaluate `postcond()`. `gpp run` and `gpp test` are both thin layers over `run_program`."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from gpp import diagnostics as diag
from gpp.check import CheckResult, check_program
from gpp.platform import platform_class
from gpp.platform.base import Platform, PlatformError
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.executor import Executor, RunResult, RunStatus
from gpp.runtime.trace import Trace, TraceRecord


class RunSetupError(Exception):
    """The run cannot start: unknown platform, bad scenario or world file (a usage error)."""


@dataclass
class RunOptions:
    platform: str = "dummy"
    scenario: Path | None = None
    # None: not given (the dummy platform uses 1, the sim its world's `[faults] seed`).
    seed: int | None = None
    random: bool = False
    timeout: float | None = None
    trace: Path | None = None
    world: str | None = None
    record: Path | None = None
    snapshot: Path | None = None
    realtime: bool = False
    entry: str = "main"


@dataclass
class RunOutcome:
    path: Path
    check: CheckResult
    result: RunResult | None = None
    trace: Trace | None = None
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)

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


_DIRECTIVE = re.compile(r"^\s*//\s*(scenario|world)\s*:\s*(\S+)\s*$")


def file_directives(path: Path) -> dict[str, str]:
    """`// scenario: FILE` and `// world: NAME` comments at the top of a program."""
    found: dict[str, str] = {}
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return found
    for line in lines[:40]:
        stripped = line.strip()
        if stripped and not stripped.startswith("//"):
            break
        m = _DIRECTIVE.match(line)
        if m:
            found.setdefault(m.group(1), m.group(2))
    return found


def make_platform(options: RunOptions, program: Path) -> Platform:
    try:
        cls = platform_class(options.platform)
    except PlatformError as e:
        raise RunSetupError(str(e)) from None
    create = getattr(cls, "create", None)
    if create is not None:
        try:
            platform: Platform = create(options, program)
        except (PlatformError, ValueError) as e:
            raise RunSetupError(str(e)) from None
        return platform
    if options.platform == "dummy":
        from gpp.platform.dummy import DummyPlatform, Scenario, ScenarioError

        scenario = None
        scenario_path = options.scenario
        if scenario_path is None:
            named = file_directives(program).get("scenario")
            if named is not None:
                scenario_path = program.parent / named
        if scenario_path is not None:
            try:
                scenario = Scenario.load(scenario_path)
            except ScenarioError as e:
                raise RunSetupError(str(e)) from None
        return DummyPlatform(scenario, options.seed if options.seed is not None else 1, options.random)
    return cls()


def run_program(
    path: Path,
    options: RunOptions,
    listeners: list[Callable[[TraceRecord], None]] | None = None,
    checked: CheckResult | None = None,
) -> RunOutcome:
    """Check and run one program (`checked`: the result of checking it already). Raises OSError
    for an unreadable file and RunSetupError when the platform cannot be set up; everything
    about the program itself is in the outcome."""
    check = checked if checked is not None else check_program(path)
    outcome = RunOutcome(path, check, diagnostics=list(check.diagnostics))
    if check.errors:
        return outcome
    if check.model.main is None:
        outcome.diagnostics.append(
            diag.error("R0008", "the program has no `procedure main()` to run", check.loaded.files[-1].program.span)
        )
        return outcome
    platform = make_platform(options, path)
    trace = Trace(options.trace, listeners)
    outcome.trace = trace
    try:
        from gpp.planner.policy import PolicyPlanner
        from gpp.runtime.compiled import CompiledProgram

        executor = Executor(
            CompiledProgram(check.model), platform, trace, options.timeout, options.entry, planner=PolicyPlanner()
        )
        problems = platform.attach(executor.interface())
        if problems:
            main = check.model.main
            span = main.span if main.span is not None else check.loaded.files[-1].program.span
            problem = diag.error("R0007", f"the program does not fit platform `{platform.name}`", span, notes=problems)
            outcome.diagnostics.append(problem)
            trace.emit("error", platform.now(), code=problem.code, message="; ".join(problems), at=str(span))
            trace.emit("finish", platform.now(), status=RunStatus.ERROR.value, actions=0, failures=0, exog_events=0)
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
    finally:
        platform.close()
        trace.close()
