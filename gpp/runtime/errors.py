"""Errors a running program can make; each stops the run with a diagnostic at the source."""

from __future__ import annotations

from gpp import diagnostics as diag
from gpp.source import Span


class GppRuntimeError(Exception):
    """A runtime error with its code (R0xxx) and the span of the expression or statement."""

    def __init__(self, code: str, message: str, span: Span | None, notes: tuple[str, ...] = ()) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.span = span
        self.notes = notes

    def diagnostic(self) -> diag.Diagnostic | None:
        if self.span is None:
            return None
        return diag.error(self.code, self.message, self.span, notes=self.notes)
