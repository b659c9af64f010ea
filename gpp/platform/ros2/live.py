"""The run on ROS while it goes on: every trace record on the agent's `~/events` topic, and the
state the records tell so far on its latched `~/state` topic (docs/platforms.md, "The agent on
ROS"). Both are `std_msgs/String` holding JSON: a record exactly as its trace line, the state
as one object (`RunState.as_json`).

`LiveTopics` is a trace listener: it is told each record on the interpreter's thread, keeps
the record's line and the newest state, and hands the publishing to the spin thread (one task
for all the records that come before it runs; the states in between are not published). The
records the run writes before the node is up (its header) wait for it.
"""

from __future__ import annotations

import json
import math
import threading
from collections import deque
from typing import TYPE_CHECKING, Any

from gpp.runtime.events import (
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    FinishEvent,
    HeaderEvent,
    JsonValue,
    PlanEvent,
    ReplanEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    encode,
    waiting_fields,
)

if TYPE_CHECKING:
    from gpp.platform.ros2.bridge import Bridge

# The topics, relative to the agent's node: /gpp_agent/events and /gpp_agent/state by default.
EVENTS_TOPIC = "~/events"
STATE_TOPIC = "~/state"
# Records the events topic keeps for a subscriber that joins late (transient local).
EVENTS_KEPT = 1000


class RunState:
    """What a run's records tell so far: its status, the activities started and not consumed
    yet, the newest plan, what the program waits for, and the last error."""

    def __init__(self) -> None:
        self.t = 0.0
        self.records = 0
        self.program: str | None = None
        self.platform: str | None = None
        self.started: str | None = None
        self.status = "starting"
        self.activities: dict[int, dict[str, JsonValue]] = {}
        self.plan: dict[str, JsonValue] | None = None
        self.waiting: dict[str, JsonValue] | None = None
        self.error: str | None = None
        self.blocked: str | None = None

    def apply(self, event: TraceEvent) -> None:
        """Take one record into account."""
        self.t = event.t
        self.records += 1
        match event:
            case HeaderEvent():
                self.program, self.platform, self.started = event.program, event.platform, event.started
                self.status = "running"
            case StartEvent():
                self.activities[event.id] = {"id": event.id, "action": event.action, "status": "running"}
            case UpdateEvent():
                if event.id in self.activities:
                    self.activities[event.id]["status"] = event.status
            case CancelEvent():
                if event.id in self.activities:
                    self.activities[event.id]["cancelling"] = True
            case EndEvent():
                self._consume(event.action)
            case PlanEvent() | ReplanEvent():
                self.plan = {
                    "t": event.t,
                    "kind": event.kind,
                    "feasible": event.feasible,
                    "value": event.value if math.isfinite(event.value) else str(event.value),
                    "policy": list(event.policy),
                }
            case WaitingEvent():
                self.waiting = None if event.resumed else waiting_fields(event)
            case BlockedEvent():
                self.blocked = event.message
            case ErrorEvent():
                self.error = event.message
            case FinishEvent():
                self.status = event.status
                self.waiting = None
            case _:
                pass

    def _consume(self, action: str) -> None:
        """An `end` consumes the first terminated activity of that action (it has no id)."""
        same = [key for key, a in self.activities.items() if a["action"] == action]
        ended = [key for key in same if self.activities[key]["status"] != "running"]
        for key in (ended or same)[:1]:
            del self.activities[key]

    def as_json(self) -> dict[str, JsonValue]:
        """The state as the JSON object of the state topic."""
        return {
            "t": self.t,
            "status": self.status,
            "records": self.records,
            "program": self.program,
            "platform": self.platform,
            "started": self.started,
            "activities": list(self.activities.values()),
            "plan": self.plan,
            "waiting": self.waiting,
            "blocked": self.blocked,
            "error": self.error,
        }


class LiveTopics:
    """A trace listener that publishes the records and the state on the agent's node."""

    def __init__(self) -> None:
        self.state = RunState()
        self._lock = threading.Lock()
        self._lines: deque[str] = deque()
        self._state_due = False
        self._posted = False  # a `_publish` is on its way to the spin thread
        self._bridge: Bridge | None = None
        self._events: Any = None
        self._state: Any = None
        self._message: Any = None  # std_msgs.msg.String
        self.published = 0

    def __call__(self, event: TraceEvent) -> None:
        """On the interpreter's thread: a record of the run."""
        line = encode(event)
        with self._lock:
            self._lines.append(line)
            self.state.apply(event)
            self._state_due = True
            bridge = self._bridge if not self._posted else None
            self._posted = self._posted or bridge is not None
        if bridge is not None:
            bridge.post(self._publish)

    def attach(self, bridge: Bridge) -> None:
        """Make the publishers on the bridge's node (on its thread), then publish what waits."""
        from gpp.platform.ros2.binding import Qos
        from gpp.platform.ros2.interfaces import load_interface

        string = load_interface("std_msgs/msg/String")
        self._message = string.cls
        events = Qos(reliability="reliable", durability="transient_local", history="keep_last", depth=EVENTS_KEPT)
        latched = Qos(reliability="reliable", durability="transient_local", history="keep_last", depth=1)
        self._events = bridge.call(bridge.publisher, EVENTS_TOPIC, string, events)
        self._state = bridge.call(bridge.publisher, STATE_TOPIC, string, latched)
        with self._lock:
            self._bridge = bridge
        bridge.call(self._publish)

    @property
    def topics(self) -> tuple[str, str]:
        """The full names of the events and state topics (once attached)."""
        return str(self._events.topic_name), str(self._state.topic_name)

    def flush(self) -> None:
        """Publish what waits, now (before the node closes)."""
        bridge = self._bridge
        if bridge is not None:
            bridge.call(self._publish)

    def _publish(self) -> None:
        """On the spin thread: every record that waits, in order, then the newest state."""
        with self._lock:
            self._posted = False
            lines = list(self._lines)
            self._lines.clear()
            state = json.dumps(self.state.as_json(), ensure_ascii=False) if self._state_due else None
            self._state_due = False
        for line in lines:
            self._events.publish(self._message(data=line))
        self.published += len(lines)
        if state is not None:
            self._state.publish(self._message(data=state))
