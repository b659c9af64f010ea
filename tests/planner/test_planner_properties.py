"""Property-based tests of the planners on random small worlds and random programs.

Each example is golog++ source text: a world (a domain, bool fluents, maybe a bounded counter,
actions with random preconditions and effects, conditional ones included, and a reward that
sums random terms) and a program over it (action calls, assignments, tests, `if`, `while`,
`choose`, `pick` with and without `in`, blocks). The text must pass the checker; then it is
compiled and planned directly (gpp.planner.problem), without a platform.

What is checked (SEMANTICS §5, §6):
* the production planner returns exactly the reference planner's result: feasibility, value,
  policy, or the same error;
* every policy can be executed step by step from the start state with `trans`/`apply`, uses
  at most the horizon, ends the program unless it used the whole horizon, and its value is
  R(s0) plus the reward after every costed step;
* at every step the policy takes the first best option (stopping first, then textual order);
* a plan that ends the program before the horizon is still available with a larger horizon,
  so raising the horizon never lowers its value; infeasibility persists as the horizon grows;
* `search` returns executable plans that end the program, exactly when such an execution
  exists, and the first one a plain recursive depth-first search finds.
"""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

from gpp.planner.bounds import analyse, solve_bound
from gpp.planner.problem import PlanningProblem
from gpp.planner.result import PolicyStep
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog
from gpp.runtime.state import Activities, State
from tests.support.budget import examples
from tests.support.planner_worlds import (
    PROPERTY,
    Case,
    World,
    attempt,
    cases,
    final_reachable,
    looping_cases,
    outcome,
    replay,
    staggered_cases,
)

# ---------------------------------------------------------------- worlds


# ---------------------------------------------------------------- programs


# ---------------------------------------------------------------- helpers


# ---------------------------------------------------------------- solve


@pytest.mark.slow
@given(st.one_of(cases(), looping_cases(), staggered_cases()))
@settings(PROPERTY, max_examples=examples(1000))
def test_production_planner_returns_exactly_the_reference_result(case: Case) -> None:
    pb = case.problem()
    assert outcome(attempt(pb, "production")) == outcome(attempt(pb, "reference"))


@pytest.mark.slow
@given(cases(max_horizon=5))
@settings(PROPERTY, max_examples=examples(700))
def test_every_policy_is_executable_ends_the_program_or_the_horizon_and_is_worth_its_value(case: Case) -> None:
    pb = case.problem()
    plan = attempt(pb, "production")
    if isinstance(plan, GppRuntimeError) or not plan.feasible:
        return
    p, s, a, used, total = replay(pb, plan.steps)
    assert used == plan.cost <= pb.horizon
    assert used == pb.horizon or pb.sem.final(p, s, a)
    assert total == plan.value


def option_values(pb: PlanningProblem, p: Prog, s: State, a: Activities, h: int) -> list[tuple[bool, float]]:
    """The reference's (feasible, value) of every option at a configuration, stop first."""
    values: list[tuple[bool, float]] = []
    if pb.sem.final(p, s, a):
        values.append((True, 0.0))
    for q, step in pb.sem.trans(p, s, a):
        s2, a2 = pb.sem.apply(step, s, a)
        rest = PlanningProblem(pb.sem, q, s2, a2, h - step.cost, pb.reward, pb.span).reference()
        # A plan's value counts the reward of its start state; a free step does not earn it.
        values.append((rest.feasible, rest.value if step.cost else rest.value - pb.reward(s2)))
    return values


@given(cases(max_horizon=3))
@settings(PROPERTY, max_examples=examples(300))
def test_the_policy_takes_the_first_best_option_at_every_step(case: Case) -> None:
    pb = case.problem()
    plan = attempt(pb, "reference")
    if isinstance(plan, GppRuntimeError) or not plan.feasible:
        return
    p, s, a, h = pb.prog, pb.state, pb.acts, pb.horizon
    for i in range(len(plan.steps) + 1):
        if h <= 0:
            assert i == len(plan.steps)
            break
        values = option_values(pb, p, s, a, h)
        offset = 1 if pb.sem.final(p, s, a) else 0
        if i == len(plan.steps):
            chosen = 0  # the policy stops: the stop option
            assert offset == 1
        else:
            _, step, after = plan.steps[i]
            chosen = offset + pb.sem.trans(p, s, a).index((after, step))
        feasible, value = values[chosen]
        assert feasible
        for j, (other_feasible, other) in enumerate(values):
            if other_feasible:
                assert other < value if j < chosen else other <= value
        if i < len(plan.steps):
            s, a = pb.sem.apply(step, s, a)
            p, h = after, h - step.cost


@pytest.mark.slow
@given(cases(max_horizon=4, min_horizon=0), st.integers(1, 2))
@settings(PROPERTY, max_examples=examples(500))
def test_raising_the_horizon_never_lowers_the_value_of_a_plan_that_ends_the_program(case: Case, more: int) -> None:
    pb = case.problem()
    low = attempt(pb, "production")
    high = attempt(pb.with_horizon(pb.horizon + more), "production")
    if isinstance(low, GppRuntimeError) or isinstance(high, GppRuntimeError):
        return
    if not low.feasible:
        assert not high.feasible  # infeasible stays infeasible
    elif low.cost < pb.horizon:  # the plan ends the program before the horizon
        assert high.feasible
        assert high.value >= low.value
    if high.feasible:
        assert low.feasible  # a branch feasible with more horizon is feasible with less


@st.composite
def blocks_worlds(draw: st.DrawFn, sizes: tuple[int, int] = (3, 4), risky: bool = False) -> Case:
    """Larger instances: a blocks world of 3 or 4 blocks from a random arrangement to a random
    goal, with a random reward for the goal and per step, the whole `pick` program and a
    horizon up to 6 (3 blocks) or 4 (4 blocks): the shape the production planner is tuned for
    (pick guards, specialised successors, remembered quantifiers). `sizes`: other numbers of
    blocks (more than 4: horizons up to 8). `risky`: a step that divides by a fluent another
    step may set to 0, in the loop (the analysis must refuse to prune)."""
    blocks = draw(st.integers(*sizes))
    names = [f"b{i}" for i in range(blocks)]

    def arrangement() -> dict[str, str]:
        order = draw(st.permutations(names))
        on: dict[str, str] = {}
        for i, name in enumerate(order):
            # Each block on the table or on the block before it in the order (a stack).
            on[name] = order[i - 1] if i > 0 and draw(st.booleans()) else "table"
        return on

    start, goal = arrangement(), arrangement()
    initially = " ".join(f"({b}) = {start[b]};" for b in names)
    goal_text = " & ".join(f"loc({b}) == {goal[b]}" for b in names)
    win, step = draw(st.integers(1, 100)), draw(st.integers(-5, 2))
    world = World(
        tuple(names),
        (),
        None,
        (),
        f"""symbol domain block = {{{", ".join(names)}}}
symbol domain location = block | {{table}}
location fluent loc(block x) {{ initially: {initially} }}
action stack(block x, location y) {{
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}}
bool function goal() = {goal_text}
number function reward() = if (goal()) {win} else {step}
""",
    )
    body = draw(
        st.sampled_from(
            [
                "while (!goal()) pick (block x) pick (location y) stack(x, y);",
                "{ while (!goal()) pick (block x) pick (location y) stack(x, y); test(goal()); }",
                "while (true) choose { pick (block x) stack(x, table); pick (block x) pick (block y) stack(x, y); }",
            ]
        )
    )
    if risky:
        extra = "number fluent den() { initially: () = 1; }\naction zero() { effect: den() = 0; }\n"
        extra += "action risky() { precondition: 6 / den() > 1 }\n"
        world = replace(world, text=extra + world.text)
        body = "while (!goal()) choose { pick (block x) pick (location y) stack(x, y); zero(); risky(); }"
    return Case(world, body, draw(st.integers(1, 6 if blocks == 3 else 4 if blocks == 4 else 8)))


@given(blocks_worlds())
@settings(PROPERTY, max_examples=examples(30))
def test_production_planner_returns_exactly_the_reference_result_on_larger_blocks_worlds(case: Case) -> None:
    pb = case.problem()
    assert outcome(attempt(pb, "production")) == outcome(attempt(pb, "reference"))


@given(blocks_worlds(sizes=(5, 6)))
@settings(PROPERTY, max_examples=examples(40))
def test_pruning_keeps_the_full_planners_result_on_blocks_worlds_too_large_for_the_reference(case: Case) -> None:
    # The planner without a bound is the reference's result node for node (the tests above);
    # with the bound it must still choose the same plan where the reference is out of reach.
    pb = case.problem()
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert analysis.enabled
    event(f"pruning: {analysis.kind}")
    pruned, full = pb.production(), pb.production(prune=False)
    assert (pruned.feasible, pruned.value, pruned.steps) == (full.feasible, full.value, full.steps)
    assert pruned.stats.nodes <= full.stats.nodes


@given(blocks_worlds(sizes=(3, 3), risky=True))
@settings(PROPERTY, max_examples=examples(20))
def test_pruning_is_refused_where_a_branch_could_raise_and_the_result_is_the_references(case: Case) -> None:
    pb = case.problem()
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert (analysis.enabled, analysis.reason) == (False, "`/` by a value that may be 0")
    assert solve_bound(pb.sem, pb.solve, pb.horizon) is None
    reference = attempt(pb, "reference")
    event("raises" if isinstance(reference, GppRuntimeError) else "plans")
    assert outcome(attempt(pb, "production")) == outcome(reference)


# ---------------------------------------------------------------- search


def plain_search(pb: PlanningProblem) -> tuple[PolicyStep, ...] | None:
    """Depth-first search in textual order, skipping visited configurations, written plainly."""
    visited = {(pb.prog, pb.state, pb.acts)}

    def dfs(p: Prog, s: State, a: Activities) -> list[PolicyStep] | None:
        if pb.sem.final(p, s, a):
            return []
        for q, step in pb.sem.trans(p, s, a):
            s2, a2 = pb.sem.apply(step, s, a)
            if (q, s2, a2) in visited:
                continue
            visited.add((q, s2, a2))
            rest = dfs(q, s2, a2)
            if rest is not None:
                return [(p, step, q), *rest]
        return None

    found = dfs(pb.prog, pb.state, pb.acts)
    return tuple(found) if found is not None else None


@pytest.mark.slow
@given(cases(max_horizon=0, min_horizon=0))
@settings(PROPERTY, max_examples=examples(800))
def test_search_finds_an_executable_complete_execution_exactly_when_one_exists(case: Case) -> None:
    pb = case.problem()
    try:
        plan = pb.search(10_000)
    except GppRuntimeError as e:  # only a runtime error of the program itself
        assert e.code != "R0010"
        return
    assert plan.feasible == final_reachable(pb)
    if plan.feasible:
        p, s, a, _, _ = replay(pb, plan.steps)
        assert pb.sem.final(p, s, a)
    assert (plan.steps if plan.feasible else None) == plain_search(pb)
