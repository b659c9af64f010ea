"""How gpp stops on a signal, one design for every command (docs/design.md, Signals).

The entry point (gpp.cli.main) calls `install()` before it imports anything else: SIGINT
(Ctrl-C) raises `Interrupted` and SIGTERM raises `Terminated`, both KeyboardInterrupts, so
every clean-up that Ctrl-C runs (a run cancels its activities and finishes its trace) runs
for SIGTERM too. Each handler also records the signal, and the entry point ends the process
by that record, not by the exception: 130 with "interrupted", 143 with "terminated (SIGTERM)".
A library that catches the KeyboardInterrupt on the way (the CLI library turns it into exit
code 130) cannot make SIGTERM look like Ctrl-C, and an interruption that Python drops (raised
in a `__del__` or a weak reference's callback) is raised again. Nothing else installs a
handler.
"""

from __future__ import annotations

import signal
import sys
from types import FrameType
from typing import Any

EXIT_INTERRUPTED = 128 + signal.SIGINT  # 130, as shells report a process ended by SIGINT
EXIT_TERMINATED = 128 + signal.SIGTERM  # 143

_received: signal.Signals | None = None


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT). A subclass, not KeyboardInterrupt itself: CPython 3.11 marks the process
    to end by SIGINT at exit when a KeyboardInterrupt (that very class) passes through `exec` of
    a string (dataclasses and gpp's generated code use it), even one the entry point handles."""


class Terminated(KeyboardInterrupt):
    """The process was asked to stop (SIGTERM): handled like Ctrl-C, reported as terminated."""


def install() -> None:
    """Handle SIGINT and SIGTERM as described above (in the main thread only, as Python allows)."""
    signal.signal(signal.SIGINT, _handle)
    signal.signal(signal.SIGTERM, _handle)
    sys.unraisablehook = _unraisable


def _unraisable(unraisable: Any) -> None:
    """An exception Python had to drop (one raised in a `__del__`, or in a weak reference's
    callback, which the import system runs after every import). When it is the interruption,
    it is raised again a millisecond later, where the program goes on (by SIGALRM: raising it
    from here would drop it again), and nothing is printed."""
    if isinstance(unraisable.exc_value, Interrupted | Terminated) and hasattr(signal, "setitimer"):
        signal.signal(signal.SIGALRM, _again)
        signal.setitimer(signal.ITIMER_REAL, 0.001)
        return
    sys.__unraisablehook__(unraisable)


def _again(signum: int, frame: FrameType | None) -> None:
    raise Terminated if _received is signal.SIGTERM else Interrupted


def _handle(signum: int, frame: FrameType | None) -> None:
    global _received
    _received = signal.Signals(signum)
    raise Terminated if signum == signal.SIGTERM else Interrupted


def received() -> signal.Signals | None:
    """The signal that asked the process to stop, if one did."""
    return _received


def is_termination(e: KeyboardInterrupt | None = None) -> bool:
    """Whether an interruption (or the recorded signal) is SIGTERM."""
    return isinstance(e, Terminated) or _received is signal.SIGTERM


def message(e: KeyboardInterrupt | None = None) -> str:
    """The one line that says why the process stopped."""
    return "terminated (SIGTERM)" if is_termination(e) else "interrupted"


def exit_code(e: KeyboardInterrupt | None = None) -> int:
    """The exit code of a process stopped by an interruption or the recorded signal."""
    return EXIT_TERMINATED if is_termination(e) else EXIT_INTERRUPTED


def ignore() -> None:
    """Ignore further signals: the process is ending and says why."""
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_IGN)
    if hasattr(signal, "setitimer"):
        signal.setitimer(signal.ITIMER_REAL, 0)  # an interruption raised again (`_unraisable`)


def end_at_once_on_sigterm() -> None:
    """SIGTERM ends the process at once, by the signal (for a command with nothing to finish,
    such as the language server, which an editor stops with SIGTERM)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
