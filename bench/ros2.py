"""Speed of the ros2 platform against real ROS 2 nodes in this process (one context shared by
the agent and the test servers, discovery off, so nothing leaves the machine).

Run: .venv/bin/python bench/ros2.py [--goals N] [--messages N] [--wakes N]

Prints
* start-up: creating the platform and attaching it to a program with an action, a service and
  an exogenous topic (node, spin thread, graph look-up, checks, subscription), best of 5;
* goal round trip: `start` of a trivial action (test_msgs Fibonacci, order 1) until its
  final update is queued (send -> accepted -> result), median and 90th percentile;
* goal round trip, typed and untyped: the same on two platforms at once, one whose mapping
  names the type and one whose type came from the graph at attach (and is kept), their goals
  alternating (the test server keeps every finished goal, which slows later goals: measured
  one after the other, the second would seem slower);
* goal round trip, typed and untyped: the same on two platforms at once, one whose mapping
  names the type and one whose type came from the graph at attach (and is kept), their goals
  alternating (the test server keeps every finished goal, which slows later goals: measured
  one after the other, the second would seem slower);
* service round trip: the same for a service (std_srvs SetBool);
* first goal, typed and untyped: on a platform just attached (a new node, the mapping checked),
  its first goal from `start` to the final update, the mapping naming its type
  (`"/fib : test_msgs/action/Fibonacci"`) or not (`"/fib"`: the type came from the graph at
  attach and is kept), median of 10 platforms;
* exogenous messages per second: a burst of std_msgs Int32 messages published into a running
  program whose exogenous action counts them, from the first publish until the program has
  applied the last one;
* kill -9 to failed: the test servers in a process of their own (a random ROS domain,
  discovery on localhost only), SIGKILL while a goal runs, until the activity's failed update
  is queued: with the robot-side profile examples/ros2/fastdds_short_lease.xml (1 s lease),
  and with `feedback_timeout = 0.5` against a server sending feedback every 0.1 s; median of
  --kills runs each (`--kill-default` also measures Fast DDS's default lease, 20 s).
* exogenous function wake-up: a program waits in `test(battery() < level)` on an exogenous
  function answered from a topic (no exogenous action); from publishing the message that makes
  it true until the program resumes (its `waiting` record with `resumed`), median and p90.
"""

from __future__ import annotations

import argparse
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "OFF"
os.environ.setdefault("ROS_LOG_DIR", tempfile.mkdtemp(prefix="gpp-ros-log-"))
sys.path.insert(0, str(ROOT / "tests" / "platform" / "ros2"))

try:
    import rclpy
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions
except ImportError:
    print("bench/ros2.py: the ROS 2 packages are not installed (pip install 'gpp[ros]'); nothing measured")
    sys.exit(0)

from ros2_servers import TestRobot  # noqa: E402

from gpp.check import check_text  # noqa: E402
from gpp.platform.base import Activity, ActivityUpdate  # noqa: E402
from gpp.platform.ros2 import Ros2Platform  # noqa: E402
from gpp.platform.ros2.binding import Binding  # noqa: E402
from gpp.run.runner import RunOptions, run_program  # noqa: E402
from gpp.runtime.compiled import CompiledProgram  # noqa: E402
from gpp.runtime.contract import program_interface  # noqa: E402
from gpp.runtime.events import TraceEvent, WaitingEvent  # noqa: E402
from gpp.runtime.state import GroundAction  # noqa: E402

FIB_TYPED = '"/fib : test_msgs/action/Fibonacci"'
PROGRAM = """
action count(number n) { mapping: "/fib : test_msgs/action/Fibonacci" { order = n } }
action switch(bool on) { mapping: "/set_bool : std_srvs/srv/SetBool" { data = on } }
number fluent received() { initially: () = 0; }
exog_action counted(number n) {
mapping:
    "/count : std_msgs/msg/Int32" { data = n }
effect:
    received() = received() + 1;
}
procedure main() { test(received() == MESSAGES); }
"""


def interface(text: str) -> object:
    checked = check_text(text, Path("bench.gpp"))
    assert not checked.errors, [d.message for d in checked.diagnostics]
    return program_interface(CompiledProgram(checked.model))


def start_up(context: Context, repeat: int = 5) -> tuple[float, float]:
    """The first start-up in this process (the first node is the slowest) and the best of
    `repeat` after it."""
    first = 0.0
    best = float("inf")
    iface = interface(PROGRAM.replace("MESSAGES", "1"))
    for i in range(repeat + 1):
        started = time.perf_counter()
        platform = Ros2Platform(context=context)
        problems = platform.attach(iface)  # type: ignore[arg-type]
        took = time.perf_counter() - started
        if i == 0:
            first = took
        else:
            best = min(best, took)
        assert not problems, problems
        platform.close()
    return first, best


def round_trips(context: Context, action: str, args: dict[str, object], n: int) -> list[float]:
    """`args`: the mapped arguments (goal or request fields) of the action's one parameter."""
    platform = Ros2Platform(context=context)
    assert not platform.attach(interface(PROGRAM.replace("MESSAGES", "1")))  # type: ignore[arg-type]
    times: list[float] = []
    try:
        for i in range(n + 5):
            ground = GroundAction(action, tuple(args.values()))  # type: ignore[arg-type]
            activity = Activity(i + 1, ground, "", args)  # type: ignore[arg-type]
            started = time.perf_counter()
            platform.start(activity)
            update = None
            while update is None:
                assert platform.queue.wait(5.0), "no answer within 5 s"
                for _, event in platform.queue.drain():
                    if isinstance(event, ActivityUpdate):
                        update = event
            assert update.status.value == "final", update
            if i >= 5:  # the first goals include discovery and client creation
                times.append(time.perf_counter() - started)
    finally:
        platform.close()
    return times


def typed_and_untyped(context: Context, n: int) -> tuple[list[float], list[float]]:
    """Goal round trips of `count` mapped with its type and without, alternating."""
    program = PROGRAM.replace("MESSAGES", "1")
    platforms = [Ros2Platform(context=context), Ros2Platform(context=context)]
    times: tuple[list[float], list[float]] = ([], [])
    try:
        for platform, text in zip(platforms, (program, program.replace(FIB_TYPED, '"/fib"')), strict=True):
            assert not platform.attach(interface(text))  # type: ignore[arg-type]
        for i in range(2 * (n + 5)):
            platform = platforms[i % 2]
            args: dict[str, object] = {"order": 1}
            activity = Activity(i + 1, GroundAction("count", (1,)), "", args)  # type: ignore[arg-type]
            started = time.perf_counter()
            platform.start(activity)
            update = None
            while update is None:
                assert platform.queue.wait(5.0), "no answer within 5 s"
                for _, event in platform.queue.drain():
                    if isinstance(event, ActivityUpdate):
                        update = event
            assert update.status.value == "final", update
            if i >= 10:  # the first goals include client creation
                times[i % 2].append(time.perf_counter() - started)
    finally:
        for platform in platforms:
            platform.close()
    return times


def first_goals(context: Context, mapped: str, repeat: int = 10) -> list[float]:
    """The first goal of each of `repeat` platforms just attached, with `count` mapped to
    `mapped` (a ROS name, with or without its type)."""
    program = PROGRAM.replace("MESSAGES", "1").replace(FIB_TYPED, f'"{mapped}"')
    iface = interface(program)
    times: list[float] = []
    for i in range(repeat):
        platform = Ros2Platform(context=context)
        try:
            assert not platform.attach(iface)  # type: ignore[arg-type]
            args: dict[str, object] = {"order": 1}
            activity = Activity(i + 1, GroundAction("count", (1,)), mapped, args)  # type: ignore[arg-type]
            started = time.perf_counter()
            platform.start(activity)
            update = None
            while update is None:
                assert platform.queue.wait(5.0), "no answer within 5 s"
                for _, event in platform.queue.drain():
                    if isinstance(event, ActivityUpdate):
                        update = event
            times.append(time.perf_counter() - started)
            assert update.status.value == "final", update
        finally:
            platform.close()
    return times


def exog_rate(robot: TestRobot, messages: int) -> float:
    from std_msgs.msg import Int32

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.gpp"
        path.write_text(PROGRAM.replace("MESSAGES", str(messages)))
        began: list[float] = []

        def publish() -> None:
            robot.wait_for_subscriber(robot.count)
            began.append(time.perf_counter())
            for i in range(messages):
                robot.count.publish(Int32(data=i))

        publisher = threading.Thread(target=publish)
        publisher.start()
        outcome = run_program(path, RunOptions(platform="ros2", timeout=120.0))
        ended = time.perf_counter()
        publisher.join(30)
        assert outcome.ok and outcome.result is not None, [d.message for d in outcome.diagnostics]
        assert outcome.result.exog_events == messages, (outcome.result.exog_events, messages)
        return messages / (ended - began[0])


def kill_to_failed(order: int, profile: bool, binding: Binding) -> float:
    """Seconds from SIGKILL of the server process (while goal `order` runs) to the failed update."""
    domain = random.randint(101, 200)
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "tests" / "platform" / "ros2")])
    if profile:
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = str(ROOT / "examples" / "ros2" / "fastdds_short_lease.xml")
    server = subprocess.Popen(
        [sys.executable, str(ROOT / "tests" / "platform" / "ros2" / "ros2_servers.py")],
        env=env,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert server.stdout is not None
    saved = {k: os.environ.get(k) for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")}
    os.environ.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    platform = Ros2Platform(binding)  # its own context: the variables are read now
    try:
        assert "ready" in server.stdout.readline()
        assert not platform.attach(interface(PROGRAM.replace("MESSAGES", "1")))  # type: ignore[arg-type]
        platform.start(Activity(1, GroundAction("count", (order,)), "", {"order": order}))
        for line in server.stdout:
            if line.startswith(f"goal {order}"):
                break
        time.sleep(0.3)
        server.send_signal(signal.SIGKILL)
        killed = time.perf_counter()
        while True:
            assert platform.queue.wait(60.0), "no failure within 60 s"
            events = [e for _, e in platform.queue.drain() if isinstance(e, ActivityUpdate)]
            if events:
                assert events[0].status.value == "failed", events[0]
                return time.perf_counter() - killed
    finally:
        platform.close()
        server.wait(10)
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def seconds(values: list[float]) -> str:
    return (
        f"median {statistics.median(values):.2f} s (min {min(values):.2f}, max {max(values):.2f}; {len(values)} kills)"
    )


WAKE_PROGRAM = """
number exog_function battery();
number fluent level() { initially: () = LEVELS; }
procedure main() {
    while (level() > 0) {
        test(battery() < level());
        level() = level() - 1;
    }
}
"""


def wake_ups(robot: TestRobot, n: int) -> list[float]:
    """Seconds from publishing the battery level that makes the waiting test true until the
    program resumes, `n` times."""
    from std_msgs.msg import Float64

    battery = robot.node.create_publisher(Float64, "/battery", 10)
    waiting = threading.Event()
    resumed = threading.Event()
    at: list[float] = []

    def listen(event: TraceEvent) -> None:
        if isinstance(event, WaitingEvent):
            if event.resumed:
                at.append(time.perf_counter())
                resumed.set()
            else:
                waiting.set()

    times: list[float] = []

    def publish() -> None:
        robot.wait_for_subscriber(battery)
        for level in range(n, 0, -1):
            assert waiting.wait(10.0), "the program does not wait"
            waiting.clear()
            resumed.clear()
            time.sleep(0.005)  # it waits, with nothing else to do
            sent = time.perf_counter()
            battery.publish(Float64(data=level - 0.5))
            assert resumed.wait(10.0), "the program did not resume"
            times.append(at[-1] - sent)

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "wake.gpp"
        path.write_text(WAKE_PROGRAM.replace("LEVELS", str(n)))
        (Path(folder) / "wake.ros2.toml").write_text(
            '[exog_function.battery]\ntopic = "/battery : std_msgs/msg/Float64"\n'
        )
        publisher = threading.Thread(target=publish)
        publisher.start()
        outcome = run_program(path, RunOptions(platform="ros2", timeout=120.0), listeners=[listen])
        publisher.join(30)
        assert outcome.ok, [d.message for d in outcome.diagnostics]
    robot.node.destroy_publisher(battery)
    return times


def ms(values: list[float]) -> str:
    ordered = sorted(values)
    p90 = ordered[int(0.9 * (len(ordered) - 1))]
    return f"median {statistics.median(ordered) * 1000:.2f} ms, p90 {p90 * 1000:.2f} ms"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--goals", type=int, default=200)
    parser.add_argument("--messages", type=int, default=5000)
    parser.add_argument("--kills", type=int, default=5)
    parser.add_argument("--kill-default", action="store_true", help="also kill -9 with Fast DDS's default lease")
    parser.add_argument("--wakes", type=int, default=100)
    args = parser.parse_args()
    context = Context()
    rclpy.init(
        context=context, args=["--ros-args", "--log-level", "error"], signal_handler_options=SignalHandlerOptions.NO
    )
    robot = TestRobot(context, result_timeout=1)  # finished goals kept 1 s: later goals are not slowed
    Ros2Platform.shared_context = context
    try:
        print("ros2 platform (in-process test servers, discovery off)")
        first, best = start_up(context)
        print(f"  start-up (create + attach)  first {first * 1000:.1f} ms, then {best * 1000:.1f} ms (best of 5)")
        goals = round_trips(context, "count", {"order": 1}, args.goals)
        print(f"  goal round trip             {ms(goals)} ({args.goals} goals)")
        typed, untyped = typed_and_untyped(context, args.goals)
        print(f"  goal round trip, typed      {ms(typed)} (alternating with the untyped one)")
        print(f"  goal round trip, untyped    {ms(untyped)} (the type from the graph at attach, kept)")
        print(f"  service round trip          {ms(round_trips(context, 'switch', {'data': True}, args.goals))}")
        typed = first_goals(context, "/fib : test_msgs/action/Fibonacci")
        print(f"  first goal, typed           {ms(typed)} (10 platforms)")
        print(f"  first goal, untyped         {ms(first_goals(context, '/fib'))} (10 platforms)")
        print(f"  exogenous messages          {exog_rate(robot, args.messages):,.0f} per s ({args.messages} messages)")
        print(f"  exog function wake-up       {ms(wake_ups(robot, args.wakes))} ({args.wakes} messages)")
    finally:
        Ros2Platform.shared_context = None
        robot.close()
        context.try_shutdown()
    print("ros2 platform (test servers in another process, killed with SIGKILL mid-goal)")
    lease = [kill_to_failed(5000, True, Binding()) for _ in range(args.kills)]
    print(f"  kill -9 -> failed, 1 s lease   {seconds(lease)}")
    feedback = Binding(feedback_timeout=0.5)
    silent = [kill_to_failed(-10, False, feedback) for _ in range(args.kills)]
    print(f"  kill -9 -> failed, feedback_timeout 0.5 s  {seconds(silent)}")
    if args.kill_default:
        default = [kill_to_failed(5000, False, Binding()) for _ in range(min(args.kills, 2))]
        print(f"  kill -9 -> failed, Fast DDS defaults  {seconds(default)}")


if __name__ == "__main__":
    main()
