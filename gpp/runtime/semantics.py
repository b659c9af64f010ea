"""The transition semantics of golog++ (SEMANTICS §4, §5): `final` and `trans`, defined once
for every statement kind and used by both the online executor and the planner.

A configuration is a program continuation (a `Prog`), a State and the Activities. `trans`
returns the possible next steps as (continuation, Step) pairs, in textual order (the online
executor takes the first; the planner weighs them all). A `Step` says what happens to the
world: start or end an activity, assign fluents, pass a test. `Semantics.apply` performs a
step hypothetically (planning); the executor performs it for real (platform, clock, trace).

Two modes differ only where SEMANTICS says so: while planning (`planning=True`) an action
call `a(args);` is a single step whose activity ends instantly in `final`, `fail(...)` and
`cancel(...)` are impossible, and `solve`/`search` inside a plan are transparent; online, a
call starts an activity and waits for the platform, and `solve`/`search` ask the planner
given to the semantics, through the port `OnlinePlanner`/`PlanSession` (this module never
imports a planner).

Continuations (`Prog`) and steps (`Step`) are closed unions, so that a `match` over them can
end in `assert_never`, as a match over `ast.Statement` does.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Protocol, TypeAlias, assert_never

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.codes import R0002, R0005, R0006, R0008, R0010
from gpp.model.symbols import SymbolKind
from gpp.model.types import DomainType, ListType
from gpp.runtime.compiled import (
    ActionInfo,
    CompiledProgram,
    Context,
    Env,
    Evaluator,
    PathStep,
    check_domain,
    domain_values,
    ground,
)
from gpp.runtime.errors import GppRuntimeError, Unanswered
from gpp.runtime.planning import PlanReport
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.values import CompoundValue, Value, same, show
from gpp.syntax import ast

if TYPE_CHECKING:
    from gpp.model.symbols import Symbol
    from gpp.model.types import Type

# ---------------------------------------------------------------- bindings


class Frame:
    """Variable bindings of a procedure body, `pick` or quantifier: immutable, hashable."""

    __slots__ = ("_hash", "items", "vars")

    def __init__(self, items: tuple[tuple[int, Value], ...] = ()) -> None:
        self.items = items
        self.vars: dict[int, Value] = dict(items)
        self._hash = hash(items)

    def bind(self, var_id: int, value: Value) -> Frame:
        return Frame((*[(k, v) for k, v in self.items if k != var_id], (var_id, value)))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Frame) and self.items == other.items

    def __hash__(self) -> int:
        return self._hash


EMPTY_FRAME = Frame()

# ---------------------------------------------------------------- continuations


class ProgNode:
    """The base of the continuation classes; a continuation is a `Prog` (defined below)."""

    __slots__ = ()


@dataclass(frozen=True, slots=True)
class Done(ProgNode):
    pass


DONE = Done()


@dataclass(frozen=True, slots=True)
class Seq(ProgNode):
    first: Prog
    rest: Prog


@dataclass(frozen=True, slots=True, eq=False)
class Code(ProgNode):
    """A statement not yet started, with the bindings it sees. Compared by the statement's
    identity (not its text) and the bindings."""

    stmt: ast.Statement
    frame: Frame

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Code) and self.stmt is other.stmt and self.frame == other.frame

    def __hash__(self) -> int:
        return hash((id(self.stmt), self.frame))


@dataclass(frozen=True, slots=True, eq=False)
class Rest(ProgNode):
    """The statements of a block from `index` on."""

    block: ast.Block
    index: int
    frame: Frame

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Rest) and self.block is other.block and self.index == other.index
        ) and self.frame == other.frame

    def __hash__(self) -> int:
        return hash((id(self.block), self.index, self.frame))


class EndKind:
    CALL = "call"  # the end of `a(args);`
    DURING = "during"


@dataclass(frozen=True, slots=True)
class AwaitEnd(ProgNode):
    """`a(args);` after its start: waits for the activity to end, then ends it."""

    action: GroundAction
    span: Span = field(compare=False)


@dataclass(frozen=True, slots=True)
class DuringEnd(ProgNode):
    """The end of `during (a) body ...`: waits for `a`, then runs the matching handler."""

    action: GroundAction
    on_fail: Prog | None
    on_cancel: Prog | None
    span: Span = field(compare=False)


@dataclass(frozen=True, slots=True, eq=False)
class Watch(ProgNode):
    """`during (a) until (e) body ...` after its start (`stmt`): `body` (what is left of it)
    runs while `a` runs. When `e` holds while `a` runs, `a` is cancelled (once: `cancelling`)
    and the body is left; when `a` ends, whatever is left of the body is left, `a` is ended
    and the matching handler runs (docs/semantics.md, "Watching an activity")."""

    action: GroundAction
    stmt: ast.During
    frame: Frame
    body: Prog
    cancelling: bool

    @property
    def span(self) -> Span:
        return self.stmt.span

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Watch)
            and self.stmt is other.stmt
            and self.action == other.action
            and self.cancelling == other.cancelling
            and self.frame == other.frame
            and self.body == other.body
        )

    def __hash__(self) -> int:
        return hash((id(self.stmt), self.action, self.cancelling, self.frame, self.body))


@dataclass(frozen=True, slots=True)
class Conc(ProgNode):
    branches: tuple[Prog, ...]


@dataclass(frozen=True, slots=True, eq=False)
class Planned(ProgNode):
    """Online only: a `solve`/`search` whose plan is being executed, from its `index`-th
    planned step on; the session's plan is made when the executor performs the PlanStep or
    ReplanStep (see `PlanSession`)."""

    session: PlanSession
    index: int
    # The planned step at `index` is a call whose activity has been started: the session waits
    # for it to end (and plans again from after it if it fails).
    calling: bool = False


# A program continuation: what remains to be executed.
Prog: TypeAlias = Done | Seq | Code | Rest | AwaitEnd | DuringEnd | Watch | Conc | Planned


# ---------------------------------------------------------------- steps


class StepNode:
    """The base of the step classes; a step is a `Step` (defined below). `cost` counts
    against a `solve` horizon."""

    __slots__ = ()
    cost = 1

    def describe(self) -> str:
        raise NotImplementedError


@dataclass(frozen=True, slots=True)
class TestStep(StepNode):
    span: Span = field(compare=False)
    cost = 0

    def describe(self) -> str:
        return "test"


@dataclass(frozen=True, slots=True)
class StartStep(StepNode):
    """Start an activity: `start(a)`, or the start of `a(args);` / `during (a)` online."""

    action: GroundAction
    span: Span = field(compare=False)
    # The start of a `during`: the whole `during` counts once, at its end (where its effects
    # apply, so that the reward after that step sees them, as after a plain call).
    of_during: bool = field(compare=False, default=False)

    @property
    def cost(self) -> int:  # type: ignore[override]
        return 0 if self.of_during else 1

    def describe(self) -> str:
        return f"start({self.action.text})"


@dataclass(frozen=True, slots=True)
class EndStep(StepNode):
    """Consume a terminated activity; its effects apply only if it ended `final`."""

    action: GroundAction
    hook: str  # "end", "finish", "fail", "call", "during"
    span: Span = field(compare=False)
    # The end of a `during` with an `on_fail` handler: a failure is handled by the program.
    handles_failure: bool = field(compare=False, default=False)

    @property
    def cost(self) -> int:  # type: ignore[override]
        # The end of a plain call is part of the call, which counted at its start; a `during`
        # counts at its end (see StartStep.of_during).
        return 0 if self.hook == EndKind.CALL else 1

    def describe(self) -> str:
        return f"{'end' if self.hook in (EndKind.CALL, EndKind.DURING) else self.hook}({self.action.text})"


@dataclass(frozen=True, slots=True)
class CancelStep(StepNode):
    action: GroundAction
    span: Span = field(compare=False)
    # Why the program cancels it, for the trace: a watched `during`'s condition that holds.
    reason: str = field(compare=False, default="")

    def describe(self) -> str:
        return f"cancel({self.action.text})"


@dataclass(frozen=True, slots=True)
class DoStep(StepNode):
    """Planning only: `a(args);` as one step (start, instant success, end)."""

    action: GroundAction
    span: Span = field(compare=False)

    def describe(self) -> str:
        return self.action.text


@dataclass(frozen=True, slots=True)
class AssignStep(StepNode):
    """Assignments to fluent instances (a fluent, a field or element, push/pop)."""

    updates: tuple[tuple[int, Value], ...]
    span: Span = field(compare=False)
    text: str = field(compare=False, default="")

    def describe(self) -> str:
        return self.text


@dataclass(frozen=True, slots=True, eq=False)
class PlanStep(StepNode):
    """Online only: plan a `solve`/`search` (the session's `plan`)."""

    session: PlanSession
    cost = 0

    def describe(self) -> str:
        return "plan"


@dataclass(frozen=True, slots=True, eq=False)
class ReplanStep(StepNode):
    """Online only: the world deviated from the plan; plan again from `index` (the session's
    `replan`)."""

    session: PlanSession
    index: int
    # Why: a planned step no longer possible, a planned activity that failed, ...
    reason: str = ""
    cost = 0

    def describe(self) -> str:
        return "replan"


# What one transition does to the world.
Step: TypeAlias = TestStep | StartStep | EndStep | CancelStep | DoStep | AssignStep | PlanStep | ReplanStep

Successor = tuple[Prog, Step]

# The effects of a ground action prepared by `Semantics._effect_plan`: the parameter bindings,
# and per effect its condition, value, slot, the target's type and the span of a domain error.
_EffectPlan = tuple[dict[int, Value], tuple[tuple[Evaluator | None, Evaluator, int, "Type", Span], ...]]
_NO_PLAN: _EffectPlan = ({}, ())  # not yet prepared (compared by identity)

# How many `final` results of procedure calls are remembered (then the memo starts afresh).
_FINAL_MEMO_SIZE = 100_000

# ---------------------------------------------------------------- the online-planning port

# What the semantics and the executor need of a planner to run `solve`/`search` online
# (SEMANTICS §5, §6), without depending on one. Online, `trans` of a `solve`/`search` asks the
# `OnlinePlanner` for a `PlanSession` for the statement and continues as `Planned(session, 0)`
# after a `PlanStep(session)`. The session answers `final` (`exhausted`) and `trans`
# (`successors`) of the `Planned` continuation, and the executor, when it performs a PlanStep
# or ReplanStep, asks it to `plan` or `replan` and traces the `PlanReport` it returns.
# gpp.planner.policy implements the port; gpp.run.runner, above both layers, gives the
# executor that implementation.


class PlanSession(Protocol):
    """The plan of one `solve`/`search` being executed online: held by `Planned`, `PlanStep`
    and `ReplanStep`. It is filled (and refilled) when the executor performs those steps."""

    @property
    def stmt(self) -> ast.Solve | ast.Search: ...

    def exhausted(self, index: int) -> bool:
        """`final` of `Planned(self, index)`: the plan has been executed to its end."""
        ...

    def successors(self, sem: Semantics, p: Planned, state: State, acts: Activities) -> list[Successor]:
        """`trans` of `p` (a `Planned` of this session): the next planned step if it is still
        possible in the actual world, a ReplanStep if not."""
        ...

    def plan(self, sem: Semantics, state: State, acts: Activities) -> PlanReport:
        """Plan the statement's body from the actual state (performing the PlanStep)."""
        ...

    def replan(self, sem: Semantics, index: int, state: State, acts: Activities, reason: str = "") -> PlanReport:
        """Plan again from the program point of `Planned(self, index)` (a ReplanStep, which
        says why)."""
        ...

    def awaited(self, p: Planned, acts: Activities) -> tuple[GroundAction, int, Span] | None:
        """What `p` (a Planned of this session that cannot step) waits for, when it is a
        planned activity: the activity, the number of its step among the plan's steps (1 for
        the first), and the statement of the step (the call, the `during`)."""
        ...


class OnlinePlanner(Protocol):
    """What runs `solve`/`search` online: makes a session for a statement reached online."""

    def session(self, sem: Semantics, stmt: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanSession: ...

    def stop_at(self, deadline: float | None) -> None:
        """Planning that goes on past `deadline` (a `time.monotonic()` moment: the run's
        wall-clock bound) raises gpp.runtime.errors.WallClockReached."""
        ...


# ---------------------------------------------------------------- the semantics


class Semantics:
    """`final`, `trans` and hypothetical `apply` over a compiled program. Online, `planner`
    runs `solve`/`search`; without one, reaching them online is an error (R0010)."""

    def __init__(
        self, program: CompiledProgram, ctx: Context, planning: bool, planner: OnlinePlanner | None = None
    ) -> None:
        self.program = program
        self.ctx = ctx
        self.planning = planning
        self.planner = planner
        self.model = program.model
        self._final_memo: dict[tuple[int, Frame, State, Activities], bool] = {}
        # Per ground action and moment (`at_start`): its prepared effects (`_effect_plan`).
        self._effect_plans: dict[tuple[GroundAction, bool], _EffectPlan | None] = {}
        # `pick` values skipped because a precondition conjunct already rules them out.
        self.pruned_bindings = 0
        # Online: an exogenous function found without an answer, and the statement that reads
        # it (what a wait waits for).
        self.unanswered: tuple[Unanswered, ast.Statement] | None = None

    def forget(self) -> None:
        """Online, between two steps: what was remembered about the program's configurations
        no longer holds when an exogenous function's answer may have changed."""
        self._final_memo.clear()
        self.unanswered = None

    def with_mode(self, planning: bool) -> Semantics:
        return Semantics(self.program, self.ctx, planning, self.planner)

    def with_context(self, ctx: Context, planning: bool) -> Semantics:
        return Semantics(self.program, ctx, planning, self.planner)

    def env(self, state: State, frame: Frame) -> Env:
        return Env(state, frame.vars, self.ctx)

    def entry(self, name: str = "main", args: tuple[Value, ...] = ()) -> Prog:
        """The body of procedure `name` with its parameters bound to `args` (in order)."""
        params, body = self.program.procedure(name)
        if body is None:
            symbol = self.model.globals[name]
            raise GppRuntimeError(R0008.procedure(name), symbol.span)
        return Code(body, Frame(tuple(zip(params, args, strict=True))))

    # ---------------------------------------------------------------- final

    def final(self, p: Prog, state: State, acts: Activities) -> bool:
        match p:
            case Done():
                return True
            case Seq():
                return self.final(p.first, state, acts) and self.final(p.rest, state, acts)
            case Rest():
                body = p.block.body
                return all(self.final(Code(s, p.frame), state, acts) for s in body[p.index :])
            case Conc():
                return all(self.final(b, state, acts) for b in p.branches)
            case Planned():
                return p.session.exhausted(p.index)
            case AwaitEnd() | DuringEnd() | Watch():
                return False
            case Code():
                try:
                    return self.final_code(p.stmt, p.frame, state, acts)
                except Unanswered as e:
                    return self.unanswered_(e, p.stmt)
            case _:
                assert_never(p)

    def unanswered_(self, e: Unanswered, stmt: ast.Statement) -> Literal[False]:
        """Online, a statement that reads an exogenous function without an answer can neither
        step nor end (it waits for the answer); the first such statement and reason since the
        last `forget` are kept for the `waiting` record. While planning, it is an error."""
        if self.planning:
            raise e
        if self.unanswered is None:
            self.unanswered = (e, stmt)
        return False

    def final_code(self, s: ast.Statement, frame: Frame, state: State, acts: Activities) -> bool:
        """`final` of the statement `s` with the bindings of `frame` (`final(Code(s, frame))`):
        one case per statement kind. The planner's fast tier (gpp.planner.fast) calls it for
        the statements it does not specialise."""
        match s:
            case ast.Block():
                return all(self.final_code(x, frame, state, acts) for x in s.body)
            case ast.If():
                if self.condition(s.condition, state, frame):
                    return self.final_code(s.then, frame, state, acts)
                return s.otherwise is None or self.final_code(s.otherwise, frame, state, acts)
            case ast.While():
                return not self.condition(s.condition, state, frame) or self.final_code(s.body, frame, state, acts)
            case ast.Choose():
                return any(self.final_code(x, frame, state, acts) for x in s.alternatives)
            case ast.Concurrent():
                return all(self.final_code(x, frame, state, acts) for x in s.branches)
            case ast.Pick():
                return any(self.final_code(s.body, f, state, acts) for f in self.pick_frames(s, frame))
            case ast.Solve() | ast.Search():
                return self.planning and self.final_code(s.body, frame, state, acts)
            case ast.CallStmt():
                callee = self.callee(s)
                if callee.kind is not SymbolKind.PROCEDURE:
                    return False
                # Remembered: `trans` asks again at every level of a recursion, which would
                # make each step quadratic in the depth of the recursion.
                key = (id(s), frame, state, acts)
                known = self._final_memo.get(key)
                if known is None:
                    body, inner = self.procedure_body(s, callee.name, state, frame)
                    known = self.final_code(body, inner, state, acts)
                    if len(self._final_memo) >= _FINAL_MEMO_SIZE:
                        self._final_memo.clear()
                    self._final_memo[key] = known
                return known
            case ast.Test() | ast.Assign() | ast.ListStmt() | ast.HookStmt() | ast.During():
                return False
            case _:
                assert_never(s)

    # ---------------------------------------------------------------- trans

    def trans(self, p: Prog, state: State, acts: Activities, first: bool = False) -> list[Successor]:
        """The successors of `p`, in textual order. With `first`, only as many as it takes to
        find the first one (online execution takes the first: later alternatives are not
        evaluated, so they can neither fail nor ask the platform)."""
        match p:
            case Done():
                return []
            case Seq():
                out = [(self.seq(q, p.rest), step) for q, step in self.trans(p.first, state, acts, first)]
                if not (first and out) and self.final(p.first, state, acts):
                    out.extend(self.trans(p.rest, state, acts, first))
                return out
            case Rest():
                body = p.block.body
                if p.index >= len(body):
                    return []
                head = Code(body[p.index], p.frame)
                tail: Prog = Rest(p.block, p.index + 1, p.frame) if p.index + 1 < len(body) else DONE
                return self.trans(Seq(head, tail), state, acts, first)
            case Conc():
                # Prioritised interleaving: the first branch that can step does.
                for i, branch in enumerate(p.branches):
                    succ = self.trans(branch, state, acts, first)
                    if succ:
                        return [(self.conc(p.branches, i, q), step) for q, step in succ]
                return []
            case AwaitEnd():
                status = acts.status(p.action)
                if status is not None and status.terminal:
                    return [(DONE, EndStep(p.action, EndKind.CALL, p.span))]
                return []
            case DuringEnd():
                status = acts.status(p.action)
                if status is None or not status.terminal:
                    return []
                handler = p.on_fail if status is ActivityStatus.FAILED else None
                if status is ActivityStatus.CANCELLED:
                    handler = p.on_cancel
                end = EndStep(p.action, EndKind.DURING, p.span, handles_failure=p.on_fail is not None)
                return [(handler or DONE, end)]
            case Watch():
                return self.watch(p, state, acts, first)
            case Planned():
                return p.session.successors(self, p, state, acts)
            case Code():
                try:
                    return self.trans_code(p.stmt, p.frame, state, acts, first)
                except Unanswered as e:
                    self.unanswered_(e, p.stmt)
                    return []
            case _:
                assert_never(p)

    @staticmethod
    def seq(first: Prog, rest: Prog) -> Prog:
        """`first; rest`, kept right-nested (the `first` of a Seq is never a Seq), so that
        `trans` and `final` look at the head of a deep continuation without walking it."""
        if isinstance(first, Done):
            return rest
        if isinstance(rest, Done):
            return first
        if not isinstance(first, Seq):
            return Seq(first, rest)
        heads: list[Prog] = []
        p: Prog = first
        while isinstance(p, Seq):
            heads.append(p.first)
            p = p.rest
        out = Seq(p, rest)
        for head in reversed(heads):
            out = Seq(head, out)
        return out

    @staticmethod
    def conc(branches: tuple[Prog, ...], i: int, q: Prog) -> Prog:
        new = (*branches[:i], q, *branches[i + 1 :])
        return DONE if all(isinstance(b, Done) for b in new) else Conc(new)

    def trans_code(
        self, s: ast.Statement, frame: Frame, state: State, acts: Activities, first: bool = False
    ) -> list[Successor]:
        """`trans` of the statement `s` with the bindings of `frame` (`trans(Code(s, frame))`):
        one case per statement kind; `first` as for `trans`. The planner's fast tier
        (gpp.planner.fast) calls it for the statements it does not specialise."""
        match s:
            case ast.Block():
                if not s.body:
                    return []
                return self.trans(Rest(s, 0, frame), state, acts, first)
            case ast.If():
                if self.condition(s.condition, state, frame):
                    return self.trans_code(s.then, frame, state, acts, first)
                return self.trans_code(s.otherwise, frame, state, acts, first) if s.otherwise is not None else []
            case ast.While():
                if not self.condition(s.condition, state, frame):
                    return []
                loop = Code(s, frame)
                return [(self.seq(q, loop), step) for q, step in self.trans_code(s.body, frame, state, acts, first)]
            case ast.Test():
                return [(DONE, TestStep(s.span))] if self.condition(s.condition, state, frame) else []
            case ast.Choose():
                out: list[Successor] = []
                for alternative in s.alternatives:
                    # An alternative that waits for an exogenous function's answer cannot
                    # step: the next one may (a guard against a missing or stale value).
                    out.extend(self.trans(Code(alternative, frame), state, acts, first))
                    if first and out:
                        break
                return out
            case ast.Concurrent():
                return self.trans(Conc(tuple(Code(b, frame) for b in s.branches)), state, acts, first)
            case ast.Pick():
                out = []
                guard = self.program.pick_guard(s)
                for f in self.pick_frames(s, frame):
                    if guard is not None and guard.rejects(state, f.vars, self.ctx):
                        self.pruned_bindings += 1
                        continue
                    out.extend(self.trans_code(s.body, f, state, acts, first))
                    if first and out:
                        break
                return out
            case ast.Solve() | ast.Search():
                if self.planning:
                    return self.trans_code(s.body, frame, state, acts, first)
                session = self.plan_session(s, frame, state)
                return [(Planned(session, 0), PlanStep(session))]
            case ast.CallStmt():
                return self.call(s, frame, state, acts, first)
            case ast.Assign():
                return [(DONE, self.assign_step(s, frame, state))]
            case ast.ListStmt():
                return [(DONE, self.list_step(s, frame, state))]
            case ast.HookStmt():
                return self.hook(s, frame, state, acts)
            case ast.During():
                action, g = self.ground_call(s.action, frame, state)
                if not self.startable(action, g, state, acts):
                    return []
                if s.until is not None:
                    watch = Watch(g, s, frame, Code(s.body, frame), False)
                    return [(watch, StartStep(g, s.span, of_during=True))]
                end = DuringEnd(
                    g,
                    Code(s.on_fail, frame) if s.on_fail is not None else None,
                    Code(s.on_cancel, frame) if s.on_cancel is not None else None,
                    s.span,
                )
                return [(self.seq(Code(s.body, frame), end), StartStep(g, s.span, of_during=True))]
            case _:
                assert_never(s)

    def watch(self, p: Watch, state: State, acts: Activities, first: bool = False) -> list[Successor]:
        """`trans` of a watched activity: its end once it ended (leaving the body), its
        cancellation when the `until` condition holds while it runs, else the body's steps."""
        status = acts.status(p.action)
        if status is not None and status.terminal:
            s = p.stmt
            handler = s.on_fail if status is ActivityStatus.FAILED else None
            if status is ActivityStatus.CANCELLED:
                handler = s.on_cancel
            end = EndStep(p.action, EndKind.DURING, s.span, handles_failure=s.on_fail is not None)
            return [(Code(handler, p.frame) if handler is not None else DONE, end)]
        if status is None:
            return []  # the body consumed the activity itself: nothing ends the `during`
        if p.cancelling:
            return []  # cancelled: waits for the platform to end the activity
        if self.watch_fires(p, state):
            return [(Watch(p.action, p.stmt, p.frame, DONE, True), self.watch_cancel_step(p))]
        return [
            (Watch(p.action, p.stmt, p.frame, q, False), step) for q, step in self.trans(p.body, state, acts, first)
        ]

    def watch_cancel(self, point: Prog, step: Step, state: State) -> CancelStep | None:
        """While a planned `step` waits for its activity to end: the cancellation of the
        activity, when `step` ends a watched `during` at the head of the program point `point`
        and its `until` condition holds now (the plan assumed the activity ends first)."""
        if not isinstance(step, EndStep) or step.hook != EndKind.DURING:
            return None
        while isinstance(point, Seq):
            point = point.first
        if isinstance(point, Watch) and point.action == step.action and self.watch_fires(point, state):
            return self.watch_cancel_step(point)
        return None

    @staticmethod
    def watch_cancel_step(p: Watch) -> CancelStep:
        until = p.stmt.until
        assert until is not None
        return CancelStep(p.action, p.span, f"`until ({until.span.text})` holds")

    def watch_fires(self, p: Watch, state: State) -> bool:
        """Does the `until` condition of a watched activity hold now? Online, a condition that
        waits for an exogenous function's answer does not (yet)."""
        until = p.stmt.until
        assert until is not None
        try:
            return self.condition(until, state, p.frame)
        except Unanswered as e:
            return self.unanswered_(e, p.stmt)

    def plan_session(self, s: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanSession:
        """A session of the planner for `s`, reached online."""
        if self.planner is None:
            kind = "solve" if isinstance(s, ast.Solve) else "search"
            raise GppRuntimeError(
                R0010.no_planner(kind),
                s.span,
                ("the executor runs `solve` and `search` with the planner it is given (`gpp run` gives it one)",),
            )
        return self.planner.session(self, s, frame, state)

    # ---------------------------------------------------------------- statements

    def call(
        self, s: ast.CallStmt, frame: Frame, state: State, acts: Activities, first: bool = False
    ) -> list[Successor]:
        callee = self.callee(s)
        if callee.kind is SymbolKind.PROCEDURE:
            body, inner = self.procedure_body(s, callee.name, state, frame)
            return self.trans_code(body, inner, state, acts, first)
        action, g = self.ground_call(s.call, frame, state)
        if not self.startable(action, g, state, acts):
            return []
        if self.planning:
            return [(DONE, DoStep(g, s.span))]
        return [(AwaitEnd(g, s.span), StartStep(g, s.span))]

    def hook(self, s: ast.HookStmt, frame: Frame, state: State, acts: Activities) -> list[Successor]:
        action, g = self.ground_call(s.action, frame, state)
        status = acts.status(g)
        hook = s.hook
        if hook is ast.Hook.START:
            return [(DONE, StartStep(g, s.span))] if self.startable(action, g, state, acts) else []
        if hook is ast.Hook.END:
            ok = status is not None and status.terminal
        elif hook is ast.Hook.FINISH:
            ok = status is ActivityStatus.FINAL
        elif hook is ast.Hook.FAIL:
            ok = status is ActivityStatus.FAILED
        else:
            return [(DONE, CancelStep(g, s.span))] if status is ActivityStatus.RUNNING else []
        return [(DONE, EndStep(g, hook.value, s.span))] if ok else []

    def callee(self, s: ast.CallStmt) -> Symbol:
        symbol = self.model.target(s.call)
        assert symbol is not None
        return symbol

    def procedure_body(self, s: ast.CallStmt, name: str, state: State, frame: Frame) -> tuple[ast.Statement, Frame]:
        params, body = self.program.procedure(name)
        if body is None:
            raise GppRuntimeError(R0008.procedure(name), s.span)
        call = s.call
        assert isinstance(call, ast.Call)
        env = self.env(state, frame)
        values = tuple(self.program.expr(a)(env) for a in call.args)
        symbol = self.model.globals[name]
        for p, v, a in zip(symbol.params, values, call.args, strict=True):
            if isinstance(p.type, DomainType):
                check_domain(v, p.type, a.span)
        return body, Frame(tuple(zip(params, values, strict=True)))

    def ground_call(self, e: ast.Expr, frame: Frame, state: State) -> tuple[ActionInfo, GroundAction]:
        assert isinstance(e, ast.Call)
        symbol = self.model.target(e)
        assert symbol is not None
        action = self.program.action(symbol.name)
        env = self.env(state, frame)
        values = tuple(self.program.expr(a)(env) for a in e.args)
        for p, v, a in zip(symbol.params, values, e.args, strict=True):
            if isinstance(p.type, DomainType):
                check_domain(v, p.type, a.span)
        return action, ground(action, values)

    def startable(self, action: ActionInfo, g: GroundAction, state: State, acts: Activities) -> bool:
        """`start` needs the precondition and no identical activity running (SEMANTICS §4)."""
        if acts.status(g) is ActivityStatus.RUNNING:
            return False
        return self.precondition_holds(action, g, state)

    def precondition_holds(self, action: ActionInfo, g: GroundAction, state: State) -> bool:
        if not action.precondition:
            return True
        env = Env(state, dict(zip(action.param_ids, g.args, strict=True)), self.ctx)
        return all(check(env) is True for check, _ in action.precondition)

    def false_conjuncts(self, g: GroundAction, state: State) -> list[ast.Expr]:
        """The precondition conjuncts of `g` that do not hold (for the blocked diagnostic)."""
        action = self.program.action(g.name)
        env = Env(state, dict(zip(action.param_ids, g.args, strict=True)), self.ctx)
        return [expr for check, expr in action.precondition if check(env) is not True]

    def pick_frames(self, s: ast.Pick, frame: Frame) -> list[Frame]:
        variable = self.model.target(s.var)
        assert variable is not None
        if s.values is not None:
            empty = Env(State(), frame.vars, self.ctx)
            values: tuple[Value, ...] = tuple(self.program.expr(v)(empty) for v in s.values)
        else:
            values = domain_values(variable.type, self.model)
        return [frame.bind(id(variable), v) for v in values]

    def condition(self, e: ast.Expr, state: State, frame: Frame) -> bool:
        return self.program.expr(e)(self.env(state, frame)) is True

    def assign_step(self, s: ast.Assign, frame: Frame, state: State) -> AssignStep:
        env = self.env(state, frame)
        target = self.program.target(s.target)
        value = self.program.expr(s.value)(env)
        pending: dict[int, Value] = {}
        slot = self.program.assignment(target, value, env, pending, s.value.span)
        text = f"{self.program.instance_text(slot)} = {show(pending[slot])}"
        return AssignStep(tuple(pending.items()), s.span, text)

    def list_step(self, s: ast.ListStmt, frame: Frame, state: State) -> AssignStep:
        env = self.env(state, frame)
        target = self.program.target(s.target)
        current = self.program.expr(s.target)(env)
        if current is None:
            raise GppRuntimeError(R0002.null_list(s.op.value), s.target.span)
        assert isinstance(current, tuple)
        if s.op in (ast.ListOp.POP_BACK, ast.ListOp.POP_FRONT) and not current:
            raise GppRuntimeError(R0006.empty(s.op.value), s.span)
        if s.op is ast.ListOp.PUSH_BACK or s.op is ast.ListOp.PUSH_FRONT:
            assert s.value is not None
            element = self.program.expr(s.value)(env)
            list_type = target.value_type
            if isinstance(list_type, ListType):
                check_domain(element, list_type.element, s.value.span)
            new = (*current, element) if s.op is ast.ListOp.PUSH_BACK else (element, *current)
        else:
            new = current[:-1] if s.op is ast.ListOp.POP_BACK else current[1:]
        pending: dict[int, Value] = {}
        slot = self.program.assignment(target, new, env, pending)
        return AssignStep(tuple(pending.items()), s.span, f"{s.op.value}({self.program.instance_text(slot)})")

    # ---------------------------------------------------------------- effects

    def effects(self, g: GroundAction, state: State, at_start: bool = False) -> dict[int, Value]:
        """The updates of `g`'s effects (`effect:`, or with `at_start` its `start_effect:`), all
        evaluated in `state` (SEMANTICS §4). Two effects that give one instance (or one field
        or element of it) different values are an error."""
        plan = self._effect_plans.get((g, at_start), _NO_PLAN)
        if plan is _NO_PLAN:
            plan = self._effect_plans[g, at_start] = self._effect_plan(g, at_start)
        if plan is not None:
            bindings, writes = plan
            env = Env(state, bindings, self.ctx)
            pending: dict[int, Value] = {}
            for condition, evaluate, slot, value_type, span in writes:
                if condition is not None and condition(env) is not True:
                    continue
                value = evaluate(env)
                check_domain(value, value_type, span)
                pending[slot] = value
            return pending
        return self._effects(g, state, at_start)

    def _effect_plan(self, g: GroundAction, at_start: bool = False) -> _EffectPlan | None:
        """`g`'s effects with their slots worked out once, when every effect assigns a whole
        fluent instance whose arguments read only the action's parameters, and no two assign
        the same instance (so they cannot conflict): then `effects` is, step for step, the
        general evaluation below (condition, value, domain check, update) without computing
        the slots and paths again. None otherwise."""
        action = self.program.action(g.name)
        effects = action.start_effects if at_start else action.effects
        if not all(effect.static_target for effect in effects):
            return None
        bindings = dict(zip(action.param_ids, g.args, strict=True))
        env = Env(State(), bindings, self.ctx)
        writes = []
        try:
            for effect in effects:
                target = effect.target
                slot = self.program.slot(target.fluent, tuple(a(env) for a in target.args))
                span = effect.value_span if effect.value_span is not None else target.span
                writes.append((effect.condition, effect.value, slot, target.value_type, span))
        except GppRuntimeError:
            return None
        if len({w[2] for w in writes}) < len(writes):
            return None
        return bindings, tuple(writes)

    def _effects(self, g: GroundAction, state: State, at_start: bool = False) -> dict[int, Value]:
        action = self.program.action(g.name)
        env = Env(state, dict(zip(action.param_ids, g.args, strict=True)), self.ctx)
        pending: dict[int, Value] = {}
        # Per instance: the (path, value, span) of every effect that wrote into it.
        written: dict[int, list[tuple[tuple[str | int, ...], Value, Span]]] = {}
        for effect in action.start_effects if at_start else action.effects:
            if effect.condition is not None and effect.condition(env) is not True:
                continue
            value = effect.value(env)
            slot = self.program.assignment(effect.target, value, env, pending, effect.value_span)
            path = concrete_path(effect.target.path, env)
            for other_path, other_value, other_span in written.get(slot, []):
                if _conflict(path, value, other_path, other_value):
                    where = self.program.instance_text(slot) + "".join(
                        f".{p}" if isinstance(p, str) else f"[{p}]" for p in max(path, other_path, key=len)
                    )
                    raise GppRuntimeError(
                        R0005.conflict(g.text, where),
                        effect.span,
                        label=f"gives {show(value)}",
                        secondary=(diag.Label(other_span, f"gives {show(other_value)}"),),
                        notes=("the effects of one action are applied together, so they must agree",),
                    )
            written.setdefault(slot, []).append((path, value, effect.span))
        return pending

    def apply(self, step: Step, state: State, acts: Activities) -> tuple[State, Activities]:
        """Perform a step hypothetically (planning): activities end instantly in `final`. A
        call is its start, then its end: the start effects are evaluated in `state`, the end
        effects in the state after them."""
        program = self.program
        match step:
            case DoStep():
                if program.action(step.action.name).start_effects:
                    state = state.updated(self.effects(step.action, state, at_start=True), program.initial)
                return state.updated(self.effects(step.action, state), program.initial), acts
            case AssignStep():
                return state.updated(dict(step.updates), program.initial), acts
            case StartStep():
                if program.action(step.action.name).start_effects:
                    state = state.updated(self.effects(step.action, state, at_start=True), program.initial)
                return state, acts.with_status(step.action, ActivityStatus.FINAL)
            case EndStep():
                status = acts.status(step.action)
                if status is ActivityStatus.FINAL:
                    state = state.updated(self.effects(step.action, state), program.initial)
                return state, acts.with_status(step.action, None)
            case TestStep() | CancelStep() | PlanStep() | ReplanStep():
                return state, acts
            case _:
                assert_never(step)


def concrete_path(path: tuple[PathStep, ...], env: Env) -> tuple[str | int, ...]:
    """An assignment path with its indices evaluated: `("pos", "x")`, `(2,)`."""
    out: list[str | int] = []
    for step in path:
        if step.field is not None:
            out.append(step.field)
        else:
            assert step.index is not None
            i = step.index(env)
            out.append(int(i) if isinstance(i, int | float) and not isinstance(i, bool) else -1)
    return tuple(out)


def _conflict(path: tuple[str | int, ...], value: Value, other_path: tuple[str | int, ...], other_value: Value) -> bool:
    """Do two writes into one instance disagree? Writes to disjoint parts never do; a write
    to a part of what the other write covers disagrees if the values there differ."""
    if len(path) < len(other_path):
        path, value, other_path, other_value = other_path, other_value, path, value
    if path[: len(other_path)] != other_path:
        return False
    covered: Value = other_value
    for step in path[len(other_path) :]:
        if isinstance(step, str) and isinstance(covered, CompoundValue):
            covered = covered.get(step)
        elif isinstance(step, int) and isinstance(covered, tuple) and 0 <= step < len(covered):
            covered = covered[step]
        else:
            return True
    return not _same_deep(covered, value)


def _same_deep(a: Value, b: Value) -> bool:
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_same_deep(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, CompoundValue) and isinstance(b, CompoundValue):
        return a.type_name == b.type_name and all(
            _same_deep(x, y) for (_, x), (_, y) in zip(a.fields, b.fields, strict=True)
        )
    return same(a, b)
