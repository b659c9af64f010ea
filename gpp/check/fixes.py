"""`gpp check --fix` and `--diff`: apply the safe fixes of the diagnostics, round after round.

A round checks every program (with the texts fixed so far), takes each safe fix
(`Fix.is_safe`) whose edits lie in one file of the project (the standard library is never
changed), applies the ones that do not overlap, and checks again; fixing a name can reveal the
next problem, and of two overlapping fixes the second waits for the next round. It stops when a
round has nothing to apply, after `MAX_ROUNDS` at most. Nothing is written here: the caller
writes the new texts (`gpp.base.paths.write_atomically`) or shows them (`unified_diff`).

What was fixed is counted by what went away, not by the edits made: the problems of the first
check (by file, code and message) that the last one no longer reports, whether a fix was aimed
at them or they went with one (`action go is never used` goes with the misspelled call of
`go`); and the problems the first check did not show (a syntax error holds back the name
errors and lints of a file until it is fixed) that a later round fixed: a problem a fix was
applied for that the next check reports fewer times. Those are `found_later`, so that the
report can say that more was fixed than the check had shown.
"""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gpp.base import diagnostics as diag
from gpp.base.resources import stdlib_dir
from gpp.base.source import Source
from gpp.check import CheckResult, merged_diagnostics

MAX_ROUNDS = 10

# Check one program with some files' texts replaced (resolved path -> text).
Checker = Callable[[Path, dict[Path, str]], CheckResult]


@dataclass
class FixOutcome:
    original: dict[Path, str] = field(default_factory=dict)  # resolved path -> text before
    fixed: dict[Path, str] = field(default_factory=dict)  # resolved path -> text after (changed files)
    shown: dict[Path, str] = field(default_factory=dict)  # resolved path -> path as diagnostics show it
    applied: int = 0  # fixes applied, over all rounds
    fixed_problems: int = 0  # problems that went away (see the module's docstring)
    found_later: int = 0  # of those, how many the first check did not show
    hidden_by_syntax_errors: bool = False  # the first check had syntax errors (which hold back others)
    rounds: int = 0
    results: list[CheckResult] = field(default_factory=list)  # the check of the fixed texts

    def changed(self) -> list[Path]:
        return [p for p, text in self.fixed.items() if text != self.original[p]]


def fix_programs(paths: Sequence[Path], check: Checker, max_rounds: int = MAX_ROUNDS) -> FixOutcome:
    """Apply safe fixes to the programs at `paths` (and the project files they include) in
    memory until none is left; the outcome holds the new texts and the final check."""
    outcome = FixOutcome()
    stdlib = stdlib_dir().resolve()
    tally: _Tally | None = None
    fixed_for: Counter[_Key] = Counter()  # the problems the last round applied a fix for
    while True:
        outcome.results = [check(p, outcome.fixed) for p in paths]
        found = Counter(_key(d) for d in merged_diagnostics(outcome.results))
        if tally is None:
            tally = _Tally(found.copy(), found.copy(), found)
            outcome.hidden_by_syntax_errors = any(d.is_error for r in outcome.results for d in r.loaded.diagnostics)
        else:
            tally.went_away(fixed_for, found, outcome)
        outcome.fixed_problems = (tally.first - found).total() + outcome.found_later
        if outcome.rounds == max_rounds:
            return outcome
        files: dict[int, Path] = {}
        for result in outcome.results:
            for f in result.loaded.files:
                if not f.path.is_relative_to(stdlib):
                    files[id(f.source)] = f.path
                    outcome.shown.setdefault(f.path, f.source.path)
                    outcome.original.setdefault(f.path, f.source.text)
        pending: dict[Path, tuple[Source, list[diag.Fix]]] = {}
        problem_of: dict[int, _Key] = {}  # fix (by id) -> the problem it fixes
        for result in outcome.results:
            for d in result.diagnostics:
                fix = d.fix
                if fix is None or not fix.is_safe or not fix.edits:
                    continue
                source = fix.edits[0].span.source
                path = files.get(id(source))
                if path is None or any(e.span.source is not source for e in fix.edits):
                    continue
                entry = pending.setdefault(path, (source, []))
                if fix not in entry[1]:
                    entry[1].append(fix)
                    problem_of[id(fix)] = _key(d)
        fixed_for = Counter()
        for path, (source, fixes) in pending.items():
            chosen = choose_fixes(fixes)
            if chosen:
                outcome.fixed[path] = _applied(source.text, chosen)
                fixed_for.update(problem_of[id(f)] for f in chosen)
        if not fixed_for:
            return outcome
        outcome.applied += fixed_for.total()
        outcome.rounds += 1


_Key = tuple[str, str, str]  # a problem: the file as shown, the code, the message


def _key(d: diag.Diagnostic) -> _Key:
    return (d.span.source.path, d.code, d.message)


@dataclass
class _Tally:
    """What the first check showed and what the last one found, to count what fixes removed."""

    first: Counter[_Key]  # shown by the first check
    unseen: Counter[_Key]  # shown by the first check and not yet fixed by a fix aimed at them
    last: Counter[_Key]  # found by the last check

    def went_away(self, fixed_for: Counter[_Key], found: Counter[_Key], outcome: FixOutcome) -> None:
        """Count, of the problems the last round's fixes were aimed at and the new check
        (`found`) reports fewer times, those the first check did not show."""
        for key, count in fixed_for.items():
            gone = min(count, max(0, self.last[key] - found[key]))
            shown = min(gone, self.unseen[key])
            self.unseen[key] -= shown
            outcome.found_later += gone - shown
        self.last = found


def apply_fixes(text: str, fixes: Sequence[diag.Fix]) -> tuple[str, int]:
    """`text` with the fixes that do not overlap an earlier one (in order of position) applied,
    and how many were."""
    chosen = choose_fixes(fixes)
    return _applied(text, chosen), len(chosen)


def choose_fixes(fixes: Sequence[diag.Fix]) -> list[diag.Fix]:
    """The fixes that do not overlap an earlier one, in order of position."""
    chosen: list[diag.Fix] = []
    last_end = -1
    last_insertion = -1
    for fix in sorted(fixes, key=lambda f: (min(e.span.start for e in f.edits), max(e.span.end for e in f.edits))):
        start = min(e.span.start for e in fix.edits)
        end = max(e.span.end for e in fix.edits)
        if start < last_end or (start == end and start == last_insertion):
            continue
        chosen.append(fix)
        last_end = end
        last_insertion = start if start == end else -1
    return chosen


def _applied(text: str, chosen: Sequence[diag.Fix]) -> str:
    edits = sorted((e for f in chosen for e in f.edits), key=lambda e: (e.span.start, e.span.end), reverse=True)
    for e in edits:
        text = text[: e.span.start] + e.text + text[e.span.end :]
    return text


def unified_diff(outcome: FixOutcome) -> str:
    """The changes as one unified diff (`--- a/FILE` / `+++ b/FILE`), files in order."""
    parts: list[str] = []
    for path in sorted(outcome.changed(), key=lambda p: outcome.shown[p]):
        shown = outcome.shown[path]
        before = outcome.original[path].splitlines(keepends=True)
        after = outcome.fixed[path].splitlines(keepends=True)
        for line in difflib.unified_diff(before, after, f"a/{shown}", f"b/{shown}"):
            parts.append(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n")
    return "".join(parts)
