"""The production planner for `solve`: exactly the result of gpp.planner.reference, fast.

What makes it fast, and why each keeps the result identical to the reference's:

1. Memoisation on (continuation, state, activities, remaining horizon). The reference's value
   of a subtree is a function of exactly these (`trans`, `final`, `apply` and the reward read
   nothing else while planning), so a repeated configuration has the same best branch.

2. One expansion per configuration. `final`, `trans` and `apply` do not depend on the
   horizon, so a configuration met again with another remaining horizon reuses its options.

3. One reward evaluation per state (the reward is a function of the state).

4. Horizon-independent results. Let d be the largest number of costed steps on any branch of
   a subtree computed with horizon h. If d < h, no branch reached the horizon: every node of
   the tree had horizon left, so for any h' > d the tree is the same tree, with the same
   options in the same order, and the same best branch. The result is then kept for every
   h' > d. In particular an infeasible configuration (no branch reaches the horizon, or it
   would be feasible) is never expanded again at a larger horizon: infeasible bindings are
   pruned from then on, at the cost of one lookup, before any of their steps is looked at.

5. Duplicate options. Two options of one node that lead to the same configuration with the
   same cost have the same value; the later one can never be strictly better, and ties go to
   the earlier, so the later one is skipped.

No bound on the remaining reward is used: the reward function's range over unvisited states
is not known, and an estimate that is not a true bound would change the result.

A run of free steps (tests) that comes back to a configuration it passed is the reference's
"loop without a costed step" error, detected at the same point: the nodes on the current path
with the same remaining horizon are exactly those since the last costed step. The reference's
limit on the length of a run of free steps is kept exactly, memo hits included: every result
records the longest run of free steps its subtree starts with.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from gpp.planner.guards import FREE_STEP_LIMIT, deep_recursion, free_loop_error, free_run_error
from gpp.planner.reference import Reward
from gpp.planner.result import INFEASIBLE, STOP, Branch, Plan, PlanStats, better
from gpp.runtime.semantics import Prog, Semantics, Step
from gpp.runtime.state import Activities, State
from gpp.source import Span

Config = tuple[Prog, State, Activities]
Option = tuple[Prog, Step, State, Activities]


@dataclass(frozen=True, slots=True)
class _Result:
    branch: Branch
    depth: int  # the most costed steps on a branch of the subtree (== horizon: it was reached)
    free_run: int  # the most free steps a branch of the subtree starts with


_LEAF = _Result(STOP, 0, 0)


class _Expansion:
    """`final` and the options of one configuration, computed once, applied lazily (so that
    steps are applied in the reference's order, and an error surfaces where it would)."""

    __slots__ = ("final", "options", "seen", "successors")

    def __init__(self, sem: Semantics, p: Prog, s: State, a: Activities) -> None:
        self.final = sem.final(p, s, a)
        self.successors = sem.trans(p, s, a)
        self.options: list[Option | None] = []  # None: a duplicate of an earlier option
        self.seen: set[tuple[Prog, State, Activities, int]] = set()

    def option(self, sem: Semantics, i: int, s: State, a: Activities, stats: PlanStats) -> Option | None:
        if i < len(self.options):
            return self.options[i]
        q, step = self.successors[i]
        s2, a2 = sem.apply(step, s, a)
        key = (q, s2, a2, step.cost)
        option: Option | None = (q, step, s2, a2)
        if key in self.seen:
            stats.pruned += 1
            option = None
        else:
            self.seen.add(key)
        self.options.append(option)
        return option


def solve_plan(
    sem: Semantics,
    prog: Prog,
    state: State,
    acts: Activities,
    horizon: int,
    reward: Reward,
    span: Span | None = None,
) -> Plan:
    assert sem.planning
    stats = PlanStats()
    started = time.perf_counter()
    memo: dict[tuple[Prog, State, Activities, int], _Result] = {}
    # Results that hold for every horizon >= the int (see 4 above).
    settled: dict[Config, tuple[int, _Result]] = {}
    expansions: dict[Config, _Expansion] = {}
    rewards: dict[State, float] = {}
    on_path: set[tuple[Prog, State, Activities, int]] = set()

    def value_of(s: State) -> float:
        v = rewards.get(s)
        if v is None:
            stats.reward_evaluations += 1
            v = reward(s)
            rewards[s] = v
        return v

    def lookup(config: Config, h: int) -> _Result | None:
        known = settled.get(config)
        if known is not None and h >= known[0]:
            if known[1].branch.feasible:
                stats.cache_hits += 1
            else:
                stats.pruned += 1
            return known[1]
        hit = memo.get((*config, h))
        if hit is not None:
            stats.cache_hits += 1
        return hit

    def best(p: Prog, s: State, a: Activities, h: int, run: int) -> _Result:
        # `run`: the free steps since the last costed step on the way here.
        if h <= 0:
            return _LEAF
        config = (p, s, a)
        known = lookup(config, h)
        if known is not None:
            if run + known.free_run > FREE_STEP_LIMIT:
                raise free_run_error(span)
            return known
        stats.nodes += 1
        key = (p, s, a, h)
        on_path.add(key)
        expansion = expansions.get(config)
        if expansion is None:
            expansion = expansions[config] = _Expansion(sem, p, s, a)
        choice = STOP if expansion.final else INFEASIBLE
        depth = free_run = 0
        for i in range(len(expansion.successors)):
            option = expansion.option(sem, i, s, a, stats)
            if option is None:
                continue
            q, step, s2, a2 = option
            cost = step.cost
            if cost:
                rest = best(q, s2, a2, h - cost, 0)
            else:
                if (q, s2, a2, h) in on_path:
                    raise free_loop_error(q, step)
                if run + 1 > FREE_STEP_LIMIT:
                    raise free_run_error(span)
                rest = best(q, s2, a2, h, run + 1)
                free_run = max(free_run, 1 + rest.free_run)
            depth = max(depth, cost + rest.depth)
            if not rest.branch.feasible:
                continue
            value = value_of(s2) + rest.branch.value if cost else rest.branch.value
            candidate = Branch(True, value, ((p, step, q), *rest.branch.steps))
            if better(candidate, choice):
                choice = candidate
        on_path.discard(key)
        result = _Result(choice, depth, free_run)
        if depth < h:
            settled[config] = (depth + 1, result)
        else:
            memo[key] = result
        return result

    with deep_recursion(span):
        result = best(prog, state, acts, horizon, 0).branch
    value = value_of(state) + result.value if result.feasible else 0.0
    stats.pruned += sem.pruned_bindings
    stats.seconds = time.perf_counter() - started
    return Plan(result.feasible, value, result.steps, horizon, stats)
