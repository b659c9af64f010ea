"""The agent as a ROS node that launch files start: the ROS arguments after `--ros-args`
(namespace, node name, remapping rules, parameters, parameter files, log level) parsed by rcl,
the names resolved under the node, `main`'s parameters as ROS parameters, each usage error in
one line, and the warning about another node of the agent's name. In this process (one shared
context, discovery off) and, for the launch itself, in processes of their own started with the
command line launch_ros's `Node` builds."""

from __future__ import annotations

import json
import os
import runpy
import subprocess
import sys
import types
from pathlib import Path
from typing import Any

import pytest

from gpp.cli.common import split_ros_arguments
from tests.support.workers import ros_domain

pytest.importorskip("rclpy")

from test_ros2_processes import INTERFACES, ROOT, ros_env, start, stop
from test_ros2_processes import robot_interfaces as robot_interfaces  # a fixture

from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import UpdateEvent, WarningEvent
from gpp.runtime.executor import RunStatus

FIB = "test_msgs/action/Fibonacci"

COUNT = f"""
action count(number n) {{
mapping:
    "count : {FIB}" {{ order = n }}
}}
procedure main(number n) {{ count(n); }}
"""


@pytest.mark.parametrize(
    ("argv", "rest", "ros"),
    [
        (["run", "a.gpp"], ["run", "a.gpp"], None),
        (["run", "a.gpp", "--ros-args"], ["run", "a.gpp"], ()),
        (
            ["run", "a.gpp", "--ros-args", "-r", "__ns:=/r1", "-p", "n:=3"],
            ["run", "a.gpp"],
            ("-r", "__ns:=/r1", "-p", "n:=3"),
        ),
        (
            ["run", "a.gpp", "--ros-args", "-r", "__ns:=/r1", "--", "--trace", "t.jsonl"],
            ["run", "a.gpp", "--trace", "t.jsonl"],
            ("-r", "__ns:=/r1"),
        ),
        # launch_ros's Node: its `ros_arguments`, then its own (name, namespace, parameters, remappings)
        (
            ["run", "a.gpp", "--ros-args", "--log-level", "info", "--ros-args", "-r", "__node:=c"],
            ["run", "a.gpp"],
            ("--log-level", "info", "-r", "__node:=c"),
        ),
    ],
)
def test_the_ros_arguments_are_cut_from_the_command_line(
    argv: list[str], rest: list[str], ros: tuple[str, ...] | None
) -> None:
    assert split_ros_arguments(argv) == (rest, ros)


def run(tmp_path: Path, text: str, arguments: tuple[str, ...], timeout: float = 15.0, **options: str) -> RunOutcome:
    path = tmp_path / "agent.gpp"
    path.write_text(text, encoding="utf-8")
    return run_program(
        path,
        RunOptions(
            record=True,
            platform="ros2",
            platform_options={"server_timeout": "0.5", "discovery_timeout": "1", **options},
            platform_arguments=arguments,
            timeout=timeout,
        ),
    )


def finished(outcome: RunOutcome) -> list[UpdateEvent]:
    messages = [d.message for d in outcome.diagnostics]
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, messages
    assert outcome.recording is not None
    return outcome.recording.of(UpdateEvent)


def test_a_relative_name_under_a_namespace_reaches_the_server_its_remapping_rule_names(
    ros: Any, tmp_path: Path
) -> None:
    """`count` on node /robot1/courier is /robot1/count; the rule takes it to the test
    robot's /fib; `n` comes from a parameter file as launch_ros writes one."""
    params = tmp_path / "launch_params_x"
    entries = {"/**": {"ros__parameters": {"n": 4}}, "/robot1/other": {"ros__parameters": {"n": 9}}}
    params.write_text(json.dumps(entries), encoding="utf-8")  # JSON is YAML
    arguments = ("-r", "__node:=courier", "-r", "__ns:=/robot1", "--params-file", str(params), "-r", "count:=/fib")
    [update] = finished(run(tmp_path, COUNT, arguments))
    assert (update.action, update.status) == ("count(4)", "final")


def test_a_name_is_remapped_once_as_ros_remaps_it(ros: Any, tmp_path: Path) -> None:
    """With `count:=hop` and `hop:=/fib`, `count` is /hop (the first rule that matches, not
    on to /fib): the client is made so that rcl does not apply the rules a second time."""
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1", "-r", "count:=hop", "-r", "hop:=/fib")))
    assert update.status == "failed" and 'no action server "/hop"' in (update.reason or ""), update
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1", "-r", "count:=/fib", "-r", "hop:=/nothing")))
    assert update.status == "final", update


def test_without_the_rule_the_name_is_the_namespaced_one(ros: Any, tmp_path: Path) -> None:
    """The same program under /robot1 without the rule looks for /robot1/count (nobody
    serves it), not /count or /fib."""
    [update] = finished(run(tmp_path, COUNT, ("-r", "__ns:=/robot1", "-p", "n:=4")))
    assert update.status == "failed" and 'no action server "/robot1/count"' in (update.reason or ""), update


def test_the_namespace_option_and_ros_namespace(ros: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_NAMESPACE", "robot2")
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1")))
    assert '"/robot2/count"' in (update.reason or ""), update
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1"), namespace="/robot3"))
    assert '"/robot3/count"' in (update.reason or ""), update
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1", "-r", "__ns:=/robot4")))
    assert '"/robot4/count"' in (update.reason or ""), update


def test_a_private_name_is_under_the_node(ros: Any, tmp_path: Path) -> None:
    program = COUNT.replace('"count :', '"~/count :')
    [update] = finished(run(tmp_path, program, ("-r", "__node:=courier", "-p", "n:=1"), namespace="/robot1"))
    assert '"/robot1/courier/count"' in (update.reason or ""), update


def test_the_binding_file_names_resolve_as_the_mappings(ros: Any, tmp_path: Path) -> None:
    """A binding entry written relative is the same name as the mapping under the namespace."""
    (tmp_path / "agent.ros2.toml").write_text('["count"]\nserver_timeout = 0.2\n', encoding="utf-8")
    [update] = finished(run(tmp_path, COUNT, ("-p", "n:=1"), namespace="/robot1"))
    assert "became available within 0.2 s" in (update.reason or ""), update


def warnings(outcome: RunOutcome) -> list[str]:
    assert outcome.recording is not None
    return [w.message for w in outcome.recording.of(WarningEvent)]


@pytest.mark.fault
@pytest.mark.parametrize(("other", "warned"), [("/gpp_agent", True), ("/robot1/gpp_agent", False), ("/agent", False)])
def test_another_node_with_the_agents_name_is_warned_about(ros: Any, tmp_path: Path, other: str, warned: bool) -> None:
    import rclpy

    namespace, _, name = other.rpartition("/")
    node = rclpy.create_node(name, namespace=namespace or "/", context=ros.node.context, start_parameter_services=False)
    try:
        outcome = run(tmp_path, COUNT.replace('"count :', '"/fib :'), ("-p", "n:=2"))
    finally:
        node.destroy_node()
    finished(outcome)
    expected = [
        'platform `ros2`: another node on this ROS domain is called "/gpp_agent", as the agent\'s node is: '
        "ROS tools cannot tell the two apart"
    ]
    assert warnings(outcome) == (expected if warned else [])


# ---------------------------------------------------------------- usage errors


@pytest.fixture
def own_domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """A ROS domain of this test worker's own, discovery on localhost only (for a run whose
    node starts before its usage error)."""
    number = ros_domain()
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    monkeypatch.setenv("ROS_DOMAIN_ID", str(number))
    return number


def ros_cli_env(**extra: str) -> dict[str, str]:
    """What an in-process `gpp` needs of this environment to start a node (tests.support.cli
    gives the command these variables only): the home folder, the log folder, the domain and
    the discovery range."""
    names = ("HOME", "ROS_LOG_DIR", "ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")
    return {name: os.environ[name] for name in names if name in os.environ} | extra


@pytest.mark.fault
@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--ros-args", "-r", "navigate"], "--ros-args: couldn't parse remap rule: '-r navigate'"),
        (["--ros-args", "-r", "__ns:=robot1"], "--ros-args: couldn't parse remap rule: '-r __ns:=robot1'"),
        (["--ros-args", "-p", "n"], "--ros-args: couldn't parse parameter override rule: '-p n'"),
        (
            ["--ros-args", "--params-file", "missing.yaml"],
            "--ros-args: couldn't parse params file: '--params-file missing.yaml'",
        ),
        (["--ros-args", "--log-level", "loud"], "--ros-args: couldn't parse log level: '--log-level loud'"),
        (["--ros-args", "--frobnicate"], "--ros-args: unknown ROS arguments: --frobnicate"),
        (
            ["--ros-args", "-p", "nn:=3"],
            "the ROS parameter `nn`: `main` has no parameter `nn`; did you mean `n`? (it takes n)",
        ),
        (["--ros-args", "-p", "n:=three"], 'the ROS parameter `n`: expected a number, got "three"'),
        (
            ["--ros-args"],
            "`main(number n)` needs a value for `n`: give it with --arg n=VALUE or with -p n:=VALUE after --ros-args",
        ),
        (
            ["--arg", "n=3", "--ros-args", "-p", "n:=3"],
            "`n` of `main` is given twice: by --arg n=... and by the ROS parameter `n`",
        ),
        (
            ["-o", "node_name=a", "--ros-args", "-r", "__node:=b"],
            "the node name is given twice: by -o node_name=a and by `-r __node:=b` after --ros-args",
        ),
        (
            ["-o", "namespace=/a", "--ros-args", "-r", "__ns:=/b"],
            "the namespace is given twice: by -o namespace=/a and by `-r __ns:=/b` after --ros-args",
        ),
        (
            ["-o", "log_level=info", "--ros-args", "--log-level", "debug"],
            "the log level is given twice: by -o log_level=info and by `--log-level debug` after --ros-args",
        ),
        (
            ["--arg", "n=1", "-o", "namespace=robot1"],
            'option `namespace` of platform `ros2` must be an absolute ROS namespace (such as "/robot1": letters, '
            'digits and `_` between `/`), not "robot1"',
        ),
    ],
)
def test_each_usage_error_is_one_line(tmp_path: Path, own_domain: int, arguments: list[str], message: str) -> None:
    from tests.support.cli import run as gpp

    program = tmp_path / "agent.gpp"
    program.write_text(COUNT, encoding="utf-8")
    result = gpp("run", str(program), "--platform", "ros2", "-q", *arguments, cwd=tmp_path, env=ros_cli_env())
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip().splitlines() == [f"error: {message}"], result.stderr


def test_ros_arguments_off_ros2_and_outside_gpp_run_are_usage_errors(tmp_path: Path) -> None:
    from tests.support.cli import run as gpp

    program = tmp_path / "agent.gpp"
    program.write_text("procedure main() { }\n", encoding="utf-8")
    result = gpp("run", str(program), "--ros-args", "-r", "__ns:=/r1")
    assert (result.returncode, result.stderr.strip()) == (
        2,
        "error: --ros-args: ROS arguments are for platform ros2, and this run is on `dummy`",
    )
    result = gpp("check", str(program), "--ros-args")
    assert (result.returncode, result.stderr.strip()) == (
        2,
        "error: --ros-args: only `gpp run` (on platform ros2) takes ROS arguments",
    )


def test_a_bad_ros_namespace_variable_is_a_usage_error(tmp_path: Path, own_domain: int) -> None:
    from tests.support.cli import run as gpp

    program = tmp_path / "agent.gpp"
    program.write_text(COUNT, encoding="utf-8")
    result = gpp("run", str(program), "--platform", "ros2", "--arg", "n=1", env=ros_cli_env(ROS_NAMESPACE="/robot-1"))
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip().splitlines() == [
        'error: $ROS_NAMESPACE must be a ROS namespace (such as "/robot1": letters, digits and `_` between `/`), '
        'not "/robot-1"'
    ]


# ---------------------------------------------------------------- launched as launch_ros launches a node


def example_nodes(monkeypatch: pytest.MonkeyPatch) -> dict[str, dict[str, Any]]:
    """The `Node(...)`s of examples/ros2/agent.launch.py by name, as their keyword arguments
    (read with stand-ins for launch and launch_ros, which the pip wheels do not have)."""
    launch = types.ModuleType("launch")
    launch.LaunchDescription = list  # type: ignore[attr-defined]
    actions = types.ModuleType("launch_ros.actions")
    actions.Node = dict  # type: ignore[attr-defined]
    launch_ros = types.ModuleType("launch_ros")
    launch_ros.actions = actions  # type: ignore[attr-defined]
    for name, module in (("launch", launch), ("launch_ros", launch_ros), ("launch_ros.actions", actions)):
        monkeypatch.setitem(sys.modules, name, module)
    found = runpy.run_path(str(ROOT / "examples" / "ros2" / "agent.launch.py"))
    return {node["name"]: node for node in found["generate_launch_description"]()}


def launch_command(node: dict[str, Any], params_dir: Path) -> list[str]:
    """The command line launch_ros's `Node` starts for these keyword arguments
    (launch_ros/actions/node.py): the executable and its arguments, `--ros-args`, the name and
    namespace rules, a parameter file it writes for each dictionary (`/**: ros__parameters:`),
    the remapping rules."""
    command = [node["executable"], *node.get("arguments", []), "--ros-args"]
    command += ["-r", f"__node:={node['name']}", "-r", f"__ns:={node['namespace']}"]
    for i, parameters in enumerate(node.get("parameters", [])):
        params = params_dir / f"launch_params_{node['name']}_{i}"
        params.write_text(json.dumps({"/**": {"ros__parameters": parameters}}), encoding="utf-8")  # JSON is YAML
        command += ["--params-file", str(params)]
    for source, target in node.get("remappings", []):
        command += ["-r", f"{source}:={target}"]
    return command


def test_the_example_launch_file_starts_gpp_as_the_docs_say(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    agent = example_nodes(monkeypatch)["courier"]
    params = str(tmp_path / "launch_params_courier_0")
    assert launch_command(agent, tmp_path) == [
        "gpp", "run", str(ROOT / "examples" / "ros2" / "courier.gpp"), "--platform", "ros2",
        "--ros-args", "-r", "__node:=courier", "-r", "__ns:=/robot1", "--params-file", params,
        "-r", "navigate:=navigate_to_pose",
    ]  # fmt: skip
    assert json.loads(Path(params).read_text()) == {"/**": {"ros__parameters": {"x": 3.0, "y": 4.0}}}


# The executables of the example's nodes, here.
EXECUTABLES = {"gpp": [sys.executable, "-m", "gpp"], "python3": [sys.executable]}


@pytest.mark.slow
def test_the_example_launch_file_drives_the_robot_in_its_namespace(
    robot_interfaces: list[str], own_domain: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The nodes of examples/ros2/agent.launch.py started as launch_ros starts them: the robot
    and the agent under /robot1. `navigate` is /robot1/navigate, remapped to the robot's
    /robot1/navigate_to_pose (no server of /navigate, /navigate_to_pose or /robot1/navigate
    exists); x and y come from the parameter file. Off the map (x = 50) the robot's abort
    names the goal it got."""
    nodes = example_nodes(monkeypatch)
    env = ros_env(own_domain, robot_interfaces)
    env["LD_LIBRARY_PATH"] = os.pathsep.join([str(INTERFACES / "lib"), env.get("LD_LIBRARY_PATH", "")])
    robot_command = launch_command(nodes["robot"], tmp_path)
    robot = start([*EXECUTABLES[robot_command[0]], *robot_command[1:]], env, "robot ready")
    try:
        results = []
        nodes_named = []
        for x in (3.0, 50.0):
            trace = tmp_path / f"trace{x:g}.jsonl"
            agent_node = nodes["courier"] | {"parameters": [{"x": x, "y": 4.0}]}
            command = launch_command(agent_node, tmp_path)
            command = [*EXECUTABLES[command[0]], *command[1:], "--", "--trace", str(trace)]
            agent = subprocess.run(command, env=env, capture_output=True, text=True, timeout=120)
            assert agent.returncode == 0, agent.stdout[-3000:] + agent.stderr[-3000:]
            records = [json.loads(line) for line in trace.read_text().splitlines()]
            results.append([(r["action"], r["status"], r.get("reason")) for r in records if r["event"] == "update"])
            nodes_named.append(records[0].get("node"))
    finally:
        stop(robot)
    assert nodes_named == ["/robot1/courier", "/robot1/courier"]  # the trace's header names the node
    assert results == [
        [("navigate(3.0,4.0)", "final", None)],
        [
            (
                "navigate(50.0,4.0)",
                "failed",
                'the action server "/robot1/navigate_to_pose" aborted the goal (its result: '
                '{error_code = 9004, error_msg = "goal (50, 4) is outside the map"})',
            )
        ],
    ]


WAITS = """
bool fluent seen() { initially: () = false; }
exog_action ev(string s) {
mapping:
    "ev : std_msgs/msg/String" { data = s }
effect:
    seen() = true;
}
procedure main() { test(seen()); }
"""


@pytest.mark.fault
@pytest.mark.slow
def test_two_agents_of_one_name_on_one_domain_both_warn(own_domain: int, tmp_path: Path) -> None:
    """Two agent processes, both /gpp_agent, each waiting 8 s (discovery across processes can
    take 3 s): each warns, once it sees the other; then agents of two names, which do not."""
    program = tmp_path / "agent.gpp"
    program.write_text(WAITS, encoding="utf-8")
    env = ros_env(own_domain)

    def warned(*extra: str) -> list[list[str]]:
        def command(n: int) -> list[str]:
            trace = ["--timeout", "8", "--trace", str(tmp_path / f"trace{n}.jsonl")]
            gpp = [sys.executable, "-m", "gpp", "run", str(program), "--platform", "ros2", "-q"]
            return [*gpp, *trace, *(extra if n == 2 else ())]

        first = subprocess.Popen(command(1), env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            second = subprocess.run(command(2), env=env, capture_output=True, text=True, timeout=60)
            _, first_err = first.communicate(timeout=60)
        finally:
            if first.poll() is None:
                first.kill()
                first.communicate(timeout=10)
        # Both end at their timeout (exit 1), waiting for an event nobody sends.
        assert (first.returncode, second.returncode) == (1, 1), first_err + second.stderr
        found = []
        for n in (1, 2):
            records = [json.loads(line) for line in (tmp_path / f"trace{n}.jsonl").read_text().splitlines()]
            found.append([r["message"] for r in records if r["event"] == "warning"])
        return found

    message = (
        'platform `ros2`: another node on this ROS domain is called "/gpp_agent", as the agent\'s node is: '
        "ROS tools cannot tell the two apart"
    )
    assert warned() == [[message], [message]]
    assert warned("--ros-args", "-r", "__node:=second_agent") == [[], []]
