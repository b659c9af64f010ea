"""`gpp check` and the language server's session report what the ros2 platform would refuse of
a mapping that names its type, without a robot (gpp.platform.ros2.static): at the mapping,
with a did-you-mean. A program without such mappings costs nothing: no ROS module is imported."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.check.session import Session
from gpp.platform.static import static_diagnostics
from tests.cli.test_cli import imported_modules
from tests.support.cli import run

TYPED = """action count(number n) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { ordr = n }
}
action big() {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = 5000000000 }
}
action send(string s) {
mapping:
    "/fib : test_msgs/action/Fibonacci" { order = s }
}
exog_action heard(string what) {
mapping:
    "/events : std_msgs/msg/String" { dat = what }
}
action theirs() {
mapping:
    "/stack : a_robot_package_not_here/action/Stack" { block = 1 }
}
procedure main() { count(1); big(); send("x"); theirs(); }
"""

UNTYPED = """action count(number n) {
mapping:
    "/fib" { ordr = n }
}
procedure main() { count(1); }
"""

ROS_MODULES = ("rclpy", "rosidl_parser", "test_msgs", "gpp.platform.ros2.checks", "gpp.platform.ros2.interfaces")


@pytest.mark.fault
def test_check_reports_a_typed_mapping_at_the_mapping(tmp_path: Path) -> None:
    pytest.importorskip("rclpy")
    (tmp_path / "agent.gpp").write_text(TYPED)
    result = run("check", "--format", "concise", "agent.gpp", cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    lines = [line for line in result.stdout.splitlines() if "R0007" in line]
    assert len(lines) == 4, result.stdout
    assert "agent.gpp:3:43" in lines[0] and "has no field `ordr` (its fields: order)" in lines[0]
    assert "agent.gpp:7:43" in lines[1] and "5000000000 is out of range for int32" in lines[1]
    assert "agent.gpp:11:43" in lines[2] and "a int32 field needs a number, not string" in lines[2]
    assert "agent.gpp:15:39" in lines[3] and "`std_msgs/String` has no field `dat`" in lines[3]
    # The robot's own package is not installed here: left to the run, not an error.
    assert "a_robot_package_not_here" not in result.stdout


def test_check_shows_the_did_you_mean(tmp_path: Path) -> None:
    pytest.importorskip("rclpy")
    (tmp_path / "agent.gpp").write_text(TYPED)
    result = run("check", "agent.gpp", cwd=tmp_path)
    assert "help: did you mean `order`?" in result.stdout and "help: did you mean `data`?" in result.stdout
    assert "note: the program does not fit platform `ros2`" in result.stdout


def test_the_language_server_session_reports_them_too(tmp_path: Path) -> None:
    pytest.importorskip("rclpy")
    path = (tmp_path / "agent.gpp").resolve()
    session = Session(extra_checks=static_diagnostics)
    session.open(path, TYPED, 1)
    [result] = session.results_for(path)
    found = sorted((d.span.line, d.code) for d in result.diagnostics if d.is_error)
    assert found == [(3, "R0007"), (7, "R0007"), (11, "R0007"), (15, "R0007")]
    session.edit(path, [(((2, 42), (2, 46)), "order")], 2)
    [result] = session.results_for(path)
    assert sorted(d.span.line for d in result.diagnostics if d.is_error) == [7, 11, 15]


def test_an_untyped_mapping_is_left_to_the_run_and_imports_nothing_of_ros(tmp_path: Path) -> None:
    (tmp_path / "agent.gpp").write_text(UNTYPED)
    result = run("check", "agent.gpp", cwd=tmp_path)
    assert result.returncode == 0, result.stdout
    modules = imported_modules(["check", "agent.gpp"], tmp_path)
    assert "gpp.platform.ros2.static" in modules  # the measurement works
    assert {m for m in modules if m.startswith(ROS_MODULES)} == set()


def test_without_the_ros_packages_nothing_changes(tmp_path: Path) -> None:
    """The ros extra missing (its modules cannot be imported): a typed mapping is not checked."""
    (tmp_path / "agent.gpp").write_text(TYPED)
    (tmp_path / "sitecustomize.py").write_text(
        "import sys\n"
        "class NoRos:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] in ('rclpy', 'rosidl_parser'):\n"
        "            raise ImportError(name)\n"
        "sys.meta_path.insert(0, NoRos())\n"
    )
    import os
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    result = subprocess.run(
        [sys.executable, "-m", "gpp", "check", "agent.gpp"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "R0007" not in result.stdout
