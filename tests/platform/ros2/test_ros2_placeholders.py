"""Placeholders in mapped names (`"/{r}/navigate"`, gpp.platform.ros2.placeholders): `gpp check`
reports every placeholder the ros2 platform could not serve at the mapped name, without ROS;
a parameter that is a placeholder is used (no W0102) and binds an exogenous action's
parameter (no E0308); the runner fills the placeholders of the name a goal goes to; the
binding file's placeholders are checked when the program attaches. The two-robot example runs
against two robot processes in test_ros2_processes.py."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from gpp.model.declarations import fill_placeholders, placeholders_in
from gpp.model.types import Sym
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import ExogEvent, StartEvent
from gpp.runtime.executor import RunStatus
from tests.support.cli import run

DOMAINS = """symbol domain Robot = {robot1, robot2}
number domain Id = {1, 2}
string domain Label = {"left", "right arm"}
"""


def check(tmp_path: Path, program: str) -> list[str]:
    """The concise R0007 lines `gpp check` reports for the program."""
    (tmp_path / "agent.gpp").write_text(DOMAINS + program + "procedure main() { }\n", encoding="utf-8")
    result = run("check", "--format", "concise", "agent.gpp", cwd=tmp_path)
    lines = [line for line in result.stdout.splitlines() if "R0007" in line or "W0102" in line or "E0308" in line]
    assert result.returncode == (1 if lines else 0), result.stdout + result.stderr
    return lines


@pytest.mark.parametrize(
    ("program", "expected"),
    [
        (
            'action go(Robot r) {\nmapping:\n    "/{robot}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{robot}` is not a parameter (its parameters: r)",
        ),
        (
            'action go(number n) {\nmapping:\n    "/robot{n}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{n}` is a parameter of type `number`, whose "
            "values are not known before the run: a placeholder takes a parameter of a domain, whose values make "
            "the names",
        ),
        (
            'action go(Label l) {\nmapping:\n    "/{l}/go" { }\n}\n',
            'agent.gpp:6:5: error[R0007] action `go`: the placeholder `{l}` takes the value "right arm" of domain '
            "`Label`: a part of a ROS name is letters, digits and `_`",
        ),
        (
            'action go(Id n) {\nmapping:\n    "/{n}/go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the placeholder `{n}` takes the value 1 of domain `Id`: it makes "
            '"/1/go", not a ROS name (a part begins with a letter or `_`)',
        ),
        (
            'action go(Robot r) {\nmapping:\n    "/{r}/go : {r}_msgs/action/Go" { }\n}\n',
            "agent.gpp:6:5: error[R0007] action `go`: the type after `:` cannot have a placeholder",
        ),
        (
            'action go(Robot r) {\nmapping:\n    "/{r/go" { }\n}\n',
            'agent.gpp:6:5: error[R0007] action `go`: "/{r/go": a placeholder is a parameter\'s name in braces, '
            'such as "/{r}/navigate" (braces that do not pair, or are empty)',
        ),
        (
            'exog_action bumped(Robot r) {\nmapping:\n    "/{r}/bumper" { id = r }\n}\n',
            "agent.gpp:6:5: error[R0007] exogenous action `bumped`: parameter `r` is filled from the topic's name "
            "(the placeholder `{r}`), so the mapping cannot fill it from the message field `id` too",
        ),
        (
            'exog_action bumped(Robot r, number v) {\nmapping:\n    "/{x}/bumper" { data = v, id = r }\n}\n',
            "agent.gpp:6:5: error[R0007] exogenous action `bumped`: the placeholder `{x}` is not a parameter "
            "(its parameters: r, v)",
        ),
    ],
    ids=["unknown", "not-a-domain", "not-a-token", "leading-digit", "in-the-type", "malformed", "twice", "exog"],
)
def test_check_reports_each_placeholder_the_platform_cannot_serve(tmp_path: Path, program: str, expected: str) -> None:
    lines = check(tmp_path, program)
    assert [line for line in lines if "R0007" in line] == [expected]


def test_placeholders_of_domains_are_fine_and_use_their_parameters(tmp_path: Path) -> None:
    program = """action go(Robot r, Id n, number x) {
mapping:
    "/{r}/arm{n}/go" { x = x }
}
exog_action bumped(Robot r, number v) {
mapping:
    "/{r}/bumper" { data = v }
}
"""
    assert check(tmp_path, program) == []


def test_the_language_server_session_reports_them_as_you_type(tmp_path: Path) -> None:
    from gpp.check.session import Session
    from gpp.platform.static import static_diagnostics

    path = (tmp_path / "agent.gpp").resolve()
    text = DOMAINS + 'action go(Robot r) {\nmapping:\n    "/{robot}/go" { }\n}\nprocedure main() { go(robot1); }\n'
    session = Session(extra_checks=static_diagnostics)
    session.open(path, text, 1)
    [result] = session.results_for(path)
    assert [(d.span.line, d.code) for d in result.diagnostics if d.is_error] == [(6, "R0007")]
    session.edit(path, [(((5, 7), (5, 12)), "r")], 2)
    [result] = session.results_for(path)
    assert [d for d in result.diagnostics if d.is_error] == []


def test_a_typed_mapping_with_placeholders_is_checked_once_against_its_type(tmp_path: Path) -> None:
    pytest.importorskip("rclpy")
    program = """action count(Robot r, number n) {
mapping:
    "/{r}/fib : test_msgs/action/Fibonacci" { ordr = n }
}
"""
    [line] = check(tmp_path, program)
    assert "agent.gpp:6:47" in line and '"/robot1/fib"' in line and "has no field `ordr` (its fields: order)" in line


def test_the_runner_fills_the_placeholders_of_the_mapped_name() -> None:
    assert placeholders_in("/{r}/arm{n}/{r}/go : pkg/action/Go") == ("r", "n")
    filled = fill_placeholders("/{r}/arm{n}/go : pkg/action/Go", {"r": Sym("robot1"), "n": 2.0})
    assert filled == "/robot1/arm2/go : pkg/action/Go"


def test_the_dummy_platform_sees_the_filled_name(tmp_path: Path) -> None:
    path = tmp_path / "agent.gpp"
    path.write_text(
        DOMAINS + 'action go(Robot r) {\nmapping:\n    "/{r}/go" { }\n}\n' + "procedure main() { go(robot2); }\n",
        encoding="utf-8",
    )
    outcome = run_program(path, RunOptions(record=True, platform="dummy"))
    assert outcome.recording is not None
    assert [e.mapped for e in outcome.recording.of(StartEvent)] == ["/robot2/go"]


# ---------------------------------------------------------------- the binding file, at attach


FUNCTION = (
    DOMAINS
    + """number exog_function level(Robot r);
procedure main() { }
"""
)


@pytest.mark.parametrize(
    ("binding", "expected"),
    [
        (
            '[exog_function.level]\ntopic = "/{robot}/battery : std_msgs/msg/Float64"\n',
            "binding file: [exog_function.level] topic: the placeholder `{robot}` is not a parameter "
            "(its parameters: r)",
        ),
        (
            '[exog_function.level]\ntopic = "/battery : std_msgs/msg/Float64"\n',
            "binding file: [exog_function.level]: `level` has parameters (r); a topic answers only a function whose "
            'parameters are placeholders of its name (such as "/{r}/battery"; use a service for other parameters)',
        ),
    ],
    ids=["unknown", "not-a-placeholder"],
)
def test_the_binding_files_placeholders_are_checked_at_attach(
    ros: Any, tmp_path: Path, binding: str, expected: str
) -> None:
    path = tmp_path / "agent.gpp"
    path.write_text(FUNCTION, encoding="utf-8")
    (tmp_path / "binding.toml").write_text(binding, encoding="utf-8")
    options = {"binding": str(tmp_path / "binding.toml")}
    outcome = run_program(path, RunOptions(platform="ros2", platform_options=options, timeout=10))
    messages = [d.message for d in outcome.diagnostics if d.severity.name.lower() == "error"]
    assert [m.replace(str(tmp_path) + "/", "") for m in messages] == [expected]


def test_a_binding_file_table_cannot_have_a_placeholder(tmp_path: Path) -> None:
    from gpp.platform.ros2.binding import Binding, BindingError

    path = tmp_path / "binding.toml"
    path.write_text('["/{r}/battery"]\nqos = { depth = 1 }\n', encoding="utf-8")
    with pytest.raises(BindingError) as raised:
        Binding.load(path)
    assert str(raised.value) == (
        f'{path}:1: ["/{{r}}/battery"]: a table of the binding file is for one ROS name and cannot have a '
        'placeholder: write a table for each name the mapping stands for, such as ["/robot1/navigate"]'
    )


# ---------------------------------------------------------------- two robots' topics and services, in one process

FLEET = """symbol domain Robot = {robot1, robot2}
string fluent said(Robot r) { initially: (r) = ""; }
exog_action heard(Robot r, string what) {
mapping:
    "/{r}/chatter : std_msgs/msg/String" { data = what }
effect:
    said(r) = what;
}
string exog_function last(Robot r);
string exog_function who(Robot r, bool on);
procedure main() {
    test(said(robot1) == "one" & said(robot2) == "two");
    test(last(robot1) == "one" & last(robot2) == "two");
    test(who(robot2, true) == "robot2 on" & who(robot1, false) == "robot1 off");
}
"""

FLEET_BINDING = """[exog_function.last]
topic = "/{r}/chatter : std_msgs/msg/String"
field = "data"

[exog_function.who]
service = "/{r}/set_bool : std_srvs/srv/SetBool"
request = { data = "on" }
field = "message"
"""


class Fleet:
    """A node of two robots' interfaces (`/robot1/...`, `/robot2/...`) on the test's context:
    make them on `node`, then `spin`."""

    def __init__(self, context: Any) -> None:
        import rclpy
        from rclpy.executors import MultiThreadedExecutor

        self.node = rclpy.create_node("fleet", context=context, start_parameter_services=False)
        self.executor = MultiThreadedExecutor(num_threads=2, context=context)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.executed: list[tuple[str, int]] = []

    def spin(self) -> None:
        self.executor.add_node(self.node)
        self.thread.start()

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=2)
        if self.thread.is_alive():
            self.thread.join(5)
        self.node.destroy_node()


@pytest.fixture
def fleet(ros: Any) -> Iterator[Fleet]:
    made = Fleet(ros.node.context)
    try:
        yield made
    finally:
        made.close()


def run_fleet(tmp_path: Path, program: str, binding: str) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(program, encoding="utf-8")
    (tmp_path / "agent.ros2.toml").write_text(binding, encoding="utf-8")
    outcome = run_program(path, RunOptions(record=True, platform="ros2", timeout=15))
    messages = [d.message for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.recording is not None
    return outcome


def test_topics_and_services_of_two_robots_answer_for_their_robot(fleet: Fleet, tmp_path: Path) -> None:
    """On /robot1/chatter and /robot2/chatter: a message fills `r` of the exogenous action
    with the robot whose topic it came on, and answers `last(r)` of that robot; `who(r, on)`
    calls the service of robot r with the other parameter in the request."""
    from ros2_servers import KEEP_ALL
    from std_msgs.msg import String
    from std_srvs.srv import SetBool

    publishers = {r: fleet.node.create_publisher(String, f"/{r}/chatter", KEEP_ALL) for r in ("robot1", "robot2")}
    for robot in publishers:

        def answer(request: Any, response: Any, robot: str = robot) -> Any:
            response.success = True
            response.message = f"{robot} {'on' if request.data else 'off'}"
            return response

        fleet.node.create_service(SetBool, f"/{robot}/set_bool", answer)
    fleet.spin()

    def publish() -> None:
        # Each topic has two subscriptions once the agent attached: the exogenous action's and
        # the function's.
        deadline = time.monotonic() + 10
        while any(p.get_subscription_count() < 2 for p in publishers.values()) and time.monotonic() < deadline:
            time.sleep(0.005)
        publishers["robot1"].publish(String(data="one"))
        publishers["robot2"].publish(String(data="two"))

    publisher = threading.Thread(target=publish)
    publisher.start()
    try:
        outcome = run_fleet(tmp_path, FLEET, FLEET_BINDING)
    finally:
        publisher.join(15)
    assert outcome.recording is not None
    assert sorted(e.action for e in outcome.recording.of(ExogEvent)) == ['heard(robot1,"one")', 'heard(robot2,"two")']


COUNT = """symbol domain Robot = {robot1, robot2}
list[number] exog_function progress(Robot r);
number fluent seen() { initially: () = 0; }
action count(Robot r, number n) {
mapping:
    "/{r}/fib : test_msgs/action/Fibonacci" { order = n }
}
procedure main() {
    start(count(robot2, 5));
    test(length(progress(robot2)) >= 2);
    seen() = length(progress(robot2));
    end(count(robot2, 5));
    count(robot1, 3);
}
bool function postcond() = seen() >= 2
"""


def test_goals_go_to_their_robots_server_and_its_feedback_answers_for_it(fleet: Fleet, tmp_path: Path) -> None:
    """`count(robot2, 5)` is a goal on /robot2/fib, whose feedback answers `progress(robot2)`
    (a feedback source with a placeholder); `count(robot1, 3)` goes to /robot1/fib."""
    from rclpy.action.server import ActionServer
    from test_msgs.action import Fibonacci

    servers = []
    for robot in ("robot1", "robot2"):

        def execute(handle: Any, robot: str = robot) -> Any:
            fleet.executed.append((robot, handle.request.order))
            for i in range(handle.request.order):
                handle.publish_feedback(Fibonacci.Feedback(sequence=list(range(i + 1))))
                time.sleep(0.05)
            handle.succeed()
            return Fibonacci.Result(sequence=[])

        servers.append(ActionServer(fleet.node, Fibonacci, f"/{robot}/fib", execute_callback=execute))
    fleet.spin()
    binding = '[exog_function.progress]\nfeedback = "/{r}/fib"\nfield = "sequence"\n'
    outcome = run_fleet(tmp_path, COUNT, binding)
    assert outcome.postcond is True
    assert fleet.executed == [("robot2", 5), ("robot1", 3)]
    starts = outcome.recording.of(StartEvent) if outcome.recording is not None else []
    assert [e.mapped for e in starts] == [
        "/robot2/fib : test_msgs/action/Fibonacci",
        "/robot1/fib : test_msgs/action/Fibonacci",
    ]


@pytest.mark.fault
def test_each_robots_name_is_checked_against_the_type_the_graph_shows_for_it(fleet: Fleet, tmp_path: Path) -> None:
    """A mapping without a type is checked once per robot: /robot2/fib is of another type, whose
    goal has no field `order`: one error, about robot2's name; the run does not start."""
    from rclpy.action.server import ActionServer
    from test_msgs.action import Fibonacci, NestedMessage

    def execute(handle: Any) -> Any:
        fleet.executed.append(("any", 0))
        handle.succeed()
        return handle.request

    servers = [
        ActionServer(fleet.node, Fibonacci, "/robot1/fib", execute_callback=execute),
        ActionServer(fleet.node, NestedMessage, "/robot2/fib", execute_callback=execute),
    ]
    fleet.spin()
    path = tmp_path / "agent.gpp"
    path.write_text(
        'symbol domain Robot = {robot1, robot2}\naction count(Robot r, number n) {\nmapping:\n    "/{r}/fib" '
        "{ order = n }\n}\nprocedure main() { count(robot1, 3); }\n",
        encoding="utf-8",
    )
    outcome = run_program(path, RunOptions(platform="ros2", timeout=15))
    errors = [d.message for d in outcome.diagnostics if d.severity.name.lower() == "error"]
    assert len(errors) == 1 and errors[0].startswith('action `count`: "/robot2/fib" (test_msgs/action/NestedMessage)')
    assert "has no field `order`" in errors[0]
    assert fleet.executed == [] and len(servers) == 2


def test_a_relative_name_is_resolved_under_the_agents_namespace_once_its_placeholders_are_filled(
    fleet: Fleet, tmp_path: Path
) -> None:
    """`"{r}/fib"` on an agent in namespace /fleet: `count(robot2, 2)` goes to
    /fleet/robot2/fib (placeholders filled first, then the name resolved as ROS resolves it)."""
    from rclpy.action.server import ActionServer
    from test_msgs.action import Fibonacci

    servers = []
    for robot in ("robot1", "robot2"):

        def execute(handle: Any, robot: str = robot) -> Any:
            fleet.executed.append((robot, handle.request.order))
            handle.succeed()
            return Fibonacci.Result(sequence=[])

        servers.append(ActionServer(fleet.node, Fibonacci, f"/fleet/{robot}/fib", execute_callback=execute))
    fleet.spin()
    path = tmp_path / "agent.gpp"
    path.write_text(
        'symbol domain Robot = {robot1, robot2}\naction count(Robot r, number n) {\nmapping:\n    "{r}/fib" '
        "{ order = n }\n}\nprocedure main() { count(robot2, 2); count(robot1, 1); }\n",
        encoding="utf-8",
    )
    outcome = run_program(path, RunOptions(platform="ros2", platform_options={"namespace": "/fleet"}, timeout=15))
    messages = [d.message for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, messages
    assert fleet.executed == [("robot2", 2), ("robot1", 1)] and len(servers) == 2
