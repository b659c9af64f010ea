"""The trace backend: `launch` with `"trace"` replays a recorded run (gpp.traceview.replay) with
stepping both ways (`stepBack`, `reverseContinue`), breakpoints (line, conditional, hit counts,
logpoints, functions, the run's error or block) and the same views as a live run: the stack,
the parameters and locals, the fluents, the activities, the plan, evaluate.

The program is the one the trace's header names (as the run was given it: relative to `cwd`,
else to the trace's folder), checked and compiled as `gpp run` does; the fluent values at a
position are the trace's, on top of the program's initial values. What the trace cannot show
(a trace without steps, an old schema) is said in the debug console at launch and under the
`Run` scope.

Arguments: `trace` (the trace file, the first part of a split trace, or its folder), `cwd`,
`stopOnEntry` (stop at the start of the recording; otherwise the replay runs to the first
breakpoint, or to the end of the recording)."""

from __future__ import annotations

import hashlib
from pathlib import Path

from gpp.base.source import Span
from gpp.dap.backend import (
    Capabilities,
    Client,
    Evaluated,
    Host,
    Resumption,
    Scope,
    SessionBackend,
    StackFrame,
    Stop,
    StopReason,
    Variable,
)
from gpp.dap.breakpoints import Breakpoint, Breakpoints, stops
from gpp.dap.program import DebugProgram, ExpressionError
from gpp.dap.protocol import DapError, Message
from gpp.dap.variables import Handles, fluent_scope, value_variable, values_scope
from gpp.model.symbols import SymbolKind
from gpp.model.types import Type
from gpp.runtime.compiled import CompiledProgram, Env
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.events import JsonValue, StepEvent, UpdateEvent
from gpp.runtime.state import State
from gpp.runtime.values import Value, from_json, show_json
from gpp.syntax import ast
from gpp.traceview.model import TraceReadError
from gpp.traceview.replay import Replay, ReplayState

ARGUMENTS = {"trace", "cwd", "stopOnEntry", "noDebug"}


class _ReplayContext:
    """Evaluation at a recorded position: the clock is the position's time; an exogenous
    function's answer is not in the trace."""

    def __init__(self, now: float) -> None:
        self._now = now

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        from gpp.codes import R0007

        raise GppRuntimeError(R0007.exog_function_failed(name, "its answers are not in the trace"), span)

    def now(self) -> float:
        return self._now

    def wake_at(self, t: float) -> None:
        pass


class TraceBackend(SessionBackend):
    """A debugging session of a recorded run."""

    capabilities = Capabilities(step_back=True)

    def __init__(self, client: Client, breakpoints: Breakpoints, replay: Replay, program: DebugProgram) -> None:
        self.client = client
        self.breakpoints = breakpoints
        self.replay = replay
        self.program = program
        self.compiled: CompiledProgram = program.compiled
        self.handles = Handles()
        self.index = 0
        self.view: ReplayState = replay.state(0)
        self._state: State | None = None
        self._started = False
        self._ended = False
        # location text -> its statement (None: not a statement of the program).
        self._statements: dict[str, ast.Statement | None] = {}
        # The trace's program path and where the program was found (relative locations).
        self.base: Path | None = None
        self._paths: dict[str, str] = {}

    # ---------------------------------------------------------------- the session

    def start(self, stop_on_entry: bool) -> None:
        self._started = True
        if stop_on_entry:
            self.go_to(0)
            self.client.stopped(Stop("entry", self.describe("the start of the recorded run")))
            return
        self.client.stopped(self.move(-1, 1, 0, run=True))

    def stopped(self) -> bool:
        return self._started and not self._ended

    def pause(self) -> None:
        """A replay is always stopped between requests."""

    def terminate(self) -> None:
        if self._ended:
            return
        self._ended = True
        self.replay.close()
        self.client.ended(0)

    def resume(self, how: Resumption) -> Stop | None:
        replay, index = self.replay, self.index
        forward, backward = index < replay.last, index > 0
        match how:
            case "stepIn":
                return self.move(index, 1, replay.forward(index) if forward else None)
            case "next":
                return self.move(index, 1, replay.forward(index, over=True) if forward else None)
            case "stepOut":
                return self.move(index, 1, replay.forward(index, out=True) if forward else None)
            case "stepBack":
                return self.move(index, -1, replay.backward(index) if backward else None)
            case "continue":
                return self.move(index, 1, index + 1 if forward else None, run=True)
            case "reverseContinue":
                return self.move(index, -1, index - 1 if backward else None, run=True)
        raise DapError(f"`{how}` is not a way to go on")

    # ---------------------------------------------------------------- moving

    def move(self, index: int, direction: int, target: int | None, run: bool = False) -> Stop:
        """Go from `index` to `target` (with `run`, on to the end or the start of the recording
        that way), stopping earlier at a breakpoint on the way (the target's own included);
        the stop to report. No target: there is nothing more that way."""
        if target is None:
            self.go_to(max(index, 0))
            return Stop("step", self.describe(self.edge(direction)))
        end = target if not run else (self.replay.last if direction > 0 else 0)
        q = index + direction
        while (q <= end) if direction > 0 else (q >= end):
            hit = self.hit(q)
            if hit is not None:
                self.go_to(q)
                reason, ids, text = hit
                return Stop(reason, self.describe(text), text if reason == "exception" else None, ids)
            q += direction
        self.go_to(end)
        return Stop("step", self.describe(self.edge(direction) if run else ""))

    def edge(self, direction: int) -> str:
        return "the end of the recorded run" if direction > 0 else "the start of the recorded run"

    def go_to(self, index: int) -> None:
        self.index = index
        self.view = self.replay.state(index)
        self._state = None
        self.handles.reset()

    def hit(self, q: int) -> tuple[StopReason, tuple[int, ...], str] | None:
        """The breakpoints that stop at position `q`: (reason, ids, what), or None."""
        table = self.breakpoints
        position = self.replay.position(q)
        ids: list[int] = []
        reason: StopReason = "breakpoint"
        stmt = self.statement(position.location)
        for b in table.at_statement(stmt) if stmt is not None else ():
            if self.passes(b, q, stmt):
                ids.append(b.id)
        for call in self.calls_begun(q) if table.by_statement and not position.continues else ():
            # A call is no transition of its own: its line's breakpoint stops at its first one.
            for b in table.at_statement(call):
                if self.passes(b, q, stmt):
                    ids.append(b.id)
        functions = table.functions
        if functions:
            for name in (position.started, position.procedure):
                b2 = functions.get(name) if name is not None else None
                if b2 is None:
                    continue
                symbol = self.program.model.globals.get(b2.name)
                entered = (
                    self.replay.enters(b2.name)(q)
                    if symbol is not None and symbol.kind is SymbolKind.PROCEDURE
                    else self.replay.starts(b2.name)(q)
                )
                if entered and self.passes(b2, q, stmt):
                    ids.append(b2.id)
                    reason = "function breakpoint"
        if ids:
            return reason, tuple(ids), "breakpoint hit" if reason == "breakpoint" else "call of a function breakpoint"
        if position.failed and "failed" in table.exceptions:
            failed = [e.action for e in self.replay.before(q) if isinstance(e, UpdateEvent) and e.status == "failed"]
            return "exception", (), f"`{'`, `'.join(failed)}` failed"
        if position.no_plan and "no-plan" in table.exceptions:
            return "exception", (), "`solve` or `search` found no feasible plan"
        if position.kind in ("error", "blocked") and position.kind in table.exceptions:
            record = self.replay.record(q)
            message = str(getattr(record, "message", position.kind))
            return "exception", (), message
        return None

    def calls_begun(self, q: int) -> list[ast.Statement]:
        """The call statements of the calls position `q`'s step begins: its calls (innermost
        first) that the step before it was not in, compared from the entry procedure inwards."""
        record = self.replay.record(q)
        if not isinstance(record, StepEvent) or not record.frames:
            return []
        before: tuple[dict[str, JsonValue], ...] = ()
        if q > 0:
            previous = self.replay.record(q - 1)
            before = previous.frames if isinstance(previous, StepEvent) else ()
        frames = record.frames
        same = 0
        while same < min(len(frames), len(before)) and _call(frames[-1 - same]) == _call(before[-1 - same]):
            same += 1
        found = []
        for frame in frames[: len(frames) - same]:
            at = frame.get("at")
            stmt = self.statement(at) if isinstance(at, str) else None
            if stmt is not None:
                found.append(stmt)
        return found

    def passes(self, b: Breakpoint, q: int, stmt: ast.Statement | None) -> bool:
        """Does breakpoint `b` stop at position `q` (its condition in that position's state,
        then its hit count)? A logpoint prints and does not stop."""
        if b.condition is None and b.hit_condition is None and b.log is None:
            return True
        span = stmt.span if stmt is not None else None
        return stops(b, self.env(self.replay.state(q), 0), self.client.output, span)

    def describe(self, what: str = "") -> str:
        """A stop's description: where in the recording, and what happens next there."""
        upcoming = self.upcoming()
        head = f"{what}: " if what else ""
        return (
            f"{head}position {self.index + 1} of {len(self.replay)} at {self.view.t:.3f} s, next: {upcoming}"
            " (recorded run)"
        )

    def upcoming(self) -> str:
        """What happens next at the stop: its step, or (a trace without steps) its record in
        the words of `gpp run`'s event lines."""
        if self.replay.stepped and self.view.step is not None:
            return self.view.step
        from gpp.run.view import describe

        record = self.replay.record(self.index)
        said = describe(record)
        if said is None:  # a record `gpp run` does not print (a final update, a resumed wait)
            said = " ".join(str(getattr(record, f, None) or "") for f in ("EVENT", "action", "status"))
        return " ".join(said.split())

    # ---------------------------------------------------------------- the state

    def state(self) -> State:
        """The position's fluent values as a state of the compiled program."""
        if self._state is None:
            self._state = self.state_of(self.view)
        return self._state

    def state_of(self, view: ReplayState) -> State:
        updates: dict[int, Value] = {}
        for text, value in view.fluents.items():
            slot = self.slot(text)
            if slot is not None:
                updates[slot] = from_json(value)
        return State().updated(updates, self.compiled.initial)

    def slot(self, instance: str) -> int | None:
        """The fluent slot of an instance as the trace writes it (`loc(a)`), read by the
        program's own front end."""
        try:
            checked = self.program.expression(instance, None)
        except ExpressionError:
            return None
        expr = checked.expr
        if not isinstance(expr, ast.Call):
            return None
        symbol = self.program.model.target(expr)
        if symbol is None or symbol.kind is not SymbolKind.FLUENT:
            return None
        env = Env(State(), {}, _ReplayContext(0.0))
        try:
            args = tuple(self.compiled.expr(a)(env) for a in expr.args)
        except GppRuntimeError:
            return None
        return self.compiled.slot(symbol.name, args)

    def statement(self, location: str | None) -> ast.Statement | None:
        """The program's statement at a location of the trace (`FILE:LINE:COL`)."""
        if location is None:
            return None
        if location in self._statements:
            return self._statements[location]
        found: ast.Statement | None = None
        parts = location.rsplit(":", 2)
        if len(parts) == 3 and parts[1].isdigit() and parts[2].isdigit():
            path = self.resolve(parts[0])
            line, col = int(parts[1]), int(parts[2])
            first = self.program.statement_at(path, line)
            if first is not None and first.span.line == line:
                from gpp.dap.program import _file_key

                same = [s for ln, _, s in self.program.by_file.get(_file_key(path), []) if ln == line]
                found = next((s for s in same if s.span.col == col), first)
        self._statements[location] = found
        return found

    def resolve(self, path: str) -> str:
        """A path of the trace as a path here. A relative one (the run writes a file under its
        working folder relative to it) is the program's file whose path ends with it, else
        taken from where the program was found."""
        if Path(path).is_absolute():
            return path
        found = self._paths.get(path)
        if found is None:
            tail = Path(path).parts
            for file in self.program.check.loaded.files:
                whole = Path(file.source.path).resolve()
                if whole.parts[-len(tail) :] == tail:
                    found = str(whole)
                    break
            else:
                found = str(self.base / path) if self.base is not None else path
            self._paths[path] = found
        return found

    def frames(self) -> list[tuple[str, dict[str, JsonValue], dict[str, JsonValue], ast.Statement | None]]:
        """(name, arguments, locals, statement) of each call, innermost first."""
        stmt = self.statement(self.view.location)
        if not self.view.frames:
            procedure = self.program.procedure_of(stmt) if stmt is not None else None
            name = procedure.name if procedure is not None else "main"
            return [(name, {}, {}, stmt)]
        out: list[tuple[str, dict[str, JsonValue], dict[str, JsonValue], ast.Statement | None]] = []
        for i, frame in enumerate(self.view.frames):
            args = frame.get("args")
            local = frame.get("locals")
            at: ast.Statement | None = stmt
            if i > 0:
                called = self.view.frames[i - 1].get("at")
                at = self.statement(called) if isinstance(called, str) else None
            out.append(
                (
                    str(frame.get("procedure")),
                    args if isinstance(args, dict) else {},
                    local if isinstance(local, dict) else {},
                    at,
                )
            )
        return out

    def env(self, view: ReplayState, frame_id: int) -> Env:
        """The evaluation environment of call `frame_id` at a position."""
        state = self.state() if view is self.view else self.state_of(view)
        return Env(state, self.bindings(view, frame_id), _ReplayContext(view.t))

    def bindings(self, view: ReplayState, frame_id: int) -> dict[int, Value]:
        """The values of the parameters and locals of call `frame_id`, by variable identity."""
        if not view.frames or not 0 <= frame_id < len(view.frames):
            return {}
        frame = view.frames[frame_id]
        symbol = self.program.model.globals.get(str(frame.get("procedure")))
        if symbol is None:
            return {}
        args = frame.get("args")
        values: dict[int, Value] = {}
        if isinstance(args, dict):
            for p in symbol.params:
                if p.name in args:
                    values[id(p)] = from_json(args[p.name])
        local = frame.get("locals")
        if isinstance(local, dict) and local:
            stmt = self.statement(view.location) if frame_id == 0 else None
            for s in self.program.visible(stmt):
                if s.name in local and s.kind is SymbolKind.VARIABLE:
                    values[id(s)] = from_json(local[s.name])
        return values

    # ---------------------------------------------------------------- what a stop shows

    def stack(self) -> list[StackFrame]:
        out = []
        frames = self.frames()
        for i, (name, args, _, stmt) in enumerate(frames):
            shown = ", ".join(show_json(v) for v in args.values())
            suffix = f"({shown})" if self.view.frames else "  [calls not recorded]"
            if i == len(frames) - 1 and self.view.calls > len(frames):
                # A deep recursion: the trace lists its innermost calls and the entry procedure.
                left = self.view.calls - len(frames)
                out.append(StackFrame(len(frames), f"... {left} more calls (not in the trace)", None))
            out.append(StackFrame(i, f"{name}{suffix}", stmt.span if stmt is not None else None))
        return out

    def scopes(self, frame_id: int) -> list[Scope]:
        frames = self.frames()
        if not 0 <= frame_id < len(frames):
            raise DapError(f"there is no stack frame {frame_id}")
        _, args, local, _ = frames[frame_id]
        view = self.view
        out = [
            values_scope(self.handles, "Arguments", [(n, from_json(v)) for n, v in args.items()], "arguments"),
            values_scope(self.handles, "Locals", [(n, from_json(v)) for n, v in local.items()], "locals"),
            fluent_scope(self.handles, self.compiled, self.state()),
            self.activity_scope(view),
        ]
        if view.plan is not None and self.planning(view):
            out.append(self.plan_scope(view))
        out.append(self.run_scope(view))
        return out

    def activity_scope(self, view: ReplayState) -> Scope:
        def children() -> list[Variable]:
            return [
                Variable(a.action, f"{a.status}, started at {a.started:.3f} s", "activity")
                for a in view.activities.values()
            ]

        return Scope("Activities", self.handles.add(children), count=len(view.activities))

    def planning(self, view: ReplayState) -> bool:
        """Is the stop inside the `solve` or `search` that made the latest plan? (Without steps
        the trace does not say where that is: the latest plan is shown.)"""
        if view.plan_at is None:
            return not self.replay.stepped
        solve, here = self.statement(view.plan_at), self.statement(view.location)
        if solve is None or here is None:
            return False
        inner, outer = here.span, solve.span
        return inner.source is outer.source and outer.start <= inner.start and inner.end <= outer.end

    def plan_scope(self, view: ReplayState) -> Scope:
        plan = view.plan
        assert plan is not None

        def children() -> list[Variable]:
            out = [
                Variable("kind", f"{plan.kind} ({plan.EVENT} at {plan.t:.3f} s)"),
                Variable("feasible", "true" if plan.feasible else "false"),
                Variable("value", f"{plan.value:g}"),
                Variable("horizon", str(plan.horizon)),
                Variable("done", f"{view.plan_done} of {len(plan.policy)} steps started"),
            ]
            for i, step in enumerate(plan.policy):
                mark = "✓ " if i < view.plan_done else "→ " if i == view.plan_done else "  "
                out.append(Variable(f"{mark}{i + 1}", step, "step"))
            return out

        return Scope("Plan", self.handles.add(children), count=len(plan.policy) + 5)

    def run_scope(self, view: ReplayState) -> Scope:
        def children() -> list[Variable]:
            out = [
                Variable("position", f"{self.index + 1} of {len(self.replay)}"),
                Variable("time", f"{view.t:.3f} s"),
                Variable("next", self.upcoming()),
                Variable("actions started", str(view.actions)),
                Variable("failures", str(view.failures)),
                Variable("exogenous events", str(view.exog_events)),
            ]
            if view.waiting is not None:
                out.append(Variable("waiting for", str(view.waiting.get("condition", ""))))
            if view.stopped is not None:
                out.append(Variable("stopped", view.stopped))
            out.extend(Variable("not recorded", limit) for limit in self.replay.limits())
            out.append(Variable("not recorded", "the events the platform had queued and not yet delivered"))
            return out

        return Scope("Run", self.handles.add(children), count=None)

    def variables(self, reference: int) -> list[Variable]:
        return self.handles.expand(reference)

    def evaluate(self, expression: str, frame_id: int | None, context: str) -> Evaluated:
        frames = self.frames()
        i = frame_id if frame_id is not None else 0
        if not 0 <= i < len(frames):
            raise DapError(f"there is no stack frame {i}")
        try:
            checked = self.program.expression(expression, frames[i][3])
        except ExpressionError as e:
            raise DapError(str(e)) from None
        from gpp.dap.live import evaluated

        value = evaluated(checked, self.env(self.view, i))
        v = value_variable(self.handles, "", value, checked.type, expression)
        return Evaluated(v.value, v.type, v.reference)


def make_trace_backend(args: Message, server: Host) -> SessionBackend:
    """The backend of `launch` with `"trace"`."""
    from gpp.check import check_program
    from gpp.dap.launch import _path, _unknown
    from gpp.dap.live import check_errors

    _unknown(args, ARGUMENTS)
    cwd_text = args.get("cwd")
    cwd = Path(cwd_text) if isinstance(cwd_text, str) and cwd_text else Path.cwd()
    trace = _path(args, "trace", cwd)
    assert trace is not None
    if not trace.exists():
        raise DapError(f"launch's `trace`: no such file {trace}")
    try:
        replay = Replay.open(trace)
    except TraceReadError as e:
        raise DapError(f"launch's `trace`: {e}") from None
    header = replay.header
    if header is None:
        replay.close()
        raise DapError(
            "launch's `trace`: the trace has no header (schema 1.0): it does not say which program ran, "
            "so there is nothing to show its records in"
        )
    given = Path(header.program)
    candidates = [given] if given.is_absolute() else [cwd / given, trace.parent / given, trace.parent / given.name]
    program_path = next((c for c in candidates if c.is_file()), None)
    if program_path is None:
        replay.close()
        raise DapError(
            f"launch's `trace`: the program it recorded, {header.program}, is not there "
            f"(looked in {cwd} and {trace.parent}): set `cwd` to the folder the run started in"
        )
    try:
        check = check_program(program_path)
    except OSError as e:
        replay.close()
        raise DapError(f"cannot read {program_path}: {e.strerror}") from None
    if check.errors:
        replay.close()
        raise DapError(check_errors(check.diagnostics))
    backend = TraceBackend(server, server.breakpoints, replay, DebugProgram(check, CompiledProgram(check.model)))
    backend.base = program_path.parent if given.is_absolute() else _base(program_path, given)
    if hashlib.sha256(program_path.read_bytes()).hexdigest() != header.program_sha256:
        server.output(
            f"{program_path} changed since the run was recorded: its lines and declarations may not match the trace\n",
            "important",
        )
    for warning in replay.warnings:
        server.output(f"{warning}\n", "console")
    for limit in replay.limits():
        server.output(f"not in this trace: {limit}\n", "console")
    return backend


def _call(frame: dict[str, JsonValue]) -> tuple[JsonValue, ...]:
    """What tells one call of a `step` record from another: its procedure, arguments and call."""
    return frame.get("procedure"), frame.get("args"), frame.get("at")


def _base(found: Path, given: Path) -> Path:
    """The folder relative paths of the trace start from: `found` less the parts of `given`."""
    base = found
    for _ in given.parts:
        base = base.parent
    return base


__all__ = ["TraceBackend", "make_trace_backend"]
