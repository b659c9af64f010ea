"""`during` inside `solve`: the plan counts a `during` once, at its end (where its effects
apply), and a failed activity runs the program's `on_fail` handler and re-plans."""

from __future__ import annotations

from pathlib import Path

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.run.view import describe
from gpp.runtime.events import PlanEvent, ReplanEvent, WaitingEvent, decode
from gpp.runtime.executor import RunStatus
from tests.support.cli import run as gpp

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


# ---------------------------------------------------------------- retries (issue 24, items 1 and 2)

ROOT = Path(__file__).resolve().parents[2]
RETRIES = ROOT / "tests" / "programs" / "solve_retries.gpp"

# The receptionist of tests/programs/solve_retries.gpp with one visit, a bookkeeping step in its
# `on_fail` handler, and the drive to room1 failing three times.
COUNTED_RETRIES = """
// scenario: retries.toml
symbol domain Room = {lobby, room1, room2}
Room fluent robot_at() { initially: () = lobby; }
bool fluent served(Room r) { initially: (r) = false; }
number fluent failures() { initially: () = 0; }
action goto(Room r) { precondition: robot_at() != r effect: robot_at() = r; duration: [5, 5] }
action greet(Room r) { precondition: robot_at() == r effect: served(r) = true; }
procedure visit(Room r) {
    while (robot_at() != r) { during (goto(r)) { } on_fail { failures() = failures() + 1; } }
    greet(r);
}
number function reward() = if (served(room1) & served(room2)) 100 else 0
procedure main() { solve(6, reward()) { visit(room1); visit(room2); } }
"""

# A planned plain call that fails (the failure is not handled: the loop tries again).
PLAIN_CALL_RETRIES = """
// scenario: retries.toml
symbol domain Room = {lobby, room1, room2}
Room fluent robot_at() { initially: () = lobby; }
bool fluent served(Room r) { initially: (r) = false; }
action goto(Room r) { precondition: robot_at() != r effect: robot_at() = r; duration: [5, 5] }
action greet(Room r) { precondition: robot_at() == r effect: served(r) = true; }
number function reward() = if (served(room1)) 10 else 0
procedure main() { solve(2, reward()) { while (robot_at() != room1) goto(room1); greet(room1); } }
bool function postcond() = served(room1)
"""

THREE_FAILURES = '[[action]]\nmatch = "goto(room1)"\noutcome = "fail"\nduration = 2.0\ntimes = 3\n'


def run_retries(tmp_path: Path, text: str) -> RunOutcome:
    program = tmp_path / "agent.gpp"
    program.write_text(text)
    (tmp_path / "retries.toml").write_text(THREE_FAILURES)
    return run_program(program, RunOptions(record=True))


def test_a_wait_for_a_planned_activity_says_which_activity_and_step_it_waits_for() -> None:
    outcome = run_program(RETRIES, RunOptions(record=True))
    assert outcome.recording is not None
    waits = [r for r in outcome.recording.of(WaitingEvent) if not r.resumed]
    assert waits, "a planned activity that runs is a wait with a record"
    assert all("found no plan" not in w.condition for w in waits)
    first = waits[0]
    assert (first.reason, first.action, first.plan_step) == ("activity", "goto(room1)", 1)
    assert first.condition == "waiting for `goto(room1)` to end, step 1 of the plan"
    assert first.statement == "during (goto(r)) { } on_fail { }"
    assert first.at is not None and first.at.endswith("solve_retries.gpp:37:9")
    # The log has a line per start and end; the wait between them is not another line.
    assert describe(first) is None
    # After the first visit, the plan's later steps: greet(room1) is step 2, goto(room2) step 3.
    steps = [(w.action, w.plan_step) for w in waits[-3:]]
    assert steps == [("greet(room1)", 2), ("goto(room2)", 3), ("greet(room2)", 4)]


def test_the_summary_and_the_page_show_what_a_planned_wait_waits_for(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    run_program(RETRIES, RunOptions(trace=trace))
    summary = gpp("trace", "summary", str(trace), "--color", "never", "--width", "200")
    assert summary.returncode == 0, summary.stderr
    assert "found no plan" not in summary.stdout
    assert "waiting for `goto(room1)` to end, step 1 of the plan" in " ".join(summary.stdout.split())
    page = tmp_path / "run.html"
    html = gpp("trace", "html", str(trace), "-o", str(page))
    assert html.returncode == 0, html.stderr
    text = page.read_text(encoding="utf-8")
    assert "found no plan" not in text
    assert "waiting for `goto(room1)` to end, step 1 of the plan" in text


def test_failed_attempts_do_not_use_up_the_solve_horizon() -> None:
    outcome = run_program(RETRIES, RunOptions(record=True))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    replans = outcome.recording.of(ReplanEvent)
    assert len(replans) == 3
    # Each failure gives the whole horizon back: the attempt made no progress.
    assert [r.horizon for r in replans] == [6, 6, 6]
    assert all(r.unfinished is False for r in replans)
    assert not [d for d in outcome.diagnostics if d.code == "R0014"]
    assert outcome.postcond is True


def test_the_programs_own_on_fail_is_named_as_the_reason_of_its_replan() -> None:
    outcome = run_program(RETRIES, RunOptions(record=True))
    assert outcome.recording is not None
    reasons = {r.reason for r in outcome.recording.of(ReplanEvent)}
    assert reasons == {"`goto(room1)` failed: its `on_fail` handler runs next"}
    [replan] = outcome.recording.of(ReplanEvent)[:1]
    line = describe(replan)
    assert line is not None and line.startswith("replan because `goto(room1)` failed: its `on_fail` handler")


def test_r0014_names_the_horizon_as_written_and_where_the_rest_went(tmp_path: Path) -> None:
    outcome = run_retries(tmp_path, COUNTED_RETRIES)
    [warning] = [d for d in outcome.diagnostics if d.code == "R0014"]
    assert "horizon of 6" in warning.message
    # Two bookkeeping steps were executed before the last replan; the failed drives gave theirs back.
    assert any(
        n.startswith(
            "2 of its 6 step(s) went to the steps of the `solve` already executed: `failures() = 1`, `failures() = 2`"
        )
        for n in warning.notes
    ), warning.notes
    assert warning.help == "raise the horizon to at least 7"
    assert outcome.recording is not None
    last = outcome.recording.of(ReplanEvent)[-1]
    assert (last.horizon, last.written_horizon) == (4, 6)


def test_a_planned_call_that_fails_gives_its_step_back(tmp_path: Path) -> None:
    outcome = run_retries(tmp_path, PLAIN_CALL_RETRIES)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.result.unhandled_failures == 3
    assert outcome.recording is not None
    assert [r.horizon for r in outcome.recording.of(ReplanEvent)] == [2, 2, 2]
    assert {r.reason for r in outcome.recording.of(ReplanEvent)} == {"`goto(room1)` failed"}
    assert outcome.postcond is True


def test_a_waiting_record_of_an_older_trace_still_reads() -> None:
    record = decode('{"t": 2.0, "event": "waiting", "statement": "test(ready());", "at": null, "condition": "c"}')
    assert isinstance(record, WaitingEvent)
    assert (record.reason, record.action, record.plan_step) == (None, None, None)


def test_the_live_panel_says_which_planned_activity_it_waits_for() -> None:
    from tests.support.traces import live_panel_at_first_wait

    outcome = run_program(RETRIES, RunOptions(record=True))
    assert outcome.recording is not None
    text, _ = live_panel_at_first_wait(outcome.recording.records, "solve_retries.gpp")
    assert "waiting since 0.00 s for `goto(room1)` to end, step 1 of the plan" in text
    assert "found no plan" not in text


def test_a_during_without_a_handler_is_planned_again_without_naming_one(tmp_path: Path) -> None:
    text = RETRIES.read_text(encoding="utf-8").replace("during (goto(r)) { } on_fail { }", "during (goto(r)) { }")
    text = text.replace("// scenario: solve_retries.toml", "// scenario: retries.toml")
    outcome = run_retries(tmp_path, text)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.recording is not None
    assert {r.reason for r in outcome.recording.of(ReplanEvent)} == {"`goto(room1)` failed"}
    assert [r.horizon for r in outcome.recording.of(ReplanEvent)] == [6, 6, 6]
    assert outcome.postcond is True
