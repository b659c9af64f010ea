"""The agent visible to ROS tools, and sim time, across processes (a random ROS domain of the
test worker's own, discovery on localhost only):

* a subscriber in another process, up before the run, receives every trace record on
  `/gpp_agent/events` as the run goes, in order, exactly the trace file's lines; one that
  joins while the program waits gets the latched state on `/gpp_agent/state` (what runs, what
  the program waits for) and only then lets the run go on;
* in one process (one context, discovery off), the topics are named after the node and
  `publish_trace=false` turns them off;
* with `use_sim_time` (the platform option, or the ROS parameter in the node's arguments) the
  platform's clock, a `wait_for` of stdlib/time.gpp and the stamps of the messages it sends
  follow `/clock` from another process, faster and slower than real time.
"""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("rclpy")

from test_ros2_processes import domain, ros_env, servers, start, stop  # noqa: F401  (fixtures)

from gpp.platform.ros2 import Ros2Platform
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import AssignEvent, TraceEvent, WaitingEvent

HERE = Path(__file__).resolve().parent

LATE_JOINER = """
bool fluent went() {
initially:
    () = false;
}

exog_action go(string who) {
mapping:
    "/go : std_msgs/msg/String" { data = who }
effect:
    went() = true;
}

action count(number n) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = n }
}

procedure main() {
    start(count(4));
    test(went());
    end(count(4));
}
"""


def listened(process: subprocess.Popen[str]) -> list[tuple[str, float, dict[str, Any]]]:
    """(kind, arrival time, JSON) of what a listener printed, up to its `done` (at most 60 s)."""
    assert process.stdout is not None
    found: list[tuple[str, float, dict[str, Any]]] = []
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if not line or line.strip() == "done":
            break
        kind, arrived, data = line.split(" ", 2)
        found.append((kind, float(arrived), json.loads(data)))
    stop(process)
    return found


@pytest.mark.slow
def test_subscribers_in_another_process_follow_the_run_live_and_a_late_one_sees_where_it_is(
    servers: subprocess.Popen[str],  # noqa: F811
    domain: int,  # noqa: F811
    tmp_path: Path,
) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text(LATE_JOINER, encoding="utf-8")
    trace = tmp_path / "run.jsonl"
    env = ros_env(domain)
    command = [sys.executable, str(HERE / "ros2_listener.py"), "/gpp_agent/events", "/gpp_agent/state"]
    early = start(command, env, "ready")
    late: list[subprocess.Popen[str]] = []
    waiting: list[float] = []

    def join_while_waiting(event: TraceEvent) -> None:
        if isinstance(event, WaitingEvent) and not event.resumed and not waiting:
            waiting.append(time.monotonic())
            # The late subscriber lets the program go on (`--go`) once it has the state.
            threading.Thread(target=lambda: late.append(start([*command, "--go", "/go"], env, "ready"))).start()

    outcome = run_program(
        program, RunOptions(platform="ros2", trace=trace, timeout=60.0), listeners=[join_while_waiting]
    )
    ended = time.monotonic()
    assert outcome.result is not None and outcome.result.status.value == "finished", outcome.diagnostics
    lines = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]

    heard = listened(early)
    events = [data for kind, _, data in heard if kind == "event"]
    assert events == lines  # every record, in order, as in the trace file
    # Live: the `waiting` record arrived while the run was still going on.
    # (The first wait is for went(); `end(count(4))` may wait too, when the goal still runs.)
    arrived = next(t for kind, t, d in heard if kind == "event" and d["event"] == "waiting" and "resumed" not in d)
    assert arrived < ended
    states = [data for kind, _, data in heard if kind == "state"]
    assert states[-1]["status"] == "finished" and states[-1]["records"] == len(lines)
    assert states[-1]["activities"] == [] and states[-1]["waiting"] is None

    [joiner] = late
    heard_late = listened(joiner)
    first_state = next(data for kind, _, data in heard_late if kind == "state")
    # Where the run was when it joined: the goal started and not consumed, the wait.
    assert first_state["status"] == "running"
    assert [(a["action"], a["id"]) for a in first_state["activities"]] == [("count(4)", 1)]
    assert first_state["activities"][0]["status"] in ("running", "final")
    assert "went()" in first_state["waiting"]["condition"]
    assert first_state["program"] == str(program) and first_state["platform"] == "ros2"
    # It also got the records so far (the events topic keeps the last 1000 for late joiners)
    # and the rest live.
    assert [data for kind, _, data in heard_late if kind == "event"] == lines
    exog = [line for line in lines if line["event"] == "exog"]
    assert [e["action"] for e in exog] == ['go("late")']


CLOCKED = """
#include "time.gpp"

action mark() {
mapping:
    "/stamped : geometry_msgs/msg/PoseStamped" { }
}

procedure main() {
    mark();
    wait_for(SECONDS);
}
"""

SIM_START = 1000.0  # s: the simulated time the clock starts at


@pytest.fixture
def parameter_context(domain: int) -> Iterator[None]:  # noqa: F811
    """The node's arguments set the ROS parameter `use_sim_time` (as `--ros-args -p
    use_sim_time:=true` on the command line does): the platform joins this context."""
    import rclpy
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions

    context = Context()
    rclpy.init(
        context=context,
        args=["--ros-args", "--log-level", "error", "-p", "use_sim_time:=true"],
        domain_id=domain,
        signal_handler_options=SignalHandlerOptions.NO,
    )
    Ros2Platform.shared_context = context
    try:
        yield
    finally:
        Ros2Platform.shared_context = None
        context.try_shutdown()


def run_on_sim_time(
    tmp_path: Path, domain_id: int, rate: float, seconds: float, options: dict[str, Any]
) -> dict[str, Any]:
    """Run CLOCKED against a clock moving `rate` times as fast as real time; what it measured."""
    program = tmp_path / "agent.gpp"
    program.write_text(CLOCKED.replace("SECONDS", f"{seconds:g}"), encoding="utf-8")
    (tmp_path / "agent.ros2.toml").write_text('["/stamped"]\nstamp = ["header.stamp"]\n', encoding="utf-8")
    clock = start([sys.executable, str(HERE / "ros2_clock.py"), str(rate), str(SIM_START)], ros_env(domain_id), "ready")
    walls: dict[str, float] = {}

    def wall(event: TraceEvent) -> None:
        if isinstance(event, AssignEvent):
            walls["deadline set"] = time.monotonic()
        if isinstance(event, WaitingEvent) and event.resumed:
            walls["resumed"] = time.monotonic()

    try:
        outcome = run_program(
            program,
            RunOptions(platform="ros2", record=True, timeout=120.0, platform_options=options),
            listeners=[wall],
        )
    finally:
        printed = stop(clock)
    assert outcome.result is not None and outcome.result.status.value == "finished", outcome.diagnostics
    assert outcome.recording is not None
    times = [e.t for e in outcome.recording]
    assert times == sorted(times)  # from the header (written before the clock was followed) on
    [assign] = outcome.recording.of(AssignEvent)
    resumed = [e for e in outcome.recording.of(WaitingEvent) if e.resumed]
    stamps = [float(line.split()[1]) for line in printed.splitlines() if line.startswith("stamp ")]
    return {
        "deadline": assign.value,
        "resumed_at": resumed[-1].t,
        "wall": walls["resumed"] - walls["deadline set"],
        "stamps": stamps,
    }


@pytest.mark.slow
@pytest.mark.parametrize(
    ("rate", "seconds", "how"),
    [(10.0, 10.0, "option"), (0.25, 1.0, "parameter")],
    ids=["10x faster, the option", "4x slower, the ROS parameter"],
)
def test_sim_time_follows_clock_faster_and_slower_than_real_time(
    request: pytest.FixtureRequest,
    domain: int,  # noqa: F811
    tmp_path: Path,
    rate: float,
    seconds: float,
    how: str,
) -> None:
    if how == "parameter":
        request.getfixturevalue("parameter_context")
    options: dict[str, Any] = {"use_sim_time": True} if how == "option" else {}
    found = run_on_sim_time(tmp_path, domain, rate, seconds, options)
    # The clock is simulated time since the clock's first message: the wait's deadline is
    # `seconds` after the time it was set, and it resumed once the clock had reached it.
    assert found["resumed_at"] >= found["deadline"] >= seconds
    if rate > 1:
        assert found["wall"] < seconds / 2  # following the wall clock it would take `seconds`
    else:
        assert found["wall"] > seconds * 2  # ... and here it would be over sooner
    # The stamp the agent put in its message is simulated time too (the clock began at 1000 s).
    [stamp] = found["stamps"]
    assert SIM_START <= stamp < SIM_START + 3600


@pytest.mark.slow
@pytest.mark.fault
def test_sim_time_without_a_clock_is_an_error_naming_clock(domain: int, tmp_path: Path) -> None:  # noqa: F811
    program = tmp_path / "agent.gpp"
    program.write_text('#include "time.gpp"\nprocedure main() { wait_for(1); }\n', encoding="utf-8")
    options = {"use_sim_time": True, "discovery_timeout": 0.5}
    outcome = run_program(program, RunOptions(platform="ros2", record=True, platform_options=options))
    assert outcome.result is None
    [message] = [d.message for d in outcome.diagnostics]
    assert "use_sim_time is set, but no message on /clock arrived within 0.5 s" in message


def test_the_topics_follow_the_node_name_and_can_be_turned_off(ros: Any, tmp_path: Path) -> None:
    """A subscriber on the shared context (its own node and thread) hears every record of a run
    as `/courier/events` when the node is `courier`, and nothing when publishing is off."""
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    program = tmp_path / "agent.gpp"
    program.write_text(
        'action count(number n) { mapping: "/fib : test_msgs/action/Fibonacci" { order = n } }\n'
        "procedure main() { count(3); count(2); }\n",
        encoding="utf-8",
    )
    node = rclpy.create_node("test_listener", context=ros.node.context, start_parameter_services=False)
    executor = SingleThreadedExecutor(context=ros.node.context)
    executor.add_node(node)
    heard: dict[str, list[str]] = {"/courier/events": [], "/gpp_agent/events": []}
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    for topic, lines in heard.items():
        node.create_subscription(String, topic, lambda msg, lines=lines: lines.append(msg.data), qos)
    stopping = threading.Event()

    def spin() -> None:
        while not stopping.is_set():
            executor.spin_once(timeout_sec=0.05)

    spinner = threading.Thread(target=spin, daemon=True)
    spinner.start()
    try:
        for name, publish in (("courier", "true"), ("gpp_agent", "false")):
            trace = tmp_path / f"{name}.jsonl"
            options: dict[str, Any] = {"node_name": name, "publish_trace": publish}
            outcome = run_program(program, RunOptions(platform="ros2", trace=trace, platform_options=options))
            assert outcome.ok, outcome.diagnostics
        deadline = time.monotonic() + 10
        expected = (tmp_path / "courier.jsonl").read_text(encoding="utf-8").splitlines()
        while heard["/courier/events"] != expected and time.monotonic() < deadline:
            time.sleep(0.02)
    finally:
        stopping.set()
        spinner.join(5)
        executor.shutdown(timeout_sec=0)
        node.destroy_node()
    assert heard["/courier/events"] == expected
    assert heard["/gpp_agent/events"] == []
