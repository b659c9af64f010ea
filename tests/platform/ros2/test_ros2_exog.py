"""Exogenous topics, exogenous functions and action feedback on the ros2 platform, against a
publisher and servers in other processes (a random ROS domain of each test worker's own,
discovery on localhost only): a new message wakes a waiting program, a missing or stale value
makes it wait (and a `choose` guard can react), feedback is seen while the goal runs, an
untyped topic is subscribed as soon as its publisher shows up and loses nothing a keep-all
publisher sends after the match, and what does not fit is a `dropped` record and a warning."""

from __future__ import annotations

import itertools
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rclpy")

from test_ros2_processes import domain, ros_env, servers, start, stop  # noqa: F401  (fixtures)

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import AssignEvent, DroppedEvent, UpdateEvent, WaitingEvent, WarningEvent
from gpp.runtime.executor import RunStatus

HERE = Path(__file__).resolve().parent

pytestmark = pytest.mark.slow


class Publisher:
    """ros2_publisher.py in its own process: `ask` sends a command and returns its answer."""

    def __init__(self, domain_id: int) -> None:
        self.process = start([sys.executable, str(HERE / "ros2_publisher.py")], ros_env(domain_id), "ready")
        self.lock = threading.Lock()

    def ask(self, command: str, timeout: float = 40.0) -> str:
        process = self.process
        assert process.stdin is not None and process.stdout is not None
        with self.lock:
            process.stdin.write(command + "\n")
            process.stdin.flush()
            answer: list[str] = []
            reader = threading.Thread(target=lambda: answer.append(process.stdout.readline() if process.stdout else ""))
            reader.start()
            reader.join(timeout)
        assert answer and answer[0], f"the publisher did not answer `{command}`"
        return answer[0].strip()


@pytest.fixture
def publisher(domain: int) -> Iterator[Publisher]:  # noqa: F811
    p = Publisher(domain)
    try:
        yield p
    finally:
        stop(p.process)


def run_with(
    tmp_path: Path, program: str, binding: str | None, drive: Callable[[], None], timeout: float = 30.0
) -> RunOutcome:
    """Run the program on ros2 while `drive` works the publisher in a thread."""
    path = tmp_path / "agent.gpp"
    path.write_text(program, encoding="utf-8")
    if binding is not None:
        (tmp_path / "agent.ros2.toml").write_text(binding, encoding="utf-8")
    failure: list[BaseException] = []

    def guarded() -> None:
        try:
            drive()
        except BaseException as e:
            failure.append(e)

    driver = threading.Thread(target=guarded)
    driver.start()
    outcome = run_program(path, RunOptions(record=True, platform="ros2", timeout=timeout))
    driver.join(60)
    assert not failure, failure
    return outcome


def finished(outcome: RunOutcome) -> RunOutcome:
    messages = [f"{d.code} {d.message} {' '.join(d.notes)}" for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.postcond is not False, messages
    return outcome


def appear_after_attach(publisher: Publisher, advertised: str) -> None:
    """Advertise a topic once the agent's node is up and has looked at the graph (a mapping
    whose type the graph shows at attach is checked there: R0007, not a dropped message)."""
    assert publisher.ask("node gpp_agent") == "found"
    time.sleep(0.3)
    assert publisher.ask(f"advertise {advertised}") == "advertised"


BATTERY = '[exog_function.battery]\ntopic = "/battery : std_msgs/msg/Float64"\n'


# ---------------------------------------------------------------- item 3: a new answer wakes the program


@pytest.mark.fault
def test_a_message_on_an_exogenous_functions_topic_wakes_the_waiting_program(
    publisher: Publisher, tmp_path: Path
) -> None:
    program = """
number exog_function battery();
number fluent seen() { initially: () = -1; }
procedure main() { test(battery() < 50); seen() = battery(); }
bool function postcond() = seen() == 45
"""

    def drive() -> None:
        assert publisher.ask("advertise /battery float64 keep_all") == "advertised"
        assert publisher.ask("match /battery") == "matched"
        for level in (80, 70, 60):
            publisher.ask(f"send /battery {level}")
            time.sleep(0.1)
        publisher.ask("send /battery 45")

    outcome = finished(run_with(tmp_path, program, BATTERY, drive))
    assert outcome.recording is not None
    waits = outcome.recording.of(WaitingEvent)
    assert any('no message on "/battery" yet' in w.condition for w in waits), waits
    assert waits[-1].resumed and waits[-1].statement == "test(battery() < 50);"


def test_max_rate_limits_the_wake_ups_and_the_value_read_is_the_latest(
    publisher: Publisher, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Messages at 50 Hz, `max_rate = 5`: the platform wakes the waiting program at most 5
    times a second (each wake-up it queues is counted, with its time), not once a message;
    each evaluation reads the latest value (they skip values, never go back), and the last
    message, whose wake-up is held back, is the one the program reads at the end."""
    from gpp.platform.base import ExogFunctionChanged
    from gpp.platform.ros2.platform import Ros2Platform
    from gpp.runtime.contract import EventQueue

    program = """
number exog_function battery();
number fluent seen() { initially: () = -1; }
procedure main() { test(battery() >= 99); seen() = battery(); }
bool function postcond() = seen() == 99
"""
    wakes: list[float] = []  # platform times of the wake-ups queued
    put = EventQueue.put

    def counted(self: EventQueue, event: Any, t: float) -> None:
        if isinstance(event, ExogFunctionChanged) and event.function == "battery":
            wakes.append(t)
        put(self, event, t)

    read: list[Any] = []
    ask = Ros2Platform._ask

    def asked(self: Ros2Platform, *args: Any) -> Any:
        value = ask(self, *args)
        read.append(value)
        return value

    monkeypatch.setattr(EventQueue, "put", counted)
    monkeypatch.setattr(Ros2Platform, "_ask", asked)
    sent: list[float] = []

    def drive() -> None:
        assert publisher.ask("advertise /battery float64 keep_all") == "advertised"
        assert publisher.ask("match /battery") == "matched"
        _, began, ended = publisher.ask("ramp /battery 100 50").split()  # 0..99, 2 s
        sent.extend((float(began), float(ended)))

    finished(run_with(tmp_path, program, BATTERY + "max_rate = 5\n", drive))
    gaps = [b - a for a, b in itertools.pairwise(wakes)]
    assert len(wakes) >= 3, wakes
    assert min(gaps) >= 1 / 5 - 1e-9, gaps  # never two wake-ups within 1/max_rate s
    # Over the 2 s of messages (100 of them): about 10 wake-ups, not one a message.
    assert len(wakes) <= 5 * (sent[1] - sent[0]) + 3, (len(wakes), sent)
    assert read == sorted(read) and read[-1] == 99.0, read
    assert len(set(read)) < 50, read  # the latest value, not each message in turn


# ---------------------------------------------------------------- item 4: missing and stale values


@pytest.mark.fault
def test_a_stale_value_is_no_answer_and_a_choose_guard_reacts(publisher: Publisher, tmp_path: Path) -> None:
    program = """#include "time.gpp"
symbol domain Status = {unknown, fresh, stale}
Status fluent status() { initially: () = unknown; }
number exog_function battery();
number fluent last() { initially: () = -1; }
procedure main() {
    test(battery() >= 0);              // the first message: 30
    wait_for(0.6);                     // the robot falls silent: the 30 is too old now
    choose {
        { test(battery() >= 0); status() = fresh; }
        { status() = stale; }          // taken: the first alternative cannot step
    }
    test(battery() < 50);              // not true on the old 30: waits for a fresh message
    last() = battery();
}
bool function postcond() = status() == stale & last() == 40
"""

    def drive() -> None:
        publisher.ask("advertise /battery float64 keep_all")
        publisher.ask("match /battery")
        publisher.ask("send /battery 30")
        time.sleep(2.0)
        publisher.ask("send /battery 40")

    outcome = finished(run_with(tmp_path, program, BATTERY + "max_age = 0.3\n", drive))
    assert outcome.recording is not None
    stale = [w for w in outcome.recording.of(WaitingEvent) if "s old (max_age 0.3 s)" in w.condition]
    assert stale and stale[0].statement == "test(battery() < 50);", outcome.recording.of(WaitingEvent)
    [assign] = [a for a in outcome.recording.of(AssignEvent) if a.fluent == "last()"]
    assert assign.value == 40.0


# ---------------------------------------------------------------- item 8: action feedback


def test_action_feedback_is_an_exogenous_function_the_program_waits_on(
    servers: subprocess.Popen[str],  # noqa: F811
    tmp_path: Path,
) -> None:
    program = """
list[number] exog_function progress();
number fluent seen() { initially: () = -1; }
action count(number n) { mapping: "/fib : test_msgs/action/Fibonacci" { order = n } }
procedure main() {
    start(count(-7));
    test(length(progress()) >= 5);     // while the goal runs, from its feedback
    seen() = length(progress());
    end(count(-7));
}
bool function postcond() = seen() >= 5 & seen() <= 11
"""
    binding = '[exog_function.progress]\nfeedback = "/fib"\nfield = "sequence"\nmax_rate = 50\n'
    outcome = finished(run_with(tmp_path, program, binding, lambda: None))
    assert outcome.recording is not None
    records = outcome.recording.records
    seen = next(i for i, r in enumerate(records) if isinstance(r, AssignEvent) and r.fluent == "seen()")
    ended = next(i for i, r in enumerate(records) if isinstance(r, UpdateEvent))
    assert seen < ended  # seen while the goal still ran
    assert [u.status for u in outcome.recording.of(UpdateEvent)] == ["final"]


# ---------------------------------------------------------------- item 10: exogenous topics


COUNTED = """
number fluent received() { initially: () = 0; }
number fluent last() { initially: () = -1; }
bool fluent in_order() { initially: () = true; }
exog_action counted(number n) {
mapping:
    "/count" { data = n }
effect:
    in_order() = in_order() & n > last();
    received() = received() + 1;
    last() = n;
}
"""


@pytest.mark.fault
def test_an_untyped_topic_is_subscribed_when_its_publisher_appears_and_loses_nothing_after_the_match(
    publisher: Publisher, tmp_path: Path
) -> None:
    program = COUNTED + "procedure main() { test(received() == 2000); }\nbool function postcond() = in_order()\n"

    def drive() -> None:
        time.sleep(0.5)  # the agent runs, without a publisher of /count yet
        publisher.ask("advertise /count int32 keep_all")
        assert publisher.ask("match /count") == "matched"
        publisher.ask("burst /count 2000")

    outcome = finished(run_with(tmp_path, program, None, drive))
    assert outcome.result is not None and outcome.result.exog_events == 2000


@pytest.mark.fault
def test_messages_a_shallow_publisher_loses_are_reported(publisher: Publisher, tmp_path: Path) -> None:
    program = (
        '#include "time.gpp"\n'
        + COUNTED
        + "procedure main() { test(last() == 9999); wait_for(1); }\nbool function postcond() = in_order()\n"
    )

    def drive() -> None:
        publisher.ask("advertise /count int32 depth10")
        assert publisher.ask("match /count") == "matched"
        publisher.ask("burst /count 10000")

    outcome = finished(run_with(tmp_path, program, None, drive, timeout=60.0))
    assert outcome.recording is not None and outcome.result is not None
    lost = sum(d.count for d in outcome.recording.of(DroppedEvent))
    assert outcome.result.exog_events + lost == 10000, (outcome.result.exog_events, lost)
    if lost:
        [warning] = [d for d in outcome.diagnostics if d.code == "R0015"]
        assert "lost on the way" in warning.message and warning.span is not None and warning.span.line == 8


@pytest.mark.fault
def test_a_message_that_does_not_fit_is_dropped_with_a_record_and_a_located_warning(
    publisher: Publisher, tmp_path: Path
) -> None:
    program = """
symbol domain Door = {open, closed}
Door fluent door() { initially: () = closed; }
string fluent heard() { initially: () = ""; }
exog_action said(string what) { mapping: "/events" { data = what } effect: heard() = what; }
exog_action door_moved(Door d) { mapping: "/events" { data = d } effect: door() = d; }
procedure main() { test(heard() == "open"); }
bool function postcond() = door() == open
"""

    def drive() -> None:
        appear_after_attach(publisher, "/events string keep_all")
        publisher.ask("match /events")
        publisher.ask("send /events ajar")
        publisher.ask("send /events open")

    outcome = finished(run_with(tmp_path, program, None, drive))
    assert outcome.recording is not None
    dropped = [(d.target, d.reason) for d in outcome.recording.of(DroppedEvent)]
    assert [t for t, _ in dropped] == ["door_moved"] and "ajar" in dropped[0][1], dropped
    assert all("KeyError" not in r and "'" not in r for _, r in dropped), dropped
    [warning] = [d for d in outcome.diagnostics if d.code == "R0015"]
    assert len(outcome.recording.of(WarningEvent)) == 1
    assert "dropped for `door_moved`" in warning.message
    assert warning.span is not None and warning.span.line == 6
    # A field the message does not have is no drop: the mapping is wrong, and the run stops with
    # R0007 (test_ros2_mapping_checks.py::test_a_topic_that_appears_late_is_checked_before_its_messages_become_events).


@pytest.mark.fault
def test_a_best_effort_publisher_is_a_warning_at_the_mapping(publisher: Publisher, tmp_path: Path) -> None:
    program = """
string fluent heard() { initially: () = ""; }
exog_action said(string what) { mapping: "/scan" { data = what } effect: heard() = what; }
procedure main() { test(heard() == "x"); }
"""

    def drive() -> None:
        publisher.ask("advertise /scan string best_effort")
        publisher.ask("match /scan")
        for _ in range(20):  # best effort: sent a few times
            publisher.ask("send /scan x")
            time.sleep(0.1)

    outcome = finished(run_with(tmp_path, program, None, drive))
    [warning] = [d for d in outcome.diagnostics if d.code == "R0015"]
    assert 'topic "/scan" has a best-effort publisher' in warning.message
    assert warning.span is not None and warning.span.line == 3


def test_the_explanation_of_r0015_warns_on_a_robot_and_its_fix_does_not(publisher: Publisher, tmp_path: Path) -> None:
    from gpp.codes import CODES
    from tests.codes.test_explain import ON_A_ROBOT, example_blocks

    assert ON_A_ROBOT["R0015"] == "tests/platform/ros2/test_ros2_exog.py"
    problem, fix = example_blocks(CODES["R0015"].explanation)
    assert publisher.ask("advertise /events string keep_all") == "advertised"
    for name, block, expected in (("problem", problem, ["R0015"]), ("fixed", fix, [])):
        folder = tmp_path / name
        folder.mkdir()

        def drive() -> None:
            publisher.ask("match /events")
            publisher.ask("send /events ajar")
            for _ in range(30):  # until the program has heard it
                publisher.ask("send /events open")
                time.sleep(0.05)

        outcome = run_with(folder, block, None, drive, timeout=3.0)
        assert [d.code for d in outcome.diagnostics if d.code.startswith("R0015")] == expected, name
