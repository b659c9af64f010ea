"""`gpp test`: run agent programs and check their `postcond()`; select them by name (`-k`),
run them in parallel processes (`-j`), and write the results as JUnit XML."""

from __future__ import annotations

import re
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable, Collection, Iterable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from enum import Enum
from pathlib import Path

from gpp.base.diagnostics import Diagnostic
from gpp.report.text import render_text
from gpp.run.runner import RunOptions, RunOutcome, RunSetupError, run_program
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
    # The errors of the program (check or run), kept when the outcome is dropped (`-j`).
    errors: tuple[Diagnostic, ...] = field(default=())

    def __post_init__(self) -> None:
        if self.outcome is not None and not self.errors:
            self.errors = tuple(d for d in self.outcome.diagnostics if d.is_error)

    @property
    def failed(self) -> bool:
        return self.verdict in (Verdict.FAIL, Verdict.ERROR)


def discover(paths: Sequence[Path]) -> list[Path]:
    """The .gpp files to run: files as given, directories searched recursively, sorted."""
    found: list[Path] = []
    for p in paths:
        if p.is_dir():
            found.extend(sorted(q for q in p.rglob("*.gpp") if q.is_file()))
        else:
            found.append(p)
    return found


def _takes_arguments(path: Path, options: RunOptions) -> bool:
    """Does the program's entry procedure take parameters that the options give no value?"""
    from gpp.check import check_program

    try:
        model = check_program(path, allow=options.allow, include_dirs=options.include_dirs).model
    except OSError:
        return False
    entry = model.globals.get(options.entry) if model is not None else None
    return entry is not None and any(p.name not in options.args for p in entry.params)


def run_case(path: Path, options: RunOptions, named: bool = False) -> TestCase:
    """Run one program (on the platform its directives choose when `options.platform` is None).
    A program without `main` found in a folder is skipped (it may be a file others include), as
    is one whose `main` takes parameters it is not given (it is run with arguments); one
    `named` on the command line is an error, since it was meant to run."""
    started = time.perf_counter()
    try:
        outcome = run_program(path, options)
    except RunSetupError as e:
        if not named and _takes_arguments(path, options):
            # A program to run with arguments (`gpp run --arg`, a launch file's parameters).
            return TestCase(path, Verdict.SKIP, time.perf_counter() - started, f"{e} (`main` takes parameters)")
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


def run_all(
    paths: Iterable[Path],
    options: RunOptions,
    *,
    jobs: int = 1,
    stop_at_first_failure: bool = False,
    on_case: Callable[[TestCase], None] | None = None,
    named: Collection[Path] = (),
) -> list[TestCase]:
    """Run the programs in order, or in `jobs` worker processes at once (the results come back
    in the order of `paths` either way). `stop_at_first_failure`: no program is started after
    one failed (with several jobs, those already running finish). `named`: the programs given
    by name on the command line (not found in a folder)."""
    paths = list(paths)
    if jobs <= 1 or len(paths) <= 1:
        cases: list[TestCase] = []
        for p in paths:
            cases.append(run_case(p, options, p in named))
            if on_case is not None:
                on_case(cases[-1])
            if stop_at_first_failure and cases[-1].failed:
                break
        return cases
    return list(_run_parallel(paths, options, jobs, stop_at_first_failure, on_case, named))


def _run_detached(path: Path, options: RunOptions, named: bool) -> TestCase:
    """`run_case` in a worker process: the outcome (interpreter state, platform) stays there."""
    return replace(run_case(path, options, named), outcome=None)


def _run_parallel(
    paths: list[Path],
    options: RunOptions,
    jobs: int,
    stop_at_first_failure: bool,
    on_case: Callable[[TestCase], None] | None,
    named: Collection[Path],
) -> Iterator[TestCase]:
    from concurrent.futures import Future, ProcessPoolExecutor

    # The platform's default start method (fork on Linux: the workers start with gpp loaded;
    # nothing has run in this process yet, so there is no thread to lose).
    with ProcessPoolExecutor(max_workers=min(jobs, len(paths))) as pool:
        futures: list[Future[TestCase]] = [pool.submit(_run_detached, p, options, p in named) for p in paths]
        stopped = False
        for future in futures:
            if stopped:
                future.cancel()
                continue
            case = future.result()
            if on_case is not None:
                on_case(case)
            yield case
            if stop_at_first_failure and case.failed:
                stopped = True
                for later in futures:
                    later.cancel()


# ---------------------------------------------------------------- -k EXPRESSION


NameTest = Callable[[str], bool]


class SelectionError(ValueError):
    """A `-k` expression that does not parse."""


_K_TOKEN = re.compile(r"\s*(\(|\)|[^\s()]+)")


def selector(expression: str) -> Callable[[str], bool]:
    """The test of `-k EXPRESSION` on a program's name, as pytest's: words match as substrings
    (ignoring case), combined with `and`, `or`, `not` and parentheses."""
    tokens = [m.group(1) for m in _K_TOKEN.finditer(expression)]
    position = 0

    def peek() -> str | None:
        return tokens[position] if position < len(tokens) else None

    def take() -> str:
        nonlocal position
        token = peek()
        if token is None:
            raise SelectionError(f"-k `{expression}`: the expression ends too early")
        position += 1
        return token

    def chain(operator: str, operand: Callable[[], NameTest], combine: Callable[[Iterable[bool]], bool]) -> NameTest:
        """Operands joined by `operator` (`and`, `or`), as one test."""
        parts = [operand()]
        while peek() == operator:
            take()
            parts.append(operand())
        return lambda name: combine(p(name) for p in parts)

    def either() -> NameTest:
        return chain("or", both, any)

    def both() -> NameTest:
        return chain("and", negation, all)

    def negation() -> NameTest:
        if peek() == "not":
            take()
            inner = negation()
            return lambda name: not inner(name)
        token = take()
        if token == "(":
            inner = either()
            if take() != ")":
                raise SelectionError(f"-k `{expression}`: `(` without `)`")
            return inner
        if token in (")", "and", "or"):
            raise SelectionError(f"-k `{expression}`: unexpected `{token}`")
        word = token.lower()
        return lambda name: word in name.lower()

    if not tokens:
        raise SelectionError("-k needs an expression")
    test = either()
    if peek() is not None:
        raise SelectionError(f"-k `{expression}`: unexpected `{peek()}`")
    return test


# ---------------------------------------------------------------- JUnit XML


def junit_xml(cases: Sequence[TestCase], suite: str = "gpp test") -> str:
    """The results as JUnit XML: one `testsuite` with a `testcase` per program (classname: its
    folder, name: its file name); `failure` for a failed run or postcond, `error` for a program
    that did not check or could not start, `skipped` for one without `main`."""
    root = ET.Element("testsuites")
    counts = {v: sum(1 for c in cases if c.verdict is v) for v in Verdict}
    total = sum(c.seconds for c in cases)
    attributes = {
        "name": suite,
        "tests": str(len(cases)),
        "failures": str(counts[Verdict.FAIL]),
        "errors": str(counts[Verdict.ERROR]),
        "skipped": str(counts[Verdict.SKIP]),
        "time": f"{total:.3f}",
    }
    root.attrib.update({k: v for k, v in attributes.items() if k != "name"})
    testsuite = ET.SubElement(root, "testsuite", attributes)
    for case in cases:
        folder = case.path.parent.as_posix()
        element = ET.SubElement(
            testsuite,
            "testcase",
            {"classname": folder if folder != "." else "", "name": case.path.name, "time": f"{case.seconds:.3f}"},
        )
        text = render_text(list(case.errors), summary=False) if case.errors else case.detail
        if case.verdict is Verdict.FAIL:
            ET.SubElement(element, "failure", {"message": case.detail, "type": "failure"}).text = text
        elif case.verdict is Verdict.ERROR:
            ET.SubElement(element, "error", {"message": case.detail, "type": "error"}).text = text
        elif case.verdict is Verdict.SKIP:
            ET.SubElement(element, "skipped", {"message": case.detail})
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
