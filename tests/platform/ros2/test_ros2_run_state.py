"""The state the ros2 platform publishes on `~/state` (gpp.platform.ros2.live.RunState), told
only the run's records, agrees with the executor's own account of where the run is: the
snapshot that starts each part of a split trace (the activities started and not consumed,
what the program waits for). Needs no ROS."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gpp.platform.ros2.live import RunState
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import FinishEvent, SnapshotEvent, decode
from gpp.runtime.trace import TraceSplit, trace_parts
from gpp.traceview.model import load_trace

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize(
    ("program", "options"),
    [
        ("examples/durative.gpp", RunOptions()),
        ("examples/blocksworld_faults.gpp", RunOptions(platform="sim")),
        (
            "tests/planner_scenarios/blocks.gpp",
            RunOptions(platform_options={"scenario": ROOT / "tests/planner_scenarios/knocked.toml"}),
        ),
    ],
    ids=["durative", "sim", "replan"],
)
def test_the_state_agrees_with_the_snapshot_of_every_part(tmp_path: Path, program: str, options: RunOptions) -> None:
    trace = tmp_path / "run.jsonl"
    options.trace = trace
    options.trace_split = TraceSplit(max_seconds=0.5)
    outcome = run_program(ROOT / program, options)
    assert outcome.result is not None
    state = RunState()
    compared = 0
    for number, part in enumerate(trace_parts(trace)):
        events = [decode(line) for line in part.read_text(encoding="utf-8").splitlines()]
        if number > 0:
            snapshot = events[1]
            assert isinstance(snapshot, SnapshotEvent)
            found = state.as_json()
            assert found["status"] == "running"
            shown = [{"action": a["action"], "id": a["id"], "status": a["status"]} for a in found["activities"]]
            assert sorted(shown, key=lambda a: a["id"]) == sorted(snapshot.activities, key=lambda a: a["id"])
            assert found["waiting"] == snapshot.waiting
            compared += bool(snapshot.activities) + bool(snapshot.waiting)
            events = events[2:]
        for event in events:
            state.apply(event)
    assert compared > 0  # the parts begin where something runs or the program waits
    final = json.loads(json.dumps(state.as_json()))
    finish = events[-1]
    assert isinstance(finish, FinishEvent)
    assert final["status"] == finish.status and final["waiting"] is None
    assert final["records"] == len(load_trace(trace).events)  # the run's records, not the parts' own
