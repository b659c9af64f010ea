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

Given `distance`, a lower bound on the steps from a state to an end that
gpp.planner.bounds.goal_distance proves (with no error possible in what it skips), iterative
deepening also cuts a configuration whose steps left are fewer than that bound, and goes on
with the next limit at which a cut configuration could reach an end; it finds the same
execution, or none, or the same error (docs/design.md, "`search`").

Both strategies take `final`, `trans` and `apply` from the planner's speed tier
(gpp.planner.fast, as `solve` does): the same nodes, in the same order, as the semantics
itself (`tier=INTERPRETED`, which the tests compare them with).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol

from gpp.base.source import Span
from gpp.codes import R0010
from gpp.planner.bounds import GoalDistance
from gpp.planner.fast.port import ApplyFn, FinalFn, TransFn
from gpp.planner.fast.successors import successors_of
from gpp.planner.guards import program_point_span
from gpp.planner.result import Plan, PlanStats, PolicyStep
from gpp.runtime.errors import GppRuntimeError, WallClockReached
from gpp.runtime.semantics import Prog, Semantics, Step
from gpp.runtime.state import Activities, State

DEFAULT_STEP_BOUND = 10_000

DEPTH_FIRST = "depth-first"
ITERATIVE_DEEPENING = "iterative-deepening"
STRATEGIES = (DEPTH_FIRST, ITERATIVE_DEEPENING)

# Where `final`, `trans` and `apply` come from: the speed tier with generated source (what
# `solve` runs), its closures alone, or gpp.runtime.semantics itself (the definition).
GENERATED = "generated"
CLOSURES = "closures"
INTERPRETED = "interpreted"
TIERS = (GENERATED, CLOSURES, INTERPRETED)


def search_plan(
    sem: Semantics,
    prog: Prog,
    state: State,
    acts: Activities,
    bound: int,
    span: Span | None = None,
    strategy: str = DEPTH_FIRST,
    deadline: float | None = None,
    distance: GoalDistance | None = None,
    tier: str = GENERATED,
) -> Plan:
    """`deadline` (a `time.monotonic()` moment, the run's wall-clock bound): searching still
    going on then raises WallClockReached. `distance`: gpp.planner.bounds.goal_distance of the
    `search`'s body (iterative deepening only; None: no cut). `tier`: one of TIERS."""
    assert sem.planning
    assert tier in TIERS, tier
    moves = _Moves(sem, tier)
    if strategy == ITERATIVE_DEEPENING:
        return _iterative_deepening(moves, prog, state, acts, bound, span, deadline, distance)
    assert strategy == DEPTH_FIRST, strategy
    assert distance is None, "the bound cuts iterative deepening only"
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
    if moves.final(prog, state, acts):
        return found()
    stack.append((prog, state, acts, moves.trans(prog, state, acts)[::-1]))
    while stack:
        p, s, a, todo = stack[-1]
        if not todo:
            stack.pop()
            if path:
                path.pop()
            continue
        q, step = todo.pop()
        s2, a2 = moves.apply(step, s, a)
        if (q, s2, a2) in visited:
            stats.pruned += 1
            continue
        visited.add((q, s2, a2))
        stats.nodes += 1
        _check(deadline, stats.nodes)
        path.append((p, step, q))
        if moves.final(q, s2, a2):
            return found()
        if len(path) >= bound:
            raise _bound_error(q, bound, span, DEPTH_FIRST)
        stack.append((q, s2, a2, moves.trans(q, s2, a2)[::-1]))
    stats.seconds = time.perf_counter() - started
    return Plan(False, 0.0, (), bound, stats)


class _Tier(Protocol):
    """`final`, `trans` and `apply` as functions of (state, activities), per continuation or
    step (gpp.planner.fast.successors.Successors)."""

    def final_of(self, p: Prog) -> FinalFn: ...

    def trans_of(self, p: Prog) -> TransFn: ...

    def apply_fn(self, step: Step) -> ApplyFn: ...


class _Moves:
    """`final`, `trans` and `apply` of one tier: the semantics' own methods, or the speed
    tier's functions found by the identity of the continuation or step (each made once per
    object, which the tables keep alive so that an identity is not reused)."""

    def __init__(self, sem: Semantics, tier: str) -> None:
        self.final: Callable[[Prog, State, Activities], bool]
        self.trans: Callable[[Prog, State, Activities], list[tuple[Prog, Step]]]
        self.apply: Callable[[Step, State, Activities], tuple[State, Activities]]
        if tier == INTERPRETED:
            self.final, self.trans, self.apply = sem.final, sem.trans, sem.apply
            return
        self.tier: _Tier = successors_of(sem, tier == GENERATED)
        self.finals: dict[int, tuple[Prog, FinalFn]] = {}
        self.transes: dict[int, tuple[Prog, TransFn]] = {}
        self.applies: dict[int, tuple[Step, ApplyFn]] = {}
        self.final, self.trans, self.apply = self._final, self._trans, self._apply

    def _final(self, p: Prog, state: State, acts: Activities) -> bool:
        entry = self.finals.get(id(p))
        if entry is None or entry[0] is not p:
            entry = self.finals[id(p)] = (p, self.tier.final_of(p))
        return entry[1](state, acts)

    def _trans(self, p: Prog, state: State, acts: Activities) -> list[tuple[Prog, Step]]:
        entry = self.transes.get(id(p))
        if entry is None or entry[0] is not p:
            entry = self.transes[id(p)] = (p, self.tier.trans_of(p))
        return entry[1](state, acts)

    def _apply(self, step: Step, state: State, acts: Activities) -> tuple[State, Activities]:
        entry = self.applies.get(id(step))
        if entry is None or entry[0] is not step:
            entry = self.applies[id(step)] = (step, self.tier.apply_fn(step))
        return entry[1](state, acts)


def _bound_error(q: Prog, bound: int, span: Span | None, strategy: str) -> GppRuntimeError:
    where = program_point_span(q) or span
    notes: tuple[str, ...] = (f"the `search` started at {span}",) if span is not None and where is not span else ()
    if strategy == DEPTH_FIRST:
        notes += (
            "depth first follows the first alternative as far as it goes; if a shorter execution "
            f"exists, `gpp run --search-strategy {ITERATIVE_DEEPENING}` finds a shortest one",
        )
    return GppRuntimeError(R0010.search_bound(bound), where, notes)


class _Node:
    """A configuration met by iterative deepening: `final` and its successors (worked out
    once for all limits, applied in textual order), the bound's distance from its state, and
    the limit and steps left with which it was last entered."""

    __slots__ = ("acts", "distance", "final", "left", "limit", "prog", "state", "successors")

    def __init__(self, prog: Prog, state: State, acts: Activities) -> None:
        self.prog = prog
        self.state = state
        self.acts = acts
        self.final: bool | None = None
        self.successors: list[tuple[Step, _Node]] | None = None
        self.distance = -1  # not known yet
        self.limit = 0  # entered at no limit yet (limits start at 1)
        self.left = -1


def _iterative_deepening(
    moves: _Moves,
    prog: Prog,
    state: State,
    acts: Activities,
    bound: int,
    span: Span | None,
    deadline: float | None,
    distance: GoalDistance | None,
) -> Plan:
    stats = PlanStats()
    started = time.perf_counter()
    # Every configuration met, once: the successors of a node point to the nodes they lead to.
    nodes: dict[tuple[Prog, State, Activities], _Node] = {}

    def node(p: Prog, s: State, a: Activities) -> _Node:
        n = nodes.get((p, s, a))
        if n is None:
            n = nodes[p, s, a] = _Node(p, s, a)
        return n

    def successors(n: _Node) -> list[tuple[Step, _Node]]:
        # Worked out once for all limits, applied in textual order (an error surfaces at the
        # first limit that reaches the configuration, where depth first would meet it too).
        known = n.successors
        if known is None:
            s, a = n.state, n.acts
            known = n.successors = [(step, node(q, *moves.apply(step, s, a))) for q, step in moves.trans(n.prog, s, a)]
        return known

    root = node(prog, state, acts)
    stats.nodes += 1
    if moves.final(prog, state, acts):
        stats.seconds = time.perf_counter() - started
        return Plan(True, 0.0, (), bound, stats)
    root.final = False
    # Below the distance of the start no limit can reach an end: start there.
    limit = 1 if distance is None else max(1, min(distance(state), bound))
    while limit <= bound:
        # The last limit searches without the bound, so that the step bound's error (or its
        # absence) is exactly the plain search's (docs/design.md, "`search`").
        cutting = distance if limit < bound else None
        root.limit, root.left = limit, limit
        path: list[PolicyStep] = []
        cut = False  # something was cut off by the limit
        nearest: int | None = None  # the least limit at which a node cut by the bound may end
        stack = [iter(successors(root))]
        points = [prog]
        while stack:
            following = next(stack[-1], None)
            if following is None:
                stack.pop()
                points.pop()
                if path:
                    path.pop()
                continue
            step, n = following
            left = limit - len(path) - 1
            if n.limit == limit and n.left >= left:
                stats.pruned += 1
                continue
            if cutting is not None:
                d = n.distance
                if d < 0:
                    d = n.distance = cutting(n.state)
                if d > left:  # no end within the steps left
                    stats.pruned += 1
                    stats.bound_skips += 1
                    if nearest is None or limit - left + d < nearest:
                        nearest = limit - left + d
                    continue
            n.limit, n.left = limit, left
            stats.nodes += 1
            _check(deadline, stats.nodes)
            path.append((points[-1], step, n.prog))
            final = n.final
            if final is None:
                final = n.final = moves.final(n.prog, n.state, n.acts)
            if final:
                stats.seconds = time.perf_counter() - started
                return Plan(True, 0.0, tuple(path), bound, stats)
            if left == 0:
                if successors(n):
                    cut = True
                    if limit == bound:
                        raise _bound_error(n.prog, bound, span, ITERATIVE_DEEPENING)
                path.pop()
                continue
            stack.append(iter(successors(n)))
            points.append(n.prog)
        if cut:
            limit += 1
        elif nearest is not None:
            # Every limit below `nearest` would search the same nodes again: skip them.
            limit = min(nearest, bound)
        else:
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
