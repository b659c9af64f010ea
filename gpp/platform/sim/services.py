"""What the sim serves, by mapped name (like ROS action servers), and the check of a program's
mappings against it when the program attaches: an unknown name or argument is a problem
message with the available names and a did-you-mean.

An action or exogenous action without a `mapping:` is not the world's: the scenario serves it
(gpp.platform.sim.platform), and so does it an explicitly mapped one that the scenario names."""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass

from gpp.base.suggest import did_you_mean
from gpp.model.types import DomainType, Type
from gpp.platform.base import ActionBinding, ExogActionBinding, Problem, ProgramInterface
from gpp.platform.sim.world import World
from gpp.platform.values import ConversionError, to_value
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
    """Exogenous events the world can produce -> their field names. The battery's event is
    known in every world (sim/navigation.gpp maps it): without `[map.battery]` it never
    happens."""
    events = world.region_events()
    events[BATTERY_EVENT] = ("level",)
    return dict(sorted(events.items()))


def _names(names: list[str] | tuple[str, ...]) -> str:
    return ", ".join(f"`{n}`" for n in names) if names else "none"


def check_interface(
    interface: ProgramInterface,
    world: World,
    scripted_actions: Collection[str] = (),
    scripted_exogs: Collection[str] = (),
) -> list[Problem]:
    """Problems with the program's mappings in this world, each at the mapping it is about;
    empty when everything fits. What the scenario names (`scripted_actions`,
    `scripted_exogs`) and what has no mapping is the scenario's, unless the sim serves it."""
    problems: list[Problem] = []
    served_note = "the sim serves " + _signatures({n: s.args for n, s in SERVICES.items()})
    for name, binding in sorted(interface.actions.items()):
        if binding.mapped_name not in SERVICES and (not binding.explicit or name in scripted_actions):
            continue
        problems.extend(_check_action(name, binding, world, served_note))
    events = produced_events(world)
    produced_note = f"world `{world.name}` produces " + _signatures(events)
    for name, signature in sorted(interface.exog_actions.items()):
        fields = events.get(signature.mapped_name)
        if fields is None and (not signature.explicit or name in scripted_exogs):
            continue
        if fields is None:
            problems.append(
                Problem(
                    f'exogenous action `{name}` is mapped to "{signature.mapped_name}", which world `{world.name}` '
                    "does not produce",
                    signature.span,
                    "not produced by the sim",
                    notes=(produced_note,),
                    help=did_you_mean(signature.mapped_name, events),
                )
            )
            continue
        for backend_field in signature.fields:
            if backend_field not in fields:
                problems.append(
                    Problem(
                        f'exogenous action `{name}`: "{signature.mapped_name}" has no field `{backend_field}` '
                        f"(its fields: {_names(fields)})",
                        signature.field_spans.get(backend_field, signature.span),
                        "no such field",
                        help=did_you_mean(backend_field, fields),
                    )
                )
        problems.extend(_event_values(name, signature, world))
    return problems


def _check_action(name: str, binding: ActionBinding, world: World, served_note: str) -> list[Problem]:
    mapped = binding.mapped_name
    service = SERVICES.get(mapped)
    if service is None:
        return [
            Problem(
                f'action `{name}` is mapped to "{mapped}", which the sim does not serve',
                binding.span,
                "not served by the sim",
                notes=(
                    served_note,
                    f"a scenario (`--scenario`) serves what the world does not model: an `[[action]]` rule "
                    f'`match = "{name}"` (or no `mapping:` at all) makes it the scenario\'s',
                ),
                help=did_you_mean(mapped, SERVICES),
            )
        ]
    problems: list[Problem] = []
    scene = world.workbench if service.scene == "workbench" else world.map
    if scene is None:
        problems.append(
            Problem(
                f'action `{name}`: "{mapped}" needs a {service.scene}, and world `{world.name}` has none',
                binding.span,
            )
        )
    for arg in binding.args:
        if arg.name not in service.args:
            problems.append(
                Problem(
                    f'action `{name}`: "{mapped}" has no argument `{arg.name}` (its arguments: {_names(service.args)})',
                    arg.span,
                    "no such argument",
                    help=did_you_mean(arg.name, service.args),
                )
            )
    given = {a.name for a in binding.args}
    missing = [a for a in service.args if a not in given]
    if missing:
        problems.append(
            Problem(f'action `{name}`: the mapping to "{mapped}" must give {_names(missing)}', binding.span)
        )
    if mapped == "/navigate_to_frame" and world.map is not None:
        problems.extend(_unknown_frames(binding, world))
    if binding.sensing is not None:
        if not service.senses:
            problems.append(Problem(f'action `{name}` senses a value, but "{mapped}" returns no result', binding.span))
        elif mapped == "/get_block_pose" and world.workbench is not None:
            problems.extend(_sensed_type(binding, binding.sensing, world))
    return problems


def _signatures(items: Mapping[str, tuple[str, ...]]) -> str:
    if not items:
        return "nothing"
    return ", ".join(f'"{name}" {{{", ".join(args)}}}' for name, args in sorted(items.items()))


def _unknown_frames(binding: ActionBinding, world: World) -> list[Problem]:
    """Every value the `frame` argument can take must be a frame of the world's map."""
    assert world.map is not None
    frames = [f.name for f in world.map.frames]
    problems: list[Problem] = []
    for arg in binding.args:
        if arg.name != "frame" or not isinstance(arg.type, DomainType):
            continue
        missing = [str(getattr(v, "name", v)) for v in arg.type.values if getattr(v, "name", v) not in frames]
        if missing:
            problems.append(
                Problem(
                    f"action `{binding.name}`: world `{world.name}` has no frame {_names(missing)} "
                    f"(its frames: {_names(frames)})",
                    arg.span,
                    "not a frame of the map",
                    help="run it in a world that has these frames (`--world`), or add them as `[[map.frame]]`",
                )
            )
    return problems


def _sensed_type(binding: ActionBinding, t: Type, world: World) -> list[Problem]:
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
        Problem(
            f'action `{binding.name}` senses into type `{t.name}`, which lacks {_names(missing)}: "/get_block_pose" '
            f"can report these in world `{world.name}`",
            binding.span,
        )
    ]


def _event_values(name: str, signature: ExogActionBinding, world: World) -> list[Problem]:
    """Every value a region of the world sends for this event must fit the parameter types."""
    problems: list[Problem] = []
    if world.map is None:
        return problems
    types = {p.name: p.type for p in signature.params}
    for region in world.map.regions:
        if region.event != signature.mapped_name:
            continue
        for backend_field, param in signature.fields.items():
            if backend_field not in region.fields or param not in types:
                continue
            try:
                to_value(region.fields[backend_field], types[param])
            except ConversionError as e:
                problems.append(
                    Problem(
                        f"exogenous action `{name}`: region `{region.name}` sends {backend_field}: {e}",
                        signature.field_spans.get(backend_field, signature.span),
                    )
                )
    return problems


def event_args(signature: ExogActionBinding, fields: Mapping[str, object]) -> tuple[Value, ...] | None:
    """The argument values of an exogenous action, in parameter order, from event fields."""
    by_param = {param: backend for backend, param in signature.fields.items()}
    args: list[Value] = []
    for param in signature.params:
        backend = by_param.get(param.name, param.name)
        if backend not in fields:
            return None
        try:
            args.append(to_value(fields[backend], param.type))
        except ConversionError:
            return None
    return tuple(args)
