"""The run's record: one event per line (gpp.runtime.events), flushed as it happens, so that a
run stopped by Ctrl-C or a crash still leaves a complete trace up to that point."""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from pathlib import Path
from typing import IO, TypeVar

from gpp.runtime.events import EventBase, TraceEvent, encode

E = TypeVar("E", bound=EventBase)

TraceListener = Callable[[TraceEvent], None]


class TraceWriteError(Exception):
    """The trace file could not be written (a full disk, a device that takes nothing): the run
    stops, its activities are cancelled, and the command says why in one line."""


class Trace:
    def __init__(self, path: Path | None = None, listeners: list[TraceListener] | None = None) -> None:
        self.records: list[TraceEvent] = []
        self.listeners = list(listeners or [])
        self.path = path
        self._file: IO[str] | None = path.open("w", encoding="utf-8") if path is not None else None

    def emit(self, event: TraceEvent) -> TraceEvent:
        """Record the event: keep it, write its line to the trace file, tell the listeners. A
        write that fails raises TraceWriteError once; the file is not written again."""
        self.records.append(event)
        if self._file is not None:
            try:
                self._file.write(encode(event) + "\n")
                self._file.flush()
            except OSError as e:
                self._abandon()
                raise TraceWriteError(f"cannot write the trace '{self.path}': {e.strerror or e}") from None
        for listener in self.listeners:
            listener(event)
        return event

    def of(self, kind: type[E]) -> list[E]:
        """The events of one kind, in order: `trace.of(StartEvent)`."""
        return [e for e in self.records if isinstance(e, kind)]

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def _abandon(self) -> None:
        """Stop writing the file (what is still buffered is dropped, not written again)."""
        assert self._file is not None
        file, self._file = self._file, None
        with contextlib.suppress(OSError):
            file.close()
