"""What the console's page shows of a run: one view, from either of two sources.

* `ConsoleState`, the run's own console (`gpp run --console`), a trace listener that keeps
  almost nothing of each record: the latest ones (a bounded ring, for the page's lines of
  events), a count, and a note of the few kinds whose news the executor does not keep (the
  header, a plan and the step it is at, failures, problems, the finish). The world itself, the
  fluents' values and the running activities, is read from the executor when the page asks
  (`view`, on the server's thread): the executor's state and activity set are values it
  replaces whole at each step, never changes, so another thread reads them without a lock. So
  the run pays for no record the page will not show, and holds none beyond the ring, however
  fast it goes and however long no browser looks.
* `RecordFold`, a run known only by its records (the `gpp console` hub reading an agent's live
  event topic): every record is folded in as it comes.

Besides what records say, the page needs the fluent instances at their initial values and the
forms of the actions an operator may trigger; the console's run control hands them over once,
when the program starts (`Setup`).
"""

from __future__ import annotations

import math
import threading
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

from gpp.run.view import describe
from gpp.runtime.events import (
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    EventBase,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    JsonValue,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    SnapshotEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    waiting_fields,
)
from gpp.runtime.trace import KindListener, TraceListener
from gpp.runtime.values import Value, same, show, show_json

if TYPE_CHECKING:
    from gpp.runtime.contract import Activity
    from gpp.runtime.control import Executor

# Lines of the latest events and failures the page shows.
EVENTS_SHOWN = 40
FAILURES_SHOWN = 20
# Records a run's console keeps (the latest): those lines come from them.
LATEST_KEPT = EVENTS_SHOWN * 4


@dataclass(frozen=True, slots=True)
class Parameter:
    """One parameter of an action's form: its name and how it is entered: `choice` (one of
    `choices`), `number`, `bool`, `string`, `symbol` (a name) or `json` (a list or compound)."""

    name: str
    kind: str
    choices: tuple[str, ...] = ()

    def as_json(self) -> dict[str, JsonValue]:
        return {"name": self.name, "kind": self.kind, "choices": list(self.choices)}


@dataclass(frozen=True, slots=True)
class Form:
    """An action the operator can trigger: an `exog_action` (sent as an event), or an action
    (run before the start)."""

    name: str
    parameters: tuple[Parameter, ...]

    def as_json(self) -> dict[str, JsonValue]:
        return {"name": self.name, "parameters": [p.as_json() for p in self.parameters]}


@dataclass(frozen=True, slots=True)
class Setup:
    """What the page needs besides the records, from the program as it starts: the fluent
    instances it can enumerate (their slots in the run's state and their text), and the forms."""

    instances: tuple[tuple[int, str], ...]
    exogenous: tuple[Form, ...]
    actions: tuple[Form, ...]
    # Fluent instances left out (more than the page shows).
    fluents_left_out: int = 0
    slots: frozenset[int] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "slots", frozenset(slot for slot, _ in self.instances))


@dataclass
class _Activity:
    id: int
    action: str
    started: float
    args: dict[str, JsonValue]
    status: str = "running"
    cancelling: bool = False


@dataclass
class _View:
    """A `RecordFold`'s fold of the records so far."""

    agent: dict[str, JsonValue] = field(default_factory=dict)
    status: str = "starting"
    t: float = 0.0
    fluents: dict[str, JsonValue] = field(default_factory=dict)
    changed: dict[str, float] = field(default_factory=dict)
    activities: dict[int, _Activity] = field(default_factory=dict)
    plan: dict[str, JsonValue] | None = None
    plan_step: int = 0
    waiting: dict[str, JsonValue] | None = None
    # The latest records, described (a line each) only when the page is sent.
    latest: deque[TraceEvent] = field(default_factory=lambda: deque(maxlen=LATEST_KEPT))
    failures: deque[dict[str, JsonValue]] = field(default_factory=lambda: deque(maxlen=FAILURES_SHOWN))
    problem: str | None = None
    counts: dict[str, JsonValue] = field(default_factory=dict)
    records: int = 0


class _Watched:
    """What a console's server needs of a view's source: it is told of changes through
    `on_change`, the run control sets `control_status`."""

    def __init__(self) -> None:
        # Set by the server: called (from the run's thread) when something changed and the
        # server is not already told; it then makes a new view and pushes it.
        self._wake: Callable[[], None] | None = None
        self._told = False
        # What the run control says beyond the records: waiting for Start, paused.
        self.control_status: str | None = None

    def nudge(self) -> None:
        """Tell the server something changed (once until it looks)."""
        wake = self._wake
        if wake is not None and not self._told:
            self._told = True
            wake()

    def on_change(self, wake: Callable[[], None] | None) -> None:
        """The server's callback for `nudge` (None: none)."""
        self._wake = wake
        self._told = False

    def _status(self, status: str) -> str:
        if self.control_status is not None and status == "running":
            return self.control_status
        return status


class ConsoleState(_Watched):
    """The view of the run this process runs: its trace listeners (`listeners`), and a reader
    of the executor's state (given by the run control when the program starts: `attach`)."""

    def __init__(self) -> None:
        super().__init__()
        # ---- written on the run's thread only (the server reads them)
        self._latest: deque[TraceEvent] = deque(maxlen=LATEST_KEPT)
        self._run: Executor | None = None
        self._setup: Setup | None = None
        self._agent: dict[str, JsonValue] = {}
        self._status_now = "starting"
        self._plan: dict[str, JsonValue] | None = None
        self._policy: tuple[str, ...] = ()
        self._plan_step = 0
        self._failures: deque[dict[str, JsonValue]] = deque(maxlen=FAILURES_SHOWN)
        self._problem: str | None = None
        self._counts: dict[str, JsonValue] = {}
        self._cancelling: set[int] = set()
        # The kinds of record noted, each with its note: all rare (a failure comes from the run
        # control, `failed`; the starts are told only while a plan is followed, `_follow`).
        self._notes: dict[type[EventBase], Callable[[Any], None]] = {
            HeaderEvent: self._header,
            PlanEvent: self._planned,
            ReplanEvent: self._planned,
            CancelEvent: self._cancelled,
            BlockedEvent: self._problem_noted,
            ErrorEvent: self._problem_noted,
            FinishEvent: self._finished,
        }
        self._following = False
        # ---- the server's thread only
        self._view_lock = threading.Lock()
        # Per slot shown: the value last shown (compared by identity first: the run's states
        # share their values), its text, and the latest record's time when it changed.
        self._shown: dict[int, tuple[Value, str, float | None]] = {}
        # Instances beyond the Setup's (of fluents with infinite parameter types), in the
        # order they were first seen set: shown from then on.
        self._extra: dict[int, str] = {}

    # ------------------------------------------------------------ the run's thread

    def listeners(self) -> list[TraceListener]:
        """The run's trace listeners for this view: every record goes to the ring of the latest
        (a C method, no Python code per record); the kinds the executor does not keep the news
        of go to their notes, which tell the server."""
        return [self._latest.append, KindListener(frozenset(self._notes), self._note)]

    def _note(self, event: TraceEvent) -> None:
        self._notes[type(event)](event)
        if self._wake is not None and not self._told:
            self.nudge()

    def attach(self, run: Executor, setup: Setup) -> None:
        """The run's program starts: from now on the view reads `run`'s world."""
        self._setup = setup
        self._run = run
        self.nudge()

    @property
    def records(self) -> int:
        """The run's records so far."""
        run = self._run
        return run.trace.written if run is not None else len(self._latest)

    def _header(self, event: HeaderEvent) -> None:
        self._agent = _agent(event)
        self._status_now = "running"

    def _planned(self, event: PlanEvent | ReplanEvent) -> None:
        self._policy = tuple(event.policy)
        self._plan_step = 0
        self._plan = _plan(event)
        self._follow(bool(self._policy))

    def _follow(self, following: bool) -> None:
        """Be told of the run's starts (while a plan is followed: its step) or no longer."""
        run = self._run
        if run is None or following == self._following:
            return
        self._following = following
        if following:
            run.trace.listen(StartEvent, self._step_taken)
        else:
            run.trace.unlisten(StartEvent, self._step_taken)

    def _step_taken(self, event: TraceEvent) -> None:
        """A start while a plan is followed: the plan's step is past the next entry that is
        this action (the entries before it were the plan's other steps: assignments, tests)."""
        policy, action = self._policy, cast(StartEvent, event).action
        for step in range(self._plan_step, len(policy)):
            if policy[step] == action:
                self._plan_step = step + 1
                break
        if self._plan_step >= len(policy):
            self._follow(False)

    def failed(self, t: float, action: str, reason: str | None) -> None:
        """An activity failed (told by the run control, from the run's thread)."""
        self._failures.append({"t": t, "action": action, "reason": reason or ""})
        self.nudge()

    def _cancelled(self, event: CancelEvent) -> None:
        run = self._run
        if run is not None and len(self._cancelling) >= 64:  # those consumed since go
            self._cancelling = {r.id for r in list(run.records.values())} & self._cancelling
        self._cancelling.add(event.id)

    def _problem_noted(self, event: BlockedEvent | ErrorEvent) -> None:
        self._problem = _problem_text(self._problem, event)

    def _finished(self, event: FinishEvent) -> None:
        self._status_now = event.status
        self._counts = _counts(event)
        self._follow(False)

    # ------------------------------------------------------------ the server's side

    def view(self, clock: float | None = None) -> dict[str, Any]:
        """What the page shows now, as JSON data (`clock`: the platform's clock now, if the
        server can read it)."""
        with self._view_lock:
            self._told = False
            latest = _copy(self._latest)
            t = latest[-1].t if latest else 0.0
            now = clock if clock is not None and math.isfinite(clock) else t
            run, setup = self._run, self._setup
            finished = self._status_now not in ("starting", "running")
            waiting = run.waiting_at if run is not None and not finished else None
            return _page(
                agent=self._agent,
                status=self._status(self._status_now),
                t=t,
                clock=now,
                fluents=self._fluents(run, setup, t) if run is not None and setup is not None else [],
                fluents_left_out=setup.fluents_left_out if setup is not None else 0,
                activities=self._activities(run, now) if run is not None else [],
                plan=None if self._plan is None else {**self._plan, "step": self._plan_step},
                waiting=None if waiting is None else waiting_fields(waiting),
                latest=latest,
                failures=list(self._failures),
                problem=self._problem,
                exogenous=[f.as_json() for f in setup.exogenous] if setup is not None else [],
                actions=[f.as_json() for f in setup.actions] if setup is not None else [],
                counts=self._counts,
                records=self.records,
            )

    def _fluents(self, run: Executor, setup: Setup, t: float) -> list[dict[str, JsonValue]]:
        program = run.program
        held = run.state.held()  # a state's values are never changed: read without a lock
        initial = program.initial
        shown, extra = self._shown, self._extra
        known = setup.slots
        for slot in held:
            if slot not in known and slot not in extra:
                extra[slot] = program.instance_text(slot)
        rows: list[dict[str, JsonValue]] = []
        for instances in (setup.instances, extra.items()):
            for slot, name in instances:
                value = held[slot] if slot in held else initial(slot)
                before = shown.get(slot)
                if before is None:
                    before = shown[slot] = (value, show(value), None)
                elif before[0] is not value and not same(before[0], value):
                    before = shown[slot] = (value, show(value), t)
                rows.append({"name": name, "value": before[1], "changed": before[2]})
        return rows

    def _activities(self, run: Executor, now: float) -> list[dict[str, JsonValue]]:
        acts = run.acts
        rows: list[dict[str, JsonValue]] = []
        for record in sorted(list(run.records.values()), key=_id):
            status = acts.status(record.action)
            if status is None:
                continue  # consumed between the two reads
            started = record.started if math.isfinite(record.started) else now
            args: dict[str, JsonValue] = {k: show(v) for k, v in record.args.items()}
            cancelling = record.id in self._cancelling
            rows.append(_activity(record.id, record.action.text, status.value, cancelling, started, now, args))
        return rows


class RecordFold(_Watched):
    """The view of a run known only by its records (the hub's view of an agent's event topic):
    a trace listener that folds every record in."""

    def __init__(self) -> None:
        super().__init__()
        self._view = _View()

    def __call__(self, event: TraceEvent) -> None:
        view = self._view
        fold = _FOLDS.get(type(event))
        if fold is not None:
            fold(view, event)
        view.latest.append(event)
        view.t = event.t
        view.records += 1
        self.nudge()

    def view(self, clock: float | None = None) -> dict[str, Any]:
        """What the page shows now, as JSON data."""
        self._told = False
        view = self._view
        now = clock if clock is not None and math.isfinite(clock) else view.t
        return _page(
            agent=view.agent,
            status=self._status(view.status),
            t=view.t,
            clock=now,
            fluents=[
                {"name": name, "value": show_json(value), "changed": view.changed.get(name)}
                for name, value in view.fluents.items()
            ],
            fluents_left_out=0,
            activities=[
                _activity(a.id, a.action, a.status, a.cancelling, a.started, now, _shown(a.args))
                for a in view.activities.values()
            ],
            plan=None if view.plan is None else {**view.plan, "step": view.plan_step},
            waiting=view.waiting,
            latest=list(view.latest),
            failures=list(view.failures),
            problem=view.problem,
            exogenous=[],
            actions=[],
            counts=view.counts,
            records=view.records,
        )


def _page(*, latest: list[TraceEvent], **parts: Any) -> dict[str, Any]:
    """The view as the page takes it (the same keys from either source)."""
    return {**parts, "events": _latest_lines(latest)}


def _activity(
    id: int, action: str, status: str, cancelling: bool, started: float, now: float, args: dict[str, JsonValue]
) -> dict[str, JsonValue]:
    """A running activity as the page shows it (`args`: each argument's text)."""
    return {
        "id": id,
        "action": action,
        "status": status,
        "cancelling": cancelling,
        "started": started,
        "elapsed": max(0.0, now - started),
        "args": args,
    }


def _shown(args: dict[str, JsonValue]) -> dict[str, JsonValue]:
    """Arguments as the trace has them, as text."""
    return {k: show_json(v) for k, v in args.items()}


def _copy(ring: deque[TraceEvent]) -> list[TraceEvent]:
    """The records in `ring` (appended to by another thread) as a list."""
    while True:
        try:
            return list(ring)
        except RuntimeError:  # appended to while copied
            continue


def _id(record: Activity) -> int:
    return record.id


def _agent(event: HeaderEvent) -> dict[str, JsonValue]:
    return {
        "program": event.program,
        "platform": event.platform,
        "started": event.started,
        "node": event.node,
        "world": event.world,
    }


def _plan(event: PlanEvent | ReplanEvent) -> dict[str, JsonValue]:
    return {"kind": event.kind, "feasible": event.feasible, "policy": list(event.policy), "t": event.t}


def _failure(event: UpdateEvent) -> dict[str, JsonValue]:
    return {"t": event.t, "action": event.action, "reason": event.reason or ""}


def _problem_text(before: str | None, event: BlockedEvent | ErrorEvent) -> str:
    # The first says why the run ended; what went wrong while it ended comes after it.
    return event.message if before is None else f"{before}\n{event.message}"


def _counts(event: FinishEvent) -> dict[str, JsonValue]:
    return {"actions": event.actions, "failures": event.failures, "exog_events": event.exog_events}


def _header(view: _View, event: HeaderEvent) -> None:
    view.agent = _agent(event)
    view.status = "running"


def _snapshot(view: _View, event: SnapshotEvent) -> None:
    for change in event.fluents:
        _set_fluent(view, change, event.t)


def _start(view: _View, event: StartEvent) -> None:
    view.activities[event.id] = _Activity(event.id, event.action, event.t, dict(event.args))
    policy = view.plan["policy"] if view.plan is not None else None
    if isinstance(policy, list) and view.plan_step < len(policy) and policy[view.plan_step] == event.action:
        view.plan_step += 1
    _changes(view, event)  # its `start_effect:`


def _update(view: _View, event: UpdateEvent) -> None:
    activity = view.activities.get(event.id)
    if activity is not None:
        activity.status = event.status
    if event.status == "failed":
        view.failures.append(_failure(event))


def _cancel(view: _View, event: CancelEvent) -> None:
    activity = view.activities.get(event.id)
    if activity is not None:
        activity.cancelling = True


def _end(view: _View, event: EndEvent) -> None:
    """An `end` (which has no id) consumes the oldest terminated activity of its action, or
    else the oldest of that action."""
    same = [a for a in view.activities.values() if a.action == event.action]
    ended = [a for a in same if a.status != "running"]
    for a in (ended or same)[:1]:
        del view.activities[a.id]
    _changes(view, event)


def _changes(view: _View, event: StartEvent | EndEvent | ExogEvent) -> None:
    for change in event.changes:
        _set_fluent(view, change, event.t)


def _assigned(view: _View, event: SenseEvent | AssignEvent) -> None:
    view.fluents[event.fluent] = event.value
    view.changed[event.fluent] = event.t


def _planned(view: _View, event: PlanEvent | ReplanEvent) -> None:
    view.plan = _plan(event)
    view.plan_step = 0


def _waiting(view: _View, event: WaitingEvent) -> None:
    view.waiting = None if event.resumed else waiting_fields(event)


def _problem(view: _View, event: BlockedEvent | ErrorEvent) -> None:
    view.problem = _problem_text(view.problem, event)


def _finish(view: _View, event: FinishEvent) -> None:
    view.status = event.status
    view.waiting = None
    view.counts = _counts(event)


# What each kind of record changes in the view (the others only go to the latest events).
_FOLDS: dict[type, Callable[[_View, Any], None]] = {
    HeaderEvent: _header,
    SnapshotEvent: _snapshot,
    StartEvent: _start,
    UpdateEvent: _update,
    CancelEvent: _cancel,
    EndEvent: _end,
    ExogEvent: _changes,
    SenseEvent: _assigned,
    AssignEvent: _assigned,
    PlanEvent: _planned,
    ReplanEvent: _planned,
    WaitingEvent: _waiting,
    BlockedEvent: _problem,
    ErrorEvent: _problem,
    FinishEvent: _finish,
}


def _latest_lines(latest: Sequence[TraceEvent]) -> list[dict[str, JsonValue]]:
    """The lines of the latest records worth one (silent actions' records left out)."""
    lines: list[dict[str, JsonValue]] = []
    for event in reversed(latest):
        line = None if getattr(event, "silent", False) else describe(event)
        if line is not None:
            lines.append({"t": event.t, "kind": event.EVENT, "text": line})
            if len(lines) == EVENTS_SHOWN:
                break
    return lines[::-1]


def _set_fluent(view: _View, change: dict[str, JsonValue], t: float) -> None:
    name = change.get("fluent")
    if isinstance(name, str):
        view.fluents[name] = change.get("value")
        view.changed[name] = t
