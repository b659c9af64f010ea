"""Conformance: every program in tests/programs runs to its end on the dummy platform and its
`postcond()` holds (each program checks one part of SEMANTICS §3-§4, see its first comment)."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.check import check_program
from gpp.report.text import render_text
from gpp.run.runner import RunOptions, RunOutcome, run_program
from gpp.runtime.events import encode
from gpp.runtime.executor import RunStatus
from tests.support.cli import run

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS_DIR = ROOT / "tests" / "programs"
PROGRAMS = sorted(PROGRAMS_DIR.glob("*.gpp"))


def _explain(outcome: RunOutcome) -> str:
    """Diagnostics as the terminal shows them, and the end of the trace."""
    lines = [render_text(outcome.diagnostics)] if outcome.diagnostics else []
    records = outcome.recording.records[-15:] if outcome.recording is not None else []
    lines.extend(encode(r) for r in records)
    return "\n".join(lines)


def test_there_are_conformance_programs() -> None:
    assert len(PROGRAMS) >= 20


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_program_finishes_and_its_postcondition_holds(path: Path) -> None:
    outcome = run_program(path, RunOptions(record=True, timeout=10_000))
    assert not outcome.check.errors, _explain(outcome)
    assert outcome.result is not None, _explain(outcome)
    assert outcome.result.status is RunStatus.FINISHED, _explain(outcome)
    assert outcome.postcond is True, _explain(outcome)


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_program_is_documented_and_has_a_postcondition(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    assert text.startswith(f"// {path.name} — "), "the first line names the file and says what it checks"
    assert "bool function postcond()" in text


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_program_reads_as_written(path: Path) -> None:
    """No operator chain that golog++ would read differently: a postcondition such as
    `a & b == false & c` would otherwise hold for the wrong reason."""
    mixed = [d for d in check_program(path).diagnostics if d.code == "W0110"]
    assert not mixed, render_text(mixed)


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_scenario_named_by_a_program_exists(path: Path) -> None:
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("// scenario:"):
            assert (path.parent / line.split(":", 1)[1].strip()).is_file()


def _has_gpp_test() -> bool:
    return " test " in run("--help", cwd=ROOT).stdout


@pytest.mark.skipif(not _has_gpp_test(), reason="`gpp test` is not available yet")
def test_gpp_test_passes_on_the_conformance_programs() -> None:
    done = run("test", "tests/programs", cwd=ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
