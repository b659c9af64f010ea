"""ROS 2 names: the mapped name of the ros2 platform (`"name"` or `"name : package/kind/Type"`)
and how a name is resolved against the agent's node, as ROS resolves the names of any node.

Kept free of rclpy so that the binding file and the mappings can be read (and their errors
reported) on a machine without ROS; the remapping rules are applied by rclpy (the platform
passes `remap`).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

_TOKEN = r"[A-Za-z_][A-Za-z0-9_]*"
# `~`, `~/a/b`, `/a/b` or `a/b`: tokens of letters, digits and `_` (not starting with a digit).
_NAME = re.compile(rf"^(~(/{_TOKEN})*|/?{_TOKEN}(/{_TOKEN})*)$")
_NAMESPACE = re.compile(rf"^(/|(/{_TOKEN})+)$")

# The name of the agent's node unless `-o node_name=` or `-r __node:=` says otherwise.
DEFAULT_NODE_NAME = "gpp_agent"


class NameError_(ValueError):
    """A mapped name that is not a ROS 2 name (with an optional type)."""


@dataclass(frozen=True)
class MappedName:
    name: str  # absolute: "/stack"
    type: str | None  # "pkg/action/Type" as written, or None: looked up in the graph
    # The name as written ("stack", "~/said"), resolved again under the node's namespace.
    written: str = field(default="", compare=False)


def is_name(name: str) -> bool:
    """Is `name` a ROS 2 name (absolute, relative or private with `~`)?"""
    return bool(_NAME.match(name))


def is_namespace(namespace: str) -> bool:
    """Is `namespace` an absolute ROS 2 namespace (`/`, `/robot1`, `/fleet/robot1`)?"""
    return bool(_NAMESPACE.match(namespace))


def resolve(
    name: str,
    namespace: str = "/",
    node_name: str = DEFAULT_NODE_NAME,
    remap: Callable[[str], str] | None = None,
) -> str:
    """The absolute name that `name` stands for on the node `node_name` in `namespace`, as ROS
    resolves it: an absolute name (`/a`) is itself; a relative one (`a`) is under the
    namespace (`/robot1/a`); a private one (`~`, `~/a`) is under the node (`/robot1/agent/a`).
    Then the remapping rules (`remap`: the node's, applied by rclpy to the expanded name) may
    replace it. NameError_ when `name` is not a ROS 2 name."""
    name = name.strip()
    if not is_name(name):
        raise NameError_(
            f'"{name}" is not a ROS 2 name: names are letters, digits and `_` (not starting with a digit), '
            "separated by `/`; `~` may begin one"
        )
    if not is_namespace(namespace):
        raise NameError_(f'"{namespace}" is not an absolute ROS 2 namespace (such as "/" or "/robot1")')
    prefix = namespace.rstrip("/")
    if name.startswith("~"):
        expanded = f"{prefix}/{node_name}{name[1:]}"
    elif name.startswith("/"):
        expanded = name
    else:
        expanded = f"{prefix}/{name}"
    return remap(expanded) if remap is not None else expanded


def normalize(name: str) -> str:
    """A name as the agent's node resolves it in the root namespace, without remapping rules
    (`stack` and `/stack` are the same name there); a name that is not a ROS name is made
    absolute as it is (its error is reported where it is parsed)."""
    try:
        return resolve(name)
    except NameError_:
        name = name.strip()
        return name if name.startswith("/") else "/" + name


_PLACEHOLDER = re.compile(r"\{[A-Za-z_][A-Za-z0-9_]*\}")


def parse_mapped(text: str, placeholders: bool = False) -> MappedName:
    """`"name"` or `"name : pkg/kind/Type"`, its name resolved in the root namespace (the
    platform resolves the names under the node's namespace with `resolve`). With
    `placeholders`, the name may have placeholders (`"/{r}/battery"`:
    gpp.platform.ros2.placeholders): such a name is kept as written, and each name it stands
    for is resolved once its placeholders are filled."""
    name, sep, type_name = text.partition(":")
    name = name.strip()
    if placeholders and "{" in type_name:
        raise NameError_(f'"{text}": the type after `:` cannot have a placeholder (it is the same for every name)')
    checked = _PLACEHOLDER.sub("x", name) if placeholders else name
    if not _NAME.match(checked):
        raise NameError_(
            f'"{text}" is not a ROS 2 name: write "/name" or "/name : package/action/Type" '
            "(names are letters, digits and `_`, separated by `/`)"
        )
    t = type_name.strip() if sep else None
    if sep and not t:
        raise NameError_(f'"{text}": the type after `:` is missing (write "/name : package/action/Type")')
    if checked != name:
        return MappedName(name, t, name)  # placeholders: resolved once filled
    return MappedName(resolve(name), t, name)
