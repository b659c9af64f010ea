"""Executing a plan online, with re-planning when the world deviates (SEMANTICS §5, §6).

This module implements the online-planning port of gpp.runtime.planning: `PolicyPlanner`
is the OnlinePlanner that gpp.run.runner gives the executor, and `PlanHolder` the PlanSession.
A `solve`/`search` statement reached online becomes a `Planned` continuation holding a
PlanHolder. The executor has the holder plan when it performs the PlanStep, and plan again on
every ReplanStep. `PlanHolder.successors` offers the next planned step if it is still possible
in the actual world, and a ReplanStep otherwise.

"Still possible" is decided by the same `trans` the planner used: the planned step must be a
transition, to the planned continuation, of the planned program point in the actual state.
That re-evaluates the step's precondition and every condition assumed on the way (the
conditions of `if`/`while`, tests, the alternative of a `choose`). A plan that ended because
the program could end also assumed that: after its last step the program must still be final
in the actual state (checked by one more, free, step), else the planner plans again from there
with the horizon that is left.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from gpp.base.source import Span
from gpp.codes import R0010
from gpp.model.types import Type
from gpp.planner.dp import ProgressCallback
from gpp.planner.result import Plan, PolicyStep, policy_text
from gpp.runtime.compiled import Context
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.planning import PlanReport
from gpp.runtime.semantics import (
    Code,
    DoStep,
    DuringEnd,
    EndKind,
    EndStep,
    Frame,
    Planned,
    Prog,
    ReplanStep,
    Semantics,
    Seq,
    StartStep,
    Step,
    Successor,
    TestStep,
)
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.values import Value, show
from gpp.syntax import ast


class PolicyPlanner:
    """The planner online (an OnlinePlanner): plans a policy for each `solve`/`search` reached
    and executes it, re-planning when the world deviates."""

    def __init__(self, search_strategy: str = "depth-first", progress: ProgressCallback | None = None) -> None:
        self.search_strategy = search_strategy  # gpp.planner.search.STRATEGIES
        # Told how a `solve` that takes longer than a second is getting on.
        self.progress = progress
        # The run's wall-clock bound (a time.monotonic() moment): planning stops there.
        self.deadline: float | None = None

    def stop_at(self, deadline: float | None) -> None:
        self.deadline = deadline

    def session(self, sem: Semantics, stmt: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanHolder:
        holder = PlanHolder.for_statement(sem, stmt, frame, state)
        holder.search_strategy = self.search_strategy
        holder.progress = self.progress
        holder.deadline = self.deadline
        return holder


class OncePerPlan:
    """The evaluation context of one planning run: each exogenous function is asked of the
    platform at most once per name and argument values; the clock is read as it is."""

    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self.answers: dict[tuple[str, tuple[tuple[str, Value], ...]], Value] = {}

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        key = (name, tuple(sorted(args.items())))
        if key not in self.answers:
            self.answers[key] = self.ctx.exog_function(name, args, return_type, span)
        return self.answers[key]

    def now(self) -> float:
        return self.ctx.now()

    def wake_at(self, t: float) -> None:
        pass  # a plan is made at one moment: its conditions name no moment to wake at


# How far `steps_to_finish` looks: costed steps, and configurations expanded.
FINISH_STEP_LIMIT = 50
FINISH_NODE_BUDGET = 20_000


def steps_to_finish(sem: Semantics, prog: Prog, state: State, acts: Activities) -> int | None:
    """The fewest costed steps after which `prog` may end (breadth first over the planning
    semantics, free steps followed within a level); None when none is found within
    FINISH_STEP_LIMIT steps and FINISH_NODE_BUDGET configurations."""
    level: set[tuple[Prog, State, Activities]] = {(prog, state, acts)}
    seen: set[tuple[Prog, State, Activities]] = set(level)
    budget = FINISH_NODE_BUDGET
    for cost in range(FINISH_STEP_LIMIT + 1):
        following: set[tuple[Prog, State, Activities]] = set()
        pending = list(level)
        while pending:
            p, s, a = pending.pop()
            budget -= 1
            if budget < 0:
                return None
            try:
                if sem.final(p, s, a):
                    return cost
                successors = sem.trans(p, s, a)
            except GppRuntimeError:
                continue
            for q, step in successors:
                try:
                    s2, a2 = sem.apply(step, s, a)
                except GppRuntimeError:
                    continue
                config = (q, s2, a2)
                if config in seen:
                    continue
                seen.add(config)
                if step.cost:
                    following.add(config)
                else:
                    pending.append(config)
        if not following:
            return None
        level = following
    return None


@dataclass(frozen=True, slots=True, eq=False)
class WatchCancelled(Planned):
    """A planned step that ends a watched activity (`during (a) until (e)`) whose condition
    fired while it ran: its cancellation was asked for, and the step waits for the end."""


@dataclass(eq=False)
class PlanHolder:
    """The plan of one `solve`/`search` being executed online (a PlanSession)."""

    kind: str  # "solve" or "search"
    body: Prog
    horizon: int  # remaining horizon (solve) or step bound (search)
    frame: Frame
    stmt: ast.Solve | ast.Search
    policy: tuple[PolicyStep, ...] | None = None
    # The Planned index at which `policy[0]` applies (it moves on every re-plan).
    base: int = 0
    # The policy ends where the program may end (not at the horizon): one more index checks
    # that it still may (see `successors`).
    ends_program: bool = False
    plans: list[Plan] = field(default_factory=list)
    # The state of the last planning attempt that found no plan: only a changed world is
    # worth planning again.
    failed_in: State | None = None
    # The evaluation context of the last planning run (its exogenous function answers).
    context: OncePerPlan | None = None
    search_strategy: str = "depth-first"  # of a `search`: gpp.planner.search.STRATEGIES
    progress: ProgressCallback | None = None
    # A `solve`'s horizon as written, and the costed steps of this `solve` executed before the
    # current policy (as text): only progress, not the steps of failed attempts.
    written: int = 0
    spent: tuple[str, ...] = ()
    # Why this holder plans (one made after a planned activity failed): the first replan's reason.
    reason: str = ""
    # The run's wall-clock bound (a time.monotonic() moment): planning stops there.
    deadline: float | None = None

    @classmethod
    def for_statement(cls, sem: Semantics, s: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanHolder:
        if isinstance(s, ast.Search):
            from gpp.planner.search import DEFAULT_STEP_BOUND

            return cls("search", Code(s.body, frame), DEFAULT_STEP_BOUND, frame, s)
        h = sem.program.expr(s.horizon)(sem.env(state, frame))
        if isinstance(h, float) and h.is_integer():
            h = int(h)
        if not isinstance(h, int) or isinstance(h, bool) or h < 0:
            raise GppRuntimeError(R0010.bad_horizon(show(h)), s.horizon.span)
        return cls("solve", Code(s.body, frame), h, frame, s, written=h)

    @property
    def span(self) -> Span:
        return self.stmt.span

    def _length(self) -> int:
        assert self.policy is not None
        return len(self.policy) + (1 if self.ends_program else 0)

    def exhausted(self, index: int) -> bool:
        return self.policy is not None and index - self.base >= self._length()

    def step_at(self, index: int) -> PolicyStep | None:
        assert self.policy is not None
        i = index - self.base
        return self.policy[i] if 0 <= i < len(self.policy) else None

    def program_at(self, index: int) -> Prog:
        step = self.step_at(index)
        if step is not None:
            return step[0]
        assert self.policy is not None
        return self.policy[-1][2] if self.policy else self.body

    def used_horizon(self, index: int) -> int:
        """Costed steps of the current policy executed before `index` (a `search` bound is
        per search: re-searching starts with the whole bound again)."""
        assert self.policy is not None
        if self.kind == "search":
            return 0
        return sum(step.cost for _, step, _ in self.policy[: index - self.base])

    def make_plan(self, sem: Semantics, prog: Prog, state: State, acts: Activities) -> Plan:
        # One plan asks each ground exogenous function once (docs/semantics.md, "Planning and
        # the outside world"): on a robot every question is a service call.
        self.context = OncePerPlan(sem.ctx)
        planning = sem.with_context(self.context, True)
        stmt = self.stmt
        if isinstance(stmt, ast.Solve):
            from gpp.planner.bounds import solve_bound
            from gpp.planner.dp import solve_plan
            from gpp.planner.problem import make_reward

            reward = make_reward(planning, stmt, self.frame)
            bound = solve_bound(planning, stmt, self.horizon)
            return solve_plan(
                planning,
                prog,
                state,
                acts,
                self.horizon,
                reward,
                stmt.span,
                self.progress,
                bound=bound,
                deadline=self.deadline,
            )
        from gpp.planner.bounds import goal_distance
        from gpp.planner.search import ITERATIVE_DEEPENING, search_plan

        # The bound holds for every configuration the body reaches, so for a re-search too.
        distance = None
        if self.search_strategy == ITERATIVE_DEEPENING:
            distance = goal_distance(planning, stmt.body).distance
        return search_plan(
            planning,
            prog,
            state,
            acts,
            self.horizon,
            stmt.span,
            self.search_strategy,
            deadline=self.deadline,
            distance=distance,
        )

    def plan(self, sem: Semantics, state: State, acts: Activities) -> PlanReport:
        """The PlanStep: plan the body from the actual state."""
        plan = self.make_plan(sem, self.body, state, acts)
        self.install(plan, 0, state)
        return self.unfinished(sem, self.body, plan, state, acts)

    def replan(self, sem: Semantics, index: int, state: State, acts: Activities, reason: str = "") -> PlanReport:
        """A ReplanStep at `index`: plan again from the planned program point there, with the
        horizon the executed steps left (or from the body, if there was no plan)."""
        point = self.program_at(index) if self.policy is not None else self.body
        if self.policy is not None:
            self.spent += self.executed(index)
            self.horizon -= self.used_horizon(index)
            self.body = point
        plan = self.make_plan(sem, point, state, acts)
        self.install(plan, index, state)
        return replace(self.unfinished(sem, point, plan, state, acts), reason=reason or None)

    def executed(self, index: int, attempt: int | None = None) -> tuple[str, ...]:
        """The costed steps of the current policy executed before `index`, as text, without
        the one at `attempt` (the start of an activity that failed); none for a `search`."""
        assert self.policy is not None
        if self.kind == "search":
            return ()
        steps = self.policy[: index - self.base]
        return tuple(policy_text(step) for i, (_, step, _) in enumerate(steps) if step.cost and i != attempt)

    def after_failure(self, index: int, action: GroundAction, rest: Prog, reason: str) -> PlanHolder:
        """The holder that plans `rest` after the planned activity `action`, consumed at `index`,
        failed (or was cancelled): only progress uses up the horizon (SEMANTICS §5), so the
        start and end of the failed attempt give their steps back."""
        assert self.policy is not None
        steps = self.policy[: index - self.base]
        # The start of the attempt: the last one of `action` before its end (a plain call's
        # start is the call itself; a `during`'s start costs nothing).
        attempt = next(
            (i for i in range(len(steps) - 1, -1, -1) if _starts(steps[i][1], action)),
            None,
        )
        refund = steps[attempt][1].cost if attempt is not None else 0
        left = self.horizon if self.kind == "search" else max(0, self.horizon - self.used_horizon(index) + refund)
        return PlanHolder(
            self.kind,
            rest,
            left,
            self.frame,
            self.stmt,
            search_strategy=self.search_strategy,
            progress=self.progress,
            written=self.written,
            spent=self.spent + self.executed(index, attempt),
            reason=reason,
            deadline=self.deadline,
        )

    def awaited(self, p: Planned, acts: Activities) -> tuple[GroundAction, int, Span] | None:
        if self.policy is None:
            return None
        entry = self.step_at(p.index)
        if entry is None:
            return None
        step = entry[1]
        if not isinstance(step, DoStep | EndStep) or acts.status(step.action) is not ActivityStatus.RUNNING:
            return None
        if isinstance(step, DoStep) and not p.calling:
            return None  # an identical activity runs: the plan is made again (see `successors`)
        number = 1 + sum(1 for _, before, _ in self.policy[: p.index - self.base] if before.cost)
        return step.action, number, step.span

    def unfinished(self, sem: Semantics, prog: Prog, plan: Plan, state: State, acts: Activities) -> PlanReport:
        """The plan's report, saying whether a `solve` plan ends at its horizon with the program
        unfinished, and then how many more costed steps the program needs at least."""
        report = plan.report(self.kind)
        if self.kind == "solve":
            report = replace(report, written=self.written, spent=self.spent)
        if self.kind != "solve" or not plan.feasible or plan.cost < plan.horizon:
            return report
        assert self.context is not None  # make_plan set it: the same answers as the plan's
        planning = sem.with_context(self.context, True)
        end = plan.steps[-1][2] if plan.steps else prog
        try:
            for _, step, _ in plan.steps:
                state, acts = planning.apply(step, state, acts)
            if planning.final(end, state, acts):
                return report
            left = steps_to_finish(planning, end, state, acts)
        except GppRuntimeError:
            return report
        return replace(report, unfinished=True, steps_left=left)

    def successors(self, sem: Semantics, p: Planned, state: State, acts: Activities) -> list[Successor]:
        """`trans` of `p`, a Planned of this holder: the planned step if it is still a
        transition of the planned program point in the actual world, else a ReplanStep."""
        if self.policy is None:
            # No feasible plan: blocked until the world changes, then planned again.
            if self.failed_in == state:
                return []
            why = "the world changed since no plan was found" if self.failed_in is not None else self.reason
            return [(p, ReplanStep(self, p.index, why))]
        planning = sem.with_mode(True)
        entry = self.step_at(p.index)
        if entry is None:
            if self.exhausted(p.index):
                return []
            # The end of a policy that ends the program: does it still end here?
            point = self.program_at(p.index)
            if planning.final(point, state, acts):
                return [(Planned(self, p.index + 1), TestStep(self.span))]
            return [(p, ReplanStep(self, p.index, "the program no longer ends where its plan ended it"))]
        before, step, after = entry
        if p.calling:
            assert isinstance(step, DoStep)
            return self.call_ended(p, step, after, acts)
        status = acts.status(step.action) if isinstance(step, EndStep) else None
        if status is ActivityStatus.RUNNING:
            # The planned end waits for the platform, as `end` does; a watched activity is
            # cancelled when its condition holds meanwhile (the plan assumed it ends first).
            cancel = None if isinstance(p, WatchCancelled) else sem.watch_cancel(before, step, state)
            return [] if cancel is None else [(WatchCancelled(self, p.index), cancel)]
        failed = status is ActivityStatus.FAILED or status is ActivityStatus.CANCELLED
        if isinstance(step, EndStep) and failed and step.hook in (EndKind.DURING, "end"):
            # The plan assumed success. The program reacts to the failure or cancellation (a
            # `during`'s `on_fail`/`on_cancel` handler), and is planned again from there.
            assert status is not None
            for q, candidate in planning.trans(before, state, acts):
                if candidate == step:
                    reason = f"`{step.action.text}` {status.value}" + _handler_note(before, step.action, status)
                    return [(Planned(self.after_failure(p.index, step.action, q, reason), 0), candidate)]
        if (after, step) in planning.trans(before, state, acts):
            if isinstance(step, DoStep):
                return [(Planned(self, p.index, calling=True), StartStep(step.action, step.span))]
            return [(Planned(self, p.index + 1), step)]
        shown = policy_text(step) if not isinstance(step, TestStep) else "a condition the plan assumed"
        return [(p, ReplanStep(self, p.index, f"{shown} is no longer possible"))]

    def call_ended(self, p: Planned, step: DoStep, after: Prog, acts: Activities) -> list[Successor]:
        """`trans` of `p`, a planned call whose activity was started: its end once the activity
        has ended; after a failure (or cancellation) the rest is planned again."""
        status = acts.status(step.action)
        if status is ActivityStatus.RUNNING:
            return []  # the call waits for the platform
        end = EndStep(step.action, EndKind.CALL, step.span)
        if status is None:  # consumed by another part of the program: go on with the plan
            return [(Planned(self, p.index + 1), TestStep(self.span))]
        if status is ActivityStatus.FINAL:
            return [(Planned(self, p.index + 1), end)]
        reason = f"`{step.action.text}` {status.value}"
        return [(Planned(self.after_failure(p.index + 1, step.action, after, reason), 0), end)]

    def install(self, plan: Plan, index: int, state: State) -> None:
        self.plans.append(plan)
        self.policy = plan.steps if plan.feasible else None
        # A `solve` policy that used less than its horizon stopped because the program may end
        # there; a `search` plan always ends the program.
        self.ends_program = plan.feasible and (self.kind == "search" or plan.cost < plan.horizon)
        self.failed_in = None if plan.feasible else state
        self.base = index


def _starts(step: Step, action: GroundAction) -> bool:
    """Does the policy step start an activity of `action` (a call, a `start`, a `during`)?"""
    return isinstance(step, DoStep | StartStep) and step.action == action


def _handler_note(p: Prog, action: GroundAction, status: ActivityStatus) -> str:
    """When `p` is about to end the `during` of `action`, whose handler for `status` (failed,
    cancelled) runs next: a note that says so."""
    while isinstance(p, Seq) and not (isinstance(p.first, DuringEnd) and p.first.action == action):
        p = p.rest  # what comes before the end (an empty body) makes no step
    if isinstance(p, Seq):
        p = p.first
    if not isinstance(p, DuringEnd) or p.action != action:
        return ""
    failed = status is ActivityStatus.FAILED
    handler = p.on_fail if failed else p.on_cancel
    return f": its `{'on_fail' if failed else 'on_cancel'}` handler runs next" if handler is not None else ""
