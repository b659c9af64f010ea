"""A subscriber of an agent's run topics in a process of its own, as `ros2 topic echo` would be:
`python ros2_listener.py EVENTS STATE [--go TOPIC]` prints `ready` once subscribed, then
`event T JSON` for each message on EVENTS and `state T JSON` for each on STATE (T: its
time.monotonic() when it arrived; both topics reliable and transient local, as the agent
publishes them). With `--go`, once the first state arrives it publishes one std_msgs/String
("late") on TOPIC. It prints `done` and exits after the `finish` record.
"""

from __future__ import annotations

import argparse
import json
import time

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("events")
    parser.add_argument("state")
    parser.add_argument("--go")
    args = parser.parse_args()
    context = Context()
    rclpy.init(context=context, args=["--ros-args", "--log-level", "error"])
    node = rclpy.create_node("test_listener", context=context, start_parameter_services=False)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    latched = QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1000,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
    go = node.create_publisher(String, args.go, 10) if args.go else None
    seen = {"states": 0, "finished": False}

    def event(msg: String) -> None:
        print(f"event {time.monotonic()} {msg.data}", flush=True)
        if json.loads(msg.data)["event"] == "finish":
            seen["finished"] = True

    def state(msg: String) -> None:
        print(f"state {time.monotonic()} {msg.data}", flush=True)
        seen["states"] += 1
        if go is not None and seen["states"] == 1:
            deadline = time.monotonic() + 30
            while go.get_subscription_count() == 0 and time.monotonic() < deadline:
                time.sleep(0.01)
            go.publish(String(data="late"))

    node.create_subscription(String, args.events, event, latched)
    node.create_subscription(String, args.state, state, latched)
    print("ready", flush=True)
    deadline = time.monotonic() + 120
    while not seen["finished"] and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    # The state that follows the finish record.
    end = time.monotonic() + 1.0
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    print("done", flush=True)
    executor.shutdown(timeout_sec=0)
    node.destroy_node()
    context.try_shutdown()


if __name__ == "__main__":
    main()
