"""`search P` (SEMANTICS §6): find offline one complete execution of P, depth-first in textual
order, pruning configurations already visited, with a step bound.

A configuration (continuation, state, activities) that was visited before is not entered
again: either it is on the current path (a cycle, which cannot lead anywhere new) or it was
fully explored without finding an end. So every configuration is expanded at most once and the
search terminates on every finite state space; on an infinite one the step bound stops a path
that grows too long, with an error at the program point it reached.
"""

from __future__ import annotations

import time

from gpp.planner.guards import LOOP_CODE, program_point_span
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
    visited: set[tuple[Prog, State, Activities]] = {(prog, state, acts)}
    path: list[PolicyStep] = []
    # Iterative depth-first search: each frame is a configuration and its successors not yet
    # tried, last one first (so `pop` takes them in textual order).
    stack: list[tuple[Prog, State, Activities, list[tuple[Prog, Step]]]] = []

    def found() -> Plan:
        stats.seconds = time.perf_counter() - started
        return Plan(True, 0.0, tuple(path), bound, stats)

    stats.nodes += 1
    if sem.final(prog, state, acts):
        return found()
    stack.append((prog, state, acts, sem.trans(prog, state, acts)[::-1]))
    while stack:
        p, s, a, todo = stack[-1]
        if not todo:
            stack.pop()
            if path:
                path.pop()
            continue
        q, step = todo.pop()
        s2, a2 = sem.apply(step, s, a)
        if (q, s2, a2) in visited:
            stats.pruned += 1
            continue
        visited.add((q, s2, a2))
        stats.nodes += 1
        path.append((p, step, q))
        if sem.final(q, s2, a2):
            return found()
        if len(path) >= bound:
            where = program_point_span(q) or span
            notes = (f"the `search` started at {span}",) if span is not None and where is not span else ()
            raise GppRuntimeError(
                LOOP_CODE, f"`search` exceeded its bound of {bound} steps without finding an end", where, notes
            )
        stack.append((q, s2, a2, sem.trans(q, s2, a2)[::-1]))
    stats.seconds = time.perf_counter() - started
    return Plan(False, 0.0, (), bound, stats)
