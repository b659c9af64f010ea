"""The ros2 platform across processes (a random ROS domain of each test worker's own, discovery
on localhost only): a server that dies during a goal, Ctrl-C and SIGTERM of a running agent
(goals cancelled, no abort at exit), and the papers' blocksworld robot (examples/ros2) against
`--platform sim`."""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import sysconfig
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.workers import ros_domain

pytest.importorskip("rclpy")

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import PlanEvent, SenseEvent, UpdateEvent

ROOT = Path(__file__).resolve().parents[3]
HERE = Path(__file__).resolve().parent
INTERFACES = ROOT / "build" / "ros-interfaces"

# Processes that start ROS 2 nodes, and a CMake build: `make quick` leaves them out.
pytestmark = pytest.mark.slow

COUNT = """
action count(number n) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = n }
}
"""


def ros_env(domain: int, extra_path: list[str] | None = None) -> dict[str, str]:
    env = dict(os.environ)
    env["ROS_DOMAIN_ID"] = str(domain)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    paths = [*(extra_path or []), str(ROOT), str(HERE)]
    if env.get("PYTHONPATH"):
        paths.append(env["PYTHONPATH"])
    env["PYTHONPATH"] = os.pathsep.join(paths)
    return env


def start(command: list[str], env: dict[str, str], ready: str, timeout: float = 60.0) -> subprocess.Popen[str]:
    return wait_ready(spawn(command, env), ready, timeout)


def spawn(command: list[str], env: dict[str, str]) -> subprocess.Popen[str]:
    return subprocess.Popen(
        command, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def wait_ready(process: subprocess.Popen[str], ready: str, timeout: float = 60.0) -> subprocess.Popen[str]:
    """The process, once it wrote a line with `ready` (it fails the test if it did not within
    `timeout` s)."""
    command = process.args
    assert process.stdout is not None and isinstance(command, list)
    deadline = time.monotonic() + timeout
    line = ""
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if ready in line or process.poll() is not None:
            break
    if ready not in line:
        process.kill()
        _, err = process.communicate(timeout=10)
        pytest.fail(f"{command[-1]} did not start: {err[-2000:]}")
    return process


def stop(process: subprocess.Popen[str]) -> str:
    """Stop the process (SIGTERM, then SIGKILL after 10 s); what it wrote to stdout since last
    read (also when it had ended already: its output is still in the pipe)."""
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
    try:
        out, _ = process.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        process.kill()
        out, _ = process.communicate(timeout=10)
    return out or ""


@pytest.fixture
def domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """A random ROS domain no other test worker uses, discovery on localhost only (also for the
    agent in this process)."""
    number = ros_domain()
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    monkeypatch.setenv("ROS_DOMAIN_ID", str(number))
    return number


@pytest.fixture
def servers(domain: int) -> Iterator[subprocess.Popen[str]]:
    process = start([sys.executable, str(HERE / "ros2_servers.py")], ros_env(domain), "ready")
    try:
        yield process
    finally:
        stop(process)


def trace_events(path: Path) -> list[dict[str, Any]]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def kill_during_goal(
    servers: subprocess.Popen[str], tmp_path: Path, order: int, sig: signal.Signals, binding: str = ""
) -> tuple[UpdateEvent, float]:
    """Run `count(order)` against the server process, send it `sig` once the goal runs (and a
    little after); the activity's update and the seconds from the signal to the end of the run."""
    import threading

    program = tmp_path / "agent.gpp"
    program.write_text(COUNT + f"procedure main() {{ count({order}); }}\n")
    (tmp_path / "agent.ros2.toml").write_text(binding)
    killed: list[float] = []

    def kill_soon() -> None:
        # Once the goal runs (discovery can take seconds on a busy machine), and a little after.
        assert servers.stdout is not None
        for line in servers.stdout:
            if line.startswith(f"goal {order}"):
                break
        time.sleep(0.5)
        killed.append(time.monotonic())
        servers.send_signal(sig)

    threading.Thread(target=kill_soon, daemon=True).start()
    outcome = run_program(program, RunOptions(record=True, platform="ros2", timeout=60.0))
    assert outcome.recording is not None and killed
    [update] = outcome.recording.of(UpdateEvent)
    return update, time.monotonic() - killed[0]


@pytest.mark.fault
def test_a_server_process_that_exits_during_a_goal_fails_it(servers: subprocess.Popen[str], tmp_path: Path) -> None:
    update, took = kill_during_goal(servers, tmp_path, 5000, signal.SIGTERM)
    assert update.status == "failed" and "went away" in (update.reason or ""), update
    assert took < 10


# Fast DDS keeps a participant killed outright for its lease, 20 s by default: the failures
# below must come well before (bench/ros2.py measures how long they take).
DEFAULT_LEASE = 20.0


@pytest.fixture
def short_lease_servers(domain: int) -> Iterator[subprocess.Popen[str]]:
    """The test servers with the robot-side profile of examples/ros2 (a 1 s lease)."""
    env = ros_env(domain)
    env["FASTDDS_DEFAULT_PROFILES_FILE"] = str(ROOT / "examples" / "ros2" / "fastdds_short_lease.xml")
    process = start([sys.executable, str(HERE / "ros2_servers.py")], env, "ready")
    try:
        yield process
    finally:
        stop(process)


@pytest.mark.fault
def test_a_server_process_killed_during_a_goal_fails_it_within_its_lease(
    short_lease_servers: subprocess.Popen[str], tmp_path: Path
) -> None:
    update, took = kill_during_goal(short_lease_servers, tmp_path, 5000, signal.SIGKILL)
    assert update.status == "failed" and 'the action server "/fib" went away' in (update.reason or ""), update
    assert took < DEFAULT_LEASE / 2


@pytest.mark.fault
def test_a_server_process_killed_during_a_goal_fails_it_by_its_feedback_timeout(
    servers: subprocess.Popen[str], tmp_path: Path
) -> None:
    """No profile on the robot's side: the goal's feedback stops (-10 sends it every 0.1 s)."""
    update, took = kill_during_goal(servers, tmp_path, -10, signal.SIGKILL, '["/fib"]\nfeedback_timeout = 0.5\n')
    assert update.status == "failed" and "sent no feedback for 0.5 s" in (update.reason or ""), update
    assert took < DEFAULT_LEASE / 2


def test_the_first_message_reaches_a_subscriber_process_that_was_up_before_the_run(
    servers: subprocess.Popen[str], tmp_path: Path
) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text(
        'action say(string s) { mapping: "/said : std_msgs/msg/String" { data = s } }\n'
        'procedure main() { say("first"); }\n'
    )
    outcome = run_program(program, RunOptions(record=True, platform="ros2", timeout=30.0))
    assert outcome.ok and outcome.recording is not None
    assert not [e for e in outcome.recording.records if e.EVENT == "notice"]
    assert "heard first" in stop(servers).splitlines()


@pytest.mark.fault
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupted_agent_cancels_its_goals_and_exits_cleanly(
    servers: subprocess.Popen[str], domain: int, tmp_path: Path, sig: signal.Signals
) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text(COUNT + "procedure main() { count(5000); }\n")
    trace = tmp_path / "trace.jsonl"
    agent = subprocess.Popen(
        [sys.executable, "-m", "gpp", "run", str(program), "--platform", "ros2", "--trace", str(trace)],
        env=ros_env(domain),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not any(e.get("event") == "start" for e in trace_events(trace)) and time.monotonic() < deadline:
            assert agent.poll() is None, agent.communicate(timeout=10)
            time.sleep(0.05)
        time.sleep(0.5)  # the goal is on the server
        agent.send_signal(sig)
        _, err = agent.communicate(timeout=30)
    finally:
        if agent.poll() is None:
            agent.kill()
            agent.communicate(timeout=10)
    assert agent.returncode == 128 + sig, err  # SIGTERM exits 143, not 130 as Ctrl-C does
    assert err.splitlines()[-1] == ("terminated (SIGTERM)" if sig == signal.SIGTERM else "interrupted"), err
    assert "terminate called" not in err and "Traceback" not in err, err
    ends = [e for e in trace_events(trace) if e.get("event") == "update"]
    assert [(e["action"], e["status"]) for e in ends] == [("count(5000)", "cancelled")], err


# ---------------------------------------------------------------- the papers' robot


def _toolchain_missing() -> str | None:
    for tool in ("cmake", "make"):
        if shutil.which(tool) is None:
            return f"`{tool}` is not installed"
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        return "no C compiler (cc or gcc)"
    if shutil.which("c++") is None and shutil.which("g++") is None:
        return "no C++ compiler (c++ or g++)"
    if not (Path(sysconfig.get_paths()["include"]) / "Python.h").exists():
        return "the Python headers (Python.h) are not installed"
    return None


@pytest.fixture(scope="module")
def robot_interfaces() -> list[str]:
    """The robot's interface package, built with CMake from the wheels (`make ros-interfaces`,
    kept in build/ between runs); skipped where the build tools are missing."""
    missing = _toolchain_missing()
    if missing is not None:
        pytest.skip(f"building the robot's ROS 2 interfaces needs cmake, a compiler and Python.h: {missing}")
    base = getattr(sys, "_base_executable", sys.executable)
    (ROOT / "build").mkdir(exist_ok=True)
    # One build at a time: parallel test workers (-n) wait for the first, then find it built.
    with open(ROOT / "build" / ".ros-interfaces.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        result = subprocess.run(
            ["make", "-s", "ros-interfaces", f"PYTHON={base}"], cwd=ROOT, capture_output=True, text=True, timeout=1200
        )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    [site] = list(INTERFACES.glob("lib/python*/site-packages"))
    return [str(site)]


def test_the_robot_interfaces_build_without_colcon(robot_interfaces: list[str]) -> None:
    env = ros_env(0, robot_interfaces)
    env["LD_LIBRARY_PATH"] = os.pathsep.join([str(INTERFACES / "lib"), env.get("LD_LIBRARY_PATH", "")])
    script = (
        "from gpp_robot_interfaces.action import Stack, GetBlockPose, NavigateToFrame, GripperHome\n"
        "from gpp_robot_interfaces.msg import Battery\n"
        "print(sorted(Stack.Goal.get_fields_and_field_types()), list(GetBlockPose.Result.get_fields_and_field_types()))"
    )
    result = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "['block', 'location'] ['location']"


def run_on_the_example_robot(
    program: Path,
    trace: Path,
    domain: int,
    robot_interfaces: list[str],
    timeout: float,
    namespaces: tuple[str, ...] = (),
    speed: float = 0,
) -> subprocess.CompletedProcess[str]:
    """`gpp run program --platform ros2 --trace trace` against the example robot
    (examples/ros2/robot.py, at `--speed`) in a process of its own, stopped afterwards; with
    `namespaces`, one robot process in each (`--ros-args -r __ns:=NAMESPACE`)."""
    env = ros_env(domain, robot_interfaces)
    env["LD_LIBRARY_PATH"] = os.pathsep.join([str(INTERFACES / "lib"), env.get("LD_LIBRARY_PATH", "")])
    robot = [sys.executable, str(ROOT / "examples" / "ros2" / "robot.py"), "--speed", str(speed)]
    # Started side by side: each takes a second or so to import rclpy and the sim.
    spawned = [spawn(robot + (["--ros-args", "-r", f"__ns:={ns}"] if ns else []), env) for ns in namespaces or ("",)]
    try:
        for process in spawned:
            wait_ready(process, "robot ready")
        return subprocess.run(
            [sys.executable, "-m", "gpp", "run", str(program), "--platform", "ros2", "--trace", str(trace)],
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    finally:
        for process in spawned:
            stop(process)


def test_blocksworld_on_the_ros2_robot_as_on_the_sim(robot_interfaces: list[str], domain: int, tmp_path: Path) -> None:
    example = ROOT / "examples" / "blocksworld.gpp"
    on_sim = run_program(example, RunOptions(record=True, platform="sim"))
    assert on_sim.ok and on_sim.recording is not None
    trace = tmp_path / "trace.jsonl"
    agent = run_on_the_example_robot(example, trace, domain, robot_interfaces, timeout=300)
    assert agent.returncode == 0, agent.stdout[-3000:] + agent.stderr[-3000:]
    events = trace_events(trace)
    plans = [tuple(e["policy"]) for e in events if e.get("event") == "plan"]
    sensed = {e["fluent"]: e["value"] for e in events if e.get("event") == "sense"}
    assert plans[0] == on_sim.recording.of(PlanEvent)[0].policy
    assert sensed == {s.fluent: s.value for s in on_sim.recording.of(SenseEvent)}
    finals = [(e["action"], e["status"]) for e in events if e.get("event") == "update"]
    assert finals == [(u.action, u.status) for u in on_sim.recording.of(UpdateEvent)]


NAV2 = """
compound NavResult { number error_code, string error_msg }
NavResult exog_function nav_result(string name);
symbol domain outcome = {arrived, outside_map, failed}
outcome fluent how() { initially: () = null; }
outcome fluent then() { initially: () = null; }

action navigate(number x, number y) {
mapping:
    "/navigate_to_pose" { pose__header__frame_id = "map", pose__pose__position__x = x,
                          pose__pose__position__y = y }
}

procedure go(number x, number y) {
    during (navigate(x, y)) { how() = arrived; } on_fail {
        if (nav_result("/navigate_to_pose").error_code == 9004) how() = outside_map;
        else how() = failed;
    }
}

procedure main() { go(50, 0); then() = how(); go(3, 4); }
bool function postcond() = then() == outside_map & how() == arrived
"""


@pytest.mark.fault
def test_a_nav2_style_error_code_decides_what_the_program_does(
    robot_interfaces: list[str], domain: int, tmp_path: Path
) -> None:
    """The example robot's Nav2-shaped /navigate_to_pose aborts a goal outside its map with
    error_code 9004 (GOAL_OUTSIDE_MAP); `on_fail` reads it."""
    program = tmp_path / "agent.gpp"
    program.write_text(NAV2)
    trace = tmp_path / "trace.jsonl"
    agent = run_on_the_example_robot(program, trace, domain, robot_interfaces, timeout=120)
    assert agent.returncode == 0, agent.stdout[-3000:] + agent.stderr[-3000:]
    assert "postcond()         holds" in agent.stdout, agent.stdout
    failed = [e for e in trace_events(trace) if e.get("event") == "update" and e["status"] == "failed"]
    assert [e["reason"] for e in failed] == [
        'the action server "/navigate_to_pose" aborted the goal (its result: '
        '{error_code = 9004, error_msg = "goal (50, 0) is outside the map"})'
    ]


def test_two_robots_from_one_declaration_of_each_action(
    robot_interfaces: list[str], domain: int, tmp_path: Path
) -> None:
    """examples/ros2/two_robots.gpp against the example robot started twice, under /robot1
    and /robot2 (at 20 times real time, so that a stack takes a moment): each goal goes to
    its robot's server by the placeholder `{r}`, both robots work at once, and the battery
    messages of each robot's topic fill `r` of the exogenous action and answer
    `battery_level(r)` (each robot's first `test(battery_level(r) > 20)` waits for it)."""
    trace = tmp_path / "trace.jsonl"
    example = ROOT / "examples" / "ros2" / "two_robots.gpp"
    agent = run_on_the_example_robot(
        example, trace, domain, robot_interfaces, timeout=120, namespaces=("/robot1", "/robot2"), speed=20
    )
    assert agent.returncode == 0, agent.stdout[-3000:] + agent.stderr[-3000:]
    assert "postcond()         holds" in agent.stdout, agent.stdout
    events = trace_events(trace)
    starts = [(e["action"], e["mapped"]) for e in events if e.get("event") == "start"]
    for robot in ("robot1", "robot2"):
        assert (f"stack({robot},a,t3)", f"/{robot}/stack") in starts
        assert (f"get_block_pose({robot},a)", f"/{robot}/get_block_pose") in starts
    assert all(mapped.startswith(f"/{action.split('(')[1].split(',')[0]}/") for action, mapped in starts)
    # At once: each robot's stack starts before the other robot's stack ends.
    order = [(e["event"], e["action"]) for e in events if e.get("event") in ("start", "update")]
    for robot, other in (("robot1", "robot2"), ("robot2", "robot1")):
        assert order.index(("start", f"stack({robot},a,t3)")) < order.index(("update", f"stack({other},a,t3)"))
    batteries = [e["action"] for e in events if e.get("event") == "exog"]
    assert {b.split(",")[0] for b in batteries} == {"battery(robot1", "battery(robot2"}
    sensed = {e["fluent"]: e["value"] for e in events if e.get("event") == "sense"}
    assert sensed == {"loc(robot1,a)": {"symbol": "t3"}, "loc(robot2,a)": {"symbol": "t3"}}
