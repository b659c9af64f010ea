"""The ros2 platform (gpp.platform.ros2.platform): importing this package does not import rclpy,
so that gpp can say how to install the ROS 2 packages where they are missing."""

from gpp.platform.options import Ros2Options
from gpp.platform.ros2.platform import INSTALL_HINT, Ros2Platform

__all__ = ["INSTALL_HINT", "Ros2Options", "Ros2Platform"]
