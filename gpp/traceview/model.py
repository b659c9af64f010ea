"""A run as the viewers see it, built from the trace's events only (gpp.runtime.events).

`load_trace(path)` reads a trace file (TraceReadError with a one-line message for anything
that is not a trace); `build_run_model(events)` pairs each activity's `start` with its `update`,
`cancel` and `end`, puts activities into lanes (one per action name, with extra rows where
activities of that action overlap), and collects exogenous events, plans, waits, problems,
and the numeric series to plot.

Fluent values over time come from `fluent_histories`, the one place that knows which records set a
fluent (assignments, sensing results, and the `changes` of each `start`, `end` and `exog`): a fluent
instance whose values are all numbers is a numeric series (`numeric_samples` adds the numeric
arguments of exogenous events), any other one (a symbol such as where the robot is, a truth
value, text, a list or compound) is a state series: bands of the value it held from one change
to the next (`build_states`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from collections import defaultdict
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gpp.runtime.events import (
    ABSENT,
    TRACE_SCHEMA_VERSION,
    Absent,
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    JsonValue,
    NoticeEvent,
    OperatorEvent,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    SnapshotEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    decode,
)
from gpp.runtime.trace import part_header, trace_parts
from gpp.runtime.values import show_json


class TraceReadError(Exception):
    """The file cannot be read as a trace; the message is one line. `usage` is true when the
    file could not be read at all (missing, a directory, no permission), false when it was
    read and is not a valid trace."""

    def __init__(self, message: str, *, usage: bool = False) -> None:
        super().__init__(message)
        self.usage = usage


@dataclass(frozen=True, slots=True)
class LoadedTrace:
    events: list[TraceEvent]
    # Warnings about what was skipped (an incomplete last line of a run that was killed).
    warnings: list[str] = field(default_factory=list)


def load_trace(path: Path) -> LoadedTrace:
    """The events of a run's trace: a trace file, or all the parts of a split trace given its
    first part or the folder that holds it (gpp.runtime.trace.trace_parts), read as one run:
    the header and snapshot that start each later part are left out. A last line without its
    newline that does not decode is the partial write of a killed run: it is skipped with a
    warning. Blank lines are skipped."""
    if path.is_dir():
        path = _first_part_in(path)
    parts = trace_parts(path)
    loaded = _load_file(parts[0])
    events, warnings = loaded.events, list(loaded.warnings)
    header = events[0] if isinstance(events[0], HeaderEvent) else None
    if header is not None and header.part is not None:
        warnings.append(
            f"{path}: part {header.part} of a split trace (after {header.previous}): the run before it is not read; "
            "give the first part to read the whole run"
        )
    for part in parts[1:]:
        more = _load_file(part)
        events.extend(e for e in more.events if not isinstance(e, HeaderEvent | SnapshotEvent))
        warnings.extend(more.warnings)
    return LoadedTrace(events, warnings)


def _first_part_in(folder: Path) -> Path:
    """The first part of the one trace in `folder` (its `.jsonl` files whose header names no
    earlier part); a TraceReadError when there is none or more than one."""
    try:
        files = sorted(p for p in folder.iterdir() if p.suffix == ".jsonl" and p.is_file())
    except OSError as e:
        raise TraceReadError(f"cannot read '{folder}': {e.strerror or e}", usage=True) from None
    firsts = [p for p in files if (h := part_header(p)) is not None and h.part is None]
    if not firsts:
        raise TraceReadError(f"'{folder}' holds no trace (no .jsonl file that starts with a header)", usage=True)
    if len(firsts) > 1:
        names = ", ".join(p.name for p in firsts[:5]) + (", ..." if len(firsts) > 5 else "")
        raise TraceReadError(f"'{folder}' holds {len(firsts)} traces ({names}): name the one to read", usage=True)
    return firsts[0]


def _load_file(path: Path) -> LoadedTrace:
    """The events of one trace file."""
    try:
        data = path.read_bytes()
    except IsADirectoryError:
        raise TraceReadError(f"cannot read '{path}': it is a directory", usage=True) from None
    except OSError as e:
        raise TraceReadError(f"cannot read '{path}': {e.strerror or e}", usage=True) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise TraceReadError(f"{path}: not a trace (not UTF-8 text); traces are written by `gpp run --trace`") from None
    lines = text.split("\n")
    complete = text.endswith("\n")
    if complete:
        lines.pop()
    events: list[TraceEvent] = []
    warnings: list[str] = []
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            event = decode(line)
            problem = _type_problem(event)
            if problem:
                raise ValueError(problem)
            events.append(event)
        except json.JSONDecodeError as e:
            if number == len(lines) and not complete and events:
                warnings.append(f"{path}:{number}: ignoring the incomplete last line (the run was stopped mid-write)")
                continue
            hint = "; traces are written by `gpp run --trace`" if not events else ""
            raise TraceReadError(
                f"{path}:{number}: not a JSON trace record ({e.msg}, column {e.colno}){hint}"
            ) from None
        except (ValueError, TypeError) as e:
            if number == len(lines) and not complete and events:
                warnings.append(f"{path}:{number}: ignoring the incomplete last line (the run was stopped mid-write)")
                continue
            raise TraceReadError(f"{path}:{number}: not a trace record: {_one_line(str(e))}") from None
    if not events:
        raise TraceReadError(f"{path}: empty trace (no records)")
    header = events[0] if isinstance(events[0], HeaderEvent) else None
    if header is not None and not _readable_version(header.schema_version):
        warnings.append(
            f"{path}: written with trace schema {header.schema_version} by gpp {header.gpp_version}; this gpp reads "
            f"schema {TRACE_SCHEMA_VERSION} and older: what it does not know may be missing or misread"
        )
    return LoadedTrace(events, warnings)


# A trace's times are seconds since the run started; a time beyond this cannot be shown (a
# scale of microseconds or ticks would overflow), and no run lasts that long.
MAX_TRACE_TIME = 1e15


def _readable_version(version: str) -> bool:
    """Whether this gpp reads a trace of schema `version` (its own or an older one)."""
    try:
        major, minor = (int(part) for part in version.split("."))
    except ValueError:
        return False
    own_major, own_minor = (int(part) for part in TRACE_SCHEMA_VERSION.split("."))
    return (major, minor) <= (own_major, own_minor)


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _type_problem(event: TraceEvent) -> str | None:
    """What is wrong with the types of a decoded record's fields (decode checks only that the
    required fields are there), or None."""
    if not (isinstance(event.t, int | float) and math.isfinite(event.t) and abs(event.t) <= MAX_TRACE_TIME):
        return f"a `{event.EVENT}` record at time {json.dumps(event.t)}, beyond what a trace holds (at most 1e15 s)"
    for f in dataclasses.fields(event):
        value = getattr(event, f.name)
        annotation = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
        if not any(_fits(value, alternative.strip()) for alternative in annotation.split("|")):
            return (
                f"a `{event.EVENT}` record whose `{f.name}` is {json.dumps(value, default=str)} (expected {annotation})"
            )
    return None


def _fits(value: object, annotation: str) -> bool:
    if annotation in ("JsonValue", "object", "Any"):
        return True
    if annotation == "None":
        return value is None
    if annotation == "Absent":
        return value is ABSENT
    if annotation == "bool":
        return isinstance(value, bool)
    if annotation == "int":
        return isinstance(value, int) and not isinstance(value, bool)
    if annotation == "float":
        return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if annotation == "str":
        return isinstance(value, str)
    if annotation.startswith("dict["):
        return isinstance(value, dict)
    if annotation.startswith("tuple[str"):
        return isinstance(value, tuple) and all(isinstance(v, str) for v in value)
    return True  # a type this reader does not check


# ---------------------------------------------------------------- the model


@dataclass(slots=True)
class Activity:
    """One activity from its `start` to the platform's `update` (or the end of the trace)."""

    id: int
    action: str  # the ground action text
    name: str  # the action's name: its lane
    start: float
    stop: float  # when the platform reported it terminated, else the trace's last time
    status: str  # final, failed, cancelled, or `running` when the trace ends before its update
    mapped: str
    args: dict[str, JsonValue]
    at: str | None
    silent: bool = False
    reason: str | None = None
    result: JsonValue | Absent = ABSENT
    cancelled_at: float | None = None  # when the program (or the run's end) preempted it
    cancel_reason: str | None = None
    consumed_at: float | None = None  # the `end` record: when the program took the outcome
    hook: str | None = None
    unhandled: bool = False
    lane: int = 0
    row: int = 0  # the row within the lane (activities of one action that overlap get more rows)

    @property
    def duration(self) -> float:
        return self.stop - self.start


@dataclass(slots=True)
class Lane:
    name: str  # the action name
    rows: int
    activities: list[Activity]


@dataclass(frozen=True, slots=True)
class Wait:
    """The program waited from `start` on a false condition, until `stop` (None: still waiting
    when the trace ends)."""

    start: float
    stop: float | None
    statement: str
    condition: str
    at: str | None


@dataclass(frozen=True, slots=True)
class Sample:
    t: float
    value: float
    source: str  # the record kind that carried it: assign, sense, exog, ...
    label: str  # what set it: `assign`, the sensing action, the exogenous action
    at: str | None = None


@dataclass(slots=True)
class Series:
    name: str  # `battery()`, `temperature()`, `battery_report(·)`
    kind: str  # `fluent`, or `exog argument` (a numeric argument of an exogenous action)
    samples: list[Sample]


@dataclass(frozen=True, slots=True)
class Segment:
    """A fluent instance held `value` (as golog++ writes it) from `start` to `stop`."""

    start: float
    stop: float
    value: str
    label: str  # what set it: `assignment`, the action whose effect or sensing it was


@dataclass(slots=True)
class StateSeries:
    """A fluent instance with values other than numbers, as the bands of what it held. Before
    its first change the trace does not say its value (its initial one): no band there."""

    name: str  # `robot_at()`, `holding(cup)`
    segments: list[Segment]

    @property
    def values(self) -> list[str]:
        """Its distinct values, in order of first appearance."""
        return list(dict.fromkeys(s.value for s in self.segments))


@dataclass(slots=True)
class RunModel:
    events: list[TraceEvent]
    header: HeaderEvent | None
    finish: FinishEvent | None
    start: float
    end: float
    activities: list[Activity]
    lanes: list[Lane]
    exog: list[ExogEvent]
    plans: list[PlanEvent | ReplanEvent]
    changes: list[AssignEvent | SenseEvent]
    waits: list[Wait]
    problems: list[ErrorEvent | BlockedEvent]
    series: list[Series]
    states: list[StateSeries] = field(default_factory=list)
    # What operators did at the console (`gpp run --console`), in order.
    operator: list[OperatorEvent] = field(default_factory=list)

    @property
    def duration(self) -> float:
        return self.end - self.start

    @property
    def program(self) -> str | None:
        """The program's path: from the header, else the file most source locations name."""
        if self.header is not None:
            return self.header.program
        counts: dict[str, int] = defaultdict(int)
        for at in self.locations():
            loc = parse_location(at)
            if loc is not None:
                counts[loc[0]] += 1
        return max(counts, key=lambda f: counts[f]) if counts else None

    @property
    def status(self) -> str:
        """How the run ended (`finish` status), or `incomplete` when the trace has no finish."""
        return self.finish.status if self.finish is not None else "incomplete"

    def locations(self) -> list[str]:
        """Every source location the trace names, in order of first appearance."""
        seen: dict[str, None] = {}
        for event in self.events:
            at = getattr(event, "at", None)
            if isinstance(at, str):
                seen.setdefault(at, None)
        return list(seen)


def build_run_model(events: Sequence[TraceEvent]) -> RunModel:
    """The run the events describe (events in trace order; at least one)."""
    times = [e.t for e in events]
    start, end = (min(times), max(times)) if times else (0.0, 0.0)
    header = next((e for e in events if isinstance(e, HeaderEvent)), None)
    finish = next((e for e in reversed(events) if isinstance(e, FinishEvent)), None)
    activities: list[Activity] = []
    by_id: dict[int, Activity] = {}
    # Terminated activities not consumed yet, by action text: `end` names no id.
    unconsumed: dict[str, list[Activity]] = defaultdict(list)
    exog: list[ExogEvent] = []
    operator: list[OperatorEvent] = []
    plans: list[PlanEvent | ReplanEvent] = []
    changes: list[AssignEvent | SenseEvent] = []
    problems: list[ErrorEvent | BlockedEvent] = []
    waits: list[Wait] = []
    waiting: WaitingEvent | None = None
    for event in events:
        match event:
            case StartEvent():
                activity = Activity(
                    id=event.id,
                    action=event.action,
                    name=action_name(event.action),
                    start=event.t,
                    stop=end,
                    status="running",
                    mapped=event.mapped,
                    args=dict(event.args),
                    at=event.at,
                    silent=event.silent,
                )
                activities.append(activity)
                by_id[event.id] = activity
            case UpdateEvent():
                found = by_id.get(event.id)
                if found is not None and found.status == "running":
                    found.stop = event.t
                    found.status = event.status
                    found.reason = event.reason
                    found.result = event.result
                    unconsumed[found.action].append(found)
            case CancelEvent():
                found = by_id.get(event.id)
                if found is not None and found.cancelled_at is None:
                    found.cancelled_at = event.t
                    found.cancel_reason = event.reason
            case EndEvent():
                queue = unconsumed.get(event.action)
                if queue:
                    taken = queue.pop(0)
                    taken.consumed_at = event.t
                    taken.hook = event.hook
                    taken.unhandled = event.unhandled
            case ExogEvent():
                exog.append(event)
            case OperatorEvent():
                operator.append(event)
            case PlanEvent() | ReplanEvent():
                plans.append(event)
            case AssignEvent() | SenseEvent():
                changes.append(event)
            case ErrorEvent() | BlockedEvent():
                problems.append(event)
            case WaitingEvent():
                if event.resumed:
                    if waiting is not None:
                        waits.append(Wait(waiting.t, event.t, waiting.statement, waiting.condition, waiting.at))
                        waiting = None
                else:
                    if waiting is not None:  # waiting on something else now
                        waits.append(Wait(waiting.t, event.t, waiting.statement, waiting.condition, waiting.at))
                    waiting = event
            case HeaderEvent() | SnapshotEvent() | FinishEvent() | NoticeEvent():
                pass
    if waiting is not None:
        waits.append(Wait(waiting.t, None, waiting.statement, waiting.condition, waiting.at))
    lanes = _lanes(activities)
    histories = fluent_histories(events)
    return RunModel(
        events=list(events),
        header=header,
        finish=finish,
        start=start,
        end=end,
        activities=activities,
        lanes=lanes,
        exog=exog,
        plans=plans,
        changes=changes,
        waits=waits,
        problems=problems,
        series=build_series(events, histories),
        states=build_states(histories, end),
        operator=operator,
    )


def _lanes(activities: list[Activity]) -> list[Lane]:
    """One lane per action name, in order of first start, its activities in rows
    (`packed_rows`)."""
    by_name: dict[str, list[Activity]] = {}
    for activity in sorted(activities, key=lambda a: (a.start, a.id)):
        by_name.setdefault(activity.name, []).append(activity)
    lanes: list[Lane] = []
    for index, (name, members) in enumerate(by_name.items()):
        rows = packed_rows(members)
        for number, row in enumerate(rows):
            for activity in row:
                activity.lane, activity.row = index, number
        lanes.append(Lane(name, len(rows), members))
    return lanes


def packed_rows(activities: Iterable[Activity]) -> list[list[Activity]]:
    """The activities in rows, in order of start: each goes to the first row whose last
    activity has stopped when it starts, so the activities of a row never overlap."""
    rows: list[list[Activity]] = []
    for activity in sorted(activities, key=lambda a: (a.start, a.id)):
        free = next((row for row in rows if row[-1].stop <= activity.start), None)
        if free is None:
            rows.append([activity])
        else:
            free.append(activity)
    return rows


# ---------------------------------------------------------------- numeric series


@dataclass(frozen=True, slots=True)
class FluentValue:
    """A value the trace records for a fluent instance."""

    t: float
    value: JsonValue
    kind: str  # the record kind that carried it: assign, sense, start, end, exog
    label: str  # what set it: `assignment`, the sensing, starting or ending action, the exogenous action
    at: str | None = None


def fluent_histories(events: Iterable[TraceEvent]) -> dict[str, list[FluentValue]]:
    """Every fluent instance's values, in trace order, in order of its first value: from
    assignments, sensing results, and the effects (`changes`) of each `start`, `end` and `exog`."""
    histories: dict[str, list[FluentValue]] = defaultdict(list)
    for event in events:
        match event:
            case AssignEvent():
                histories[event.fluent].append(FluentValue(event.t, event.value, "assign", "assignment", event.at))
            case SenseEvent():
                histories[event.fluent].append(FluentValue(event.t, event.value, "sense", event.action))
            case StartEvent() | EndEvent() | ExogEvent():
                for change in event.changes:
                    fluent = change.get("fluent")
                    if isinstance(fluent, str):
                        histories[fluent].append(FluentValue(event.t, change.get("value"), event.EVENT, event.action))
            case _:
                pass
    return histories


def _numeric(history: list[FluentValue]) -> bool:
    """Whether every value of a fluent instance is a number (or `null`)."""
    return all(v.value is None or as_number(v.value) is not None for v in history)


def numeric_samples(
    events: Iterable[TraceEvent], histories: Mapping[str, list[FluentValue]]
) -> Iterator[tuple[str, str, Sample]]:
    """(series name, series kind, sample) for every number the trace records over time: a
    fluent instance whose every recorded value is a number (its `null`s left out), a numeric
    argument of an exogenous action."""
    for fluent, history in histories.items():
        if _numeric(history):
            for v in history:
                number = as_number(v.value)
                if number is not None:
                    yield fluent, "fluent", Sample(v.t, number, v.kind, v.label, v.at)
    for event in events:
        if isinstance(event, ExogEvent):
            name, args = split_action(event.action)
            for index, arg in enumerate(args):
                number = _number_literal(arg)
                if number is not None:
                    shown = ",".join("·" if i == index else "_" for i in range(len(args)))
                    yield f"{name}({shown})", "exog argument", Sample(event.t, number, "exog", event.action)


def build_states(histories: Mapping[str, list[FluentValue]], end: float) -> list[StateSeries]:
    """The state series: every fluent instance with a recorded value that is not a number
    (`null` aside), in order of first change; each value holds until the next change, the
    last until `end`."""
    states: list[StateSeries] = []
    for fluent, history in histories.items():
        if _numeric(history):
            continue  # a numeric series
        stops = [v.t for v in history[1:]] + [end]
        states.append(
            StateSeries(
                fluent,
                [Segment(v.t, stop, show_value(v.value), v.label) for v, stop in zip(history, stops, strict=True)],
            )
        )
    return states


def build_series(events: Iterable[TraceEvent], histories: Mapping[str, list[FluentValue]]) -> list[Series]:
    """The numeric series, fluents first, each in order of first appearance."""
    series: dict[tuple[str, str], Series] = {}
    for name, kind, sample in numeric_samples(events, histories):
        key = (kind, name)
        if key not in series:
            series[key] = Series(name, kind, [])
        series[key].samples.append(sample)
    return sorted(series.values(), key=lambda s: s.kind != "fluent")


def as_number(value: JsonValue) -> float | None:
    """A JSON value as a plottable number (booleans are not numbers here)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


_NUMBER = re.compile(r"^-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")


def _number_literal(text: str) -> float | None:
    if not _NUMBER.match(text):
        return None
    number = float(text)
    return number if math.isfinite(number) else None


# ---------------------------------------------------------------- texts


def action_name(action: str) -> str:
    """The name of a ground action text: `go(kitchen)` → `go`."""
    return action.split("(", 1)[0]


def split_action(action: str) -> tuple[str, list[str]]:
    """A ground action text as its name and its arguments' texts (commas inside strings,
    lists and compounds do not split)."""
    name, paren, rest = action.partition("(")
    if not paren or not rest.endswith(")"):
        return action, []
    inner = rest[:-1]
    if not inner:
        return name, []
    args: list[str] = []
    depth = 0
    quoted = False
    escaped = False
    current: list[str] = []
    for ch in inner:
        if quoted:
            current.append(ch)
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                quoted = False
            continue
        if ch == '"':
            quoted = True
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            args.append("".join(current))
            current = []
            continue
        current.append(ch)
    args.append("".join(current))
    return name, args


_LOCATION = re.compile(r"^(?P<file>.+):(?P<line>\d+):(?P<col>\d+)$")


def parse_location(at: str) -> tuple[str, int, int] | None:
    """`FILE:LINE:COL` as its parts, or None."""
    match = _LOCATION.match(at)
    if match is None:
        return None
    return match["file"], int(match["line"]), int(match["col"])


def show_value(value: JsonValue | Absent) -> str:
    """A trace value as golog++ writes it (gpp.runtime.values.show): symbols bare, strings
    quoted, lists and compounds in literal form; "" when absent."""
    if value is ABSENT:
        return ""
    return show_json(value)


def short_number(value: float) -> str:
    """A number without a needless `.0`: 80, 21.5, 0.333333."""
    if isinstance(value, int):
        return str(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.6g}"


def format_seconds(t: float) -> str:
    """A time in seconds with 3 decimals (the trace keeps 6): `35.817 s`."""
    return f"{t:.3f} s"


__all__ = [
    "Activity",
    "FluentValue",
    "Lane",
    "LoadedTrace",
    "RunModel",
    "Sample",
    "Segment",
    "Series",
    "StateSeries",
    "TraceReadError",
    "Wait",
    "action_name",
    "as_number",
    "build_run_model",
    "build_series",
    "build_states",
    "fluent_histories",
    "format_seconds",
    "load_trace",
    "numeric_samples",
    "packed_rows",
    "parse_location",
    "short_number",
    "show_value",
    "split_action",
]
