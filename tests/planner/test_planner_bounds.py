"""Branch and bound in the production `solve` planner (gpp.planner.bounds, gpp.planner.dp).

* On random programs and rewards (those of test_planner_properties, programs whose loop ends at
  the goal the reward pays for, and programs with a division by zero on some branches) the
  production planner, pruning wherever the analysis allows it, returns exactly the reference's
  result, error included; when the analysis enables pruning, the reference never raises.
* A program whose error lies only in a branch the bound would skip: the analysis refuses, so
  the error is reported; pruning with the bound anyway would have hidden it.
* On a program built to show it, the bound prunes (node counts with and without).
* The analysis: what it proves, and why it refuses.
"""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

from bench.planner import hazards_program, tower_problem
from gpp.check import check_text
from gpp.planner.bounds import PER_STEP, STEPS_TO_GOAL, analyse, goal_distance, solve_bound
from gpp.planner.dp import solve_plan
from gpp.planner.problem import PlanningProblem, first_solve, procedure_body
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.state import State
from gpp.syntax import ast
from gpp.syntax.walk import walk
from tests.support.budget import examples
from tests.support.planner_worlds import (
    PROPERTY,
    Case,
    World,
    action_call,
    attempt,
    cases,
    conditions,
    looping_cases,
    outcome,
    statements,
    worlds,
)

# ---------------------------------------------------------------- random programs


def _with_reward(w: World, reward: str, extra: str = "") -> World:
    """`w` with another reward function (the last line of its text) and `extra` declarations."""
    lines = w.text.rstrip("\n").split("\n")
    assert lines[-1].startswith("number function reward()")
    return replace(w, text="\n".join([*lines[:-1], extra, reward]) + "\n")


@st.composite
def goal_conditions(draw: st.DrawFn, w: World) -> str:
    """A goal: a random condition, or (for the steps-to-the-goal bound) a conjunction of
    literals on distinct fluent instances."""
    if draw(st.booleans()):
        return draw(conditions(w, [], 1))
    instances = sorted({f"{f.name}({v})" if f.unary else f"{f.name}()" for f in w.fluents for v in w.values})
    chosen = draw(st.lists(st.sampled_from(instances), min_size=1, max_size=3, unique=True))
    return " & ".join(f"{draw(st.sampled_from(['', '!']))}{atom}" for atom in chosen)


@st.composite
def goal_cases(draw: st.DrawFn) -> Case:
    """`while (!goal()) choose { ... }` with one costed step per alternative, and a reward that
    pays one amount at the goal and another elsewhere: the loop-ends-at-the-goal bound, and
    the steps-to-the-goal bound when the goal is a conjunction of literals."""
    w = draw(worlds())
    condition = draw(goal_conditions(w))
    at_goal, elsewhere = draw(st.integers(-3, 9)), draw(st.integers(-3, 3))
    goal = f"bool function goal() = {condition}"
    w = _with_reward(w, f"number function reward() = if (goal()) {at_goal} else {elsewhere}", goal)

    def one_step() -> str:
        if draw(st.booleans()):
            return f"{action_call(draw, w, [])};"
        return f"pick (D v) {action_call(draw, w, ['v'])};"

    alternatives = " ".join(one_step() for _ in range(draw(st.integers(1, 4))))
    return Case(w, f"while (!goal()) choose {{ {alternatives} }}", draw(st.integers(1, 5)))


SWITCHES = """
symbol domain D = {d0, d1, d2}
bool fluent on(D x) { initially: (x) = false; }
bool fluent lit(D x) { initially: (x) = false; }
action set(D x) { precondition: !on(x) effect: on(x) = true; }
action clear(D x) { effect: on(x) = false; }
action both(D x) { effect: on(x) = true; lit(x) = !lit(x); }
action shine(D x) { precondition: on(x) effect: lit(x) = true; }
"""


@st.composite
def switch_cases(draw: st.DrawFn) -> Case:
    """Switches to set, to reach a goal of literals on distinct switches (false at the start):
    the steps-to-the-goal bound, with actions that write one or two instances."""
    instances = [f"{f}(d{i})" for f in ("on", "lit") for i in range(3)]
    chosen = draw(st.lists(st.sampled_from(instances), min_size=1, max_size=3, unique=True))
    goal = " & ".join(f"{draw(st.sampled_from(['', '', '!']))}{atom}" for atom in chosen)
    at_goal, elsewhere = draw(st.integers(0, 9)), draw(st.integers(-2, 1))

    def alternative() -> str:
        action = draw(st.sampled_from(["set", "clear", "both", "shine"]))
        if draw(st.booleans()):
            return f"pick (D v) {action}(v);"
        return f"{action}(d{draw(st.integers(0, 2))});"

    alternatives = " ".join(alternative() for _ in range(draw(st.integers(1, 4))))
    text = (
        SWITCHES + f"bool function goal() = {goal}\nnumber function reward() = if (goal()) {at_goal} else {elsewhere}\n"
    )
    world = World(("d0", "d1", "d2"), (), None, (), text)
    return Case(world, f"while (!goal()) choose {{ {alternatives} }}", draw(st.integers(1, 6)))


@st.composite
def choice_cases(draw: st.DrawFn) -> Case:
    """Choices between action calls, one after the other: many options whose values are close."""
    w = draw(worlds())

    def alternative() -> str:
        if draw(st.booleans()):
            return f"{action_call(draw, w, [])};"
        return f"pick (D v) {action_call(draw, w, ['v'])};"

    rounds = draw(st.integers(1, 3))
    body = " ".join(
        "choose { " + " ".join(alternative() for _ in range(draw(st.integers(2, 4)))) + " }" for _ in range(rounds)
    )
    return Case(w, "{ " + body + " }", draw(st.integers(max(1, rounds - 1), rounds + 1)))


@st.composite
def tight_cases(draw: st.DrawFn) -> Case:
    """A reward of at most 0 (penalties only): every option that earns 0 from here on is worth
    the bound, so the bound prunes often and exactly at the edge (equal values)."""
    base = draw(st.one_of(cases(max_horizon=3), looping_cases(max_horizon=3), goal_cases(), choice_cases()))
    terms = " + ".join(
        f"(if ({draw(conditions(base.world, [], 1))}) 0 else {draw(st.integers(-2, -1))})"
        for _ in range(draw(st.integers(1, 2)))
    )
    lines = base.world.text.rstrip("\n").split("\n")
    w = replace(base.world, text="\n".join([*lines[:-1], f"number function reward() = {terms}"]) + "\n")
    if "goal()" in base.body:  # keep the goal loop's bound: the reward pays at the goal
        paid = w.text.replace("number function reward() =", "number function reward() = if (goal()) 0 else")
        w = replace(w, text=paid)
    return Case(w, base.body, base.horizon)


@st.composite
def risky_cases(draw: st.DrawFn) -> Case:
    """A division by a fluent that some branches set to 0: the reference raises on those."""
    w = draw(worlds())
    extra = (
        "number fluent den() { initially: () = 1; }\n"
        "action zero() { effect: den() = 0; }\n"
        "action risky() { precondition: 6 / den() > 1 }"
    )
    lines = w.text.rstrip("\n").split("\n")
    w = _with_reward(w, lines[-1], extra)
    parts = draw(st.lists(statements(w, [], 1), min_size=1, max_size=3))
    parts.insert(draw(st.integers(0, len(parts))), f"choose {{ {action_call(draw, w, [])}; zero(); }}")
    parts.append(f"choose {{ {action_call(draw, w, [])}; risky(); }}")
    return Case(w, "{ " + " ".join(parts) + " }", draw(st.integers(1, 4)))


@given(st.one_of(cases(), goal_cases(), switch_cases(), tight_cases(), risky_cases()))
@settings(PROPERTY, max_examples=examples(150))
def test_pruning_production_planner_returns_exactly_the_reference_result(case: Case) -> None:
    pb = case.problem()
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    event(f"pruning: {analysis.kind or 'off'}")
    reference = attempt(pb, "reference")
    assert outcome(attempt(pb, "production")) == outcome(reference)
    if analysis.enabled:
        assert not isinstance(reference, GppRuntimeError), "the analysis proved this `solve` cannot raise"


# ---------------------------------------------------------------- an error only in a skipped branch

HIDDEN_ERROR = """
number fluent den() { initially: () = 1; }
bool fluent done() { initially: () = false; }
action complete() { effect: done() = true; }
action zero() { effect: den() = 0; }
action risky() { precondition: 6 / den() > 1 }
number function reward() = if (done()) 0 else -1
procedure main() {
    solve(3, reward()) choose { complete(); { zero(); risky(); } }
}
"""


def problem(text: str) -> PlanningProblem:
    result = check_text(text, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    return first_solve(result.model)


def test_an_error_in_a_branch_the_bound_would_skip_is_reported() -> None:
    pb = problem(HIDDEN_ERROR)
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert (analysis.reason, analysis.enabled) == ("`/` by a value that may be 0", False)
    assert analysis.span is not None and analysis.span.text == "den()"
    reference = attempt(pb, "reference")
    assert isinstance(reference, GppRuntimeError) and reference.message == "division by zero"
    assert outcome(attempt(pb, "production")) == outcome(reference)
    # The bound itself holds (the reward is at most 0): pruning with it regardless would skip
    # `zero(); risky()` after `complete()` earned 0, and hide the error.
    unchecked = solve_plan(
        pb.sem, pb.prog, pb.state, pb.acts, pb.horizon, pb.reward, pb.span, bound=lambda state, h: 0.0
    )
    assert (unchecked.feasible, unchecked.value, unchecked.actions()) == (True, -1.0, ["complete()"])


# ---------------------------------------------------------------- the memo

LATER_IS_LONGER = """
bool fluent lit() { initially: () = false; }
action on() { effect: lit() = true; }
action idle() { }
number function reward() = if (lit()) 1 else 0
procedure main() {
    solve(3, reward()) {
        choose { idle(); test(true); }
        choose { on(); { idle(); on(); on(); } }
    }
}
"""


def test_a_result_that_skipped_an_option_is_kept_for_its_horizon_only() -> None:
    # The second `choose` is met with 2 steps left (after `idle()`), where `on()` is worth 1 and
    # the longer branch, worth at most 0 + 1, is skipped; then with 3 steps left (after the
    # test), where the longer branch is worth 0 + 1 + 1. The first result must not be reused.
    pb = problem(LATER_IS_LONGER)
    assert pb.solve is not None and analyse(pb.sem.model, pb.solve).kind == PER_STEP
    pruned, reference = pb.production(), pb.reference()
    assert (pruned.value, pruned.actions()) == (reference.value, reference.actions())
    assert (pruned.value, pruned.actions()) == (2.0, ["idle()", "on()", "on()"])
    assert pruned.stats.bound_skips > 0


# ---------------------------------------------------------------- what it prunes


@pytest.mark.parametrize("trap", [0, 7])
def test_the_bound_prunes_on_a_reward_with_a_small_maximum(trap: int) -> None:
    pb = problem(hazards_program(8, trap, 6))
    pruned, full = pb.production(), pb.production(prune=False)
    assert (pruned.feasible, pruned.value, pruned.steps) == (full.feasible, full.value, full.steps)
    assert pruned.value == 0.0 and f"visit(d{trap})" not in pruned.actions()
    # Without the bound: every set of at most 5 of the 8 places visited is expanded (with 6
    # visited the horizon is reached).
    assert full.stats.nodes == sum((1, 8, 28, 56, 70, 56))
    if trap == 7:
        # The first option is always worth the bound: every later one is skipped (the places
        # not visited yet but the first, at each of the 6 steps).
        assert pruned.stats.nodes == 6
        assert pruned.stats.bound_skips == 7 + 6 + 5 + 4 + 3 + 2
    else:
        assert pruned.stats.nodes < full.stats.nodes // 2


def test_the_towers_bound_counts_the_steps_to_the_goal() -> None:
    pb = tower_problem(4, 10)
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert (analysis.reason, analysis.kind, analysis.reward_low, analysis.reward_high) == (None, STEPS_TO_GOAL, -1, 100)
    assert analysis.goal_atoms is not None and len(analysis.goal_atoms) == 4
    assert (analysis.writes_per_step, analysis.goal_values) == (1, (100, -1))
    # Without the steps: the goal pays 100 once, at the last step, whatever the horizon.
    assert analysis.bound is not None and [analysis.bound(h) for h in range(4)] == [0.0, 100.0, 100.0, 100.0]
    bound = solve_bound(pb.sem, pb.solve, pb.horizon)
    assert bound is not None
    # From the start all four blocks are misplaced: at least 4 steps, so at most 100 - 3; with
    # 3 steps left the goal is out of reach, and as the loop's body always steps (the loop ends
    # only at the goal) a branch that does not reach it makes every step, worth -1 each.
    assert analysis.always_steps
    assert [bound(pb.state, h) for h in range(6)] == [0.0, -1.0, -2.0, -3.0, 97.0, 97.0]
    pruned, full = pb.production(), pb.production(prune=False)
    assert (pruned.value, pruned.steps) == (full.value, full.steps)
    assert full.stats.nodes == 392 and pruned.stats.nodes < 392 // 10


# ---------------------------------------------------------------- the analysis

WORLD = """
symbol domain D = {a, b}
symbol domain E = {a, b, c}
D fluent at() { initially: () = a; }
E fluent wide() { initially: () = c; }
number fluent n() { initially: () = 0; }
number fluent grow() { initially: () = 0; }
bool fluent p(D x) { initially: (x) = false; }
action go(D x) { precondition: at() != x effect: at() = x; }
action tick() { effect: n() = (n() + 1) % 3; }
action inc() { effect: grow() = grow() + 1; }
action put(E y) { effect: wide() = y; }
"""


@pytest.mark.parametrize(
    ("reward", "body", "reason"),
    [
        ("n()", "while (true) pick (D x) go(x);", None),
        ("if (p(a)) 5 else n() * 2 - 1", "{ test(p(a)); tick(); choose { go(a); go(b); } }", None),
        ("grow()", "inc();", "the reward is not a whole number in a known interval"),
        ("n() / 2", "tick();", "the reward is not a whole number in a known interval"),
        ("1", "if (grow() + 1 > 2) tick();", "an operand of arithmetic that may be `null` or unbounded"),
        ("1", "if (6 % n() == 1) tick();", "`%` by a value that may be 0"),
        ("1", "while (true) { test(p(a)); tick(); }", "a test inside a loop (a loop of free steps is an error)"),
        ("1", "pick (E y) go(y);", "a value that may be outside domain `D`"),
        ("1", "at() = wide();", "a value that may be outside domain `D`"),
        ("1", "{ put(c); wide() = at(); }", None),
        ("1", "{ start(tick()); end(tick()); }", "`HookStmt` statements are not analysed"),
        ("1", "again();", "procedure `again` is recursive"),
    ],
)
def test_the_analysis_proves_or_says_why_not(reward: str, body: str, reason: str | None) -> None:
    text = WORLD + "procedure again() { tick(); again(); }\n"
    text += f"number function r() = {reward}\nprocedure main() {{ solve(4, r()) {body} }}\n"
    pb = problem(text)
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert analysis.reason == reason
    assert analysis.kind == (PER_STEP if reason is None else None)


def test_no_bound_beyond_exact_sums_or_the_largest_horizon() -> None:
    large = "number function r() = if (p(a)) 1000000000000 else 0\n"
    pb = problem(WORLD + large + "procedure main() { solve(4, r()) go(b); }\n")
    assert pb.solve is not None
    assert solve_bound(pb.sem, pb.solve, 4) is not None
    assert solve_bound(pb.sem, pb.solve, 9000) is None  # 10**12 * 9001 >= 2**53
    small = problem(WORLD + "number function r() = n()\nprocedure main() { solve(4, r()) go(b); }\n")
    assert small.solve is not None
    assert solve_bound(small.sem, small.solve, 1000) is not None
    assert solve_bound(small.sem, small.solve, 1001) is None


@pytest.mark.parametrize(
    ("body", "reason", "distance"),
    [
        ("while (!(p(a) & p(b))) pick (D x) mark(x);", None, 2),
        ("while (!(!p(a) & p(b))) pick (D x) mark(x);", None, 1),
        ("while (!(p(a) & p(b))) choose { mark(a); if (p(a)) mark(b); else go(b); }", None, 2),
        ("while (!(p(a) & p(b))) if (p(a)) mark(b);", "a run of the loop's body may end without a costed step", 0),
        ("while (!(p(a) & p(b))) {}", "a run of the loop's body may end without a costed step", 0),
        ("while (!(p(a) & p(b))) { mark(a); mark(b); }", "a run of the loop's body may end without a costed step", 0),
        ("while (p(a)) mark(b);", "the loop's condition is not `!G`", 0),
        ("mark(a);", "not a `while` loop", 0),
        ("while (!(p(a) | p(b))) mark(a);", None, 1),
        ("while (!exists(D x) p(x)) mark(a);", "the goal is not a conjunction on distinct fluent instances", 0),
        ("while (!(p(a) & !p(a))) mark(a);", "the goal is not a conjunction on distinct fluent instances", 0),
        ("while (!p(a)) { test(p(b)); mark(a); }", "a test inside a loop (a loop of free steps is an error)", 0),
    ],
)
def test_the_goal_distance_for_search_or_why_not(body: str, reason: str | None, distance: int) -> None:
    text = WORLD + "action mark(D x) { effect: p(x) = true; }\n"
    text += f"procedure main() {{ search {body} }}\n"
    result = check_text(text, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    sem, _ = procedure_body(result.model)
    search = next(n for f in result.model.files for n in walk(f.program) if isinstance(n, ast.Search))
    analysis = goal_distance(sem, search.body)
    assert analysis.reason == reason
    assert (analysis.distance is None) == (reason is not None)
    if analysis.distance is not None:
        assert analysis.distance(State()) == distance  # conjuncts false at the start, one instance a step


# ---------------------------------------------------------------- objects not well placed

STACKS = """
symbol domain block = {a, b, c}
symbol domain location = block | {table}
location fluent loc(block x) { initially: (a) = b; (b) = table; (c) = table; }
bool fluent lit() { initially: () = false; }
action stack(block x, location y) {
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}
action put(block x, location y) { precondition: x != y effect: loc(x) = y; }
action light() { effect: lit() = true; }
"""


@pytest.mark.parametrize(
    ("goal", "body", "reason", "distance"),
    [
        # b must move onto c; a is on b (its goal holds) and must leave and come back: 2 + 1.
        ("loc(a) == b & loc(b) == c", "pick (block x) pick (location y) stack(x, y);", None, 3),
        ("loc(a) == b & loc(b) == c & loc(c) == table", "pick (block x) stack(x, table);", None, 3),
        ("loc(c) == a", "pick (block x) pick (location y) stack(x, y);", None, 1),
        # `put` moves a block with others on it: b onto c carries a along, one step.
        (
            "loc(a) == b & loc(b) == c",
            "pick (block x) pick (location y) put(x, y);",
            "action `put` writes `loc(p)` without requiring `!exists(z) loc(z) == p`",
            1,
        ),
        (
            "loc(a) == b & lit()",
            "choose { light(); pick (block x) stack(x, table); }",
            "a conjunct of the goal is not `F(b) == v` for a unary fluent F",
            1,
        ),
        (
            "loc(a) == b & loc(b) == c",
            "choose { loc(c) = a; pick (block x) stack(x, table); }",
            "a statement assigns `loc`",
            1,
        ),
    ],
)
def test_the_not_well_placed_distance_or_why_not(goal: str, body: str, reason: str | None, distance: int) -> None:
    text = STACKS + f"bool function goal() = {goal}\nnumber function reward() = if (goal()) 10 else -1\n"
    pb = problem(text + f"procedure main() {{ solve(4, reward()) while (!goal()) {body} }}\n")
    assert pb.solve is not None
    analysis = analyse(pb.sem.model, pb.solve)
    assert analysis.kind == STEPS_TO_GOAL
    assert analysis.placement_reason == reason
    assert (analysis.placement is None) == (reason is not None)
    bound = solve_bound(pb.sem, pb.solve, pb.horizon)
    assert bound is not None
    # Reaching the goal at step n at the soonest: worth at most 10 - (n - 1).
    assert bound(pb.state, 4) == 10 - (distance - 1)
    pruned, reference = pb.production(), pb.reference()
    assert (pruned.feasible, pruned.value, pruned.steps) == (reference.feasible, reference.value, reference.steps)
    if reason is not None and "put" in body:
        # The stronger distance would say 3 here: it does not hold without the precondition.
        assert reference.actions() == ["put(b,c)"]


# ---------------------------------------------------------------- global pruning


@pytest.mark.parametrize("blocks", [5, 6, 7])
def test_global_pruning_walks_straight_to_the_towers_reversal(blocks: int) -> None:
    # The root is asked for its bound (every block moved once: 100 - (blocks - 1), and the
    # plan's value counts R(s0) = -1 too); the best
    # option first is always one that puts a block in place, and nothing else reaches the
    # threshold: one node per step and the root, the plan of the full planner.
    pb = tower_problem(blocks, 14)
    pruned, full = pb.production(), pb.production(prune=False)
    assert (pruned.value, pruned.steps) == (full.value, full.steps)
    assert pruned.value == 100 - blocks
    assert pruned.stats.nodes == blocks + 1
    assert full.stats.nodes > 100 * pruned.stats.nodes
