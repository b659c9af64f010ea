"""The operator console as a run control (gpp.runtime.control): Start, Pause, Resume, Stop, an
exogenous event sent by hand, an action run before the start.

The server's thread only records a request (`ConsoleControl.request`) and asks for the
executor's attention; everything else happens in the executor's thread: the `operator` trace
record of each request, the event put on the platform's queue, the wait for Start, the hold of
a pause, the stop.
"""

from __future__ import annotations

import itertools
import math
import threading
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import gpp.runtime.events as ev
from gpp.base.source import Span
from gpp.console.state import ConsoleState, Form, Parameter, Setup
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import BOOL, NUMBER, STRING, SYMBOL, DomainType, Type
from gpp.platform.values import ConversionError
from gpp.run.runner import value_from_text
from gpp.runtime.compiled import domain_values
from gpp.runtime.contract import EventQueue, ExogOccurrence
from gpp.runtime.control import Executor, Happening, RunControl, RunStopped, request_attention
from gpp.runtime.semantics import Prog
from gpp.runtime.state import GroundAction
from gpp.runtime.values import Value, show

# Wall-clock seconds between looks at the run's requests while it holds (waiting for Start,
# paused): a request wakes it at once; the look lets Ctrl-C through.
HOLD_LOOK = 0.25
# Fluent instances the page shows at most (those of fluents with finite parameter types).
MAX_FLUENT_INSTANCES = 2000

STOP_REASON = "stopped by the operator at the console"


@dataclass(frozen=True, slots=True)
class Request:
    """What an operator asked for: `command` is one of ev.OPERATOR_COMMANDS; `action` the
    event or action (with `exog` and `act`); `client` who asked."""

    command: str
    action: GroundAction | None = None
    client: str | None = None


class ConsoleControl(RunControl):
    """The console's run control. `wait`: the run waits for Start before `main` begins
    (`--console-wait`)."""

    def __init__(self, state: ConsoleState, model: Model, wait: bool) -> None:
        self.state = state
        self.model = model
        self.wait = wait
        self.exogenous = forms(model, SymbolKind.EXOG_ACTION)
        self.actions = forms(model, SymbolKind.ACTION)
        self._requests: deque[Request] = deque()
        self._ready = threading.Condition()
        self._queue: EventQueue | None = None
        self._clock: Callable[[], float] | None = None
        self.started_run = not wait
        self.paused = False
        self.finished_run = False
        self._holding = False

    # ------------------------------------------------------------ the server's thread

    def request(self, request: Request) -> None:
        """Record a request and wake the executor (it is handled in the executor's thread)."""
        with self._ready:
            self._requests.append(request)
            self._ready.notify_all()
            queue = self._queue
        if queue is not None:
            request_attention(queue, self._now())

    def _now(self) -> float:
        return self.clock() or 0.0

    def clock(self) -> float | None:
        """The platform's clock now, once the run started (None before)."""
        clock = self._clock
        if not callable(clock):
            return None
        try:
            return float(clock())
        except Exception:  # a platform closing: no reading
            return None

    def can(self) -> dict[str, bool]:
        """Which requests the page offers now."""
        return {command: self.refusal(command) is None for command in ev.OPERATOR_COMMANDS}

    def refusal(self, command: str) -> str | None:
        """Why a request cannot be made now (None: it can)."""
        if self.finished_run:
            return "the run has ended"
        if command == "start" and self.started_run:
            return "the run has started"
        if command in ("pause", "resume") and not self.started_run:
            return "the run has not started"
        if command == "pause" and self.paused:
            return "the run is paused"
        if command == "resume" and not self.paused:
            return "the run is not paused"
        if command == "act" and self.started_run:
            return "an action is run by hand only before the start"
        if command == "exog" and not self.exogenous:
            return "the program has no exogenous action"
        return None

    # ------------------------------------------------------------ the executor's thread

    def started(self, executor: Executor, prog: Prog) -> None:
        with self._ready:
            self._queue = executor.platform.queue
            self._clock = executor.platform.now
        if self.wait:
            self.state.control_status = "waiting for Start"
        self.state.attach(executor, setup(executor, self.exogenous, self.actions))
        if not self.wait:
            self._handle(executor)
            return
        self._hold(executor, until=lambda: self.started_run)

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        if self.paused:
            self._hold(executor, until=lambda: not self.paused)

    def happened(self, executor: Executor, prog: Prog | None, happening: Happening) -> None:
        if happening.kind == "failed" and happening.t is not None and happening.action is not None:
            self.state.failed(happening.t, happening.action, happening.reason)

    def attend(self, executor: Executor) -> None:
        if not self._holding:
            self._handle(executor)

    def live(self) -> bool:
        # An operator can unblock a program only by an exogenous event (or end it by Stop).
        return bool(self.exogenous) and not self.finished_run

    def finished(self, executor: Executor) -> None:
        self.finished_run = True
        self.state.control_status = None
        self.state.nudge()

    def _hold(self, executor: Executor, until: Callable[[], bool]) -> None:
        """Handle requests until `until()` holds (Start given, pause ended)."""
        self._holding = True
        try:
            while not until():
                self._handle(executor)
                if until():
                    break
                with self._ready:
                    if not self._requests:
                        self._ready.wait(HOLD_LOOK)
        finally:
            self._holding = False

    def _handle(self, executor: Executor) -> None:
        """Every request recorded so far, in order."""
        while True:
            with self._ready:
                if not self._requests:
                    return
                request = self._requests.popleft()
            self._do(executor, request)

    def _do(self, executor: Executor, request: Request) -> None:
        command = request.command
        if command == "start" and self.started_run:
            return
        if command in ("pause", "resume") and (not self.started_run or self.paused == (command == "pause")):
            return
        if command == "act" and self.started_run:
            return
        now = executor.platform.now()
        action = request.action.text if request.action is not None else None
        executor.trace.emit(ev.OperatorEvent(t=now, command=command, action=action, client=request.client))
        if command == "start":
            self.started_run = True
            self.state.control_status = None
        elif command == "pause":
            self.paused = True
            self.state.control_status = "paused"
        elif command == "resume":
            self.paused = False
            self.state.control_status = None
        elif command == "stop":
            raise RunStopped(STOP_REASON)
        elif command == "exog":
            assert request.action is not None
            executor.platform.queue.put(ExogOccurrence(request.action.name, request.action.args), now)
            if not self.started_run or self.paused:
                # Nothing else takes events in while the run holds: the operator sees the
                # event's effects at once (the Scan before the Start).
                executor.drain()
        elif command == "act":
            assert request.action is not None
            why = executor.operate(request.action, _span(self.model, request.action.name))
            if why is not None:
                executor.trace.emit(ev.NoticeEvent(t=executor.platform.now(), message=f"not run: {why}"))
        self.state.nudge()


def ground(model: Model, name: str, args: Mapping[str, str], kind: SymbolKind) -> GroundAction:
    """The action an operator's form names, its arguments read from their text as the
    parameters' types say; ValueError with the reason when it is not one."""
    symbol = model.globals.get(name)
    if symbol is None or symbol.kind is not kind:
        what = "exogenous action" if kind is SymbolKind.EXOG_ACTION else "action"
        raise ValueError(f"the program has no {what} `{name}`")
    unknown = set(args) - {p.name for p in symbol.params}
    if unknown:
        raise ValueError(f"`{name}` has no parameter `{sorted(unknown)[0]}`")
    values: list[Value] = []
    for p in symbol.params:
        text = args.get(p.name)
        if text is None:
            raise ValueError(f"`{name}` needs a value for `{p.name}`")
        assert p.type is not None
        try:
            values.append(value_from_text(text, p.type))
        except ConversionError as e:
            raise ValueError(f"`{p.name}` of `{name}`: {e}") from None
    return GroundAction(name, tuple(values))


def _span(model: Model, name: str) -> Span:
    symbol = model.globals[name]
    assert symbol.span is not None
    return symbol.span


def forms(model: Model, kind: SymbolKind) -> tuple[Form, ...]:
    """The forms of the program's actions of `kind` (exogenous or not), by name."""
    found = [s for s in model.globals.values() if s.kind is kind and not s.predefined]
    return tuple(Form(s.name, tuple(_parameter(p, model) for p in s.params)) for s in sorted(found, key=_name))


def _name(symbol: Symbol) -> str:
    return symbol.name


def _parameter(param: Symbol, model: Model) -> Parameter:
    t = param.type
    if isinstance(t, DomainType):
        return Parameter(param.name, "choice", tuple(show(v) for v in t.values))
    if t is BOOL:
        return Parameter(param.name, "choice", ("true", "false"))
    if t is NUMBER:
        return Parameter(param.name, "number")
    if t is STRING:
        return Parameter(param.name, "string")
    if t is SYMBOL:
        return Parameter(param.name, "choice", tuple(s.name for s in model.declared_symbols()))
    return Parameter(param.name, "json")


def setup(executor: Executor, exogenous: tuple[Form, ...], actions: tuple[Form, ...]) -> Setup:
    """The fluent instances the page shows (those of fluents whose parameters all have finite
    types, up to MAX_FLUENT_INSTANCES), and the forms."""
    program = executor.program
    instances: list[tuple[int, str]] = []
    left_out = 0
    for symbol in program.model.globals.values():
        if symbol.kind is not SymbolKind.FLUENT or symbol.predefined or not all(_finite(p.type) for p in symbol.params):
            continue  # a parameter of an infinite type: its instances show once they are set
        domains = [domain_values(p.type, program.model) for p in symbol.params]
        count = math.prod(len(d) for d in domains)
        if len(instances) + count > MAX_FLUENT_INSTANCES:
            left_out += count
            continue
        for args in itertools.product(*domains):
            slot = program.slot(symbol.name, args)  # the slot made here, in the run's thread
            instances.append((slot, program.instance_text(slot)))
    return Setup(tuple(instances), exogenous, actions, left_out)


def _finite(t: Type | None) -> bool:
    return t is BOOL or t is SYMBOL or isinstance(t, DomainType)
