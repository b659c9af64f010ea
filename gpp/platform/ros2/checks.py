"""The checks the ros2 platform makes when a program attaches: every mapping whose type is known
(written in the mapping, given in the binding file, or found in the ROS graph right now) is
checked against that type: the type can be imported, the mapping's keys are fields (with a
did-you-mean), the values' types fit the fields, literal constants fit their ranges, and a
sensing action's result fits the sensed type. Each problem is located at the mapping entry
(or the binding file entry) it is about, and all are reported at once.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from rosidl_parser.definition import NamespacedType

from gpp.base.source import Span
from gpp.base.suggest import did_you_mean
from gpp.model.types import CompoundType, Type, base
from gpp.platform.base import (
    ActionBinding,
    ExogActionBinding,
    ExogFunctionSignature,
    Parameter,
    Problem,
    ProgramInterface,
)
from gpp.platform.ros2 import placeholders
from gpp.platform.ros2.binding import Binding, FunctionEntry, NameEntry
from gpp.platform.ros2.interfaces import (
    FieldError,
    Interface,
    InterfaceError,
    convert,
    describe,
    field_at,
    fields,
    load_interface,
    message_problem,
    type_problem,
)
from gpp.platform.ros2.names import MappedName, NameError_, normalize, parse_mapped
from gpp.runtime.values import Value

if TYPE_CHECKING:
    from gpp.platform.ros2.bridge import Bridge

_KIND_WORD = {"action": "an action", "srv": "a service", "msg": "a topic"}


@dataclass
class Target:
    """A mapped action as the platform serves it (made by `action_target`)."""

    binding: ActionBinding
    name: MappedName
    entry: NameEntry
    # None until the graph shows the name's type; then the mapping is checked against it, and
    # the type is kept (no graph look-up per goal) while a server of that type answers.
    interface: Interface | None = None
    from_graph: bool = False
    # The problems found when the mapping was checked against a type from the graph late.
    unfit: tuple[Problem, ...] = ()


class Graph:
    """The names in the ROS graph when the program attaches (kind and type of each). The names
    in `wanted` (those mapped without a type) are waited for until `deadline` (a
    `time.monotonic()` time): discovery takes a moment after the agent's node starts, and a
    mapping is checked before the run only if its type is known by then. A topic that only has
    subscribers is `listened`: its type is enough for an action that publishes on it (the
    names `wanted` with True), not for an exogenous action or function (they need a
    publisher's)."""

    def __init__(self, bridge: Bridge | None, wanted: Mapping[str, bool] | None = None, deadline: float = 0.0) -> None:
        self.known: dict[str, tuple[str, str]] = {}
        self.listened: dict[str, str] = {}
        if bridge is None:
            return
        wanted = wanted or {}
        while True:
            try:
                self.known, self.listened = bridge.call(snapshot, bridge, timeout=5.0)
            except Exception:
                self.known, self.listened = {}, {}
                return
            found = all(self.lookup(name, subscribed) is not None for name, subscribed in wanted.items())
            if found or time.monotonic() >= deadline:
                return
            time.sleep(DISCOVERY_POLL)

    def lookup(self, name: str, subscribed: bool = False) -> tuple[str, str] | None:
        """(kind, type) of `name`; `subscribed`: a topic that only has subscribers counts too."""
        found = self.known.get(name)
        if found is None and subscribed and name in self.listened:
            return "msg", self.listened[name]
        return found


# s between two looks at the graph while waiting for names to be discovered
DISCOVERY_POLL = 0.02


def snapshot(bridge: Bridge) -> tuple[dict[str, tuple[str, str]], dict[str, str]]:
    """Every name in the ROS graph now (on the spin thread): its kind (action, srv, or msg for
    a topic with publishers) and type; and the topics that only have subscribers, with their
    types."""
    from rclpy.action.graph import get_action_names_and_types

    node = bridge.node
    known: dict[str, tuple[str, str]] = {}
    listened: dict[str, str] = {}
    for name, types in node.get_topic_names_and_types():
        if types and node.count_publishers(name) > 0:
            known[name] = ("msg", types[0])
        elif types and node.count_subscribers(name) > 0:
            listened[name] = types[0]
    for name, types in node.get_service_names_and_types():
        if types:
            known[name] = ("srv", types[0])
    for name, types in get_action_names_and_types(node):
        if types:
            known[name] = ("action", types[0])
    return known, listened


def untyped_names(
    interface: ProgramInterface, b: Binding, resolve: Callable[[str], str] | None = None
) -> dict[str, bool]:
    """The ROS names the program maps without a type (in the mapping or the binding file):
    their types come from the graph. True: only actions use the name, and a topic's
    subscribers tell its type as well as a publisher."""
    names: dict[str, bool] = {}
    mapped = [(i, True) for a in interface.actions.values() for i in _instances(a.mapped_name, a.params, resolve)]
    mapped += [
        (i, False) for e in interface.exog_actions.values() for i in _instances(e.mapped_name, e.params, resolve)
    ]
    for text, by_action in mapped:
        try:
            name = parse_mapped(text)
        except NameError_:
            continue
        entry = b.names.get(name.name)
        if name.type is None and (entry is None or entry.type is None):
            names[name.name] = names.get(name.name, True) and by_action
    for f in b.functions.values():
        signature = interface.exog_functions.get(f.function)
        if f.source.type is None:
            params = signature.params if signature is not None else ()
            for text in _instances(f.source.written or f.source.name, params, resolve):
                try:
                    names[parse_mapped(text).name] = False
                except NameError_:
                    continue
    return names


def _instances(text: str, params: Sequence[Parameter], resolve: Callable[[str], str] | None = None) -> list[str]:
    """The names a mapped name stands for (`text` itself without placeholders; none while its
    placeholders cannot be served: they are reported), each resolved by `resolve` (the node's
    resolution of a mapped name, for those with placeholders) when given."""
    if not placeholders.has_braces(text):
        return [text]
    if placeholders.problems("", text, params, None):
        return []
    return [resolve(i.text) if resolve is not None else i.text for i in placeholders.instances(text, params)]


def _parse(mapped: str, span: Span, what: str) -> tuple[MappedName | None, list[Problem]]:
    try:
        return parse_mapped(mapped), []
    except NameError_ as e:
        return None, [Problem(f"{what}: {e}", span, "not a ROS 2 name")]


def _type_name(
    name: MappedName, binding: Binding, graph: Graph, span: Span, what: str, subscribed: bool = False
) -> tuple[str | None, list[Problem]]:
    entry = binding.names.get(name.name)
    declared = name.type
    if entry is not None and entry.type is not None:
        if declared is not None and declared != entry.type:
            return None, [
                Problem(
                    f'{what}: the mapping says "{name.name}" is `{declared}`, the binding file says `{entry.type}`',
                    span,
                    "two types",
                )
            ]
        declared = entry.type
    if declared is None:
        found = graph.lookup(name.name, subscribed)
        if found is not None:
            return found[1], []
    return declared, []


def _load(type_name: str, span: Span, what: str) -> tuple[Interface | None, list[Problem]]:
    try:
        return load_interface(type_name), []
    except InterfaceError as e:
        return None, [Problem(f"{what}: {e}", span, "cannot import this type")]


def action_target(binding: ActionBinding, b: Binding, graph: Graph) -> tuple[Target | None, list[Problem]]:
    what = f"action `{binding.name}`"
    name, problems = _parse(binding.mapped_name, binding.span, what)
    if name is None:
        return None, problems
    entry = b.entry(name.name)
    # An action that publishes on a topic finds its type from the subscribers too.
    type_name, problems = _type_name(name, b, graph, binding.span, what, subscribed=True)
    if problems:
        return None, problems
    if type_name is None:
        return Target(binding, name, entry), []  # checked once the graph shows its type
    iface, problems = _load(type_name, binding.span, what)
    if iface is None:
        return None, problems
    from_graph = name.type is None and entry.type is None
    return Target(binding, name, entry, iface, from_graph), action_problems(binding, name, entry, iface)


def action_problems(binding: ActionBinding, name: MappedName, entry: NameEntry, iface: Interface) -> list[Problem]:
    """What does not fit in an action's mapping (and its binding file entry) to interface
    `iface`: keys that are no fields, values of the wrong type or out of range, stamps, the
    sensed result."""
    what = f"action `{binding.name}`"
    problems: list[Problem] = []
    request = iface.request
    for arg in binding.args:
        try:
            t = field_at(request, arg.name)
        except FieldError as e:
            problems.append(
                Problem(f'{what}: "{name.name}" ({iface.name}): {e}', arg.span, "no such field", help=e.hint)
            )
            continue
        wrong = type_problem(t, arg.type)
        if wrong is not None:
            problems.append(Problem(f"{what}: `{arg.name}`: {wrong}", arg.span, f"the field is {describe(t)}"))
            continue
        if not arg.parameter:
            known, value = literal(arg.span)
            if known:
                try:
                    convert(t, value, arg.name)
                except FieldError as e:
                    problems.append(Problem(f"{what}: {e}", arg.span, f"the field is {describe(t)}"))
    where = entry.span or binding.span
    for path in entry.stamp:
        try:
            t = field_at(request, path)
        except FieldError as e:
            problems.append(Problem(f'binding file: "{name.name}" stamp: {e}', where, help=e.hint))
            continue
        if describe(t) != "builtin_interfaces/Time":
            problems.append(
                Problem(f'binding file: "{name.name}" stamp: `{path}` is {describe(t)}, not a time stamp', where)
            )
    if binding.sensing is not None:
        problems.extend(_result_problems(what, name.name, iface, binding.sensing, entry.result, binding.span, where))
    elif entry.result is not None:
        problems.append(Problem(f'binding file: "{name.name}" result: `{binding.name}` senses nothing', where))
    return problems


def _result_problems(
    what: str, name: str, iface: Interface, sensing: Type, path: str | None, span: Span, entry_span: Span
) -> list[Problem]:
    response = iface.response
    if response is None:
        return [Problem(f'{what} senses a value, but "{name}" is a topic: publishing returns nothing', span)]
    kind = "result" if iface.kind == "action" else "response"
    if path is not None:
        try:
            t = field_at(response, path)
        except FieldError as e:
            return [Problem(f'binding file: "{name}" result: the {kind} of {iface.name}: {e}', entry_span, help=e.hint)]
        wrong = type_problem(t, sensing)
        return [] if wrong is None else [Problem(f"{what}: the sensed {kind} field `{path}`: {wrong}", span)]
    known = fields(response)
    if not known:
        return [Problem(f"{what} senses a value, but the {kind} of {iface.name} has no fields", span)]
    compound = base(sensing)
    if len(known) == 1:
        ((field_name, t),) = known.items()
        if not isinstance(compound, CompoundType) or (
            isinstance(t, NamespacedType) and field_name not in compound.fields
        ):
            # The one field is the sensed value (a message fills the compound).
            wrong = type_problem(t, sensing)
            return [] if wrong is None else [Problem(f"{what}: the {kind} field `{field_name}`: {wrong}", span)]
    if not isinstance(compound, CompoundType):
        return [
            Problem(
                f"{what} senses a {sensing}, but the {kind} of {iface.name} has {len(known)} fields "
                f"({', '.join(known)})",
                span,
                help=f'sense a compound type with these field names, or pick one with `result = "FIELD"` in the '
                f'binding file\'s ["{name}"] entry',
            )
        ]
    wrong = message_problem(response, sensing)
    return [] if wrong is None else [Problem(f"{what}: the sensed {kind}: {wrong}", span)]


def exog_route(
    exog: ExogActionBinding, b: Binding, graph: Graph, from_name: Mapping[str, Value] | None = None
) -> tuple[tuple[str, Interface | None, list[tuple[str, str, Type]]] | None, list[Problem]]:
    """The topic of an exogenous action's mapping, its type when known, and the message field
    that fills each parameter (path, parameter, type); the parameters in `from_name` (the
    values of its placeholders) are filled from the topic's name instead."""
    what = f"exogenous action `{exog.name}`"
    name, problems = _parse(exog.mapped_name, exog.span, what)
    if name is None:
        return None, problems
    by_param = {param: backend for backend, param in exog.fields.items()}
    routes = [(by_param.get(p.name, p.name), p.name, p.type) for p in exog.params if p.name not in (from_name or {})]
    type_name, problems = _type_name(name, b, graph, exog.span, what)
    if problems:
        return None, problems
    if type_name is None:
        return (name.name, None, routes), []
    iface, problems = _load(type_name, exog.span, what)
    if iface is None:
        return None, problems
    problems = route_problems(exog, name.name, iface, routes)
    if problems and iface.kind != "msg":
        return None, problems
    return (name.name, iface, routes), problems


def route_problems(
    exog: ExogActionBinding, name: str, iface: Interface, routes: list[tuple[str, str, Type]]
) -> list[Problem]:
    """What does not fit in an exogenous action's mapping to the topic's type `iface`."""
    what = f"exogenous action `{exog.name}`"
    if iface.kind != "msg":
        return [
            Problem(
                f'{what}: "{name}" is {_KIND_WORD[iface.kind]} ({iface.name}); exogenous actions come from '
                "topics (write `package/msg/Type`)",
                exog.span,
            )
        ]
    problems: list[Problem] = []
    for path, param, t in routes:
        span = exog.field_spans.get(path, exog.span)
        try:
            ft = field_at(iface.cls, path)
        except FieldError as e:
            problems.append(Problem(f'{what}: "{name}" ({iface.name}): {e}', span, "no such field", help=e.hint))
            continue
        wrong = type_problem(ft, t)
        if wrong is not None:
            problems.append(Problem(f"{what}: field `{path}` for parameter `{param}`: {wrong}", span))
    return problems


_SOURCE_KIND = {"topic": "msg", "service": "srv", "feedback": "action"}


def function_source(
    entry: FunctionEntry,
    signature: ExogFunctionSignature,
    graph: Graph,
    known: str | None = None,
    from_name: frozenset[str] = frozenset(),
) -> tuple[Interface | None, list[Problem]]:
    """The interface that answers an exogenous function, checked against it; `known`: its type
    when the program's mappings say it (the action of a feedback source); `from_name`: the
    parameters its source's name has as placeholders (they are not asked for in a request)."""
    what = f"binding file: [exog_function.{entry.function}]"
    span = entry.span
    problems: list[Problem] = []
    wanted = _SOURCE_KIND[entry.kind]
    type_name = entry.source.type or known
    if type_name is None:
        found = graph.lookup(entry.source.name)
        if found is None:
            return None, [
                Problem(
                    f'{what}: the type of "{entry.source.name}" is not known: write it after the name '
                    f'("{entry.source.name} : package/{wanted}/Type")',
                    span,
                )
            ]
        type_name = found[1]
    try:
        iface = load_interface(type_name)
    except InterfaceError as e:
        return None, [Problem(f"{what}: {e}", span)]
    if iface.kind != wanted:
        return None, [
            Problem(
                f'{what}: "{entry.source.name}" is {_KIND_WORD[iface.kind]} ({iface.name}), not {_KIND_WORD[wanted]}',
                span,
            )
        ]
    params = {p.name: p.type for p in signature.params if p.name not in from_name}
    if entry.kind != "service" and params:
        problems.append(
            Problem(
                f"{what}: `{entry.function}` has parameters ({', '.join(params)}); a {entry.kind} answers only a "
                'function whose parameters are placeholders of its name (such as "/{r}/battery"; use a service '
                "for other parameters)",
                span,
            )
        )
    if entry.kind == "service":
        given = dict(entry.request)
        for p in params:
            if p not in given.values():
                given[p] = p
        for path, param in given.items():
            if param not in params:
                problems.append(
                    Problem(
                        f"{what} request: `{entry.function}` has no parameter `{param}`",
                        span,
                        help=did_you_mean(param, params),
                    )
                )
                continue
            try:
                t = field_at(iface.request, path)
            except FieldError as e:
                problems.append(Problem(f"{what}: the request of {iface.name}: {e}", span, help=e.hint))
                continue
            wrong = type_problem(t, params[param])
            if wrong is not None:
                problems.append(Problem(f"{what}: request field `{path}` for parameter `{param}`: {wrong}", span))
    answer = {"srv": iface.response, "action": getattr(iface.cls, "Feedback", None)}.get(iface.kind, iface.cls)
    kind = {"srv": "response", "action": "feedback"}.get(iface.kind, "message")
    if entry.field is not None:
        try:
            t = field_at(answer, entry.field)
        except FieldError as e:
            problems.append(Problem(f"{what} field: the {kind} of {iface.name}: {e}", span, help=e.hint))
        else:
            wrong = type_problem(t, signature.return_type)
            if wrong is not None:
                problems.append(Problem(f"{what}: field `{entry.field}`: {wrong}", span))
    else:
        answer_fields = fields(answer)
        if len(answer_fields) != 1 and not isinstance(base(signature.return_type), CompoundType):
            problems.append(
                Problem(
                    f"{what}: the {kind} of {iface.name} has {len(answer_fields)} fields ({', '.join(answer_fields)}): "
                    f'say which one answers `{entry.function}` with `field = "NAME"`',
                    span,
                )
            )
    return iface, problems


def unused_entries(
    b: Binding, interface: ProgramInterface, resolve: Callable[[str], str] | None = None
) -> list[Problem]:
    """Binding file entries for ROS names that no mapping of the program uses."""
    used: set[str] = set()
    mapped = [t for a in interface.actions.values() for t in _instances(a.mapped_name, a.params, resolve)]
    mapped += [t for e in interface.exog_actions.values() for t in _instances(e.mapped_name, e.params, resolve)]
    for text in mapped:
        try:
            used.add(parse_mapped(text).name)
        except NameError_:
            used.add(normalize(text))
    problems: list[Problem] = []
    for name, entry in b.names.items():
        if name not in used:
            problems.append(
                Problem(
                    f'binding file: ["{name}"]: no mapping of the program uses this ROS name',
                    entry.span,
                    "not mapped",
                    help=did_you_mean(name, used),
                )
            )
    return problems


# ---------------------------------------------------------------- literal constants

_NUMBER = re.compile(r"^-?\d+(\.\d+)?([eE][-+]?\d+)?$")
_STRING = re.compile(r'^"([^"\\]*)"$')


def literal(span: Span) -> tuple[bool, Value]:
    """The value of a mapping entry `name = literal` (number, string, true or false) from its
    source text; (False, None) for any other expression."""
    _, sep, text = span.text.partition("=")
    text = text.strip()
    if not sep:
        return False, None
    if _NUMBER.match(text):
        number = float(text)
        return True, int(number) if number.is_integer() and "." not in text and "e" not in text.lower() else number
    m = _STRING.match(text)
    if m:
        return True, m.group(1)
    if text in ("true", "false"):
        return True, text == "true"
    return False, None
