"""gpp's spans as LSP positions and ranges (0-based lines, UTF-16 characters: Source.lsp_position),
for the features, the request handlers and the server alike."""

from __future__ import annotations

from lsprotocol import types

from gpp.base.source import Source, Span


def position(source: Source, offset: int) -> types.Position:
    """The LSP position of an offset of `source` (clamped to its text)."""
    line, character = source.lsp_position(offset)
    return types.Position(line=line, character=character)


def lsp_range(span: Span) -> types.Range:
    """The LSP range of a span (its ends clamped to the text)."""
    (l1, c1), (l2, c2) = span.lsp_range()
    return types.Range(start=types.Position(line=l1, character=c1), end=types.Position(line=l2, character=c2))
