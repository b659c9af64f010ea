"""Time wakes programs: a program blocked on a condition that compares the clock with a value
steps as soon as the platform's clock gets there, on the dummy and on the sim; waits are in the
trace; `--timeout` also bounds wall-clock time."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import AssignEvent, CancelEvent, StartEvent, WaitingEvent
from gpp.runtime.executor import RunStatus

TIMEOUT = """
#include "time.gpp"

action listen() { duration: [30, 30] }
bool fluent listening() { initially: () = false; }
number fluent gave_up_at() { initially: () = -1; }
number fluent waited_until() { initially: () = -1; }

procedure listen_until(number deadline) {
    listening() = true;
    start(listen());
    concurrent {
        { end(listen()); listening() = false; }
        { test(!listening() | passed(deadline)); if (listening()) { gave_up_at() = context_time(); cancel(listen()); } }
    }
}

procedure main() {
    wait_for(2.5);
    waited_until() = context_time();
    listen_until(context_time() + 5);
}

bool function postcond() = waited_until() == 2.5 & gave_up_at() == 7.5 & !listening()
"""


def run(tmp_path: Path, text: str, name: str = "p.gpp", **options: object) -> RunOutcome:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return run_program(path, RunOptions(record=True, **options))  # type: ignore[arg-type]


def test_the_timeout_pattern_works_on_the_dummy(tmp_path: Path) -> None:
    outcome = run(tmp_path, TIMEOUT)
    assert outcome.ok, [d.message for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.platform_time == 7.5  # not 30 + 2.5
    trace = outcome.recording
    assert trace is not None
    [cancel] = trace.of(CancelEvent)
    assert (cancel.t, cancel.action) == (7.5, "listen()")


def test_the_timeout_pattern_works_on_the_sim(tmp_path: Path) -> None:
    # The sim's clock steps its physics; a program with nothing running waits for the clock.
    program = """// world: blocksworld
#include "sim/blocksworld.gpp"
#include "time.gpp"
symbol domain block = {a, b, c}
symbol domain slot = {t1, t2, t3}
number fluent woke_at() { initially: () = -1; }
procedure main() {
    wait_for(1.5);
    woke_at() = context_time();
    get_block_pose(a);
}
bool function postcond() = woke_at() == 1.5
"""
    outcome = run(tmp_path, program, platform="sim")
    assert outcome.ok, [d.message for d in outcome.diagnostics]


@pytest.mark.parametrize(
    ("condition", "woke"),
    [
        ("context_time() >= 4", 4.0),
        ("context_time() > 4", 4.0),  # just after 4
        ("4 <= context_time()", 4.0),
        ("context_time() - 1 >= 3", 4.0),
        ("10 - context_time() < 6", 4.0),
        ("!(context_time() < 4)", 4.0),
        ("context_time() + offset() >= 6", 4.0),
    ],
)
def test_comparisons_with_the_clock_wake_the_program(tmp_path: Path, condition: str, woke: float) -> None:
    program = (
        "number fluent offset() { initially: () = 2; }\n"
        "number fluent woke() { initially: () = -1; }\n"
        f"procedure main() {{ test({condition}); woke() = context_time(); }}\n"
    )
    outcome = run(tmp_path, program)
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, outcome.diagnostics
    trace = outcome.recording
    assert trace is not None
    [assign] = trace.of(AssignEvent)
    assert assign.value == pytest.approx(woke) and assign.value >= 4.0


def test_a_wait_and_its_end_are_in_the_trace(tmp_path: Path) -> None:
    outcome = run(tmp_path, TIMEOUT)
    assert outcome.recording is not None
    waits = outcome.recording.of(WaitingEvent)
    first, resumed = waits[0], waits[1]
    assert (first.t, first.statement, first.resumed) == (0.0, "test(context_time() >= t);", False)
    assert first.at is not None and first.at.endswith("time.gpp:31:5")
    assert first.condition == "this test is false (context_time() = 0.0)"
    assert (resumed.t, resumed.statement, resumed.resumed) == (2.5, first.statement, True)
    # Waiting for an activity is not a `waiting` record: start and end say it.
    assert all("listen()" not in w.condition for w in waits)


def test_a_deadline_that_moves_with_the_clock_is_reported_as_blocked(tmp_path: Path) -> None:
    # Both sides read the clock: the comparison names no time to wake at, and nothing else comes.
    program = "procedure main() { test(context_time() >= context_time() + 1); }\n"
    outcome = run(tmp_path, program)
    assert outcome.result is not None and outcome.result.status is RunStatus.BLOCKED
    # A procedure's arguments are evaluated anew until its first step: the deadline moves.
    program = (
        "procedure chase(number t) { test(context_time() >= t); }\nprocedure main() { chase(context_time() + 1); }\n"
    )
    outcome = run(tmp_path, program)
    assert outcome.result is not None and outcome.result.status is RunStatus.BLOCKED
    [d] = outcome.diagnostics
    assert d.code == "R0011" and "the time it waits for moves with the clock" in d.notes[-1]


def test_a_loop_that_takes_no_time_stops_at_the_wall_clock_timeout(tmp_path: Path) -> None:
    program = "number fluent n() { initially: () = 0; }\nprocedure main() { while (true) n() = n() + 1; }\n"
    outcome = run(tmp_path, program, timeout=0.5)
    assert outcome.result is not None and outcome.result.status is RunStatus.TIMEOUT
    [d] = outcome.diagnostics
    assert d.code == "R0013" and "of wall-clock time (`--timeout`; platform time: 0 s)" in d.message
    assert d.span.text == "while (true) n() = n() + 1;"


def test_a_wait_on_an_activity_wakes_as_before(tmp_path: Path) -> None:
    program = "action a() { duration: [3, 3] }\nprocedure main() { a(); }\n"
    outcome = run(tmp_path, program)
    assert outcome.ok and outcome.result is not None and outcome.result.platform_time == 3.0
    assert outcome.recording is not None and outcome.recording.of(WaitingEvent) == []
    assert [s.action for s in outcome.recording.of(StartEvent)] == ["a()"]


KNOCK = """// scenario: knock.toml
bool fluent door_open() { initially: () = false; }
number fluent knocks() { initially: () = 0; }
exog_action knock() { effect: knocks() = knocks() + 1; }
exog_action open_door() { effect: door_open() = true; }

procedure main() {
    while (knocks() > 0) knocks() = knocks() - 1;   // answer every knock
    test(door_open());                               // then wait for the door
}
"""


def test_a_blocked_sequence_steps_back_into_an_earlier_loop_and_the_trace_shows_it(tmp_path: Path) -> None:
    """The example of docs/semantics.md, "A blocked sequence can step back into an earlier loop"."""
    doc = (Path(__file__).resolve().parents[2] / "docs" / "semantics.md").read_text(encoding="utf-8")
    assert "while (knocks() > 0) knocks() = knocks() - 1;" in doc
    (tmp_path / "knock.toml").write_text(
        '[[exog]]\nat = 1\naction = "knock"\n\n[[exog]]\nat = 2\naction = "open_door"\n', encoding="utf-8"
    )
    outcome = run(tmp_path, KNOCK, "knock.gpp")
    assert outcome.ok and outcome.recording is not None
    steps = [(e.EVENT, e.t, getattr(e, "at", None), getattr(e, "resumed", None)) for e in outcome.recording.records[1:]]
    test_at = f"{tmp_path / 'knock.gpp'}:9:5"
    assert steps[:5] == [
        ("waiting", 0.0, test_at, False),
        ("exog", 1.0, None, None),
        ("waiting", 1.0, test_at, True),
        ("assign", 1.0, f"{tmp_path / 'knock.gpp'}:8:26", None),  # back in the loop's body
        ("waiting", 1.0, test_at, False),
    ]


def test_the_live_view_shows_what_the_program_waits_for(tmp_path: Path) -> None:
    import io

    from gpp.run.view import LiveView, PlainView
    from tests.support.traces import live_panel_at_first_wait

    outcome = run(tmp_path, TIMEOUT)
    assert outcome.recording is not None
    events = outcome.recording.records
    first_wait = next(i for i, e in enumerate(events) if isinstance(e, WaitingEvent))
    text, live = live_panel_at_first_wait(events, "p.gpp")
    assert isinstance(live, LiveView)
    assert "waiting since 0.00 s: this test is false (context_time() = 0.0)" in text
    assert "test(context_time() >= t);" in text and "time.gpp:31:5" in text
    # When it resumes, the panel no longer says it waits; the plain view has one line per wait.
    for event in events[first_wait + 1 :]:
        live(event)
    assert live.waiting is None
    plain = io.StringIO()
    view = PlainView(plain)
    for event in events:
        view(event)
    assert "wait   this test is false (context_time() = 0.0): test(context_time() >= t);" in plain.getvalue()


def test_a_comparison_with_the_clock_evaluates_its_other_side_once(tmp_path: Path) -> None:
    from collections.abc import Mapping

    from gpp.check import check_text
    from gpp.model.types import Type
    from gpp.platform.base import Activity
    from gpp.platform.dummy import DummyPlatform, Scenario
    from gpp.runtime.compiled import CompiledProgram
    from gpp.runtime.executor import Executor
    from gpp.runtime.trace import Trace
    from gpp.runtime.values import Value

    class Counting(DummyPlatform):
        asked = 0

        def exog_function(
            self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
        ) -> Value:
            self.asked += 1
            return super().exog_function(name, args, return_type, activity)

    program = "number exog_function deadline();\nprocedure main() { test(context_time() >= deadline()); }\n"
    check = check_text(program, tmp_path / "p.gpp", lint=False)
    platform = Counting(Scenario.from_data({"exog_function": [{"name": "deadline", "value": 3}]}))
    result = Executor(CompiledProgram(check.model), platform, Trace()).run()
    assert result.status is RunStatus.FINISHED and result.platform_time == 3.0
    # Asked once when the test was false at 0 s and once when it held at 3 s: never twice for one test.
    assert platform.asked == 2
