"""The platform interface: one contract between the executor and the world (a simulator, a
robot, a dummy).

The executor asks a platform to start and preempt activities and to evaluate exogenous
functions, and reads its clock. The platform reports back through one thread-safe EventQueue:
activity updates (final / failed / cancelled, with an optional sensing result) and exogenous
events. The executor drains the queue between program steps. When the program is blocked the
executor calls `wait(deadline)`: a virtual-time platform advances its clock to its next
scheduled happening; a real-time platform waits for the queue.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field

from gpp.model.types import Type
from gpp.runtime.state import ActivityStatus, GroundAction
from gpp.runtime.values import Value


class PlatformError(Exception):
    """A platform cannot do what it was asked (unknown mapped name, no connection, ...)."""


@dataclass(frozen=True, slots=True)
class Activity:
    """A started action as the platform sees it."""

    id: int
    action: GroundAction
    mapped_name: str
    # Mapped arguments, evaluated when the activity starts (LANGUAGE.md §7.2).
    args: Mapping[str, Value]
    # `duration: [min, max]` of the action, if given.
    duration: tuple[float, float] | None = None


@dataclass(frozen=True, slots=True)
class ActivityUpdate:
    activity_id: int
    status: ActivityStatus  # FINAL, FAILED or CANCELLED
    # The sensing result (for a `senses:` section), when the platform produced one.
    result: Value = None
    has_result: bool = False
    reason: str = ""


@dataclass(frozen=True, slots=True)
class ExogEvent:
    """An exogenous action happened: its golog++ name and argument values in parameter order."""

    action: str
    args: tuple[Value, ...]


Event = ActivityUpdate | ExogEvent


class EventQueue:
    """Thread-safe FIFO of events; platforms put, the executor drains."""

    def __init__(self) -> None:
        self._items: deque[tuple[float, Event]] = deque()
        self._ready = threading.Condition()

    def put(self, event: Event, time: float) -> None:
        with self._ready:
            self._items.append((time, event))
            self._ready.notify_all()

    def drain(self) -> list[tuple[float, Event]]:
        with self._ready:
            items = list(self._items)
            self._items.clear()
        return items

    def wait(self, timeout: float | None) -> bool:
        """Wait until an event is queued (or `timeout` seconds pass); True if one is."""
        with self._ready:
            if self._items:
                return True
            self._ready.wait(timeout)
            return bool(self._items)

    def __len__(self) -> int:
        with self._ready:
            return len(self._items)


@dataclass(frozen=True, slots=True)
class ExogSignature:
    """What a platform needs to know about an exogenous action to report it."""

    name: str
    params: tuple[str, ...]
    param_types: tuple[Type, ...]
    mapped_name: str
    # backend field name -> parameter name
    fields: Mapping[str, str] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class ProgramInterface:
    """The program's side of the contract, handed to the platform before the run."""

    actions: Mapping[str, tuple[str, tuple[str, ...]]]  # action -> (mapped name, mapped argument names)
    exog_actions: Mapping[str, ExogSignature]
    exog_functions: Mapping[str, tuple[tuple[str, ...], Type]]  # name -> (parameter names, return type)
    # Actions with a `senses:` section -> the type of the sensed value.
    sensing: Mapping[str, Type] = field(default_factory=dict)


class Platform:
    """Base class of platforms. Subclasses override what they serve."""

    name = "platform"
    # True when time is simulated (the run goes as fast as the CPU allows).
    virtual_time = True

    def __init__(self) -> None:
        self.queue = EventQueue()

    def attach(self, interface: ProgramInterface) -> list[str]:
        """Called once before the run. Returns problems with the program's mappings (unknown
        mapped names or arguments), each a message; an empty list means the program fits."""
        return []

    def start(self, activity: Activity) -> None:
        raise NotImplementedError

    def preempt(self, activity: Activity) -> None:
        raise NotImplementedError

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        """Evaluate an exogenous function; `activity` is set while a `senses:` section of that
        activity is evaluated. (When the activity's update carried a result, the executor
        answers with it and does not ask the platform.)"""
        raise PlatformError(f"platform `{self.name}` does not provide exogenous function `{name}`")

    def now(self) -> float:
        raise NotImplementedError

    def wait(self, deadline: float | None) -> bool:
        """The program is blocked: make time pass until something is queued or `deadline`
        (platform time) is reached. Returns False when nothing can ever arrive."""
        raise NotImplementedError

    def live(self) -> bool:
        """Can an event still arrive (running activities, scheduled or live exogenous sources)?"""
        return True

    def close(self) -> None:
        """Stop threads and release resources. Called once, also after errors."""
