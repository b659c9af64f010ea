"""What `gpp check` and the language server report of the ros2 platform's mappings: a mapping
that names its type (`"/stack : my_robot/action/Stack" { ... }`) is checked against the
message classes as at attach (fields with a did-you-mean, value types, constants' ranges, the
sensed result), where the ROS 2 packages are installed. Without them, or without such a
mapping, nothing is reported and nothing of ROS is imported; a type whose package is not
installed here is left to the run (a robot's own package may be importable only there).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gpp.model.symbols import SymbolKind
from gpp.platform.ros2.names import NameError_, parse_mapped
from gpp.syntax import ast

if TYPE_CHECKING:
    from gpp.model.model import Model
    from gpp.platform.base import Problem


def check(model: Model) -> list[Problem]:
    typed = typed_mappings(model)
    if not typed:
        return []
    import importlib.util

    try:
        from gpp.platform.ros2 import checks
        from gpp.platform.ros2.binding import Binding
        from gpp.platform.ros2.interfaces import InterfaceError, split_type_name
    except ImportError:  # the ros extra is not installed
        return []
    from gpp.runtime.compiled import CompiledProgram
    from gpp.runtime.contract import program_interface

    def installed(type_name: str) -> bool:
        try:
            package = split_type_name(type_name)[0]
        except InterfaceError:
            return True  # not a type name: reported
        return importlib.util.find_spec(package) is not None

    checkable = {name for name, type_name in typed.items() if installed(type_name)}
    if not checkable:
        return []
    interface = program_interface(CompiledProgram(model))
    binding = Binding()
    graph = checks.Graph(None)
    problems: list[Problem] = []
    for name, action in sorted(interface.actions.items()):
        if name in checkable:
            problems.extend(checks.action_target(action, binding, graph)[1])
    for name, exog in sorted(interface.exog_actions.items()):
        if name in checkable:
            problems.extend(checks.exog_route(exog, binding, graph)[1])
    return problems


def typed_mappings(model: Model) -> dict[str, str]:
    """Action and exogenous action name -> the type its mapping names (`"/name : type"`)."""
    typed: dict[str, str] = {}
    for symbol in model.globals.values():
        if symbol.kind not in (SymbolKind.ACTION, SymbolKind.EXOG_ACTION) or not isinstance(
            symbol.decl, ast.ActionDecl
        ):
            continue
        section = symbol.decl.section(ast.MappingSection)
        if not isinstance(section, ast.MappingSection) or ":" not in section.mapping.name.value:
            continue
        if "::" in section.mapping.name.value:
            continue  # Fawkes's `Interface::id` (golog++ on Fawkes), never a ROS name with a type
        try:
            mapped = parse_mapped(section.mapping.name.value)
        except NameError_:
            continue
        if mapped.type is not None:
            typed[symbol.name] = mapped.type
    return typed
