"""`gpp test`: run agent programs and check their `postcond()`."""

from __future__ import annotations

import time
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from gpp.runner import RunOptions, RunOutcome, RunSetupError, run_program
from gpp.runtime.executor import RunStatus


class Verdict(Enum):
    PASS = "pass"
    FAIL = "fail"
    ERROR = "error"
    SKIP = "skip"


@dataclass
class TestCase:
    path: Path
    verdict: Verdict
    seconds: float
    detail: str
    outcome: RunOutcome | None = None


def discover(paths: Sequence[Path]) -> list[Path]:
    """The .gpp files to run: files as given, directories searched recursively, sorted."""
    found: list[Path] = []
    for p in paths:
        if p.is_dir():
            found.extend(sorted(q for q in p.rglob("*.gpp") if q.is_file()))
        else:
            found.append(p)
    return found


def run_case(path: Path, options: RunOptions, named: bool = False) -> TestCase:
    """Run one program (on the platform its directives choose when `options.platform` is None).
    A program without `main` found in a folder is skipped (it may be a file others include);
    one `named` on the command line is an error, since it was meant to run."""
    started = time.perf_counter()
    try:
        outcome = run_program(path, options)
    except RunSetupError as e:
        return TestCase(path, Verdict.ERROR, time.perf_counter() - started, str(e))
    seconds = time.perf_counter() - started
    if outcome.check.errors:
        error = next(d for d in outcome.diagnostics if d.is_error)
        return TestCase(path, Verdict.ERROR, seconds, f"{error.code} at {error.span}: {error.message}", outcome)
    if outcome.check.model.main is None:
        return TestCase(path, Verdict.ERROR if named else Verdict.SKIP, seconds, "no `procedure main()`", outcome)
    result = outcome.result
    if result is None:
        first = next((d for d in outcome.diagnostics if d.is_error), None)
        return TestCase(path, Verdict.ERROR, seconds, first.message if first else "not run", outcome)
    if result.status is not RunStatus.FINISHED:
        first = next((d for d in result.diagnostics if d.is_error), None)
        detail = f"{result.status.value}" + (f": {first.message}" if first else "")
        return TestCase(path, Verdict.FAIL, seconds, detail, outcome)
    if result.postcond is False:
        return TestCase(path, Verdict.FAIL, seconds, "postcond() does not hold", outcome)
    detail = "postcond() holds" if result.postcond else "finished (no postcond())"
    return TestCase(path, Verdict.PASS, seconds, detail, outcome)


def run_all(paths: Iterable[Path], options: RunOptions, named: Collection[Path] = ()) -> list[TestCase]:
    """Run each program; `named` are the files given by name (not found in a folder)."""
    return [run_case(p, options, p in named) for p in paths]
