"""`search` on the planner's speed tier, and its iterative deepening cut by the goal distance
(gpp.planner.search, gpp.planner.bounds.goal_distance).

* On the random programs of the planners' property tests, both strategies enter the same nodes
  and return the same execution or the same error with the generated successors, with the
  closures alone and with the semantics itself (what `search` ran on before).
* On goal loops (the programs the goal distance is for, and programs just outside it, where
  the cut must be refused), iterative deepening cut by the bound returns exactly what the uncut
  one returns: the same execution, none, or the same error, the step bound's included; it
  enters no more nodes; and where the analysis allows the cut, no error but the step bound's
  is possible.
* Random blocks worlds (the not-well-placed distance): the same, cut or not.
* The towers: cut, one node per move; uncut, exactly the nodes the interpreted search entered.
* `gpp run --search-strategy iterative-deepening` cuts with the bound too.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

from bench.blocksworld import program, random_instance
from bench.planner import reversal, tower_problem, tower_program
from gpp.check import check_text
from gpp.planner.bounds import goal_distance
from gpp.planner.problem import PlanningProblem, first_solve
from gpp.planner.search import (
    CLOSURES,
    DEFAULT_STEP_BOUND,
    DEPTH_FIRST,
    GENERATED,
    INTERPRETED,
    ITERATIVE_DEEPENING,
)
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Code
from tests.support.budget import examples
from tests.support.cli import run
from tests.support.planner_worlds import (
    PROPERTY,
    Action,
    Case,
    Fluent,
    World,
    action_call,
    cases,
    conditions,
    effects,
    looping_cases,
    staggered_cases,
    worlds,
)

Outcome = tuple[object, ...]


def searched(pb: PlanningProblem, bound: int, strategy: str, prune: bool = True, tier: str = GENERATED) -> Outcome:
    """What a search returns (its execution and the nodes it entered and skipped), or its error."""
    try:
        plan = pb.search(bound, strategy, prune=prune, tier=tier)
    except GppRuntimeError as e:
        return ("error", e.code, e.message, e.span, e.notes)
    counts = replace(plan.stats, seconds=0.0)
    return ("plan", plan.feasible, plan.steps, [s.describe() for _, s, _ in plan.steps], counts)


def result_of(outcome: Outcome) -> Outcome:
    """The outcome without the statistics."""
    return outcome[:-1] if outcome[0] == "plan" else outcome


# ---------------------------------------------------------------- the speed tier


@st.composite
def search_cases(draw: st.DrawFn) -> tuple[Case, str, int]:
    """A random program, a strategy and a step bound (a small one for iterative deepening, which
    on an endless program goes on to the bound)."""
    case = draw(st.one_of(cases(max_horizon=0, min_horizon=0), looping_cases(), staggered_cases()))
    strategy = draw(st.sampled_from([DEPTH_FIRST, ITERATIVE_DEEPENING]))
    bounds = [2, 5, 12] + ([DEFAULT_STEP_BOUND] if strategy == DEPTH_FIRST else [])
    return case, strategy, draw(st.sampled_from(bounds))


@given(search_cases())
@settings(PROPERTY, max_examples=examples(200))
def test_search_on_the_speed_tier_enters_the_nodes_the_semantics_enters(drawn: tuple[Case, str, int]) -> None:
    case, strategy, bound = drawn
    pb = case.problem()
    interpreted = searched(pb, bound, strategy, prune=False, tier=INTERPRETED)
    event(f"{strategy}: {interpreted[0]}")
    # Generated twice: the second search runs the functions the first one made.
    for tier in (GENERATED, GENERATED, CLOSURES):
        assert searched(pb, bound, strategy, prune=False, tier=tier) == interpreted


# ---------------------------------------------------------------- the cut


# Actions that turn switches on, which goals of switches mostly need.
SWITCHING = """
action set(D p) { effect: on(p) = true; }
action light(D p) { precondition: on(p) effect: lit(p) = true; up() = !up(); }
"""


@st.composite
def switch_worlds(draw: st.DrawFn) -> World:
    """Switches, all off at the start but one, actions that turn them on, and random actions:
    goals of switches to turn on need steps, and can often be reached."""
    values = ("d0", "d1", "d2")
    fluents = (Fluent("on", True), Fluent("lit", True), Fluent("up", False))
    random = tuple(Action(f"act{i}", draw(st.booleans())) for i in range(draw(st.integers(0, 2))))
    shell = World(values, fluents, None, random, "")
    lines = [
        "symbol domain D = {d0, d1, d2}",
        "bool fluent on(D x) { initially: (x) = false; }",
        "bool fluent lit(D x) { initially: (x) = false; (d2) = true; }",
        "bool fluent up() { initially: () = false; }",
        SWITCHING,
    ]
    for a in random:
        scope = ["p"] if a.unary else []
        body = []
        if draw(st.booleans()):
            body.append(f"precondition:\n    {draw(conditions(shell, scope, 1))}")
        body.append("effect:\n    " + "\n    ".join(draw(effects(shell, scope)) or ["up() = true;"]))
        lines.append(f"action {a.name}({'D p' if a.unary else ''}) {{\n" + "\n".join(body) + "\n}")
    lines.append("number function reward() = 0")
    actions = (Action("set", True), Action("light", True), *random)
    return World(values, fluents, None, actions, "\n".join(lines) + "\n")


@st.composite
def goal_loops(draw: st.DrawFn) -> Case:
    """`while (!goal()) choose { ... }` over a random world or switches. The goal: mostly a
    conjunction of literals on distinct fluent instances, else a random condition. The
    alternatives: one costed step each (an action call, a `pick` of one, an assignment, an `if`
    of two such), or now and then one that may end the loop without a step or make two (an `if`
    without `else`, an empty block, a test, two calls), where the cut must be refused."""
    switches = draw(st.booleans())
    w = draw(switch_worlds() if switches else worlds())
    instances = sorted({f"{f.name}({v})" if f.unary else f"{f.name}()" for f in w.fluents for v in w.values})
    if draw(st.sampled_from([False, False, False, True])):  # (integers would favour 0)
        goal = draw(conditions(w, [], 1))
    else:
        chosen = draw(st.lists(st.sampled_from(instances), min_size=1, max_size=4, unique=True))
        # Switches: mostly to turn on (off at the start).
        signs = ["", "", "", "", "!"] if switches else ["", "!"]
        goal = " & ".join(f"{draw(st.sampled_from(signs))}{atom}" for atom in chosen)

    def one_step() -> str:
        kind = draw(st.sampled_from(["call", "pick", "pick", "assign", "if"]))
        if kind == "call":
            return f"{action_call(draw, w, [])};"
        if kind == "pick":
            unary = [a.name for a in w.actions if a.unary]
            if unary and draw(st.booleans()):  # the same action on each value
                return f"pick (D v) {draw(st.sampled_from(unary))}(v);"
            return f"pick (D v) {action_call(draw, w, ['v'])};"
        if kind == "assign":
            return f"{draw(st.sampled_from(instances))} = {draw(st.sampled_from(['true', 'false']))};"
        return f"if ({draw(conditions(w, [], 1))}) {action_call(draw, w, [])}; else {action_call(draw, w, [])};"

    def refused() -> str:
        kind = draw(st.sampled_from(["if", "empty", "test", "two"]))
        if kind == "if":
            return f"if ({draw(conditions(w, [], 1))}) {action_call(draw, w, [])};"
        if kind == "empty":
            return "{ }"
        if kind == "test":
            return f"test({draw(conditions(w, [], 1))});"
        return f"{{ {action_call(draw, w, [])}; {action_call(draw, w, [])}; }}"

    alternatives = [one_step() for _ in range(draw(st.integers(1, 4)))]
    if switches:  # with ways to turn each switch on, among the others
        alternatives += draw(
            st.sampled_from([[], ["pick (D v) set(v);"], ["pick (D v) set(v);", "pick (D v) light(v);"]])
        )
        alternatives = draw(st.permutations(alternatives))
    if draw(st.sampled_from([False, False, False, False, True])):
        alternatives.insert(draw(st.integers(0, len(alternatives))), refused())
    world = replace(w, text=w.text + f"bool function goal() = {goal}\n")
    return Case(world, f"while (!goal()) choose {{ {' '.join(alternatives)} }}", 1)


@given(goal_loops(), st.integers(1, 12))
@settings(PROPERTY, max_examples=examples(300))
def test_the_cut_iterative_deepening_returns_exactly_what_the_uncut_one_returns(case: Case, bound: int) -> None:
    pb = case.problem()
    assert isinstance(pb.prog, Code)
    analysis = goal_distance(pb.sem, pb.prog.stmt)
    uncut = searched(pb, bound, ITERATIVE_DEEPENING, prune=False)
    cut = searched(pb, bound, ITERATIVE_DEEPENING)
    skips = cut[-1].bound_skips if cut[0] == "plan" else 0  # type: ignore[attr-defined]
    event(f"cut: {'off' if analysis.distance is None else 'on, used' if skips else 'on'}; {uncut[0]}")
    assert result_of(cut) == result_of(uncut)
    if cut[0] == "plan":
        assert cut[-1].nodes <= uncut[-1].nodes  # type: ignore[attr-defined]
    if analysis.distance is not None and uncut[0] == "error":
        assert uncut[2] == f"`search` exceeded its bound of {bound} steps without finding an end"


@given(st.integers(4, 6), st.integers(0, 10**6), st.sampled_from([3, 5, 8, DEFAULT_STEP_BOUND]))
@settings(PROPERTY, max_examples=examples(40))
def test_the_cut_search_of_a_random_blocks_world_is_the_uncut_one(blocks: int, seed: int, bound: int) -> None:
    # The distance here is the not-well-placed one (gpp.planner.bounds): blocks that must move.
    instance = random_instance(blocks, seed)
    result = check_text(program(instance, 14), lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    pb = first_solve(result.model)
    cut = searched(pb, bound, ITERATIVE_DEEPENING)
    uncut = searched(pb, bound, ITERATIVE_DEEPENING, prune=False)
    event(f"{cut[0]}")
    assert result_of(cut) == result_of(uncut)
    if cut[0] == "plan":
        assert cut[1] and cut[-1].nodes <= uncut[-1].nodes  # type: ignore[attr-defined]


# ---------------------------------------------------------------- the towers


# The nodes iterative deepening entered on the towers before it ran on the speed tier (on the
# semantics itself, uncut).
UNCUT_NODES = {4: 27, 5: 100, 6: 407}


@pytest.mark.parametrize("blocks", sorted(UNCUT_NODES))
def test_the_cut_search_of_a_tower_enters_one_node_per_move(blocks: int) -> None:
    pb = tower_problem(blocks, 14)
    cut = pb.search(DEFAULT_STEP_BOUND, ITERATIVE_DEEPENING)
    uncut = pb.search(DEFAULT_STEP_BOUND, ITERATIVE_DEEPENING, prune=False)
    assert cut.actions() == uncut.actions() == reversal(blocks)
    assert cut.steps == uncut.steps
    assert (cut.stats.nodes, uncut.stats.nodes) == (blocks + 1, UNCUT_NODES[blocks])
    assert cut.stats.bound_skips > 0 and uncut.stats.bound_skips == 0


def test_a_tower_longer_than_the_step_bound_is_the_bound_s_error_cut_or_not() -> None:
    pb = tower_problem(4, 14)
    errors = []
    for prune in (True, False):
        with pytest.raises(GppRuntimeError) as caught:
            pb.search(3, ITERATIVE_DEEPENING, prune=prune)
        errors.append((caught.value.message, caught.value.span, caught.value.notes))
    assert errors[0] == errors[1]
    assert errors[0][0] == "`search` exceeded its bound of 3 steps without finding an end"


SWITCHES = """
symbol domain D = {d0, d1, d2}
bool fluent on(D x) { initially: (x) = false; }
bool fluent lit(D x) { initially: (x) = false; }
action set(D x) { precondition: !on(x) effect: on(x) = true; }
bool function goal() = on(d0) & lit(d1)
number function reward() = 0
procedure main() { solve(1, reward()) while (!goal()) pick (D v) set(v); }
"""


def test_a_goal_out_of_reach_is_no_execution_cut_or_not() -> None:
    result = check_text(SWITCHES, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    pb = first_solve(result.model)
    assert isinstance(pb.prog, Code) and goal_distance(pb.sem, pb.prog.stmt).distance is not None
    cut = pb.search(50, ITERATIVE_DEEPENING)
    uncut = pb.search(50, ITERATIVE_DEEPENING, prune=False)
    assert not cut.feasible and not uncut.feasible
    assert cut.stats.bound_skips > 0 and cut.stats.nodes <= uncut.stats.nodes


def test_gpp_run_cuts_iterative_deepening_with_the_goal_distance(tmp_path: Path) -> None:
    program = tmp_path / "tower.gpp"
    program.write_text(tower_program(5, 14).replace("solve(14, reward())", "search"))
    trace = tmp_path / "trace.jsonl"
    result = run("run", "--quiet", "--trace", str(trace), "--search-strategy", ITERATIVE_DEEPENING, str(program))
    assert result.returncode == 0, result.stderr
    text = trace.read_text()
    assert '"policy": [' + ", ".join(f'"{move}"' for move in reversal(5)) + "]" in text
    assert '"nodes": 6,' in text
