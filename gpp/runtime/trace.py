"""The run's record: one event per line (gpp.runtime.events), flushed as it happens, so that a
run stopped by Ctrl-C or a crash still leaves a complete trace up to that point."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import IO, TypeVar

from gpp.runtime.events import EventBase, TraceEvent, encode

E = TypeVar("E", bound=EventBase)

TraceListener = Callable[[TraceEvent], None]


class Trace:
    def __init__(self, path: Path | None = None, listeners: list[TraceListener] | None = None) -> None:
        self.records: list[TraceEvent] = []
        self.listeners = list(listeners or [])
        self._file: IO[str] | None = path.open("w", encoding="utf-8") if path is not None else None

    def emit(self, event: TraceEvent) -> TraceEvent:
        """Record the event: keep it, write its line to the trace file, tell the listeners."""
        self.records.append(event)
        if self._file is not None:
            self._file.write(encode(event) + "\n")
            self._file.flush()
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
