"""Answers from the check of a document's earlier version, while its current text is being
checked: an edit changes one stretch of the text (gpp.syntax.incremental.changed_stretch);
what lies before it is where it was, what lies after it has moved by the difference in length,
and what lies in it the earlier check never saw."""

from __future__ import annotations

from dataclasses import dataclass

from lsprotocol import types

from gpp.base.source import Source
from gpp.syntax.incremental import changed_stretch
from lsp.ranges import position


class Unplaced(Exception):
    """An answer from an earlier check is about text that has changed since."""


@dataclass(frozen=True, slots=True)
class Moved:
    """How a text moved from its checked version to its current one: the stretch that changed
    (from `start`, to `checked_end` in the checked text and to `now_end` in the current one)."""

    start: int
    checked_end: int
    now_end: int

    @classmethod
    def between(cls, checked: str, now: str) -> Moved:
        return cls(*changed_stretch(checked, now))

    def to_checked(self, offset: int) -> int | None:
        """Where the character at `offset` of the current text was in the checked text; None
        when it is in the changed stretch."""
        if offset < self.start:
            return offset
        if offset >= self.now_end:
            return offset - self.now_end + self.checked_end
        return None

    def to_now(self, start: int, end: int) -> tuple[int, int] | None:
        """Where the stretch [start, end) of the checked text is now; None when the edit
        changed some of it."""
        if end <= self.start:
            return start, end
        if start >= self.checked_end:
            shift = self.now_end - self.checked_end
            return start + shift, end + shift
        return None


@dataclass(frozen=True, slots=True)
class EarlierText:
    """A file as an earlier check read it (`checked`) and as it is now."""

    checked: Source
    now: Source
    moved: Moved

    @classmethod
    def of(cls, checked: Source, now: Source) -> EarlierText:
        return cls(checked, now, Moved.between(checked.text, now.text))

    def offset_checked(self, where: types.Position) -> int | None:
        """The offset in the checked text of a position of the current text; None when the
        character there is new."""
        return self.moved.to_checked(self.now.lsp_offset(where.line, where.character))

    def range_now(self, r: types.Range) -> types.Range:
        """A range of the checked text, in the current text (Unplaced when it was edited)."""
        start = self.checked.lsp_offset(r.start.line, r.start.character)
        end = self.checked.lsp_offset(r.end.line, r.end.character)
        found = self.moved.to_now(start, end)
        if found is None:
            raise Unplaced
        return types.Range(start=position(self.now, found[0]), end=position(self.now, found[1]))
