"""Run control: the one hook through which another thread holds, steps and stops a run, and
hands it events of its own. The debugger (`gpp dap`) and the operator console (`gpp run
--console`) are both run controls; a plain run has none.

The executor calls its control from the executor's own thread, at these points:

* `started(executor, prog)` once, after the entry procedure is entered and before its first
  transition (a debugger's stop on entry; the console's wait for Start);
* `checkpoint(executor, prog)` at the top of every turn of the executor's loop, after the
  platform's events are taken in and before the program's next transition is looked for (also
  on each wake-up of a waiting program);
* `stepping(executor, prog, step, after)` when the next transition is found, before it is
  performed: `step` (what it does to the world, with the span of its statement) takes `prog`
  to `after` (a debugger's breakpoints and stepping stop here, before the statement);
* `happened(executor, prog, happening)` when something a user may want to stop at happens: an
  action failed, the program is blocked, a run-time error, `solve` found no plan (before the run
  goes on or ends because of it);
* `attend(executor)` when the executor takes an `Attention` from the platform's queue: the
  control's other thread asked for it (see below).

Any of these may block for as long as the control likes: the run holds. While it holds nothing
asks the platform to let time pass, so a virtual-time platform's clock stands still; a
real-time platform's activities go on (their ends wait in the queue). Any of them may raise
`RunStopped`: the run ends as on Ctrl-C (activities cancelled, the trace finished), with the
stop's reason as the run's last error record. Look-ahead (`solve`, `search`) runs inside one
transition and never reaches a control.

The control's other thread (a debugger's protocol loop, the console's web server) never touches
the executor: it records what it wants (pause, stop, an operator's event) and calls
`request_attention(queue)`, which puts an `Attention` on the platform's event queue. That wakes a
waiting executor on every platform (a platform's `wait` returns when its queue is not empty), and
the executor hands it to `attend` in its own thread, where the control may write trace records
and put events on the queue.

`live()` says the control may still bring events (an operator at the console): a program that
is blocked, with nothing else able to happen, then waits for the control in real time instead
of ending as blocked.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, Protocol

from gpp.base.source import Span
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.contract import Activity, Attention, EventQueue, PlatformPort
from gpp.runtime.events import WaitingEvent
from gpp.runtime.state import Activities, GroundAction, State
from gpp.runtime.trace import Trace

if TYPE_CHECKING:
    from gpp.runtime.semantics import Prog, Semantics, Step


class Executor(Protocol):
    """What a control sees of the executor (gpp.runtime.executor.Executor), in the executor's
    thread only."""

    @property
    def program(self) -> CompiledProgram: ...
    @property
    def platform(self) -> PlatformPort: ...
    @property
    def trace(self) -> Trace: ...
    @property
    def sem(self) -> Semantics: ...
    @property
    def state(self) -> State: ...
    @property
    def acts(self) -> Activities: ...
    @property
    def records(self) -> Mapping[GroundAction, Activity]:
        """The activities not consumed yet, by action (changed in place by the executor)."""
        ...

    @property
    def waiting_at(self) -> WaitingEvent | None:
        """The `waiting` record of the wait the program is in (None: it is not waiting)."""
        ...

    def drain(self) -> None:
        """Take in the platform's queued events now (while the control holds the run)."""
        ...

    def operate(self, action: GroundAction, span: Span) -> str | None:
        """Run one action now, to its end (the console's actions before the start): None when
        it ran, else why not."""
        ...


class RunStopped(KeyboardInterrupt):
    """A run control ended the run (the operator's Stop, the debugger's disconnect or terminate).
    A KeyboardInterrupt so that every clean-up Ctrl-C runs runs for it too; `reason` is the
    one line the trace and the user get."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


HappeningKind = Literal["failed", "blocked", "error", "no-plan"]


@dataclass(frozen=True, slots=True)
class Happening:
    """Something a user may want to stop at (a debugger's exception breakpoints)."""

    kind: HappeningKind
    # One line saying what happened (for `blocked`, R0011's explanation).
    description: str
    span: Span | None = None
    # For `failed`: the platform time, the action (as in the trace) and the platform's reason.
    t: float | None = None
    action: str | None = None
    reason: str | None = None


class RunControl:
    """A control that does nothing: the base of the debugger's and the console's."""

    def started(self, executor: Executor, prog: Prog) -> None:
        """The entry procedure is entered; its first transition comes next."""

    def checkpoint(self, executor: Executor, prog: Prog) -> None:
        """A turn of the executor's loop begins: `prog` is what remains of the program."""

    def stepping(self, executor: Executor, prog: Prog, step: Step, after: Prog) -> None:
        """The next transition is found: `step` takes `prog` to `after`; it is performed next."""

    def happened(self, executor: Executor, prog: Prog | None, happening: Happening) -> None:
        """Something a user may want to stop at happened."""

    def attend(self, executor: Executor) -> None:
        """The control's other thread asked for the executor's attention."""

    def live(self) -> bool:
        """The control may still bring events: a blocked program waits for it."""
        return False

    def finished(self, executor: Executor) -> None:
        """The run ended (after its activities were stopped, before its `finish` record)."""


def request_attention(queue: EventQueue, time: float) -> None:
    """From the control's other thread: wake the executor and have it call `attend` (at platform
    time `time`, the clock's reading now)."""
    queue.put(Attention(), time)
