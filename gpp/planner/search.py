"""`search P` (SEMANTICS §6): find offline one complete execution of P, depth-first in textual
order, pruning configurations already visited, with a step bound.

A configuration (continuation, state, activities) that was visited before is not entered
again: either it is on the current path (a cycle, which cannot lead anywhere new) or it was
fully explored without finding an end. So every configuration is expanded at most once and the
search terminates on every finite state space; on an infinite one the step bound stops a path
that grows too long, with an error at the program point it reached.

With the strategy ITERATIVE_DEEPENING (`gpp run --search-strategy iterative-deepening`) the
search is complete in another sense: it finds a shortest execution (the fewest steps, tests
included), the first one in textual order among the shortest. It searches depth first with a
depth limit of 0, 1, 2, ... steps; within one limit a configuration met again with no more
steps left than when it was first met is not entered again (that visit found no end within
what it had left, and this one has no more). A limit at which nothing was cut off by the limit
and no end was found means there is none; a plan longer than the step bound is the bound's
error, as depth first.
"""

from __future__ import annotations

import time

from gpp.base.source import Span
from gpp.codes import R0010
from gpp.planner.guards import program_point_span
from gpp.planner.result import Plan, PlanStats, PolicyStep
from gpp.runtime.errors import GppRuntimeError, WallClockReached
from gpp.runtime.semantics import Prog, Semantics, Step
from gpp.runtime.state import Activities, State

DEFAULT_STEP_BOUND = 10_000

DEPTH_FIRST = "depth-first"
ITERATIVE_DEEPENING = "iterative-deepening"
STRATEGIES = (DEPTH_FIRST, ITERATIVE_DEEPENING)


def search_plan(
    sem: Semantics,
    prog: Prog,
    state: State,
    acts: Activities,
    bound: int,
    span: Span | None = None,
    strategy: str = DEPTH_FIRST,
    deadline: float | None = None,
) -> Plan:
    """`deadline` (a `time.monotonic()` moment, the run's wall-clock bound): searching still
    going on then raises WallClockReached."""
    assert sem.planning
    if strategy == ITERATIVE_DEEPENING:
        return _iterative_deepening(sem, prog, state, acts, bound, span, deadline)
    assert strategy == DEPTH_FIRST, strategy
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
        _check(deadline, stats.nodes)
        path.append((p, step, q))
        if sem.final(q, s2, a2):
            return found()
        if len(path) >= bound:
            raise _bound_error(q, bound, span, DEPTH_FIRST)
        stack.append((q, s2, a2, sem.trans(q, s2, a2)[::-1]))
    stats.seconds = time.perf_counter() - started
    return Plan(False, 0.0, (), bound, stats)


def _bound_error(q: Prog, bound: int, span: Span | None, strategy: str) -> GppRuntimeError:
    where = program_point_span(q) or span
    notes: tuple[str, ...] = (f"the `search` started at {span}",) if span is not None and where is not span else ()
    if strategy == DEPTH_FIRST:
        notes += (
            "depth first follows the first alternative as far as it goes; if a shorter execution "
            f"exists, `gpp run --search-strategy {ITERATIVE_DEEPENING}` finds a shortest one",
        )
    return GppRuntimeError(R0010.search_bound(bound), where, notes)


def _iterative_deepening(
    sem: Semantics, prog: Prog, state: State, acts: Activities, bound: int, span: Span | None, deadline: float | None
) -> Plan:
    stats = PlanStats()
    started = time.perf_counter()
    trans: dict[tuple[Prog, State, Activities], list[tuple[Prog, Step, State, Activities]]] = {}

    def successors(p: Prog, s: State, a: Activities) -> list[tuple[Prog, Step, State, Activities]]:
        # Worked out once for all limits, applied in textual order (an error surfaces at the
        # first limit that reaches the configuration, where depth first would meet it too).
        known = trans.get((p, s, a))
        if known is None:
            known = []
            for q, step in sem.trans(p, s, a):
                s2, a2 = sem.apply(step, s, a)
                known.append((q, step, s2, a2))
            trans[(p, s, a)] = known
        return known

    stats.nodes += 1
    if sem.final(prog, state, acts):
        stats.seconds = time.perf_counter() - started
        return Plan(True, 0.0, (), bound, stats)
    finals: dict[tuple[Prog, State, Activities], bool] = {}
    for limit in range(1, bound + 1):
        # The most steps left with which a configuration was entered at this limit.
        left_at: dict[tuple[Prog, State, Activities], int] = {(prog, state, acts): limit}
        path: list[PolicyStep] = []
        cut = False
        stack = [iter(successors(prog, state, acts))]
        points = [prog]
        while stack:
            following = next(stack[-1], None)
            if following is None:
                stack.pop()
                points.pop()
                if path:
                    path.pop()
                continue
            q, step, s2, a2 = following
            left = limit - len(path) - 1
            config = (q, s2, a2)
            if left_at.get(config, -1) >= left:
                stats.pruned += 1
                continue
            left_at[config] = left
            stats.nodes += 1
            _check(deadline, stats.nodes)
            path.append((points[-1], step, q))
            final = finals.get(config)
            if final is None:
                final = finals[config] = sem.final(q, s2, a2)
            if final:
                stats.seconds = time.perf_counter() - started
                return Plan(True, 0.0, tuple(path), bound, stats)
            if left == 0:
                if successors(q, s2, a2):
                    cut = True
                    if limit == bound:
                        raise _bound_error(q, bound, span, ITERATIVE_DEEPENING)
                path.pop()
                continue
            stack.append(iter(successors(q, s2, a2)))
            points.append(q)
        if not cut:
            break
    stats.seconds = time.perf_counter() - started
    return Plan(False, 0.0, (), bound, stats)


# How often (in nodes) a search reads the clock for the run's wall-clock bound.
_CLOCK_EVERY = 128


def _check(deadline: float | None, nodes: int) -> None:
    """Raise WallClockReached when the run's wall-clock bound has passed (looked at every
    _CLOCK_EVERY nodes)."""
    if deadline is not None and not nodes % _CLOCK_EVERY and time.monotonic() >= deadline:
        raise WallClockReached
