"""What `gpp check` and the language server report of the ros2 platform's mappings: the
placeholders of mapped names (`"/{r}/navigate"`: gpp.platform.ros2.placeholders), and a mapping
that names its type (`"/stack : my_robot/action/Stack" { ... }`) is checked against the
message classes as at attach (fields with a did-you-mean, value types, constants' ranges, the
sensed result), where the ROS 2 packages are installed. Without them, or without such a
mapping, nothing of ROS is imported and only the placeholders are checked; a type whose package is not
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
    braced = braced_mappings(model)
    if not typed and not braced:
        return []
    from gpp.platform.ros2 import placeholders
    from gpp.runtime.compiled import CompiledProgram
    from gpp.runtime.contract import program_interface

    interface = program_interface(CompiledProgram(model))
    unserved = placeholders.mapping_problems(interface)
    problems: list[Problem] = [p for name in sorted(unserved) for p in unserved[name]]
    typed = {name: t for name, t in typed.items() if name not in unserved}
    if not typed:
        return problems
    import importlib.util

    try:
        from gpp.platform.ros2 import checks
        from gpp.platform.ros2.binding import Binding
        from gpp.platform.ros2.interfaces import InterfaceError, split_type_name
    except ImportError:  # the ros extra is not installed
        return problems

    def installed(type_name: str) -> bool:
        try:
            package = split_type_name(type_name)[0]
        except InterfaceError:
            return True  # not a type name: reported
        return importlib.util.find_spec(package) is not None

    checkable = {name for name, type_name in typed.items() if installed(type_name)}
    if not checkable:
        return problems
    binding = Binding()
    graph = checks.Graph(None)
    # A mapping with placeholders is checked once, as the first name it stands for: every name
    # has the same type.
    for name, action in sorted(interface.actions.items()):
        if name in checkable:
            first = placeholders.bound_instances(action)[0][1]
            problems.extend(checks.action_target(first, binding, graph)[1])
    for name, exog in sorted(interface.exog_actions.items()):
        if name in checkable:
            instance, first_exog = placeholders.bound_instances(exog)[0]
            problems.extend(checks.exog_route(first_exog, binding, graph, instance.values)[1])
    return problems


def _mappings(model: Model) -> list[tuple[str, str]]:
    """(action or exogenous action name, its mapped name as written)."""
    found: list[tuple[str, str]] = []
    for symbol in model.globals.values():
        if symbol.kind not in (SymbolKind.ACTION, SymbolKind.EXOG_ACTION) or not isinstance(
            symbol.decl, ast.ActionDecl
        ):
            continue
        section = symbol.decl.section(ast.MappingSection)
        if isinstance(section, ast.MappingSection):
            found.append((symbol.name, section.mapping.name.value))
    return found


def braced_mappings(model: Model) -> list[str]:
    """The actions and exogenous actions whose mapped names have braces (placeholders)."""
    return [name for name, text in _mappings(model) if "{" in text or "}" in text]


def typed_mappings(model: Model) -> dict[str, str]:
    """Action and exogenous action name -> the type its mapping names (`"/name : type"`)."""
    typed: dict[str, str] = {}
    for name, text in _mappings(model):
        if ":" not in text:
            continue
        if "::" in text:
            continue  # Fawkes's `Interface::id` (golog++ on Fawkes), never a ROS name with a type
        try:
            mapped = parse_mapped(text, placeholders=True)
        except NameError_:
            continue
        if mapped.type is not None:
            typed[name] = mapped.type
    return typed
