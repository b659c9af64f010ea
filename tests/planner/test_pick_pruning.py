"""Early pruning of `pick` values: a precondition conjunct that reads only outer `pick`
variables rules a value out before any inner value is tried. It must never change a plan."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.events import PlanEvent
from gpp.runtime.executor import RunStatus

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def plan_of(path: Path) -> tuple[float, tuple[str, ...], int]:
    outcome = run_program(path, RunOptions(record=True))
    assert outcome.recording is not None
    [plan] = outcome.recording.of(PlanEvent)
    return plan.value, plan.policy, plan.pruned


@pytest.mark.parametrize("name", ["blocks_planning.gpp", "tower5.gpp"])
def test_pruning_keeps_the_plan_and_prunes_something(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    value, policy, pruned = plan_of(EXAMPLES / name)
    assert pruned > 0
    monkeypatch.setattr(CompiledProgram, "pick_guard", lambda self, pick: None)
    unpruned_value, unpruned_policy, _ = plan_of(EXAMPLES / name)
    assert (value, policy) == (unpruned_value, unpruned_policy)


def test_an_error_in_an_early_conjunct_is_still_reported(tmp_path: Path) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text(
        """
symbol domain item = {a, b}
number fluent d(item x) { initially: (x) = 1; (a) = 0; }
number fluent n() { initially: () = 0; }
action put(item x, item y) {
precondition:
    x != y & 1 / d(x) > 0
effect:
    n() = n() + 1;
}
number function reward() = n()
procedure main() { solve(1, reward()) pick (item x) pick (item y) put(x, y); }
"""
    )
    outcome = run_program(program, RunOptions(record=True))
    assert outcome.result is not None and outcome.result.status is RunStatus.ERROR
    assert [d.code for d in outcome.diagnostics if d.is_error] == ["R0001"]
