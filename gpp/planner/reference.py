"""The reference planner: the plain recursive definition of SEMANTICS §5, kept short and
obviously right. It is the oracle the tests compare the production planner (gpp.planner.dp)
with; it is exponential in the horizon, so use it only on small problems.

best(P, s, h):
  * h = 0: feasible, value 0 (the horizon is reached);
  * the options, in this order: stop here if P is final (feasible, value 0), then every
    transition (P', step) of P in the order `trans` gives them (textual order of `choose`,
    order of the `pick` values). A costed step is worth R(s') + best(P', s', h - cost), a free
    step (a test) best(P', s', h). An option whose rest is infeasible is infeasible;
  * no feasible option: infeasible (an impossible action or a false test ends every branch);
  * the best option: feasible beats infeasible, then the higher value; ties go to the earlier
    option (so stopping wins a tie with going on).
The value of the plan is R(s0) + best(P, s0, h).

A run of free steps that comes back to a configuration it passed is a loop that makes no
costed step: an error (SEMANTICS §5), raised where the circle closes. A run of more than
FREE_STEP_LIMIT free steps (a recursion that makes no costed step) is an error at the `solve`.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from gpp.base.source import Span
from gpp.planner.guards import FREE_STEP_LIMIT, free_loop_error, free_run_error, planning_recursion_guard
from gpp.planner.result import INFEASIBLE, STOP, Branch, Plan, PlanStats, better
from gpp.runtime.semantics import Prog, Semantics
from gpp.runtime.state import Activities, State

Reward = Callable[[State], float]
Config = tuple[Prog, State, Activities]


class NodeBudgetExceeded(Exception):
    """The reference planner was stopped after `budget` nodes (benchmarks cap it this way)."""

    def __init__(self, budget: int, seconds: float) -> None:
        super().__init__(f"more than {budget} nodes")
        self.budget = budget
        self.seconds = seconds


def reference_plan(
    sem: Semantics,
    prog: Prog,
    state: State,
    acts: Activities,
    horizon: int,
    reward: Reward,
    span: Span | None = None,
    budget: int | None = None,
) -> Plan:
    assert sem.planning
    stats = PlanStats()
    started = time.perf_counter()

    def best(p: Prog, s: State, a: Activities, h: int, since_cost: frozenset[Config]) -> Branch:
        # `since_cost`: the configurations since the last costed step, this one included.
        stats.nodes += 1
        if budget is not None and stats.nodes > budget:
            raise NodeBudgetExceeded(budget, time.perf_counter() - started)
        if h <= 0:
            return STOP
        choice = STOP if sem.final(p, s, a) else INFEASIBLE
        for q, step in sem.trans(p, s, a):
            s2, a2 = sem.apply(step, s, a)
            if step.cost:
                rest = best(q, s2, a2, h - step.cost, frozenset({(q, s2, a2)}))
            else:
                if (q, s2, a2) in since_cost:
                    raise free_loop_error(q, step)
                if len(since_cost) > FREE_STEP_LIMIT:  # this step would be free step number len(since_cost)
                    raise free_run_error(span)
                rest = best(q, s2, a2, h, since_cost | {(q, s2, a2)})
            if not rest.feasible:
                continue  # INFEASIBLE never beats the current choice
            value = rest.value
            if step.cost:
                stats.reward_evaluations += 1
                value = reward(s2) + value
            option = Branch(True, value, ((p, step, q), *rest.steps))
            if better(option, choice):
                choice = option
        return choice

    with planning_recursion_guard(span):
        result = best(prog, state, acts, horizon, frozenset({(prog, state, acts)}))
    value = 0.0
    if result.feasible:
        stats.reward_evaluations += 1
        value = reward(state) + result.value
    stats.seconds = time.perf_counter() - started
    return Plan(result.feasible, value, result.steps, horizon, stats)


def reference_node_count(sem: Semantics, prog: Prog, state: State, acts: Activities, horizon: int) -> int:
    """The number of nodes `reference_plan` expands on this problem, counted without expanding
    them: the reference explores its whole tree, and the size of a subtree depends only on its
    root configuration and remaining horizon, so it can be counted with memoisation. The
    tests check that the count equals the reference's own on every problem it finishes."""
    sizes: dict[tuple[Prog, State, Activities, int], int] = {}

    def size(p: Prog, s: State, a: Activities, h: int) -> int:
        if h <= 0:
            return 1
        key = (p, s, a, h)
        known = sizes.get(key)
        if known is not None:
            return known
        sizes[key] = 0  # a free loop would come back here; the planners report it as an error
        total = 1
        for q, step in sem.trans(p, s, a):
            s2, a2 = sem.apply(step, s, a)
            total += size(q, s2, a2, h - step.cost)
        sizes[key] = total
        return total

    with planning_recursion_guard(None):
        return size(prog, state, acts, horizon)
