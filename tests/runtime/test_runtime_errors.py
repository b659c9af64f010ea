"""Runtime errors and deadlocks (SEMANTICS §3, §4): each stops the run with exactly one
diagnostic (code R0xxx, the span of the offending expression or statement, a message), an
`error` or `blocked` trace record and a final `finish` record; never a Python traceback.

The programs in tests/runtime_errors/ state what they expect in their leading comments:

    // expect: STATUS CODE at LINE:COL: MESSAGE
    // expect-note: a note the diagnostic must have
    // expect-label: the label under the primary span
    // time-limit: SECONDS   (run with this --time-limit, platform time)
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.check import check_text
from gpp.planner.policy import PolicyPlanner
from gpp.platform.dummy import DummyPlatform, Scenario
from gpp.report.text import render_text
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.events import (
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    FinishEvent,
    PlanEvent,
    decode,
    encode,
)
from gpp.runtime.executor import Executor, RunResult, RunStatus
from gpp.runtime.trace import Recording, Trace
from tests.support.cli import run

ROOT = Path(__file__).resolve().parents[2]
ERRORS_DIR = ROOT / "tests" / "runtime_errors"
PROGRAMS = sorted(ERRORS_DIR.glob("*.gpp"))

_EXPECT = re.compile(r"^// expect: (\w+) (R\d{4}) at (\d+):(\d+): (.*)$")


@dataclass
class Expectation:
    status: str
    code: str
    line: int
    col: int
    message: str
    notes: list[str] = field(default_factory=list)
    label: str | None = None
    timeout: float | None = None


def _reject_constant(name: str) -> object:
    raise ValueError(f"not strict JSON: {name}")


def strict_json(line: str) -> object:
    """A trace line parsed as strict JSON: NaN and infinities are not JSON (docs/trace.md)."""
    return json.loads(line, parse_constant=_reject_constant)


def expectation(path: Path) -> Expectation:
    found: Expectation | None = None
    notes: list[str] = []
    label: str | None = None
    timeout: float | None = None
    for line in path.read_text(encoding="utf-8").splitlines():
        m = _EXPECT.match(line)
        if m:
            found = Expectation(m[1], m[2], int(m[3]), int(m[4]), m[5])
        elif line.startswith("// expect-note: "):
            notes.append(line.removeprefix("// expect-note: ").strip())
        elif line.startswith("// expect-label: "):
            label = line.removeprefix("// expect-label: ").strip()
        elif line.startswith("// time-limit: "):
            timeout = float(line.removeprefix("// time-limit: "))
    assert found is not None, f"{path.name} has no `// expect:` line"
    found.notes, found.label, found.timeout = notes, label, timeout
    return found


def _errors(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in diagnostics if d.is_error]


def _explain(outcome: RunOutcome) -> str:
    records = outcome.recording.records[-10:] if outcome.recording is not None else []
    return render_text(outcome.diagnostics) + "\n" + "\n".join(encode(r) for r in records)


def test_there_is_a_program_for_every_runtime_error_code() -> None:
    codes = {expectation(p).code for p in PROGRAMS}
    assert codes >= {f"R00{n:02d}" for n in (1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13)}


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_program_stops_with_exactly_the_expected_diagnostic(path: Path, tmp_path: Path) -> None:
    expected = expectation(path)
    trace_file = tmp_path / "trace.jsonl"
    outcome = run_program(path, RunOptions(record=True, time_limit=expected.timeout, trace=trace_file))
    assert not outcome.check.errors, _explain(outcome)
    assert outcome.result is not None
    assert outcome.result.status.value == expected.status, _explain(outcome)
    assert outcome.postcond is None  # not evaluated after a failed run
    assert not outcome.ok and outcome.exit_code == 1

    [d] = _errors(outcome.diagnostics)
    assert d.code == expected.code, _explain(outcome)
    assert (d.span.line, d.span.col) == (expected.line, expected.col), _explain(outcome)
    assert d.message == expected.message
    assert Path(d.span.source.path).resolve() == path
    for note in expected.notes:
        assert note in [n.strip() for n in d.notes], d.notes
    if expected.label is not None:
        assert d.label == expected.label

    lines = trace_file.read_text(encoding="utf-8").splitlines()
    for line in lines:
        strict_json(line)
    records = [decode(line) for line in lines]
    stops = [r for r in records if isinstance(r, ErrorEvent | BlockedEvent)]
    assert len(stops) == 1
    [stop] = stops
    assert stop.message == expected.message
    assert isinstance(stop.at, str)
    where, line, col = stop.at.rsplit(":", 2)
    assert (Path(where).resolve(), int(line), int(col)) == (path, expected.line, expected.col)
    if isinstance(stop, ErrorEvent):
        assert stop.code == expected.code
    assert isinstance(records[-1], FinishEvent) and records[-1].status == expected.status


@pytest.mark.slow
def test_no_runtime_error_prints_a_traceback() -> None:
    script = (
        "import sys\n"
        "from pathlib import Path\n"
        "from gpp.run.runner import RunOptions, run_program\n"
        "for name in sys.argv[1:]:\n"
        "    o = run_program(Path(name), RunOptions(record=True, time_limit=30))\n"
        "    print(name, o.result.status.value, o.exit_code)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script, *[str(p.relative_to(ROOT)) for p in PROGRAMS]],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    statuses = dict(line.split(" ", 1) for line in done.stdout.splitlines())
    assert len(statuses) == len(PROGRAMS)
    assert all(value.split()[0] in ("error", "blocked", "timeout") for value in statuses.values())


def _has_gpp_run() -> bool:
    return " run " in run("--help", cwd=ROOT).stdout


@pytest.mark.skipif(not _has_gpp_run(), reason="`gpp run` is not available yet")
@pytest.mark.parametrize("name", ["division_by_zero", "blocked_precondition", "runaway_recursion"])
def test_gpp_run_reports_a_runtime_error_without_a_traceback(name: str) -> None:
    done = run("run", f"tests/runtime_errors/{name}.gpp", cwd=ROOT)
    assert done.returncode != 0
    assert "Traceback" not in done.stdout + done.stderr
    assert expectation(ERRORS_DIR / f"{name}.gpp").code in done.stdout + done.stderr


# ---------------------------------------------------------------- small cases, inline

PRELUDE = """
compound Pose { number x, number y }
number fluent n() { initially: () = 0; }
number fluent nothing() { initially: () = null; }
string fluent no_text() { initially: () = null; }
bool fluent flag() { initially: () = false; }
list[number] fluent l() { initially: () = list[number] [1, 2]; }
list[number] fluent no_list() { initially: () = null; }
Pose fluent no_pose() { initially: () = null; }
number function r() = 1
action a() { }
"""


def run_text(
    body: str, tmp_path: Path, extra: str = "", time_limit: float | None = None
) -> tuple[RunResult, Recording]:
    check = check_text(PRELUDE + extra + "\nprocedure main() {\n" + body + "\n}\n", tmp_path / "t.gpp", lint=False)
    assert not check.errors, render_text(check.diagnostics)
    trace = Recording()
    executor = Executor(
        CompiledProgram(check.model), DummyPlatform(), Trace(listeners=[trace]), time_limit, planner=PolicyPlanner()
    )
    return executor.run(), trace


@pytest.mark.parametrize(
    ("statement", "code", "message", "span_text"),
    [
        ("n() = -nothing();", "R0002", "`-` applied to `null`", "-nothing()"),
        ("n() = length(no_list());", "R0002", "`length` of `null`", "length(no_list())"),
        ("push_back(no_list(), 1);", "R0002", "`push_back` on a `null` list", "no_list()"),
        ("no_pose().x = 1;", "R0002", "assignment into a `null` value", "no_pose().x"),
        ('no_text() = no_text() + "!";', "R0002", "`+` applied to `null`", 'no_text() + "!"'),
        ("flag() = nothing() >= 1;", "R0002", "`>=` compares `null`", "nothing() >= 1"),
        ("n() = l()[0.5];", "R0003", "list index `0.5` is not a whole number", "l()[0.5]"),
        ("n() = l()[-1];", "R0003", "list index -1 is out of range (the list has 2 elements)", "l()[-1]"),
        ("n() = 1 / 0.0;", "R0001", "division by zero", "1 / 0.0"),
        ("n() = (10 ** 300) / 1e-300;", "R0001", "the result of `/` is too large for a number", "(10 ** 300) / 1e-300"),
        ("n() = 1e308 + 1e308;", "R0001", "the result of `+` is too large for a number", "1e308 + 1e308"),
        ("n() = -1e308 - 1e308;", "R0001", "the result of `-` is too large for a number", "-1e308 - 1e308"),
        ("n() = (10 ** 308) * 10;", "R0001", "the result of `*` is too large for a number", "(10 ** 308) * 10"),
        ("n() = (10 ** 308) * 10.0;", "R0001", "the result of `*` is too large for a number", "(10 ** 308) * 10.0"),
        ("n() = 10 ** 309;", "R0001", "`10 ** 309` is too large", "10 ** 309"),
        ("n() = (-10) ** 309;", "R0001", "`(-10) ** 309` is too large", "(-10) ** 309"),
        ("n() = 2.0 ** 10000;", "R0001", "`2.0 ** 10000` is too large", "2.0 ** 10000"),
        ("n() = 10 ** 10000000;", "R0001", "`10 ** 10000000` is too large", "10 ** 10000000"),
        ("n() = (0 - 8) ** 0.5;", "R0001", "`(-8) ** 0.5` is not a real number", "(0 - 8) ** 0.5"),
        ("solve(n() - 1, r()) a();", "R0010", "the horizon of `solve` must be a whole number >= 0", "n() - 1"),
    ],
)
def test_expression_error_has_its_code_message_and_span(
    statement: str, code: str, message: str, span_text: str, tmp_path: Path
) -> None:
    result, trace = run_text(statement, tmp_path)
    assert result.status is RunStatus.ERROR
    [d] = _errors(result.diagnostics)
    assert d.code == code
    assert message in d.message
    assert d.span.text == span_text
    [error] = trace.of(ErrorEvent)
    assert error.code == code and isinstance(error.at, str) and error.at.endswith(f":{d.span.line}:{d.span.col}")
    assert isinstance(trace.records[-1], FinishEvent)


def test_error_stops_the_run_before_the_next_statement(tmp_path: Path) -> None:
    result, trace = run_text("n() = 1; n() = n() / 0; n() = 3;", tmp_path)
    assert result.status is RunStatus.ERROR
    assert [r.value for r in trace.of(AssignEvent)] == [1]


def test_error_in_a_planned_program_is_reported_at_its_source(tmp_path: Path) -> None:
    result, _ = run_text("solve(2, r()) n() = 1 / nothing();", tmp_path)
    [d] = _errors(result.diagnostics)
    assert d.code == "R0002" and d.span.text == "1 / nothing()"


@pytest.mark.parametrize("statement", ["solve(2, r()) a();", "search a();"])
def test_solve_without_a_planner_is_an_error_at_the_statement(statement: str, tmp_path: Path) -> None:
    check = check_text(PRELUDE + "procedure main() { n() = 1; " + statement + " }\n", tmp_path / "t.gpp", lint=False)
    assert not check.errors, render_text(check.diagnostics)
    trace = Recording()
    result = Executor(CompiledProgram(check.model), DummyPlatform(), Trace(listeners=[trace])).run()
    assert result.status is RunStatus.ERROR
    [d] = _errors(result.diagnostics)
    kind = statement.split("(")[0].split(" ")[0]
    assert d.code == "R0010" and d.message == f"`{kind}` cannot plan: this run has no planner"
    assert d.span.text == statement
    assert [r.value for r in trace.of(AssignEvent)] == [1]
    assert trace.of(PlanEvent) == [] and isinstance(trace.records[-1], FinishEvent)


def test_unhandled_failure_continues_and_is_counted(tmp_path: Path) -> None:
    check = check_text(PRELUDE + "procedure main() { a(); n() = 1; }\n", tmp_path / "t.gpp", lint=False)
    trace = Recording()
    platform = DummyPlatform(Scenario.from_data({"action": [{"match": "a()", "outcome": "fail"}]}))
    result = Executor(CompiledProgram(check.model), platform, Trace(listeners=[trace])).run()
    assert result.status is RunStatus.FINISHED
    assert result.failures == 1 and result.unhandled_failures == 1
    [end] = trace.of(EndEvent)
    assert end.status == "failed" and end.unhandled is True
    [finish] = trace.of(FinishEvent)
    assert finish.unhandled_failures == 1
    assert trace.of(AssignEvent)[0].value == 1


# ---------------------------------------------------------------- deadlocks and timeouts


def test_blocked_precondition_names_every_false_conjunct_with_its_fluent_values(tmp_path: Path) -> None:
    extra = """
    symbol domain Room = {hall, kitchen}
    Room fluent at() { initially: () = hall; }
    number fluent battery() { initially: () = 5; }
    action go(Room r) { precondition: at() != r & battery() > 10 & (r == kitchen | n() > 0) }
    """
    result, trace = run_text("go(hall);", tmp_path, extra)
    assert result.status is RunStatus.BLOCKED
    [d] = _errors(result.diagnostics)
    assert d.code == "R0011" and d.span.text == "go(hall);"
    assert d.message == "the program is blocked: the precondition of `go(hall)` is false"
    notes = [n.strip() for n in d.notes]
    assert "false: `at() != r` (with r = hall)" in notes
    assert "at() = hall" in notes
    assert "false: `battery() > 10`" in notes
    assert "battery() = 5" in notes
    assert "false: `(r == kitchen | n() > 0)` (with r = hall)" in notes
    assert "n() = 0" in notes
    [blocked] = trace.of(BlockedEvent)
    assert blocked.message == d.message


def test_blocked_inside_a_procedure_points_into_the_procedure(tmp_path: Path) -> None:
    extra = "procedure wait_for_flag() { n() = 1; test(flag()); }\n"
    result, _ = run_text("wait_for_flag();", tmp_path, extra)
    [d] = _errors(result.diagnostics)
    assert d.span.text == "test(flag());"
    assert "flag() = false" in d.notes


def test_second_start_waits_for_the_running_activity_then_is_an_error(tmp_path: Path) -> None:
    result, _ = run_text("start(a()); start(a());", tmp_path)
    [d] = _errors(result.diagnostics)
    assert d.code == "R0009" and d.span.text == "start(a());" and d.span.col == 13
    # The second start waited for the first activity (1 s) instead of failing at once.
    assert result.platform_time == 1.0


def test_the_time_limit_stops_a_run_that_waits_for_a_long_activity(tmp_path: Path) -> None:
    extra = "action long() { duration: [100, 100] }\n"
    result, trace = run_text("long();", tmp_path, extra, time_limit=10)
    assert result.status is RunStatus.TIMEOUT
    [d] = _errors(result.diagnostics)
    assert d.code == "R0013" and d.message == "the run reached its time limit of 10 s of platform time (`--time-limit`)"
    assert "it waits here: it waits for `long()` to end" in d.notes
    assert result.platform_time == 10
    # The still running activity is cancelled when the run stops.
    [cancel] = trace.of(CancelEvent)
    assert cancel.action == "long()" and cancel.reason == "the program ended"


def test_the_time_limit_does_not_stop_a_run_that_ends_in_time(tmp_path: Path) -> None:
    extra = "action long() { duration: [100, 100] }\n"
    result, _ = run_text("long();", tmp_path, extra, time_limit=100)
    assert result.status is RunStatus.FINISHED
    assert result.platform_time == 100


def test_nothing_left_to_wait_for_is_blocked_not_a_timeout(tmp_path: Path) -> None:
    result, _ = run_text("test(flag());", tmp_path, time_limit=50)
    assert result.status is RunStatus.BLOCKED
    assert result.platform_time == 0
