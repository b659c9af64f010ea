"""Rendering diagnostics: rustc-style text (plain or coloured through rich) and JSON.

Every renderer reads the same `Diagnostic` objects. The text layout is computed once, as
lines of pieces that each carry a `Role` (error mark, gutter, label, ...); `render_plain`
joins the pieces into plain text and `to_rich_text` maps the roles to rich styles, so the
coloured and the plain output can never disagree. rich is imported only when colour is
wanted, which keeps `gpp check` quick to start when its output goes to a file or a pipe.

The text layout follows rustc:

    error[E0011]: expected `;` after this statement
     --> agent.gpp:2:12
      |
    2 |     x() = 1
      |            ^ add `;` here
      |
    help: insert `;`
      |
    2 |     x() = 1;
      |            +
"""

from __future__ import annotations

import json
import re
import unicodedata
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, TypedDict

from gpp.base.diagnostics import Diagnostic, Edit, Fix, Label, Severity
from gpp.base.source import Source, Span

if TYPE_CHECKING:
    from rich.console import Console
    from rich.text import Text

JSON_FORMAT_VERSION = 1
TAB_WIDTH = 4  # every tab is shown as this many spaces, in source lines and under them alike
_MAX_GAP = 1  # unannotated lines between two annotated ones that are shown rather than elided
# A source line longer than this (in characters) is shown shortened: only the characters within
# _CONTEXT of each end of a label, the rest elided as `…` (the location line keeps the real
# column). Rendering a diagnostic thus costs the same on a line of 100 characters or of 1 MB.
LONG_LINE = 160
_CONTEXT = 40
_MIN_ELISION = 8  # a gap shorter than this between two shown parts is shown rather than elided
ELLIPSIS = "…"


class Role(Enum):
    """What a piece of rendered text is; the colour theme maps roles to styles."""

    PLAIN = "plain"
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"
    HELP = "help"
    MESSAGE = "message"
    GUTTER = "gutter"
    SECONDARY = "secondary"
    ADDED = "added"
    REMOVED = "removed"


# Close to rustc's colours: severities in bold colour, the gutter and secondary labels in blue.
THEME: dict[Role, str] = {
    Role.PLAIN: "",
    Role.ERROR: "bold red",
    Role.WARNING: "bold yellow",
    Role.NOTE: "bold green",
    Role.HELP: "bold cyan",
    Role.MESSAGE: "bold",
    Role.GUTTER: "bold blue",
    Role.SECONDARY: "bold blue",
    Role.ADDED: "green",
    Role.REMOVED: "red",
}

_SEVERITY_ROLE = {Severity.ERROR: Role.ERROR, Severity.WARNING: Role.WARNING, Severity.NOTE: Role.NOTE}

Piece = tuple[str, Role]
Line = list[Piece]


# ---------------------------------------------------------------- public text API


def layout_diagnostic(diagnostic: Diagnostic) -> list[Line]:
    """The rendered lines of one diagnostic, each a list of (text, role) pieces."""
    return _DiagnosticLayout(diagnostic).lines()


def render_plain(diagnostic: Diagnostic) -> str:
    """One diagnostic as plain text (no colour), ending with a newline."""
    return _lines_to_str(layout_diagnostic(diagnostic))


def count_problems(diagnostics: Iterable[Diagnostic]) -> tuple[int, int]:
    """The number of errors and of warnings."""
    errors = warnings = 0
    for d in diagnostics:
        if d.severity is Severity.ERROR:
            errors += 1
        elif d.severity is Severity.WARNING:
            warnings += 1
    return errors, warnings


def summary_line(diagnostics: Sequence[Diagnostic]) -> Line:
    """`error: 2 errors, 1 warning`, `warning: 1 warning` or `no problems found`."""
    errors, warnings = count_problems(diagnostics)
    if not errors and not warnings:
        return [("no problems found", Role.PLAIN)]
    counts = []
    if errors:
        counts.append(_plural(errors, "error"))
    if warnings:
        counts.append(_plural(warnings, "warning"))
    severity = Severity.ERROR if errors else Severity.WARNING
    return [(severity.value, _SEVERITY_ROLE[severity]), (": " + ", ".join(counts), Role.MESSAGE)]


def render_text(diagnostics: Sequence[Diagnostic], *, summary: bool = True, max_per_code: int = 0) -> str:
    """All diagnostics as plain text, a blank line after each, then the summary line. With
    `max_per_code`, at most that many of one code in one file (see `limit_diagnostics`)."""
    return _lines_to_str(_report_lines(diagnostics, summary, max_per_code))


def to_rich_text(lines: Iterable[Line]) -> Text:
    """Laid-out lines as a rich Text with the theme's styles."""
    from rich.text import Text

    text = Text()
    for line in lines:
        for piece, role in line:
            text.append(piece, style=THEME[role])
        text.append("\n")
    return text


def print_diagnostics(
    console: Console, diagnostics: Sequence[Diagnostic], *, summary: bool = True, max_per_code: int = 0
) -> None:
    """Write diagnostics (and the summary line) to a rich Console, coloured if it is."""
    lines = _report_lines(diagnostics, summary, max_per_code)
    # soft_wrap: never fold a long source line, which would break the alignment of the carets.
    console.print(to_rich_text(lines), end="", soft_wrap=True, highlight=False)


# ---------------------------------------------------------------- many diagnostics

DEFAULT_MAX_DIAGNOSTICS = 50  # of one code in one file, in the text output of the commands


@dataclass(frozen=True, slots=True)
class Omitted:
    """Diagnostics of one code in one file left out of a report, counted."""

    path: str
    code: str
    severity: Severity
    count: int


def limit_diagnostics(diagnostics: Sequence[Diagnostic], max_per_code: int) -> tuple[list[Diagnostic], list[Omitted]]:
    """The first `max_per_code` diagnostics of each code in each file (of the primary span), in
    their order, and the counts of the rest, by file and code. `max_per_code` 0 keeps all."""
    if max_per_code <= 0:
        return list(diagnostics), []
    seen: dict[tuple[str, str], int] = {}
    kept: list[Diagnostic] = []
    omitted: dict[tuple[str, str], Omitted] = {}
    for d in diagnostics:
        key = (d.span.source.path, d.code)
        n = seen[key] = seen.get(key, 0) + 1
        if n <= max_per_code:
            kept.append(d)
        else:
            before = omitted.get(key)
            omitted[key] = Omitted(key[0], d.code, d.severity, 1 if before is None else before.count + 1)
    return kept, list(omitted.values())


def omitted_line(omitted: Omitted, max_per_code: int) -> Line:
    """`note: 950 more E0010 errors in x.gpp not shown (the first 50 of a code in a file are)`."""
    code = f"{omitted.code} " if omitted.code else ""
    what = _plural(omitted.count, omitted.severity.value).replace(" ", f" more {code}", 1)
    text = f" {what} in {omitted.path} not shown (the first {max_per_code} of a code in a file are)"
    return [("note", Role.NOTE), (":" + text, Role.MESSAGE)]


def _report_lines(diagnostics: Sequence[Diagnostic], summary: bool, max_per_code: int = 0) -> list[Line]:
    lines: list[Line] = []
    shown, omitted = limit_diagnostics(diagnostics, max_per_code)
    for d in shown:
        lines.extend(layout_diagnostic(d))
        lines.append([])
    for o in omitted:
        lines.append(omitted_line(o, max_per_code))
    if omitted:
        lines.append([])
    if summary:
        lines.append(summary_line(diagnostics))
    return lines


def _lines_to_str(lines: Iterable[Line]) -> str:
    return "".join("".join(piece for piece, _ in line) + "\n" for line in lines)


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


# ---------------------------------------------------------------- source lines as displayed


@dataclass(frozen=True, slots=True)
class _DisplayLine:
    """A source line as shown: tabs expanded, control characters made visible, and the
    display column (0-based) of every character index, plus one past the end."""

    text: str
    columns: list[int]

    @classmethod
    def of(cls, raw: str) -> _DisplayLine:
        if raw.isascii() and raw.isprintable():  # the common case: one column per character
            return cls(raw, list(range(len(raw) + 1)))
        parts: list[str] = []
        columns: list[int] = []
        col = 0
        for ch in raw:
            columns.append(col)
            if ch == "\t":
                shown, width = " " * TAB_WIDTH, TAB_WIDTH
            elif unicodedata.category(ch) == "Cc":
                # Never echo raw control characters (an escape sequence would restyle the terminal).
                shown, width = "\ufffd", 1
            else:
                shown, width = ch, _char_width(ch)
            parts.append(shown)
            col += width
        columns.append(col)
        return cls("".join(parts), columns)

    def column(self, index: int) -> int:
        """Display column of a character index; indices past the end continue one per char."""
        if index < len(self.columns):
            return self.columns[index]
        return self.columns[-1] + index - (len(self.columns) - 1)

    def width(self) -> int:
        return self.columns[-1]


def _char_width(ch: str) -> int:
    if unicodedata.combining(ch) or unicodedata.category(ch) in ("Mn", "Me", "Cf"):
        return 0
    return 2 if unicodedata.east_asian_width(ch) in ("W", "F") else 1


def _line_bounds(source: Source, line: int) -> tuple[int, int]:
    """Offsets of the first character of a 1-based line and one past its last (no line break)."""
    starts = source.line_starts
    start = starts[line - 1]
    end = starts[line] - 1 if line < len(starts) else len(source.text)
    while end > start and source.text[end - 1] == "\r":
        end -= 1
    return start, end


@dataclass(frozen=True, slots=True)
class _LineView:
    """A source line as a snippet shows it: whole, or, when longer than LONG_LINE, only the
    parts around some character positions, joined by `…`. Maps character indices of the line
    to display columns of the shown text."""

    text: str
    # Each shown part: its first character index, one past its last, the display column where
    # it starts, and its display.
    parts: list[tuple[int, int, int, _DisplayLine]]

    @classmethod
    def of(cls, source: Source, line: int, keep: Iterable[int] = ()) -> _LineView:
        """The view of `line` that shows the characters near the indices `keep` (the start of
        the line when there are none)."""
        start, end = _line_bounds(source, line)
        length = end - start
        if length <= LONG_LINE:
            whole = _DisplayLine.of(source.text[start:end])
            return cls(whole.text, [(0, length, 0, whole)])
        wanted = sorted((max(0, k - _CONTEXT), min(length, k + _CONTEXT)) for k in keep) or [(0, 2 * _CONTEXT)]
        merged: list[tuple[int, int]] = []
        for a, b in wanted:
            if merged and a <= merged[-1][1] + _MIN_ELISION:
                merged[-1] = (merged[-1][0], max(merged[-1][1], b))
            else:
                merged.append((a, b))
        texts: list[str] = []
        parts: list[tuple[int, int, int, _DisplayLine]] = []
        column = shown_to = 0
        for a, b in merged:
            if a > shown_to:
                texts.append(ELLIPSIS)
                column += 1
            shown = _DisplayLine.of(source.text[start + a : start + b])
            parts.append((a, b, column, shown))
            texts.append(shown.text)
            column += shown.width()
            shown_to = b
        if shown_to < length:
            texts.append(ELLIPSIS)
        return cls("".join(texts), parts)

    def column(self, index: int) -> int:
        """Display column of a character index (0-based) that is shown, or one past a shown part."""
        for a, b, column, shown in self.parts:
            if index < a:
                return column
            if index <= b:
                return column + shown.column(index - a)
        a, _, column, shown = self.parts[-1]
        return column + shown.column(index - a)


# ---------------------------------------------------------------- annotated snippets


@dataclass(frozen=True, slots=True)
class _Mark:
    """A label placed on the source: display columns of its first and last line."""

    primary: bool
    message: str
    start_line: int
    start_col: int  # display column where the span starts
    end_line: int  # line of the span's last character
    end_col: int  # display column one past the span's last character (at least start_col + 1)
    at_indent: bool  # only blanks precede the start on its line

    @property
    def multiline(self) -> bool:
        return self.start_line != self.end_line

    @property
    def char(self) -> str:
        return "^" if self.primary else "-"


def _clamp(span: Span) -> tuple[int, int]:
    n = len(span.source.text)
    start = max(0, min(span.start, n))
    return start, max(start, min(span.end, n))


@dataclass(frozen=True, slots=True)
class _Anchor:
    """Where a span is drawn, in characters: the line and 0-based index of its first character
    and of its last visible one (a zero-width span: the same, flagged)."""

    start_line: int
    start_char: int
    end_line: int
    last_char: int
    zero_width: bool
    at_indent: bool  # only blanks precede the start on its line

    def positions(self) -> list[tuple[int, int]]:
        """(line, character index) that must be visible to draw it."""
        return [(self.start_line, self.start_char), (self.end_line, self.last_char + 1)]


_BLANKS = re.compile(r"\s*")


def _anchor(span: Span) -> _Anchor:
    source = span.source
    start, end = _clamp(span)
    start_line, start_char = source.line_col(start)
    line_start = start - start_char + 1
    blanks = _BLANKS.match(source.text, line_start, start)
    at_indent = blanks is not None and blanks.end() == start
    if end == start:  # zero width: one caret at its column
        return _Anchor(start_line, start_char - 1, start_line, start_char - 1, True, at_indent)
    # A span that ends with line breaks is drawn up to its last visible character.
    while end - 1 > start and source.text[end - 1] in "\r\n":
        end -= 1
    end_line, last_char = source.line_col(end - 1)
    return _Anchor(start_line, start_char - 1, end_line, last_char - 1, False, at_indent)


def _mark(anchor: _Anchor, message: str, primary: bool, views: dict[int, _LineView]) -> _Mark:
    a = anchor
    message = message.replace("\n", " ")
    start_col = views[a.start_line].column(a.start_char)
    if a.zero_width:
        return _Mark(primary, message, a.start_line, start_col, a.start_line, start_col + 1, a.at_indent)
    last = views[a.end_line]
    last_col = last.column(a.last_char)
    end_col = max(last.column(a.last_char + 1), last_col + 1)
    if a.end_line == a.start_line:
        end_col = max(end_col, start_col + 1)
    return _Mark(primary, message, a.start_line, start_col, a.end_line, end_col, a.at_indent)


class _Canvas:
    """One output row drawn cell by cell, each cell with a role."""

    def __init__(self) -> None:
        self.cells: list[tuple[str, Role]] = []

    def put(self, col: int, text: str, role: Role) -> None:
        while len(self.cells) < col + len(text):
            self.cells.append((" ", Role.PLAIN))
        for i, ch in enumerate(text):
            self.cells[col + i] = (ch, role)

    def pieces(self) -> Line:
        end = len(self.cells)
        while end and self.cells[end - 1][0] == " ":
            end -= 1
        out: Line = []
        for ch, role in self.cells[:end]:
            if out and out[-1][1] is role:
                out[-1] = (out[-1][0] + ch, role)
            else:
                out.append((ch, role))
        return out


class _Snippet:
    """The annotated source lines of one file, laid out for a given gutter width."""

    def __init__(self, source: Source, labels: list[tuple[Span, str, bool]], primary_role: Role) -> None:
        self.source = source
        anchors = [(_anchor(span), message, primary) for span, message, primary in labels]
        keep: dict[int, list[int]] = {}
        for anchor, _, _ in anchors:
            for line, index in anchor.positions():
                keep.setdefault(line, []).append(index)
        self.views = {line: _LineView.of(source, line, indices) for line, indices in keep.items()}
        self.marks = [_mark(anchor, message, primary, self.views) for anchor, message, primary in anchors]
        self.primary_role = primary_role
        # Multi-line marks each get a column in a margin between the gutter and the text.
        self.multiline = sorted((m for m in self.marks if m.multiline), key=lambda m: (m.start_line, m.start_col))
        self.margin = len(self.multiline) + 1 if self.multiline else 0

    def annotated_lines(self) -> list[int]:
        lines = {m.start_line for m in self.marks} | {m.end_line for m in self.marks}
        return sorted(lines)

    def max_line(self) -> int:
        return max(self.annotated_lines())

    def role_of(self, mark: _Mark) -> Role:
        return self.primary_role if mark.primary else Role.SECONDARY

    def rows(self, width: int) -> list[Line]:
        out: list[Line] = []
        shown = self.annotated_lines()
        previous: int | None = None
        for line in shown:
            if previous is not None and line - previous > 1:
                if line - previous - 1 <= _MAX_GAP:
                    for gap_line in range(previous + 1, line):
                        out.append(self.source_row(gap_line, width))
                else:
                    out.append(self.elision_row(previous, width))
            out.append(self.source_row(line, width))
            out.extend(self.annotation_rows(line, width))
            previous = line
        return out

    # A multi-line mark is "open" on the rows between its start row and its end row. One that
    # starts at the first non-blank of its line is drawn with `/` on that line instead of `_`s.
    def open_on_source_row(self, mark: _Mark, line: int) -> bool:
        if mark.start_line == line:
            return mark.at_indent
        return mark.start_line < line <= mark.end_line

    def open_below(self, mark: _Mark, line: int) -> bool:
        return mark.start_line <= line < mark.end_line

    def margin_row(self, width: int, is_open: Iterable[bool], gutter: str = "") -> _Canvas:
        canvas = _Canvas()
        canvas.put(0, gutter.rjust(width) + " |", Role.GUTTER)
        for i, open_ in enumerate(is_open):
            if open_:
                canvas.put(width + 3 + i, "|", self.role_of(self.multiline[i]))
        return canvas

    def source_row(self, line: int, width: int) -> Line:
        canvas = self.margin_row(width, (self.open_on_source_row(m, line) for m in self.multiline), str(line))
        for i, m in enumerate(self.multiline):
            if m.start_line == line and m.at_indent:
                canvas.put(width + 3 + i, "/", self.role_of(m))
        row = canvas.pieces()
        view = self.views.get(line) or _LineView.of(self.source, line)
        text = view.text
        if text:
            gap = width + 3 + self.margin - sum(len(p) for p, _ in row)
            row.append((" " * gap + text, Role.PLAIN))
        return row

    def elision_row(self, line: int, width: int) -> Line:
        canvas = _Canvas()
        canvas.put(0, "...", Role.GUTTER)
        for i, m in enumerate(self.multiline):
            if self.open_below(m, line):
                canvas.put(width + 3 + i, "|", self.role_of(m))
        return canvas.pieces()

    def annotation_rows(self, line: int, width: int) -> list[Line]:
        rows: list[Line] = []
        base = width + 3 + self.margin

        def blank() -> _Canvas:
            return self.margin_row(width, (self.open_below(m, line) for m in self.multiline))

        singles = sorted(
            (m for m in self.marks if not m.multiline and m.start_line == line),
            key=lambda m: (m.start_col, m.end_col),
        )
        if singles:
            canvas = blank()
            # Longer marks first, so a span nested in another stays visible; the primary wins ties.
            for m in sorted(singles, key=lambda m: (m.start_col - m.end_col, m.primary)):
                canvas.put(base + m.start_col, m.char * (m.end_col - m.start_col), self.role_of(m))
            # The rightmost label is written after the marks, unless another span overlaps it;
            # the others hang below, each from the start of its mark.
            last = singles[-1]
            inline = last if all(m.end_col <= last.start_col for m in singles[:-1]) else None
            if inline and inline.message:
                canvas.put(base + inline.end_col + 1, inline.message, self.role_of(inline))
            rows.append(canvas.pieces())
            hanging = [m for m in singles if m.message and m is not inline]
            if hanging:
                canvas = blank()
                for m in hanging:
                    canvas.put(base + m.start_col, "|", self.role_of(m))
                rows.append(canvas.pieces())
                for k in range(len(hanging) - 1, -1, -1):
                    canvas = blank()
                    for m in hanging[:k]:
                        canvas.put(base + m.start_col, "|", self.role_of(m))
                    canvas.put(base + hanging[k].start_col, hanging[k].message, self.role_of(hanging[k]))
                    rows.append(canvas.pieces())
        for i, m in enumerate(self.multiline):
            if m.start_line == line and not m.at_indent:
                canvas = self.margin_row(width, (self.open_below(o, line) and o is not m for o in self.multiline))
                role = self.role_of(m)
                canvas.put(width + 4 + i, "_" * (self.margin - i - 1 + m.start_col), role)
                canvas.put(base + m.start_col, m.char, role)
                rows.append(canvas.pieces())
        for i, m in enumerate(self.multiline):
            if m.end_line == line:
                canvas = blank()
                role = self.role_of(m)
                canvas.put(width + 3 + i, "|", role)
                canvas.put(width + 4 + i, "_" * (self.margin - i - 1 + m.end_col - 1), role)
                canvas.put(base + m.end_col - 1, m.char, role)
                if m.message:
                    canvas.put(base + m.end_col + 1, m.message, role)
                rows.append(canvas.pieces())
        return rows


# ---------------------------------------------------------------- suggested fixes


@dataclass(frozen=True, slots=True)
class _FixPreview:
    """A fix whose edits all fall on one source line, shown as that line after the edits."""

    source: Source
    line: int
    old: str
    new: str
    inserted: list[tuple[int, int]]  # character ranges in `new` of inserted text
    insertions_only: bool

    @classmethod
    def of(cls, fix: Fix) -> _FixPreview | None:
        if not fix.edits:
            return None
        source = fix.edits[0].span.source
        line = fix.edits[0].span.line
        edits: list[Edit] = sorted(fix.edits, key=lambda e: (e.span.start, e.span.end))
        for e in edits:
            if e.span.source is not source or "\n" in e.text or "\r" in e.text:
                return None
            start, end = _clamp(e.span)
            if start != e.span.start or end != e.span.end or source.line_col(start)[0] != line:
                return None
            if "\n" in source.text[start:end]:
                return None
        window = _preview_window(source, line, edits[0].span.start, edits[-1].span.end)
        if window is None:
            return None
        old, base = window
        new_parts: list[str] = []
        inserted: list[tuple[int, int]] = []
        cursor = 0
        length = 0
        for e in edits:
            a, b = e.span.start - base, e.span.end - base
            if a < cursor or b > len(old):
                return None  # overlapping edits, or an edit of the line break itself
            new_parts.append(old[cursor:a])
            length += a - cursor
            inserted.append((length, length + len(e.text)))
            new_parts.append(e.text)
            length += len(e.text)
            cursor = b
        new_parts.append(old[cursor:])
        insertions_only = all(e.span.start == e.span.end and e.text for e in edits)
        return cls(source, line, old, "".join(new_parts), inserted, insertions_only)

    def rows(self, width: int) -> list[Line]:
        number = str(self.line).rjust(width)
        new = _DisplayLine.of(self.new)
        if self.insertions_only:
            canvas = _Canvas()
            canvas.put(0, " " * width + " |", Role.GUTTER)
            for a, b in self.inserted:
                start = new.column(a)
                canvas.put(width + 3 + start, "+" * max(1, new.column(b) - start), Role.ADDED)
            return [_gutter_text(number, "|", new.text, Role.PLAIN), canvas.pieces()]
        old = _DisplayLine.of(self.old)
        return [_gutter_text(number, "-", old.text, Role.REMOVED), _gutter_text(number, "+", new.text, Role.ADDED)]


def _preview_window(source: Source, line: int, first: int, last: int) -> tuple[str, int] | None:
    """The part of `line` a fix preview shows for edits between offsets `first` and `last`,
    and the offset that its index 0 stands for: the whole line, or for a long one the edited
    stretch with _CONTEXT characters either side and `…` for the rest (None when the edited
    stretch itself is too long to show)."""
    start, end = _line_bounds(source, line)
    if end - start <= LONG_LINE:
        return source.text[start:end], start
    if last - first > LONG_LINE or last > end:
        return None
    lo, hi = max(start, first - _CONTEXT), min(end, last + _CONTEXT)
    before = ELLIPSIS if lo > start else ""
    after = ELLIPSIS if hi < end else ""
    return before + source.text[lo:hi] + after, lo - len(before)


def _gutter_text(number: str, bar: str, text: str, role: Role) -> Line:
    line: Line = [(number + " " + bar, Role.GUTTER)] if bar == "|" else [(number + " ", Role.GUTTER), (bar, role)]
    if text:
        line.append((" " + text, role))
    return line


# ---------------------------------------------------------------- one whole diagnostic


class _DiagnosticLayout:
    def __init__(self, diagnostic: Diagnostic) -> None:
        self.d = diagnostic
        self.role = _SEVERITY_ROLE[diagnostic.severity]
        primary = diagnostic.span.source
        groups: dict[int, tuple[Source, list[tuple[Span, str, bool]]]] = {id(primary): (primary, [])}
        for span, message, is_primary in [
            (diagnostic.span, diagnostic.label, True),
            *((label.span, label.message, False) for label in diagnostic.secondary),
        ]:
            source = span.source
            groups.setdefault(id(source), (source, []))[1].append((span, message, is_primary))
        self.snippets = [_Snippet(source, marks, self.role) for source, marks in groups.values()]
        fix = diagnostic.fix
        # A fix that is the help line (a did-you-mean) is not shown a second time as a preview.
        self.preview = _FixPreview.of(fix) if fix and fix.message != diagnostic.help else None
        numbers = [s.max_line() for s in self.snippets]
        if self.preview:
            numbers.append(self.preview.line)
        self.width = len(str(max(numbers)))

    def lines(self) -> list[Line]:
        d, w = self.d, self.width
        pad = " " * w
        header: Line = [(d.severity.value + (f"[{d.code}]" if d.code else ""), self.role)]
        message_lines = d.message.split("\n")
        header.append((": " + message_lines[0], Role.MESSAGE))
        out: list[Line] = [
            header,
            *[[(" " * (len(d.severity.value) + 2) + m, Role.MESSAGE)] for m in message_lines[1:]],
        ]
        for k, snippet in enumerate(self.snippets):
            span = _first_span(d, snippet.source)
            if k == 0:
                out.append([(pad + "--> ", Role.GUTTER), (_location(span), Role.PLAIN)])
            else:
                out.append([(pad + " |", Role.GUTTER)])
                out.append([(pad + "::: ", Role.GUTTER), (_location(span), Role.PLAIN)])
            out.append([(pad + " |", Role.GUTTER)])
            out.extend(snippet.rows(w))
        helps = [d.help] if d.help else []
        fix = d.fix
        if fix and not self.preview and fix.message and fix.message not in helps:
            helps.append(fix.message)
        if d.notes or helps:
            out.append([(pad + " |", Role.GUTTER)])
        for kind, texts in (("note", d.notes), ("help", helps)):
            for text in texts:
                first, *rest = text.split("\n")
                out.append([(pad + " = ", Role.GUTTER), (kind + ":", Role.MESSAGE), (" " + first, Role.PLAIN)])
                indent = " " * (w + 5 + len(kind))
                out.extend([[(indent + r, Role.PLAIN)] for r in rest])
        if fix and self.preview:
            if not (d.notes or helps):
                out.append([(pad + " |", Role.GUTTER)])
            out.append([("help", Role.HELP), (": " + (fix.message or "try this"), Role.MESSAGE)])
            if self.preview.source is not d.span.source:
                out.append([(pad + "::: ", Role.GUTTER), (_location(fix.edits[0].span), Role.PLAIN)])
            out.append([(pad + " |", Role.GUTTER)])
            out.extend(self.preview.rows(w))
        return out


def _first_span(diagnostic: Diagnostic, source: Source) -> Span:
    """The span a file group's location line points at: the primary one, or the first label."""
    if diagnostic.span.source is source:
        return diagnostic.span
    return min((label.span for label in diagnostic.secondary if label.span.source is source), key=lambda s: s.start)


def _location(span: Span) -> str:
    start, _ = _clamp(span)
    line, col = span.source.line_col(start)
    return f"{span.source.path}:{line}:{col}"


# ---------------------------------------------------------------- JSON


class JsonRange(TypedDict):
    file: str
    line: int
    column: int
    end_line: int
    end_column: int


class JsonLabel(JsonRange):
    message: str


class JsonEdit(JsonRange):
    text: str


class JsonFix(TypedDict):
    message: str
    applicability: str  # "safe" (`gpp check --fix` applies it) or "unsafe"
    edits: list[JsonEdit]


class JsonDiagnostic(JsonRange):
    code: str
    severity: str
    message: str
    offset: int
    end_offset: int
    label: str
    secondary: list[JsonLabel]
    notes: list[str]
    help: str | None
    fix: JsonFix | None


class JsonSummary(TypedDict):
    errors: int
    warnings: int


class JsonReport(TypedDict):
    version: int
    diagnostics: list[JsonDiagnostic]
    summary: JsonSummary


def _json_range(span: Span) -> JsonRange:
    """1-based line and column of the start, and of the (exclusive) end, in characters."""
    start, end = _clamp(span)
    line, column = span.source.line_col(start)
    end_line, end_column = span.source.line_col(end)
    return {"file": span.source.path, "line": line, "column": column, "end_line": end_line, "end_column": end_column}


def diagnostic_to_json(d: Diagnostic) -> JsonDiagnostic:
    start, end = _clamp(d.span)
    fix: JsonFix | None = None
    if d.fix is not None:
        fix = {
            "message": d.fix.message,
            "applicability": d.fix.applicability.value,
            "edits": [{**_json_range(e.span), "text": e.text} for e in d.fix.edits],
        }
    return {
        "code": d.code,
        "severity": d.severity.value,
        "message": d.message,
        **_json_range(d.span),
        "offset": start,
        "end_offset": end,
        "label": d.label,
        "secondary": [_label_to_json(label) for label in d.secondary],
        "notes": list(d.notes),
        "help": d.help,
        "fix": fix,
    }


def _label_to_json(label: Label) -> JsonLabel:
    return {**_json_range(label.span), "message": label.message}


def report_to_json(diagnostics: Sequence[Diagnostic]) -> JsonReport:
    errors, warnings = count_problems(diagnostics)
    return {
        "version": JSON_FORMAT_VERSION,
        "diagnostics": [diagnostic_to_json(d) for d in diagnostics],
        "summary": {"errors": errors, "warnings": warnings},
    }


def render_json(diagnostics: Sequence[Diagnostic]) -> str:
    """The JSON report of `gpp check --format json`, ending with a newline."""
    return json.dumps(report_to_json(diagnostics), indent=2, ensure_ascii=False) + "\n"
