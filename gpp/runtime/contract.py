"""The platform contract as the executor sees it: what the executor asks of a platform (the
`PlatformPort`), the activities and events that cross it, and the program's side of it (the
`ProgramInterface`, with types and source spans for every mapping).

It lives in the runtime layer because the executor needs it; platforms (gpp.platform, a layer
above) implement it. The platform base class with its life cycle (create from a configuration,
attach, close) is `gpp.platform.base.Platform`.

The executor asks a platform to start and preempt activities and to evaluate exogenous
functions, and reads its clock. The platform reports back through one thread-safe EventQueue:
activity updates (final / failed / cancelled, with an optional sensing result), exogenous
events, changes of an exogenous function's answer (which wake a waiting program: it evaluates
its conditions again), messages the platform dropped because they do not fit the program, and
warnings. The executor drains the queue between program steps. When the program is blocked the
executor calls `wait(deadline)`: a virtual-time platform advances its clock to its next
scheduled happening; a real-time platform waits for the queue.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Protocol

from gpp.base.source import Span
from gpp.codes import R0007
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import Type
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.state import ActivityStatus, GroundAction
from gpp.runtime.values import Value
from gpp.syntax import ast
from gpp.syntax.walk import walk


class PlatformError(Exception):
    """A platform cannot do what it was asked (unknown mapped name, no connection, bad option...)."""


class NoAnswer(PlatformError):
    """An exogenous function has no current answer: no value has arrived yet, or the last one is
    older than the function may be. Not an error of the run: the step that reads the function
    cannot be taken (as a false test), and the platform reports an `ExogFunctionChanged` when
    an answer arrives. The message says why (it is shown while the program waits)."""


# ---------------------------------------------------------------- what crosses the contract


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
    # The platform's clock when the executor started it (NaN: not told).
    started: float = math.nan


@dataclass(frozen=True, slots=True)
class ActivityUpdate:
    activity_id: int
    status: ActivityStatus  # FINAL, FAILED or CANCELLED
    # The sensing result (for a `senses:` section), when the platform produced one.
    result: Value = None
    has_result: bool = False
    reason: str = ""


@dataclass(frozen=True, slots=True)
class ExogOccurrence:
    """An exogenous action happened: its golog++ name and argument values in parameter order."""

    action: str
    args: tuple[Value, ...]


@dataclass(frozen=True, slots=True)
class PlatformFault:
    """While the program runs, the platform found something about the program it cannot serve
    (a mapping it could check only once the robot showed the mapped name's type): the run
    stops with each problem as an error, as when the platform attaches."""

    problems: tuple[Problem, ...]


@dataclass(frozen=True, slots=True)
class PlatformNotice:
    """Something the program goes on without, for the trace: about an activity (its server
    refused to cancel it, its message reached nobody) or, without an id, about the platform."""

    message: str
    activity_id: int | None = None
    # The platform refused to stop the activity (its server refused the cancel): it still runs,
    # and its end is reported when it comes.
    cancel_refused: bool = False


@dataclass(frozen=True, slots=True)
class ExogFunctionChanged:
    """The answer of an exogenous function changed (a new message, a value that became too old):
    a waiting program evaluates its conditions again. Nothing else happens; a change that is
    still queued is not queued twice."""

    function: str


@dataclass(frozen=True, slots=True)
class MessageDropped:
    """The platform dropped what came in for an exogenous action or function (a message whose
    fields do not fit the parameters, messages lost in transport): the run goes on, the trace
    records it and the run warns (once per action) at `span`, the mapping it is about."""

    source: str  # where it came from, e.g. the topic name
    target: str  # the exogenous action or function it was for
    reason: str
    span: Span | None = None
    help: str | None = None
    count: int = 1  # how many messages


@dataclass(frozen=True, slots=True)
class PlatformWarning:
    """Something the program should know that stops nothing (e.g. a publisher whose QoS can
    lose messages): a warning at `span`."""

    message: str
    span: Span | None = None
    label: str = ""
    help: str | None = None


@dataclass(frozen=True, slots=True)
class Attention:
    """Put by a run control's own thread (gpp.runtime.control): the executor hands it to the
    control in the executor's thread. It wakes a waiting executor like any event."""


Event = (
    ActivityUpdate
    | ExogOccurrence
    | ExogFunctionChanged
    | MessageDropped
    | PlatformWarning
    | PlatformFault
    | PlatformNotice
    | Attention
)


class EventQueue:
    """Thread-safe FIFO of events; platforms put, the executor drains."""

    def __init__(self) -> None:
        self._items: deque[tuple[float, Event]] = deque()
        self._ready = threading.Condition()
        self._latest = -math.inf
        # Functions with an ExogFunctionChanged in the queue (one is enough).
        self._changed: set[str] = set()

    def put(self, event: Event, time: float) -> None:
        """Queue an event that happened at `time`. Events put by two threads are queued in the
        order they are put, and so are their times: a time earlier than the last one queued
        (taken by a thread that was overtaken) is raised to it, so that the trace's times
        never go back."""
        with self._ready:
            if isinstance(event, ExogFunctionChanged):
                if event.function in self._changed:
                    return
                self._changed.add(event.function)
            self._latest = max(self._latest, time)
            self._items.append((self._latest, event))
            self._ready.notify_all()

    def drain(self) -> list[tuple[float, Event]]:
        with self._ready:
            items = list(self._items)
            self._items.clear()
            self._changed.clear()
        return items

    def wait(self, timeout: float | None) -> bool:
        """Wait until an event is queued (or `timeout` seconds pass); True if one is."""
        with self._ready:
            if self._items:
                return True
            self._ready.wait(timeout)
            return bool(self._items)

    def wake(self) -> None:
        """Wake a `wait` with nothing queued: its caller looks again at what else it waits for
        (a clock that another thread moves)."""
        with self._ready:
            self._ready.notify_all()

    def __len__(self) -> int:
        with self._ready:
            return len(self._items)

    def pending(self) -> list[tuple[float, Event]]:
        """The events queued and not yet taken (what a debugger shows), oldest first."""
        with self._ready:
            return list(self._items)


class PlatformPort(Protocol):
    """What the executor needs of a platform while it runs a program."""

    @property
    def name(self) -> str: ...

    @property
    def queue(self) -> EventQueue: ...

    def start(self, activity: Activity) -> None:
        """Begin an activity; its end comes later as an ActivityUpdate on the queue. Raises
        PlatformError when the platform cannot even begin it."""

    def preempt(self, activity: Activity) -> None:
        """Ask a running activity to stop; a CANCELLED update acknowledges it (or the activity
        ends otherwise first). Does nothing for an activity that already ended."""

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        """Evaluate an exogenous function; `activity` is set while a `senses:` section of that
        activity is evaluated. Raises NoAnswer when there is no current answer (the program
        waits for one), PlatformError when it cannot be asked at all."""

    def now(self) -> float:
        """The platform's clock, in seconds since the run began."""

    def wait(self, deadline: float | None, wall_deadline: float | None = None) -> bool:
        """The program is blocked: make time pass until something is queued or `deadline`
        (platform time) is reached. Returns False when nothing can ever arrive, or when the
        wall clock reaches `wall_deadline` (a `time.monotonic()` moment: the run's
        `--timeout`) first: a platform whose waiting takes wall-clock time returns by then."""

    def live(self) -> bool:
        """Can an event still arrive (running activities, scheduled or live exogenous sources)?"""


# ---------------------------------------------------------------- the program's side


@dataclass(frozen=True, slots=True)
class Parameter:
    name: str
    type: Type


@dataclass(frozen=True, slots=True)
class MappedArgument:
    """One `name = expression` entry of a mapping: the backend's name for the value, the type of
    the expression, and where the entry is."""

    name: str
    type: Type
    span: Span
    # The action parameter the expression is, or "" when it is another expression.
    parameter: str = ""


@dataclass(frozen=True, slots=True)
class ActionBinding:
    """How the program maps an action onto the platform."""

    name: str
    params: tuple[Parameter, ...]
    mapped_name: str
    args: tuple[MappedArgument, ...]
    # For an action that senses: the type of the result that answers its `senses:` section,
    # the return type of the exogenous function the section calls (`d() = nav("/nav").distance`
    # is answered with a value of `nav`'s type, of which the section takes a field), or the
    # sensed fluent's type when the section calls none.
    sensing: Type | None
    # The mapped name in the `mapping:` section, or the action's name when it has no mapping.
    span: Span
    # False when the action has no `mapping:` (it is mapped to its own name and parameters).
    explicit: bool = True


@dataclass(frozen=True, slots=True)
class ExogActionBinding:
    """What a platform needs to know about an exogenous action to report it."""

    name: str
    params: tuple[Parameter, ...]
    mapped_name: str
    # Backend field name -> the parameter it fills.
    fields: Mapping[str, str]
    span: Span
    # Backend field name -> where the program names it.
    field_spans: Mapping[str, Span] = field(default_factory=dict)
    explicit: bool = True

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)

    @property
    def param_types(self) -> tuple[Type, ...]:
        return tuple(p.type for p in self.params)


@dataclass(frozen=True, slots=True)
class ExogFunctionSignature:
    name: str
    params: tuple[Parameter, ...]
    return_type: Type
    span: Span

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)


@dataclass(frozen=True, slots=True)
class ProgramInterface:
    """The program's side of the contract, handed to the platform before the run."""

    actions: Mapping[str, ActionBinding]
    exog_actions: Mapping[str, ExogActionBinding]
    exog_functions: Mapping[str, ExogFunctionSignature]

    def sensing(self, action: str) -> Type | None:
        binding = self.actions.get(action)
        return binding.sensing if binding is not None else None


@dataclass(frozen=True, slots=True)
class Problem:
    """Something about the program that the platform cannot serve, found when it attaches: the
    runner reports each as an error at `span` (a mapping in the program, or an entry of a data
    file such as a scenario), or at the program's entry when `span` is None."""

    message: str
    span: Span | None = None
    label: str = ""
    notes: tuple[str, ...] = ()
    help: str | None = None


def unfit_error(problem: Problem, platform: str, fallback: Span | None) -> GppRuntimeError:
    """A problem a platform found with the program (when it attached, or later: PlatformFault)
    as the error that reports it: R0007 at the mapping (or data file entry) it is about, else
    at `fallback`."""
    return GppRuntimeError(
        R0007.unfit(problem.message),
        problem.span or fallback,
        (*problem.notes, f"the program does not fit platform `{platform}`"),
        problem.label,
        help=problem.help,
    )


def program_interface(program: CompiledProgram) -> ProgramInterface:
    """The mapped actions, exogenous actions and exogenous functions of a program."""
    model = program.model
    actions: dict[str, ActionBinding] = {}
    exogs: dict[str, ExogActionBinding] = {}
    functions: dict[str, ExogFunctionSignature] = {}
    for symbol in model.globals.values():
        if symbol.predefined or symbol.span is None:
            continue
        if symbol.kind is SymbolKind.ACTION or symbol.kind is SymbolKind.EXOG_ACTION:
            info = program.action(symbol.name)
            mapping = _mapping(info.decl)
            params = _parameters(symbol)
            span = mapping.name.span if mapping is not None else symbol.span
            if symbol.kind is SymbolKind.ACTION:
                args = _mapped_arguments(model.type_of, mapping, params, symbol.span)
                sensing = _sensed_type(model, info.decl, info.senses.target.value_type) if info.senses else None
                actions[symbol.name] = ActionBinding(
                    symbol.name, params, info.mapped_name, args, sensing, span, mapping is not None
                )
            else:
                spans = {a.name.name: a.span for a in mapping.args} if mapping is not None else {}
                exogs[symbol.name] = ExogActionBinding(
                    symbol.name,
                    params,
                    info.mapped_name,
                    {backend: param for backend, param in info.mapped_params},
                    span,
                    spans,
                    mapping is not None,
                )
        elif symbol.kind is SymbolKind.EXOG_FUNCTION:
            assert symbol.type is not None
            functions[symbol.name] = ExogFunctionSignature(symbol.name, _parameters(symbol), symbol.type, symbol.span)
    return ProgramInterface(actions, exogs, functions)


def _sensed_type(model: Model, decl: ast.ActionDecl | None, assigned: Type) -> Type:
    """The type of the result that answers an action's `senses:` section: the return type of
    the first exogenous function the section calls, else the type of what it assigns."""
    section = decl.section(ast.SensesSection) if decl is not None else None
    if not isinstance(section, ast.SensesSection):
        return assigned
    calls = [
        (n.span.start, s.type)
        for n in walk(section.value)
        if isinstance(n, ast.Call)
        and (s := model.target(n)) is not None
        and s.kind is SymbolKind.EXOG_FUNCTION
        and s.type is not None
    ]
    return min(calls, key=lambda c: c[0])[1] if calls else assigned


def _mapping(decl: ast.ActionDecl | None) -> ast.Mapping | None:
    section = decl.section(ast.MappingSection) if decl is not None else None
    return section.mapping if isinstance(section, ast.MappingSection) else None


def _parameters(symbol: Symbol) -> tuple[Parameter, ...]:
    out: list[Parameter] = []
    for p in symbol.params:
        assert p.type is not None
        out.append(Parameter(p.name, p.type))
    return tuple(out)


def _mapped_arguments(
    type_of: _TypeOf, mapping: ast.Mapping | None, params: tuple[Parameter, ...], fallback: Span
) -> tuple[MappedArgument, ...]:
    if mapping is None:
        # Without a mapping, the action's parameters are passed by their own names.
        return tuple(MappedArgument(p.name, p.type, fallback, p.name) for p in params)
    return tuple(
        MappedArgument(
            a.name.name,
            type_of(a.value),
            a.span,
            a.value.name if isinstance(a.value, ast.Name) and any(p.name == a.value.name for p in params) else "",
        )
        for a in mapping.args
    )


class _TypeOf(Protocol):
    def __call__(self, expr: ast.Expr, /) -> Type: ...
