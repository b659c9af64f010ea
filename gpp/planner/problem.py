"""A `solve` statement as a planning problem of its own, planned offline without a platform:
what tests, benchmarks and tools use to call the planners directly."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from gpp.base.source import Span
from gpp.codes import R0002, R0007
from gpp.model.model import Model
from gpp.model.types import Type
from gpp.planner.bounds import goal_distance, solve_bound
from gpp.planner.dp import solve_plan
from gpp.planner.reference import Reward, reference_node_count, reference_plan
from gpp.planner.result import Plan
from gpp.planner.search import DEPTH_FIRST, GENERATED, ITERATIVE_DEEPENING, search_plan
from gpp.runtime.codegen import state_function
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import EMPTY_FRAME, Code, Frame, Prog, Semantics
from gpp.runtime.state import Activities, State
from gpp.runtime.values import Value, show
from gpp.syntax import ast
from gpp.syntax.walk import walk


class OfflineContext:
    """Planning without a platform: the clock stands still and nothing can be sensed."""

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        raise GppRuntimeError(R0007.exog_function_offline(name), span)

    def now(self) -> float:
        return 0.0

    def wake_at(self, t: float) -> None:
        pass  # the clock stands still


def make_reward(planning: Semantics, stmt: ast.Solve, frame: Frame) -> Reward:
    """The reward of `stmt` as a function of the state (a type error is a runtime error at the
    reward's span)."""
    closure = planning.program.expr(stmt.reward)
    span = stmt.reward.span
    # Generated source when the expression allows it (gpp.runtime.codegen), else the closure.
    unit = state_function(planning.program, stmt.reward, frame.vars, "reward")
    evaluate: Callable[[State], Value] = unit.build() if unit is not None else lambda s: closure(planning.env(s, frame))

    def reward(s: State) -> float:
        v = evaluate(s)
        if not isinstance(v, int | float) or isinstance(v, bool):
            raise GppRuntimeError(R0002.reward_not_number(), span)
        return float(v)

    return reward


@dataclass(frozen=True)
class PlanningProblem:
    """The body of a `solve` from a configuration, with its horizon and reward."""

    sem: Semantics
    prog: Prog
    state: State
    acts: Activities
    horizon: int
    reward: Reward
    span: Span | None = None
    solve: ast.Solve | None = None  # the statement, for the bound (gpp.planner.bounds)

    def with_horizon(self, horizon: int) -> PlanningProblem:
        return replace(self, horizon=horizon)

    def production(self, prune: bool = True) -> Plan:
        """The production planner's plan; `prune`: with branch and bound where it is exact."""
        bound = solve_bound(self.sem, self.solve, self.horizon) if prune and self.solve is not None else None
        return solve_plan(self.sem, self.prog, self.state, self.acts, self.horizon, self.reward, self.span, bound=bound)

    def reference(self, budget: int | None = None) -> Plan:
        return reference_plan(self.sem, self.prog, self.state, self.acts, self.horizon, self.reward, self.span, budget)

    def reference_nodes(self) -> int:
        return reference_node_count(self.sem, self.prog, self.state, self.acts, self.horizon)

    def search(self, bound: int, strategy: str = DEPTH_FIRST, prune: bool = True, tier: str = GENERATED) -> Plan:
        """`search` of the body; `prune`: iterative deepening cut by gpp.planner.bounds.goal_distance
        where it is exact; `tier`: gpp.planner.search.TIERS."""
        distance = None
        if prune and strategy == ITERATIVE_DEEPENING and isinstance(self.prog, Code):
            distance = goal_distance(self.sem, self.prog.stmt).distance
        return search_plan(
            self.sem, self.prog, self.state, self.acts, bound, self.span, strategy, distance=distance, tier=tier
        )


def first_solve(model: Model, procedure: str = "main") -> PlanningProblem:
    """The first `solve` in `procedure`, planned from the initial state with no variables
    bound (so it must not use variables of an enclosing `pick`)."""
    program = CompiledProgram(model)
    sem = Semantics(program, OfflineContext(), planning=True)
    body = program.procedure(procedure)[1]
    solve = next((n for n in walk(body) if isinstance(n, ast.Solve)), None) if body is not None else None
    if solve is None:
        raise ValueError(f"procedure `{procedure}` has no `solve`")
    state = State()
    horizon = program.expr(solve.horizon)(sem.env(state, EMPTY_FRAME))
    if not isinstance(horizon, int | float) or isinstance(horizon, bool) or horizon != int(horizon):
        raise ValueError(f"the horizon of the `solve` is not a whole number: {show(horizon)}")
    reward = make_reward(sem, solve, EMPTY_FRAME)
    start = Code(solve.body, EMPTY_FRAME)
    return PlanningProblem(sem, start, state, Activities(), int(horizon), reward, solve.span, solve)


def procedure_body(model: Model, procedure: str = "main") -> tuple[Semantics, Prog]:
    """The planning semantics of a program and the body of `procedure` as a continuation."""
    program = CompiledProgram(model)
    sem = Semantics(program, OfflineContext(), planning=True)
    return sem, sem.entry(procedure)
