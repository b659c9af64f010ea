"""`search P` (SEMANTICS §6): find offline one complete execution of P, depth-first in textual
order, pruning configurations already visited, with a step bound."""

from __future__ import annotations

import time

from gpp.planner.result import Plan, PlanStats, PolicyStep
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog, Semantics, Step
from gpp.runtime.state import Activities, State
from gpp.source import Span

DEFAULT_STEP_BOUND = 10_000


def search_plan(
    sem: Semantics, prog: Prog, state: State, acts: Activities, bound: int, span: Span | None = None
) -> Plan:
    assert sem.planning
    stats = PlanStats()
    started = time.perf_counter()
    visited: set[tuple[Prog, State, Activities]] = set()
    path: list[PolicyStep] = []
    # Iterative depth-first search: each frame is (configuration, its remaining successors).
    stack: list[tuple[Prog, State, Activities, list[tuple[Prog, Step]]]] = []

    def push(p: Prog, s: State, a: Activities) -> bool:
        key = (p, s, a)
        if key in visited:
            stats.pruned += 1
            return False
        visited.add(key)
        stats.nodes += 1
        if len(path) > bound:
            raise GppRuntimeError("R0010", f"`search` exceeded its bound of {bound} steps", span)
        stack.append((p, s, a, list(reversed(sem.trans(p, s, a)))))
        return True

    push(prog, state, acts)
    while stack:
        p, s, a, todo = stack[-1]
        if sem.final(p, s, a):
            stats.seconds = time.perf_counter() - started
            return Plan(True, 0.0, tuple(path), bound, stats)
        if not todo:
            stack.pop()
            if path:
                path.pop()
            continue
        q, step = todo.pop()
        s2, a2 = sem.apply(step, s, a)
        path.append((p, step, q))
        if not push(q, s2, a2):
            path.pop()
    stats.seconds = time.perf_counter() - started
    return Plan(False, 0.0, (), bound, stats)
