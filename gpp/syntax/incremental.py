"""Re-parsing an edited file: only the top-level declarations the edit touched are parsed again.

`reparse` compares the old and the new text (common prefix and suffix), finds the top-level
declarations of the old parse that the changed region touches, parses only the new text of that
region (a fragment, between two clean declaration boundaries, parsed in place in the new
`Source`) and splices the result between the declarations before and after it, which are
relocated (gpp.syntax.fast.relocate) with the old diagnostics after the edit; the tokens kept
are moved when the new parse's tokens are first read (`gpp.syntax.lexer.Tokens`).

The result is exactly what `parse` of the new text gives. Where that is not certain it parses
more: from the declaration before the edit to the end of the file (a diagnostic in or near the
region, a fragment that leaves a brace, a string or a comment open), or nothing (None: the
caller parses the whole file; legacy forms, the nesting limit, an `#include` in the region, an
old diagnostic before the tail). The rules in full: docs/design.md, "Incremental re-parse".
"""

from __future__ import annotations

import dataclasses
from bisect import bisect_left, bisect_right
from collections.abc import Sequence
from dataclasses import dataclass

from gpp.base import diagnostics as diag
from gpp.base.perf import paused_gc
from gpp.base.source import Source, Span
from gpp.codes import E0014, E0040, E0041, E0042, E0043, E0044, E0045, E0046, E0047, E0048, E0049, E0050, E0051
from gpp.syntax import ast
from gpp.syntax.fast import relocators
from gpp.syntax.lexer import Token, Tokens
from gpp.syntax.parser import ParseResult, parse

# The token that ends a declaration at a clean boundary: nothing at the top level continues a
# declaration after it, and the lexer reads what follows as it reads the start of a file.
_CLEAN_END = frozenset({"SEMI", "RBRACE"})
# Diagnostics whose cause is not local to one declaration: legacy rewrites (one error for all
# the sigils of a file) and the nesting limit (the declaration is left out of the program).
_NOT_LOCAL = frozenset(
    c.code for c in (E0014, E0040, E0041, E0042, E0043, E0044, E0045, E0046, E0047, E0048, E0049, E0050, E0051)
)
_OPENERS = frozenset({"LBRACE", "MAIN_LBRACE"})
_PLATFORM = frozenset({"COMPONENT", "CONSTRAINTS"})


@dataclass(frozen=True, slots=True)
class Reparsed:
    """An incremental parse: the result, how it was made (`splice`: only the touched
    declarations were parsed; `tail`: the file was parsed from the declaration before the edit
    to its end), and how many characters of the new text were parsed."""

    result: ParseResult
    how: str
    parsed_chars: int


def relocate_diagnostic(d: diag.Diagnostic, source: Source, delta: int) -> diag.Diagnostic:
    """`d` with every span (primary, labels, fix edits: `diagnostic_spans`) moved by `delta`
    into `source` (the re-parse's kept diagnostics, and gpp.check.lintmemo's kept warnings)."""

    def span(s: Span) -> Span:
        return Span(source, s.start + delta, s.end + delta)

    fix = d.fix
    if fix is not None:
        fix = dataclasses.replace(fix, edits=tuple(dataclasses.replace(e, span=span(e.span)) for e in fix.edits))
    return dataclasses.replace(
        d,
        span=span(d.span),
        secondary=tuple(dataclasses.replace(label, span=span(label.span)) for label in d.secondary),
        fix=fix,
    )


def diagnostic_spans(d: diag.Diagnostic) -> list[Span]:
    """Every span of `d`: its own, its labels', its fix edits'."""
    spans = [d.span, *(label.span for label in d.secondary)]
    if d.fix is not None:
        spans.extend(e.span for e in d.fix.edits)
    return spans


# ---------------------------------------------------------------- finding the region


def changed_stretch(before: str, after: str) -> tuple[int, int, int]:
    """Where `after` differs from `before`: (start, end in `before`, end in `after`), the
    common beginning and ending left out (the ending does not overlap the beginning). Binary
    searches over slice comparisons, each done in C."""
    start = _common_prefix(before, after)
    common_end = _common_suffix(before, after, min(len(before), len(after)) - start)
    return start, len(before) - common_end, len(after) - common_end


def _common_prefix(a: str, b: str) -> int:
    lo, hi = 0, min(len(a), len(b))
    if a[:hi] == b[:hi]:
        return hi
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if a[lo:mid] == b[lo:mid]:
            lo = mid
        else:
            hi = mid - 1
    return lo


def _common_suffix(a: str, b: str, limit: int) -> int:
    lo, hi = 0, limit
    if a[len(a) - hi :] == b[len(b) - hi :]:
        return hi
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if a[len(a) - mid : len(a) - lo] == b[len(b) - mid : len(b) - lo]:
            lo = mid
        else:
            hi = mid - 1
    return lo


class _Old:
    """What the old parse says about its declaration boundaries (its tokens read without
    making their list, if it is not made)."""

    def __init__(self, result: ParseResult) -> None:
        self.result = result
        self.decls = result.program.declarations
        self.tokens = result.lazy_tokens
        self.starts = [d.span.start for d in self.decls]
        self.ends = [d.span.end for d in self.decls]

    def clean_after(self, k: int) -> bool:
        """Does declaration k end with a token after which a new declaration starts cleanly?"""
        end = self.ends[k]
        t = self.tokens.bisect_start(end) - 1
        if t < 0:
            return False
        token = self.tokens.at(t)
        return token.end == end and token.type in _CLEAN_END

    def adjacent(self, k: int) -> bool:
        """Is the token after declaration k the first one of declaration k + 1?"""
        t = self.tokens.bisect_start(self.ends[k])
        return k + 1 < len(self.decls) and t < len(self.tokens) and self.tokens.at(t).start == self.starts[k + 1]

    def boundary_before(self, i: int) -> int:
        """The greatest i' <= i such that the declarations before i' end cleanly."""
        while i > 0 and not self.clean_after(i - 1):
            i -= 1
        return i


def fragment_text(source: Source, old_source: Source, lo: int, hi: int) -> str:
    """The text parsed for the fragment [lo, hi) of `source`: blank before lo (with the line
    breaks of the text before lo's line, which is the old text there), the fragment, nothing
    after it."""
    starts = old_source.line_starts
    line = bisect_right(starts, lo) - 1
    first = starts[line]
    return " " * (first - line) + "\n" * line + " " * (lo - first) + source.text[lo:hi]


def _parse_fragment(source: Source, old_source: Source, lo: int, hi: int) -> ParseResult:
    text = source.text
    source.text = fragment_text(source, old_source, lo, hi)
    source._line_starts = None  # the line table is made again from the text it now holds
    try:
        return parse(source)
    finally:
        source.text = text
        source._line_starts = None


def _lexes_cleanly(tokens: Sequence[Token]) -> bool:
    """Do the fragment's tokens close every brace they open and every `component`/`constraints`
    body they start, and end with a clean declaration end (or are none)?"""
    if not tokens:
        return True
    if tokens[-1].type not in _CLEAN_END:
        return False
    depth = 0
    pending = False
    for t in tokens:
        tt = t.type
        if tt in _OPENERS:
            depth += 1
            pending = False
        elif tt == "RBRACE":
            depth -= 1
            if depth < 0:
                return False
        elif tt in _PLATFORM:
            pending = True
    return depth == 0 and not pending


def _far_below(source: Source, boundary: int, offset: int) -> bool:
    """Is `offset` at least two lines below the line of `boundary`? A syntax error's message
    looks at the token before the error and at the names on the error's line and the line before
    it (`did you mean ...?`), so an error that far below a boundary reads nothing above it."""
    return offset >= boundary and source.line_col(offset)[0] >= source.line_col(boundary)[0] + 2


def _has_include(decls: Sequence[ast.Decl]) -> bool:
    return any(type(d) is ast.Include for d in decls)


# ---------------------------------------------------------------- the re-parse


def reparse(old_text: str, old: ParseResult, source: Source, *, splice_only: bool = False) -> Reparsed | None:
    """The parse of `source` (the new text of the file whose text was `old_text` and whose parse
    was `old`), made by parsing only what the edit touched; None when that cannot be done
    exactly (the caller then parses the whole file). With `splice_only`, only a splice of at
    most half the new text is tried (the caller has another old parse to try)."""
    # One pause of the collector for the fragment's parse and the splice (the parse's own
    # pause, nested, does not start it again in between).
    with paused_gc():
        return _reparse(old_text, old, source, splice_only)


def _reparse(old_text: str, old: ParseResult, source: Source, splice_only: bool) -> Reparsed | None:
    new_text = source.text
    if any(d.code in _NOT_LOCAL for d in old.diagnostics):
        return None
    a, b_old, _ = changed_stretch(old_text, new_text)
    delta = len(new_text) - len(old_text)
    info = _Old(old)
    old_source = old.program.span.source
    # Where the old parse's first diagnostic (any of its spans) is, if it has one.
    first_diag = min((sp.start for d in old.diagnostics for sp in diagnostic_spans(d)), default=None)
    # Declarations [0, i) end before the edit; [j, n) start after it.
    i = info.boundary_before(bisect_left(info.ends, a))
    j = bisect_right(info.starts, b_old)
    n = len(info.decls)
    while j < n and not (j == 0 or info.clean_after(j - 1)):
        j += 1
    lo = info.ends[i - 1] if i > 0 else 0
    hi_old = info.starts[j] if j < n else len(old_text)
    if splice_only and 2 * (hi_old + delta - lo) > len(new_text):
        return None
    clean = first_diag is None or _far_below(old_source, hi_old, first_diag)
    if clean and not _has_include(info.decls[i:j]):
        frag = _parse_fragment(source, old_source, lo, hi_old + delta)
        if not frag.diagnostics and _lexes_cleanly(frag.tokens) and not _has_include(frag.program.declarations):
            return Reparsed(_splice(source, info, i, j, delta, frag), "splice", hi_old + delta - lo)
    if splice_only:
        return None
    # The tail: from the declaration before the touched ones (so that the parser meets the
    # first changed token after a declaration, as it does in the whole file) to the end. That
    # declaration, and those before it, must have been parsed without a diagnostic, and
    # directly one after the other (no stray token between them); it starts early enough that
    # the errors after it are far below the declarations kept (`_far_below`).
    first_error = a if first_diag is None else min(a, first_diag)
    c = i - 1
    while c > 0 and not (
        info.clean_after(c - 1) and info.adjacent(c - 1) and _far_below(old_source, info.ends[c - 1], first_error)
    ):
        c -= 1
    if c <= 0 or (first_diag is not None and first_diag < info.ends[c]) or _has_include(info.decls[c:]):
        return None
    lo = info.ends[c - 1]
    frag = _parse_fragment(source, old_source, lo, len(new_text))
    if any(d.code in _NOT_LOCAL or not _far_below(source, lo, d.span.start) for d in frag.diagnostics):
        return None
    if _has_include(frag.program.declarations):
        return None
    return Reparsed(_splice(source, info, c, n, delta, frag), "tail", len(new_text) - lo)


def _splice(source: Source, old: _Old, i: int, j: int, delta: int, frag: ParseResult) -> ParseResult:
    """Old declarations [0, i), the fragment's, old declarations [j, n) moved by delta."""
    kept = relocators(False)
    decls: list[ast.Decl] = [kept[type(d)](d, source, 0) for d in old.decls[:i]]
    decls.extend(frag.program.declarations)
    moved = relocators(delta != 0)
    decls.extend([moved[type(d)](d, source, delta) for d in old.decls[j:]])
    new_tokens = _spliced_tokens(old, i, j, delta, frag.lazy_tokens)
    diagnostics = list(frag.diagnostics)
    if j < len(old.decls):
        cut = old.starts[j]
        diagnostics.extend(relocate_diagnostic(d, source, delta) for d in old.result.diagnostics if d.span.start >= cut)
    program = ast.Program(span=Span(source, 0, len(source.text)), declarations=tuple(decls))
    return ParseResult(program, diagnostics, new_tokens)


def _spliced_tokens(old: _Old, i: int, j: int, delta: int, middle: Tokens) -> Tokens:
    """The old tokens before declaration i, `middle`, and the old tokens from declaration j on,
    moved by `delta`: made when first read (`Tokens`)."""
    tokens = old.tokens
    lo = tokens.bisect_start(old.ends[i - 1]) if i > 0 else 0
    hi = tokens.bisect_start(old.starts[j]) if j < len(old.decls) else len(tokens)
    return Tokens.spliced(
        [*tokens.pieces(0, lo, 0), *middle.pieces(0, len(middle), 0), *tokens.pieces(hi, len(tokens), delta)]
    )
