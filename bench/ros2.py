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

Across processes (`--part across`, also in the default `all`; a random ROS domain, discovery
on localhost only; `--load N` keeps N other processes busy meanwhile, as a test run does):
* exogenous function wake-up with the publisher in another process (tests/platform/ros2/
  ros2_publisher.py): it prints the time.monotonic() just before each publish; on Linux that
  is the system-wide CLOCK_MONOTONIC, the clock this process reads too (checked: each send
  time lies between this process writing the command and reading the answer);
* first goal, typed and untyped, with the test servers in another process: a platform created
  and attached (untyped: the attach waits for discovery to show "/fib"), then its first goal
  from `start` to the final update (typed: it includes discovering the server);
* discovery: how long until the agent's graph shows the servers of another process, (a) for
  an agent that starts while they run (what `discovery_timeout` bounds at attach), from its
  node being up, and (b) for servers that start while the agent runs, from their `ready`
  (their own monotonic time); median, p90 and max over --discoveries runs.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
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
from gpp.platform.ros2.bridge import Bridge  # noqa: E402
from gpp.platform.ros2.checks import DISCOVERY_POLL, snapshot  # noqa: E402
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


def goal(platform: Ros2Platform, activity: Activity) -> ActivityUpdate:
    """Start `activity` and wait (at most 5 s between events) for its update."""
    platform.start(activity)
    while True:
        assert platform.queue.wait(5.0), "no answer within 5 s"
        for _, event in platform.queue.drain():
            if isinstance(event, ActivityUpdate):
                return event


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
            update = goal(platform, activity)
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
            update = goal(platform, activity)
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
            update = goal(platform, activity)
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
    server = spawn("ros2_servers.py", domain, profile)
    assert server.stdout is not None
    platform = Ros2Platform(binding)
    with across(domain), contextlib.ExitStack() as closing:  # its own context, made at attach
        closing.callback(server.wait, 10)
        closing.callback(platform.close)
        ready(server)
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


# ---------------------------------------------------------------- across processes

HELPERS = ROOT / "tests" / "platform" / "ros2"


@contextlib.contextmanager
def across(domain: int) -> Iterator[None]:
    """ROS traffic of the platforms created meanwhile in this process: domain `domain`,
    discovery on localhost only (rclpy reads the variables when a context is initialised)."""
    keys = ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")
    saved = {k: os.environ.get(k) for k in keys}
    os.environ.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def spawn(script: str, domain: int, short_lease: bool = False) -> subprocess.Popen[str]:
    """tests/platform/ros2/SCRIPT in a process of its own, in `domain`, on localhost."""
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(HELPERS)])
    if short_lease:
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = str(ROOT / "examples" / "ros2" / "fastdds_short_lease.xml")
    return subprocess.Popen(
        [sys.executable, str(HELPERS / script)], env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )


def ready(process: subprocess.Popen[str]) -> float:
    """Wait for the process's `ready` line; the time.monotonic() it gives (or now)."""
    assert process.stdout is not None
    line = process.stdout.readline()
    assert line.startswith("ready"), f"the process did not start: {line!r}"
    words = line.split()
    return float(words[1]) if len(words) > 1 else time.monotonic()


def finish(process: subprocess.Popen[str]) -> None:
    if process.stdin is not None:
        process.stdin.close()
    try:
        process.wait(10)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(10)


def one_clock() -> None:
    """Times of other processes are compared with this one's: the system-wide monotonic clock."""
    implementation = time.get_clock_info("monotonic").implementation
    assert implementation == "clock_gettime(CLOCK_MONOTONIC)", f"not one clock for all processes: {implementation}"


class Driven:
    """ros2_publisher.py: `ask` sends a command, returns its answer and the times (this
    process's monotonic clock) just before writing it and just after reading the answer."""

    def __init__(self, domain: int) -> None:
        self.process = spawn("ros2_publisher.py", domain)
        ready(self.process)

    def ask(self, command: str) -> tuple[str, float, float]:
        assert self.process.stdin is not None and self.process.stdout is not None
        before = time.monotonic()
        self.process.stdin.write(command + "\n")
        self.process.stdin.flush()
        answer = self.process.stdout.readline().strip()
        return answer, before, time.monotonic()


def wake_ups_across(n: int) -> list[float]:
    """Seconds from the publisher process publishing the battery level that makes the waiting
    test true (its clock) until the program in this process resumes (this one's), `n` times."""
    one_clock()
    domain = random.randint(101, 200)
    publisher = Driven(domain)
    waiting = threading.Event()
    resumed = threading.Event()
    at: list[float] = []
    times: list[float] = []

    def listen(event: TraceEvent) -> None:
        if isinstance(event, WaitingEvent):
            if event.resumed:
                at.append(time.monotonic())
                resumed.set()
            else:
                waiting.set()

    def publish() -> None:
        assert publisher.ask("advertise /battery float64 keep_all")[0] == "advertised"
        assert publisher.ask("match /battery")[0] == "matched"
        for level in range(n, 0, -1):
            assert waiting.wait(30.0), "the program does not wait"
            waiting.clear()
            resumed.clear()
            time.sleep(0.005)  # it waits, with nothing else to do
            answer, before, after = publisher.ask(f"send /battery {level - 0.5}")
            sent = float(answer.split()[1])
            assert before <= sent <= after, (before, sent, after)  # one clock
            assert resumed.wait(30.0), "the program did not resume"
            times.append(at[-1] - sent)

    try:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "wake.gpp"
            path.write_text(WAKE_PROGRAM.replace("LEVELS", str(n)))
            (Path(folder) / "wake.ros2.toml").write_text(
                '[exog_function.battery]\ntopic = "/battery : std_msgs/msg/Float64"\n'
            )
            driver = threading.Thread(target=publish)
            driver.start()
            with across(domain):
                outcome = run_program(path, RunOptions(platform="ros2", timeout=300.0), listeners=[listen])
            driver.join(60)
            assert outcome.ok, [d.message for d in outcome.diagnostics]
    finally:
        finish(publisher.process)
    return times


def first_goals_across(mapped: str, repeat: int) -> tuple[list[float], list[float]]:
    """With the test servers in another process: for each of `repeat` platforms, (create +
    attach) and its first goal (`start` to the final update), `count` mapped to `mapped`."""
    domain = random.randint(101, 200)
    server = spawn("ros2_servers.py", domain)
    program = PROGRAM.replace("MESSAGES", "1").replace(FIB_TYPED, f'"{mapped}"')
    iface = interface(program)
    attaches: list[float] = []
    goals: list[float] = []
    try:
        ready(server)
        for i in range(repeat):
            began = time.perf_counter()
            platform = Ros2Platform(Binding(discovery_timeout=30.0))
            try:
                with across(domain):  # its own context, made at attach
                    assert not platform.attach(iface)  # type: ignore[arg-type]
                attaches.append(time.perf_counter() - began)
                activity = Activity(i + 1, GroundAction("count", (1,)), mapped, {"order": 1})  # type: ignore[arg-type]
                started = time.perf_counter()
                platform.start(activity)
                update = None
                while update is None:
                    assert platform.queue.wait(30.0), "no answer within 30 s"
                    for _, event in platform.queue.drain():
                        if isinstance(event, ActivityUpdate):
                            update = event
                if update.status.value == "final":
                    goals.append(time.perf_counter() - started)
                else:
                    print(f"    a first goal failed: {update.reason}")
            finally:
                platform.close()
    finally:
        finish(server)
    return attaches, goals


def shows_servers(bridge: Bridge, deadline: float) -> float:
    """Poll the agent's graph (as the attach does) until it shows the test servers' "/fib" and
    "/basic"; the time.monotonic() then."""
    while time.monotonic() < deadline:
        known, _ = bridge.call(snapshot, bridge, timeout=5.0)
        if "/fib" in known and "/basic" in known:
            return time.monotonic()
        time.sleep(DISCOVERY_POLL)
    raise TimeoutError("the agent's graph did not show the servers")


def discovery_across(runs: int) -> tuple[list[float], list[float]]:
    """(a) an agent node started while the servers run: from its node being up until its graph
    shows them; (b) servers started while an agent runs: from their `ready` until it does."""
    domain = random.randint(101, 200)
    joining: list[float] = []
    server = spawn("ros2_servers.py", domain)
    try:
        ready(server)
        for _ in range(runs):
            with across(domain):
                bridge = Bridge(None, None, "gpp_agent")
            up = time.monotonic()
            try:
                joining.append(shows_servers(bridge, up + 60) - up)
            finally:
                bridge.close()
    finally:
        finish(server)
    starting: list[float] = []
    for _ in range(runs):
        domain = random.randint(101, 200)
        with across(domain):
            bridge = Bridge(None, None, "gpp_agent")
        try:
            server = spawn("ros2_servers.py", domain)
            try:
                served = ready(server)
                starting.append(shows_servers(bridge, time.monotonic() + 60) - served)
            finally:
                finish(server)
        finally:
            bridge.close()
    return joining, starting


def spread(values: list[float]) -> str:
    ordered = sorted(values)
    p90 = ordered[int(0.9 * (len(ordered) - 1))]
    slow = sum(v > 1.0 for v in ordered)
    return (
        f"median {statistics.median(ordered) * 1000:.0f} ms, p90 {p90 * 1000:.0f} ms, "
        f"max {ordered[-1] * 1000:.0f} ms; {slow} of {len(ordered)} runs over 1 s"
    )


@contextlib.contextmanager
def load(n: int) -> Iterator[None]:
    """`n` other processes keeping a core busy each (a test run beside the agent)."""
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]
    try:
        yield
    finally:
        for process in busy:
            process.kill()
            process.wait(10)


def across_processes(args: argparse.Namespace) -> None:
    print(f"ros2 platform (test nodes in another process, discovery on localhost; {args.load} busy processes beside)")
    with load(args.load):
        joining, starting = discovery_across(args.discoveries)
        print(f"  discovery, agent joins running servers   {spread(joining)}")
        print(f"  discovery, servers join a running agent  {spread(starting)}")
        if args.verbose:
            print("    agent joins (s):", " ".join(f"{v:.2f}" for v in sorted(joining)))
            print("    servers join (s):", " ".join(f"{v:.2f}" for v in sorted(starting)))
        for word, mapped in (("typed", "/fib : test_msgs/action/Fibonacci"), ("untyped", "/fib")):
            attaches, goals = first_goals_across(mapped, args.first)
            print(
                f"  first goal, {word:<8} {ms(goals)}; create + attach {ms(attaches)} "
                f"({len(goals)} of {args.first} platforms)"
            )
        print(f"  exog function wake-up  {ms(wake_ups_across(args.wakes))} ({args.wakes} messages)")


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
    parser.add_argument("--first", type=int, default=10, help="platforms for the first goals across processes")
    parser.add_argument("--discoveries", type=int, default=10, help="runs of each discovery measure")
    parser.add_argument("--load", type=int, default=0, help="busy processes beside the cross-process part")
    parser.add_argument("--verbose", action="store_true", help="print every discovery time")
    parser.add_argument("--part", choices=("all", "in-process", "kills", "across"), default="all")
    args = parser.parse_args()
    if args.part in ("all", "in-process"):
        in_process(args)
    if args.part in ("all", "kills"):
        kills(args)
    if args.part in ("all", "across"):
        across_processes(args)


def in_process(args: argparse.Namespace) -> None:
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


def kills(args: argparse.Namespace) -> None:
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
