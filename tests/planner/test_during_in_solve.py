"""`during` inside `solve`: the plan counts a `during` once, at its end (where its effects
apply), and a failed activity runs the program's `on_fail` handler and re-plans."""

from __future__ import annotations

from pathlib import Path

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import PlanEvent, ReplanEvent
from gpp.runtime.executor import RunStatus

EFFECT_AT_END = """
number fluent n() { initially: () = 0; }
action act() { effect: n() = 100; }
number function reward() = n()
procedure main() { solve(3, reward()) during (act()) {} }
bool function postcond() = n() == 100
"""

FAIL_THEN_REPAIR = """
// scenario: fail_once.toml
symbol domain block = {a, b}
number fluent n() { initially: () = 0; }
number fluent repairs() { initially: () = 0; }
action act(block x) { effect: n() = n() + 1; }
action repair() { effect: repairs() = repairs() + 1; }
number function reward() = n()
procedure main() {
    solve(4, reward()) while (n() < 2) pick (block x) during (act(x)) {} on_fail repair();
}
bool function postcond() = n() >= 2 & repairs() == 1
"""


def run(tmp_path: Path, text: str, scenario: str | None = None) -> RunOutcome:
    program = tmp_path / "agent.gpp"
    program.write_text(text)
    if scenario is not None:
        (tmp_path / "fail_once.toml").write_text(scenario)
    return run_program(program, RunOptions(record=True))


def test_the_reward_after_a_during_sees_its_effects(tmp_path: Path) -> None:
    outcome = run(tmp_path, EFFECT_AT_END)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [plan] = outcome.recording.of(PlanEvent)
    # R(s0) = 0, and R after the `during` (its one costed step, at its end) = 100.
    assert (plan.value, plan.policy) == (100.0, ("act()",))
    assert outcome.postcond is True


def test_a_failed_during_in_a_plan_runs_on_fail_and_replans(tmp_path: Path) -> None:
    scenario = '[[action]]\nmatch = "act(a)"\noutcome = "fail"\ntimes = 1\n'
    outcome = run(tmp_path, FAIL_THEN_REPAIR, scenario)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    events = [(r.EVENT, getattr(r, "action", None)) for r in outcome.recording.records]
    # act(a) fails, the handler repair() runs, then the planner plans the rest again.
    failed_at = events.index(("update", "act(a)"))
    assert ("start", "repair()") in events[failed_at:]
    assert any(isinstance(r, ReplanEvent) for r in outcome.recording.records[failed_at:])
    assert outcome.postcond is True
