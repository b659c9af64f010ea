"""A long `solve` reports its progress (nodes, configurations met, best value so far, time),
the run view shows it, and Ctrl-C (SIGINT) stops `gpp run` cleanly while it plans."""

from __future__ import annotations

import itertools
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from bench.planner import tower_program as tower
from gpp.check import check_text
from gpp.planner.dp import Progress, solve_plan
from gpp.planner.problem import first_solve

ROOT = Path(__file__).resolve().parents[2]


def test_progress_reports_nodes_configurations_best_value_and_time_as_planning_goes_on() -> None:
    result = check_text(tower(4, 10, twice=True), lint=False)
    assert result.errors == 0
    pb = first_solve(result.model)
    reports: list[Progress] = []
    plan = solve_plan(pb.sem, pb.prog, pb.state, pb.acts, pb.horizon, pb.reward, pb.span, reports.append, 0.0)
    quiet = first_solve(check_text(tower(4, 10, twice=True), lint=False).model).production(prune=False)
    assert (plan.value, plan.actions(), plan.stats.nodes) == (quiet.value, quiet.actions(), quiet.stats.nodes)
    assert len(reports) == plan.stats.nodes // 128
    assert [r.nodes for r in reports] == [128 * (i + 1) for i in range(len(reports))]
    assert all(a.memo <= b.memo and a.seconds <= b.seconds for a, b in itertools.pairwise(reports))
    # None until the first copy has its plan, then the best value found so far.
    best = [r.best for r in reports]
    assert best[0] is None and best[-1] == plan.value == 96.0
    assert best.index(96.0) == best.count(None)


@pytest.mark.slow
def test_ctrl_c_while_planning_stops_gpp_run_with_exit_code_130_and_a_complete_trace(tmp_path: Path) -> None:
    program = tmp_path / "tower.gpp"
    # Two copies of the loop: no goal-loop bound, so branch and bound (gpp.planner.bounds)
    # cannot cut the planning short and it runs well past the first second.
    program.write_text(tower(7, 14, twice=True))
    trace = tmp_path / "trace.jsonl"
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR", "GPP_DEBUG")}
    process = subprocess.Popen(
        [sys.executable, "-m", "gpp", "run", "--trace", str(trace), str(program)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()  # the first progress line, after a second of planning
        assert line.strip().startswith("planning: "), line
        assert " nodes, " in line and " configurations, best value " in line
        process.send_signal(signal.SIGINT)
        out, _ = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 130
    assert "tower.gpp on dummy: interrupted" in out
    events = [json.loads(x) for x in trace.read_text().splitlines()]
    assert [e["event"] for e in events] == ["header", "error", "finish"]
    assert events[1]["message"] == "interrupted"
    assert events[2]["status"] == "interrupted"
