"""A simulator's clock in a process of its own: `python ros2_clock.py RATE START` publishes
rosgraph_msgs/Clock on /clock every 10 ms of wall time, starting at START s of simulated time
and moving RATE times as fast as the wall clock (faster than real time above 1). It prints
`ready` after its first message, and `stamp SECONDS` for each geometry_msgs/PoseStamped that
arrives on /stamped (its header's stamp).
"""

from __future__ import annotations

import sys
import time

import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

PERIOD = 0.01


def main() -> None:
    rate, start = float(sys.argv[1]), float(sys.argv[2])
    context = Context()
    rclpy.init(context=context, args=["--ros-args", "--log-level", "error"])
    node = rclpy.create_node("test_clock", context=context, start_parameter_services=False)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    clock = node.create_publisher(Clock, "/clock", QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))

    def stamped(msg: PoseStamped) -> None:
        print(f"stamp {msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9}", flush=True)

    node.create_subscription(PoseStamped, "/stamped", stamped, 10)
    began = time.monotonic()
    first = True
    while True:
        simulated = start + (time.monotonic() - began) * rate
        message = Clock()
        message.clock.sec = int(simulated)
        message.clock.nanosec = int((simulated - int(simulated)) * 1e9)
        clock.publish(message)
        if first:
            print("ready", flush=True)
            first = False
        executor.spin_once(timeout_sec=PERIOD)


if __name__ == "__main__":
    main()
