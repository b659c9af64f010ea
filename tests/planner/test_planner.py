"""The planners for `solve` (SEMANTICS §5) and `search` (§6), one behaviour per test.

The production planner (gpp.planner.dp) is checked against the reference planner (the plain
recursive definition) on every problem here; tests/planner/test_planner_properties.py does the same on
random worlds and programs.
"""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from rich.console import Console

from gpp.check import check_text
from gpp.planner.problem import PlanningProblem, first_solve, procedure_body
from gpp.planner.profile import render_profile
from gpp.planner.reference import NodeBudgetExceeded
from gpp.planner.result import Plan
from gpp.planner.search import search_plan
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.events import PlanEvent, StartEvent, TraceEvent, from_json_dict
from gpp.runtime.executor import RunStatus
from gpp.runtime.state import Activities, State

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
PROGRAMS = ROOT / "tests" / "programs"

BLOCKS_WORLD = """
symbol domain block = {a, b, c}
symbol domain location = block | {table}
location fluent loc(block x) { initially: (a) = c; (b) = table; (c) = b; }
action stack(block x, location y) {
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x)
    & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}
bool function goal() = loc(a) == table & loc(b) == a & loc(c) == b
number function reward() = if (goal()) 100 else -1
"""

STACK_UNTIL_GOAL = "solve(8, reward()) while (!goal()) pick (block x) pick (location y) stack(x, y);"

COUNTER_WORLD = """
symbol domain item = {x, y, z}
number fluent n() { initially: () = 0; }
bool fluent done(item i) { initially: (i) = false; }
action inc() { effect: n() = n() + 1; }
action dec() { precondition: n() > 0 effect: n() = n() - 1; }
action mark(item i) { precondition: !done(i) effect: done(i) = true; }
action noop() {}
number function r() = n()
number function flat() = 0
number function cost() = -1
"""


def problem(world: str, main: str) -> PlanningProblem:
    result = check_text(world + "\nprocedure main() {\n" + main + "\n}\n", lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    return first_solve(result.model)


def both(pb: PlanningProblem) -> Plan:
    """The production plan, after checking that it is exactly the reference plan."""
    production, reference = pb.production(), pb.reference()
    assert (production.feasible, production.value, production.steps) == (
        reference.feasible,
        reference.value,
        reference.steps,
    )
    return production


def run(path: Path) -> RunOutcome:
    return run_program(path, RunOptions(record=True))


def plans(outcome: RunOutcome) -> list[PlanEvent]:
    assert outcome.recording is not None
    return outcome.recording.of(PlanEvent)


def started(outcome: RunOutcome) -> list[str]:
    assert outcome.recording is not None
    return [r.action for r in outcome.recording.of(StartEvent)]


# ---------------------------------------------------------------- the targets


def test_three_block_blocksworld_executes_the_unique_optimum_with_value_96() -> None:
    outcome = run(EXAMPLES / "blocks_planning.gpp")
    assert outcome.ok
    [plan] = plans(outcome)
    expected = ["stack(a,table)", "stack(c,table)", "stack(b,a)", "stack(c,b)"]
    assert plan.value == 96
    assert list(plan.policy) == expected
    assert started(outcome) == expected


def test_three_block_blocksworld_reference_and_production_agree() -> None:
    plan = both(problem(BLOCKS_WORLD, STACK_UNTIL_GOAL))
    assert plan.value == 96
    assert plan.actions() == ["stack(a,table)", "stack(c,table)", "stack(b,a)", "stack(c,b)"]


def test_five_block_tower_is_reversed_by_the_optimal_five_moves() -> None:
    outcome = run(EXAMPLES / "tower5.gpp")
    assert outcome.ok
    [plan] = plans(outcome)
    expected = ["stack(a,table)", "stack(b,a)", "stack(c,b)", "stack(d,c)", "stack(e,d)"]
    assert list(plan.policy) == expected
    assert plan.value == 95  # R(s0) and four more steps at -1, then the goal at 100
    assert started(outcome) == expected


@pytest.mark.slow
def test_production_expands_over_1000_times_fewer_nodes_than_the_reference_on_the_five_block_tower() -> None:
    result = check_text((EXAMPLES / "tower5.gpp").read_text(encoding="utf-8"), lint=False)
    pb = first_solve(result.model)
    production = pb.production()
    # The reference's node count, counted exactly without running it for half an hour (the
    # count equals the reference's own, see the test below).
    assert pb.reference_nodes() >= 1000 * production.stats.nodes


@pytest.mark.parametrize("horizon", range(9))
def test_reference_node_count_is_the_number_of_nodes_the_reference_expands(horizon: int) -> None:
    pb = problem(BLOCKS_WORLD, STACK_UNTIL_GOAL)
    pb = pb.with_horizon(horizon)
    assert pb.reference_nodes() == pb.reference().stats.nodes


def test_reference_planner_stops_after_its_node_budget() -> None:
    pb = problem(BLOCKS_WORLD, STACK_UNTIL_GOAL)
    with pytest.raises(NodeBudgetExceeded) as caught:
        pb.reference(budget=100)
    assert caught.value.budget == 100


def test_production_planner_reports_its_work() -> None:
    plan = problem(BLOCKS_WORLD, STACK_UNTIL_GOAL)
    stats = plan.production(prune=False).stats
    # 13 arrangements of three blocks, all met without pruning: the reward is evaluated once
    # per state.
    assert stats.reward_evaluations == 13
    assert stats.nodes < 100
    assert stats.cache_hits > 0


# ---------------------------------------------------------------- the choice rule


def test_ties_go_to_the_first_alternative_of_choose() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(1, flat()) choose { mark(y); mark(x); }"))
    assert plan.actions() == ["mark(y)"]


def test_ties_go_to_the_first_value_of_pick() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(1, flat()) pick (item i in {z, x, y}) mark(i);"))
    assert plan.actions() == ["mark(z)"]


def test_pick_without_in_tries_the_domain_in_declaration_order() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(1, flat()) pick (item i) mark(i);"))
    assert plan.actions() == ["mark(x)"]


def test_higher_value_beats_textual_order() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(2, r()) choose { mark(x); inc(); }"))
    assert plan.actions() == ["inc()"]
    assert plan.value == 0 + 1


def test_stopping_where_the_program_may_end_wins_a_tie_with_going_on() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(3, flat()) choose { mark(x); {} }"))
    assert plan.feasible
    assert plan.steps == ()


def test_a_feasible_branch_beats_a_better_infeasible_one() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(5, r()) choose { { inc(); inc(); test(n() > 5); } mark(x); }"))
    assert plan.actions() == ["mark(x)"]
    assert plan.value == 0


def test_no_feasible_branch_gives_no_plan() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(5, r()) choose { dec(); { inc(); test(false); } }"))
    assert not plan.feasible
    assert plan.steps == ()


def test_a_branch_that_reaches_the_horizon_is_feasible() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(3, r()) { inc(); inc(); inc(); test(false); }"))
    assert plan.feasible
    assert plan.actions() == ["inc()", "inc()", "inc()"]
    assert plan.value == 0 + 1 + 2 + 3


def test_value_is_the_reward_of_the_start_state_and_after_every_costed_step() -> None:
    pb = problem(COUNTER_WORLD, "solve(4, r()) { inc(); test(true); inc(); dec(); }")
    plan = both(pb)
    assert plan.value == 0 + 1 + 2 + 1


def test_tests_are_free_and_assignments_cost_one_step() -> None:
    pb = problem(COUNTER_WORLD, "solve(2, r()) { test(true); test(n() == 0); n() = 5; inc(); inc(); }")
    plan = both(pb)
    assert [step.describe() for _, step, _ in plan.steps] == ["test", "test", "n() = 5", "inc()"]
    assert plan.value == 0 + 5 + 6


def test_horizon_zero_plans_nothing() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(0, r()) { inc(); }"))
    assert plan.feasible
    assert plan.steps == ()
    assert plan.value == 0


def test_raising_the_horizon_keeps_a_plan_that_ends_the_program() -> None:
    pb = problem(COUNTER_WORLD, "solve(2, r()) while (n() < 2) choose { dec(); inc(); }")
    low, high = both(pb), both(pb.with_horizon(5))
    assert low.actions() == ["inc()", "inc()"]
    assert low.value == 0 + 1 + 2
    # The old plan is still there; going down and up again first is worth more.
    assert high.actions() == ["inc()", "dec()", "inc()", "inc()"]
    assert high.value == 0 + 1 + 0 + 1 + 2


def test_raising_the_horizon_can_lower_the_value_of_a_program_that_cannot_end() -> None:
    # Every step costs 1 and the loop never ends: one more step of horizon is one more cost.
    pb = problem(COUNTER_WORLD, "solve(2, cost()) while (true) inc();")
    assert both(pb).value == -3
    assert both(pb.with_horizon(3)).value == -4


def test_a_result_that_never_reached_the_horizon_is_reused_only_for_larger_horizons() -> None:
    # `inc(); test(false);` is first planned with horizon 2 (after the free test): infeasible,
    # one costed step deep. After noop() the same configuration has horizon 1, where the
    # branch reaches the horizon before the false test: feasible.
    pb = problem(COUNTER_WORLD, "solve(2, r()) { choose { test(true); noop(); } inc(); test(false); }")
    plan = both(pb)
    assert plan.actions() == ["noop()", "inc()"]
    assert plan.value == 0 + 0 + 1


def test_a_repeated_configuration_is_planned_once_per_horizon() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(6, r()) while (true) choose { inc(); dec(); noop(); }"))
    assert plan.actions() == ["inc()"] * 6
    assert plan.stats.cache_hits > 0


def test_an_option_that_duplicates_an_earlier_one_is_pruned() -> None:
    pb = problem(COUNTER_WORLD, "solve(2, r()) while (true) choose { noop(); noop(); inc(); }")
    plan = both(pb)
    assert plan.actions() == ["inc()", "inc()"]
    assert plan.stats.pruned > 0


# ---------------------------------------------------------------- loops without costed steps


@pytest.mark.parametrize("planner", ["production", "reference"])
def test_a_loop_without_costed_step_is_an_error_at_the_loop(planner: str) -> None:
    pb = problem(COUNTER_WORLD, "solve(3, r()) {\n    inc();\n    while (n() > 0) test(true);\n}")
    with pytest.raises(GppRuntimeError) as caught:
        getattr(pb, planner)()
    error = caught.value
    assert error.code == "R0010"
    assert error.message == "this loop can run forever without a costed step"
    assert error.span is not None
    assert error.span.text.startswith("while (n() > 0)")


def test_tests_inside_a_loop_whose_body_always_makes_a_costed_step_are_fine() -> None:
    plan = both(problem(COUNTER_WORLD, "solve(3, r()) while (n() < 2) { test(true); inc(); test(n() > 0); }"))
    assert plan.actions() == ["inc()", "inc()"]


def test_a_loop_whose_body_may_skip_every_costed_step_is_an_error() -> None:
    # One alternative of the body makes no costed step: planning it would go round forever.
    pb = problem(COUNTER_WORLD, "solve(3, r()) while (n() < 2) choose { test(true); inc(); }")
    for planner in (pb.production, pb.reference):
        with pytest.raises(GppRuntimeError) as caught:
            planner()
        assert caught.value.code == "R0010"
        assert caught.value.span is not None
        assert caught.value.span.text.startswith("while (n() < 2)")


@pytest.mark.slow
@pytest.mark.parametrize("planner", ["production", "reference"])
def test_a_recursion_without_costed_step_is_an_error_not_a_crash(planner: str) -> None:
    world = COUNTER_WORLD + "procedure deeper() { test(true); deeper(); test(true); }\n"
    pb = problem(world, "solve(3, r()) deeper();")
    with pytest.raises(GppRuntimeError) as caught:
        getattr(pb, planner)()
    assert caught.value.code == "R0010"
    assert caught.value.span is not None
    assert caught.value.span.text.startswith("solve(3, r())")


def test_a_loop_without_costed_step_stops_the_run_with_a_diagnostic(tmp_path: Path) -> None:
    path = tmp_path / "loop.gpp"
    path.write_text(COUNTER_WORLD + "procedure main() {\n    solve(3, r()) while (true) test(true);\n}\n")
    outcome = run(path)
    assert outcome.result is not None
    assert outcome.result.status is RunStatus.ERROR
    [error] = [d for d in outcome.diagnostics if d.code == "R0010"]
    assert error.span.text.startswith("while (true)")


# ---------------------------------------------------------------- online


def test_solve_program_runs_to_its_postcondition() -> None:
    assert run(PROGRAMS / "solve.gpp").ok


def test_search_program_runs_to_its_postcondition() -> None:
    assert run(PROGRAMS / "search.gpp").ok


def test_solve_without_a_feasible_plan_blocks_with_a_diagnostic(tmp_path: Path) -> None:
    path = tmp_path / "stuck.gpp"
    path.write_text(COUNTER_WORLD + "procedure main() {\n    solve(3, r()) { dec(); }\n}\n")
    outcome = run(path)
    assert outcome.result is not None
    assert outcome.result.status is RunStatus.BLOCKED
    assert "found no plan" in outcome.diagnostics[-1].message
    [plan] = plans(outcome)
    assert plan.feasible is False


# ---------------------------------------------------------------- search


def search(world: str, main: str, bound: int = 10_000) -> Plan:
    result = check_text(world + "\nprocedure main() {\n" + main + "\n}\n", lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    sem, prog = procedure_body(result.model)
    return search_plan(sem, prog, State(), Activities(), bound)


def test_search_takes_the_first_complete_execution_in_textual_order() -> None:
    plan = search(COUNTER_WORLD, "pick (item i) { mark(i); test(i != x); }")
    assert plan.feasible
    assert plan.actions() == ["mark(y)"]


def test_search_backtracks_over_a_false_test_later_in_the_program() -> None:
    plan = search(COUNTER_WORLD, "{ choose { inc(); { inc(); inc(); } } test(n() == 2); }")
    assert plan.actions() == ["inc()", "inc()"]


def test_search_terminates_on_a_cyclic_finite_state_space_without_solution() -> None:
    plan = search(COUNTER_WORLD, "while (true) choose { mark(x); { inc(); dec(); } }")
    assert not plan.feasible
    assert plan.stats.pruned > 0


def test_search_step_bound_is_an_error_at_the_program_point_reached() -> None:
    with pytest.raises(GppRuntimeError) as caught:
        search(COUNTER_WORLD, "while (true) inc();", bound=50)
    assert caught.value.code == "R0010"
    assert caught.value.message == "`search` exceeded its bound of 50 steps without finding an end"
    assert caught.value.span is not None
    assert caught.value.span.text == "while (true) inc();"


# ---------------------------------------------------------------- profile


def render(events: list[TraceEvent]) -> str:
    out = io.StringIO()
    render_profile(events, Console(file=out, width=140, color_system=None))
    return out.getvalue()


def test_profile_has_a_row_per_plan_and_replan_with_the_planner_figures() -> None:
    trace_records: list[dict[str, object]] = [
        {"t": 0.0, "event": "start", "action": "a()", "id": 1, "mapped": "a", "args": {}, "at": None},
        {
            "t": 0.0,
            "event": "plan",
            "kind": "solve",
            "feasible": True,
            "value": 96.0,
            "horizon": 8,
            "policy": ["stack(a,table)", "stack(c,table)", "stack(b,a)", "stack(c,b)"],
            "nodes": 1899,
            "cache_hits": 5229,
            "pruned": 3,
            "reward_evaluations": 501,
            "seconds": 0.3583,
        },
        {
            "t": 2.5,
            "event": "replan",
            "kind": "solve",
            "feasible": False,
            "value": 0.0,
            "horizon": 5,
            "policy": [],
            "nodes": 7,
            "cache_hits": 0,
            "pruned": 0,
            "reward_evaluations": 2,
            "seconds": 1.5,
        },
    ]
    text = render([from_json_dict(r) for r in trace_records])
    lines = text.splitlines()
    assert lines[0].strip() == "planner profile"
    header = next(line for line in lines if "horizon" in line)
    for column in ("kind", "horizon", "value", "policy", "nodes", "cache hits", "pruned", "rewards", "time"):
        assert column in header
    plan_row = next(line for line in lines if " plan " in line)
    assert [cell.strip() for cell in plan_row.strip("│ ").split("│")] == [
        "1",
        "0",
        "plan",
        "solve",
        "8",
        "96",
        "4",
        "1,899",
        "5,229",
        "3",
        "501",
        "358.3 ms",
    ]
    replan_row = next(line for line in lines if " replan " in line)
    assert "no plan" in replan_row
    assert "1.50 s" in replan_row
    total_row = next(line for line in lines if " total " in line)
    assert "1,906" in total_row


def test_profile_of_a_run_without_planning_says_so() -> None:
    start = StartEvent(t=0.0, action="a()", id=1, mapped="a", args={}, at=None)
    assert "did not plan" in render([start])


def test_profile_of_a_real_run_shows_its_plan() -> None:
    outcome = run(EXAMPLES / "blocks_planning.gpp")
    assert outcome.recording is not None
    text = render(outcome.recording.records)
    row = next(line for line in text.splitlines() if " plan " in line)
    assert "solve" in row
    assert " 96 " in row


def test_profile_reports_a_search_that_stopped_without_a_plan() -> None:
    import io

    from rich.console import Console

    from gpp.planner.profile import render_profile

    outcome = run_program(ROOT / "tests" / "runtime_errors" / "search_unbounded.gpp", RunOptions(record=True))
    assert outcome.recording is not None
    out = io.StringIO()
    render_profile(outcome.recording.records, Console(file=out, width=200, color_system=None))
    text = out.getvalue()
    assert "did not plan" not in text
    assert "planning stopped without a plan at " in text
    assert "`search` exceeded its bound of 10000 steps without finding an end" in text


def test_a_solve_cut_at_its_horizon_warns_once_and_says_how_many_steps_are_left(tmp_path: Path) -> None:
    program = tmp_path / "deliver.gpp"
    program.write_text(
        "number fluent delivered() { initially: () = 0; }\n"
        "action deliver() { effect: delivered() = delivered() + 1; }\n"
        "number function reward() = delivered()\n"
        "procedure main() {\n"
        "    solve(3, reward()) while (delivered() < 5) deliver();\n"
        "}\n",
        encoding="utf-8",
    )
    outcome = run_program(program, RunOptions(record=True))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    [warning] = [d for d in outcome.diagnostics if d.code == "R0014"]
    assert not warning.is_error and warning.span.text.startswith("solve(3, reward())")
    assert warning.notes[1] == "finishing it needs at least 2 more step(s)"
    assert warning.help == "raise the horizon to at least 5"
    assert outcome.recording is not None
    [plan] = outcome.recording.of(PlanEvent)
    assert (plan.unfinished, plan.steps_left) == (True, 2)
    # A horizon with room for the whole program: no warning.
    program.write_text(program.read_text(encoding="utf-8").replace("solve(3,", "solve(5,"), encoding="utf-8")
    outcome = run_program(program, RunOptions(record=True))
    assert [d for d in outcome.diagnostics if d.code == "R0014"] == []
    assert outcome.recording is not None and outcome.recording.of(PlanEvent)[0].unfinished is False
