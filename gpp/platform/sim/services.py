"""What the sim serves, by mapped name (like ROS action servers), and the check of a program's
mappings against it when the program attaches: an unknown name or argument is a problem
message with the available names and a did-you-mean."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from gpp.model.types import DomainType, Type
from gpp.platform.base import ExogSignature, ProgramInterface
from gpp.platform.sim.task import closest
from gpp.platform.sim.world import World
from gpp.runtime.values import Value


@dataclass(frozen=True)
class Service:
    """A low-level action the sim serves: its argument names, the scene it needs, and
    whether it returns a sensing result."""

    args: tuple[str, ...]
    scene: str  # "workbench" or "map"
    senses: bool = False
    doc: str = ""


SERVICES: dict[str, Service] = {
    "/stack": Service(
        ("block", "location"),
        "workbench",
        doc="pick `block`, put it on slot or block `location`, release, wait until the pile settles",
    ),
    "/get_block_pose": Service(
        ("block",), "workbench", senses=True, doc="what `block` rests on, read from its contacts"
    ),
    "/gripper_home": Service((), "workbench", doc="move the empty gripper to its home position"),
    "/navigate_to_frame": Service(("frame",), "map", doc="drive the robot to map frame `frame`"),
}

BATTERY_EVENT = "/battery"


def produced_events(world: World) -> dict[str, tuple[str, ...]]:
    """Exogenous events the world can produce -> their field names."""
    events = world.region_events()
    if world.map is not None and world.map.battery is not None:
        events[BATTERY_EVENT] = ("level",)
    return dict(sorted(events.items()))


def did_you_mean(name: str, known: list[str]) -> str:
    hint = closest(name, known)
    return f"; did you mean `{hint}`?" if hint else ""


def _names(names: list[str] | tuple[str, ...]) -> str:
    return ", ".join(f"`{n}`" for n in names) if names else "none"


def check_interface(interface: ProgramInterface, world: World) -> list[str]:
    """Problems with the program's mappings in this world; empty when everything fits."""
    problems: list[str] = []
    served = sorted(SERVICES)
    unknown_action = unknown_event = False
    for action, (mapped, args) in sorted(interface.actions.items()):
        service = SERVICES.get(mapped)
        if service is None:
            problems.append(
                f'action `{action}` is mapped to "{mapped}", which the sim does not serve{did_you_mean(mapped, served)}'
            )
            unknown_action = True
            continue
        scene = world.workbench if service.scene == "workbench" else world.map
        if scene is None:
            problems.append(f'action `{action}`: "{mapped}" needs a {service.scene}, and world `{world.name}` has none')
        for arg in args:
            if arg not in service.args:
                problems.append(
                    f'action `{action}`: "{mapped}" has no argument `{arg}`{did_you_mean(arg, list(service.args))}'
                    f" (its arguments: {_names(service.args)})"
                )
        missing = [a for a in service.args if a not in args]
        if missing:
            problems.append(f'action `{action}`: the mapping to "{mapped}" must give {_names(missing)}')
        if action in interface.sensing:
            if not service.senses:
                problems.append(f'action `{action}` senses a value, but "{mapped}" returns no result')
            elif mapped == "/get_block_pose" and world.workbench is not None:
                problems.extend(_sensed_type(action, interface.sensing[action], world))
    events = produced_events(world)
    for name, signature in sorted(interface.exog_actions.items()):
        fields = events.get(signature.mapped_name)
        if fields is None:
            known = list(events)
            problems.append(
                f'exogenous action `{name}` is mapped to "{signature.mapped_name}", which world `{world.name}` '
                f"does not produce{did_you_mean(signature.mapped_name, known)}"
            )
            unknown_event = True
            continue
        for backend_field in signature.fields:
            if backend_field not in fields:
                problems.append(
                    f'exogenous action `{name}`: "{signature.mapped_name}" has no field `{backend_field}`'
                    f"{did_you_mean(backend_field, list(fields))} (its fields: {_names(fields)})"
                )
        problems.extend(_event_values(name, signature, world))
    if unknown_action:
        problems.append("the sim serves " + _signatures({n: s.args for n, s in SERVICES.items()}))
    if unknown_event:
        problems.append(f"world `{world.name}` produces " + _signatures(events))
    return problems


def _signatures(items: Mapping[str, tuple[str, ...]]) -> str:
    if not items:
        return "nothing"
    return ", ".join(f'"{name}" {{{", ".join(args)}}}' for name, args in sorted(items.items()))


def _sensed_type(action: str, t: Type, world: World) -> list[str]:
    if not isinstance(t, DomainType):
        return []
    assert world.workbench is not None
    wb = world.workbench
    possible = [*(s.name for s in wb.slots), *(b.name for b in wb.blocks), "table", "floor"]
    values = {getattr(v, "name", v) for v in t.values}
    missing = [p for p in possible if p not in values]
    if not missing:
        return []
    return [
        f'action `{action}` senses into type `{t.name}`, which lacks {_names(missing)}: "/get_block_pose" can report '
        f"these in world `{world.name}`"
    ]


def _event_values(name: str, signature: ExogSignature, world: World) -> list[str]:
    """Every value a region of the world sends for this event must fit the parameter types."""
    from gpp.platform.dummy import ScenarioError, to_value

    problems: list[str] = []
    if world.map is None:
        return problems
    types = dict(zip(signature.params, signature.param_types, strict=True))
    for region in world.map.regions:
        if region.event != signature.mapped_name:
            continue
        for backend_field, param in signature.fields.items():
            if backend_field not in region.fields or param not in types:
                continue
            try:
                to_value(region.fields[backend_field], types[param])
            except ScenarioError as e:
                problems.append(f"exogenous action `{name}`: region `{region.name}` sends {backend_field}: {e}")
    return problems


def event_args(signature: ExogSignature, fields: Mapping[str, object]) -> tuple[Value, ...] | None:
    """The argument values of an exogenous action, in parameter order, from event fields."""
    from gpp.platform.dummy import ScenarioError, to_value

    by_param = {param: backend for backend, param in signature.fields.items()}
    args: list[Value] = []
    for param, t in zip(signature.params, signature.param_types, strict=True):
        backend = by_param.get(param, param)
        if backend not in fields:
            return None
        try:
            args.append(to_value(fields[backend], t))
        except ScenarioError:
            return None
    return tuple(args)
