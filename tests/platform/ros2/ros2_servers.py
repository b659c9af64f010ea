"""Real ROS 2 servers for the ros2 platform's tests, built only from shipped interface types.

`TestRobot(context)` runs them on a node of the given context (in-process tests share one
context with the platform, discovery off); `python ros2_servers.py` runs them in a process of
their own (cross-process tests, with a random domain and discovery on localhost only) and
prints `ready T` once they serve (T: its time.monotonic() then).

Behaviours:
* `/fib` (test_msgs/action/Fibonacci), chosen by `order`: >= 0 succeed with the sequence;
  -1 abort; -2 reject; -3 succeed after 0.3 s; -5 answer each goal request only after 1.5 s;
  -6 answer only the first goal request late (1.5 s); -7 send feedback (the sequence so far,
  growing by one) every 50 ms, 10 times, then succeed; >= 1000 run until cancelled;
  -10 run until cancelled, sending feedback every 0.1 s; -11 refuse to be cancelled and
  succeed after 1 s; -12 send feedback for 0.3 s, then nothing until cancelled (stuck);
* `/nested` (test_msgs/action/NestedMessage): the result echoes the goal;
* `/basic` (test_msgs/srv/BasicTypes): echo; `/set_bool` (std_srvs/srv/SetBool):
  success = data; `/slow` (std_srvs/srv/Trigger): answers after 2 s; `/ticks`
  (std_srvs/srv/Trigger): the number of calls so far, as the message ("1", "2", ...); `/get_plan`
  (nav_msgs/srv/GetPlan, a response of one field that is a message): a path from the start to
  the goal pose, in the goal's frame;
* a subscription `/said` (std_msgs/msg/String): `heard` keeps what arrives (a process prints
  `heard TEXT`);
* publishers `/events` (std_msgs/msg/String) and `/count` (std_msgs/msg/Int32), reliable and
  keeping every message until it is delivered.
"""

from __future__ import annotations

import sys
import threading
import time
from typing import Any

import rclpy
from nav_msgs.srv import GetPlan
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.context import Context
from rclpy.executors import MultiThreadedExecutor
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Int32, String
from std_srvs.srv import SetBool, Trigger
from test_msgs.action import Fibonacci, NestedMessage
from test_msgs.srv import BasicTypes

KEEP_ALL = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)


class TestRobot:
    __test__ = False

    def __init__(
        self, context: Context, name: str = "test_robot", announce: bool = False, result_timeout: int = 10
    ) -> None:
        # announce: print `request ORDER` when a /fib goal request arrives and `goal ORDER` when
        # the goal starts (for a parent process to wait on, or to see that none came).
        # result_timeout: s /fib keeps a finished goal (rclpy's default, 10); the goals it keeps
        # slow the next ones down, which a benchmark of many goals does not want.
        self.announce = announce
        self.node = rclpy.create_node(name, context=context, start_parameter_services=False)
        self.lock = threading.Lock()
        self.executed: list[int] = []
        self.cancelled: list[int] = []
        self.requests: list[int] = []
        self.running = 0
        self.stopping = threading.Event()
        self.max_running = 0
        group = ReentrantCallbackGroup()
        node = self.node
        self.fib = ActionServer(
            node,
            Fibonacci,
            "/fib",
            execute_callback=self._fib,
            goal_callback=self._goal,
            cancel_callback=self._cancel,
            callback_group=group,
            result_timeout=result_timeout,
        )
        self.nested = ActionServer(node, NestedMessage, "/nested", execute_callback=self._nested, callback_group=group)
        node.create_service(BasicTypes, "/basic", lambda req, resp: _copy(req, resp), callback_group=group)
        node.create_service(SetBool, "/set_bool", self._set_bool, callback_group=group)
        node.create_service(Trigger, "/slow", self._slow, callback_group=group)
        node.create_service(GetPlan, "/get_plan", self._get_plan, callback_group=group)
        self.ticks = 0
        node.create_service(Trigger, "/ticks", self._tick, callback_group=group)
        self.events = node.create_publisher(String, "/events", KEEP_ALL)
        self.count = node.create_publisher(Int32, "/count", KEEP_ALL)
        self.heard: list[str] = []
        node.create_subscription(String, "/said", self._said, 10, callback_group=group)
        self.executor = MultiThreadedExecutor(num_threads=4, context=context)
        self.executor.add_node(node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.stopping.set()
        self.executor.shutdown(timeout_sec=2.0)
        self.thread.join(5.0)
        self.node.destroy_node()

    # ---------------------------------------------------------------- /fib

    def _goal(self, goal: Any) -> GoalResponse:
        with self.lock:
            self.requests.append(goal.order)
            first = self.requests.count(goal.order) == 1
        if self.announce:
            print(f"request {goal.order}", flush=True)
        if goal.order == -2:
            return GoalResponse.REJECT
        if goal.order == -5 or (goal.order == -6 and first):
            time.sleep(1.5)
        return GoalResponse.ACCEPT

    def _cancel(self, handle: Any) -> CancelResponse:
        return CancelResponse.REJECT if handle.request.order == -11 else CancelResponse.ACCEPT

    def _fib(self, handle: Any) -> Any:
        order = handle.request.order
        with self.lock:
            self.executed.append(order)
            self.running += 1
            self.max_running = max(self.max_running, self.running)
        if self.announce:
            print(f"goal {order}", flush=True)
        try:
            if order == -1:
                handle.abort()
                return Fibonacci.Result(sequence=[0])
            if order == -11:
                time.sleep(1.0)
                order = 2
            if order >= 1000 or order in (-5, -6, -10, -12):
                began = time.monotonic()
                deadline = began + (0.3 if order in (-5, -6) else 30.0)
                while time.monotonic() < deadline and not self.stopping.is_set():
                    if order == -10 or (order == -12 and time.monotonic() - began < 0.3):
                        handle.publish_feedback(Fibonacci.Feedback(sequence=[0]))
                        time.sleep(0.09)
                    if handle.is_cancel_requested:
                        with self.lock:
                            self.cancelled.append(order)
                        handle.canceled()
                        return Fibonacci.Result(sequence=[1])
                    time.sleep(0.01)
                if order not in (-5, -6):
                    handle.abort()
                    return Fibonacci.Result()
                order = 3
            if order == -3:
                time.sleep(0.3)
                order = 5
            if order == -7:
                sequence = [0]
                for _ in range(10):
                    sequence.append(len(sequence))
                    handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
                    time.sleep(0.05)
                handle.succeed()
                return Fibonacci.Result(sequence=sequence)
            sequence = [0, 1]
            for _ in range(order - 1):
                sequence.append(sequence[-1] + sequence[-2])
            handle.publish_feedback(Fibonacci.Feedback(sequence=sequence[: order + 1]))
            handle.succeed()
            return Fibonacci.Result(sequence=sequence[: order + 1])
        finally:
            with self.lock:
                self.running -= 1

    def _nested(self, handle: Any) -> Any:
        handle.succeed()
        result = NestedMessage.Result()
        _copy(handle.request, result)
        return result

    # ---------------------------------------------------------------- services

    def _set_bool(self, request: Any, response: Any) -> Any:
        response.success = request.data
        response.message = "on" if request.data else "off"
        return response

    def _get_plan(self, request: Any, response: Any) -> Any:
        response.plan.header.frame_id = request.goal.header.frame_id
        response.plan.poses = [request.start, request.goal]
        return response

    def _slow(self, request: Any, response: Any) -> Any:
        time.sleep(2.0)
        response.success = True
        response.message = "slow"
        return response

    def _tick(self, request: Any, response: Any) -> Any:
        with self.lock:
            self.ticks += 1
            response.message = str(self.ticks)
        response.success = True
        return response

    # ---------------------------------------------------------------- topics

    def _said(self, msg: Any) -> None:
        with self.lock:
            self.heard.append(msg.data)
        if self.announce:
            print(f"heard {msg.data}", flush=True)

    def wait_for_subscriber(self, publisher: Any, timeout: float = 5.0) -> None:
        deadline = time.monotonic() + timeout
        while publisher.get_subscription_count() == 0:
            if time.monotonic() > deadline:
                raise TimeoutError(f"no subscriber on {publisher.topic_name} within {timeout} s")
            time.sleep(0.005)


def _copy(source: Any, target: Any) -> Any:
    for name in source.get_fields_and_field_types():
        setattr(target, name, getattr(source, name))
    return target


def main() -> None:
    """Serve in a process of its own until stdin closes or SIGTERM."""
    import signal

    context = Context()
    rclpy.init(context=context, args=["--ros-args", "--log-level", "error"])
    robot = TestRobot(context, "test_robot_process", announce=True)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    print(f"ready {time.monotonic()}", flush=True)  # the system-wide CLOCK_MONOTONIC on Linux
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
    stop.wait()
    robot.close()
    context.try_shutdown()


if __name__ == "__main__":
    main()
