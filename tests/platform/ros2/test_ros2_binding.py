"""The ros2 platform without ROS: its binding file is read and checked with clear errors
(file:line, did-you-mean), mapped names are parsed, and where the ROS 2 packages are missing
`--platform ros2` says in one line how to install them."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from gpp.platform.ros2.binding import Binding, BindingError, find_binding
from gpp.platform.ros2.names import NameError_, parse_mapped

ROOT = Path(__file__).resolve().parents[3]


def load(tmp_path: Path, text: str) -> Binding:
    path = tmp_path / "agent.ros2.toml"
    path.write_text(text, encoding="utf-8")
    return Binding.load(path)


def test_a_binding_file_with_every_kind_of_entry(tmp_path: Path) -> None:
    b = load(
        tmp_path,
        """
[defaults]
server_timeout = 2
result_timeout = 60
discovery_timeout = 1.5

["/navigate_to_pose"]
type = "nav2_msgs/action/NavigateToPose"
ack_timeout = 1.5
stamp = ["pose.header.stamp"]
result = "error_code"

["/scan"]
qos = { reliability = "best_effort", depth = 5 }

[exog_function.battery]
topic = "/battery : sensor_msgs/msg/BatteryState"
field = "percentage"
max_age = 2
max_rate = 20

[exog_function.progress]
feedback = "/navigate_to_pose"
field = "distance_remaining"

[exog_function.block_on]
service = "/get_block_pose"
request = { block = "b" }
timeout = 0.5
poll = 1
""",
    )
    assert b.server_timeout == 2.0 and b.result_timeout_for("/x", service=False) == 60.0
    assert b.discovery_timeout == 1.5 and Binding().discovery_timeout == 5.0
    nav = b.names["/navigate_to_pose"]
    assert nav.type == "nav2_msgs/action/NavigateToPose" and nav.stamp == ("pose.header.stamp",)
    assert b.ack_timeout_for("/navigate_to_pose") == 1.5 and b.ack_timeout_for("/other") == 5.0
    assert b.names["/scan"].qos is not None and b.names["/scan"].qos.reliability == "best_effort"
    assert b.functions["battery"].source.type == "sensor_msgs/msg/BatteryState"
    assert b.functions["block_on"].request == {"block": "b"} and b.functions["block_on"].timeout == 0.5
    assert b.functions["block_on"].poll == 1.0
    assert (b.functions["battery"].max_age, b.functions["battery"].max_rate) == (2.0, 20.0)
    assert b.functions["progress"].kind == "feedback" and b.functions["progress"].source.name == "/navigate_to_pose"
    assert nav.span is not None and nav.span.line == 7


def test_goals_are_sent_once_and_have_no_feedback_timeout_unless_the_binding_says_so(tmp_path: Path) -> None:
    assert Binding().resend_for("/a") is False and Binding().feedback_timeout_for("/a") is None
    b = load(tmp_path, '[defaults]\nfeedback_timeout = 2\n["/nav"]\nresend = true\nfeedback_timeout = 0\n')
    assert b.resend_for("/nav") and not b.resend_for("/other")
    assert b.feedback_timeout_for("/nav") is None and b.feedback_timeout_for("/other") == 2.0


def test_services_have_a_result_timeout_by_default_and_actions_none() -> None:
    b = Binding()
    assert b.result_timeout_for("/s", service=True) == 10.0
    assert b.result_timeout_for("/a", service=False) is None


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '["/stack"]\nserver_timout = 3\n',
            ':1: ["/stack"]: unknown key `server_timout`; did you mean `server_timeout`?',
        ),
        ("[defualts]\nserver_timeout = 3\n", ":1: [defualts]: unknown table `defualts`"),
        ('["/stack"]\nack_timeout = -1\n', "ack_timeout: expected a number of seconds > 0, not -1"),
        ("[defaults]\ndiscovery_timeout = 0\n", "discovery_timeout: expected a number of seconds > 0, not 0"),
        ('["/scan"]\nqos = { reliability = "best-effort" }\n', "did you mean `best_effort`?"),
        ('["/x"]\nstamp = [1]\n', "stamp: expected a list of field paths"),
        ('[exog_function.f]\nfield = "x"\n', "give the source of `f`"),
        ('[exog_function.f]\ntopic = "/t"\nrequest = { a = "b" }\n', "only a service source takes `request`"),
        ('[exog_function.f]\ntopic = "/t"\ntimeout = 2\n', "a topic's value has a maximum age (`max_age`) instead"),
        ('[exog_function.f]\nservice = "/s"\nmax_age = 2\n', "only a topic or feedback source takes `max_age`"),
        ('[exog_function.f]\nfeedback = "/a"\npoll = 1\n', "only a service source takes `poll`"),
        ('[exog_function.f]\ntopic = "/t"\nmax_rate = 0\n', "max_rate: expected a number of times a second > 0"),
        ('[exog_function.f]\nservice = "/s"\nrequest = { a = 1 }\n', "`a` must name a parameter of `f`"),
        ('["/nav"]\nresend = "yes"\n', 'resend: expected true or false, not "yes"'),
        ("[defaults]\nfeedback_timeout = -1\n", "feedback_timeout: expected a number of seconds >= 0 (0: no limit)"),
        ('["/a b"]\n', "is not a ROS 2 name"),
        ("x = ", "is not valid TOML"),
    ],
)
def test_binding_file_errors_say_where_and_why(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(BindingError) as caught:
        load(tmp_path, text)
    assert message in str(caught.value)
    assert str(tmp_path / "agent.ros2.toml") in str(caught.value)


def test_the_binding_file_is_found_beside_the_agent(tmp_path: Path) -> None:
    agent = tmp_path / "agent.gpp"
    assert find_binding(agent, None, None) is None
    (tmp_path / "agent.ros2.toml").write_text("")
    assert find_binding(agent, None, None) == tmp_path / "agent.ros2.toml"
    assert find_binding(agent, None, tmp_path / "robot.toml") == tmp_path / "robot.toml"
    assert find_binding(agent, Path("x.toml"), tmp_path / "robot.toml") == Path("x.toml")


def test_mapped_names() -> None:
    assert parse_mapped("/stack").name == "/stack" and parse_mapped("/stack").type is None
    assert parse_mapped("stack : pkg/action/Stack").name == "/stack"
    assert parse_mapped("/a/b :  pkg/srv/B ").type == "pkg/srv/B"
    with pytest.raises(NameError_, match="type after `:` is missing"):
        parse_mapped("/a :")
    with pytest.raises(NameError_, match="not a ROS 2 name"):
        parse_mapped("/a-b")


def test_without_the_ros_packages_the_platform_says_how_to_install_them(tmp_path: Path) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text("action go() { }\nprocedure main() { go(); }\n")
    # A Python in which rclpy cannot be imported, whether or not it is installed here.
    script = (
        "import sys\n"
        "class Block:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'rclpy' or name.startswith('rclpy.'): raise ModuleNotFoundError(name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "from gpp.cli.main import main\n"
        "main(['run', sys.argv[1], '--platform', 'ros2'])\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    result = subprocess.run(
        [sys.executable, "-c", script, str(program)], capture_output=True, text=True, timeout=60, env=env
    )
    assert result.returncode == 2, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert "pip install 'gpp[ros]'" in lines[0] and "Traceback" not in result.stderr
