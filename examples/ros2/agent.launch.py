"""A launch file that starts the example robot and a golog++ agent beside it under /robot1,
as `ros2 launch` starts any node (launch_ros is part of a ROS 2 installation, not of the pip
wheels):

    ros2 launch examples/ros2/agent.launch.py

launch_ros's `Node` runs `gpp run AGENT --platform ros2 --ros-args -r __node:=courier -r
__ns:=/robot1 --params-file PARAMS -r navigate:=navigate_to_pose`: gpp hands what follows
`--ros-args` to rcl, so the agent's node is /robot1/courier, its relative names are under
/robot1, `navigate` is remapped to the robot's `navigate_to_pose`, and `main`'s parameters
`x` and `y` (courier.gpp) are ROS parameters. tests/platform/ros2/test_ros2_launch.py starts
gpp with this command line. The robot's interfaces come from `make ros-interfaces` (see
robot.py).
"""

from pathlib import Path

from launch import LaunchDescription
from launch_ros.actions import Node

HERE = Path(__file__).resolve().parent


def generate_launch_description() -> LaunchDescription:
    agent = HERE / "courier.gpp"
    return LaunchDescription(
        [
            Node(
                executable="python3",
                arguments=[str(HERE / "robot.py")],
                name="robot",
                namespace="/robot1",
                output="screen",
            ),
            Node(
                executable="gpp",
                arguments=["run", str(agent), "--platform", "ros2"],
                name="courier",
                namespace="/robot1",
                parameters=[{"x": 3.0, "y": 4.0}],
                remappings=[("navigate", "navigate_to_pose")],
                output="screen",
            ),
        ]
    )
