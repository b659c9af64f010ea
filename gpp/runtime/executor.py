"""The online executor (SEMANTICS §4): runs `main()` against a platform.

Between program steps it drains the platform's queue (activity updates and exogenous events,
in arrival order). Each step is the first successor `trans` offers (so online `choose` and
`pick` take the first alternative that can step). When no step is possible the program is
blocked: the executor lets the platform's time pass until something arrives; when nothing
can arrive any more, the run stops with a diagnostic that says what the program waits for.
Every step and event goes to the trace as it happens.
"""

from __future__ import annotations

import contextlib
import dataclasses
import inspect
import os
import re
import sys
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import assert_never

import gpp.runtime.events as ev
from gpp.base import diagnostics as diag
from gpp.base import signals
from gpp.base.source import Span
from gpp.codes import R0007, R0009, R0011, R0012, R0013, R0014, R0015, R0099
from gpp.model.declarations import fill_placeholders
from gpp.model.types import Type
from gpp.runtime.blocked import BLOCKED, Wait, waits_for, why_blocked
from gpp.runtime.callstack import MAX_FRAMES, CallStacks
from gpp.runtime.compiled import CompiledProgram, Env
from gpp.runtime.contract import (
    Activity,
    ActivityUpdate,
    Attention,
    Event,
    ExogFunctionChanged,
    ExogOccurrence,
    MessageDropped,
    NoAnswer,
    PlatformError,
    PlatformFault,
    PlatformNotice,
    PlatformPort,
    PlatformWarning,
    Problem,
    unfit_error,
)
from gpp.runtime.control import Happening, RunControl, RunStopped
from gpp.runtime.errors import GppRuntimeError, Unanswered, WallClockReached
from gpp.runtime.planning import PlanReport
from gpp.runtime.semantics import (
    AssignStep,
    AwaitEnd,
    CancelStep,
    Code,
    Conc,
    Done,
    DoStep,
    DuringEnd,
    EndKind,
    EndStep,
    OnlinePlanner,
    Planned,
    PlanStep,
    Prog,
    ReplanStep,
    Rest,
    Semantics,
    Seq,
    StartStep,
    Step,
    TestStep,
    Watch,
)
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.trace import Trace, TraceWriteError
from gpp.runtime.values import Value
from gpp.syntax import ast

# Wall-clock seconds a blocked program waits at a time for a run control's events (it looks
# again at the run's bounds in between).
CONTROL_WAIT = 0.5
# Wall-clock seconds the executor waits, when a run ends, for the platform to acknowledge the
# cancellation of the activities still running.
CANCEL_GRACE = 2.0


class RunStatus(Enum):
    FINISHED = "finished"
    BLOCKED = "blocked"
    ERROR = "error"
    TIMEOUT = "timeout"
    INTERRUPTED = "interrupted"


@dataclass
class RunResult:
    status: RunStatus
    diagnostics: list[diag.Diagnostic] = field(default_factory=list)
    state: State = field(default_factory=State)
    activities: Activities = field(default_factory=Activities)
    postcond: bool | None = None
    actions: int = 0
    failures: int = 0
    unhandled_failures: int = 0
    exog_events: int = 0
    steps: int = 0
    platform_time: float = 0.0
    wall_time: float = 0.0
    # Interrupted by SIGTERM (not Ctrl-C).
    terminated: bool = False


class _ExecContext:
    """Evaluation context online: exog functions go to the platform, the clock is its clock."""

    def __init__(self, platform: PlatformPort) -> None:
        self.platform = platform
        self.activity: Activity | None = None
        # While a `senses:` section is evaluated: the activity's result, if it has one.
        self.result: tuple[bool, Value] = (False, None)
        # The earliest future time at which a comparison with the clock evaluated since the
        # last reset changes its truth value.
        self.wake: float | None = None
        # While the executor explains a wait: the platform is not asked (an answer could change).
        self.explaining = False

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        if self.result[0]:
            return self.result[1]
        if self.explaining:
            raise GppRuntimeError(R0007.not_asked_explaining(), span)
        try:
            return self.platform.exog_function(name, args, return_type, self.activity)
        except NoAnswer as e:
            raise Unanswered(R0007.no_answer(name, e), span) from None
        except PlatformError as e:
            raise GppRuntimeError(R0007.exog_function_failed(name, e), span) from None

    def now(self) -> float:
        return self.platform.now()

    def wake_at(self, t: float) -> None:
        if self.wake is None or t < self.wake:
            self.wake = t


class Executor:
    def __init__(
        self,
        program: CompiledProgram,
        platform: PlatformPort,
        trace: Trace,
        time_limit: float | None = None,
        entry: str = "main",
        planner: OnlinePlanner | None = None,
        timeout: float | None = None,
        entry_args: tuple[Value, ...] = (),
        control: RunControl | None = None,
        trace_steps: bool = False,
    ) -> None:
        """`planner` runs `solve`/`search` (gpp.run.runner gives gpp.planner's); without one, a
        program that reaches them stops with an error (R0010). The run's two bounds (SEMANTICS
        §4): `timeout`, wall-clock seconds (`--timeout`), and `time_limit`, seconds of platform
        time (`--time-limit`). `control`: a debugger or the operator console (gpp.runtime.control).
        `trace_steps`: a `step` record before each transition (`--trace-steps`), for a replay."""
        self.program = program
        self.control = control if control is not None else RunControl()
        self.platform = platform
        self.trace = trace
        self.call_stacks = CallStacks(program) if trace_steps else None
        self.time_limit = time_limit
        self.timeout = timeout
        self.planner = planner
        # The moment (time.monotonic()) the wall-clock bound is reached, once the run started.
        self.wall_deadline: float | None = None
        self._wait_takes_wall_deadline: bool | None = None  # see wait_for_platform
        self.entry = entry
        # The values of the entry procedure's parameters (`gpp run --arg n=3`), in order.
        self.entry_args = entry_args
        self.ctx = _ExecContext(platform)
        self.sem = Semantics(program, self.ctx, planning=False, planner=planner)
        self.state = State()
        self.acts = Activities()
        self.records: dict[GroundAction, Activity] = {}
        self.by_id: dict[int, GroundAction] = {}
        self.results: dict[GroundAction, tuple[bool, Value]] = {}
        self.next_id = 1
        # Activities the platform took (its `start` returned): only these can be acknowledged.
        self.accepted: set[int] = set()
        # Activities whose cancel the platform refused (they still run): not waited for at the end.
        self.cancel_refused: set[int] = set()
        self.cancel_grace = CANCEL_GRACE
        # `solve` statements already warned about (R0014).
        self.warned: set[int] = set()
        # The `waiting` record of the wait the program is in, if it is waiting, and what it
        # waits for (`_waited_for`: the record is written again only when that changes).
        self.waiting_at: ev.WaitingEvent | None = None
        self.waiting_for: tuple[str, str | None, str] | None = None
        # The program waited for clock times that kept moving with the clock.
        self.chasing = False
        # The program cannot step and waits for the platform (since its last step).
        self.blocked = False
        self.result = RunResult(RunStatus.FINISHED)
        self._silent: dict[str, bool] = {}
        # Problems with the program the platform reported while it runs (PlatformFault).
        self.faults: list[Problem] = []
        # Exogenous actions and functions already warned about (R0015), and warnings given.
        self.warned_dropped: set[str] = set()
        self.warned_platform: set[str] = set()

    def wait_for_platform(self, deadline: float | None) -> bool:
        """The platform's `wait` until `deadline` (platform time) or the run's wall-clock bound. A
        platform plugin written before the port had `wall_deadline` is asked without it (its
        `wait` then returns by `deadline` or an event, and the bound is checked after)."""
        if self.wall_deadline is None:
            return self.platform.wait(deadline)
        if self._wait_takes_wall_deadline is None:
            try:
                parameters = inspect.signature(self.platform.wait).parameters
            except (TypeError, ValueError):
                parameters = {}  # type: ignore[assignment]
            self._wait_takes_wall_deadline = "wall_deadline" in parameters or any(
                p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()
            )
        if self._wait_takes_wall_deadline:
            return self.platform.wait(deadline, wall_deadline=self.wall_deadline)
        return self.platform.wait(deadline)

    # ---------------------------------------------------------------- the loop

    def run(self) -> RunResult:
        with raised_recursion_limit():
            return self._run()

    def _run(self) -> RunResult:
        started = time.perf_counter()
        result = self.result
        prog: Prog | None = None
        try:
            if self.timeout is not None:
                self.wall_deadline = time.monotonic() + self.timeout
            if self.planner is not None:
                self.planner.stop_at(self.wall_deadline)
            prog = self.sem.entry(self.entry, self.entry_args)
            self.control.started(self, prog)
            # Wake-ups in a row at which the program still could not step.
            chased = 0
            while True:
                if self.trace.split_due(self.platform.now()):
                    self.trace.next_part(self.snapshot())
                self.drain()
                self.stop_at_fault()
                self.control.checkpoint(self, prog)
                # An exogenous function's answer may have changed since the last look.
                self.sem.forget()
                # Comparisons with the clock evaluated from here on say when to wake up.
                self.ctx.wake = None
                if self.sem.final(prog, self.state, self.acts):
                    result.status = RunStatus.FINISHED
                    break
                if self.timed_out(strictly=True):
                    self.stop_at_timeout(prog)
                    break
                if self.wall_timed_out():
                    self.stop_at_wall_timeout(prog, started)
                    break
                successors = self.sem.trans(prog, self.state, self.acts, first=True)
                if successors:
                    chased = 0
                    next_prog, step = successors[0]
                    if self.call_stacks is not None:
                        self.trace_step(prog, next_prog, step)
                    if self.waiting_at is not None:
                        self.trace.emit(dataclasses.replace(self.waiting_at, t=self.platform.now(), resumed=True))
                        self.waiting_at = self.waiting_for = None
                    self.blocked = False
                    self.control.stepping(self, prog, step, next_prog)
                    self.perform(step)
                    result.steps += 1
                    prog = next_prog
                    continue
                # Blocked: let the platform's time pass until something arrives, or until the
                # clock reaches a time at which a condition the program waits on changes.
                wake = self.ctx.wake
                if self.timed_out():
                    self.stop_at_timeout(prog)
                    break
                if wake is not None or self.platform.live():
                    self.blocked = True
                    self.note_waiting(prog)
                    deadline = min((t for t in (wake, self.time_limit) if t is not None), default=None)
                    if self.wait_for_platform(deadline) or len(self.platform.queue) > 0:
                        continue
                    if wake is not None and self.platform.now() >= wake:
                        chased += 1
                        if chased < CHASE_LIMIT:
                            continue
                        self.chasing = True  # the blocked diagnostic says why
                    if self.timed_out():
                        self.stop_at_timeout(prog)
                        break
                    if self.wall_timed_out():
                        self.stop_at_wall_timeout(prog, started)
                        break
                    if self.platform.live():
                        continue
                if self.control.live():
                    # Nothing else can happen, but the control (an operator) may still bring events.
                    self.blocked = True
                    self.note_waiting(prog)
                    self.platform.queue.wait(CONTROL_WAIT)
                    continue
                if len(self.platform.queue) > 0:
                    continue  # the control brought something while the executor looked
                d = self.blocked_diagnostic(prog)
                said = "\n".join((d.message + (f": {d.label}" if d.label else ""), *d.notes))
                self.control.happened(self, prog, Happening("blocked", said, d.span))
                if len(self.platform.queue) > 0:
                    continue  # the control brought something while it held the run
                result.status = RunStatus.BLOCKED
                result.diagnostics.append(d)
                self.trace.emit(ev.BlockedEvent(t=self.platform.now(), message=d.message, at=_where(d.span)))
                break
        except GppRuntimeError as e:
            self.fail(e)
        except WallClockReached:  # the planner was planning when the wall-clock bound came
            assert prog is not None
            self.stop_at_wall_timeout(prog, started, planning=True)
        except RecursionError:
            self.fail(
                GppRuntimeError(
                    R0012.calls(),
                    _head_span(prog) if prog is not None else None,
                    ("a recursion without an end, or one deeper than the interpreter's stack allows",),
                    label="while executing this statement",
                )
            )
        except RunStopped as e:
            result.status = RunStatus.INTERRUPTED
            message = e.reason
            self.trace.emit(ev.ErrorEvent(t=self.platform.now(), message=message))
        except KeyboardInterrupt as e:
            result.status = RunStatus.INTERRUPTED
            result.terminated = signals.is_termination(e)
            message = signals.message(e)
            self.trace.emit(ev.ErrorEvent(t=self.platform.now(), message=message))
        except TraceWriteError:
            result.status = RunStatus.ERROR
            raise  # after the activities are stopped: the command says why
        except Exception as e:  # a bug in gpp or in a platform: still a diagnostic, never a traceback
            if os.environ.get("GPP_DEBUG") == "1":
                raise
            self.fail(
                GppRuntimeError(
                    R0099.internal(e),
                    self.entry_span(),
                    (
                        "this is a bug in gpp (or in the platform); please report it with the program",
                        "run again with GPP_DEBUG=1 to see the traceback",
                    ),
                )
            )
        finally:
            # The run has ended: no control holds or stops the clean-up (it is told once it is done).
            control, self.control = self.control, RunControl()
            self.stop_running_activities()
            control.finished(self)
            result.state, result.activities = self.state, self.acts
            result.platform_time = self.platform.now()
            result.wall_time = time.perf_counter() - started
            self.trace.emit(
                ev.FinishEvent(
                    t=self.platform.now(),
                    status=result.status.value,
                    actions=result.actions,
                    failures=result.failures,
                    unhandled_failures=result.unhandled_failures,
                    exog_events=result.exog_events,
                )
            )
        return result

    def timed_out(self, strictly: bool = False) -> bool:
        """Has the platform's clock reached the time limit (passed it, when `strictly`)? Steps
        at the very moment of the limit still happen; waiting beyond it does not."""
        if self.time_limit is None:
            return False
        now = self.platform.now()
        return now > self.time_limit if strictly else now >= self.time_limit

    def wall_timed_out(self) -> bool:
        """Has the run taken longer than its timeout in wall-clock time?"""
        return self.wall_deadline is not None and time.monotonic() >= self.wall_deadline

    def stop_at_wall_timeout(self, prog: Prog, started: float, planning: bool = False) -> None:
        """Stop the run at its wall-clock bound (`--timeout`): where it was, and what it was
        doing (planning, waiting, or making steps without end)."""
        self.result.status = RunStatus.TIMEOUT
        assert self.timeout is not None
        notes = [f"it ran for {time.perf_counter() - started:.1f} s of wall-clock time"]
        if planning:
            notes.append("it was planning (the bound holds while the planner works too)")
            label = "planning here"
        elif self.blocked:
            waiting = self.explained(prog).why
            if waiting is not None:
                notes.append(f"it waits here: {waiting.message.removeprefix(BLOCKED)}")
            label = "waiting here"
        else:
            notes.append("it was making steps: a loop whose steps take no platform time never ends on its own")
            label = "running here"
        span = _head_span(prog) or self.entry_span()
        assert span is not None
        d = diag.error(R0013.wall_clock(self.timeout, self.platform.now()), span, label, notes=notes)
        self.result.diagnostics.append(d)
        self.trace.emit(ev.ErrorEvent(t=self.platform.now(), code=d.code, message=d.message, at=_where(d.span)))

    def explained(self, prog: Prog) -> Wait:
        """What the blocked program waits for, without asking the platform anything (an answer
        could change what it waits for): only where it waits when explaining would ask."""
        self.ctx.explaining = True
        try:
            return waits_for(self.sem, prog, self.state, self.acts)
        except GppRuntimeError:
            return Wait(None, "event")
        finally:
            self.ctx.explaining = False

    def note_waiting(self, prog: Prog) -> None:
        """Record, once per wait, what the blocked program waits for (a `waiting` trace record).
        A wait for a running activity is not recorded (its start and end records tell it),
        unless the activity is a step of a plan: the record says which step."""
        wait = self.explained(prog)
        why = wait.why
        if wait.reason == "activity" and wait.plan_step is None:
            return
        if self.sem.unanswered is not None:
            # It waits for an exogenous function's answer: that is the condition to show.
            unanswered, stmt = self.sem.unanswered
            why = diag.error(diag.Message(unanswered.code, unanswered.message), stmt.span)
            wait = Wait(why, "answer")
        span = why.span if why is not None else _head_span(prog)
        condition = why.message.removeprefix(BLOCKED) if why is not None else "an event or an activity update"
        if wait.action is not None and wait.plan_step is not None:
            condition = R0011.planned_wait(wait.action.text, wait.plan_step)
        text = span.text.strip().splitlines()[0] if span is not None and span.text.strip() else ""
        statement = text if len(text) <= 80 else text[:77] + "..."
        waited_for = (statement, _where(span), _without_figures(condition))
        if waited_for == self.waiting_for:
            return  # the values it looks at changed, not what it waits for
        if why is not None and why.notes:
            condition += " (" + "; ".join(n.strip() for n in why.notes) + ")"
        self.waiting_for = waited_for
        self.waiting_at = ev.WaitingEvent(
            t=self.platform.now(),
            statement=statement,
            at=_where(span),
            condition=condition,
            reason=wait.reason,
            action=wait.action.text if wait.action is not None else None,
            plan_step=wait.plan_step,
        )
        self.trace.emit(self.waiting_at)

    def snapshot(self) -> ev.SnapshotEvent:
        """The state between two steps, for a new part of a split trace: the fluent instances
        not at their initial value, the activities not consumed, what the program waits for."""
        waiting = self.waiting_at
        return ev.SnapshotEvent(
            t=self.platform.now(),
            fluents=self.changes(self.state.held()),
            activities=tuple(
                {"action": g.text, "id": self.records[g].id, "status": status.value} for g, status in self.acts.items()
            ),
            waiting=None if waiting is None else ev.waiting_fields(waiting),
            actions=self.result.actions,
            failures=self.result.failures,
            exog_events=self.result.exog_events,
        )

    def stop_at_timeout(self, prog: Prog) -> None:
        self.result.status = RunStatus.TIMEOUT
        d = self.timeout_diagnostic(prog)
        self.result.diagnostics.append(d)
        self.trace.emit(ev.ErrorEvent(t=self.platform.now(), code=d.code, message=d.message, at=_where(d.span)))

    def fail(self, e: GppRuntimeError) -> None:
        """Stop the run on a runtime error: one diagnostic and an `error` trace record."""
        self.result.status = RunStatus.ERROR
        error = e.diagnostic(self.entry_span())
        if error is not None:
            self.result.diagnostics.append(error)
        at = _where(error.span if error is not None else None)
        self.trace.emit(ev.ErrorEvent(t=self.platform.now(), code=e.code, message=e.message, at=at))
        with contextlib.suppress(RunStopped):  # the run ends anyway
            self.control.happened(self, None, Happening("error", e.message, error.span if error else None))

    def entry_span(self) -> Span | None:
        symbol = self.program.model.globals.get(self.entry)
        return symbol.span if symbol is not None else None

    def evaluate_postcond(self) -> bool | None:
        """`bool function postcond()` in the final state, if the program defines one."""
        symbol = self.program.model.globals.get("postcond")
        if symbol is None or symbol.kind.name != "FUNCTION" or symbol.params:
            return None
        _, body = self.program.function("postcond")
        if body is None:
            return None
        try:
            with raised_recursion_limit():
                value = body(Env(self.state, {}, self.ctx))
        except RecursionError:
            raise GppRuntimeError(R0012.postcond(), symbol.span) from None
        self.result.postcond = value is True
        return self.result.postcond

    # ---------------------------------------------------------------- events

    def drain(self) -> None:
        """Take in what the platform queued. Every event taken is handled even when the control
        stops the run on one of them (a debugger's stop at a failure, then terminate): an
        activity's end must not be lost, or the run's end would wait for it. The control's
        `attend` comes once, after the platform's events."""
        stopped: RunStopped | None = None
        attention = False
        for t, event in self.platform.queue.drain():
            try:
                attention = self.take(t, event) or attention
            except RunStopped as e:
                stopped = stopped or e
        if attention and stopped is None:
            try:
                self.control.attend(self)
            except RunStopped as e:
                stopped = e
        if stopped is not None:
            raise stopped

    def take(self, t: float, event: Event) -> bool:
        """Handle one event of the platform's queue; True for an `Attention` (the caller tells
        the control)."""
        if isinstance(event, ActivityUpdate):
            self.on_update(t, event)
        elif isinstance(event, PlatformNotice):
            self.on_notice(t, event)
        elif isinstance(event, ExogOccurrence):
            self.on_exog(t, event)
        elif isinstance(event, ExogFunctionChanged):
            pass  # the program evaluates its conditions again: that is all
        elif isinstance(event, MessageDropped):
            self.on_dropped(t, event)
        elif isinstance(event, PlatformWarning):
            self.on_warning(t, event)
        elif isinstance(event, PlatformFault):
            self.faults.extend(event.problems)
        elif isinstance(event, Attention):
            return True
        else:
            assert_never(event)
        return False

    def stop_at_fault(self) -> None:
        """Stop the run when the platform reported problems with the program (PlatformFault):
        each is an error at the mapping it is about, as when the platform attached."""
        if not self.faults:
            return
        errors = [unfit_error(p, self.platform.name, self.entry_span()) for p in self.faults]
        self.faults.clear()
        for e in errors[:-1]:
            self.fail(e)
        raise errors[-1]

    def on_notice(self, t: float, notice: PlatformNotice) -> None:
        g = self.by_id.get(notice.activity_id) if notice.activity_id is not None else None
        if notice.cancel_refused and notice.activity_id is not None:
            self.cancel_refused.add(notice.activity_id)
        self.trace.emit(
            ev.NoticeEvent(
                t=t,
                message=notice.message,
                action=g.text if g is not None else None,
                id=notice.activity_id if g is not None else None,
            )
        )

    def on_dropped(self, t: float, dropped: MessageDropped) -> None:
        """A `dropped` record for each; a warning (R0015) the first time for its target."""
        self.trace.emit(
            ev.DroppedEvent(
                t=t,
                source=dropped.source,
                target=dropped.target,
                reason=dropped.reason,
                count=dropped.count,
                at=_where(dropped.span),
            )
        )
        if dropped.target in self.warned_dropped or dropped.span is None:
            return
        self.warned_dropped.add(dropped.target)
        d = diag.warning(
            R0015.dropped(dropped.source, dropped.target, dropped.reason),
            dropped.span,
            "what came in does not fit this",
            notes=[f"at {t:.3f} s; the trace has a `dropped` record for each drop (this warning is given once)"],
            help=dropped.help,
        )
        self.result.diagnostics.append(d)
        self.trace.emit(ev.WarningEvent(t=t, code=d.code, message=d.message, at=_where(d.span)))

    def on_warning(self, t: float, warning: PlatformWarning) -> None:
        """A platform's warning (R0015), once per text."""
        if warning.message in self.warned_platform:
            return
        self.warned_platform.add(warning.message)
        message = R0015.platform(self.platform.name, warning.message)
        if warning.span is not None:
            d = diag.warning(message, warning.span, warning.label, help=warning.help)
            self.result.diagnostics.append(d)
        self.trace.emit(ev.WarningEvent(t=t, code=message.code, message=message.text, at=_where(warning.span)))

    def on_update(self, t: float, update: ActivityUpdate) -> None:
        g = self.by_id.get(update.activity_id)
        if g is None or self.acts.status(g) is not ActivityStatus.RUNNING:
            return  # a late update for an activity already consumed
        self.acts = self.acts.with_status(g, update.status)
        if update.has_result:
            self.results[g] = (True, update.result)
        self.trace.emit(
            ev.UpdateEvent(
                t=t,
                action=g.text,
                status=update.status.value,
                id=update.activity_id,
                reason=update.reason or None,
                result=ev.json_value(update.result) if update.has_result else ev.ABSENT,
                silent=self.quiet(g.name),
            )
        )
        if update.status is ActivityStatus.FAILED:
            self.result.failures += 1
            reason = f": {update.reason}" if update.reason else ""
            failed = Happening("failed", f"{g.text} failed{reason}", t=t, action=g.text, reason=update.reason or None)
            self.control.happened(self, None, failed)

    def on_exog(self, t: float, event: ExogOccurrence) -> None:
        info = self.program.action(event.action)
        g = GroundAction(event.action, event.args)
        holds = self.sem.precondition_holds(info, g, self.state)
        self.result.exog_events += 1
        try:
            updates = self.sem.effects(g, self.state)
        except GppRuntimeError as e:
            # The event is named in the trace and in the diagnostic; the error record follows.
            self.trace.emit(
                ev.ExogEvent(t=t, action=g.text, precondition=holds, silent=self.quiet(event.action), failed=True)
            )
            e.notes = (f"in the effect of the exogenous event `{g.text}`, which arrived at {t:.3f} s", *e.notes)
            raise
        self.state = self.state.updated(updates, self.program.initial)
        self.trace.emit(
            ev.ExogEvent(
                t=t, action=g.text, precondition=holds, silent=self.quiet(event.action), changes=self.changes(updates)
            )
        )

    def changes(self, updates: Mapping[int, Value]) -> tuple[dict[str, ev.JsonValue], ...]:
        """The `changes` of a trace record: each fluent instance set, with its new value."""
        return tuple(ev.fluent_change(self.program.instance_text(slot), value) for slot, value in updates.items())

    def quiet(self, action: str) -> bool:
        """Is the action declared `silent: true`? Its records are marked `silent`: the trace
        keeps them (it is the complete record), a console view leaves them out."""
        silent = self._silent.get(action)
        if silent is None:
            decl = self.program.action(action).decl
            section = decl.section(ast.SilentSection) if decl is not None else None
            value = section.value if isinstance(section, ast.SilentSection) else None
            silent = isinstance(value, ast.BoolLit) and value.value
            self._silent[action] = silent
        return silent

    # ---------------------------------------------------------------- steps

    def trace_step(self, prog: Prog, next_prog: Prog, step: Step) -> None:
        """The `step` record of the transition `step` from `prog` to `next_prog`."""
        assert self.call_stacks is not None
        span = step.session.stmt.span if isinstance(step, PlanStep | ReplanStep) else step.span
        frames = self.call_stacks.step_frames(prog, next_prog, span)
        depth = len(frames) if len(frames) > MAX_FRAMES else None
        if depth is not None:  # a deep recursion: the innermost calls and the entry procedure
            frames = (*frames[: MAX_FRAMES - 1], frames[-1])
        self.trace.emit(
            ev.StepEvent(
                t=self.platform.now(),
                at=_where(span),
                step=step.describe() or (span.text.strip().splitlines() or [""])[0],
                frames=frames,
                depth=depth,
                continues=isinstance(step, ReplanStep)
                or (isinstance(step, EndStep) and step.hook in (EndKind.CALL, EndKind.DURING)),
            )
        )

    def perform(self, step: Step) -> None:
        now = self.platform.now()
        if isinstance(step, StartStep):
            self.start(step.action, step.span)
        elif isinstance(step, EndStep):
            self.end(step)
        elif isinstance(step, CancelStep):
            record = self.records[step.action]
            self.trace.emit(ev.CancelEvent(t=now, action=step.action.text, id=record.id, reason=step.reason or None))
            self.platform.preempt(record)
        elif isinstance(step, AssignStep):
            self.state = self.state.updated(dict(step.updates), self.program.initial)
            for slot, value in step.updates:
                self.trace.emit(
                    ev.AssignEvent(
                        t=now, fluent=self.program.instance_text(slot), value=ev.json_value(value), at=_where(step.span)
                    )
                )
        elif isinstance(step, PlanStep):
            report = step.session.plan(self.sem, self.state, self.acts)
            self.trace_plan("plan", report)
            self.warn_unfinished(step.session.stmt, report)
        elif isinstance(step, ReplanStep):
            report = step.session.replan(self.sem, step.index, self.state, self.acts, step.reason)
            self.trace_plan("replan", report)
            self.warn_unfinished(step.session.stmt, report)
        elif isinstance(step, TestStep | DoStep):
            pass
        else:
            assert_never(step)

    def operate(self, g: GroundAction, span: Span) -> str | None:
        """Run one action a run control asks for (the operator console's actions before the
        start), from the control's call in the executor's thread: start it, let the platform's
        time pass until it ends, consume it (its `senses:` and effects apply when it ended
        final). None when it ran; else why it did not (its precondition is false, it runs
        already, or the platform can never end it)."""
        info = self.program.action(g.name)
        if self.acts.status(g) is not None:
            return f"`{g.text}` runs already"
        if not self.sem.precondition_holds(info, g, self.state):
            return f"the precondition of `{g.text}` does not hold"
        self.start(g, span)
        while self.acts.status(g) is ActivityStatus.RUNNING:
            self.drain()
            if self.acts.status(g) is not ActivityStatus.RUNNING:
                break
            if not self.wait_for_platform(None) and len(self.platform.queue) == 0 and not self.platform.live():
                return f"platform `{self.platform.name}` has nothing more to report: `{g.text}` does not end"
        self.end(EndStep(g, "call", span))
        return None

    def warn_unfinished(self, stmt: ast.Solve | ast.Search, report: PlanReport) -> None:
        """A warning (once per `solve`) when its plan ends at the horizon with the program
        unfinished: what runs after the plan is not planned."""
        if not report.unfinished or id(stmt) in self.warned:
            return
        self.warned.add(id(stmt))
        h = report.horizon
        written = report.written if report.written is not None else h
        notes = []
        if report.spent:
            # Where the rest of the horizon went: the steps already executed (failed attempts
            # gave theirs back).
            shown = ", ".join(f"`{s}`" for s in report.spent[:6]) + (", ..." if len(report.spent) > 6 else "")
            notes.append(R0014.spent(written, len(report.spent), shown))
        notes.append(f"its plan uses all {h} step(s) left of the horizon, and the program is not finished after them")
        if report.steps_left is not None:
            notes.append(f"finishing it needs at least {report.steps_left} more step(s)")
        notes.append("the rest of the `solve`'s program is not executed: the run goes on after the `solve`")
        self.result.diagnostics.append(
            diag.warning(
                R0014.unfinished(written),
                stmt.span,
                "planned only up to its horizon",
                notes=notes,
                help=f"raise the horizon to at least {written + report.steps_left}"
                if report.steps_left is not None
                else "raise the horizon",
            )
        )

    def trace_plan(self, event: str, plan: PlanReport) -> None:
        """A `plan` or `replan` record; a `replan` also says why, and the horizon as written."""
        record = ev.ReplanEvent(
            t=self.platform.now(),
            kind=plan.kind,
            feasible=plan.feasible,
            value=plan.value,
            horizon=plan.horizon,
            policy=plan.policy,
            nodes=plan.nodes,
            cache_hits=plan.cache_hits,
            pruned=plan.pruned,
            reward_evaluations=plan.reward_evaluations,
            seconds=round(plan.seconds, 6),
            unfinished=plan.unfinished,
            steps_left=plan.steps_left,
            reason=plan.reason,
            written_horizon=plan.written if plan.written != plan.horizon else None,
        )
        if event == "plan":
            shared = {f.name: getattr(record, f.name) for f in dataclasses.fields(ev.PlanEvent)}
            self.trace.emit(ev.PlanEvent(**shared))
        else:
            self.trace.emit(record)
        if not plan.feasible:
            self.control.happened(self, None, Happening("no-plan", f"`{plan.kind}` found no feasible plan"))

    def start(self, g: GroundAction, span: Span) -> None:
        status = self.acts.status(g)
        if status is not None and status.terminal:
            raise GppRuntimeError(
                R0009.started_again(g.text),
                span,
                ("`end(...)`, `finish(...)` or `fail(...)` consumes an activity that has terminated",),
            )
        info = self.program.action(g.name)
        env = Env(self.state, dict(zip(info.param_ids, g.args, strict=True)), self.ctx)
        args = {name: evaluate(env) for name, evaluate in info.mapped_args}
        duration = info.duration
        mapped = info.mapped_name
        if "{" in mapped:  # placeholders: `"/{r}/navigate"` is `/robot1/navigate` for r = robot1
            mapped = fill_placeholders(mapped, dict(zip(info.param_names, g.args, strict=True)))
        # The start effects: evaluated in the state the precondition held in, applied with the
        # start (before the platform hears of it, so an update it sends sees them).
        updates = self.sem.effects(g, self.state, at_start=True) if info.start_effects else {}
        if updates:
            self.state = self.state.updated(updates, self.program.initial)
        now = self.platform.now()
        activity = Activity(self.next_id, g, mapped, args, duration, now)
        self.next_id += 1
        self.records[g] = activity
        self.by_id[activity.id] = g
        self.results.pop(g, None)
        self.acts = self.acts.with_status(g, ActivityStatus.RUNNING)
        self.result.actions += 1
        self.trace.emit(
            ev.StartEvent(
                t=now,
                action=g.text,
                id=activity.id,
                mapped=mapped,
                args={k: ev.json_value(v) for k, v in args.items()},
                at=_where(span),
                silent=self.quiet(g.name),
                changes=self.changes(updates),
            )
        )
        try:
            self.platform.start(activity)
        except PlatformError as e:
            raise GppRuntimeError(R0007.cannot_start(g.text, e), span) from None
        self.accepted.add(activity.id)

    def end(self, step: EndStep) -> None:
        g = step.action
        status = self.acts.status(g)
        assert status is not None
        record = self.records.get(g)
        now = self.platform.now()
        updates: dict[int, Value] = {}
        if status is ActivityStatus.FINAL:
            info = self.program.action(g.name)
            if info.senses is not None and record is not None:
                self.sense(g, record, info.senses, now)
            updates = self.sem.effects(g, self.state)
            self.state = self.state.updated(updates, self.program.initial)
        unhandled = status is ActivityStatus.FAILED and step.hook != "fail" and not step.handles_failure
        if unhandled:
            # Nothing in the program reacts to this failure: it goes on, but it is reported.
            self.result.unhandled_failures += 1
        self.trace.emit(
            ev.EndEvent(
                t=now,
                action=g.text,
                status=status.value,
                hook=step.hook,
                unhandled=unhandled,
                silent=self.quiet(g.name),
                changes=self.changes(updates),
            )
        )
        self.acts = self.acts.with_status(g, None)
        consumed = self.records.pop(g, None)
        self.results.pop(g, None)
        if consumed is not None:  # what is kept per activity goes with it (a run keeps no history)
            self.by_id.pop(consumed.id, None)
            self.accepted.discard(consumed.id)
            self.cancel_refused.discard(consumed.id)

    def sense(self, g: GroundAction, record: Activity, senses: object, now: float) -> None:
        """Apply the `senses:` section of an activity that ended final; its record is stamped
        `now`, the time of the `end` record that follows it."""
        from gpp.runtime.compiled import Effect

        assert isinstance(senses, Effect)
        info = self.program.action(g.name)
        env = Env(self.state, dict(zip(info.param_ids, g.args, strict=True)), self.ctx)
        self.ctx.activity = record
        self.ctx.result = self.results.get(g, (False, None))
        try:
            value = senses.value(env)
        finally:
            self.ctx.activity = None
            self.ctx.result = (False, None)
        pending: dict[int, Value] = {}
        slot = self.program.assignment(senses.target, value, env, pending, senses.value_span)
        self.state = self.state.updated(pending, self.program.initial)
        self.trace.emit(
            ev.SenseEvent(
                t=now,
                action=g.text,
                fluent=self.program.instance_text(slot),
                value=ev.json_value(value),
                silent=self.quiet(g.name),
            )
        )

    def stop_running_activities(self) -> None:
        """Preempt every activity still running, then wait (at most `cancel_grace` seconds of wall time)
        for the platform to acknowledge each, so that the trace records how each ended. One whose
        cancel the platform refused is not waited for: it still runs, as its `notice` says."""
        stopping: list[GroundAction] = []
        for g in self.acts.running():
            record = self.records.get(g)
            if record is None:
                continue
            self.trace.emit(
                ev.CancelEvent(t=self.platform.now(), action=g.text, id=record.id, reason="the program ended")
            )
            if record.id in self.accepted:
                stopping.append(g)
            # Stopping must go on whatever the platform does.
            with contextlib.suppress(Exception):
                self.platform.preempt(record)
        grace = self.cancel_grace
        deadline = time.monotonic() + grace
        while True:
            with contextlib.suppress(Exception):
                self.drain()
            open_ = [
                g
                for g in stopping
                if self.acts.status(g) is ActivityStatus.RUNNING and self.records[g].id not in self.cancel_refused
            ]
            left = deadline - time.monotonic()
            if not open_ or left <= 0:
                break
            self.platform.queue.wait(min(left, 0.05))
        for g in open_:
            self.trace.emit(
                ev.ErrorEvent(
                    t=self.platform.now(),
                    message=f"platform `{self.platform.name}` did not acknowledge the cancellation of `{g.text}` "
                    f"within {grace:g} s",
                )
            )

    # ---------------------------------------------------------------- diagnostics

    def blocked_diagnostic(self, prog: Prog) -> diag.Diagnostic:
        why = why_blocked(self.sem, prog, self.state, self.acts)
        final_note = f"nothing can change this: platform `{self.platform.name}` has no more events to report"
        if self.chasing:
            final_note = (
                "the time it waits for moves with the clock: it is computed from `context_time()` whenever the "
                "condition is evaluated (take the time once, in an assignment, and compare with that)"
            )
        if why is None:
            span = self.entry_span()
            assert span is not None
            return diag.error(R0011.no_step(), span, notes=[final_note])
        return dataclasses.replace(why, notes=(*why.notes, final_note))

    def timeout_diagnostic(self, prog: Prog) -> diag.Diagnostic:
        """R0013 at the time limit (`--time-limit`, platform time): where the program waits."""
        waiting = why_blocked(self.sem, prog, self.state, self.acts)
        span = waiting.span if waiting is not None else self.entry_span()
        assert span is not None and self.time_limit is not None
        notes = [f"it waits here: {waiting.message.removeprefix(BLOCKED)}", *waiting.notes] if waiting else []
        return diag.error(R0013.time_limit(self.time_limit), span, "waiting here", notes=notes)


# A program that wakes up this many times in a row at the time its condition named, and still
# cannot step, waits for a time that moves with the clock (`test(context_time() >=
# context_time() + 1)`): it is blocked.
CHASE_LIMIT = 1000

# Python frames a run may use: golog++ recursion (procedures, functions) nests a few frames
# per level; the default limit of 1000 would stop a recursion about 100 levels deep.
RECURSION_LIMIT = 20_000


@contextlib.contextmanager
def raised_recursion_limit() -> Iterator[None]:
    """Python's recursion limit raised to RECURSION_LIMIT for the block (restored after)."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, RECURSION_LIMIT))
    try:
        yield
    finally:
        sys.setrecursionlimit(old)


def _head_span(p: Prog) -> Span | None:
    """The span of the statement a continuation executes next."""
    for _ in range(10_000):
        match p:
            case Seq():
                p = p.first
            case Rest():
                return p.block.body[p.index].span if p.index < len(p.block.body) else p.block.span
            case Conc():
                if not p.branches:
                    return None
                p = p.branches[0]
            case Code(stmt=ast.Block() as block) if block.body:
                p = Rest(block, 0, p.frame)
            case Code():
                return p.stmt.span
            case AwaitEnd() | DuringEnd() | Watch():
                return p.span
            case Planned():
                return p.session.stmt.span
            case Done():
                return None
            case _:
                assert_never(p)
    return None


def _without_figures(text: str) -> str:
    """`text` with its numbers blanked: a wait for an exogenous function's answer says how old
    the last one is, which changes with every look but is still the same wait."""
    return re.sub(r"[0-9]+(?:\.[0-9]+)?", "#", text)


def _where(span: Span | None) -> str | None:
    return str(span) if span is not None else None


__all__ = ["Executor", "Mapping", "RunResult", "RunStatus"]
