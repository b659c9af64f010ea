"""The checks of mappings without a type (their type comes from the ROS graph): made before
anything is sent, at attach once discovery has found the name, or the moment the graph shows
a name that appeared later; the type is looked up once, not per goal; sensing through an
expression. In one process (shared context, discovery off) and, for the default style of
the docs, against servers in another process (tests/platform/ros2/test_ros2_processes.py's
fixtures)."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rclpy")

from gpp.platform.ros2.bridge import Bridge
from gpp.run.runner import RunOptions, RunOutcome, RunSetupError, run_program
from gpp.runtime.events import UpdateEvent
from gpp.runtime.executor import RunStatus
from tests.platform.ros2.test_ros2_exog import Publisher, publisher  # noqa: F401 (fixtures)
from tests.platform.ros2.test_ros2_processes import domain, ros_env, servers, trace_events  # noqa: F401 (fixtures)


def run(tmp_path: Path, text: str, timeout: float = 15.0, **options: str) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(text, encoding="utf-8")
    return run_program(path, RunOptions(record=True, platform="ros2", platform_options=options, timeout=timeout))


def r0007(outcome: RunOutcome) -> list[tuple[int, str, str | None]]:
    """(line, message, help) of each R0007 error, in order."""
    return [(d.span.line if d.span else 0, d.message, d.help) for d in outcome.diagnostics if d.code == "R0007"]


def finished(outcome: RunOutcome) -> RunOutcome:
    messages = [f"{d.message} {' '.join(d.notes)}" for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.postcond is not False, messages
    return outcome


# ---------------------------------------------------------------- checked at attach


@pytest.mark.fault
def test_an_untyped_mapping_is_checked_at_attach(ros: Any, tmp_path: Path) -> None:
    program = """
action count(number n) {
mapping:
    "/fib" { ordr = n }
}
action echo(string s) {
mapping:
    "/basic" { string_value = s, int8_value = 300 }
}
procedure main() { count(1); echo("x"); }
"""
    outcome = run(tmp_path, program)
    assert outcome.result is None and outcome.exit_code == 1
    found = r0007(outcome)
    assert [line for line, _, _ in found] == [4, 8], found
    assert "`test_msgs/Fibonacci_Goal` has no field `ordr` (its fields: order)" in found[0][1]
    assert found[0][2] == "did you mean `order`?"
    assert "int8_value: 300 is out of range for int8 (-128..127)" in found[1][1]
    assert ros.requests == []


@pytest.mark.fault
def test_a_name_that_appears_late_is_checked_before_its_first_goal(ros: Any, tmp_path: Path) -> None:
    """The name is not in the graph at attach (discovery_timeout passes): the goal waits for
    it; once the graph shows its type, the mapping is checked, found wrong, and the run stops
    with R0007 at the mapping. The late server never gets a goal request."""
    import rclpy
    from rclpy.action.server import ActionServer, GoalResponse
    from test_msgs.action import Fibonacci

    requests: list[int] = []
    program = """
action count(number n) {
mapping:
    "/late" { ordr = n }
}
procedure main() { count(1); }
"""
    late: list[Any] = []

    def serve_late() -> None:
        time.sleep(0.6)
        node = rclpy.create_node("late_server", context=ros.node.context, start_parameter_services=False)

        def goal(request: Any) -> GoalResponse:
            requests.append(request.order)
            return GoalResponse.ACCEPT

        late.append(ActionServer(node, Fibonacci, "/late", execute_callback=lambda h: None, goal_callback=goal))
        ros.executor.add_node(node)
        late.append(node)

    server = threading.Thread(target=serve_late)
    server.start()
    started = time.monotonic()
    outcome = run(tmp_path, program, discovery_timeout="0.2", server_timeout="10")
    server.join(10)
    assert time.monotonic() - started < 8  # stopped when the type showed, not at the server timeout
    assert outcome.result is not None and outcome.result.status is RunStatus.ERROR
    [(line, message, hint)] = r0007(outcome)
    assert line == 4 and "has no field `ordr`" in message and hint == "did you mean `order`?"
    assert requests == []
    assert outcome.recording is not None
    [update] = outcome.recording.of(UpdateEvent)
    assert update.status == "failed" and "nothing was sent" in (update.reason or "")


@pytest.mark.fault
def test_a_topic_that_appears_late_is_checked_before_its_messages_become_events(ros: Any, tmp_path: Path) -> None:
    from std_msgs.msg import String

    program = """
string fluent heard() { initially: () = ""; }
exog_action said(string what) {
mapping:
    "/late_events" { dat = what }
effect:
    heard() = what;
}
procedure main() { test(heard() == "hello"); }
"""
    late: list[Any] = []

    def publish_late() -> None:
        time.sleep(0.5)
        late.append(ros.node.create_publisher(String, "/late_events", 10))

    publishing = threading.Thread(target=publish_late)
    publishing.start()
    outcome = run(tmp_path, program, discovery_timeout="0.2")
    publishing.join(10)
    assert outcome.result is not None and outcome.result.status is RunStatus.ERROR
    [(line, message, hint)] = r0007(outcome)
    assert line == 5 and "`std_msgs/String` has no field `dat`" in message and hint == "did you mean `data`?"


@pytest.mark.fault
def test_a_name_never_discovered_waits_the_discovery_timeout_then_fails_its_goal(ros: Any, tmp_path: Path) -> None:
    program = 'action poke() { mapping: "/nowhere" {} }\nprocedure main() { poke(); }\n'
    started = time.monotonic()
    outcome = finished(run(tmp_path, program, discovery_timeout="0.3", server_timeout="0.3"))
    assert time.monotonic() - started < 5
    assert outcome.recording is not None
    [update] = outcome.recording.of(UpdateEvent)
    assert update.status == "failed" and '"/nowhere" is not available' in (update.reason or "")


def test_the_discovery_timeout_must_be_positive(ros: Any, tmp_path: Path) -> None:
    with pytest.raises(RunSetupError, match=r"discovery_timeout.*> 0"):
        run(tmp_path, "procedure main() { }\n", discovery_timeout="0")


# ---------------------------------------------------------------- the type is kept


def test_an_untyped_name_is_not_looked_up_per_goal(ros: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    looked: list[str] = []
    graph_type = Bridge.graph_type

    def counted(self: Bridge, name: str) -> tuple[str, str] | None:
        looked.append(name)
        return graph_type(self, name)

    monkeypatch.setattr(Bridge, "graph_type", counted)
    program = 'action count(number n) { mapping: "/fib" { order = n } }\n'
    program += "procedure main() { count(1); count(2); count(3); }\n"
    outcome = finished(run(tmp_path, program))
    assert outcome.recording is not None
    assert [u.status for u in outcome.recording.of(UpdateEvent)] == ["final"] * 3
    assert ros.executed == [1, 2, 3]
    assert looked == []  # the type came with the graph read at attach, and was kept


# ---------------------------------------------------------------- sensing through an expression


def test_sensing_an_element_of_the_result(ros: Any, tmp_path: Path) -> None:
    program = """
number fluent last() { initially: () = -1; }
list[number] exog_function seq(string name);
action count(number n) {
senses:
    last() = seq("/fib")[n];
mapping:
    "/fib" { order = n }
}
procedure main() { count(5); }
bool function postcond() = last() == 5
"""
    finished(run(tmp_path, program))


def test_sensing_a_field_of_a_compound_result(ros: Any, tmp_path: Path) -> None:
    program = """
compound Answer { bool success, string message }
string fluent said() { initially: () = ""; }
Answer exog_function response(string name);
action switch(bool on) {
senses:
    said() = response("/set_bool").message;
mapping:
    "/set_bool" { data = on }
}
procedure main() { switch(true); }
bool function postcond() = said() == "on"
"""
    finished(run(tmp_path, program))


def test_a_result_of_one_message_field_fills_a_compound(ros: Any, tmp_path: Path) -> None:
    program = """
compound Header { string frame_id }
compound Plan { Header header }
Plan fluent plan() { initially: () = null; }
Plan exog_function planned(string name);
action plan_to(string frame) {
senses:
    plan() = planned("/get_plan");
mapping:
    "/get_plan" { goal__header__frame_id = frame }
}
procedure main() { plan_to("map"); }
bool function postcond() = plan().header.frame_id == "map"
"""
    finished(run(tmp_path, program))


def test_a_sensed_expression_of_the_wrong_type_is_reported_at_attach(ros: Any, tmp_path: Path) -> None:
    program = """
number fluent last() { initially: () = -1; }
list[string] exog_function seq(string name);
action count(number n) {
senses:
    last() = length(seq("/fib"));
mapping:
    "/fib" { order = n }
}
procedure main() { count(5); }
"""
    outcome = run(tmp_path, program)
    assert outcome.result is None
    [(line, message, _)] = r0007(outcome)
    assert line == 8 and "the result field `sequence`" in message and "needs a number, not string" in message, message


# ---------------------------------------------------------------- across processes


@pytest.mark.fault
@pytest.mark.slow
def test_a_mistyped_field_in_an_untyped_mapping_stops_the_run_before_any_goal(
    servers: subprocess.Popen[str],  # noqa: F811
    domain: int,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The documented default style (no type in the mapping) against a server in another
    process: the run stops with R0007 at the mapping, and the server got no goal request."""
    program = tmp_path / "agent.gpp"
    program.write_text(
        'action count(number n) {\nmapping:\n    "/fib" { ordr = n }\n}\nprocedure main() { count(1); }\n'
    )
    trace = tmp_path / "trace.jsonl"
    # Discovery across processes takes a moment, more on a busy machine: attach waits for it
    # (generously here), so that the mapping is checked before the run starts.
    command = [sys.executable, "-m", "gpp", "run", str(program), "--platform", "ros2", "--trace", str(trace)]
    agent = subprocess.run(
        [*command, "-o", "discovery_timeout=30"],
        env=ros_env(domain),
        capture_output=True,
        text=True,
        timeout=120,
    )
    servers.send_signal(signal.SIGTERM)
    out, _ = servers.communicate(timeout=30)
    assert agent.returncode == 1, agent.stdout + agent.stderr
    shown = agent.stdout + agent.stderr
    assert "error[R0007]" in shown and "has no field `ordr` (its fields: order)" in shown, shown
    assert f"{program}:3:14" in shown and "did you mean `order`?" in shown, shown
    assert "Traceback" not in shown
    assert not [line for line in out.splitlines() if line.startswith(("request", "goal"))], out
    assert not [e for e in trace_events(trace) if e.get("event") == "start"]  # nothing ran


# ---------------------------------------------------------------- a server that comes back with another type

SWAP = """
string fluent heard() { initially: () = ""; }
exog_action said(string what) {
mapping:
    "/events : std_msgs/msg/String" { data = what }
effect:
    heard() = what;
}
action go(PARAMS) {
mapping:
    "/swap" { MAPPING }
}
procedure main() { test(heard() == "seen"); go(FIRST); test(heard() == "swapped"); go(SECOND); }
"""


def swap_servers(publisher: Publisher, tmp_path: Path, program: str) -> RunOutcome:  # noqa: F811
    """Run `program` against a Fibonacci server on "/swap" in another process that, after the
    first goal, goes and comes back as a NestedMessage server (then the program is told
    "swapped" on /events)."""
    path = tmp_path / "agent.gpp"
    path.write_text(program, encoding="utf-8")
    assert publisher.ask("serve /swap fib") == "serving"
    assert publisher.ask("advertise /events string keep_all") == "advertised"
    failure: list[BaseException] = []

    def swap() -> None:
        try:
            # The first goal once the server's process sees the agent: discovery can be one-sided
            # for a while (up to Fast DDS's next announcement, 3 s), and a goal request sent
            # meanwhile is lost (a failed goal after ack_timeout, not what this test is about).
            assert publisher.ask("node gpp_agent") == "found"
            assert publisher.ask("match /events") == "matched"
            time.sleep(0.3)
            publisher.ask("send /events seen")
            deadline = time.monotonic() + 60
            while publisher.ask("goals /swap") != "goals 1":
                assert time.monotonic() < deadline, "no goal on /swap"
                time.sleep(0.02)
            assert publisher.ask("unserve /swap") == "gone"
            assert publisher.ask("serve /swap nested") == "serving"
            assert publisher.ask("match /events") == "matched"
            time.sleep(0.5)  # the agent's graph shows the change (it is not ordered with messages)
            publisher.ask("send /events swapped")
        except BaseException as e:
            failure.append(e)

    swapper = threading.Thread(target=swap)
    swapper.start()
    # Discovery across processes takes a moment, more on a busy machine: waited for generously.
    options = RunOptions(platform="ros2", platform_options={"discovery_timeout": "30"}, timeout=60.0, record=True)
    outcome = run_program(path, options)
    swapper.join(60)
    assert not failure, failure
    return outcome


@pytest.mark.fault
@pytest.mark.slow
def test_a_server_that_comes_back_with_another_type_that_fits_gets_the_next_goal(
    publisher: Publisher,  # noqa: F811
    tmp_path: Path,
) -> None:
    """No server of the kept type answers any more, and the graph shows another: the mapping
    is checked against it, fits (it names no field), and the next goal goes to the new server."""
    program = SWAP.replace("PARAMS", "").replace("MAPPING", "").replace("FIRST", "").replace("SECOND", "")
    outcome = finished(swap_servers(publisher, tmp_path, program))
    assert outcome.recording is not None
    assert [u.status for u in outcome.recording.of(UpdateEvent)] == ["final", "final"]
    assert publisher.ask("goals /swap") == "goals 2"


@pytest.mark.fault
@pytest.mark.slow
def test_a_server_that_comes_back_with_another_type_is_checked_against_it(
    publisher: Publisher,  # noqa: F811
    tmp_path: Path,
) -> None:
    """No server of the kept type (Fibonacci) answers any more; the graph shows NestedMessage,
    which has no field `order`: the run stops with R0007 at the mapping, and the new server
    never gets a goal."""
    program = SWAP.replace("PARAMS", "number n").replace("MAPPING", "order = n")
    outcome = swap_servers(publisher, tmp_path, program.replace("FIRST", "1").replace("SECOND", "2"))
    assert outcome.result is not None and outcome.result.status is RunStatus.ERROR
    [(line, message, _)] = r0007(outcome)
    assert line == 11 and "test_msgs/NestedMessage" in message and "has no field `order`" in message, message
    assert publisher.ask("goals /swap") == "goals 1"
    assert outcome.recording is not None
    updates = outcome.recording.of(UpdateEvent)
    assert [u.status for u in updates] == ["final", "failed"], [u.reason for u in updates]
    assert "nothing was sent" in (updates[1].reason or "")
