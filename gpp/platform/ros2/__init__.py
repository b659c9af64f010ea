"""The ros2 platform (gpp.platform.ros2.platform): importing this package imports neither rclpy
nor the platform, so that gpp can say how to install the ROS 2 packages where they are
missing, and `gpp check` can look at the mappings (gpp.platform.ros2.static) at no cost."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from gpp.platform.options import Ros2Options

if TYPE_CHECKING:
    from gpp.platform.ros2.platform import INSTALL_HINT, Ros2Platform

__all__ = ["INSTALL_HINT", "Ros2Options", "Ros2Platform"]


def __getattr__(name: str) -> Any:
    if name in ("INSTALL_HINT", "Ros2Platform"):
        from gpp.platform.ros2 import platform

        return getattr(platform, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
