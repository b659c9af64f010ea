"""The run's record: one JSON object per line, flushed as it happens, so that a run stopped by
Ctrl-C or a crash still leaves a complete trace up to that point."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

TraceRecord = dict[str, Any]


class Trace:
    def __init__(self, path: Path | None = None, listeners: list[Callable[[TraceRecord], None]] | None = None) -> None:
        self.records: list[TraceRecord] = []
        self.listeners = list(listeners or [])
        self._file: IO[str] | None = path.open("w", encoding="utf-8") if path is not None else None

    def emit(self, event: str, t: float, **fields: Any) -> TraceRecord:
        record: TraceRecord = {"t": round(float(t), 6), "event": event, **fields}
        self.records.append(record)
        if self._file is not None:
            self._file.write(json.dumps(record, ensure_ascii=False) + "\n")
            self._file.flush()
        for listener in self.listeners:
            listener(record)
        return record

    def events(self, kind: str) -> list[TraceRecord]:
        return [r for r in self.records if r["event"] == kind]

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
