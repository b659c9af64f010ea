"""A ROS 2 publisher in a process of its own, driven line by line on stdin, for the tests of
exogenous topics and functions against a real publisher in another process.

Commands (each answered with one line on stdout once done):
* `advertise TOPIC TYPE QOS`: create a publisher; TYPE is `string`, `int32` or `float64`
  (std_msgs), QOS `keep_all` (reliable, keeping every message until delivered), `depth10`
  (reliable, keeping the last 10) or `best_effort` -> `advertised`
* `match TOPIC`: wait (at most 30 s) until a subscriber is matched -> `matched`
* `node NAME`: wait (at most 30 s) until a node of that name is in the graph -> `found`
* `send TOPIC VALUE`: publish one message -> `sent T` (T: time.monotonic() just before)
* `burst TOPIC N`: publish the numbers 0..N-1 as fast as possible -> `sent`
"""

from __future__ import annotations

import sys
import time
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Float64, Int32, String

TYPES: dict[str, Any] = {"string": String, "int32": Int32, "float64": Float64}
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
    print("ready", flush=True)
    for line in sys.stdin:
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
            text = words[2]
            data: Any = text if cls is String else int(text) if cls is Int32 else float(text)
            t = time.monotonic()
            publisher.publish(cls(data=data))
            print(f"sent {t}", flush=True)
        elif command == "burst":
            publisher, cls = publishers[topic]
            for i in range(int(words[2])):
                publisher.publish(cls(data=i))
            print("sent", flush=True)
    # Messages still on their way are delivered before the node goes.
    end = time.monotonic() + 1.0
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    executor.shutdown()
    node.destroy_node()
    context.try_shutdown()


if __name__ == "__main__":
    main()
