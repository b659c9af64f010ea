"""How the ros2 platform resolves a mapped name: as ROS resolves the names of any node
(absolute, relative to the namespace, `~` under the node), then the node's remapping rules;
checked against rclpy's own resolution."""

from __future__ import annotations

from typing import Any

import pytest

from gpp.platform.ros2.names import NameError_, parse_mapped, resolve

NAMES = ["navigate", "/navigate", "a/b", "/a/b", "~", "~/events", "~/a/b"]


@pytest.mark.parametrize(
    ("name", "namespace", "node", "expected"),
    [
        ("navigate", "/", "gpp_agent", "/navigate"),
        ("navigate", "/robot1", "courier", "/robot1/navigate"),
        ("/navigate", "/robot1", "courier", "/navigate"),
        ("arm/home", "/fleet/robot1", "courier", "/fleet/robot1/arm/home"),
        ("~", "/robot1", "courier", "/robot1/courier"),
        ("~/events", "/robot1", "courier", "/robot1/courier/events"),
        ("~/events", "/", "gpp_agent", "/gpp_agent/events"),
        (" navigate ", "/robot1", "courier", "/robot1/navigate"),
    ],
)
def test_names_resolve_as_ros_resolves_them(name: str, namespace: str, node: str, expected: str) -> None:
    assert resolve(name, namespace, node) == expected


def test_remapping_rules_apply_to_the_expanded_name() -> None:
    rules = {"/robot1/navigate": "/robot1/move_base"}
    assert resolve("navigate", "/robot1", "courier", lambda n: rules.get(n, n)) == "/robot1/move_base"
    assert resolve("/navigate", "/robot1", "courier", lambda n: rules.get(n, n)) == "/navigate"


@pytest.mark.parametrize("name", ["~x", "a//b", "a/", "1a", "/", "~/", "a-b", ""])
def test_what_is_not_a_ros_name_is_refused(name: str) -> None:
    with pytest.raises(NameError_, match="not a ROS 2 name"):
        resolve(name)


@pytest.mark.parametrize("namespace", ["robot1", "/robot1/", "/1robot", ""])
def test_what_is_not_a_namespace_is_refused(namespace: str) -> None:
    with pytest.raises(NameError_, match="not an absolute ROS 2 namespace"):
        resolve("a", namespace)


def test_a_mapped_name_keeps_its_type_and_is_resolved_in_the_root_namespace() -> None:
    assert parse_mapped("navigate : pkg/action/Nav") == parse_mapped("/navigate : pkg/action/Nav")
    assert parse_mapped("~/said").name == "/gpp_agent/said"


@pytest.mark.parametrize("namespace", ["/", "/robot1", "/fleet/robot1"])
def test_the_resolution_is_rclpys(namespace: str) -> None:
    """The same names on a real node, with a remapping rule: rclpy gives the same answers."""
    rclpy = pytest.importorskip("rclpy")
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions

    context = Context()
    rclpy.init(
        context=context, args=["--ros-args", "--log-level", "error"], signal_handler_options=SignalHandlerOptions.NO
    )
    try:
        node: Any = rclpy.create_node(
            "courier",
            namespace=namespace,
            context=context,
            cli_args=["--ros-args", "-r", "a/b:=moved"],
            start_parameter_services=False,
        )
        try:
            for name in NAMES:
                assert resolve(name, namespace, "courier", node.resolve_topic_name) == node.resolve_topic_name(name)
            assert resolve("a/b", namespace, "courier", node.resolve_topic_name).endswith("/moved")
        finally:
            node.destroy_node()
    finally:
        context.try_shutdown()
