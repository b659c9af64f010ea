"""Diagnostics: one type for every problem gpp reports, from syntax errors to failed runs.

A Diagnostic carries a stable code, a severity, a primary span with an optional label,
labelled secondary spans, notes, a help line and an optional fix (replacement edits). The
renderers in gpp.report.text turn it into rustc-style terminal text, plain text or JSON.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from enum import Enum
from typing import NamedTuple, TypedDict, Unpack

from gpp.base.source import Span


class Severity(Enum):
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@dataclass(frozen=True, slots=True)
class Label:
    """A span with a short message, drawn under the source line."""

    span: Span
    message: str = ""


@dataclass(frozen=True, slots=True)
class Edit:
    """Replace the text of `span` with `text` (an insertion when the span is empty)."""

    span: Span
    text: str


class Applicability(Enum):
    """Whether `gpp check --fix` may apply a fix on its own (as ruff's safe and unsafe fixes).

    SAFE: the fix keeps what the program means or repairs it in the one way the diagnostic
    names (a missing `;`, the only close name for a misspelled one); UNSAFE: the fix is a guess
    among several, or changes what the program does. Both are shown and carried in JSON/SARIF."""

    SAFE = "safe"
    UNSAFE = "unsafe"


@dataclass(frozen=True, slots=True)
class Fix:
    """A suggested change: a description, the edits that make it, and whether it is safe."""

    message: str
    edits: tuple[Edit, ...]
    applicability: Applicability = Applicability.UNSAFE

    @property
    def is_safe(self) -> bool:
        return self.applicability is Applicability.SAFE


class Message(NamedTuple):
    """A diagnostic's code and its text, as a message of the registry (gpp.codes) makes them
    (`E0204.cannot_compare(left, right)`). The code is "" for a problem without one (an
    unreadable `gpp.toml`)."""

    code: str
    text: str


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    span: Span
    label: str = ""
    secondary: tuple[Label, ...] = ()
    notes: tuple[str, ...] = ()
    help: str | None = None
    fix: Fix | None = None

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def sort_key(self) -> tuple[str, int, int, str]:
        return (self.span.source.path, self.span.start, self.span.end, self.code)


class Details(TypedDict, total=False):
    """The optional parts of a diagnostic, as keyword arguments of `error` and `warning`."""

    secondary: Iterable[Label]
    notes: Iterable[str]
    help: str | None
    fix: Fix | None


def _make(severity: Severity, message: Message, span: Span, label: str, details: Details) -> Diagnostic:
    return Diagnostic(
        message.code,
        severity,
        message.text,
        span,
        label,
        tuple(details.get("secondary", ())),
        tuple(details.get("notes", ())),
        details.get("help"),
        details.get("fix"),
    )


def error(message: Message, span: Span, label: str = "", **details: Unpack[Details]) -> Diagnostic:
    return _make(Severity.ERROR, message, span, label, details)


def warning(message: Message, span: Span, label: str = "", **details: Unpack[Details]) -> Diagnostic:
    return _make(Severity.WARNING, message, span, label, details)


@dataclass
class DiagnosticSink:
    """Collects diagnostics from a phase; phases append, callers read `items`."""

    items: list[Diagnostic] = field(default_factory=list)

    def add(self, diagnostic: Diagnostic) -> None:
        self.items.append(diagnostic)

    @property
    def has_errors(self) -> bool:
        return any(d.is_error for d in self.items)
