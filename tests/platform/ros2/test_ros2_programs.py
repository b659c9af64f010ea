"""golog++ programs on the ros2 platform against real ROS 2 servers (in one process, one
shared context, discovery off): goals, services, sensing, failures of every kind, preemption,
exogenous events from topics and exogenous functions, and the checks made at attach."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rclpy")

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import (
    ABSENT,
    NoticeEvent,
    SenseEvent,
    StartEvent,
    UpdateEvent,
    WaitingEvent,
    encode,
    load_schema,
)
from gpp.runtime.executor import RunStatus

# Real ROS 2 nodes over DDS: each test waits for discovery and for its robot's answers.
pytestmark = pytest.mark.slow

FIB = '"/fib : test_msgs/action/Fibonacci"'

COUNT = f"""
list[number]
list[number] fluent seq() {{
initially:
    () = list[number] [];
}}
list[number] exog_function result(string name);

action count(number n) {{
senses:
    seq() = result("/fib");
mapping:
    {FIB} {{ order = n }}
}}
"""


def run(tmp_path: Path, text: str, binding: str | None = None, timeout: float = 15.0, **options: str) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(text, encoding="utf-8")
    if binding is not None:
        (tmp_path / "agent.ros2.toml").write_text(binding, encoding="utf-8")
    return run_program(path, RunOptions(record=True, platform="ros2", platform_options=options, timeout=timeout))


def ok(outcome: RunOutcome) -> RunOutcome:
    messages = [f"{d.message} {' '.join(d.notes)}" for d in outcome.diagnostics]
    assert outcome.result is not None, messages
    assert outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.postcond is not False, messages
    return outcome


def updates(outcome: RunOutcome) -> list[UpdateEvent]:
    assert outcome.recording is not None
    return outcome.recording.of(UpdateEvent)


def errors(outcome: RunOutcome) -> list[str]:
    return [d.message for d in outcome.diagnostics if d.severity.name.lower() == "error"]


# ---------------------------------------------------------------- goals and sensing


def test_a_goal_result_is_the_sensed_value(ros: Any, tmp_path: Path) -> None:
    program = COUNT + "procedure main() { count(5); }\nbool function postcond() = length(seq()) == 6 & seq()[5] == 5\n"
    outcome = ok(run(tmp_path, program))
    [update] = updates(outcome)
    assert update.status == "final" and update.result == [0, 1, 1, 2, 3, 5]
    assert ros.executed == [5]


def test_a_name_without_a_type_is_looked_up_in_the_graph(ros: Any, tmp_path: Path) -> None:
    program = COUNT.replace(FIB, '"/fib"') + "procedure main() { count(3); }\n"
    program += "bool function postcond() = length(seq()) == 4 & seq()[3] == 2\n"
    ok(run(tmp_path, program))


def test_a_service_response_fills_a_compound_with_the_same_field_names(ros: Any, tmp_path: Path) -> None:
    program = """
compound Answer { bool success, string message }
Answer fluent answer() { initially: () = null; }
Answer exog_function response(string name);
action switch(bool on) {
senses:
    answer() = response("/set_bool");
mapping:
    "/set_bool" { data = on }
}
procedure main() { switch(true); }
bool function postcond() = answer().success & answer().message == "on"
"""
    ok(run(tmp_path, program))


def test_nested_fields_by_path_and_by_compound_value(ros: Any, tmp_path: Path) -> None:
    program = """
compound Stamp { number sec, number nanosec }
compound Basic { number int32_value, number float64_value, bool bool_value }
compound Echo { Basic nested_field, Stamp nested_different_pkg }
Echo fluent echo() { initially: () = null; }
Echo exog_function echoed(string name);
action send(number n, number x, Stamp t) {
senses:
    echo() = echoed("/nested");
mapping:
    "/nested : test_msgs/action/NestedMessage" {
        nested_field__int32_value = n,
        nested_field__float64_value = x,
        nested_field__bool_value = true,
        nested_different_pkg = t
    }
}
procedure main() { send(-7, 2.5, Stamp { sec = 12, nanosec = 34 }); }
bool function postcond() =
    echo().nested_field.int32_value == -7 & echo().nested_field.float64_value == 2.5
    & echo().nested_field.bool_value & echo().nested_different_pkg.sec == 12
    & echo().nested_different_pkg.nanosec == 34
"""
    ok(run(tmp_path, program))


def test_lists_fill_arrays_and_constants_fill_fields(ros: Any, tmp_path: Path) -> None:
    program = """
string fluent got() { initially: () = ""; }
string exog_function text(string name);
action echo(string s) {
senses:
    got() = text("/basic");
mapping:
    "/basic : test_msgs/srv/BasicTypes" { string_value = s, int8_value = -128, float32_value = 1.5 }
}
procedure main() { echo("hello"); }
bool function postcond() = got() == "hello"
"""
    binding = '["/basic"]\nresult = "string_value"\n'
    ok(run(tmp_path, program, binding))


# ---------------------------------------------------------------- failures


@pytest.mark.fault
def test_an_aborted_goal_fails_with_the_reason(ros: Any, tmp_path: Path) -> None:
    outcome = ok(run(tmp_path, COUNT + "procedure main() { count(-1); }\n"))
    [update] = updates(outcome)
    assert update.status == "failed"
    assert 'the action server "/fib" aborted the goal' in (update.reason or "")
    assert outcome.recording is not None and not outcome.recording.of(SenseEvent)


@pytest.mark.fault
def test_a_rejected_goal_fails(ros: Any, tmp_path: Path) -> None:
    outcome = ok(run(tmp_path, COUNT + "procedure main() { count(-2); }\n"))
    [update] = updates(outcome)
    assert update.status == "failed" and "rejected the goal" in (update.reason or "")


@pytest.mark.fault
def test_a_missing_server_fails_after_the_server_timeout(ros: Any, tmp_path: Path) -> None:
    program = COUNT.replace("/fib :", "/nowhere :") + "procedure main() { count(1); }\n"
    started = time.monotonic()
    outcome = ok(run(tmp_path, program, "[defaults]\nserver_timeout = 0.3\n"))
    assert time.monotonic() - started < 5
    [update] = updates(outcome)
    assert update.status == "failed"
    assert 'no action server "/nowhere" became available within 0.3 s' in (update.reason or "")


@pytest.mark.fault
def test_a_missing_name_without_a_type_fails_too(ros: Any, tmp_path: Path) -> None:
    program = COUNT.replace(FIB, '"/nowhere"') + "procedure main() { count(1); }\n"
    outcome = ok(run(tmp_path, program, server_timeout="0.3", discovery_timeout="0.3"))
    [update] = updates(outcome)
    assert update.status == "failed" and '"/nowhere" is not available' in (update.reason or "")


@pytest.mark.fault
def test_arguments_that_do_not_fit_fail_before_anything_is_sent(ros: Any, tmp_path: Path) -> None:
    program = COUNT + "procedure main() { count(2.5); count(3000000000); }\n"
    outcome = ok(run(tmp_path, program))
    reasons = [u.reason or "" for u in updates(outcome)]
    assert [u.status for u in updates(outcome)] == ["failed", "failed"]
    assert "order: expected a whole number (int32), got 2.5" in reasons[0]
    assert "order: 3000000000 is out of range for int32" in reasons[1]
    assert ros.requests == []


@pytest.mark.fault
def test_a_result_that_does_not_fit_the_sensed_type_fails(ros: Any, tmp_path: Path) -> None:
    program = """
symbol domain Place = {table, shelf}
Place fluent where() { initially: () = null; }
Place exog_function sensed(string name);
action look(string s) {
senses:
    where() = sensed("/basic");
mapping:
    "/basic : test_msgs/srv/BasicTypes" { string_value = s }
}
procedure main() { look("table"); look("floor"); }
bool function postcond() = where() == table
"""
    outcome = ok(run(tmp_path, program, '["/basic"]\nresult = "string_value"\n'))
    first, second = updates(outcome)
    assert first.status == "final"
    assert second.status == "failed" and "bad result" in (second.reason or "") and "floor" in (second.reason or "")


@pytest.mark.slow
@pytest.mark.fault
def test_a_lost_goal_request_is_sent_again_and_the_late_duplicate_cancelled(ros: Any, tmp_path: Path) -> None:
    from std_msgs.msg import String

    # The program goes on until the test has seen the first goal cancelled (or 5 s passed).
    program = (
        COUNT
        + """
string fluent heard() { initially: () = ""; }
exog_action said(string what) {
mapping:
    "/events : std_msgs/msg/String" { data = what }
effect:
    heard() = what;
}
procedure main() { count(-6); test(heard() == "done"); }
"""
    )

    def finish() -> None:
        ros.wait_for_subscriber(ros.events)
        deadline = time.monotonic() + 5
        while -6 not in ros.cancelled and time.monotonic() < deadline:
            time.sleep(0.01)
        ros.events.publish(String(data="done"))

    finisher = threading.Thread(target=finish)
    finisher.start()
    outcome = ok(run(tmp_path, program, '["/fib"]\nack_timeout = 0.5\nresend = true\n'))
    finisher.join(10)
    [update] = updates(outcome)
    assert update.status == "final"
    assert ros.requests == [-6, -6]
    assert ros.cancelled == [-6]  # the first goal, accepted late, was not left running


@pytest.mark.slow
@pytest.mark.fault
def test_goal_requests_never_answered_fail(ros: Any, tmp_path: Path) -> None:
    binding = '["/fib"]\nack_timeout = 0.3\nresend = true\n'
    outcome = ok(run(tmp_path, COUNT + "procedure main() { count(-5); }\n", binding))
    [update] = updates(outcome)
    assert update.status == "failed" and "did not answer the goal request within 0.3 s (sent twice)" in (
        update.reason or ""
    )


@pytest.mark.slow
@pytest.mark.fault
def test_a_goal_request_is_not_sent_again_unless_the_binding_says_so(ros: Any, tmp_path: Path) -> None:
    """A goal need not be idempotent: by default, a goal request not answered within
    ack_timeout fails the activity, and the goal, accepted late, is cancelled."""
    # The program goes on while the late acceptance (1.5 s after the request) arrives.
    program = '#include "time.gpp"\n' + COUNT + "procedure main() { count(-6); wait_for(2.5); }\n"
    outcome = ok(run(tmp_path, program, '["/fib"]\nack_timeout = 0.3\n'))
    [update] = updates(outcome)
    assert update.status == "failed"
    assert (update.reason or "").endswith("did not answer the goal request within 0.3 s"), update.reason
    deadline = time.monotonic() + 10
    while -6 not in ros.cancelled and time.monotonic() < deadline:
        time.sleep(0.01)
    assert ros.requests == [-6] and ros.cancelled == [-6]


@pytest.mark.slow
@pytest.mark.fault
def test_a_slow_service_times_out(ros: Any, tmp_path: Path) -> None:
    program = """
action poke() { mapping: "/slow : std_srvs/srv/Trigger" {} }
procedure main() { poke(); }
"""
    started = time.monotonic()
    outcome = ok(run(tmp_path, program, '["/slow"]\nresult_timeout = 0.3\n'))
    assert time.monotonic() - started < 2.0
    [update] = updates(outcome)
    assert update.status == "failed" and "gave no result within 0.3 s" in (update.reason or "")


@pytest.mark.fault
# The test server is destroyed while its own executor's threads spin (as a crash would): rclpy
# may then fail inside one of them ("action server pointer is invalid"), on the server's side.
@pytest.mark.filterwarnings("ignore::pytest.PytestUnhandledThreadExceptionWarning")
def test_a_server_that_goes_away_during_a_goal_fails_it(ros: Any, tmp_path: Path) -> None:
    def kill_soon() -> None:
        deadline = time.monotonic() + 10
        while 5000 not in ros.executed and time.monotonic() < deadline:
            time.sleep(0.01)
        ros.fib.destroy()

    killer = threading.Thread(target=kill_soon)
    killer.start()
    outcome = ok(run(tmp_path, COUNT + "procedure main() { count(5000); }\n"))
    killer.join(10)
    [update] = updates(outcome)
    assert update.status == "failed" and 'the action server "/fib" went away' in (update.reason or "")


@pytest.mark.fault
def test_a_goal_without_feedback_for_its_feedback_timeout_fails_and_is_cancelled(ros: Any, tmp_path: Path) -> None:
    """-12 sends feedback for 0.3 s, then none: a stuck (or, across processes, dead) server."""
    outcome = ok(run(tmp_path, COUNT + "procedure main() { count(-12); }\n", '["/fib"]\nfeedback_timeout = 0.5\n'))
    [update] = updates(outcome)
    assert update.status == "failed"
    assert 'the action server "/fib" sent no feedback for 0.5 s (feedback_timeout)' in (update.reason or "")
    deadline = time.monotonic() + 10
    while -12 not in ros.cancelled and time.monotonic() < deadline:
        time.sleep(0.01)
    assert ros.cancelled == [-12]


def test_a_goal_that_sends_feedback_runs_past_its_feedback_timeout(ros: Any, tmp_path: Path) -> None:
    program = COUNT + "procedure main() { start(count(-10)); wait_for(1.0); cancel(count(-10)); end(count(-10)); }\n"
    outcome = ok(run(tmp_path, '#include "time.gpp"\n' + program, '["/fib"]\nfeedback_timeout = 0.4\n'))
    assert [(u.action, u.status) for u in updates(outcome)] == [("count(-10)", "cancelled")]


@pytest.mark.fault
def test_an_aborted_goals_result_decides_what_the_program_does(ros: Any, tmp_path: Path) -> None:
    """The result of an aborted goal is the name's last result: `on_fail` reads it."""
    program = (
        COUNT
        + """
string fluent handled() { initially: () = ""; }
procedure main() {
    during (count(-1)) {} on_fail {
        if (length(result("/fib")) == 1 & result("/fib")[0] == 0) handled() = "aborted with [0]";
        else handled() = "something else";
    }
}
bool function postcond() = handled() == "aborted with [0]" & length(seq()) == 0
"""
    )
    outcome = ok(run(tmp_path, program))
    [update] = updates(outcome)
    assert update.status == "failed" and update.result is ABSENT  # not sensed: the goal failed
    assert update.reason == 'the action server "/fib" aborted the goal (its result: {sequence = [0]})'


@pytest.mark.fault
def test_a_cancel_the_server_refuses_is_reported_and_the_goal_still_tracked(ros: Any, tmp_path: Path) -> None:
    program = COUNT + "procedure main() { start(count(-11)); cancel(count(-11)); end(count(-11)); }\n"
    outcome = ok(run(tmp_path, program))
    assert outcome.recording is not None
    [notice] = outcome.recording.of(NoticeEvent)
    assert notice.action == "count(-11)"
    assert notice.message == 'the action server "/fib" refused to cancel the goal: it still runs'
    [update] = updates(outcome)
    assert update.status == "final" and update.result == [0, 1, 1]  # it ran to its end, and was tracked
    assert update.t >= notice.t
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.Draft202012Validator(load_schema()).validate(json.loads(encode(notice)))


@pytest.mark.fault
def test_a_goal_still_running_at_the_end_whose_cancel_is_refused_is_not_waited_for(ros: Any, tmp_path: Path) -> None:
    outcome = ok(run(tmp_path, COUNT + "procedure main() { start(count(-11)); }\n"))
    assert outcome.recording is not None
    [notice] = outcome.recording.of(NoticeEvent)
    assert "refused to cancel the goal: it still runs" in notice.message
    assert not [d for d in outcome.diagnostics if "did not acknowledge" in d.message]


# ---------------------------------------------------------------- preemption and concurrency


def test_cancel_preempts_exactly_that_goal(ros: Any, tmp_path: Path) -> None:
    program = (
        COUNT
        + """
procedure main() {
    start(count(5000));
    start(count(5001));
    cancel(count(5000));
    end(count(5000));
    cancel(count(5001));
    end(count(5001));
}
"""
    )
    outcome = ok(run(tmp_path, program))
    assert [(u.action, u.status) for u in updates(outcome)] == [
        ("count(5000)", "cancelled"),
        ("count(5001)", "cancelled"),
    ]
    assert ros.cancelled == [5000, 5001]


def test_concurrent_goals_on_one_action(ros: Any, tmp_path: Path) -> None:
    program = (
        COUNT.replace("order = n", "order = n")
        + """
procedure main() {
    start(count(-3)); start(count(1)); start(count(2));
    end(count(-3)); end(count(1)); end(count(2));
}
"""
    )
    outcome = ok(run(tmp_path, program))
    results = {u.action: (u.status, u.result) for u in updates(outcome)}
    assert results == {
        "count(-3)": ("final", [0, 1, 1, 2, 3, 5]),
        "count(1)": ("final", [0, 1]),
        "count(2)": ("final", [0, 1, 1]),
    }
    assert ros.max_running >= 2


def test_goals_still_running_at_the_end_are_cancelled(ros: Any, tmp_path: Path) -> None:
    outcome = ok(run(tmp_path, COUNT + "procedure main() { start(count(5000)); }\n"))
    assert [(u.action, u.status) for u in updates(outcome)] == [("count(5000)", "cancelled")]
    assert ros.cancelled == [5000]


# ---------------------------------------------------------------- exogenous events and functions


def test_a_burst_of_exogenous_messages_arrives_complete_and_in_order(ros: Any, tmp_path: Path) -> None:
    from std_msgs.msg import Int32

    program = """
number fluent received() { initially: () = 0; }
bool fluent in_order() { initially: () = true; }
exog_action counted(number n) {
mapping:
    "/count : std_msgs/msg/Int32" { data = n }
effect:
    in_order() = in_order() & n == received();
    received() = received() + 1;
}
procedure main() { test(received() == 1000); }
bool function postcond() = in_order()
"""

    def publish() -> None:
        ros.wait_for_subscriber(ros.count)
        for i in range(1000):
            ros.count.publish(Int32(data=i))

    publisher = threading.Thread(target=publish)
    publisher.start()
    outcome = ok(run(tmp_path, program, timeout=30.0))
    publisher.join(10)
    assert outcome.result is not None and outcome.result.exog_events == 1000


def test_exogenous_functions_from_a_topic_and_a_service(ros: Any, tmp_path: Path) -> None:
    from std_msgs.msg import String

    program = """
string exog_function last_event();
string exog_function switched(bool want);
string fluent seen() { initially: () = ""; }
string fluent answer() { initially: () = ""; }
procedure main() { seen() = last_event(); answer() = switched(false); }
bool function postcond() = seen() == "door opened" & answer() == "off"
"""
    binding = """
[exog_function.last_event]
topic = "/events : std_msgs/msg/String"

[exog_function.switched]
service = "/set_bool : std_srvs/srv/SetBool"
request = { data = "want" }
field = "message"
"""

    def publish() -> None:
        ros.wait_for_subscriber(ros.events)
        ros.events.publish(String(data="door opened"))

    publisher = threading.Thread(target=publish)
    publisher.start()
    ok(run(tmp_path, program, binding))
    publisher.join(10)


def test_an_exogenous_action_from_a_topic_runs_its_effects(ros: Any, tmp_path: Path) -> None:
    from std_msgs.msg import String

    program = """
string fluent heard() { initially: () = ""; }
exog_action said(string what) {
mapping:
    "/events : std_msgs/msg/String" { data = what }
effect:
    heard() = what;
}
procedure main() { test(heard() == "hello"); }
"""

    def publish() -> None:
        ros.wait_for_subscriber(ros.events)
        ros.events.publish(String(data="hello"))

    publisher = threading.Thread(target=publish)
    publisher.start()
    ok(run(tmp_path, program))
    publisher.join(10)


# ---------------------------------------------------------------- publishing

SAY = """
action say(string s) {
mapping:
    "/said : std_msgs/msg/String" { data = s }
}
"""


@pytest.mark.parametrize("typed", [True, False], ids=["typed", "untyped"])
def test_the_first_message_published_reaches_a_subscriber_that_was_up_before_the_run(
    ros: Any, tmp_path: Path, typed: bool
) -> None:
    # Untyped, the mapping's type comes from the graph: the subscriber's.
    say = SAY if typed else SAY.replace("/said : std_msgs/msg/String", "/said")
    outcome = ok(run(tmp_path, say + 'procedure main() { say("first"); say("second"); }\n'))
    deadline = time.monotonic() + 5
    while len(ros.heard) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert ros.heard == ["first", "second"]
    assert outcome.recording is not None and not outcome.recording.of(NoticeEvent)


@pytest.mark.fault
def test_a_message_published_with_no_subscriber_is_said_in_the_trace(ros: Any, tmp_path: Path) -> None:
    program = SAY.replace("/said", "/nobody_listens") + 'procedure main() { say("lost"); }\n'
    outcome = ok(run(tmp_path, program, discovery_timeout="0.3"))  # the attach waits for a subscriber
    [update] = updates(outcome)
    assert update.status == "final"
    assert outcome.recording is not None
    [notice] = outcome.recording.of(NoticeEvent)
    assert notice.action == 'say("lost")'
    assert notice.message == 'published on "/nobody_listens" with no subscriber matched: nobody received it'


@pytest.mark.fault
def test_the_attach_waits_once_for_discovery_names_and_subscribers_alike(
    ros: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A name mapped without a type that never appears and a topic nobody subscribes to: the
    attach waits for both at once, at most `discovery_timeout` in all (not that and then a
    wait for subscribers on top). The attach alone is timed, not the rest of the run."""
    from gpp.platform.ros2.platform import Ros2Platform

    attach = Ros2Platform.attach
    took: list[float] = []

    def timed(platform: Ros2Platform, interface: Any) -> Any:
        started = time.monotonic()
        try:
            return attach(platform, interface)
        finally:
            took.append(time.monotonic() - started)

    monkeypatch.setattr(Ros2Platform, "attach", timed)
    program = SAY.replace("/said", "/nobody_listens") + 'action poke() { mapping: "/nowhere" {} }\n'
    program += "procedure main() { }\n"
    ok(run(tmp_path, program, discovery_timeout="1.5"))
    [waited] = took
    assert 1.5 <= waited < 1.5 + 0.9, waited  # two waits took 2.5 s and more


def test_a_transient_local_publisher_keeps_its_message_for_a_late_joiner(ros: Any, tmp_path: Path) -> None:
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    discovery_timeout = 0.5
    program = (
        SAY.replace("/said", "/late")
        + """
string fluent heard() { initially: () = ""; }
exog_action said(string what) {
mapping:
    "/events : std_msgs/msg/String" { data = what }
effect:
    heard() = what;
}
procedure main() { say("kept"); test(heard() == "done"); }
"""
    )
    got: list[str] = []

    def join_late() -> None:
        deadline = time.monotonic() + 10
        while ros.node.count_publishers("/late") == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        # The message is published before anyone subscribes: after the attach's wait for one.
        time.sleep(discovery_timeout + 0.5)
        latched = QoSProfile(
            depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
        )
        ros.node.create_subscription(String, "/late", lambda m: got.append(m.data), latched)
        while not got and time.monotonic() < deadline:
            time.sleep(0.01)
        ros.wait_for_subscriber(ros.events)
        ros.events.publish(String(data="done"))

    joiner = threading.Thread(target=join_late)
    joiner.start()
    binding = '["/late"]\nqos = { durability = "transient_local", depth = 1 }\n'
    outcome = ok(run(tmp_path, program, binding, discovery_timeout=str(discovery_timeout)))
    joiner.join(15)
    assert got == ["kept"]
    assert outcome.recording is not None
    [notice] = outcome.recording.of(NoticeEvent)
    assert notice.message.endswith("with no subscriber matched: it is kept for a subscriber that joins later")


# ---------------------------------------------------------------- exogenous functions from services


def test_a_polled_service_wakes_a_waiting_program_and_an_unpolled_one_does_not(ros: Any, tmp_path: Path) -> None:
    program = """
string exog_function ticks();
procedure main() { test(ticks() == "3"); }
"""
    binding = '[exog_function.ticks]\nservice = "/ticks : std_srvs/srv/Trigger"\nfield = "message"\n'
    ok(run(tmp_path, program, binding + "poll = 0.05\n"))
    assert ros.ticks >= 3
    ros.ticks = 0
    outcome = run(tmp_path, program, binding)
    assert outcome.result is not None and outcome.result.status is RunStatus.BLOCKED
    assert ros.ticks == 1  # asked once; nothing can change the answer without a poll
    [blocked] = errors(outcome)
    assert "this test is false" in blocked


@pytest.mark.fault
def test_a_service_that_cannot_answer_is_no_answer_and_the_program_waits(ros: Any, tmp_path: Path) -> None:
    program = """
string exog_function state();
procedure main() { test(state() == "on"); }
"""
    binding = '[exog_function.state]\nservice = "/nowhere : std_srvs/srv/Trigger"\nfield = "message"\n'
    binding += "server_timeout = 0.1\ntimeout = 0.1\npoll = 0.2\n"
    outcome = run(tmp_path, program, binding, timeout=1.0)
    assert outcome.result is not None and outcome.result.status is RunStatus.TIMEOUT
    assert outcome.recording is not None
    [waiting] = [w for w in outcome.recording.of(WaitingEvent) if not w.resumed]
    assert "exogenous function `state` has no answer" in waiting.condition
    assert waiting.statement == 'test(state() == "on");'


# ---------------------------------------------------------------- checks at attach


@pytest.mark.fault
def test_mapping_problems_are_reported_at_once_at_the_mapping(ros: Any, tmp_path: Path) -> None:
    program = """
compound Where { number x, number yy }
number fluent got() { initially: () = 0; }
number exog_function fib(string name);
action count(number n) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { ordr = n }
}
action wrong_type(string s) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = s }
}
action too_big() {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = 5000000000 }
}
action nested(Where w) {
mapping:
    "/pose : geometry_msgs/msg/Point" { x = 1, z = w }
}
action no_such_type() {
mapping:
    "/x : test_msgs/action/Fibonaci" {}
}
action senses_a_number() {
senses:
    got() = fib("/fib");
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = 2 }
}
exog_action heard(string what) {
mapping:
    "/events : std_msgs/msg/String" { dat = what }
}
procedure main() { count(1); }
"""
    outcome = run(tmp_path, program)
    assert outcome.result is None
    found = {(d.span.line if d.span else 0, d.message, d.help) for d in outcome.diagnostics if d.code == "R0007"}
    messages = sorted(found)
    text = "\n".join(f"{line}: {m} [{h}]" for line, m, h in messages)
    assert "has no field `ordr` (its fields: order)" in text and "did you mean `order`?" in text
    assert "`order`: a int32 field needs a number, not string" in text
    assert "order: 5000000000 is out of range for int32" in text
    assert "`z`: a double field needs a number, not Where" in text
    assert (
        "cannot import `test_msgs/action/Fibonaci`: package `test_msgs` has no such type; did you mean `Fibonacci`?"
        in text
    )
    assert "the result field `sequence`: a sequence<int32>" in text or "the result field `sequence`" in text
    assert "has no field `dat`" in text and "did you mean `data`?" in text
    assert len(messages) == 7, text
    lines = {line for line, _, _ in messages}
    assert {7, 11, 15, 19, 23, 29, 33} == lines, text
    assert ros.requests == []


def test_binding_entries_that_fit_no_mapping_are_reported(ros: Any, tmp_path: Path) -> None:
    program = COUNT + "procedure main() { count(1); }\n"
    binding = '["/fibb"]\nack_timeout = 1.0\n\n[exog_function.nope]\ntopic = "/events : std_msgs/msg/String"\n'
    outcome = run(tmp_path, program, binding)
    assert outcome.result is None
    found = {(d.message, d.help, d.span.line if d.span else 0) for d in outcome.diagnostics if d.code == "R0007"}
    assert ('binding file: ["/fibb"]: no mapping of the program uses this ROS name', "did you mean `/fib`?", 1) in found
    assert any("declares no exogenous function `nope`" in m and line == 4 for m, _, line in found), found


@pytest.mark.fault
def test_a_run_starts_nothing_when_a_mapping_is_wrong(ros: Any, tmp_path: Path) -> None:
    program = COUNT.replace("order = n", "ordr = n") + "procedure main() { count(1); }\n"
    outcome = run(tmp_path, program)
    assert outcome.exit_code == 1
    assert outcome.recording is not None and not outcome.recording.of(StartEvent)
    assert ros.requests == []


# ---------------------------------------------------------------- time


def test_a_program_waiting_for_the_clock_wakes_up_on_wall_time(ros: Any, tmp_path: Path) -> None:
    program = """#include "time.gpp"
number fluent woke_at() { initially: () = -1; }
procedure main() { wait_for(0.3); woke_at() = context_time(); }
bool function postcond() = woke_at() >= 0.3 & woke_at() < 2
"""
    outcome = ok(run(tmp_path, program))
    assert outcome.result is not None and 0.3 <= outcome.result.platform_time < 2


def test_trace_times_never_go_back(ros: Any, tmp_path: Path) -> None:
    """A `sense` record is stamped with the time of its `end` (it was stamped after it)."""
    program = COUNT + "procedure main() { count(3); count(4); }\n"
    outcome = ok(run(tmp_path, program))
    assert outcome.recording is not None
    times = [e.t for e in outcome.recording.records]
    assert len(outcome.recording.of(SenseEvent)) == 2
    assert times == sorted(times), times


# ---------------------------------------------------------------- options


@pytest.mark.fault
@pytest.mark.parametrize(
    ("option", "message"),
    [
        ("domain_id=300", "error: option `domain_id` of platform `ros2` must be a whole number from 0 to 232, not 300"),
        (
            "node_name=robot1/gpp_agent",
            "error: option `node_name` of platform `ros2` must be a ROS node name (letters, digits and `_`, not "
            'starting with a digit; no `/` or namespace), not "robot1/gpp_agent"',
        ),
        (
            "log_level=warning",
            "error: option `log_level` of platform `ros2` must be one of debug, info, warn, error, fatal, "
            'not "warning"; did you mean `warn`?',
        ),
    ],
)
def test_options_ros_would_refuse_are_one_line_usage_errors(tmp_path: Path, option: str, message: str) -> None:
    from tests.support.cli import run as gpp

    program = tmp_path / "agent.gpp"
    program.write_text(COUNT + "procedure main() { count(1); }\n", encoding="utf-8")
    result = gpp("run", str(program), "--platform", "ros2", "-o", option)
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip().splitlines() == [message], result.stderr
