"""The session backend: what the DAP server (gpp.dap.server) asks for everything it shows and
does. The server speaks the protocol; a backend runs or replays a program. `LiveBackend`
(gpp.dap.live) runs one; a trace backend replays a recorded run (`launch` with `"trace"`,
gpp.dap.launch chooses).

Threads: the server calls a backend from the protocol loop's thread; a backend tells the
server what happens (a stop, output, the end) through its `Client` from any thread.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol

from gpp.base.source import Span
from gpp.dap.breakpoints import Breakpoints
from gpp.dap.program import DebugProgram
from gpp.dap.protocol import DapError

# How a stopped run goes on.
Resumption = Literal["continue", "next", "stepIn", "stepOut", "stepBack", "reverseContinue"]

# The DAP `reason` of a stop.
StopReason = Literal["entry", "step", "breakpoint", "function breakpoint", "exception", "pause", "goto"]

# The thread every backend shows: a golog++ program is one thread of control (concurrent
# branches interleave in it).
THREAD_ID = 1


@dataclass(frozen=True, slots=True)
class StackFrame:
    id: int
    name: str
    span: Span | None


@dataclass(frozen=True, slots=True)
class Scope:
    name: str
    reference: int
    # DAP presentation hints: "arguments", "locals", "registers" or none.
    hint: str | None = None
    expensive: bool = False
    count: int | None = None


@dataclass(frozen=True, slots=True)
class Variable:
    name: str
    value: str
    type: str = ""
    # > 0: expandable (its children are `variables(reference)`).
    reference: int = 0
    # A golog++ expression that gives this value (the editor's "copy as expression", watch).
    evaluate_name: str | None = None


@dataclass(frozen=True, slots=True)
class Evaluated:
    result: str
    type: str = ""
    reference: int = 0


@dataclass(frozen=True, slots=True)
class Stop:
    """Why the run stopped: the DAP `stopped` event's body."""

    reason: StopReason
    description: str = ""
    text: str | None = None
    breakpoint_ids: tuple[int, ...] = ()


class Client(Protocol):
    """What a backend tells the server (from any thread)."""

    def stopped(self, stop: Stop) -> None: ...

    def output(self, text: str, category: str = "console", span: Span | None = None) -> None: ...

    def ended(self, exit_code: int) -> None:
        """The run is over (its trace finished): the server sends `exited` and `terminated`."""
        ...


class Host(Client, Protocol):
    """The server as a backend's maker sees it (gpp.dap.launch): the client and the table."""

    @property
    def breakpoints(self) -> Breakpoints: ...


@dataclass
class Capabilities:
    """What a backend can do beyond the common requests (DAP `capabilities` fields)."""

    step_back: bool = False
    extra: dict[str, Any] = field(default_factory=dict)


class SessionBackend(ABC):
    """A debugging session of one program, live or replayed. Every method except `start` is
    answered while the run is stopped (the server refuses them otherwise, with a clear error)."""

    capabilities = Capabilities()
    # The program being debugged: breakpoints are placed and expressions checked in it.
    program: DebugProgram

    @abstractmethod
    def start(self, stop_on_entry: bool) -> None:
        """Begin the run (after the editor's `configurationDone`)."""

    # ---- what a stopped run shows

    @abstractmethod
    def stack(self) -> list[StackFrame]:
        """The procedure calls, innermost first."""

    @abstractmethod
    def scopes(self, frame_id: int) -> list[Scope]: ...

    @abstractmethod
    def variables(self, reference: int) -> list[Variable]: ...

    @abstractmethod
    def evaluate(self, expression: str, frame_id: int | None, context: str) -> Evaluated:
        """A golog++ expression in the current situation, in the scope of frame `frame_id`
        (the top one when None). DapError with the located message when it does not check."""

    # ---- run control

    @abstractmethod
    def resume(self, how: Resumption) -> Stop | None:
        """Go on from a stop: continue, step over (`next`), in, out, or back (a trace only).
        A stop reached at once, without the run going on (a step into a call stops at the
        callee's first statement), is returned: the server sends it after the response."""

    @abstractmethod
    def pause(self) -> None:
        """Stop at the next transition."""

    @abstractmethod
    def stopped(self) -> bool:
        """The run is stopped (its state can be shown)."""

    @abstractmethod
    def terminate(self) -> None:
        """End the run as Ctrl-C does (activities cancelled, the trace finished); returns once
        it ended."""

    def unsupported(self, what: str) -> DapError:
        return DapError(f"{what} is not supported by this session")
