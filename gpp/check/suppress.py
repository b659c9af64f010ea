"""Suppressing lints in the source: `// gpp: allow CODES` comments.

* At the end of a line of code, it allows the lints on that line (those whose primary span
  starts there).
* On a line of its own directly above a top-level declaration, it allows them in the whole
  declaration; above any other line of code, on that next line.
* `// gpp: allow-file CODES` allows them in the whole file, wherever it is written.

CODES are lint codes or names, separated by commas (`// gpp: allow W0101, busy-wait`); text
after the last one is a free comment (`// gpp: allow unused -- kept for the ROS mapping`).
Only lints can be allowed: naming an error, or a code that does not exist, is lint W0117. A
suppression that allows nothing is lint W0116, with a fix that removes it. Both are reported only
where the lints ran (the files checked, without syntax errors) and not for lints that are
turned off anyway (`--allow`, the configuration).
"""

from __future__ import annotations

import re
from collections.abc import Collection, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gpp import codes
from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.syntax.directives import SUPPRESSION
from gpp.syntax.loader import ParsedFile

_COMMENTS = re.compile(r"/\*.*?\*/|//[^\n]*", re.DOTALL)
_ENTRY = re.compile(r"[ \t]*([A-Za-z][A-Za-z0-9_-]*)")
_SEPARATOR = re.compile(r"[ \t]*,")

UNUSED = codes.W0116.code
INVALID = codes.W0117.code
SUPPRESSION_LINTS = (UNUSED, INVALID)


@dataclass
class _Entry:
    text: str
    span: Span
    code: str | None  # the lint's code; None when the text names no lint
    used: bool = False


@dataclass
class _Suppression:
    source: Source
    comment: Span  # `// gpp: allow ...` to the end of the line
    removal: Span  # what removing the whole comment removes (its line, when it is alone there)
    kind: str  # "line", "next-line", "declaration", "file"
    start: int  # the offsets of the primary spans it covers: [start, end)
    end: int
    entries: list[_Entry] = field(default_factory=list)

    def covers(self, d: diag.Diagnostic) -> bool:
        return d.span.source is self.source and self.start <= d.span.start < self.end


def apply_suppressions(
    files: Sequence[ParsedFile],
    found: list[diag.Diagnostic],
    roots: Collection[Path],
    report: bool,
    allow: Collection[str] = (),
) -> list[diag.Diagnostic]:
    """`found` without the lints that comments allow, plus (when `report`) W0116 for each
    suppression that allowed nothing and W0117 for each that names no lint, in root files."""
    suppressions = [s for f in files if "gpp:" in f.source.text for s in _suppressions(f)]
    if not suppressions:
        return found
    kept: list[diag.Diagnostic] = []
    for d in found:
        allowed = False
        if codes.CODES.get(d.code) is not None and codes.CODES[d.code].is_lint:
            for s in suppressions:
                if s.covers(d):
                    for e in s.entries:
                        if e.code == d.code:
                            e.used = allowed = True
        if not allowed:
            kept.append(d)
    if report:
        root_sources = {id(f.source) for f in files if f.path in roots}
        allowed_codes = {info.code for info in map(codes.lookup, allow) if info is not None}
        for s in suppressions:
            if id(s.source) in root_sources:
                kept.extend(_problems(s, allowed_codes))
    return kept


def _problems(s: _Suppression, allowed: set[str]) -> Iterator[diag.Diagnostic]:
    if not s.entries and INVALID not in allowed:
        remove = diag.Fix("remove the suppression", (diag.Edit(s.removal, ""),), diag.Applicability.SAFE)
        yield diag.warning(
            codes.W0117.names_nothing(),
            s.comment,
            "allows nothing",
            help="name lints: `// gpp: allow unused`",
            fix=remove,
        )
    for i, e in enumerate(s.entries):
        what = "the suppression" if len(s.entries) == 1 else f"`{e.text}` from the suppression"
        remove = diag.Fix(f"remove {what}", (_removal(s, i),), diag.Applicability.SAFE)
        if e.code is None:
            info = codes.lookup(e.text)
            if INVALID in allowed:
                continue
            if info is not None:
                yield diag.warning(
                    codes.W0117.not_a_lint(e.text, error=info.code.startswith("E")),
                    e.span,
                    "cannot be suppressed",
                    help="fix the problem instead; errors cannot be suppressed",
                    fix=remove,
                )
            else:
                close = codes.close_matches(e.text, lints=True)
                fix = None
                if close:
                    safe = diag.Applicability.SAFE if len(close) == 1 else diag.Applicability.UNSAFE
                    fix = diag.Fix(f"replace with `{close[0]}`", (diag.Edit(e.span, close[0]),), safe)
                yield diag.warning(
                    codes.W0117.unknown(e.text),
                    e.span,
                    "not a lint code or name",
                    help=f"did you mean `{close[0]}`?" if close else "`gpp check --list-lints` lists the lints",
                    fix=fix,
                )
        elif not e.used and e.code not in allowed and UNUSED not in allowed:
            name = codes.CODES[e.code].name
            yield diag.warning(
                codes.W0116.unused(name, e.code, _where(s.kind)),
                e.span,
                "allows nothing",
                fix=remove,
            )


def _where(kind: str) -> str:
    return {
        "line": "on this line",
        "next-line": "on the next line",
        "declaration": "in this declaration",
        "file": "in this file",
    }[kind]


def _removal(s: _Suppression, i: int) -> diag.Edit:
    """The edit removing entry `i` (with its comma), or the whole comment when it is the only one."""
    entries = s.entries
    if len(entries) == 1:
        return diag.Edit(s.removal, "")
    if i + 1 < len(entries):
        return diag.Edit(Span(s.source, entries[i].span.start, entries[i + 1].span.start), "")
    return diag.Edit(Span(s.source, entries[i - 1].span.end, entries[i].span.end), "")


def _suppressions(f: ParsedFile) -> Iterator[_Suppression]:
    source, text = f.source, f.source.text
    starts = {d.span.start: d for d in f.program.declarations}
    previous_end = 0
    for token in [*f.tokens, None]:
        gap_end = token.start if token is not None else len(text)
        if gap_end > previous_end and "gpp:" in text[previous_end:gap_end]:
            for m in _COMMENTS.finditer(text, previous_end, gap_end):
                s = _parse(source, m.start(), m.end(), previous_end, token.start if token is not None else None)
                if s is not None:
                    if s.kind == "declaration":
                        decl = starts.get(s.start)
                        if decl is None:
                            s.kind, s.end = "next-line", _line_end(text, s.start)
                        else:
                            s.end = decl.span.end
                    yield s
        if token is not None:
            previous_end = max(previous_end, token.end)


def _parse(source: Source, start: int, end: int, code_before: int, next_token: int | None) -> _Suppression | None:
    text = source.text
    m = SUPPRESSION.match(text, start, end)
    if m is None:
        return None
    line_start = text.rfind("\n", 0, start) + 1
    alone = text[line_start:start].strip() == "" and code_before <= line_start
    after = end + 1 if end < len(text) and text[end] == "\n" else end
    removal = Span(source, line_start, after) if alone else Span(source, _blank_before(text, start), end)
    if m.group(1) == "allow-file":
        kind, first, last = "file", 0, len(text) + 1
    elif not alone:
        kind, first, last = "line", line_start, _line_end(text, start)
    elif next_token is not None:
        kind, first, last = "declaration", next_token, next_token  # `end` is set by the caller
    else:
        return None  # a comment at the end of the file, above nothing: no suppression
    s = _Suppression(source, Span(source, start, end), removal, kind, first, last)
    for span in _entry_spans(source, m.end(), end):
        name = text[span.start : span.end]
        info = codes.lookup(name)
        s.entries.append(_Entry(name, span, info.code if info is not None and info.is_lint else None))
    return s


def _entry_spans(source: Source, at: int, end: int) -> Iterator[Span]:
    """The spans of the comma-separated codes or names of a suppression, from `at` (after
    `gpp: allow`) to the comment's `end`."""
    text = source.text
    while True:
        entry = _ENTRY.match(text, at, end)
        if entry is None:
            return
        yield Span(source, entry.start(1), entry.end(1))
        at = entry.end()
        comma = _SEPARATOR.match(text, at, end)
        if comma is None:
            return
        at = comma.end()


def suppressed_code_at(source: Source, offset: int) -> tuple[Span, str] | None:
    """The code or name written at `offset` in a `// gpp: allow` comment, with its span (for
    the language server's hover, which explains it), or None."""
    text = source.text
    line_start = text.rfind("\n", 0, offset) + 1
    line_end = _line_end(text, offset)
    m = SUPPRESSION.search(text, line_start, line_end)
    if m is None:
        return None
    for span in _entry_spans(source, m.end(), line_end):
        if span.start <= offset <= span.end:
            return span, text[span.start : span.end]
    return None


def _line_end(text: str, at: int) -> int:
    end = text.find("\n", at)
    return len(text) if end < 0 else end


def _blank_before(text: str, at: int) -> int:
    while at > 0 and text[at - 1] in " \t":
        at -= 1
    return at
