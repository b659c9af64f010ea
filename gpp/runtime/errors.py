"""Errors a running program can make; each stops the run with a diagnostic at the source."""

from __future__ import annotations

from gpp.base import diagnostics as diag
from gpp.base.source import Span


class GppRuntimeError(Exception):
    """A runtime error with its message (code and text, from gpp.codes) and the span of the
    expression or statement."""

    def __init__(
        self,
        message: diag.Message,
        span: Span | None,
        notes: tuple[str, ...] = (),
        label: str = "",
        secondary: tuple[diag.Label, ...] = (),
        help: str | None = None,
    ) -> None:
        super().__init__(message.text)
        self.code = message.code
        self.message = message.text
        self.span = span
        self.notes = notes
        self.label = label
        self.secondary = secondary
        self.help = help

    def diagnostic(self, fallback: Span | None = None) -> diag.Diagnostic | None:
        """The diagnostic at the error's span (or at `fallback` when it has none)."""
        span = self.span if self.span is not None else fallback
        if span is None:
            return None
        return diag.error(
            diag.Message(self.code, self.message),
            span,
            self.label,
            secondary=self.secondary,
            notes=self.notes,
            help=self.help,
        )


class WallClockReached(Exception):
    """Planning went on past the run's wall-clock bound (`--timeout`): the planner stops, and
    the executor stops the run at its timeout."""


class Unanswered(GppRuntimeError):
    """An exogenous function has no current answer (the platform's NoAnswer). Online, the step
    that evaluates it cannot be taken, as a false test, and the program waits for an answer;
    where no step can be held back (an effect, a `senses:` section, planning) it stops the run
    like any runtime error."""
