"""Executing a plan online, with re-planning when the world deviates (SEMANTICS §5, §6).

A `solve`/`search` statement reached online becomes a `Planned` continuation holding a
PlanHolder. The executor fills the holder by running the planner when it performs the
PlanStep, and again on every ReplanStep. `planned_successors` offers the next planned step if
it is still possible in the actual world (its preconditions and every condition assumed on
the way are re-evaluated through the same `trans`), and a ReplanStep otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from gpp.planner.result import Plan, PolicyStep
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import (
    AwaitEnd,
    Code,
    DoStep,
    EndStep,
    Frame,
    Planned,
    Prog,
    ReplanStep,
    Semantics,
    Seq,
    StartStep,
    Successor,
)
from gpp.runtime.state import Activities, ActivityStatus, State
from gpp.source import Span
from gpp.syntax import ast


@dataclass(eq=False)
class PlanHolder:
    kind: str  # "solve" or "search"
    body: Prog
    horizon: int  # remaining horizon (solve) or step bound (search)
    frame: Frame
    stmt: ast.Solve | ast.Search
    policy: tuple[PolicyStep, ...] | None = None
    # The Planned index at which `policy[0]` applies (it moves on every re-plan).
    base: int = 0
    plans: list[Plan] = field(default_factory=list)
    # The state of the last planning attempt that found no plan: only a changed world is
    # worth planning again.
    failed_in: State | None = None

    @classmethod
    def for_statement(cls, sem: Semantics, s: ast.Solve | ast.Search, frame: Frame, state: State) -> PlanHolder:
        if isinstance(s, ast.Search):
            from gpp.planner.search import DEFAULT_STEP_BOUND

            return cls("search", Code(s.body, frame), DEFAULT_STEP_BOUND, frame, s)
        h = sem.program.expr(s.horizon)(sem.env(state, frame))
        if isinstance(h, float) and h.is_integer():
            h = int(h)
        if not isinstance(h, int) or isinstance(h, bool) or h < 0:
            raise GppRuntimeError(
                "R0010", f"the horizon of `solve` must be a whole number >= 0, got {h!r}", s.horizon.span
            )
        return cls("solve", Code(s.body, frame), h, frame, s)

    @property
    def span(self) -> Span:
        return self.stmt.span

    def exhausted(self, index: int) -> bool:
        return self.policy is not None and index - self.base >= len(self.policy)

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
        """Costed steps of the current policy executed before `index`."""
        assert self.policy is not None
        return sum(step.cost for _, step, _ in self.policy[: index - self.base])

    def make_plan(self, sem: Semantics, prog: Prog, state: State, acts: Activities) -> Plan:
        planning = sem.with_mode(True)
        stmt = self.stmt
        if isinstance(stmt, ast.Solve):
            from gpp.planner.dp import solve_plan

            reward_expr = sem.program.expr(stmt.reward)
            reward_span = stmt.reward.span
            frame_vars = self.frame.vars

            def reward(s: State) -> float:
                v = reward_expr(planning.env(s, Frame(tuple(frame_vars.items()))))
                if not isinstance(v, int | float) or isinstance(v, bool):
                    raise GppRuntimeError("R0002", "the reward is not a number", reward_span)
                return float(v)

            return solve_plan(planning, prog, state, acts, self.horizon, reward)
        from gpp.planner.search import search_plan

        return search_plan(planning, prog, state, acts, self.horizon, self.stmt.span)

    def install(self, plan: Plan, index: int, state: State) -> None:
        self.plans.append(plan)
        self.policy = plan.steps if plan.feasible else None
        self.failed_in = None if plan.feasible else state
        self.base = index


def planned_successors(sem: Semantics, p: Planned, state: State, acts: Activities) -> list[Successor]:
    holder = p.holder
    if holder.policy is None:
        # No feasible plan: blocked until the world changes, then planned again.
        return [] if holder.failed_in == state else [(p, ReplanStep(holder, p.index))]
    entry = holder.step_at(p.index)
    if entry is None:
        return []
    before, step, _ = entry
    if isinstance(step, EndStep) and acts.status(step.action) is ActivityStatus.RUNNING:
        return []  # the planned end waits for the platform, as `end` does
    planning = sem.with_mode(True)
    if any(candidate == step for _, candidate in planning.trans(before, state, acts)):
        following = Planned(holder, p.index + 1)
        if isinstance(step, DoStep):
            return [(Seq(AwaitEnd(step.action, step.span), following), StartStep(step.action, step.span))]
        return [(following, step)]
    return [(p, ReplanStep(holder, p.index))]
