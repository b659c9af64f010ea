"""The blocksworld robot of the golog++ papers as a ROS 2 node, backed by gpp's pymunk sim.

It serves the robot's own ROS 2 interfaces (package gpp_robot_interfaces, built by
`make ros-interfaces`), under its namespace (the root unless `--ros-args -r __ns:=/robot1`
says otherwise, as for any ROS node: `/robot1/stack`, ...):

    /stack              action  Stack            block, location -> success, message
    /get_block_pose     action  GetBlockPose     block -> location
    /navigate_to_frame  action  NavigateToFrame  frame -> success, message
    /gripper_home       action  GripperHome
    /navigate_to_pose   action  NavigateToPose   pose -> error_code, error_msg (Nav2's shape)
    /battery            topic   Battery          level (latched)

Each goal becomes an activity of the sim's world (the same scenes and physics as
`--platform sim`), so an agent gets the same outcome on either platform:

    python examples/ros2/robot.py [--world blocksworld] [--speed 1] [--ros-args ...]
    gpp run examples/blocksworld.gpp --platform ros2

`--speed` is sim time per wall time (0: as fast as the CPU allows). The node knows nothing
about golog++: any ROS 2 client can drive it.
"""

from __future__ import annotations

import argparse
import queue
import signal
import sys
import threading
import time
from typing import Any

import rclpy
from gpp_robot_interfaces.action import GetBlockPose, GripperHome, NavigateToFrame, NavigateToPose, Stack
from gpp_robot_interfaces.msg import Battery
from rclpy.action.server import ActionServer, CancelResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.context import Context
from rclpy.executors import MultiThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from gpp.base.source import Source, Span
from gpp.model.types import NUMBER, Sym
from gpp.platform.base import ActivityUpdate, ExogActionBinding, ExogOccurrence, Parameter, ProgramInterface
from gpp.platform.sim import SimPlatform, World
from gpp.platform.sim.platform import make_activity
from gpp.runtime.state import ActivityStatus

# /navigate_to_pose drives the base on a square map of this half-width (m), at DRIVE_SPEED m/s
# (times --speed), with feedback every FEEDBACK_PERIOD s; as Nav2 does, a goal it cannot reach
# is aborted with an error code.
MAP_HALF_WIDTH = 10.0
DRIVE_SPEED = 2.0
FEEDBACK_PERIOD = 0.1

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class SimThread:
    """The sim world, stepped by one thread; goals hand it activities through a queue."""

    def __init__(self, world: World, speed: float, on_battery: Any) -> None:
        self.sim = SimPlatform(world)
        self.speed = speed
        self.on_battery = on_battery
        self.commands: queue.Queue[tuple[str, Any, Any]] = queue.Queue()
        self.waiting: dict[int, tuple[threading.Event, list[ActivityUpdate]]] = {}
        self.stop = threading.Event()
        # The sim reports battery levels as an exogenous event mapped to "/battery".
        nowhere = Span(Source("", "<robot>"), 0, 0)
        battery = ExogActionBinding("battery", (Parameter("level", NUMBER),), "/battery", {"level": "level"}, nowhere)
        self.sim.attach(ProgramInterface({}, {"battery": battery}, {}))
        self.thread = threading.Thread(target=self._run, name="sim", daemon=True)
        self.thread.start()

    def run(self, mapped: str, handle: Any, **args: str) -> ActivityUpdate:
        """Run one activity to its end, preempting it when the goal is cancelled."""
        activity = make_activity(mapped, **args)
        done = threading.Event()
        box: list[ActivityUpdate] = []
        self.commands.put(("start", activity, (done, box)))
        preempted = False
        while not done.wait(0.02):
            if handle.is_cancel_requested and not preempted:
                preempted = True
                self.commands.put(("preempt", activity, None))
            if self.stop.is_set():
                return ActivityUpdate(activity.id, ActivityStatus.FAILED, reason="the robot shut down")
        return box[0]

    def _run(self) -> None:
        wall0, sim0 = time.monotonic(), self.sim.now()
        self._deliver()
        while not self.stop.is_set():
            try:
                while True:
                    command, activity, extra = self.commands.get_nowait()
                    if command == "start":
                        self.waiting[activity.id] = extra
                        self.sim.start(activity)
                    else:
                        self.sim.preempt(activity)
            except queue.Empty:
                pass
            if self.sim.tasks:
                self.sim.wait(self.sim.now() + 0.05)
                if self.speed > 0:
                    ahead = (self.sim.now() - sim0) / self.speed - (time.monotonic() - wall0)
                    if ahead > 0:
                        time.sleep(ahead)
            else:
                time.sleep(0.005)
                wall0, sim0 = time.monotonic(), self.sim.now()
            self._deliver()

    def _deliver(self) -> None:
        for _, event in self.sim.queue.drain():
            if isinstance(event, ExogOccurrence):
                self.on_battery(float(event.args[0]))  # type: ignore[arg-type]
                continue
            waiting = self.waiting.pop(event.activity_id, None)
            if waiting is not None:
                waiting[1].append(event)
                waiting[0].set()


class Robot:
    def __init__(self, context: Context, world: World, speed: float) -> None:
        self.node = rclpy.create_node("blocksworld_robot", context=context, start_parameter_services=False)
        self.battery = self.node.create_publisher(Battery, "battery", LATCHED)
        self.sim = SimThread(world, speed, lambda level: self.battery.publish(Battery(level=level)))
        group = ReentrantCallbackGroup()
        accept = {"cancel_callback": lambda _: CancelResponse.ACCEPT, "callback_group": group}
        self.servers = [
            ActionServer(self.node, Stack, "stack", execute_callback=self._stack, **accept),
            ActionServer(self.node, GetBlockPose, "get_block_pose", execute_callback=self._pose, **accept),
            ActionServer(self.node, NavigateToFrame, "navigate_to_frame", execute_callback=self._navigate, **accept),
            ActionServer(self.node, GripperHome, "gripper_home", execute_callback=self._home, **accept),
            ActionServer(self.node, NavigateToPose, "navigate_to_pose", execute_callback=self._drive, **accept),
        ]
        self.speed = speed
        self.base = (0.0, 0.0)
        self.executor = MultiThreadedExecutor(num_threads=4, context=context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, name="ros", daemon=True)
        self.thread.start()

    def _end(self, handle: Any, update: ActivityUpdate) -> None:
        if update.status is ActivityStatus.FINAL:
            handle.succeed()
        elif update.status is ActivityStatus.CANCELLED and handle.is_cancel_requested:
            handle.canceled()
        else:
            handle.abort()

    def _stack(self, handle: Any) -> Any:
        goal = handle.request
        update = self.sim.run("/stack", handle, block=goal.block, location=goal.location)
        self._end(handle, update)
        return Stack.Result(success=update.status is ActivityStatus.FINAL, message=update.reason)

    def _pose(self, handle: Any) -> Any:
        update = self.sim.run("/get_block_pose", handle, block=handle.request.block)
        self._end(handle, update)
        value = update.result
        return GetBlockPose.Result(location=value.name if isinstance(value, Sym) else str(value or ""))

    def _navigate(self, handle: Any) -> Any:
        update = self.sim.run("/navigate_to_frame", handle, frame=handle.request.frame)
        self._end(handle, update)
        return NavigateToFrame.Result(success=update.status is ActivityStatus.FINAL, message=update.reason)

    def _home(self, handle: Any) -> Any:
        update = self.sim.run("/gripper_home", handle)
        self._end(handle, update)
        return GripperHome.Result()

    def _drive(self, handle: Any) -> Any:
        """Nav2's NavigateToPose, on an empty square map: a pose in another frame or off the map
        is aborted with Nav2's kind of error code; otherwise the base drives there."""
        result = NavigateToPose.Result
        pose = handle.request.pose
        x, y = pose.pose.position.x, pose.pose.position.y
        if pose.header.frame_id != "map":
            handle.abort()
            return result(error_code=result.TF_ERROR, error_msg=f'no transform from "{pose.header.frame_id}" to "map"')
        if max(abs(x), abs(y)) > MAP_HALF_WIDTH:
            handle.abort()
            return result(error_code=result.GOAL_OUTSIDE_MAP, error_msg=f"goal ({x:g}, {y:g}) is outside the map")
        x0, y0 = self.base
        distance = ((x - x0) ** 2 + (y - y0) ** 2) ** 0.5
        took = distance / (DRIVE_SPEED * self.speed) if self.speed > 0 else 0.0
        began = time.monotonic()
        while (done := min(1.0, (time.monotonic() - began) / took) if took > 0 else 1.0) < 1.0:
            if handle.is_cancel_requested:
                self.base = (x0 + (x - x0) * done, y0 + (y - y0) * done)
                handle.canceled()
                return result(error_code=result.NONE)
            feedback = NavigateToPose.Feedback(distance_remaining=distance * (1.0 - done))
            feedback.current_pose.header.frame_id = "map"
            feedback.current_pose.pose.position.x = x0 + (x - x0) * done
            feedback.current_pose.pose.position.y = y0 + (y - y0) * done
            handle.publish_feedback(feedback)
            time.sleep(FEEDBACK_PERIOD)
        self.base = (x, y)
        handle.succeed()
        return result(error_code=result.NONE)

    def close(self) -> None:
        self.sim.stop.set()
        self.sim.thread.join(5)
        self.executor.shutdown(timeout_sec=2)
        self.thread.join(5)
        self.node.destroy_node()


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    parser.add_argument("--world", default="blocksworld", help="a world of stdlib/worlds or a TOML file")
    parser.add_argument("--speed", type=float, default=1.0, help="sim time per wall time (0: unpaced)")
    # The ROS arguments (`--ros-args -r __ns:=/robot1 ...`) are rcl's, as for any node.
    args = parser.parse_args(remove_ros_args(["robot.py", *argv])[1:])
    context = Context()
    rclpy.init(
        context=context,
        args=["robot.py", "--ros-args", "--log-level", "warn", "--", *argv],
        signal_handler_options=SignalHandlerOptions.NO,
    )
    robot = Robot(context, World.load(args.world), args.speed)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    print(
        f"robot ready: world {args.world}, speed {args.speed:g}, node {robot.node.get_fully_qualified_name()}",
        flush=True,
    )
    while not stop.wait(0.2):
        pass
    robot.close()
    context.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
