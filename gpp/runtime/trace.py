"""The run's record: one event per line (gpp.runtime.events), flushed as it happens, so that a
run stopped by Ctrl-C or a crash still leaves a complete trace up to that point.

A Trace keeps no events: its memory does not grow with the run. Whoever needs the events
asks for a listener (`Recording`, all of them or the latest few) or reads the file. A listener
that wants only a few kinds of record says so (`KindListener`): the trace tells it only those,
so a run that makes many records of the other kinds pays nothing for it.

A long run's trace can be split into parts (`TraceSplit`: by size, by platform time): the
first part is the file given (`run.jsonl`), the next ones `run.1.jsonl`, `run.2.jsonl`, ...
(`part_path`). Every part is a trace of its own: it starts with the run's header (with its
part number and the previous part's name) and a snapshot of the state (SnapshotEvent).
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TypeVar

from gpp.runtime.events import EventBase, FinishEvent, HeaderEvent, SnapshotEvent, TraceEvent, decode, encode

E = TypeVar("E", bound=EventBase)

TraceListener = Callable[[TraceEvent], None]


class TraceWriteError(Exception):
    """The trace file could not be written (a full disk, a device that takes nothing): the run
    stops, its activities are cancelled, and the command says why in one line."""


class Recording:
    """A trace listener that keeps the events it is told: all of them (`keep=None`; memory
    grows with the run), or only the latest `keep`; with `kinds`, only events of those kinds."""

    def __init__(self, keep: int | None = None, kinds: tuple[type[EventBase], ...] = ()) -> None:
        self.records: deque[TraceEvent] | list[TraceEvent] = deque(maxlen=keep) if keep is not None else []
        self.kinds = kinds

    def __call__(self, event: TraceEvent) -> None:
        if not self.kinds or isinstance(event, self.kinds):
            self.records.append(event)

    def of(self, kind: type[E]) -> list[E]:
        """The events of one kind, in order: `recording.of(StartEvent)`."""
        return [e for e in self.records if isinstance(e, kind)]

    def __iter__(self) -> Iterator[TraceEvent]:
        return iter(self.records)

    def __len__(self) -> int:
        return len(self.records)


@dataclass(frozen=True, slots=True)
class KindListener:
    """A listener told only the records of `kinds` (a Trace looks the record's class up: the
    records of other kinds cost nothing, not even a call)."""

    kinds: frozenset[type[EventBase]]
    listener: TraceListener

    def __call__(self, event: TraceEvent) -> None:
        if type(event) in self.kinds:
            self.listener(event)


@dataclass(frozen=True, slots=True)
class TraceSplit:
    """When a trace file goes on in a new part: once it holds `max_bytes`, or once it covers
    `max_seconds` of platform time (either, when both are given)."""

    max_bytes: int | None = None
    max_seconds: float | None = None


def part_path(first: Path, part: int) -> Path:
    """The file of part `part` (0: the first) of the trace whose first part is `first`:
    `run.jsonl`, `run.1.jsonl`, `run.2.jsonl`, ... (`run`, `run.1`, ... without a suffix)."""
    if part == 0:
        return first
    stem = first.name[: -len(first.suffix)] if first.suffix else first.name
    return first.with_name(f"{stem}.{part}{first.suffix}")


def part_header(path: Path) -> HeaderEvent | None:
    """The header of the trace file at `path`, if its first line is one."""
    try:
        with path.open("rb") as file:
            line = file.readline(1 << 20)
        event = decode(line)
    except (OSError, ValueError, TypeError):
        return None
    return event if isinstance(event, HeaderEvent) else None


def trace_parts(first: Path) -> list[Path]:
    """The parts of the trace whose first part is `first`, in order: `first`, then each
    `part_path(first, n)` whose header says it follows the part before it in the same run."""
    parts = [first]
    head = part_header(first)
    if head is None or head.part is not None:
        return parts
    while True:
        candidate = part_path(first, len(parts))
        header = part_header(candidate) if candidate.is_file() else None
        if header is None or header.part != len(parts) or header.previous != parts[-1].name:
            return parts
        if dataclasses.replace(header, t=head.t, part=None, previous=None) != head:
            return parts  # a part of another run that wrote to the same name
        parts.append(candidate)


class Trace:
    def __init__(
        self, path: Path | None = None, listeners: list[TraceListener] | None = None, split: TraceSplit | None = None
    ) -> None:
        """A trace written to `path` (None: to no file, only to the listeners), split into parts
        as `split` says. The parts after the first that an earlier run left at this name are
        removed (they would read as part of this run)."""
        self.listeners: list[TraceListener] = []
        # The listeners of some kinds only, by kind (KindListener).
        self.by_kind: dict[type, list[TraceListener]] = {}
        for listener in listeners or []:
            if isinstance(listener, KindListener):
                for kind in listener.kinds:
                    self.by_kind.setdefault(kind, []).append(listener.listener)
            else:
                self.listeners.append(listener)
        self.path = path
        self.split = split if path is not None else None
        # Records written to this trace (all parts), and whether the `finish` was one of them.
        self.written = 0
        self.finished = False
        # The run's header (each part starts with it), and the part being written.
        self.header: HeaderEvent | None = None
        self.part = 0
        self._part_bytes = 0
        self._part_since: float | None = None
        self._part_records = 0
        self._file: IO[str] | None = None
        if path is not None:
            self._file = path.open("w", encoding="utf-8")
            _remove_stale_parts(path)

    @property
    def part_file(self) -> Path | None:
        """The file of the part being written."""
        return part_path(self.path, self.part) if self.path is not None else None

    def emit(self, event: TraceEvent) -> TraceEvent:
        """Record the event: write its line to the trace file, tell the listeners. A write that
        fails raises TraceWriteError once; the file is not written again."""
        if isinstance(event, HeaderEvent) and self.header is None:
            self.header = event
        self._write(event)
        self.written += 1
        if isinstance(event, FinishEvent):
            self.finished = True
        for listener in self.listeners:
            listener(event)
        if self.by_kind:
            for listener in self.by_kind.get(type(event), ()):
                listener(event)
        return event

    def listen(self, kind: type[EventBase], listener: TraceListener) -> None:
        """Tell `listener` the records of `kind` from now on (from the run's thread; a record
        being told meanwhile is told to the listeners it found)."""
        self.by_kind[kind] = [*self.by_kind.get(kind, ()), listener]

    def unlisten(self, kind: type[EventBase], listener: TraceListener) -> None:
        """Stop telling `listener` the records of `kind` (as `listen`)."""
        rest = [other for other in self.by_kind.get(kind, ()) if other != listener]
        if rest:
            self.by_kind[kind] = rest
        else:
            self.by_kind.pop(kind, None)

    def split_due(self, now: float) -> bool:
        """Should the trace go on in a new part (asked between steps, where the state is whole)?
        Never before the part holds a record after its header and snapshot."""
        split = self.split
        if split is None or self._file is None or self.header is None or self._part_records < 3:
            return False
        if split.max_bytes is not None and self._part_bytes >= split.max_bytes:
            return True
        since = self._part_since
        return split.max_seconds is not None and since is not None and now - since >= split.max_seconds

    def next_part(self, snapshot: SnapshotEvent) -> None:
        """Close this part and go on in the next: its header (the run's, with the part number
        and the previous part's name) and `snapshot`, the state here. The listeners are not
        told: these two records are the file's, not the run's."""
        assert self.path is not None and self.header is not None and self._file is not None
        previous = self.part_file
        assert previous is not None
        self._close_file()
        self.part += 1
        target = part_path(self.path, self.part)
        try:
            self._file = target.open("w", encoding="utf-8")
        except OSError as e:
            raise TraceWriteError(f"cannot write the trace '{target}': {e.strerror or e}") from None
        self._part_bytes = self._part_records = 0
        self._part_since = None
        self._write(dataclasses.replace(self.header, t=snapshot.t, part=self.part, previous=previous.name))
        self._write(snapshot)

    def close(self) -> None:
        if self._file is not None:
            self._close_file()

    def _write(self, event: TraceEvent) -> None:
        if self._file is None:
            return
        line = encode(event) + "\n"
        try:
            self._file.write(line)
            self._file.flush()
        except OSError as e:
            self._close_file()  # not written again
            raise TraceWriteError(f"cannot write the trace '{self.part_file}': {e.strerror or e}") from None
        self._part_bytes += len(line) if line.isascii() else len(line.encode("utf-8"))
        self._part_records += 1
        if self._part_since is None:
            self._part_since = event.t

    def _close_file(self) -> None:
        assert self._file is not None
        file, self._file = self._file, None
        # Every line was flushed when written; after a failed write what is still buffered is
        # dropped, not written again.
        with contextlib.suppress(OSError):
            file.close()


def _remove_stale_parts(first: Path) -> None:
    """Remove `part_path(first, 1)`, `part_path(first, 2)`, ... while each is a part of a trace
    (a header with that part number): an earlier run's parts at the name this run writes."""
    part = 1
    while True:
        candidate = part_path(first, part)
        header = part_header(candidate) if candidate.is_file() else None
        if header is None or header.part != part:
            return
        with contextlib.suppress(OSError):
            candidate.unlink()
        part += 1
