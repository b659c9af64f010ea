"""Fixtures of the ros2 platform's tests: one rclpy Context per test, shared by the test
servers and the platform, with discovery off, so that no traffic leaves the process; the
ROS log files go to a temporary folder."""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

# Read by rclpy when a context is initialised: set before any test does.
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "OFF"
os.environ.setdefault("ROS_LOG_DIR", tempfile.mkdtemp(prefix="gpp-ros-log-"))
sys.path.insert(0, str(Path(__file__).parent))


def pytest_configure(config: pytest.Config) -> None:
    # rclpy's action server leaves this behind when its executor stops with goals pending.
    config.addinivalue_line("filterwarnings", "ignore:coroutine 'ActionServer._execute_goal':RuntimeWarning")


@pytest.fixture
def ros() -> Iterator[Any]:
    """A context with the test servers on it; the ros2 platforms created meanwhile join it."""
    rclpy = pytest.importorskip("rclpy")
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions
    from ros2_servers import TestRobot

    from gpp.platform.ros2 import Ros2Platform

    context = Context()
    rclpy.init(
        context=context, args=["--ros-args", "--log-level", "error"], signal_handler_options=SignalHandlerOptions.NO
    )
    robot = TestRobot(context)
    Ros2Platform.shared_context = context
    try:
        yield robot
    finally:
        Ros2Platform.shared_context = None
        robot.close()
        context.try_shutdown()
