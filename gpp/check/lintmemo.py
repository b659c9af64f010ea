"""Lints after an edit: only the declarations the edit touched are linted anew.

A check made with a `LintMemo` (`gpp.check.check_loaded(memo=...)`; gpp.check.session.Session
passes the one of the program's previous check) hands back a new one: the environment and, per
top-level declaration of the root file, its kind, text, start and the *local* lints' warnings.
The next check with the same environment takes the warnings of every unchanged declaration
over, relocated, and runs the local lints only over the others (`run_lints_split`); the
*global* lints run over the whole program. Anything it cannot reuse is linted as `run_lints`
lints it, and the result is exactly `run_lints`'s (tests/check/test_lint_reuse.py). The local and
global lints, and why reuse is exact: docs/design.md, "Lint reuse".
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.check.lints import run_lints, run_lints_split, skipped_lints
from gpp.model.model import Model
from gpp.syntax import ast
from gpp.syntax.incremental import diagnostic_spans, relocate_diagnostic
from gpp.syntax.loader import ParsedFile


@dataclass(frozen=True, slots=True)
class _Declaration:
    """A top-level declaration of the root file, as the memo keeps it."""

    kind: type[ast.Decl]
    text: str
    start: int
    warnings: tuple[diag.Diagnostic, ...]  # the local lints' warnings about it, in `run_lints` order

    @property
    def end(self) -> int:
        return self.start + len(self.text)


@dataclass(frozen=True, slots=True)
class LintMemo:
    """The local lints' warnings of a check, per declaration, for the next check to reuse.
    `LintMemo()` holds nothing: a check made with it lints all and notes the result."""

    environment: tuple[object, ...] | None = None
    source: Source | None = None  # the root file's, to which the warnings' spans refer
    declarations: tuple[_Declaration, ...] = ()
    reused: int = 0  # how many declarations' warnings the check that made it took over


def lint_again(
    model: Model, roots: Collection[Path], allow: Collection[str], memo: LintMemo
) -> tuple[list[diag.Diagnostic], LintMemo]:
    """The warnings `run_lints` gives, reusing what `memo` knows; and the memo for next time."""
    root_files = [f for f in model.files if f.path in roots]
    if len(root_files) != 1 or any(isinstance(d, ast.MainBlock) for d in root_files[0].program.declarations):
        return run_lints(model, roots, allow), LintMemo()
    root = root_files[0]
    decls = root.program.declarations
    source = root.source
    texts = [source.text[d.span.start : d.span.end] for d in decls]
    environment = _environment(model, root, roots, allow)
    reused: dict[int, tuple[diag.Diagnostic, ...]] = {}
    if memo.environment == environment and memo.source is not None and len(memo.declarations) == len(decls):
        reused = _relocated(memo, memo.source, decls, texts, source)
    relint = [d for k, d in enumerate(decls) if k not in reused]
    global_warnings, local = run_lints_split(model, roots, allow, relint if reused else None)
    fresh = _by_declaration(local, decls, source)
    if fresh is None or not fresh.keys().isdisjoint(reused):
        # A local lint warned outside the declaration it looked at: not what the memo can keep.
        return run_lints(model, roots, allow), LintMemo()
    entries = tuple(
        _Declaration(type(d), texts[k], d.span.start, reused[k] if k in reused else tuple(fresh.get(k, ())))
        for k, d in enumerate(decls)
    )
    found = global_warnings + [w for e in entries for w in e.warnings]
    return found, LintMemo(environment, source, entries, len(reused))


def _environment(model: Model, root: ParsedFile, roots: Collection[Path], allow: Collection[str]) -> tuple[object, ...]:
    """What the local lints may read besides the declaration they look at: the root file's
    declarations without the bodies of procedures (whether there is one counts), the other
    files of the program, the lints skipped and the roots."""
    text = root.source.text
    headers: list[tuple[object, ...]] = []
    for d in root.program.declarations:
        if isinstance(d, ast.ProcedureDecl) and d.body is not None:
            body = d.body.span
            headers.append((type(d), text[d.span.start : body.start], text[body.end : d.span.end]))
        else:
            headers.append((type(d), text[d.span.start : d.span.end]))
    others = tuple((f.path, f.source.text) for f in model.files if f is not root)
    return root.path, frozenset(roots), skipped_lints(allow), tuple(headers), others


def _relocated(
    memo: LintMemo, old_source: Source, decls: tuple[ast.Decl, ...], texts: list[str], source: Source
) -> dict[int, tuple[diag.Diagnostic, ...]]:
    """The old warnings of the declarations (by index) whose kind and text did not change,
    moved to where they are now; a declaration with a warning that cannot be moved so is left
    out."""
    old = memo.declarations
    same = [k for k, d in enumerate(decls) if old[k].text == texts[k] and old[k].kind is type(d)]
    # Where the unchanged declarations were, and how far each moved.
    starts = [old[k].start for k in same]
    ends = [old[k].end for k in same]
    moves = [decls[k].span.start - old[k].start for k in same]

    def moved(span: Span) -> int | None:
        j = bisect_right(starts, span.start) - 1
        inside = span.source is old_source and j >= 0 and span.end <= ends[j]
        return moves[j] if inside else None

    out: dict[int, tuple[diag.Diagnostic, ...]] = {}
    for k in same:
        warnings = old[k].warnings
        if not warnings:
            out[k] = ()
            continue
        delta = decls[k].span.start - old[k].start
        if all(moved(span) == delta for w in warnings for span in diagnostic_spans(w)):
            out[k] = tuple(relocate_diagnostic(w, source, delta) for w in warnings)
    return out


def _by_declaration(
    warnings: list[diag.Diagnostic], decls: tuple[ast.Decl, ...], source: Source
) -> dict[int, list[diag.Diagnostic]] | None:
    """The warnings per declaration (by index) their primary span is in, in order; None when
    one is in none."""
    starts = [d.span.start for d in decls]
    out: dict[int, list[diag.Diagnostic]] = {}
    for w in warnings:
        k = bisect_right(starts, w.span.start) - 1
        if w.span.source is not source or k < 0 or w.span.end > decls[k].span.end:
            return None
        out.setdefault(k, []).append(w)
    return out
