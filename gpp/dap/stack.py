"""The call stack of a run, read from its continuation (gpp.runtime.semantics.Prog).

A procedure call has no frame of its own in the continuation: `trans` of a call is the
transition of the callee's body with the callee's bindings, so what remains of a call is the
rest of the callee's body followed by the rest of the caller's. The stack is recovered from
that sequence: each element belongs to the procedure whose body holds its statement, and a new
stack frame begins where the procedure, or its arguments' values, change. Inside a `solve` or
`search`, the elements are those of the executed policy's program at the current step, then
the `solve` itself in its procedure. A call that is the last statement of its caller leaves
nothing of the caller behind (a tail call): the caller is then not on the stack."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from gpp.base.source import Span
from gpp.dap.program import DebugProgram
from gpp.model.symbols import Symbol
from gpp.runtime.semantics import (
    DONE,
    AssignStep,
    AwaitEnd,
    Code,
    Conc,
    Done,
    DoStep,
    DuringEnd,
    Frame,
    Planned,
    Prog,
    Rest,
    Seq,
    StartStep,
    TestStep,
    Watch,
)
from gpp.runtime.values import show
from gpp.syntax import ast


@dataclass(frozen=True, slots=True)
class Element:
    """One piece of a continuation: the statement it is at (None: only its span is known), its
    bindings, and the `solve` being executed around it, if any."""

    stmt: ast.Statement | None
    span: Span
    frame: Frame | None
    planned: Planned | None = None
    # A Rest: the statement before it in its block (the call a caller's frame is at).
    before: ast.Statement | None = None
    # What remains of the program from here to the end of this piece (a Rest or a Code).
    piece: Prog | None = None


@dataclass(frozen=True, slots=True)
class CallFrame:
    procedure: Symbol
    frame: Frame
    # Where this call is: the next statement of the innermost frame, the call of the others.
    span: Span | None
    # The statement that scopes its expressions (evaluate, conditions).
    stmt: ast.Statement | None
    planned: Planned | None
    # Its bindings are not known yet (it waits for an activity: the rest of it tells them).
    unbound: bool = False
    # At a transition: the statement the transition starts from, when the transition's own
    # statement is inside it (an `if` or `while` whose test is no transition of its own).
    head: ast.Statement | None = None

    def name(self) -> str:
        args = ", ".join(show(self.frame.vars[id(p)]) for p in self.procedure.params if id(p) in self.frame.vars)
        return f"{self.procedure.name}({args})"


def elements(p: Prog, program: DebugProgram, planned: Planned | None = None) -> Iterator[Element]:
    """The pieces of continuation `p`, the next one to execute first."""
    while True:
        match p:
            case Done():
                return
            case Seq():
                yield from elements(p.first, program, planned)
                p = p.rest
                continue
            case Rest():
                if p.index < len(p.block.body):
                    stmt = p.block.body[p.index]
                    before = p.block.body[p.index - 1] if p.index > 0 else None
                    yield Element(stmt, stmt.span, p.frame, planned, before, p)
                return
            case Code():
                stmt = p.stmt
                while isinstance(stmt, ast.Block) and stmt.body:
                    stmt = stmt.body[0]
                yield Element(stmt, stmt.span, p.frame, planned, None, p)
                return
            case AwaitEnd() | DuringEnd():
                yield Element(None, p.span, None, planned)
                return
            case Watch():
                yield from elements(p.body, program, planned)
                yield Element(p.stmt, p.stmt.span, p.frame, planned)
                return
            case Conc():
                branch = next((b for b in p.branches if not isinstance(b, Done)), DONE)
                yield from elements(branch, program, planned)
                return
            case Planned():
                session = p.session
                yield from _policy_elements(p, program)
                stmt = session.stmt
                frame = getattr(session, "frame", None)
                yield Element(stmt, stmt.span, frame if isinstance(frame, Frame) else None, planned)
                return


def _policy_elements(p: Planned, program: DebugProgram) -> Iterator[Element]:
    """The elements of a `solve` being executed, at `p`'s step of its policy (the planner's
    PlanHolder): the statement of the planned step first (the policy's program before the
    step is still before the choices the step makes), then what remains after the step."""
    step_at = getattr(p.session, "step_at", None)
    if step_at is None or getattr(p.session, "policy", None) is None:
        return
    try:
        planned = step_at(p.index)
    except (AssertionError, IndexError):
        return
    if planned is None:
        return
    before, step, after = planned
    rest = list(elements(after, program, p))
    # A planned call whose activity runs (`calling`) is past its start: no breakpoint there.
    if isinstance(step, StartStep | DoStep | AssignStep | TestStep) and not p.calling:
        stmt = program.statement_of(step.span)
        if stmt is not None:
            frame = next((e.frame for e in rest if e.frame is not None and sees(e.frame, program, stmt)), None)
            if frame is None:
                frame = next((e.frame for e in elements(before, program, p) if e.frame is not None), None)
            yield Element(stmt, stmt.span, frame, p)
    else:
        found = program.statement_of(step.span)
        yield Element(None, step.span, None, p) if found is None else Element(None, found.span, None, p)
    yield from rest


def sees(frame: Frame, program: DebugProgram, stmt: ast.Statement) -> bool:
    """`frame` binds every variable visible at `stmt`."""
    return all(id(s) in frame.vars for s in program.visible(stmt))
