"""The production planner for `solve`: exactly the result of gpp.planner.reference, fast.

`solve_plan` plans by dynamic programming over (continuation, state, activities, remaining
horizon): memoised, one expansion per configuration, results kept for every horizon they hold
for, duplicate options skipped (`expand`: no bound, every node the reference expands); where
gpp.planner.bounds proves a bound exact, global branch and bound with an inherited threshold
instead (`bounded`); `final`, `trans` and `apply` run through the speed tier gpp.planner.fast. Why each of these
keeps the reference's result, and how the loop is laid out: docs/design.md, "The production
planner".
"""

from __future__ import annotations

import gc
import math
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from gpp.base.source import Span
from gpp.planner.bounds import StateBound, ends_at_goal
from gpp.planner.fast.port import ApplyFn, FinalFn, TransFn
from gpp.planner.fast.successors import successors_of
from gpp.planner.guards import FREE_STEP_LIMIT, free_loop_error, free_run_error, planning_recursion_guard
from gpp.planner.reference import Reward
from gpp.planner.result import Plan, PlanStats, PolicyStep
from gpp.runtime.errors import GppRuntimeError, WallClockReached
from gpp.runtime.semantics import Prog, Semantics, Step
from gpp.runtime.state import Activities, State

Config = tuple[Prog, State, Activities]


# The best branch from a configuration, never changed once made: a tuple (one is made per
# node, and a tuple is made and read faster than an object), read by index:
#   [0] feasible or not, [1] its value,
#   [2] depth: the most costed steps on a branch of the subtree (== horizon: it was reached),
#   [3] free run: the most free steps a branch of the subtree starts with,
#   [4] the option of its first step and [5] the result of the rest (None, None: it stops
#   here). The option, not the policy step: one policy step is made per step of the plan, at
#   the end, not one per option (see `_steps`).
_Result = tuple[bool, float, int, int, "_Option | None", "_Result | None"]

_LEAF: _Result = (True, 0.0, 0, 0, None, None)


def _steps(result: _Result, start: Prog) -> tuple[PolicyStep, ...]:
    """The steps of a result's branch from a configuration of continuation `start`, first to
    last: each from the continuation of the configuration the step before led to."""
    out: list[PolicyStep] = []
    r: _Result | None = result
    before = start
    while r is not None and r[4] is not None:
        _, target, step, after = r[4]
        out.append((before, step, after))
        before = target.prog
        r = r[5]
    return tuple(out)


# An option of a configuration: its step's cost, the configuration it leads to, the step, and
# the continuation `trans` gave with it (a tuple: unpacked in the loop, cheaper than attribute
# lookups).
_Option = tuple[int, "_Config", Step, Prog]


class _Config:
    """One configuration met while planning: its expansion (`final` and the options, computed
    once, applied lazily so that steps are applied in the reference's order and an error
    surfaces where it would), its horizon-independent result and its memo."""

    __slots__ = (
        "acts",
        "expanded",
        "final",
        "live",
        "memo",
        "on_path",
        "options",
        "prog",
        "reward",
        "seen",
        "settled",
        "state",
        "successors",
    )

    def __init__(self, prog: Prog, state: State, acts: Activities, horizon: int) -> None:
        self.prog = prog
        self.state = state
        self.acts = acts
        self.expanded = False
        self.final = False
        self.successors: list[tuple[Prog, Step]] = []
        self.options: list[_Option | None] = []  # None: a duplicate of an earlier option
        self.live: list[_Option] | None = None  # the options but the duplicates, once all are made
        # The (target, cost) of the options made: a target alone for a cost of 1 (most steps),
        # sparing a tuple per option. Dropped, with the successors, once all options are made.
        self.seen: set[object] | None = None
        # The result known for every remaining horizon above its depth (see 4 above), and the
        # results for one horizon alone, by horizon (None: not known; see `remember`).
        self.settled: _Result | None = None
        self.memo: list[_Result | None] | None = None  # made when a result needs it
        self.on_path = 0  # bit h: this configuration is on the path with remaining horizon h
        self.reward: float | None = None


@contextmanager
def _collector_paused() -> Iterator[None]:
    """Python's cyclic garbage collector off while planning. Planning allocates millions of
    objects that all stay alive until the plan is made (configurations, options, results),
    and every full collection walks all of them again: with seven blocks that was a quarter
    of the time. Reference counting still frees what is dropped, and `release` below breaks
    the cycles between configurations before the collector is back on (its first collection
    then has little to look at)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


@dataclass(frozen=True, slots=True)
class Progress:
    """How far a long `solve` has got: reported to a progress callback now and then."""

    nodes: int
    memo: int  # configurations met so far
    best: float | None  # the value of the best complete plan found so far (None: none yet)
    seconds: float


ProgressCallback = Callable[[Progress], None]

# How often (in expanded nodes) the clock is read for a progress report.
_PROGRESS_EVERY = 128


def solve_plan(
    sem: Semantics,
    prog: Prog,
    state: State,
    acts: Activities,
    horizon: int,
    reward: Reward,
    span: Span | None = None,
    progress: ProgressCallback | None = None,
    progress_interval: float = 1.0,
    bound: StateBound | None = None,
    generate: bool = True,
    deadline: float | None = None,
) -> Plan:
    """The plan of SEMANTICS §5 for `prog` from (state, acts). With `progress`, a planning that
    takes longer than `progress_interval` seconds reports a `Progress` about every interval.
    `deadline` (a `time.monotonic()` moment, the run's wall-clock bound): planning still going
    on then raises WallClockReached.
    `bound`: from gpp.planner.bounds.solve_bound, for branch and bound (None: none).
    `generate=False`: `trans` and `apply` by the closures of gpp.planner.fast.successors only (no
    generated source; for tests and benchmarks)."""
    assert sem.planning
    deepening = bound is not None and ends_at_goal(bound)
    stats = PlanStats()
    started = time.perf_counter()
    # The configurations met, by continuation, then activities, then state. A continuation
    # and activities are found by their identity first (`trans` returns the same
    # continuations again and again, and an action step keeps the activities object), so
    # they are hashed and compared once per object, not once per option.
    # A table holds the configurations of one continuation and activities by the hash of
    # their state (an int: hashed and compared without Python code), the rare second state
    # of the same hash by the state itself.
    Table = tuple[dict[int, _Config], dict[State, _Config]]
    by_prog: dict[Prog, dict[Activities, Table]] = {}
    by_id: dict[tuple[int, int], tuple[Prog, Activities, Table]] = {}
    met = 0  # configurations met
    successors = successors_of(sem, generate)  # reused by later plannings with `sem`
    # By the identity of a step or a continuation: its `apply`, its `final` and `trans`.
    applies: dict[int, tuple[Step, ApplyFn]] = {}
    functions: dict[int, tuple[Prog, FinalFn, TransFn]] = {}
    rewards: dict[State, float] = {}
    next_report = started + progress_interval
    root_best: list[float] = []  # the best value found at the root so far

    def intern(p: Prog, s: State, a: Activities) -> _Config:
        nonlocal met
        entry = by_id.get((id(p), id(a)))
        if entry is None or entry[0] is not p or entry[1] is not a:
            tables = by_prog.get(p)
            if tables is None:
                tables = by_prog[p] = {}
            table = tables.get(a)
            if table is None:
                table = tables[a] = ({}, {})
            entry = by_id[id(p), id(a)] = (p, a, table)  # keeps p and a alive: ids not reused
        by_hash = entry[2][0]
        h = s._hash  # the state's hash once known: read directly, sparing a call
        if h is None:
            h = hash(s)
        c = by_hash.get(h)
        if c is not None:
            t = c.state
            if t is s or (t._values == s._values if t._plain and s._plain else t == s):  # `==`, inline
                return c
            clashes = entry[2][1]  # another state of the same hash
            c = clashes.get(s)
            if c is None:
                c = clashes[s] = _Config(p, s, a, horizon)
                met += 1
            return c
        c = by_hash[h] = _Config(p, s, a, horizon)
        met += 1
        return c

    def value_of(c: _Config) -> float:
        v = c.reward
        if v is None:
            v = rewards.get(c.state)
            if v is None:
                stats.reward_evaluations += 1
                v = rewards[c.state] = reward(c.state)
            c.reward = v
        return v

    def made(c: _Config) -> Iterator[_Option]:
        """The options of `c` but the duplicates, made as they are reached (steps applied in
        the reference's order, so that an error surfaces where it would)."""
        options, state, acts = c.options, c.state, c.acts
        for i, (q, step) in enumerate(c.successors):
            if i < len(options):
                o = options[i]
            else:
                entry = applies.get(id(step))
                if entry is None or entry[0] is not step:
                    entry = applies[id(step)] = (step, successors.apply_fn(step))  # keeps step alive
                s2, a2 = entry[1](state, acts)
                target = intern(q, s2, a2)
                cost = step.cost
                key = target if cost == 1 else (target, cost)
                seen = c.seen
                if seen is None:
                    seen = c.seen = set()
                if key in seen:
                    stats.pruned += 1
                    o = None
                else:
                    seen.add(key)
                    o = (cost, target, step, q)
                options.append(o)
            if o is not None:
                yield o

    def report() -> None:
        nonlocal next_report
        if deadline is not None and time.monotonic() >= deadline:
            raise WallClockReached
        if progress is None:
            return
        now = time.perf_counter()
        if now >= next_report and progress is not None:
            next_report = now + progress_interval
            progress(Progress(stats.nodes, met, best_so_far(), now - started))

    def best_so_far() -> float | None:
        if not root_best:
            return None
        try:  # R(s0) is part of a plan's value; an error in it is reported when planning ends
            return reward(root.state) + root_best[-1]
        except GppRuntimeError:
            return None

    def open_config(c: _Config) -> None:
        """`final` and `trans` of a configuration, once."""
        p = c.prog
        fns = functions.get(id(p))
        if fns is None or fns[0] is not p:
            fns = functions[id(p)] = (p, successors.final_of(p), successors.trans_of(p))  # keeps p alive
        c.final = fns[1](c.state, c.acts)
        c.successors = fns[2](c.state, c.acts)
        c.expanded = True

    def best(c: _Config, h: int, run: int) -> _Result:
        # `run`: the free steps since the last costed step on the way here.
        if h <= 0:
            return _LEAF
        known = c.settled
        if known is None or known[2] >= h:
            m = c.memo
            known = m[h] if m is not None and h < len(m) else None
        if known is not None:
            if known[0] or known[2] >= h:
                stats.cache_hits += 1
            else:
                stats.pruned += 1  # known infeasible for every horizon (see 4 above)
            if run + known[3] > FREE_STEP_LIMIT:
                raise free_run_error(span)
            return known
        return expand(c, h, run)

    def expand(c: _Config, h: int, run: int) -> _Result:
        """`best` of a configuration and remaining horizon not known yet (without a bound)."""
        stats.nodes += 1
        if not stats.nodes % _PROGRESS_EVERY:
            report()
        c.on_path |= 1 << h
        if not c.expanded:
            open_config(c)
        feasible = c.final
        value = 0.0
        chosen: _Option | None = None
        chosen_rest: _Result | None = None
        depth = free_run = 0
        hits = infeasible = 0  # memo hits, and those of a result infeasible at every horizon
        # All options are made after the first expansion; until then they are made as reached.
        live = c.live
        walk: Iterable[_Option] = live if live is not None else made(c)
        for o in walk:
            cost, target, step, _ = o
            if cost:
                # `best(target, h - cost, 0)`, the lookups written out (most options are known).
                left = h - cost
                if left <= 0:
                    rest = _LEAF
                else:
                    known = target.settled
                    if known is None or known[2] >= left:
                        m = target.memo
                        known = m[left] if m is not None and left < len(m) else None
                    if known is None:
                        rest = expand(target, left, 0)
                    else:
                        hits += 1
                        if not known[0] and known[2] < left:
                            infeasible += 1  # known infeasible for every horizon (see 4 above)
                        # No check of the free steps' limit here: after a costed step the run
                        # starts at 0, and a result made at a node reached after r free steps
                        # starts with at most FREE_STEP_LIMIT - r of them (more would have
                        # raised), so `0 + known[3]` is never above the limit.
                        rest = known
                if cost + rest[2] > depth:
                    depth = cost + rest[2]
                if not rest[0]:
                    continue
                reward_after = target.reward
                v = (value_of(target) if reward_after is None else reward_after) + rest[1]
            else:
                if target.on_path >> h & 1:
                    raise free_loop_error(target.prog, step)
                if run + 1 > FREE_STEP_LIMIT:
                    raise free_run_error(span)
                rest = best(target, h, run + 1)
                free_run = max(free_run, 1 + rest[3])
                depth = max(depth, rest[2])
                if not rest[0]:
                    continue
                v = rest[1]
            # Strictly better (the earlier option wins ties; feasible beats infeasible).
            if not feasible or v > value:
                feasible, value, chosen, chosen_rest = True, v, o, rest
                if c is root and h == horizon:
                    root_best.append(value)
        c.on_path &= ~(1 << h)
        stats.cache_hits += hits - infeasible
        stats.pruned += infeasible
        if live is None and c.live is None and len(c.options) == len(c.successors):
            settle(c, [o for o in c.options if o is not None])
        if chosen is None:
            result: _Result = (feasible, value if feasible else 0.0, depth, free_run, None, None)
        else:
            result = (True, value, depth, free_run, chosen, chosen_rest)
        remember(c, h, result)
        return result

    def remember(c: _Config, h: int, result: _Result) -> None:
        """Keep the result of `c` with `h` steps left: for every horizon above its depth if
        that is below h (see 4 above: one slot, `settled`), else for h alone (a list by
        horizon up to the largest one kept, made for the configurations that need one: one met
        deep in the tree only has small horizons left)."""
        if result[2] < h:
            c.settled = result
            return
        memo = c.memo
        if memo is None:
            memo = c.memo = [None] * (h + 1)
        elif len(memo) <= h:
            memo.extend([None] * (h + 1 - len(memo)))
        memo[h] = result

    def options_of(c: _Config) -> list[_Option]:
        """All options of `c` but the duplicates (with a bound no step of planning can raise:
        they are all made at once)."""
        live = c.live
        if live is None:
            if not c.expanded:
                open_config(c)
            live = list(made(c))
            settle(c, live)
        return live

    def settle(c: _Config, live: list[_Option]) -> None:
        """All options of `c` are made: keep those but the duplicates, and drop what making
        them needed (new objects, not cleared in place: an enclosing `made` of `c` may still
        hold them)."""
        c.live = live
        c.options = []
        c.successors = []
        c.seen = None

    def bounded(c: _Config, h: int, need: float) -> _Result:
        """Branch and bound with an inherited threshold (docs/design.md, "Global pruning"): the
        exact result of `c` with `h` steps left if its value is at least `need`; otherwise
        either that, or (False, u, h, ...) with u < need an upper bound of its value (-inf:
        exactly infeasible). The options are tried in the order of their bounds, best first,
        ties in textual order; the first best option in textual order is chosen, as the
        reference chooses."""
        assert bound is not None
        stats.nodes += 1
        if not stats.nodes % _PROGRESS_EVERY:
            report()
        c.on_path |= 1 << h
        options = options_of(c)
        feasible = c.final
        value = 0.0
        chosen = -1  # the index of the incumbent (-1: stopping here, before every option)
        chosen_rest: _Result | None = None
        partial = False  # an option was skipped or only bounded: not every value is known
        ceiling = -math.inf  # an upper bound of the options not chosen
        depth = 0
        ranked: list[tuple[float, int]] = []
        for i, (cost, target, _, _) in enumerate(options):
            if cost:
                r = target.reward
                ranked.append((-((value_of(target) if r is None else r) + bound(target.state, max(h - cost, 0))), i))
            else:
                ranked.append((-math.inf, i))  # a free step: no bound, tried first
        ranked.sort()
        for negated, i in ranked:
            cost, target, step, _ = options[i]
            threshold = need
            if feasible:
                beat = value + 1.0 if i > chosen else value  # whole numbers: "strictly better" is +1
                if beat > threshold:
                    threshold = beat
            if cost:
                if -negated < threshold:
                    partial = True
                    if -negated > ceiling:
                        ceiling = -negated
                    stats.pruned += 1
                    stats.bound_skips += 1
                    continue
                earned = target.reward
                assert earned is not None
                left = h - cost
            else:
                if target.on_path >> h & 1:
                    raise free_loop_error(target.prog, step)
                earned, left = 0.0, h
            if left <= 0:
                rest = _LEAF
            else:
                known = target.settled
                if known is None or known[2] >= left:
                    m = target.memo
                    known = m[left] if m is not None and left < len(m) else None
                if known is None or not (known[0] or known[1] < threshold - earned or known[1] == -math.inf):
                    rest = bounded(target, left, threshold - earned)
                else:
                    stats.cache_hits += 1
                    rest = known
            if cost + rest[2] > depth:
                depth = cost + rest[2]
            if not rest[0]:
                if rest[1] != -math.inf:
                    partial = True  # only bounded
                    if earned + rest[1] > ceiling:
                        ceiling = earned + rest[1]
                continue
            v = earned + rest[1]
            if not feasible or v > value or (v == value and i < chosen):
                if feasible and value > ceiling:
                    ceiling = value
                feasible, value, chosen, chosen_rest = True, v, i, rest
                if c is root and h == horizon:
                    root_best.append(value)
            elif v > ceiling:
                ceiling = v
        c.on_path &= ~(1 << h)
        result: _Result
        if feasible and (value >= need or not partial):
            if partial:
                depth = h
            first = options[chosen] if chosen >= 0 else None
            result = (True, value, depth, 0, first, chosen_rest if chosen >= 0 else None)
        elif not partial:
            result = (False, -math.inf, depth, 0, None, None)  # infeasible, exactly
        else:
            result = (False, max(ceiling, value) if feasible else ceiling, h, 0, None, None)
        remember(c, h, result)
        return result

    def iterative(c: _Config) -> _Result:
        """The root's result by `bounded`. For a goal loop's bound (close to the value) with the
        threshold lowered from the bound, each attempt to the upper bound the one before
        returned (as IDA* lowers its f-limit; the memo keeps what each attempt learned);
        for another bound (far above it) in one attempt that keeps every feasible branch."""
        assert bound is not None
        if horizon <= 0:
            return _LEAF
        need = bound(c.state, horizon) if deepening else -math.inf
        while True:
            result = bounded(c, horizon, need)
            if result[0] or result[1] == -math.inf:
                return result
            need = result[1]

    def release() -> None:
        """Break the cycles between configurations (an option holds the configuration it leads
        to), so that reference counting frees them all: none is left for the collector."""
        for tables in by_prog.values():
            for by_hash, clashes in tables.values():
                for c in (*by_hash.values(), *clashes.values()):
                    c.options.clear()
                    c.live = None
        by_prog.clear()
        by_id.clear()

    root = intern(prog, state, acts)
    with planning_recursion_guard(span), _collector_paused():
        try:
            result = best(root, horizon, 0) if bound is None else iterative(root)
        finally:
            release()
    value = value_of(root) + result[1] if result[0] else 0.0
    stats.pruned += sem.pruned_bindings
    stats.seconds = time.perf_counter() - started
    return Plan(result[0], value, _steps(result, root.prog) if result[0] else (), horizon, stats)
