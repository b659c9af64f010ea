"""`gpp check`: load, build the code model, lint; all problems of a program at once.

Lints allowed by `// gpp: allow CODE` comments are dropped here (gpp.check.suppress), so every
tool that checks (check, run, test, the language server) honours them. A check made with a
`LintMemo` (the language server's session) lints anew only the declarations an edit touched
(gpp.check.lintmemo)."""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from gpp.base import diagnostics as diag
from gpp.base.perf import paused_gc, with_deep_stack
from gpp.base.source import Span
from gpp.check.suppress import apply_suppressions
from gpp.codes import E0047, E0101, E0102, E0103, E0105, E0106, E0107
from gpp.model.build import build_model
from gpp.model.model import Model
from gpp.syntax.loader import LoadResult, ParseCache, load

if TYPE_CHECKING:
    from gpp.check.lintmemo import LintMemo

# After a syntax error the parser may have skipped a declaration; names declared there would
# then be reported as unknown. These follow-on reports are held back until the syntax is fixed.
_NAME_CODES = frozenset(c.code for c in (E0101, E0102, E0103, E0105, E0106, E0107))
# Errors of the parse whose rewrite leaves the whole program (a name overloaded by arity, each
# declaration renamed): the checker goes on as without a syntax error, lints included.
_WHOLE_PROGRAM = frozenset({E0047.code})


@dataclass
class CheckResult:
    loaded: LoadResult
    model: Model
    diagnostics: list[diag.Diagnostic]
    # For the next check of the same program, when this one was made with a memo.
    lint_memo: LintMemo | None = None

    @property
    def errors(self) -> int:
        return sum(1 for d in self.diagnostics if d.is_error)

    @property
    def warnings(self) -> int:
        return sum(1 for d in self.diagnostics if d.severity is diag.Severity.WARNING)


def check_loaded(
    loaded: LoadResult, lint: bool = True, allow: Collection[str] = (), memo: LintMemo | None = None
) -> CheckResult:
    """Check a loaded program. `memo`: the `lint_memo` of the previous check of the same
    program (or `LintMemo()` for a first one): its lint warnings about the declarations that
    did not change are reused, and the result carries a memo for the next check."""
    # The checker recurses over the tree; thousands of nested terms need a deep stack. Like
    # parsing, checking allocates many long-lived objects: the cyclic collector waits.
    with paused_gc():
        return with_deep_stack(lambda: _check_loaded(loaded, lint, allow, memo))


def _check_loaded(loaded: LoadResult, lint: bool, allow: Collection[str], memo: LintMemo | None) -> CheckResult:
    model, model_diagnostics = build_model(loaded.files)
    syntax_errors = [d for d in loaded.diagnostics if d.is_error and d.code not in _WHOLE_PROGRAM]
    found = list(loaded.diagnostics)
    roots = {f.path for f in loaded.files if f.path in loaded.roots}
    if syntax_errors:
        damaged = _damaged_declarations(loaded, syntax_errors)
        found.extend(d for d in model_diagnostics if d.code not in _NAME_CODES and not _inside_any(damaged, d.span))
    else:
        found.extend(model_diagnostics)
        if lint and memo is not None:
            from gpp.check.lintmemo import lint_again

            warnings, memo = lint_again(model, roots, allow, memo)
            found.extend(warnings)
        elif lint:
            from gpp.check.lints import run_lints

            found.extend(run_lints(model, roots, allow))
    found = apply_suppressions(loaded.files, found, roots, report=lint and not syntax_errors, allow=allow)
    return CheckResult(loaded, model, _dedupe(found), memo)


def check_program(
    path: Path,
    lint: bool = True,
    allow: Collection[str] = (),
    overrides: dict[Path, str] | None = None,
    include_dirs: Sequence[Path] = (),
    cache: ParseCache | None = None,
) -> CheckResult:
    """Check one program: the file and everything it includes (`include_dirs`: the project's
    include folders; `cache`: parsed files to reuse). An unreadable file raises OSError."""
    return check_loaded(load([path], overrides, include_dirs, cache=cache), lint, allow)


def check_paths(
    paths: Sequence[Path], lint: bool = True, allow: Collection[str] = (), include_dirs: Sequence[Path] = ()
) -> list[CheckResult]:
    """Check each file as a program of its own (programs share code through `#include`; a file
    included by several of them is parsed once)."""
    cache = ParseCache()
    return [check_program(p, lint, allow, include_dirs=include_dirs, cache=cache) for p in paths]


def merged_diagnostics(results: Sequence[CheckResult]) -> list[diag.Diagnostic]:
    """All problems of several programs, each once (a shared include is reported once)."""
    return _dedupe([d for r in results for d in r.diagnostics])


def check_text(text: str, path: Path = Path("<input>.gpp"), lint: bool = True) -> CheckResult:
    return check_program(path, lint, overrides={path: text})


def _damaged_declarations(
    loaded: LoadResult, syntax_errors: list[diag.Diagnostic]
) -> dict[int, tuple[list[int], list[int]]]:
    """The declarations that contain a syntax error: the parser repaired them, so what the
    checker would say about them is likely about the repair, not the program. Per source (by
    id), the starts and the ends of those declarations, in order."""
    damaged: dict[int, tuple[list[int], list[int]]] = {}
    for pf in loaded.files:
        errors = sorted(d.span.start for d in syntax_errors if d.span.source is pf.source)
        if not errors:
            continue
        starts: list[int] = []
        ends: list[int] = []
        decls = pf.program.declarations
        for k, decl in enumerate(decls):
            # Up to the next declaration: an error just after a declaration (`f() = n() = 1`)
            # is about it too.
            end = decls[k + 1].span.start if k + 1 < len(decls) else len(pf.source.text)
            first = bisect_left(errors, decl.span.start)
            if first < len(errors) and errors[first] <= end:
                starts.append(decl.span.start)
                ends.append(end)
        damaged[id(pf.source)] = (starts, ends)
    return damaged


def _inside_any(damaged: dict[int, tuple[list[int], list[int]]], span: Span) -> bool:
    """Does `span` start in one of the damaged declarations? They follow each other and meet
    at most at an end, so the last one that starts before `span` is the one to ask."""
    starts, ends = damaged.get(id(span.source), ([], []))
    k = bisect_right(starts, span.start) - 1
    return k >= 0 and span.start <= ends[k]


def _dedupe(found: list[diag.Diagnostic]) -> list[diag.Diagnostic]:
    seen: set[tuple[str, str, int, int, str]] = set()
    out: list[diag.Diagnostic] = []
    for d in sorted(found, key=diag.Diagnostic.sort_key):
        key = (d.code, d.span.source.identity, d.span.start, d.span.end, d.message)
        if key not in seen:
            seen.add(key)
            out.append(d)
    return out
