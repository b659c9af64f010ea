"""The live backend: a run of the program on a platform, with the debugger as its run control
(gpp.runtime.control). The run is `gpp.run.runner.run_program` on a thread of its own (the
same executor and platforms as `gpp run`); the protocol loop asks it things through a queue of
jobs that the run's thread does while it holds, so that only the run's thread ever touches the
executor (a question may ask the platform: an exogenous function in `evaluate`)."""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, TypeVar, cast

from gpp.base import diagnostics as diag
from gpp.check import CheckResult
from gpp.dap.backend import Client, Evaluated, Resumption, Scope, SessionBackend, StackFrame, Stop, Variable
from gpp.dap.breakpoints import Breakpoints
from gpp.dap.program import CheckedExpression, DebugProgram, ExpressionError
from gpp.dap.protocol import DapError
from gpp.dap.stack import CallFrame, elements, sees
from gpp.dap.variables import Handles, activity_scope, fluent_scope, plan_scope, value_variable, values_scope
from gpp.model.symbols import SymbolKind
from gpp.runtime.callstack import Call, CallStacks
from gpp.runtime.compiled import Env
from gpp.runtime.contract import EventQueue, ExogFunctionChanged, ExogOccurrence
from gpp.runtime.control import Executor, Happening, RunControl, RunStopped, request_attention
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import (
    DONE,
    Code,
    DoStep,
    EndKind,
    EndStep,
    Frame,
    Planned,
    PlanStep,
    Prog,
    ReplanStep,
    Rest,
    Seq,
    StartStep,
    Step,
)
from gpp.runtime.values import Value, show
from gpp.syntax import ast

T = TypeVar("T")

# How many calls a stop between transitions enters at most to show where the next transition
# is (a recursion that deep before its first transition is shown from its outermost calls).
MAX_ENTERED = 100

# What a stop's description adds on a platform whose time does not stand still.
REAL_TIME_NOTE = "the agent holds, but activities already started go on running on the robot"


@dataclass
class _Job:
    do: Callable[[], Any]
    done: threading.Event
    result: Any = None
    error: BaseException | None = None


@dataclass(frozen=True)
class _Resume:
    how: Resumption
    # Set once the run went on.
    done: threading.Event


class _Terminate:
    pass


class LiveBackend(RunControl, SessionBackend):
    """A debugging session of a live run (see the module docstring)."""

    def __init__(self, client: Client, breakpoints: Breakpoints, check: CheckResult, run: Callable[[], int]) -> None:
        self.client = client
        self.breakpoints = breakpoints
        self.check = check
        # Made when the run starts, over the run's own compiled program (its fluent slots).
        self.program: DebugProgram = cast(DebugProgram, None)
        self._run = run
        self._jobs: queue.Queue[_Job | _Resume | _Terminate] = queue.Queue()
        self._thread: threading.Thread | None = None
        # Set once the run reached its first transition (`started`) or ended before it.
        self.ready = threading.Event()
        self.setup_error: str | None = None
        self._go = threading.Event()
        self._stop_on_entry = False
        # Stop on entry at the first transition (or where the program waits before it).
        self._entry = False
        # The calls of the run's continuations (made when the run starts).
        self.stacks: CallStacks = cast(CallStacks, None)
        self._held = False
        self._terminating = False
        self._ended_run = False
        # Where the last stop was (statement, depth), and whether no transition was made since.
        self._from: tuple[int, int] | None = None
        self._fresh = False
        self._pause = False
        self._mode: Resumption | None = None
        self._depth = 0
        self.executor: Executor | None = None
        self.prog: Prog = DONE
        # What remained of the program at the last checkpoint (where a happening is shown).
        self.last_prog: Prog = DONE
        # `noDebug`: the run goes on without stopping.
        self.no_debug = False
        self.frames: list[CallFrame] = []
        self.handles = Handles()
        self.started_at: dict[int, float] = {}
        self.exit_code = 0
        self.ended = threading.Event()

    # ---------------------------------------------------------------- the session

    def launch(self) -> None:
        """Start the run's thread; it holds at the first transition until `start`."""
        self._thread = threading.Thread(target=self._thread_main, name="gpp-dap-run", daemon=True)
        self._thread.start()
        self.ready.wait()

    def _thread_main(self) -> None:
        try:
            self.exit_code = self._run()
        except BaseException as e:
            self.exit_code = 1
            self.setup_error = str(e) or type(e).__name__
        finally:
            self.ready.set()
            self.ended.set()
            self._held = False
            if self.executor is not None:  # a run that could not start is the launch's error
                self.client.ended(self.exit_code)

    def start(self, stop_on_entry: bool) -> None:
        self._stop_on_entry = stop_on_entry
        self._go.set()

    def stopped(self) -> bool:
        return self._held

    def terminate(self) -> None:
        self._terminating = True
        self._go.set()
        if self._held:
            self._jobs.put(_Terminate())
        elif self.executor is not None and not self.ended.is_set():
            request_attention(self.executor.platform.queue, self.executor.platform.now())
        if self._thread is not None:
            self._thread.join(timeout=30)

    def pause(self) -> None:
        if self._held or self.ended.is_set():
            return
        self._pause = True
        if self.executor is not None:
            request_attention(self.executor.platform.queue, self.executor.platform.now())

    def resume(self, how: Resumption) -> Stop | None:
        # Answered once the run went on: the response comes before the next `stopped` event.
        job = _Resume(how, threading.Event())
        self._jobs.put(job)
        while not job.done.wait(0.05):
            if self.ended.is_set():
                return None
        return None  # a live run never stops without going on first

    # ---------------------------------------------------------------- questions (run's thread)

    def ask(self, do: Callable[[], T]) -> T:
        """`do()` in the run's thread while it holds."""
        if not self._held:
            raise DapError("the run is running: pause it first")
        job = _Job(do, threading.Event())
        self._jobs.put(job)
        job.done.wait()
        if job.error is not None:
            raise job.error
        return job.result  # type: ignore[no-any-return]

    def stack(self) -> list[StackFrame]:
        return [StackFrame(i, f.name(), f.span) for i, f in enumerate(self.frames)]

    def scopes(self, frame_id: int) -> list[Scope]:
        return self.ask(lambda: self._scopes(frame_id))

    def variables(self, reference: int) -> list[Variable]:
        return self.ask(lambda: self.handles.expand(reference))

    def evaluate(self, expression: str, frame_id: int | None, context: str) -> Evaluated:
        return self.ask(lambda: self._evaluate(expression, frame_id))

    # ---------------------------------------------------------------- the run control (run's thread)

    def started(self, executor: Executor, prog: Prog) -> None:
        self.program = DebugProgram(self.check, executor.program)
        self.stacks = CallStacks(executor.program)
        self.executor = executor
        self.last_prog = prog
        self.ready.set()
        self._go.wait()
        self.end_if_asked()
        self.note_activities(executor)
        # Stopping on entry is stopping before the first transition (see `stepping`).
        self._entry = self._stop_on_entry and not self.no_debug

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        self.end_if_asked()
        self.last_prog = prog
        if self.no_debug:
            return
        self.note_activities(executor)
        if self._entry and getattr(executor, "blocked", False):
            # The program waits before its first transition: stop on entry where it waits.
            self._entry = False
            self.hold(executor, prog, self.frames_of(executor, prog), Stop("entry", "stopped on entry"), between=True)
        if self._pause:
            self._pause = False
            self.hold(executor, prog, self.frames_of(executor, prog), Stop("pause", "paused"), between=True)

    def stepping(self, executor: Executor, prog: Prog, step: Step, after: Prog) -> None:
        """Every stop of a transition is before it, at its statement, inside the calls it is
        in (gpp.runtime.callstack, as the trace's `step` records): a procedure call is no
        transition of its own, so a breakpoint on a call line stops at the first transition
        of that call, inside the callee."""
        self.end_if_asked()
        self.last_prog = after
        if self.no_debug:
            return
        stmt = self.statement_of(step)
        if stmt is None:
            return
        span = step.session.stmt.span if isinstance(step, PlanStep | ReplanStep) else step.span
        calls = self.stacks.step_calls(prog, after, span)
        frames = self.stack_of(executor, calls, stmt, prog, after)
        if self._entry:
            self._entry = False
            self.hold(executor, prog, frames, Stop("entry", "stopped on entry"))
            return
        if self._fresh:  # the first transition after a stop between transitions begins there
            self._fresh = False
            if _place(frames) == self._from:
                return
        stop = self.breakpoint_stop(executor, step, frames, calls)
        if stop is None and self._mode in ("next", "stepIn", "stepOut") and _is_statement_step(step):
            depth = len(frames)
            if (
                self._mode == "stepIn"
                or (self._mode == "next" and depth <= self._depth)
                or (self._mode == "stepOut" and depth < self._depth)
            ):
                stop = Stop("step")
        if stop is not None:
            self.hold(executor, prog, frames, stop)

    def happened(self, executor: Executor, prog: Prog | None, happening: Happening) -> None:
        if happening.kind not in self.breakpoints.exceptions or self._terminating or self.no_debug:
            return
        label = {"failed": "action failed", "blocked": "program blocked", "error": "run-time error"}.get(
            happening.kind, "no plan"
        )
        at = prog if prog is not None else self.last_prog
        self.hold(
            executor, at, self.frames_of(executor, at), Stop("exception", happening.description, label), between=True
        )

    def attend(self, executor: Executor) -> None:
        self.end_if_asked()

    def end_if_asked(self) -> None:
        """End the run if the editor asked to (once: the run's clean-up, which cancels the
        activities, goes through the control's hooks again)."""
        if self._terminating and not self._ended_run:
            self._ended_run = True
            raise RunStopped("the debugger ended the run")

    def note_activities(self, executor: Executor) -> None:
        """The platform time each activity was first seen running (its start, to the step)."""
        records = getattr(executor, "records", {})
        if len(records) != len(self.started_at):
            now = executor.platform.now()
            for activity in records.values():
                self.started_at.setdefault(activity.id, now)

    # ---------------------------------------------------------------- stopping

    def frames_of(self, executor: Executor, prog: Prog) -> list[CallFrame]:
        """The stack between two transitions: the calls of `prog` (gpp.runtime.callstack) at
        the statement the next transition can come from (pieces that may end where they are
        are passed over, as `trans` passes over them)."""
        view, first = prog, None
        for _ in range(MAX_ENTERED):  # a call is no transition: the stop is inside the callee
            entering = self.entered(executor, view)
            if entering is None:
                break
            view = entering[0]
            first = first or entering[1]
        head = self.head_of(executor, view)
        if head is None:
            return []
        calls = self.stacks.calls(view)
        outer = self.stacks.calls(prog)
        if (
            first is not None
            and outer
            and calls
            and (calls[-1].procedure, calls[-1].args)
            != (
                outer[-1].procedure,
                outer[-1].args,
            )
        ):
            # The caller, at the call it began, also when nothing of it is left after the call.
            at = calls[-1] if calls[-1].at is not None else replace(calls[-1], at=first)
            calls = (*calls[:-1], at, *outer)
        return self.stack_of(executor, calls, head[0], view, view)

    def statement_of(self, step: Step) -> ast.Statement | None:
        """The statement a transition executes (a `solve`'s planning: the `solve`)."""
        if isinstance(step, PlanStep | ReplanStep):
            return step.session.stmt
        return self.program.statement_of(step.span)

    def head_of(self, executor: Executor, prog: Prog) -> tuple[ast.Statement, Prog] | None:
        """The statement the next transition of `prog` comes from, and the piece that holds it."""
        for e in elements(prog, self.program):
            if e.piece is not None and may_end(executor, e.piece):
                continue
            stmt = e.stmt if e.stmt is not None else self.program.statement_of(e.span)
            return (stmt, e.piece or prog) if stmt is not None else None
        return None

    def stack_of(
        self, executor: Executor, calls: tuple[Call, ...], stmt: ast.Statement, prog: Prog, after: Prog
    ) -> list[CallFrame]:
        """The stack of calls `calls` (innermost first), the innermost at `stmt`: each caller
        at its call statement. The innermost call's bindings are those `stmt` sees (a `pick`
        binds its variable in the transition that runs its body's first statement, and inside a
        `solve` they are the executed policy's)."""
        out: list[CallFrame] = []
        for i, call in enumerate(calls):
            if i == 0:
                frame = call.frame
                if frame is None or not sees(frame, self.program, stmt):
                    found = (
                        e.frame
                        for p in (after, prog)
                        for e in elements(p, self.program)
                        if e.frame is not None and sees(e.frame, self.program, stmt)
                    )
                    frame = next(found, frame)
                head = self.head_of(executor, prog)
                outer = head[0] if head is not None else None
                contains = outer is not None and outer is not stmt and _inside(stmt, outer)
                out.append(
                    CallFrame(call.procedure, frame or Frame(), stmt.span, stmt, None, head=outer if contains else None)
                )
                continue
            at = calls[i - 1].at
            out.append(CallFrame(call.procedure, call.frame or Frame(), at.span if at else None, at, None))
        return out

    def breakpoint_stop(
        self, executor: Executor, step: Step, frames: list[CallFrame], calls: tuple[Call, ...]
    ) -> Stop | None:
        """The stop of the line or function breakpoints at this transition, if one stops
        (logpoints print and go on): a line breakpoint on its statement (or on the `if` or
        `while` it starts from) or on the call statement of a call it begins; a function
        breakpoint on a procedure a call of which it begins, or on the action it starts."""
        if not frames:
            return None
        table = self.breakpoints
        top = frames[0]
        ids: list[int] = []
        statements = [top.stmt, top.head] if _is_statement_step(step) else []
        statements += [c.at for c in calls if c.entered]
        for stmt in statements:
            if stmt is not None:
                ids.extend(b.id for b in table.at_statement(stmt) if self.passes(executor, b, top))
        function_ids: list[int] = []
        if table.functions:
            names = [c.procedure.name for c in calls if c.entered]
            if isinstance(step, StartStep | DoStep):
                names.append(step.action.name)
            for name in names:
                b = table.functions.get(name)
                if b is not None and self.passes(executor, b, top):
                    function_ids.append(b.id)
        if ids:
            return Stop("breakpoint", "breakpoint hit", None, tuple(ids + function_ids))
        if function_ids:
            return Stop("function breakpoint", "a call of a function breakpoint starts", None, tuple(function_ids))
        return None

    def passes(self, executor: Executor, b: Any, at: CallFrame) -> bool:
        """Does breakpoint `b` stop here (its condition, then its hit count)? A logpoint prints
        and does not stop."""
        env = Env(executor.state, at.frame.vars, executor.sem.ctx)
        if b.condition is not None:
            try:
                if evaluated(b.condition, env) is not True:
                    return False
            except DapError as err:
                self.client.output(f"breakpoint condition `{b.condition.text}`: {err}\n", "stderr", at.span)
                return True
        b.hits += 1
        if b.hit_condition is not None and not b.hit_condition.holds(b.hits):
            return False
        if b.log is not None:
            text = "".join(p if isinstance(p, str) else self.shown(p, env) for p in b.log_parts)
            self.client.output(text + "\n", "console", at.span)
            return False
        return True

    @staticmethod
    def shown(expression: CheckedExpression, env: Env) -> str:
        try:
            return show(evaluated(expression, env))
        except DapError as e:
            return f"<{e}>"

    def entered(self, executor: Executor, prog: Prog) -> tuple[Prog, ast.CallStmt, Prog] | None:
        """`prog` with its next statement, a procedure call, replaced by the callee's body with
        its arguments bound (the same continuation, seen from inside the callee), that call,
        and the callee's body; None when the next statement is no procedure call."""
        sem = executor.sem
        calls: list[tuple[ast.CallStmt, Prog]] = []

        def inside(p: Prog) -> Prog | None:
            """Pieces that may end here are passed over: the next transition comes after them."""
            if isinstance(p, Seq):
                first = inside(p.first)
                if first is None:
                    return inside(p.rest) if may_end(executor, p.first) else None
                return sem.seq(first, p.rest)
            if isinstance(p, Rest) and p.index < len(p.block.body):
                head = Code(p.block.body[p.index], p.frame)
                rest: Prog = Rest(p.block, p.index + 1, p.frame) if p.index + 1 < len(p.block.body) else DONE
                body = inside(head)
                if body is None:
                    return inside(rest) if may_end(executor, head) else None
                return sem.seq(body, rest)
            if isinstance(p, Code):
                s = p.stmt
                if isinstance(s, ast.Block) and s.body:
                    return inside(Rest(s, 0, p.frame))
                if isinstance(s, ast.CallStmt):
                    callee = sem.callee(s)
                    if callee.kind is SymbolKind.PROCEDURE:
                        callee_body, callee_frame = sem.procedure_body(s, callee.name, executor.state, p.frame)
                        entered = Code(callee_body, callee_frame)
                        calls.append((s, entered))
                        return entered
            return None

        try:
            found = inside(prog)
        except GppRuntimeError:
            return None
        return (found, *calls[0]) if found is not None else None

    def hold(self, executor: Executor, prog: Prog, frames: list[CallFrame], stop: Stop, between: bool = False) -> None:
        """Hold the run, stopped at `prog` with the stack `frames`, until the editor says how to
        go on; meanwhile do the protocol loop's questions. `between`: stopped between two
        transitions (on entry, paused, at a happening), where the next transition begins."""
        self.end_if_asked()
        self.prog = prog
        self.frames = frames
        self.handles.reset()
        if not getattr(executor.platform, "virtual_time", True):
            stop = Stop(stop.reason, f"{stop.description} ({REAL_TIME_NOTE})", stop.text, stop.breakpoint_ids)
        self._held = True
        self.client.stopped(stop)
        try:
            while True:
                job = self._jobs.get()
                if isinstance(job, _Terminate):
                    self.end_if_asked()
                    continue
                if isinstance(job, _Resume):
                    self._mode = job.how
                    self._depth = len(self.frames)
                    self._from = _place(self.frames)
                    self._fresh = between
                    self._held = False
                    job.done.set()
                    return
                try:
                    job.result = job.do()
                except BaseException as e:
                    job.error = e
                finally:
                    job.done.set()
        finally:
            self._held = False

    # ---------------------------------------------------------------- what a stop shows

    def frame_at(self, frame_id: int | None) -> CallFrame | None:
        if not self.frames:
            return None
        i = 0 if frame_id is None else frame_id
        if not 0 <= i < len(self.frames):
            raise DapError(f"there is no stack frame {i}")
        return self.frames[i]

    def _scopes(self, frame_id: int) -> list[Scope]:
        executor = self.executor
        assert executor is not None
        frame = self.frame_at(frame_id)
        out: list[Scope] = []
        if frame is not None:
            params = [(p.name, frame.frame.vars[id(p)]) for p in frame.procedure.params if id(p) in frame.frame.vars]
            param_ids = {id(p) for p in frame.procedure.params}
            local_symbols = [s for s in self.program.visible(frame.stmt) if id(s) not in param_ids]
            local = [(s.name, frame.frame.vars[id(s)]) for s in local_symbols if id(s) in frame.frame.vars]
            out.append(values_scope(self.handles, "Arguments", params, "arguments"))
            out.append(values_scope(self.handles, "Locals", local, "locals"))
        out.append(fluent_scope(self.handles, executor.program, executor.state))
        out.append(activity_scope(self.handles, executor.acts, getattr(executor, "records", {}), self.started_at))
        planned = next((f.planned for f in self.frames if f.planned is not None), None)
        if planned is None:
            planned = _planned_in(self.prog)
        if planned is not None:
            out.append(plan_scope(self.handles, planned))
        pending = pending_events(executor.platform.queue)
        out.append(Scope("Exogenous events", self.handles.add(lambda: pending), count=len(pending)))
        return out

    def _evaluate(self, expression: str, frame_id: int | None) -> Evaluated:
        executor = self.executor
        assert executor is not None
        frame = self.frame_at(frame_id)
        try:
            checked = self.program.expression(expression, frame.stmt if frame is not None else None)
        except ExpressionError as e:
            raise DapError(str(e)) from None
        env = Env(executor.state, frame.frame.vars if frame is not None else {}, executor.sem.ctx)
        value = evaluated(checked, env)
        v = value_variable(self.handles, "", value, checked.type, expression)
        return Evaluated(v.value, v.type, v.reference)


def may_end(executor: Executor, piece: Prog) -> bool:
    """`final` of a piece of the continuation in the run's situation (an error: it may not)."""
    try:
        return executor.sem.final(piece, executor.state, executor.acts)
    except GppRuntimeError:
        return False


def evaluated(expression: CheckedExpression, env: Env) -> Value:
    """An expression's value; DapError with the run-time error's message, or when a variable it
    reads has no value yet (a `pick` that binds it in the transition about to be made)."""
    try:
        return expression.evaluate(env)
    except GppRuntimeError as e:
        raise DapError(e.message) from None
    except KeyError:
        raise DapError("a variable of this expression has no value at this point yet") from None


def _inside(stmt: ast.Statement, outer: ast.Statement) -> bool:
    """Is `stmt` inside statement `outer` (an `if` or `while` whose test is no transition)?"""
    a, b = stmt.span, outer.span
    return a.source is b.source and b.start <= a.start and a.end <= b.end


def _place(frames: list[CallFrame]) -> tuple[int, int] | None:
    """Where a stack is: its innermost statement and its depth."""
    return (id(frames[0].stmt), len(frames)) if frames and frames[0].stmt is not None else None


def _is_statement_step(step: Step) -> bool:
    """A transition that executes a statement (not the end of a call or `during` whose start
    was its statement's, nor a re-planning)."""
    if isinstance(step, EndStep):
        return step.hook not in (EndKind.CALL, EndKind.DURING)
    return not isinstance(step, ReplanStep)


def _planned_in(p: Prog) -> Planned | None:
    while isinstance(p, Seq):
        p = p.first
    return p if isinstance(p, Planned) else None


def pending_events(queue: EventQueue) -> list[Variable]:
    """The exogenous events the platform reported that the program has not taken in yet."""
    out: list[Variable] = []
    for t, e in queue.pending():
        if isinstance(e, ExogOccurrence):
            out.append(Variable(f"{t:.3f} s", f"{e.action}({', '.join(show(a) for a in e.args)})", "exogenous action"))
        elif isinstance(e, ExogFunctionChanged):
            out.append(Variable(f"{t:.3f} s", f"{e.function}(...) has a new answer", "exogenous function"))
    return out


def check_errors(diagnostics: list[diag.Diagnostic]) -> str:
    """The first error of a program that does not check, and how many there are."""
    errors = [d for d in diagnostics if d.is_error]
    first = errors[0]
    where = f"{first.span}: " if first.span is not None else ""
    more = (
        f" (and {len(errors) - 1} more error{'s' if len(errors) > 2 else ''}: run `gpp check`)"
        if len(errors) > 1
        else ""
    )
    return f"the program does not check: {where}{first.message}{more}"
