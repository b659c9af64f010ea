"""What `gpp run` shows while a program runs, fed only by trace events (the run view is not
tangled into the interpreter). On a terminal: a live panel with the platform clock, the
running activities, the current plan and the latest events. Elsewhere: one plain line per
event, so logs and CI output stay readable."""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol, TextIO, assert_never

from gpp.runtime.events import (
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    DroppedEvent,
    EndEvent,
    ErrorEvent,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    NoticeEvent,
    OperatorEvent,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    SnapshotEvent,
    StartEvent,
    StepEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    WarningEvent,
)
from gpp.runtime.values import show_json

if TYPE_CHECKING:
    from rich.console import Console, RenderableType
    from rich.live import Live

    from gpp.planner.dp import Progress
    from gpp.run.runner import RunOutcome


def describe(event: TraceEvent) -> str | None:
    """One line for a trace event (None for events not worth a line of their own)."""
    match event:
        case StartEvent():
            return f"start  {event.action}"
        case EndEvent():
            mark = "" if event.status == "final" else f"  [{event.status}]"
            return f"end    {event.action}{mark}"
        case UpdateEvent():
            if event.status == "final":
                return None
            return f"update {event.action} {event.status}" + (f" ({event.reason})" if event.reason else "")
        case ExogEvent():
            suffix = " (its precondition was false)" if event.precondition is False else ""
            if event.failed:
                suffix += " (its effect failed)"
            return f"exog   {event.action}{suffix}"
        case SenseEvent():
            return f"sense  {event.fluent} = {show_json(event.value)} (by {event.action})"
        case AssignEvent():
            return f"assign {event.fluent} = {show_json(event.value)}"
        case CancelEvent():
            return f"cancel {event.action}" + (f" ({event.reason})" if event.reason else "")
        case NoticeEvent():
            return "notice " + (f"{event.action}: " if event.action else "") + event.message
        case PlanEvent() | ReplanEvent():
            # A replan says why: the program's own `on_fail` handler is not a deviation.
            why = f"because {event.reason}; " if isinstance(event, ReplanEvent) and event.reason else ""
            if not event.feasible:
                return f"{event.EVENT:<6} {why}no feasible plan ({event.nodes} nodes)"
            policy = "; ".join(event.policy) or "(nothing to do)"
            return (
                f"{event.EVENT:<6} {why}value {event.value:g}, horizon {_horizon(event)}: {policy}"
                f"  [{event.nodes} nodes, {event.seconds:.3f} s]"
            )
        case BlockedEvent() | ErrorEvent():
            return f"{event.EVENT:<6} {event.message}"
        case WarningEvent():
            return f"warn   {event.message}" + (f" at {event.at}" if event.at else "")
        case DroppedEvent():
            return None  # its first one is a warning, shown as such
        case FinishEvent():
            return f"finish {event.status}"
        case WaitingEvent():
            if event.resumed or event.reason == "activity":
                # A planned activity's wait: its start and end lines tell it, as for any call
                # (the live panel, the summary and the page show which step of the plan it is).
                return None
            return f"wait   {event.condition}: {event.statement}" + (f" at {event.at}" if event.at else "")
        case OperatorEvent():
            return (
                f"operator {event.command}"
                + (f" {event.action}" if event.action else "")
                + (f" (from {event.client})" if event.client else "")
            )
        case HeaderEvent() | SnapshotEvent() | StepEvent():
            return None  # a step's records say what it did
        case _:
            assert_never(event)


class RunView(Protocol):
    """A trace listener that is also a context manager (set up and torn down around a run)."""

    shows: bool

    def __call__(self, event: TraceEvent) -> None: ...

    def progress(self, p: Progress) -> None:
        """A `solve` that has planned for more than a second says how far it got."""
        ...

    def watch_clock(self, now: Callable[[], float]) -> None:
        """The platform's clock, once the platform exists: a live view shows it between events."""
        ...

    def __enter__(self) -> RunView: ...

    def __exit__(self, *exc: object) -> None: ...


class NoView:
    """`--quiet`: show nothing while running."""

    shows = False

    def __call__(self, event: TraceEvent) -> None:
        pass

    def progress(self, p: Progress) -> None:
        pass

    def watch_clock(self, now: Callable[[], float]) -> None:
        pass

    def __enter__(self) -> NoView:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


class PlainView:
    """One line per event: `[   4.000 s] start  stack(a,table)`."""

    shows = True

    def __init__(self, out: TextIO) -> None:
        self.out = out

    def __call__(self, event: TraceEvent) -> None:
        line = describe(event)
        if line is not None:
            self.out.write(f"[{event.t:>9.3f} s] {line}\n")
            self.out.flush()

    def progress(self, p: Progress) -> None:
        self.out.write(f"{'':13} {progress_text(p)}\n")
        self.out.flush()

    def watch_clock(self, now: Callable[[], float]) -> None:
        pass  # one line per event: the event's time is the time

    def __enter__(self) -> PlainView:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


class LiveView:
    """A rich live panel, redrawn a few times a second. Its clock is the platform's, read at
    every redraw while the run goes on, so a long drive does not look hung; the events are
    recorded by the run's thread and drawn by rich's refresh thread (one lock guards both)."""

    shows = True

    def __init__(self, console: Console, title: str) -> None:
        self.console = console
        self.title = title
        self.time = 0.0
        self.running: dict[str, float] = {}
        self.events: deque[str] = deque(maxlen=10)
        self.plan: PlanEvent | ReplanEvent | None = None
        # Where the program is: the source location of the last action started or fluent set.
        self.at: str | None = None
        self.counts = {"actions": 0, "failed": 0, "exog": 0}
        # What the program waits for, while it waits.
        self.waiting: WaitingEvent | None = None
        # How a long `solve` is getting on, while it plans.
        self.planning: Progress | None = None
        # The platform's clock while the run goes on (None: only the events' times).
        self.clock: Callable[[], float] | None = None
        self._lock = threading.Lock()
        self._live: Live | None = None

    def watch_clock(self, now: Callable[[], float]) -> None:
        with self._lock:
            self.clock = now

    def __call__(self, event: TraceEvent) -> None:
        with self._lock:  # drawn by rich's refresh thread, 8 times a second
            self._record(event)

    def _record(self, event: TraceEvent) -> None:
        self.time = event.t
        match event:
            case StartEvent():
                if event.at:
                    self.at = f"{event.at}  {event.action}"
                self.running[event.action] = event.t
                self.counts["actions"] += 1
            case AssignEvent():
                if event.at:
                    self.at = f"{event.at}  {event.fluent}"
            case EndEvent() | CancelEvent():
                self.running.pop(event.action, None)
            case UpdateEvent(status="failed"):
                self.counts["failed"] += 1
            case ExogEvent():
                self.counts["exog"] += 1
            case PlanEvent() | ReplanEvent():
                self.plan = event
                self.planning = None
            case WaitingEvent():
                self.waiting = None if event.resumed else event
            case FinishEvent():
                self.clock = None  # the run is over: its last event's time is its end
            case _:
                pass
        line = describe(event)
        if line is not None:
            self.events.append(f"[dim]{event.t:>8.2f}s[/dim] {_escape(line)}")

    def progress(self, p: Progress) -> None:
        with self._lock:
            self.planning = p

    def now(self) -> float:
        """The time the panel shows: the platform's clock while the run goes on, else the time
        of the last event."""
        if self.clock is None:
            return self.time
        try:
            return max(self.time, self.clock())
        except Exception:  # a platform closing under the reading: its last event's time will do
            return self.time

    def render(self) -> RenderableType:
        with self._lock:
            return self._render()

    def _render(self) -> RenderableType:
        from rich.console import Group
        from rich.panel import Panel
        from rich.table import Table

        header = (
            f"[bold]{_escape(self.title)}[/bold]   t = {self.now():.2f} s   actions {self.counts['actions']}"
            f"   failed {self.counts['failed']}   exog events {self.counts['exog']}"
        )
        running = Table(show_header=True, header_style="bold", box=None, expand=False)
        running.add_column("running activity")
        running.add_column("since", justify="right")
        for action, since in self.running.items():
            running.add_row(_escape(action), f"{since:.2f} s")
        if not self.running:
            running.add_row("[dim](none)[/dim]", "")
        parts: list[RenderableType] = [header]
        if self.at is not None:
            parts.append(f"[dim]at[/dim] {_escape(self.at)}")
        if self.waiting is not None:
            w = self.waiting
            where = f" [dim]at {_escape(w.at)}[/dim]" if w.at else ""
            # A planned activity's condition says "waiting for ...": the panel does not repeat it.
            said = f" {w.condition.removeprefix('waiting ')}" if w.reason == "activity" else f": {w.condition}"
            parts.append(
                f"[yellow]waiting[/yellow] since {w.t:.2f} s{_escape(said)}\n        {_escape(w.statement)}{where}"
            )
        parts.append(running)
        if self.planning is not None:
            parts.append(f"[cyan]{_escape(progress_text(self.planning))}[/cyan]  [dim](Ctrl-C stops the run)[/dim]")
        if self.plan is not None and self.plan.feasible:
            plan = self.plan
            policy = " → ".join(plan.policy) or "(nothing to do)"
            title = f"{plan.EVENT} (value {plan.value:g}, horizon {_horizon(plan)})"
            parts.append(Panel(_escape(policy), title=title, title_align="left"))
        parts.append(Panel("\n".join(self.events) or "[dim](no events yet)[/dim]", title="events", title_align="left"))
        return Group(*parts)

    def __enter__(self) -> LiveView:
        from rich.live import Live

        self._live = Live(console=self.console, refresh_per_second=8, transient=False, get_renderable=self.render)
        self._live.__enter__()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._live is not None:
            self._live.refresh()
            self._live.__exit__(None, None, None)
            self._live = None


def _horizon(event: PlanEvent | ReplanEvent) -> str:
    """`4`, or `4 of 6` for a replan of a `solve` whose executed steps used part of its horizon."""
    written = event.written_horizon if isinstance(event, ReplanEvent) else None
    return f"{event.horizon} of {written}" if written is not None else str(event.horizon)


def progress_text(p: Progress) -> str:
    best = "none yet" if p.best is None else f"{p.best:g}"
    return f"planning: {p.nodes:,} nodes, {p.memo:,} configurations, best value {best}, {p.seconds:.1f} s"


def _escape(text: str) -> str:
    from rich.markup import escape

    return escape(text)


def summary_lines(outcome: RunOutcome) -> list[str]:
    """The run summary: how it ended, what was executed, time, and postcond."""
    result = outcome.result
    if result is None:
        if outcome.platform and not outcome.check.errors:
            return [f"not run: the program does not fit platform `{outcome.platform}`"]
        return ["not run: the program has errors"]
    lines = [f"{outcome.path} on {outcome.platform}: {result.status.value}"]
    failures = f"{result.failures} failed"
    if result.unhandled_failures:
        failures += f" ({result.unhandled_failures} not handled by the program)"
    lines.append(f"  actions executed   {result.actions} ({failures})")
    lines.append(f"  exogenous events   {result.exog_events}")
    lines.append(f"  steps              {result.steps}")
    ratio = result.platform_time / result.wall_time if result.wall_time > 0 else 0.0
    lines.append(
        f"  time               {result.platform_time:.3f} s platform, {result.wall_time:.3f} s wall"
        + (f" ({ratio:,.0f}x real time)" if result.platform_time > 0 else "")
    )
    if result.postcond is not None:
        lines.append(f"  postcond()         {'holds' if result.postcond else 'does NOT hold'}")
    return lines
