"""The run's own console view (gpp.console.state.ConsoleState) on real runs, without a server:
the world read from the executor (fluents, activities with their start), the notes of what it
does not keep (a plan's step, failures, the finish), and what the view keeps of a run: the
latest records only, however long the run."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gpp.check import check_program
from gpp.console.control import ConsoleControl
from gpp.console.state import LATEST_KEPT, ConsoleState
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import AssignEvent, EndEvent, StartEvent, TraceEvent
from gpp.runtime.trace import KindListener

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"


def run_with_view(
    path: Path, kind: type, when: Any, platform_options: dict[str, str] | None = None
) -> tuple[ConsoleState, list[dict[str, Any]]]:
    """Run `path` with a console view attached; the views taken (in the run's own thread, so at
    a known point) at each record of `kind` for which `when(record)` holds."""
    checked = check_program(path)
    state = ConsoleState()
    options = RunOptions(platform="dummy", control=ConsoleControl(state, checked.model, wait=False))
    if platform_options:
        options.platform_options = dict(platform_options)
    taken: list[dict[str, Any]] = []

    def look(event: TraceEvent) -> None:
        if when(event):
            taken.append(state.view(clock=event.t + 0.5))

    outcome = run_program(path, options, [*state.listeners(), KindListener(frozenset({kind}), look)], checked=checked)
    assert outcome.ok, outcome.diagnostics
    return state, taken


def by_name(view: dict[str, Any]) -> dict[str, str]:
    return {f["name"]: f["value"] for f in view["fluents"]}


def test_the_view_reads_the_world_and_the_running_activities_from_the_run() -> None:
    # during_on_fail: the first drive to the kitchen runs from 0 until it fails at 2; while it
    # runs, its `during` body says so (the assignment the view is taken at).
    state, taken = run_with_view(
        PROGRAMS / "during_on_fail.gpp",
        AssignEvent,
        lambda e: e.fluent == "said()" and "driving" in str(e.value),
        {"scenario": str(PROGRAMS / "during_on_fail.toml")},
    )
    first = taken[0]
    assert by_name(first)["at()"] == "hall" and by_name(first)["said()"] == '["driving to kitchen"]'
    assert [(a["action"], a["status"], a["started"], a["elapsed"], a["args"]) for a in first["activities"]] == [
        ("drive(kitchen)", "running", 0.0, 0.5, {"r": "kitchen"})
    ]
    assert first["status"] == "running" and first["agent"]["platform"] == "dummy"
    end = state.view()
    assert end["status"] == "finished" and end["activities"] == [] and end["waiting"] is None
    assert by_name(end)["at()"] == "kitchen" and by_name(end)["failed()"] == "1"
    assert [(f["action"], f["t"]) for f in end["failures"]] == [("drive(kitchen)", 2.0), ("beep()", 3.0)]
    assert end["counts"] == {"actions": 4, "failures": 2, "exog_events": 0}
    assert end["records"] == state.records > 0
    assert any(line["text"].startswith("end") for line in end["events"])


def test_a_plans_step_follows_the_starts_of_its_actions() -> None:
    state, taken = run_with_view(PROGRAMS / "solve.gpp", EndEvent, lambda e: True)
    policy = taken[0]["plan"]["policy"]
    assert policy[-1] == "drop()" and taken[0]["plan"]["feasible"] is True
    # At each end of the policy's actions, the step counts its start.
    assert [v["plan"]["step"] for v in taken[: len(policy)]] == list(range(1, len(policy) + 1))
    # The next plan begins with an assignment: its action's start is its second step.
    assert taken[-1]["plan"]["policy"] == ["planned_steps() = 1", "go(a)"] and taken[-1]["plan"]["step"] == 2
    # The starts are told only while a plan is followed: after its last step, no more.
    assert state._following is False and StartEvent not in state._run.trace.by_kind  # type: ignore[union-attr]


def test_a_value_is_marked_changed_when_a_later_view_sees_it_new(tmp_path: Path) -> None:
    path = tmp_path / "count.gpp"
    path.write_text(
        """number fluent n() {
initially:
    () = 0;
}

string fluent note(string key) {
initially:
    (key) = "";
}

action tick() {
effect:
    n() = n() + 1;
duration: [1, 1]
}

procedure main() {
    tick();
    note("first") = "seen";
    tick();
    tick();
}
""",
        encoding="utf-8",
    )
    _, taken = run_with_view(path, StartEvent, lambda e: True)
    before, after, last = taken
    assert by_name(before) == {"n()": "0"}  # note(key) has an infinite type: shown once set
    assert {"name": "n()", "value": "1", "changed": 1.0} in after["fluents"]
    assert {"name": 'note("first")', "value": '"seen"', "changed": None} in after["fluents"]
    assert {"name": "n()", "value": "2", "changed": 2.0} in last["fluents"]


def test_the_view_keeps_the_latest_records_only(tmp_path: Path) -> None:
    """However many records a run makes, its console keeps the same: the ring of the latest."""
    program = """number fluent n() {
initially:
    () = 0;
}

action tick() {
effect:
    n() = n() + 1;
duration: [0.01, 0.01]
}

procedure main() {
    while (n() < %d)
        tick();
}
"""

    def kept(turns: int) -> tuple[int, int, int]:
        path = tmp_path / f"ticks{turns}.gpp"
        path.write_text(program % turns, encoding="utf-8")
        state, _ = run_with_view(path, StartEvent, lambda e: False)
        view = state.view()
        assert by_name(view)["n()"] == str(turns) and view["records"] == 3 * turns + 2
        return len(state._latest), len(state._shown), len(state._extra), len(state._cancelling)

    assert kept(100) == kept(3000) == (LATEST_KEPT, 1, 0, 0)


def test_a_stream_still_sending_is_not_ready_for_a_new_view() -> None:
    """A slow browser's stream, still sending the last view, does not count as waiting for one,
    so the server makes no view for it; it sends the newest once it can, never a queue."""
    import asyncio

    from gpp.console.server import Channel

    async def scenario() -> list[object]:
        channel = Channel()
        channel.publish('{"n": 1}')
        stream = channel.stream()
        seen: list[object] = [await anext(stream)]  # the first view, sent at once
        seen.append((channel.streams, channel.ready))  # not asking for the next: still "sending"
        asking = asyncio.ensure_future(anext(stream))
        await asyncio.sleep(0.01)
        seen.append((channel.streams, channel.ready))  # now waiting for a new view
        channel.publish('{"n": 2}')
        channel.publish('{"n": 3}')
        seen.append(await asking)
        seen.append(channel.ready)
        channel.close('{"n": 4}')
        seen.append([chunk async for chunk in stream])
        seen.append(channel.streams)
        return seen

    assert asyncio.run(scenario()) == [
        'data: {"n": 1}\n\n',
        (1, 0),
        (1, 1),
        'data: {"n": 3}\n\n',
        0,
        ['data: {"n": 4}\n\n'],
        0,
    ]
