"""The mapped name of the ros2 platform: `"/name"` or `"/name : package/kind/Type"`.

Kept free of rclpy so that the binding file and the mappings can be read (and their errors
reported) on a machine without ROS.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_NAME = re.compile(r"^~?/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")


class NameError_(ValueError):
    """A mapped name that is not a ROS 2 name (with an optional type)."""


@dataclass(frozen=True)
class MappedName:
    name: str  # absolute: "/stack"
    type: str | None  # "pkg/action/Type" as written, or None: looked up in the graph


def normalize(name: str) -> str:
    """A ROS name relative to the agent node (which lives in the root namespace) as an
    absolute one: `stack` and `/stack` are the same name."""
    name = name.strip()
    if name.startswith("~"):
        name = name[1:]
    return name if name.startswith("/") else "/" + name


_PLACEHOLDER = re.compile(r"\{[A-Za-z_][A-Za-z0-9_]*\}")


def parse_mapped(text: str, placeholders: bool = False) -> MappedName:
    """`"/name"` or `"/name : pkg/kind/Type"`; with `placeholders`, the name may have
    placeholders (`"/{r}/battery"`: gpp.platform.ros2.placeholders), kept in `name`."""
    name, sep, type_name = text.partition(":")
    name = name.strip()
    if placeholders and "{" in type_name:
        raise NameError_(f'"{text}": the type after `:` cannot have a placeholder (it is the same for every name)')
    if not _NAME.match(_PLACEHOLDER.sub("x", name) if placeholders else name):
        raise NameError_(
            f'"{text}" is not a ROS 2 name: write "/name" or "/name : package/action/Type" '
            "(names are letters, digits and `_`, separated by `/`)"
        )
    t = type_name.strip() if sep else None
    if sep and not t:
        raise NameError_(f'"{text}": the type after `:` is missing (write "/name : package/action/Type")')
    return MappedName(normalize(name), t)
