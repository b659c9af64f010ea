"""A ROS 2 publisher (and action server) in a process of its own, driven line by line on stdin,
for the tests of exogenous topics and functions against a real publisher in another process,
and of a server that comes back with another type. The node spins between commands.

Commands (each answered with one line on stdout once done):
* `advertise TOPIC TYPE QOS`: create a publisher; TYPE is `string`, `int32` or `float64`
  (std_msgs), QOS `keep_all` (reliable, keeping every message until delivered), `depth10`
  (reliable, keeping the last 10) or `best_effort` -> `advertised`
* `match TOPIC`: wait (at most 30 s) until a subscriber is matched -> `matched`
* `node NAME`: wait (at most 30 s) until a node of that name is in the graph -> `found`
* `send TOPIC VALUE`: publish one message -> `sent T` (T: time.monotonic() just before)
* `burst TOPIC N`: publish the numbers 0..N-1 as fast as possible -> `sent`
* `ramp TOPIC N HZ`: publish the numbers 0..N-1, HZ a second -> `sent T0 T1` (the
  time.monotonic() of the first and the last publish)
* `serve NAME KIND`: an action server of that name, KIND `fib` (test_msgs Fibonacci) or
  `nested` (test_msgs NestedMessage), succeeding at once -> `serving`
* `unserve NAME`: destroy that action server -> `gone`
* `goals NAME`: how many goals the servers of that name executed -> `goals N`

Times are time.monotonic(): on Linux the system-wide CLOCK_MONOTONIC, so another process on
the machine can compare them with its own.
"""

from __future__ import annotations

import queue
import sys
import threading
import time
from typing import Any

import rclpy
from rclpy.action.server import ActionServer
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Float64, Int32, String
from test_msgs.action import Fibonacci, NestedMessage

TYPES: dict[str, Any] = {"string": String, "int32": Int32, "float64": Float64}
ACTIONS: dict[str, Any] = {"fib": Fibonacci, "nested": NestedMessage}
QOS = {
    "keep_all": QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE),
    "depth10": QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE),
    "best_effort": QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.BEST_EFFORT),
}


def main() -> None:
    context = Context()
    rclpy.init(context=context, args=["--ros-args", "--log-level", "error"])
    node = rclpy.create_node("test_publisher", context=context, start_parameter_services=False)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    publishers: dict[str, tuple[Any, Any]] = {}
    servers: dict[str, Any] = {}
    goals: dict[str, int] = {}
    lines: queue.Queue[str | None] = queue.Queue()

    def read() -> None:
        for line in sys.stdin:
            lines.put(line)
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    print("ready", flush=True)
    while True:
        try:
            line = lines.get_nowait()
        except queue.Empty:
            executor.spin_once(timeout_sec=0.005)
            continue
        if line is None:
            break
        words = line.split()
        if not words:
            continue
        command, topic = words[0], words[1]
        if command == "advertise":
            cls = TYPES[words[2]]
            publishers[topic] = (node.create_publisher(cls, topic, QOS[words[3]]), cls)
            print("advertised", flush=True)
        elif command == "match":
            publisher = publishers[topic][0]
            deadline = time.monotonic() + 30
            while publisher.get_subscription_count() == 0 and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.01)
            print("matched" if publisher.get_subscription_count() else "unmatched", flush=True)
        elif command == "node":
            deadline = time.monotonic() + 30
            while topic not in node.get_node_names() and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.01)
            print("found" if topic in node.get_node_names() else "missing", flush=True)
        elif command == "send":
            publisher, cls = publishers[topic]
            t = time.monotonic()
            publisher.publish(cls(data=value(cls, words[2])))
            print(f"sent {t}", flush=True)
        elif command == "burst":
            publisher, cls = publishers[topic]
            for i in range(int(words[2])):
                publisher.publish(cls(data=value(cls, str(i))))
            print("sent", flush=True)
        elif command == "ramp":
            publisher, cls = publishers[topic]
            n, period = int(words[2]), 1.0 / float(words[3])
            began = time.monotonic()
            for i in range(n):
                while time.monotonic() < began + i * period:
                    time.sleep(0.001)
                publisher.publish(cls(data=value(cls, str(i))))
            print(f"sent {began} {time.monotonic()}", flush=True)
        elif command == "serve":
            kind = ACTIONS[words[2]]

            def execute(handle: Any, name: str = topic, kind: Any = kind) -> Any:
                goals[name] = goals.get(name, 0) + 1
                handle.succeed()
                return kind.Result()

            servers[topic] = ActionServer(node, kind, topic, execute_callback=execute)
            print("serving", flush=True)
        elif command == "unserve":
            servers.pop(topic).destroy()
            print("gone", flush=True)
        elif command == "goals":
            print(f"goals {goals.get(topic, 0)}", flush=True)
    # Messages still on their way are delivered before the node goes.
    end = time.monotonic() + 1.0
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    executor.shutdown()
    node.destroy_node()
    context.try_shutdown()


def value(cls: Any, text: str) -> Any:
    return text if cls is String else int(text) if cls is Int32 else float(text)


if __name__ == "__main__":
    main()
