"""What the console's page shows of a run, folded from the run's trace records.

The executor's thread only hands each record over (`ConsoleState.__call__`, a trace listener:
one append to a deque); the server's thread folds what was handed over into the view
(`ConsoleState.view`) when it pushes to the page. So the cost of the console to the run does
not grow with the page's work, nor with a slow browser.

Besides the records, the page needs what the trace does not say: the fluent instances at their
initial values and the forms of the actions an operator may trigger. The console's run control
hands them over once, when the program starts (`Setup`), through the same deque, so they come
in order with the records.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from gpp.run.view import describe
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
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    waiting_fields,
)
from gpp.runtime.values import show_json

# Lines of the latest events and failures the page shows.
EVENTS_SHOWN = 40
FAILURES_SHOWN = 20


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
    """What the page needs besides the records, from the program as it starts: every fluent
    instance it can enumerate with its value (`name(args)` → trace value), and the forms."""

    fluents: dict[str, JsonValue]
    exogenous: tuple[Form, ...]
    actions: tuple[Form, ...]
    # Fluent instances left out (more than the page shows).
    fluents_left_out: int = 0


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
    """The fold of the records so far (server thread only)."""

    agent: dict[str, JsonValue] = field(default_factory=dict)
    status: str = "starting"
    t: float = 0.0
    fluents: dict[str, JsonValue] = field(default_factory=dict)
    changed: dict[str, float] = field(default_factory=dict)
    fluents_left_out: int = 0
    activities: dict[int, _Activity] = field(default_factory=dict)
    plan: dict[str, JsonValue] | None = None
    plan_step: int = 0
    waiting: dict[str, JsonValue] | None = None
    # The latest records, described (a line each) only when the page is sent.
    latest: deque[TraceEvent] = field(default_factory=lambda: deque(maxlen=EVENTS_SHOWN * 4))
    failures: deque[dict[str, JsonValue]] = field(default_factory=lambda: deque(maxlen=FAILURES_SHOWN))
    problem: str | None = None
    exogenous: list[dict[str, JsonValue]] = field(default_factory=list)
    actions: list[dict[str, JsonValue]] = field(default_factory=list)
    counts: dict[str, JsonValue] = field(default_factory=dict)
    records: int = 0


class ConsoleState:
    """A trace listener that keeps what the console's page shows of one run."""

    def __init__(self) -> None:
        self._handed: deque[TraceEvent | Setup] = deque()
        self._view = _View()
        self._fold_lock = threading.Lock()
        # Set by the server: called (from the executor's thread) when something was handed over
        # and the server is not already told; it then folds and pushes.
        self._wake: Callable[[], None] | None = None
        self._told = False
        # What the run control says beyond the records: waiting for Start, paused.
        self.control_status: str | None = None
        self.version = 0

    # ------------------------------------------------------------ the executor's side

    def __call__(self, event: TraceEvent | Setup) -> None:
        """A record of the run (or the Setup): handed over, folded later by the server."""
        self._handed.append(event)
        self.nudge()

    def nudge(self) -> None:
        """Tell the server something changed (once until it looks)."""
        wake = self._wake
        if wake is not None and not self._told:
            self._told = True
            wake()

    # ------------------------------------------------------------ the server's side

    def on_change(self, wake: Callable[[], None] | None) -> None:
        """The server's callback for `nudge` (None: none)."""
        self._wake = wake
        self._told = False

    def view(self, clock: float | None = None) -> dict[str, Any]:
        """Fold what was handed over and return what the page shows, as JSON data (`clock`:
        the platform's clock now, if the server can read it)."""
        with self._fold_lock:
            self._told = False
            view = self._view
            # The fold of each record, with the lookups done once (it is the console's main cost).
            handed, take, keep, folds = self._handed, self._handed.popleft, view.latest.append, _FOLDS
            while handed:
                item = take()
                self.version += 1
                fold = folds.get(type(item))
                if fold is not None:
                    fold(view, item)
                if isinstance(item, Setup):
                    _set_up(view, item)
                else:
                    keep(item)
                    view.t = item.t
                    view.records += 1
            now = clock if clock is not None and math.isfinite(clock) else view.t
            status = view.status
            if self.control_status is not None and status == "running":
                status = self.control_status
            return {
                "agent": view.agent,
                "status": status,
                "t": view.t,
                "clock": now,
                "fluents": [
                    {"name": name, "value": show_json(value), "changed": view.changed.get(name)}
                    for name, value in view.fluents.items()
                ],
                "fluents_left_out": view.fluents_left_out,
                "activities": [
                    {
                        "id": a.id,
                        "action": a.action,
                        "status": a.status,
                        "cancelling": a.cancelling,
                        "started": a.started,
                        "elapsed": max(0.0, now - a.started),
                        "args": {k: show_json(v) for k, v in a.args.items()},
                    }
                    for a in view.activities.values()
                ],
                "plan": None if view.plan is None else {**view.plan, "step": view.plan_step},
                "waiting": view.waiting,
                "events": _latest_lines(view.latest),
                "failures": list(view.failures),
                "problem": view.problem,
                "exogenous": view.exogenous,
                "actions": view.actions,
                "counts": view.counts,
                "records": view.records,
            }


def _set_up(view: _View, setup: Setup) -> None:
    view.fluents.update(setup.fluents)
    view.fluents_left_out = setup.fluents_left_out
    view.exogenous = [f.as_json() for f in setup.exogenous]
    view.actions = [f.as_json() for f in setup.actions]


def _header(view: _View, event: HeaderEvent) -> None:
    view.agent = {
        "program": event.program,
        "platform": event.platform,
        "started": event.started,
        "node": event.node,
        "world": event.world,
    }
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
        view.failures.append({"t": event.t, "action": event.action, "reason": event.reason or ""})


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


def _plan(view: _View, event: PlanEvent | ReplanEvent) -> None:
    view.plan = {"kind": event.kind, "feasible": event.feasible, "policy": list(event.policy), "t": event.t}
    view.plan_step = 0


def _waiting(view: _View, event: WaitingEvent) -> None:
    view.waiting = None if event.resumed else waiting_fields(event)


def _problem(view: _View, event: BlockedEvent | ErrorEvent) -> None:
    # The first says why the run ended; what went wrong while it ended comes after it.
    view.problem = event.message if view.problem is None else f"{view.problem}\n{event.message}"


def _finish(view: _View, event: FinishEvent) -> None:
    view.status = event.status
    view.waiting = None
    view.counts = {"actions": event.actions, "failures": event.failures, "exog_events": event.exog_events}


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
    PlanEvent: _plan,
    ReplanEvent: _plan,
    WaitingEvent: _waiting,
    BlockedEvent: _problem,
    ErrorEvent: _problem,
    FinishEvent: _finish,
}


def _latest_lines(latest: deque[TraceEvent]) -> list[dict[str, JsonValue]]:
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
