"""Replaying a recorded run: the positions a debugger can stop at in a trace, the state at each,
and fast stepping both ways (`gpp dap` launching a trace file; docs/debugging.md, "Stepping back
through a recorded run").

A position is a record of the trace at which the replay stops, just before that record happens:
in a trace recorded with steps (`gpp run --trace-steps`, schema 1.7) each `step` record (the
program's next transition, where a debugger stopped the live run) and the records that end the
run (`blocked`, `error`, `finish`); in a trace without them, every record but the header and the
snapshot. The state at a position is what the records before it did: the fluent values, the
activities started and not consumed, the plan, what the program waits for, where it is.

The index keeps no records, only where each position's record is (its part and byte offset) and a
few small numbers per position (its line, the action it starts, its call depth, ...), plus the
whole state at every `KEYFRAME_EVERY`-th position: the state anywhere is that keyframe's with at
most `KEYFRAME_EVERY` records read again from the file, so a step back costs the same on a long
trace as on a short one, and a step forward reads one record or a few.
"""

from __future__ import annotations

import json
from array import array
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from gpp.runtime.events import (
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    JsonValue,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    SnapshotEvent,
    StartEvent,
    StepEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    decode,
    waiting_fields,
)
from gpp.runtime.trace import trace_parts
from gpp.traceview.model import TraceReadError, _first_part_in

# The state is kept whole at every this many positions.
KEYFRAME_EVERY = 256

# What happened since the position before (Position.failed, Position.no_plan).
_FAILED = 1
_NO_PLAN = 2
# The position's step goes on with a statement an earlier step began (stepping passes it).
_CONTINUES = 4

# Records that only a transition of the program writes.
_TRANSITION_RECORDS = (StartEvent, EndEvent, AssignEvent, PlanEvent, ReplanEvent, CancelEvent)

# The record kinds that are positions in a trace recorded with steps.
_STEPPED_STOPS = (StepEvent, BlockedEvent, ErrorEvent, FinishEvent)


@dataclass(frozen=True, slots=True)
class ActivityState:
    """An activity started and not consumed yet."""

    id: int
    action: str
    status: str  # running, final, failed, cancelled
    started: float  # platform time of its `start`
    at: str | None  # the statement that started it


@dataclass(slots=True)
class ReplayState:
    """The run's state at a position: what the records before it did."""

    t: float = 0.0
    # The fluent instances the trace set, by instance text (`loc(a)`), with their values as
    # the trace writes them; every other instance has its initial value.
    fluents: dict[str, JsonValue] = field(default_factory=dict)
    activities: dict[int, ActivityState] = field(default_factory=dict)
    # The latest `plan` or `replan` record; how many of its policy's steps have started since,
    # in order (its progress); where its `solve` or `search` is (traces with steps).
    plan: PlanEvent | ReplanEvent | None = None
    plan_done: int = 0
    plan_at: str | None = None
    # What the program waits for, as its `waiting` record says (None: it does not wait).
    waiting: dict[str, JsonValue] | None = None
    actions: int = 0
    failures: int = 0
    exog_events: int = 0
    # The latest source location a record named.
    location: str | None = None
    # From the latest `step` record: what the transition did and the procedure calls it was in.
    step: str | None = None
    frames: tuple[dict[str, JsonValue], ...] = ()
    # How many calls there are (more than `frames` lists in a deep recursion).
    calls: int = 0
    # How the run ended, once it has: the `blocked` or `error` message, the `finish` status.
    stopped: str | None = None
    status: str | None = None

    def copy(self) -> ReplayState:
        return ReplayState(
            self.t,
            dict(self.fluents),
            dict(self.activities),
            self.plan,
            self.plan_done,
            self.plan_at,
            self.waiting,
            self.actions,
            self.failures,
            self.exog_events,
            self.location,
            self.step,
            self.frames,
            self.calls,
            self.stopped,
            self.status,
        )

    def apply(self, event: TraceEvent) -> None:
        """What the record `event` does to the state."""
        self.t = event.t
        match event:
            case StepEvent():
                self.step, self.frames = event.step, event.frames
                self.waiting = None  # a program that steps waits no more
                if event.step in ("plan", "replan"):
                    self.plan_at = event.at
                self.calls = event.depth if isinstance(event.depth, int) else len(event.frames)
                self.location = event.at or self.location
            case StartEvent():
                self.activities[event.id] = ActivityState(event.id, event.action, "running", event.t, event.at)
                self._set(event.changes)  # its `start_effect:` (since 1.6)
                self.actions += 1
                self.location = event.at or self.location
                plan = self.plan
                if (
                    plan is not None
                    and self.plan_done < len(plan.policy)
                    and plan.policy[self.plan_done] == event.action
                ):
                    self.plan_done += 1
            case UpdateEvent():
                running = self.activities.get(event.id)
                if running is not None:
                    self.activities[event.id] = ActivityState(
                        running.id, running.action, event.status, running.started, running.at
                    )
                if event.status == "failed":
                    self.failures += 1
            case EndEvent():
                self._consume(event.action)
                self._set(event.changes)
            case ExogEvent():
                self._set(event.changes)
                if not event.failed:
                    self.exog_events += 1
            case AssignEvent():
                self.fluents[event.fluent] = event.value
                self.location = event.at or self.location
            case SenseEvent():
                self.fluents[event.fluent] = event.value
            case PlanEvent() | ReplanEvent():
                self.plan, self.plan_done = event, 0
            case WaitingEvent():
                self.waiting = None if event.resumed else waiting_fields(event)
                self.location = event.at or self.location
            case BlockedEvent():
                self.stopped = event.message
                self.location = event.at or self.location
            case ErrorEvent():
                self.stopped = event.message
                if isinstance(event.at, str):
                    self.location = event.at
            case FinishEvent():
                self.status = event.status
                self.waiting = None
                self.actions, self.failures, self.exog_events = event.actions, event.failures, event.exog_events
            case SnapshotEvent():
                self._restore(event)
            case _:
                pass

    def _set(self, changes: tuple[dict[str, JsonValue], ...]) -> None:
        for change in changes:
            fluent = change.get("fluent")
            if isinstance(fluent, str):
                self.fluents[fluent] = change.get("value")

    def _consume(self, action: str) -> None:
        """An `end` consumes the first terminated activity of its action (it has no id)."""
        same = [a for a in self.activities.values() if a.action == action]
        done = [a for a in same if a.status != "running"] or same
        if done:
            del self.activities[done[0].id]

    def _restore(self, snapshot: SnapshotEvent) -> None:
        """The state a later part of a split trace starts from."""
        self.fluents = {}
        self._set(snapshot.fluents)
        self.activities = {}
        for entry in snapshot.activities:
            ident, action, status = entry.get("id"), entry.get("action"), entry.get("status")
            if isinstance(ident, int) and isinstance(action, str) and isinstance(status, str):
                self.activities[ident] = ActivityState(ident, action, status, snapshot.t, None)
        self.waiting = dict(snapshot.waiting) if snapshot.waiting is not None else None
        self.actions, self.failures, self.exog_events = snapshot.actions, snapshot.failures, snapshot.exog_events


@dataclass(frozen=True, slots=True)
class Position:
    """What the index knows of one position without reading the trace again."""

    index: int
    kind: str  # its record's kind: step, start, end, ..., finish
    location: str | None  # its record's source location (the statement about to step)
    line: tuple[str, int] | None  # (file, line) of `location`
    started: str | None  # the name of the action it starts, if it starts one
    procedure: str | None  # the innermost procedure call it is in (traces with steps)
    depth: int  # how many procedure calls it is in (traces with steps; 0 otherwise)
    # Since the position before: an activity failed, a `solve`/`search` found no plan.
    failed: bool = False
    no_plan: bool = False
    # Its step goes on with a statement an earlier one began (the end of a call): stepping
    # passes over it.
    continues: bool = False


class Replay:
    """The positions of a recorded run and the state at each. Open it with `Replay.open`; close
    it (or use it as a context manager) to close the trace's files."""

    def __init__(self, parts: list[Path]) -> None:
        self.parts = parts
        self.header: HeaderEvent | None = None
        # The trace holds `step` records (recorded with --trace-steps).
        self.stepped = False
        # Where each position's record is: its part and byte offset.
        self._part = array("H")
        self._offset = array("q")
        # Per position: the kind, location, started action and innermost procedure as numbers
        # into `_names` (-1: none), and the call depth.
        self._kind = array("i")
        self._location = array("i")
        self._started = array("i")
        self._procedure = array("i")
        self._depth = array("H")
        self._flags = array("B")  # _FAILED | _NO_PLAN since the position before, _CONTINUES
        self._names: list[str] = []
        self._name_ids: dict[str, int] = {}
        self._keyframes: list[ReplayState] = []
        self._initial = ReplayState()
        self._files: dict[int, IO[bytes]] = {}
        # The latest position asked for and its state: a step forward goes on from it.
        self._cursor: tuple[int, ReplayState] | None = None
        self.warnings: list[str] = []
        # Records read from the files since the index was made (what a step costs).
        self.records_read = 0

    # ---------------------------------------------------------------- opening

    @classmethod
    def open(cls, path: Path) -> Replay:
        """The replay of the trace at `path`: a trace file, the first part of a split trace (its
        later parts are followed) or the folder that holds it. TraceReadError if it is not one."""
        if path.is_dir():
            path = _first_part_in(path)
        if not path.is_file():
            raise TraceReadError(f"cannot read '{path}': no such file", usage=True)
        replay = cls(trace_parts(path))
        replay._index()
        return replay

    def _index(self) -> None:
        """Read the trace once: the positions, and the state at every keyframe."""
        state = self._initial
        # The stops are known only once it is known whether the trace has steps: look first.
        self.stepped = self._has_steps()
        depth = 0
        procedure = -1
        happened = 0
        for part, offset, event in self._scan():
            if isinstance(event, HeaderEvent):
                if self.header is None:
                    self.header = event
                    if event.part is not None:
                        self.warnings.append(
                            f"{self.parts[0]}: part {event.part} of a split trace (after {event.previous}): "
                            "the replay starts at its snapshot; give the first part to replay the whole run"
                        )
                continue
            if isinstance(event, SnapshotEvent):
                if not self._offset:
                    self._apply(state, event, part, offset)  # a replay that starts at a later part starts here
                continue
            if self._is_stop(event):
                if isinstance(event, StepEvent):
                    depth = event.depth if isinstance(event.depth, int) else len(event.frames)
                    first = event.frames[0].get("procedure") if event.frames else None
                    procedure = self._name(first) if isinstance(first, str) else -1
                if len(self._offset) % KEYFRAME_EVERY == 0:
                    self._keyframes.append(state.copy())
                self._part.append(part)
                self._offset.append(offset)
                self._kind.append(self._name(event.EVENT))
                at = getattr(event, "at", None)
                self._location.append(self._name(at) if isinstance(at, str) else -1)
                started = _started_name(event)
                self._started.append(self._name(started) if started is not None else -1)
                self._procedure.append(procedure)
                self._depth.append(min(depth, 65535))
                continues = isinstance(event, StepEvent) and event.continues is True
                self._flags.append(happened | (_CONTINUES if continues else 0))
                happened = 0
            self._apply(state, event, part, offset)
            if isinstance(event, UpdateEvent) and event.status == "failed":
                happened |= _FAILED
            elif isinstance(event, PlanEvent | ReplanEvent) and not event.feasible:
                happened |= _NO_PLAN
        if not self._offset:
            raise TraceReadError(f"{self.parts[0]}: a trace without records to replay")
        self._final = state

    def _has_steps(self) -> bool:
        """Was the trace recorded with steps? A transition's `step` record comes before the
        records only a transition writes, so the first of those tells."""
        for _, _, event in self._scan():
            if isinstance(event, StepEvent):
                return True
            if isinstance(event, _TRANSITION_RECORDS):
                return False
        return False

    def _scan(self) -> Iterator[tuple[int, int, TraceEvent]]:
        """Every record of the run with its part and offset (but the header and snapshot that
        start each later part: they hold what the records before them did)."""
        for number in range(len(self.parts)):
            yield from self._records(number, 0)

    def _records(self, part: int, offset: int) -> Iterator[tuple[int, int, TraceEvent]]:
        """The records of one part from `offset` on."""
        file = self._file(part)
        file.seek(offset)
        path = self.parts[part]
        while True:
            line = file.readline()
            if not line:
                return
            at = offset
            offset += len(line)
            if not line.strip():
                continue
            try:
                # Decoded only: a field of the wrong type is met where it is used (the index
                # and the state take only what has the type they need).
                event = decode(line)
            except (ValueError, TypeError) as e:
                if not line.endswith(b"\n"):
                    warning = f"{path}: ignoring the incomplete last line (the run was stopped mid-write)"
                    if warning not in self.warnings:
                        self.warnings.append(warning)
                    return
                message = e.msg if isinstance(e, json.JSONDecodeError) else " ".join(str(e).split())
                raise TraceReadError(f"{path}: byte {at}: not a trace record ({message})") from None
            if part > 0 and isinstance(event, HeaderEvent | SnapshotEvent):
                continue  # the part's own start: the state it holds is the one read so far
            self.records_read += 1
            yield part, at, event

    def _apply(self, state: ReplayState, event: TraceEvent, part: int, offset: int) -> None:
        """`state.apply(event)`; a record whose fields do not have their types is a TraceReadError."""
        try:
            state.apply(event)
        except (AttributeError, TypeError, KeyError):
            raise TraceReadError(
                f"{self.parts[part]}: byte {offset}: a `{event.EVENT}` record whose fields do not have their types"
            ) from None

    def _file(self, part: int) -> IO[bytes]:
        file = self._files.get(part)
        if file is None:
            try:
                file = self._files[part] = self.parts[part].open("rb")
            except OSError as e:
                raise TraceReadError(f"cannot read '{self.parts[part]}': {e.strerror or e}", usage=True) from None
        return file

    def _is_stop(self, event: TraceEvent) -> bool:
        if self.stepped:
            return isinstance(event, _STEPPED_STOPS)
        return not isinstance(event, HeaderEvent | SnapshotEvent)

    def _name(self, text: str) -> int:
        number = self._name_ids.get(text)
        if number is None:
            number = self._name_ids[text] = len(self._names)
            self._names.append(text)
        return number

    def close(self) -> None:
        for file in self._files.values():
            file.close()
        self._files.clear()

    def __enter__(self) -> Replay:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    # ---------------------------------------------------------------- positions

    def __len__(self) -> int:
        """The number of positions (at least 1: the run's last record)."""
        return len(self._offset)

    @property
    def last(self) -> int:
        return len(self._offset) - 1

    def position(self, index: int) -> Position:
        """What the index knows of position `index` (0 to `last`)."""
        location = self._text(self._location[index])
        line = _file_line(location)
        return Position(
            index,
            self._names[self._kind[index]],
            location,
            line,
            self._text(self._started[index]),
            self._text(self._procedure[index]),
            self._depth[index],
            bool(self._flags[index] & _FAILED),
            bool(self._flags[index] & _NO_PLAN),
            bool(self._flags[index] & _CONTINUES),
        )

    def _text(self, number: int) -> str | None:
        return self._names[number] if number >= 0 else None

    def record(self, index: int) -> TraceEvent:
        """The record at position `index` (what happens next there), read from the file."""
        for _, _, event in self._records(self._part[index], self._offset[index]):
            return event
        raise TraceReadError(f"{self.parts[self._part[index]]}: the trace changed while it was replayed")

    def state(self, index: int) -> ReplayState:
        """The state at position `index`: what the records before it did, and where its own
        record is (its time, location, step and calls). A copy to keep."""
        if not 0 <= index < len(self._offset):
            raise IndexError(index)
        cursor = self._cursor
        if cursor is not None and cursor[0] <= index and index - cursor[0] < KEYFRAME_EVERY:
            start, state = cursor[0], cursor[1].copy()
        else:
            start = index - index % KEYFRAME_EVERY
            state = self._keyframes[start // KEYFRAME_EVERY].copy()
        if start != index:
            end = (self._part[index], self._offset[index])
            for part, offset, event in self._from(start):
                if (part, offset) == end:
                    break
                self._apply(state, event, part, offset)
        self._cursor = (index, state.copy())
        # What the position's own record says of where the run is: the statement about to step
        # and its calls (a `step`), the place of what happens next.
        upcoming = self.record(index)
        state.t = upcoming.t
        if isinstance(upcoming, StepEvent):
            state.apply(upcoming)
        else:
            at = getattr(upcoming, "at", None)
            state.location = at if isinstance(at, str) else state.location
        return state

    def before(self, index: int) -> list[TraceEvent]:
        """The records between position `index - 1` (included) and `index`: what happened since
        the position before (the one record of a trace without steps, a step's records)."""
        if index <= 0:
            return []
        end = (self._part[index], self._offset[index])
        found: list[TraceEvent] = []
        for part, offset, event in self._from(index - 1):
            if (part, offset) == end:
                break
            found.append(event)
        return found

    def _from(self, index: int) -> Iterator[tuple[int, int, TraceEvent]]:
        """The run's records from position `index`'s on, across parts."""
        part = self._part[index]
        yield from self._records(part, self._offset[index])
        for later in range(part + 1, len(self.parts)):
            yield from self._records(later, 0)

    @property
    def final(self) -> ReplayState:
        """The state after the last record."""
        return self._final.copy()

    # ---------------------------------------------------------------- moving

    def forward(self, index: int, over: bool = False, out: bool = False) -> int:
        """The position a step forward from `index` reaches: the next one (step in); with
        `over`, the next in the same call or an outer one (next); with `out`, the next in an
        outer call (step out). As the live debugger's stepping, it passes over the steps that
        go on with a statement an earlier one began (the end of a call). The last position when
        there is none."""
        return self._seek(index, 1, over, out)

    def backward(self, index: int, over: bool = False, out: bool = False) -> int:
        """As `forward`, backwards (stepBack; 0 when there is none)."""
        return self._seek(index, -1, over, out)

    def _seek(self, index: int, direction: int, over: bool, out: bool) -> int:
        depth = self._depth[index]
        q = index + direction
        while 0 <= q < len(self._offset):
            d = self._depth[q]
            if self._flags[q] & _CONTINUES:
                pass  # as the live debugger's stepping, it does not stop at the end of a call
            elif (out and d < depth) or (not out and (not over or d <= depth)):
                return q
            q += direction
        return self.last if direction > 0 else 0

    def find(self, index: int, direction: int, hits: Callable[[int], bool]) -> int | None:
        """The first position after `index` (before it, with direction -1) that `hits`, or None."""
        q = index + direction
        while 0 <= q < len(self._offset):
            if hits(q):
                return q
            q += direction
        return None

    def at_line(self, file: str, line: int) -> Callable[[int], bool]:
        """Whether a position's statement is on `line` of `file` (a path as the trace gives it,
        or one naming the same file)."""
        wanted = {n for n, text in enumerate(self._names) if _same_line(_file_line(text), file, line)}
        return lambda q: self._location[q] in wanted

    def lines(self, file: str) -> set[int]:
        """The lines of `file` some position stops at (where a line breakpoint can be)."""
        found: set[int] = set()
        for number in set(self._location):
            where = _file_line(self._text(number))
            if where is not None and _same_file(where[0], file):
                found.add(where[1])
        return found

    def starts(self, action: str) -> Callable[[int], bool]:
        """Whether a position starts an activity of the action named `action` (a function
        breakpoint on an action)."""
        number = self._name_ids.get(action, -2)
        return lambda q: self._started[q] == number

    def enters(self, procedure: str) -> Callable[[int], bool]:
        """Whether a position is the first in a call of `procedure` (a function breakpoint on a
        procedure; only a trace recorded with steps knows the calls)."""
        number = self._name_ids.get(procedure, -2)

        def entered(q: int) -> bool:
            if self._procedure[q] != number:
                return False
            return q == 0 or self._procedure[q - 1] != number or self._depth[q - 1] < self._depth[q]

        return entered

    def limits(self) -> list[str]:
        """What this trace cannot show, one sentence each (the adapter tells the user)."""
        said: list[str] = []
        version = self.header.schema_version if self.header is not None else None
        if self.header is None:
            said.append("the trace has no header (schema 1.0): it does not say which program ran")
        if not self.stepped:
            said.append(
                "the trace was recorded without steps (`gpp run --trace-steps`): the replay stops at each record "
                "(an activity's start and end, an assignment, an event) rather than at every statement, and has no "
                "procedure calls, parameters or locals to show"
            )
        if version is None or _older(version, (1, 1)):
            said.append(
                "the trace is older than schema 1.1: its `end` and `exog` records carry no effects, so fluents "
                "set by actions and events are not shown"
            )
        return said


def _started_name(event: TraceEvent) -> str | None:
    """The action name `event` starts, if it starts one: a `start` record, or a `step` whose
    transition is a start."""
    if isinstance(event, StartEvent):
        return event.action.split("(", 1)[0]
    if isinstance(event, StepEvent) and event.step.startswith("start("):
        return event.step[len("start(") :].split("(", 1)[0]
    return None


def _file_line(location: str | None) -> tuple[str, int] | None:
    """(file, line) of a location `FILE:LINE:COL`."""
    if location is None:
        return None
    parts = location.rsplit(":", 2)
    if len(parts) != 3 or not parts[1].isdigit():
        return None
    return parts[0], int(parts[1])


def _same_file(a: str, b: str) -> bool:
    if a == b:
        return True
    try:
        return Path(a).resolve() == Path(b).resolve()
    except OSError:
        return False


def _same_line(where: tuple[str, int] | None, file: str, line: int) -> bool:
    return where is not None and where[1] == line and _same_file(where[0], file)


def _older(version: str, than: tuple[int, int]) -> bool:
    try:
        major, minor = (int(p) for p in version.split("."))
    except ValueError:
        return False
    return (major, minor) < than


__all__ = ["KEYFRAME_EVERY", "ActivityState", "Position", "Replay", "ReplayState"]
