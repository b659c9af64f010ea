"""Online execution of plans with re-planning on deviation (SEMANTICS §5, §6), on the dummy
platform with scripted scenarios (tests/planner_scenarios/*.toml) that make the world deviate
from the plan: an exogenous event, a failing action, a condition the plan assumed."""

from __future__ import annotations

from pathlib import Path
from typing import TypeVar

from gpp.planner.profile import plan_events
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import EndEvent, EventBase, PlanEvent, ReplanEvent, StartEvent
from gpp.runtime.executor import RunStatus

E = TypeVar("E", bound=EventBase)

SCENARIOS = Path(__file__).resolve().parents[1] / "planner_scenarios"

FIRST_PLAN = ("stack(a,table)", "stack(c,table)", "stack(b,a)", "stack(c,b)")


def run(program: Path, scenario: str) -> RunOutcome:
    return run_program(program, RunOptions(record=True, platform_options={"scenario": SCENARIOS / scenario}))


def events(outcome: RunOutcome, kind: type[E]) -> list[E]:
    assert outcome.recording is not None
    return outcome.recording.of(kind)


def plans(outcome: RunOutcome) -> list[PlanEvent | ReplanEvent]:
    assert outcome.recording is not None
    return plan_events(outcome.recording.records)


def started(outcome: RunOutcome) -> tuple[str, ...]:
    return tuple(r.action for r in events(outcome, StartEvent))


def test_an_exogenous_event_that_invalidates_the_plan_makes_the_planner_plan_again() -> None:
    outcome = run(SCENARIOS / "blocks.gpp", "knocked.toml")
    plan, replan = plans(outcome)
    assert plan.EVENT == "plan"
    assert plan.policy == FIRST_PLAN
    # a was put onto c at t = 1.5; stack(b,a) was still possible, stack(c,b) was not.
    assert replan.EVENT == "replan"
    assert replan.t == 3.0
    assert replan.horizon == 8 - 3
    assert replan.policy == ("stack(b,table)", "stack(a,table)", "stack(b,a)", "stack(c,b)")
    assert started(outcome) == FIRST_PLAN[:3] + replan.policy
    assert outcome.ok  # the goal is reached after all


def test_a_failed_action_makes_the_planner_plan_again_from_where_the_program_is() -> None:
    outcome = run(SCENARIOS / "blocks.gpp", "stack_fails.toml")
    [failed] = [r for r in events(outcome, EndEvent) if r.status == "failed"]
    assert failed.action == "stack(c,table)"
    [replan] = events(outcome, ReplanEvent)
    assert replan.t == failed.t
    # The successful call used its step of the horizon; the failed one gave its step back.
    assert replan.horizon == 8 - 1
    assert (replan.reason, replan.written_horizon) == ("`stack(c,table)` failed", 8)
    assert replan.policy == ("stack(c,table)", "stack(b,a)", "stack(c,b)")
    assert started(outcome) == FIRST_PLAN[:2] + replan.policy
    assert outcome.ok
    assert outcome.result is not None
    assert outcome.result.unhandled_failures == 1


def test_a_plan_that_assumed_the_program_ends_is_replanned_when_it_does_not() -> None:
    # Every planned step was possible, but the last one failed: the loop has not ended.
    outcome = run(SCENARIOS / "blocks.gpp", "last_stack_fails.toml")
    [replan] = events(outcome, ReplanEvent)
    assert replan.horizon == 8 - 3  # the failed last step gave its step back
    assert replan.policy == ("stack(c,b)",)
    assert started(outcome) == (*FIRST_PLAN, "stack(c,b)")
    assert outcome.ok


def test_a_condition_the_plan_assumed_is_checked_again_before_the_step_that_follows_it() -> None:
    # The plan walks out because it is not raining; it starts raining before the walk: the
    # other alternative's test now holds, but that is not the planned branch.
    outcome = run(SCENARIOS / "umbrella.gpp", "rain.toml")
    plan, replan = plans(outcome)
    assert plan.policy == ("put_on_shoes()", "walk_out()")
    assert replan.policy == ("take_umbrella()", "walk_out()")
    assert started(outcome) == ("put_on_shoes()", "take_umbrella()", "walk_out()")
    assert outcome.ok


def test_without_deviation_the_plan_is_executed_as_planned() -> None:
    outcome = run_program(SCENARIOS / "blocks.gpp", RunOptions(record=True))
    assert [r.EVENT for r in plans(outcome)] == ["plan"]
    assert started(outcome) == FIRST_PLAN
    assert outcome.ok


def test_when_the_horizon_is_used_up_execution_continues_after_the_solve(tmp_path: Path) -> None:
    program = tmp_path / "blocks3.gpp"
    text = (SCENARIOS / "blocks.gpp").read_text(encoding="utf-8")
    program.write_text(text.replace("solve(8, reward())", "solve(3, reward())"), encoding="utf-8")
    outcome = run_program(program, RunOptions(record=True))
    # The plan used the whole horizon, so it assumed nothing about the end of the program:
    # after its last step the `solve` is over, with the goal missed.
    assert [r.EVENT for r in plans(outcome)] == ["plan"]
    assert len(started(outcome)) == 3
    assert outcome.result is not None
    assert outcome.result.status is RunStatus.FINISHED
    assert outcome.postcond is False


def test_a_failed_last_step_gives_its_step_of_the_horizon_back(tmp_path: Path) -> None:
    program = tmp_path / "blocks4.gpp"
    text = (SCENARIOS / "blocks.gpp").read_text(encoding="utf-8")
    program.write_text(text.replace("solve(8, reward())", "solve(4, reward())"), encoding="utf-8")
    outcome = run(program, "last_stack_fails.toml")
    # The plan used the whole horizon; its last step failed, which is no progress: the
    # `solve` plans that step again with the step it gave back, and reaches the goal.
    [replan] = events(outcome, ReplanEvent)
    assert (replan.horizon, replan.policy) == (1, ("stack(c,b)",))
    assert started(outcome) == (*FIRST_PLAN, "stack(c,b)")
    assert outcome.ok


def test_search_searches_again_when_the_world_deviates() -> None:
    outcome = run(SCENARIOS / "search_blocks.gpp", "knocked.toml")
    plan, replan = plans(outcome)
    assert plan.kind == replan.kind == "search"
    assert plan.policy == FIRST_PLAN
    assert replan.horizon == plan.horizon == 10_000  # every search has the whole step bound
    assert replan.policy == ("stack(b,table)", "stack(a,table)", "stack(b,a)", "stack(c,b)")
    assert outcome.ok
