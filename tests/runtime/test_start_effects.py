"""`start_effect:` (docs/semantics.md, "Effects at an action's start"): applied in the step that
starts the activity, evaluated where the precondition held; the end effects see them; they
stay when the activity fails or is cancelled; a `during`'s body and its `until` condition see
them; in planning a call applies them before its end effects, in both tiers of the planner."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.check import check_text
from gpp.planner.fast.successors import Successors
from gpp.planner.problem import first_solve
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import CancelEvent, EndEvent, StartEvent
from gpp.runtime.executor import RunStatus
from gpp.runtime.semantics import DoStep, StartStep
from gpp.traceview.model import fluent_histories
from tests.support.planner_worlds import outcome

WORLD = """\
// scenario: world.toml
number fluent n() { initially: () = 1; }
bool fluent busy() { initially: () = false; }
bool fluent done() { initially: () = false; }
number fluent seen() { initially: () = 0; }
action work() {
duration: [1, 100]
precondition:
    !busy()
start_effect:
    busy() = true;
    n() = n() + 1;
effect:
    busy() = false;
    done() = true;
    n() = n() * 10;
}
"""


def run(tmp_path: Path, main: str, scenario: str = "") -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(WORLD + main)
    (tmp_path / "world.toml").write_text(scenario)
    outcome = run_program(path, RunOptions(record=True))
    assert outcome.result is not None, [d.message for d in outcome.diagnostics]
    return outcome


def values(outcome: RunOutcome) -> dict[str, object]:
    """Each fluent instance's last value in the trace (start, end and assignment records)."""
    assert outcome.recording is not None
    out: dict[str, object] = {}
    for record in outcome.recording.records:
        for change in getattr(record, "changes", ()):
            out[str(change["fluent"])] = change["value"]
        if type(record).__name__ == "AssignEvent":
            out[record.fluent] = record.value  # type: ignore[attr-defined]
    return out


def test_the_start_applies_the_start_effects_and_the_end_sees_them(tmp_path: Path) -> None:
    outcome = run(tmp_path, "procedure main() { work(); }\n")
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [start] = outcome.recording.of(StartEvent)
    assert start.changes == ({"fluent": "busy()", "value": True}, {"fluent": "n()", "value": 2})
    [end] = outcome.recording.of(EndEvent)
    # evaluated after the start effects: (1 + 1) * 10
    assert {c["fluent"]: c["value"] for c in end.changes} == {"busy()": False, "done()": True, "n()": 20}


def test_a_start_effect_may_falsify_its_own_precondition_and_the_body_of_during_sees_it(tmp_path: Path) -> None:
    main = "procedure main() { during (work()) { seen() = if (busy()) n() else -1; } }\n"
    outcome = run(tmp_path, main)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert values(outcome)["seen()"] == 2
    assert values(outcome)["n()"] == 20


@pytest.mark.parametrize(("scenario", "status"), [('outcome = "fail"\n', "failed"), ("duration = 10.0\n", "cancelled")])
def test_start_effects_stay_when_the_activity_fails_or_is_cancelled(tmp_path: Path, scenario: str, status: str) -> None:
    main = "procedure main() { during (work()) { if (n() == 2) cancel(work()); } on_fail {} on_cancel {} }\n"
    if status == "failed":
        main = "procedure main() { during (work()) {} on_fail {} }\n"
    outcome = run(tmp_path, main, '[[action]]\nmatch = "work()"\n' + scenario)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    assert [(e.action, e.status, e.changes) for e in outcome.recording.of(EndEvent)] == [("work()", status, ())]
    assert values(outcome) == {"busy()": True, "n()": 2}


def test_an_until_condition_made_true_by_a_start_effect_cancels_at_once(tmp_path: Path) -> None:
    main = "procedure main() { during (work()) until (busy()) { seen() = 1; } on_cancel { seen() = 2; } }\n"
    outcome = run(tmp_path, main, '[[action]]\nmatch = "work()"\nduration = 10.0\n')
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [cancel] = outcome.recording.of(CancelEvent)
    assert cancel.t == 0.0
    assert values(outcome)["seen()"] == 2  # the body made no step


def test_two_start_effects_that_disagree_are_a_runtime_error(tmp_path: Path) -> None:
    path = tmp_path / "clash.gpp"
    path.write_text(
        "symbol domain D = {a, b}\n"
        "bool fluent f(D d) { initially: (d) = false; }\n"
        "action go(D x) {\nstart_effect:\n    f(x) = true;\n    f(a) = false;\n}\n"
        "procedure main() { go(a); }\n"
    )
    outcome = run_program(path, RunOptions())
    assert outcome.result is not None and outcome.result.status is RunStatus.ERROR
    assert [d.code for d in outcome.diagnostics if d.is_error] == ["R0005"]


# ---------------------------------------------------------------- planning


SOLVE = (
    WORLD.replace("// scenario: world.toml\n", "")
    + """\
number function reward() = if (busy()) 100 else 0
procedure main() {
    solve(2, reward()) choose { work(); { start(work()); end(work()); } }
}
"""
)


def test_a_planned_call_applies_its_start_effects_then_its_end_effects_in_both_tiers() -> None:
    result = check_text(SOLVE, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    pb = first_solve(result.model)
    fast = Successors(pb.sem)
    steps = pb.sem.trans(pb.prog, pb.state, pb.acts)
    [call] = [step for _, step in steps if isinstance(step, DoStep)]
    [start] = [step for _, step in steps if isinstance(step, StartStep)]
    for apply in (pb.sem.apply, fast.apply):
        state, _ = apply(call, pb.state, pb.acts)
        assert [pb.sem.program.read(state, f, ()) for f in ("n", "busy", "done")] == [20, False, True]
        state, _ = apply(start, pb.state, pb.acts)
        assert [pb.sem.program.read(state, f, ()) for f in ("n", "busy", "done")] == [2, True, False]
    # The fast tier wrote the call's start effects out, and left its end effects to the semantics.
    [source] = fast.sources
    assert "# the end effects, in the state after the start effects" in source
    # The reward after `start(work())` sees `busy()`: the written-out hooks win.
    plan = pb.production()
    assert outcome(plan) == outcome(pb.reference())
    assert [s.describe() for _, s, _ in plan.steps] == ["start(work())", "end(work())"]
    assert plan.value == 100


def test_a_solve_with_start_effects_runs_to_its_end(tmp_path: Path) -> None:
    path = tmp_path / "plan.gpp"
    path.write_text(SOLVE)
    outcome = run_program(path, RunOptions(record=True))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert values(outcome) == {"busy()": False, "n()": 20, "done()": True}


def test_the_trace_viewer_takes_the_values_a_start_set(tmp_path: Path) -> None:
    outcome = run(tmp_path, "procedure main() { work(); }\n", '[[action]]\nmatch = "work()"\nduration = 3.0\n')
    assert outcome.recording is not None
    busy = fluent_histories(outcome.recording.records)["busy()"]
    assert [(v.t, v.value, v.kind) for v in busy] == [(0.0, True, "start"), (3.0, False, "end")]
