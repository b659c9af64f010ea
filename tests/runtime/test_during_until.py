"""`during (a) until (e) body on_fail F on_cancel C` (docs/semantics.md, "Watching an
activity"): the activity is cancelled when `e` holds while it runs, the body is left when the
activity ends, and a handler always runs; the same inside `solve`, where the plan treats it as
a `during` and the watch works while the plan is executed."""

from __future__ import annotations

from pathlib import Path

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import AssignEvent, CancelEvent, EndEvent, PlanEvent, ReplanEvent
from gpp.runtime.executor import RunStatus

DECLARATIONS = """\
// scenario: world.toml
symbol domain Room = {lobby, room1}
bool fluent visitor_left() { initially: () = false; }
Room fluent at() { initially: () = lobby; }
number fluent log() { initially: () = 0; }
exog_action leaves() { effect: visitor_left() = true; }
action goto(Room r) {
duration: [1, 100]
effect:
    at() = r;
}
"""

WATCHED = (
    DECLARATIONS
    + """\
procedure main() {
    during (goto(room1)) until (visitor_left()) {
        log() = 1;
        test(false);                      // left when the activity ends
    } on_fail {
        log() = 2;
    } on_cancel {
        log() = 3;
    }
    log() = log() * 10;
}
"""
)

# The form W0119 warns about: it waits for ever when the drive ends first.
HANGING = (
    DECLARATIONS
    + """\
procedure main() {
    during (goto(room1)) {
        test(visitor_left());
        cancel(goto(room1));
    } on_fail {
        log() = 2;
    }
}
"""
)

DRIVE_10_LEAVES_AT_3 = '[[action]]\nmatch = "goto(room1)"\nduration = 10.0\n[[exog]]\nat = 3.0\naction = "leaves"\n'
DRIVE_FAILS_AT_2 = '[[action]]\nmatch = "goto(room1)"\nduration = 2.0\noutcome = "fail"\n'
DRIVE_2_LEAVES_AT_3 = '[[action]]\nmatch = "goto(room1)"\nduration = 2.0\n[[exog]]\nat = 3.0\naction = "leaves"\n'


def run(tmp_path: Path, program: str, scenario: str) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(program)
    (tmp_path / "world.toml").write_text(scenario)
    outcome = run_program(path, RunOptions(record=True))
    assert outcome.result is not None, [d.message for d in outcome.diagnostics]
    return outcome


def logged(outcome: RunOutcome) -> list[object]:
    assert outcome.recording is not None
    return [r.value for r in outcome.recording.of(AssignEvent) if r.fluent == "log()"]


def ended(outcome: RunOutcome) -> list[tuple[str, str]]:
    assert outcome.recording is not None
    return [(r.action, r.status) for r in outcome.recording.of(EndEvent)]


def test_the_condition_cancels_the_activity_and_on_cancel_runs(tmp_path: Path) -> None:
    outcome = run(tmp_path, WATCHED, DRIVE_10_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [cancel] = outcome.recording.of(CancelEvent)
    assert (cancel.action, cancel.t, cancel.reason) == ("goto(room1)", 3.0, "`until (visitor_left())` holds")
    assert ended(outcome) == [("goto(room1)", "cancelled")]
    assert logged(outcome) == [1, 3, 30]


def test_a_failure_before_the_condition_leaves_the_body_and_runs_on_fail(tmp_path: Path) -> None:
    outcome = run(tmp_path, WATCHED, DRIVE_FAILS_AT_2)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert ended(outcome) == [("goto(room1)", "failed")]
    assert logged(outcome) == [1, 2, 20]


def test_an_activity_that_ends_first_leaves_the_body_with_its_effects(tmp_path: Path) -> None:
    outcome = run(tmp_path, WATCHED, DRIVE_2_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None and outcome.recording.of(CancelEvent) == []
    assert ended(outcome) == [("goto(room1)", "final")]
    assert logged(outcome) == [1, 10]


def test_the_hanging_form_blocks_where_until_runs_on_fail(tmp_path: Path) -> None:
    outcome = run(tmp_path, HANGING, DRIVE_FAILS_AT_2)
    assert outcome.result is not None and outcome.result.status is RunStatus.BLOCKED
    assert logged(outcome) == []


def test_a_condition_true_at_the_start_cancels_at_once(tmp_path: Path) -> None:
    program = WATCHED.replace("initially: () = false;", "initially: () = true;")
    outcome = run(tmp_path, program, DRIVE_10_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert ended(outcome) == [("goto(room1)", "cancelled")]
    assert logged(outcome) == [3, 30]  # the body made no step: the watch comes first


IN_SOLVE = (
    DECLARATIONS
    + """\
number function reward() = if (at() == room1) 10 else 0
procedure main() {
    solve(4, reward()) {
        pick (Room r in {lobby, room1}) {
            during (goto(r)) until (visitor_left()) {
                log() = 1;
            } on_cancel {
                log() = 3;
            }
        }
        log() = log() + 100;
    }
}
"""
)


def test_in_solve_the_plan_is_that_of_a_plain_during(tmp_path: Path) -> None:
    # While planning an activity ends at once in `final`: the body never runs and the
    # condition is never looked at, so the plan is the call and the assignment after it.
    outcome = run(tmp_path, IN_SOLVE, DRIVE_2_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [plan] = outcome.recording.of(PlanEvent)
    assert (plan.value, plan.policy) == (20.0, ("goto(room1)", "log() = 100"))
    assert ended(outcome) == [("goto(room1)", "final")]
    assert logged(outcome) == [100]


def test_in_solve_the_watch_cancels_and_the_rest_is_planned_again(tmp_path: Path) -> None:
    outcome = run(tmp_path, IN_SOLVE, DRIVE_10_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [cancel] = outcome.recording.of(CancelEvent)
    assert (cancel.t, cancel.reason) == (3.0, "`until (visitor_left())` holds")
    assert ended(outcome) == [("goto(room1)", "cancelled")]
    [replan] = outcome.recording.of(ReplanEvent)
    assert replan.policy == ("log() = 3", "log() = 103")
    assert logged(outcome) == [3, 103]


def test_a_deadline_on_the_clock_cancels_the_activity_when_the_clock_gets_there(tmp_path: Path) -> None:
    program = WATCHED.replace("until (visitor_left())", "until (context_time() >= 2.5)")
    outcome = run(tmp_path, program, DRIVE_10_LEAVES_AT_3)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    [cancel] = outcome.recording.of(CancelEvent)
    assert cancel.t == 2.5
    assert logged(outcome) == [1, 3, 30]
