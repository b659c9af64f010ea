"""The production planner for `solve`: the same result as gpp.planner.reference, fast.

It memoises best continuations on (program continuation, state, activities, remaining
horizon) and evaluates the reward once per state. Everything else (which steps exist, what they
do) comes from the one transition semantics.
"""

from __future__ import annotations

import time

from gpp.planner.reference import Reward, better, step_span
from gpp.planner.result import Branch, Plan, PlanStats
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog, Semantics
from gpp.runtime.state import Activities, State
from gpp.source import Span


def solve_plan(sem: Semantics, prog: Prog, state: State, acts: Activities, horizon: int, reward: Reward) -> Plan:
    assert sem.planning
    stats = PlanStats()
    started = time.perf_counter()
    memo: dict[tuple[Prog, State, Activities, int], Branch] = {}
    rewards: dict[State, float] = {}
    in_progress: set[tuple[Prog, State, Activities, int]] = set()

    def value_of(s: State) -> float:
        v = rewards.get(s)
        if v is None:
            stats.reward_evaluations += 1
            v = reward(s)
            rewards[s] = v
        return v

    def best(p: Prog, s: State, a: Activities, h: int) -> Branch:
        if h <= 0:
            return Branch(True, 0.0, ())
        key = (p, s, a, h)
        hit = memo.get(key)
        if hit is not None:
            stats.cache_hits += 1
            return hit
        if key in in_progress:
            # Back to a configuration with the same horizon: only free steps were made.
            raise GppRuntimeError("R0010", "this loop can run forever without a costed step", _span(p))
        in_progress.add(key)
        stats.nodes += 1
        choice: Branch | None = Branch(True, 0.0, ()) if sem.final(p, s, a) else None
        for q, step in sem.trans(p, s, a):
            s2, a2 = sem.apply(step, s, a)
            if step.cost:
                rest = best(q, s2, a2, h - step.cost)
                option = Branch(rest.feasible, value_of(s2) + rest.value, ((p, step, q), *rest.steps))
            else:
                try:
                    rest = best(q, s2, a2, h)
                except GppRuntimeError as e:
                    if e.code == "R0010" and e.span is None:
                        raise GppRuntimeError(e.code, e.message, step_span(step)) from None
                    raise
                option = Branch(rest.feasible, rest.value, ((p, step, q), *rest.steps))
            if choice is None or better(option, choice):
                choice = option
        in_progress.discard(key)
        result = choice if choice is not None else Branch(False, 0.0, ())
        memo[key] = result
        return result

    result = best(prog, state, acts, horizon)
    stats.seconds = time.perf_counter() - started
    return Plan(result.feasible, value_of(state) + result.value, result.steps, horizon, stats)


def _span(p: Prog) -> Span | None:
    stmt = getattr(p, "stmt", None)
    return stmt.span if stmt is not None else None
