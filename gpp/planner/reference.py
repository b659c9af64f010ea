"""The reference planner: the plain recursive definition of SEMANTICS §5, kept short and
obviously right. It is the oracle the tests compare the production planner with; it is
exponential in the horizon, so use it only on small problems.

best(P, s, h):
  * h = 0: feasible, value 0 (the horizon is reached);
  * the options are: stop here if P is final (feasible, value 0), and every transition
    (P', step) of P; a costed step gives R(s') + best(P', s', h - 1), a free step (a test)
    best(P', s', h);
  * no option: infeasible (an impossible action or a false test);
  * the best option: feasible beats infeasible, then the higher value, ties to the earlier
    option (textual order of `choose`, order of the `pick` values).
The value of the plan is R(s0) + best(P, s0, h).
"""

from __future__ import annotations

import time
from collections.abc import Callable

from gpp.planner.result import Branch, Plan, PlanStats
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog, Semantics
from gpp.runtime.state import Activities, State
from gpp.source import Span

Reward = Callable[[State], float]


def better(a: Branch, b: Branch) -> bool:
    """Is `a` strictly better than `b` (so an earlier option wins ties)?"""
    if a.feasible != b.feasible:
        return a.feasible
    return a.value > b.value


def reference_plan(sem: Semantics, prog: Prog, state: State, acts: Activities, horizon: int, reward: Reward) -> Plan:
    assert sem.planning
    stats = PlanStats()
    started = time.perf_counter()

    def best(p: Prog, s: State, a: Activities, h: int, free: frozenset[tuple[Prog, State]]) -> Branch:
        stats.nodes += 1
        if h <= 0:
            return Branch(True, 0.0, ())
        choice: Branch | None = Branch(True, 0.0, ()) if sem.final(p, s, a) else None
        for q, step in sem.trans(p, s, a):
            s2, a2 = sem.apply(step, s, a)
            if step.cost:
                stats.reward_evaluations += 1
                rest = best(q, s2, a2, h - step.cost, frozenset())
                option = Branch(rest.feasible, reward(s2) + rest.value, ((p, step, q), *rest.steps))
            else:
                if (q, s2) in free:
                    raise GppRuntimeError("R0010", "this loop can run forever without a costed step", step_span(step))
                rest = best(q, s2, a2, h, free | {(p, s)})
                option = Branch(rest.feasible, rest.value, ((p, step, q), *rest.steps))
            if choice is None or better(option, choice):
                choice = option
        return choice if choice is not None else Branch(False, 0.0, ())

    stats.reward_evaluations += 1
    result = best(prog, state, acts, horizon, frozenset())
    stats.seconds = time.perf_counter() - started
    return Plan(result.feasible, reward(state) + result.value, result.steps, horizon, stats)


def step_span(step: object) -> Span | None:
    span = getattr(step, "span", None)
    return span if isinstance(span, Span) else None
