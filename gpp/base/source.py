"""Source text and positions: every diagnostic and every syntax node points into a Source."""

from __future__ import annotations

import re
from bisect import bisect_right
from dataclasses import dataclass
from pathlib import Path

# A line ends at `\n`, `\r\n` or a lone `\r` (as editors and the Language Server Protocol count).
_LINE_BREAK = re.compile(r"\r\n?|\n")

BOM = "\ufeff"


@dataclass(frozen=True, slots=True)
class NotText:
    """Why bytes are not a UTF-8 text file: the first NUL byte or byte that is not UTF-8."""

    offset: int  # character offset of the bad byte in the decoded text (after the BOM, if any)
    byte: int  # its value

    def describe(self) -> str:
        if self.byte == 0:
            return "a NUL byte (0x00)"
        return f"invalid UTF-8 byte 0x{self.byte:02x}"


def decode_text(raw: bytes) -> tuple[str, NotText | None]:
    """Decode a file's bytes as UTF-8 text. A byte-order mark at the start is dropped (so that
    columns count from the first real character). Returns the text, with any invalid byte
    replaced by U+FFFD, and what makes the bytes not text, if anything: the first NUL byte or
    invalid UTF-8 sequence. Linear in the size of the input."""
    skip = 3 if raw.startswith(b"\xef\xbb\xbf") else 0
    bad: int | None = None
    try:
        text = raw[skip:].decode("utf-8")
    except UnicodeDecodeError as e:
        bad = skip + e.start
        text = raw[skip:].decode("utf-8", errors="replace")
    nul = raw.find(b"\x00", skip, bad)
    if nul >= 0:
        bad = nul
    if bad is None:
        return text, None
    offset = len(raw[skip:bad].decode("utf-8"))
    return text, NotText(offset, raw[bad])


class Source:
    """The text of one file, with the line table needed to turn offsets into positions.

    `path` is the name diagnostics show (relative to the working directory when below it);
    `identity` says which file this is whatever the working directory: the resolved absolute
    path for a file (or `path` itself for text that is no file, such as `<input>`).
    """

    __slots__ = ("_line_starts", "identity", "path", "text")

    def __init__(self, text: str, path: str = "<input>", identity: str | None = None) -> None:
        self.path = path
        self.text = text
        self.identity = path if identity is None else identity
        self._line_starts: list[int] | None = None

    @classmethod
    def from_file(cls, path: str | Path) -> Source:
        """The file's text, decoded by `decode_text` (invalid bytes replaced)."""
        p = Path(path)
        text, _ = decode_text(p.read_bytes())
        return cls(text, str(path), str(p.resolve()))

    def __repr__(self) -> str:
        return f"Source({self.path!r})"

    @property
    def line_starts(self) -> list[int]:
        if self._line_starts is None:
            starts = [0]
            text = self.text
            if "\r" in text:
                starts.extend(m.end() for m in _LINE_BREAK.finditer(text))
            else:
                i = text.find("\n")
                while i >= 0:
                    starts.append(i + 1)
                    i = text.find("\n", i + 1)
            self._line_starts = starts
        return self._line_starts

    def line_col(self, offset: int) -> tuple[int, int]:
        """1-based line and column (in characters) of an offset."""
        starts = self.line_starts
        line = bisect_right(starts, offset) - 1
        return line + 1, offset - starts[line] + 1

    def line_count(self) -> int:
        return len(self.line_starts)

    def line_text(self, line: int) -> str:
        """The text of a 1-based line, without its line break."""
        starts = self.line_starts
        start = starts[line - 1]
        end = starts[line] if line < len(starts) else len(self.text)
        return self.text[start:end].rstrip("\r\n")

    def offset_of(self, line: int, col: int) -> int:
        """Offset of a 1-based line and column, clamped to the text."""
        starts = self.line_starts
        line = max(1, min(line, len(starts)))
        return min(starts[line - 1] + max(col, 1) - 1, len(self.text))

    def lsp_position(self, offset: int) -> tuple[int, int]:
        """0-based line and UTF-16 character of an offset, as the Language Server Protocol counts
        (a character beyond U+FFFF is two UTF-16 units)."""
        offset = max(0, min(offset, len(self.text)))
        line = self.line_col(offset)[0]
        start = self.line_starts[line - 1]
        return line - 1, _utf16_units(self.text, start, offset)

    def lsp_offset(self, line: int, character: int) -> int:
        """The offset of a 0-based line and UTF-16 character (the other direction of
        `lsp_position`). As the protocol says, a line beyond the text means its end, and a
        character beyond the line's end means the end of the line (before its line break); a
        position inside a surrogate pair is taken as the character it splits."""
        starts = self.line_starts
        if line < 0:
            return 0
        if line >= len(starts):
            return len(self.text)
        start = starts[line]
        end = len(self.text) if line + 1 >= len(starts) else starts[line + 1]
        while end > start and self.text[end - 1] in "\r\n":
            end -= 1
        text = self.text
        if _utf16_units(text, start, end) == end - start:  # no character beyond U+FFFF
            return start + max(0, min(character, end - start))
        units = 0
        i = start
        while i < end and units < character:
            units += 2 if ord(text[i]) > 0xFFFF else 1
            i += 1
        return i


def _utf16_units(text: str, start: int, end: int) -> int:
    """How many UTF-16 code units text[start:end] takes."""
    part = text[start:end]
    if part.isascii():
        return len(part)
    return len(part) + sum(1 for ch in part if ord(ch) > 0xFFFF)


@dataclass(frozen=True, slots=True)
class Span:
    """A half-open range of offsets [start, end) in a Source."""

    source: Source
    start: int
    end: int

    @property
    def line(self) -> int:
        return self.source.line_col(self.start)[0]

    @property
    def col(self) -> int:
        return self.source.line_col(self.start)[1]

    @property
    def end_line(self) -> int:
        return self.source.line_col(self.end)[0]

    @property
    def end_col(self) -> int:
        return self.source.line_col(self.end)[1]

    @property
    def text(self) -> str:
        return self.source.text[self.start : self.end]

    def to(self, other: Span) -> Span:
        """The span from the start of this one to the end of `other`."""
        return Span(self.source, self.start, other.end)

    def contains(self, offset: int) -> bool:
        return self.start <= offset <= self.end

    def lsp_range(self) -> tuple[tuple[int, int], tuple[int, int]]:
        return self.source.lsp_position(self.start), self.source.lsp_position(self.end)

    def __str__(self) -> str:
        return f"{self.source.path}:{self.line}:{self.col}"
