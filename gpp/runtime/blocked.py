"""Why a program is blocked (SEMANTICS §4): the R0011 diagnostic that says what a continuation
that cannot step waits for, walking it as `trans` does (gpp.runtime.semantics). The executor
reports it when nothing can change the world any more, and as the place a run waited at when
it reaches its timeout."""

from __future__ import annotations

from dataclasses import dataclass
from typing import assert_never

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.codes import R0011
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import (
    AwaitEnd,
    Code,
    Conc,
    Done,
    DuringEnd,
    Frame,
    Planned,
    Prog,
    Rest,
    Semantics,
    Seq,
    Watch,
)
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.values import Value, show
from gpp.syntax import ast
from gpp.syntax.walk import walk

BLOCKED = R0011.PREFIX


def awaits_activity(d: diag.Diagnostic) -> bool:
    """Does the explanation say the program waits for an activity (to end, finish, fail...)?"""
    return d.message.startswith(R0011.AWAITS)


def why_blocked(sem: Semantics, p: Prog, state: State, acts: Activities) -> diag.Diagnostic | None:
    """What `p` waits for in `state` with `acts` (None: nothing to point at)."""
    return _Explanation(sem, state, acts).why(p)


@dataclass(frozen=True, slots=True)
class Wait:
    """What a program that cannot step waits for: the explanation, its kind (one of
    gpp.runtime.events.WAIT_REASONS), and for a planned activity the activity and the number
    of its step in the plan."""

    why: diag.Diagnostic | None
    reason: str
    action: GroundAction | None = None
    plan_step: int | None = None


def waits_for(sem: Semantics, p: Prog, state: State, acts: Activities) -> Wait:
    """`why_blocked`, with what kind of thing `p` waits for."""
    explanation = _Explanation(sem, state, acts)
    why = explanation.why(p)
    if explanation.awaited is not None:
        g, number = explanation.awaited
        return Wait(why, "activity", g, number)
    if why is None:
        return Wait(None, "event")
    message = why.message
    if message == R0011.test_false().text:
        reason = "test"
    elif message.startswith(R0011.PREFIX + "the precondition of"):
        reason = "precondition"
    elif awaits_activity(why):
        reason = "activity"
    elif message.endswith("found no plan"):
        reason = "no-plan"
    else:
        reason = "event"
    return Wait(why, reason)


class _Explanation:
    def __init__(self, sem: Semantics, state: State, acts: Activities) -> None:
        self.sem = sem
        self.program = sem.program
        self.state = state
        self.acts = acts
        # A planned activity it waits for, and the number of its step in the plan.
        self.awaited: tuple[GroundAction, int] | None = None

    def why(self, p: Prog) -> diag.Diagnostic | None:
        sem, state, acts = self.sem, self.state, self.acts
        match p:
            case Seq():
                if sem.final(p.first, state, acts):
                    return self.why(p.first) or self.why(p.rest)
                return self.why(p.first)
            case Rest():
                for s in p.block.body[p.index :]:
                    why = self.why(Code(s, p.frame))
                    if why is not None or not sem.final(Code(s, p.frame), state, acts):
                        return why
                return None
            case Conc():
                for b in p.branches:
                    why = self.why(b)
                    if why is not None:
                        return why
                return None
            case AwaitEnd() | DuringEnd() | Watch():
                return self.waiting(p.action, p.span, "to end")
            case Planned():
                stmt = p.session.stmt
                awaited = p.session.awaited(p, acts)
                if awaited is not None:
                    g, number, span = awaited
                    self.awaited = g, number
                    status = acts.status(g)
                    return diag.error(
                        R0011.awaits_planned(g.text, number),
                        span,
                        f"`{g.text}` is {status.value if status is not None else 'not started'}",
                    )
                return diag.error(
                    R0011.no_plan(stmt.__class__.__name__.lower()),
                    stmt.span,
                    "no feasible plan from the current state",
                    notes=[
                        "every branch within the horizon has an impossible action or a false test"
                        if isinstance(stmt, ast.Solve)
                        else "every way to execute it meets an impossible action or a false test"
                    ],
                )
            case Code():
                return self.why_code(p.stmt, p.frame)
            case Done():
                return None
            case _:
                assert_never(p)

    def why_code(self, s: ast.Statement, frame: Frame) -> diag.Diagnostic | None:
        sem, state = self.sem, self.state
        match s:
            case ast.Block():
                return self.why(Rest(s, 0, frame)) if s.body else None
            case ast.Test():
                return diag.error(
                    R0011.test_false(),
                    s.span,
                    "waits for this condition",
                    notes=self.fluent_notes(s.condition, frame),
                )
            case ast.If():
                branch = s.then if sem.condition(s.condition, state, frame) else s.otherwise
                return self.why(Code(branch, frame)) if branch is not None else None
            case ast.While():
                return self.why(Code(s.body, frame))
            case ast.Choose():
                return self.why(Code(s.alternatives[0], frame)) if s.alternatives else None
            case ast.Pick():
                frames = sem.pick_frames(s, frame)
                return self.why(Code(s.body, frames[0])) if frames else None
            case ast.Concurrent():
                return self.why(Conc(tuple(Code(b, frame) for b in s.branches)))
            case ast.CallStmt():
                callee = sem.callee(s)
                if callee.kind.name == "PROCEDURE":
                    body, inner = sem.procedure_body(s, callee.name, state, frame)
                    return self.why(Code(body, inner))
                _, g = sem.ground_call(s.call, frame, state)
                return self.cannot_start(g, s.span)
            case ast.During():
                _, g = sem.ground_call(s.action, frame, state)
                return self.cannot_start(g, s.span)
            case ast.HookStmt():
                _, g = sem.ground_call(s.action, frame, state)
                if s.hook is ast.Hook.START:
                    return self.cannot_start(g, s.span)
                wanted = {"end": "to end", "finish": "to finish", "fail": "to fail", "cancel": "to be running"}
                return self.waiting(g, s.span, wanted[s.hook.value])
            case ast.Solve() | ast.Search() | ast.Assign() | ast.ListStmt():
                return None
            case _:
                assert_never(s)

    def waiting(self, g: GroundAction, span: Span, what: str) -> diag.Diagnostic:
        status = self.acts.status(g)
        shown = status.value if status is not None else "not started"
        return diag.error(
            R0011.awaits(g.text, what),
            span,
            f"`{g.text}` is {shown}",
        )

    def cannot_start(self, g: GroundAction, span: Span) -> diag.Diagnostic:
        if self.acts.status(g) is ActivityStatus.RUNNING:
            return self.waiting(g, span, "(already running) to end before it can start again")
        info = self.program.action(g.name)
        env_vars = dict(zip(info.param_ids, g.args, strict=True))
        false = self.sem.false_conjuncts(g, self.state)
        notes: list[str] = []
        for conjunct in false:
            used = _variables(conjunct)
            bound = ", ".join(f"{n} = {show(v)}" for n, v in zip(info.param_names, g.args, strict=True) if n in used)
            notes.append(f"false: `{_text(conjunct)}`" + (f" (with {bound})" if bound else ""))
            notes.extend(self.fluent_notes(conjunct, Frame(tuple(env_vars.items())), indent="  "))
        return diag.error(
            R0011.precondition_false(g.text),
            span,
            "cannot start",
            notes=notes,
        )

    def fluent_notes(self, e: ast.Expr, frame: Frame, indent: str = "") -> list[str]:
        """`loc(a) = table` for every fluent instance the expression reads."""
        notes: list[str] = []
        env = self.sem.env(self.state, frame)
        for node in walk(e):
            if isinstance(node, ast.Call) and not isinstance(node, ast.Quantified):
                symbol = self.program.model.target(node)
                if symbol is None or symbol.kind.name != "FLUENT":
                    continue
                try:
                    args = tuple(self.program.expr(a)(env) for a in node.args)
                except (GppRuntimeError, KeyError):
                    continue  # reads a quantified variable: not one instance
                if symbol.predefined and symbol.name == "context_time":
                    value: Value = self.sem.ctx.now()  # the clock, not a stored instance
                else:
                    value = self.program.read(self.state, symbol.name, args)
                text = f"{indent}{symbol.name}({','.join(show(a) for a in args)}) = {show(value)}"
                if text not in notes:
                    notes.append(text)
        return notes


def _variables(e: ast.Expr) -> set[str]:
    """The names of the variables (and symbols) an expression mentions."""
    return {node.name for node in walk(e) if isinstance(node, ast.Name)}


def _text(e: ast.Expr) -> str:
    return e.span.text
