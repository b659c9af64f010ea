"""The trace's events: one frozen dataclass per kind of record, and their one JSON encoding.

A trace is JSON lines, one object per event: `t` (the platform's clock, rounded to 6 decimals),
`event` (the kind, e.g. `"start"`), then the event's fields in the order they are declared
here. The field names are the JSON keys. A field marked optional is left out of the JSON when
it has its default value (so `"silent": true` appears only on the records of a silent action,
`"precondition": false` only on an exogenous event whose precondition was false). A few
optional fields can be JSON `null` when present; for them "absent" is `ABSENT`, not None.

The format is versioned (`TRACE_SCHEMA_VERSION`) and described by the JSON Schema
`gpp/trace.schema.json` and by docs/trace.md. Within a major version fields may be added (a
reader ignores keys it does not know); removing or renaming a field, or changing its meaning,
bumps the major version.
"""

from __future__ import annotations

import dataclasses
import importlib.resources
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, ClassVar, Final, TypeAlias, TypeVar, cast

from gpp.runtime.values import Value, to_json

TRACE_SCHEMA_VERSION: Final = "1.8"
# The JSON Schema (draft 2020-12) of a trace record, shipped inside the package.
SCHEMA_RESOURCE: Final = "trace.schema.json"

# What a `waiting` record's `reason` can be: a false test, a false precondition, a planned
# activity that runs, a `solve`/`search` without a feasible plan, an exogenous function's
# answer, anything else (an event or an activity update).
WAIT_REASONS: Final = ("test", "precondition", "activity", "no-plan", "answer", "event")

JsonValue: TypeAlias = bool | int | float | str | list["JsonValue"] | dict[str, "JsonValue"] | None


class Absent(Enum):
    """The type of ABSENT: an optional field that can be `null` is left out of the JSON."""

    ABSENT = "absent"

    def __repr__(self) -> str:
        return "ABSENT"


ABSENT: Final = Absent.ABSENT

_OPTIONAL: Final = {"optional": True}
_TUPLE: Final = {"tuple": True}


def fluent_change(fluent: str, value: Value) -> dict[str, JsonValue]:
    """One entry of the `changes` of an `end` or `exog` record."""
    return {"fluent": fluent, "value": json_value(value)}


def json_value(value: Value) -> JsonValue:
    """A golog++ value as it appears in the trace (gpp.runtime.values.to_json)."""
    return cast(JsonValue, to_json(value))


@dataclass(frozen=True, slots=True, kw_only=True)
class EventBase:
    """What every event has: `t`, the platform time it happened at (rounded to 6 decimals)."""

    EVENT: ClassVar[str] = ""

    t: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "t", round(float(self.t), 6))


# ---------------------------------------------------------------- the run


@dataclass(frozen=True, slots=True, kw_only=True)
class HeaderEvent(EventBase):
    """What was run: the first record of a trace."""

    EVENT: ClassVar[str] = "header"

    schema_version: str  # TRACE_SCHEMA_VERSION of the writer
    gpp_version: str
    program: str  # the program's path as given
    program_sha256: str  # of the program file's bytes
    platform: str
    world: str | None = field(default=None, metadata=_OPTIONAL)
    scenario: str | None = field(default=None, metadata=_OPTIONAL)
    seed: int | None = field(default=None, metadata=_OPTIONAL)
    # Since 1.5, on ros2: the agent's node, fully qualified (`/robot1/courier`).
    node: str | None = field(default=None, metadata=_OPTIONAL)
    started: str  # wall-clock start, ISO-8601 with time zone
    # In a part after the first of a split trace (gpp.runtime.trace): its number (1, 2, ...)
    # and the file name of the part before it; left out in the first part.
    part: int | None = field(default=None, metadata=_OPTIONAL)
    previous: str | None = field(default=None, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class SnapshotEvent(EventBase):
    """The run's state where a part of a split trace begins (its second record): what a reader
    or a replay starting from this part needs of what came before."""

    EVENT: ClassVar[str] = "snapshot"

    # The fluent instances whose value is not their initial one (`{"fluent": ..., "value": ...}`).
    fluents: tuple[dict[str, JsonValue], ...] = field(metadata=_TUPLE)
    # The activities started and not consumed yet (`{"action": ..., "id": ..., "status": ...}`).
    activities: tuple[dict[str, JsonValue], ...] = field(metadata=_TUPLE)
    # What the program waits for (`statement`, `at`, `condition` of its `waiting` record, and
    # since 1.5 its `reason`, `action` and `plan_step` where it has them), if it waits.
    waiting: dict[str, JsonValue] | None = field(default=None, metadata=_OPTIONAL)
    # The counts of the `finish` record, so far.
    actions: int
    failures: int
    exog_events: int


@dataclass(frozen=True, slots=True, kw_only=True)
class FinishEvent(EventBase):
    """The run ended (always the last record)."""

    EVENT: ClassVar[str] = "finish"

    status: str  # a RunStatus value: finished, blocked, error, timeout, interrupted
    actions: int
    failures: int
    # Left out when the run stopped before the program ran (it does not fit the platform).
    unhandled_failures: int | None = field(default=None, metadata=_OPTIONAL)
    exog_events: int


@dataclass(frozen=True, slots=True, kw_only=True)
class BlockedEvent(EventBase):
    """Nothing can step and nothing can arrive any more: the run stops."""

    EVENT: ClassVar[str] = "blocked"

    message: str
    at: str | None  # source location of what the program waits for, if known


@dataclass(frozen=True, slots=True, kw_only=True)
class ErrorEvent(EventBase):
    """The run stops on an error (or an interrupt: then there is neither `code` nor `at`)."""

    EVENT: ClassVar[str] = "error"

    code: str | None = field(default=None, metadata=_OPTIONAL)
    message: str
    at: str | Absent | None = field(default=ABSENT, metadata=_OPTIONAL)  # present exactly when `code` is

    def __post_init__(self) -> None:
        EventBase.__post_init__(self)
        if (self.code is None) != (self.at is ABSENT):
            raise ValueError("an `error` event has both `code` and `at` (null when there is no location) or neither")


@dataclass(frozen=True, slots=True, kw_only=True)
class WaitingEvent(EventBase):
    """The program is blocked on a condition and something can still arrive;
    with `resumed`, the condition became true and the program goes on."""

    EVENT: ClassVar[str] = "waiting"

    statement: str  # the statement's text
    at: str | None  # its source location
    condition: str  # the condition that is false
    resumed: bool = field(default=False, metadata=_OPTIONAL)
    # Since 1.5: what kind of thing it waits for (WAIT_REASONS); for a planned activity, the
    # activity and the number of its step in the plan.
    reason: str | None = field(default=None, metadata=_OPTIONAL)
    action: str | None = field(default=None, metadata=_OPTIONAL)
    plan_step: int | None = field(default=None, metadata=_OPTIONAL)


def waiting_fields(event: WaitingEvent) -> dict[str, JsonValue]:
    """What a snapshot (and the ros2 platform's state topic) says of a wait: its statement,
    place and condition, and those of `reason`, `action` and `plan_step` it has."""
    fields: dict[str, JsonValue] = {"statement": event.statement, "at": event.at, "condition": event.condition}
    for name in ("reason", "action", "plan_step"):
        value = getattr(event, name)
        if value is not None:
            fields[name] = value
    return fields


@dataclass(frozen=True, slots=True, kw_only=True)
class StepEvent(EventBase):
    """Since 1.7, in a trace recorded with steps (`gpp run --trace-steps`): the program takes
    its next transition (written before the records of what the transition does), so that a
    replay can stop where a debugger stopped the live run."""

    EVENT: ClassVar[str] = "step"

    at: str | None  # the statement that takes the transition
    step: str  # what it does: `test`, `start(goto(a))`, `end(goto(a))`, `loc = a`, `plan`, ...
    # The procedure calls the statement is in, innermost first: `{"procedure": "deliver",
    # "args": {"r": ...}, "at": the call's location or null}` each (the entry procedure last).
    frames: tuple[dict[str, JsonValue], ...] = field(default=(), metadata={**_OPTIONAL, **_TUPLE})
    # When the calls are more than `frames` lists (a deep recursion: the innermost ones and the
    # entry procedure are listed), how many there are.
    depth: int | None = field(default=None, metadata=_OPTIONAL)
    # The transition goes on with a statement an earlier one began (the end of a call or of a
    # `during`) or plans again: a debugger's stepping does not stop at it, a breakpoint does.
    continues: bool = field(default=False, metadata=_OPTIONAL)


# ---------------------------------------------------------------- activities


@dataclass(frozen=True, slots=True, kw_only=True)
class StartEvent(EventBase):
    """An activity was started on the platform."""

    EVENT: ClassVar[str] = "start"

    action: str  # ground action text, e.g. `go(kitchen)`
    id: int  # the activity's id (in `update` and `cancel` records too)
    mapped: str  # the name the platform knows the action by
    args: dict[str, JsonValue]  # mapped argument names to values
    at: str | None  # source location of the statement that started it
    silent: bool = field(default=False, metadata=_OPTIONAL)
    # Since 1.6: the fluent instances its `start_effect:` section set.
    changes: tuple[dict[str, JsonValue], ...] = field(default=(), metadata={**_OPTIONAL, **_TUPLE})


@dataclass(frozen=True, slots=True, kw_only=True)
class UpdateEvent(EventBase):
    """The platform reports that an activity terminated."""

    EVENT: ClassVar[str] = "update"

    action: str
    status: str  # final, failed or cancelled
    id: int
    reason: str | None = field(default=None, metadata=_OPTIONAL)
    result: JsonValue | Absent = field(default=ABSENT, metadata=_OPTIONAL)  # a sensing result (may be null)
    silent: bool = field(default=False, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class EndEvent(EventBase):
    """The program consumed a terminated activity (`end`, `finish`, `fail`, a call or `during`)."""

    EVENT: ClassVar[str] = "end"

    action: str
    status: str  # final, failed or cancelled
    hook: str  # end, finish, fail, call or during
    unhandled: bool = field(default=False, metadata=_OPTIONAL)  # a failure nothing in the program handles
    silent: bool = field(default=False, metadata=_OPTIONAL)
    # The fluent instances its effects set (`{"fluent": "loc(a)", "value": ...}`), when it ended final.
    changes: tuple[dict[str, JsonValue], ...] = field(default=(), metadata={**_OPTIONAL, **_TUPLE})


@dataclass(frozen=True, slots=True, kw_only=True)
class CancelEvent(EventBase):
    """An activity is preempted (by the program, or because the run ends)."""

    EVENT: ClassVar[str] = "cancel"

    action: str
    id: int
    reason: str | None = field(default=None, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class SenseEvent(EventBase):
    """An action's `senses:` section set a fluent."""

    EVENT: ClassVar[str] = "sense"

    action: str
    fluent: str  # the fluent instance, e.g. `pos(a)`
    value: JsonValue
    silent: bool = field(default=False, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class NoticeEvent(EventBase):
    """The platform says something the program goes on without: about an activity (its server
    refused to cancel it and it still runs, its message reached no subscriber) or about the
    platform itself."""

    EVENT: ClassVar[str] = "notice"

    message: str
    action: str | None = field(default=None, metadata=_OPTIONAL)  # the activity it is about, if any
    id: int | None = field(default=None, metadata=_OPTIONAL)


# ---------------------------------------------------------------- the world


@dataclass(frozen=True, slots=True, kw_only=True)
class ExogEvent(EventBase):
    """An exogenous action happened (its effects are applied)."""

    EVENT: ClassVar[str] = "exog"

    action: str
    precondition: bool = field(default=True, metadata=_OPTIONAL)  # written only when false
    silent: bool = field(default=False, metadata=_OPTIONAL)
    # The fluent instances its effects set (`{"fluent": "loc(a)", "value": ...}`).
    changes: tuple[dict[str, JsonValue], ...] = field(default=(), metadata={**_OPTIONAL, **_TUPLE})
    # Written only when true: its effects could not be applied (the `error` record that follows
    # says why) and the run stops there.
    failed: bool = field(default=False, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class DroppedEvent(EventBase):
    """The platform dropped what came in for an exogenous action or function: a message whose
    fields do not fit its parameters, or messages lost on the way (`count` of them)."""

    EVENT: ClassVar[str] = "dropped"

    source: str  # where it came from, e.g. a ROS topic
    target: str  # the exogenous action or function it was for
    reason: str
    count: int = field(default=1, metadata=_OPTIONAL)  # written only when more than one
    at: str | None  # source location of the mapping it is about


@dataclass(frozen=True, slots=True, kw_only=True)
class WarningEvent(EventBase):
    """A warning during the run that stops nothing (R0015: the platform dropped a message that
    does not fit, or warns about its setup)."""

    EVENT: ClassVar[str] = "warning"

    code: str
    message: str
    at: str | None


@dataclass(frozen=True, slots=True, kw_only=True)
class AssignEvent(EventBase):
    """The program assigned a fluent instance."""

    EVENT: ClassVar[str] = "assign"

    fluent: str
    value: JsonValue
    at: str | None


# ---------------------------------------------------------------- the operator

# What an `operator` record's `command` can be (the operator console, `gpp run --console`).
OPERATOR_COMMANDS: Final = ("start", "pause", "resume", "stop", "exog", "act")


@dataclass(frozen=True, slots=True, kw_only=True)
class OperatorEvent(EventBase):
    """Since 1.8: an operator did something at the console (`gpp run --console`): started,
    paused, resumed or stopped the run, sent an exogenous event, or had an action run before
    the start."""

    EVENT: ClassVar[str] = "operator"

    command: str  # one of OPERATOR_COMMANDS
    # The exogenous event sent or the action run (`exog`, `act`).
    action: str | None = field(default=None, metadata=_OPTIONAL)
    # Who: the address of the browser that asked (`127.0.0.1`, `[::1]`, `192.168.1.20`).
    client: str | None = field(default=None, metadata=_OPTIONAL)


# ---------------------------------------------------------------- planning


@dataclass(frozen=True, slots=True, kw_only=True)
class PlanEvent(EventBase):
    """`solve`/`search` made a plan."""

    EVENT: ClassVar[str] = "plan"

    kind: str  # solve or search
    feasible: bool
    value: float  # the plan's summed reward (0 for search and for no plan)
    horizon: int
    policy: tuple[str, ...] = field(metadata=_TUPLE)  # the plan's steps
    nodes: int
    cache_hits: int
    pruned: int
    reward_evaluations: int
    seconds: float  # planning time (wall clock)
    # A `solve` plan that uses its whole horizon with the program unfinished, and the fewest
    # costed steps that would finish it (left out when not found).
    unfinished: bool = field(default=False, metadata=_OPTIONAL)
    steps_left: int | None = field(default=None, metadata=_OPTIONAL)


@dataclass(frozen=True, slots=True, kw_only=True)
class ReplanEvent(EventBase):
    """A plan was made again from where the program is (its fields are those of `plan`)."""

    EVENT: ClassVar[str] = "replan"

    kind: str
    feasible: bool
    value: float
    horizon: int
    policy: tuple[str, ...] = field(metadata=_TUPLE)
    nodes: int
    cache_hits: int
    pruned: int
    reward_evaluations: int
    seconds: float
    unfinished: bool = field(default=False, metadata=_OPTIONAL)
    steps_left: int | None = field(default=None, metadata=_OPTIONAL)
    # Since 1.5: why it was planned again, and a `solve`'s horizon as written (`horizon` is
    # what the steps already executed left of it).
    reason: str | None = field(default=None, metadata=_OPTIONAL)
    written_horizon: int | None = field(default=None, metadata=_OPTIONAL)


TraceEvent: TypeAlias = (
    HeaderEvent
    | SnapshotEvent
    | StartEvent
    | UpdateEvent
    | EndEvent
    | ExogEvent
    | SenseEvent
    | AssignEvent
    | PlanEvent
    | ReplanEvent
    | CancelEvent
    | NoticeEvent
    | WaitingEvent
    | StepEvent
    | BlockedEvent
    | ErrorEvent
    | FinishEvent
    | DroppedEvent
    | WarningEvent
    | OperatorEvent
)

EVENT_TYPES: Final[Mapping[str, type[EventBase]]] = {
    cls.EVENT: cls
    for cls in (
        HeaderEvent,
        SnapshotEvent,
        StartEvent,
        UpdateEvent,
        EndEvent,
        ExogEvent,
        SenseEvent,
        AssignEvent,
        PlanEvent,
        ReplanEvent,
        CancelEvent,
        NoticeEvent,
        WaitingEvent,
        StepEvent,
        BlockedEvent,
        ErrorEvent,
        FinishEvent,
        DroppedEvent,
        WarningEvent,
        OperatorEvent,
    )
}

E = TypeVar("E", bound=EventBase)


@dataclass(frozen=True, slots=True)
class _Field:
    name: str
    optional: bool
    default: object
    as_tuple: bool


def _json_fields(cls: type[EventBase]) -> tuple[_Field, ...]:
    """The JSON fields of an event type after `t`, in order."""
    return tuple(
        _Field(f.name, bool(f.metadata.get("optional")), f.default, bool(f.metadata.get("tuple")))
        for f in dataclasses.fields(cls)
        if f.name != "t"
    )


_FIELDS: Final[Mapping[type[EventBase], tuple[_Field, ...]]] = {cls: _json_fields(cls) for cls in EVENT_TYPES.values()}


def to_json_dict(event: EventBase) -> dict[str, Any]:
    """The event as its JSON object: `t`, `event`, then the fields (optional ones at their
    default left out)."""
    record: dict[str, Any] = {"t": event.t, "event": event.EVENT}
    for f in _FIELDS[type(event)]:
        value = getattr(event, f.name)
        # A tuple field is left out when empty whether or not it is the very same empty tuple.
        if f.optional and (value is f.default or (f.as_tuple and value == f.default)):
            continue
        record[f.name] = list(value) if f.as_tuple else value
    return record


def encode(event: EventBase) -> str:
    """The event as one line of a trace file (without the newline), strict JSON whatever it
    holds: gpp keeps NaN and infinities out of program values (docs/semantics.md, "Numbers"),
    and one that still arrives (from a platform) is written as the string "NaN", "Infinity" or
    "-Infinity" (docs/trace.md)."""
    record = to_json_dict(event)
    try:
        return json.dumps(record, ensure_ascii=False, allow_nan=False)
    except ValueError:
        return json.dumps(_finite(record), ensure_ascii=False, allow_nan=False)


# Whole numbers up to this many bits have at most 4,000 digits: Python writes them as text
# (sys.get_int_max_str_digits() is 4,300 by default).
_WRITABLE_BITS = 13_000


def _finite(value: Any) -> Any:
    """`value` with every non-finite float, and every whole number too long to write as text
    (thousands of digits), replaced by its name as a string."""
    if isinstance(value, float) and not math.isfinite(value):
        return "NaN" if math.isnan(value) else "Infinity" if value > 0 else "-Infinity"
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > _WRITABLE_BITS:
        return "Infinity" if value > 0 else "-Infinity"
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    return value


def from_json_dict(record: Mapping[str, Any]) -> TraceEvent:
    """The event a JSON object describes. Keys this version does not know are ignored (a newer
    minor version may add fields); a missing required field or an unknown kind is a ValueError."""
    kind = record.get("event")
    cls = EVENT_TYPES.get(kind) if isinstance(kind, str) else None
    if cls is None:
        raise ValueError(f"unknown trace event {kind!r}")
    if "t" not in record:
        raise ValueError(f"a `{kind}` record without `t`")
    fields: dict[str, Any] = {"t": record["t"]}
    for f in _FIELDS[cls]:
        if f.name in record:
            value = record[f.name]
            fields[f.name] = tuple(value) if f.as_tuple and isinstance(value, list) else value
        elif not f.optional:
            raise ValueError(f"a `{kind}` record without `{f.name}`")
    return cast(TraceEvent, cls(**fields))


def load_schema() -> dict[str, Any]:
    """The trace record's JSON Schema (gpp/trace.schema.json)."""
    schema: dict[str, Any] = json.loads(importlib.resources.files("gpp").joinpath(SCHEMA_RESOURCE).read_text("utf-8"))
    return schema


def decode(line: str | bytes) -> TraceEvent:
    """One line of a trace file as its event."""
    record = json.loads(line)
    if not isinstance(record, dict):
        raise ValueError("a trace record is a JSON object")
    return from_json_dict(record)


__all__ = [
    "ABSENT",
    "EVENT_TYPES",
    "OPERATOR_COMMANDS",
    "SCHEMA_RESOURCE",
    "TRACE_SCHEMA_VERSION",
    "WAIT_REASONS",
    "Absent",
    "AssignEvent",
    "BlockedEvent",
    "CancelEvent",
    "EndEvent",
    "ErrorEvent",
    "EventBase",
    "ExogEvent",
    "FinishEvent",
    "HeaderEvent",
    "JsonValue",
    "NoticeEvent",
    "OperatorEvent",
    "PlanEvent",
    "ReplanEvent",
    "SenseEvent",
    "SnapshotEvent",
    "StartEvent",
    "StepEvent",
    "TraceEvent",
    "UpdateEvent",
    "WaitingEvent",
    "decode",
    "encode",
    "from_json_dict",
    "json_value",
    "load_schema",
    "to_json_dict",
]
