"""Made-up traces shared by the trace viewer's tests."""

from __future__ import annotations

from pathlib import Path

from gpp.runtime.events import (
    AssignEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
)


def stopped_run() -> list[TraceEvent]:
    """A made-up trace with what the executor does not write yet (a header, waits) and a run
    that stops on an error: two overlapping activities of one action, one still running, an
    infeasible replan, an assignment and a sensing result."""
    return [
        HeaderEvent(
            t=0,
            schema_version="1.0",
            gpp_version="0.1.0",
            program="agent.gpp",
            program_sha256="0" * 64,
            platform="dummy",
            seed=7,
            started="2025-01-01T12:00:00+00:00",
        ),
        StartEvent(t=0, action='say("hi")', id=1, mapped="speech", args={"text": "hi"}, at="agent.gpp:10:5"),
        StartEvent(t=0, action="go(kitchen)", id=2, mapped="/navigate", args={"to": {"symbol": "kitchen"}}, at=None),
        StartEvent(t=0.5, action='say("again")', id=3, mapped="speech", args={"text": "again"}, at="agent.gpp:11:5"),
        UpdateEvent(t=1, action='say("hi")', status="final", id=1, result=21.5),
        SenseEvent(t=1, action='say("hi")', fluent="temperature()", value=21.5),
        EndEvent(t=1, action='say("hi")', status="final", hook="call"),
        WaitingEvent(t=1, statement="test(door_open());", at="agent.gpp:12:5", condition="door_open()"),
        UpdateEvent(t=1.5, action='say("again")', status="failed", id=3, reason="no speaker"),
        ExogEvent(t=2, action="open_door()"),
        WaitingEvent(t=2, statement="test(door_open());", at="agent.gpp:12:5", condition="door_open()", resumed=True),
        AssignEvent(t=2, fluent="battery()", value=55, at="agent.gpp:13:5"),
        PlanEvent(
            t=2,
            kind="search",
            feasible=True,
            value=0,
            horizon=4,
            policy=("go(hall)",),
            nodes=7,
            cache_hits=1,
            pruned=0,
            reward_evaluations=0,
            seconds=0.002,
        ),
        ExogEvent(t=2.5, action="open_door()", precondition=False),
        AssignEvent(t=3, fluent="battery()", value=40, at="agent.gpp:13:5"),
        ReplanEvent(
            t=3,
            kind="solve",
            feasible=False,
            value=0,
            horizon=2,
            policy=(),
            nodes=3,
            cache_hits=0,
            pruned=0,
            reward_evaluations=4,
            seconds=0.001,
        ),
        ErrorEvent(t=4, code="R0002", message="an argument is out of its domain", at="agent.gpp:14:9"),
        CancelEvent(t=4, action="go(kitchen)", id=2, reason="the program ended"),
        FinishEvent(t=4, status="error", actions=3, failures=1, unhandled_failures=1, exog_events=2),
    ]


def live_panel_at_first_wait(records: list[TraceEvent], program: str) -> tuple[str, object]:
    """The live panel (gpp.run.view.LiveView, 120 columns, no colour) fed the records up to the
    first `waiting` one: its text, and the panel itself to feed on."""
    import io

    from rich.console import Console

    from gpp.run.view import LiveView

    first_wait = next(i for i, r in enumerate(records) if isinstance(r, WaitingEvent))
    live = LiveView(Console(file=io.StringIO(), width=120, color_system=None), program)
    for record in records[: first_wait + 1]:
        live(record)
    out = io.StringIO()
    Console(file=out, width=120, color_system=None).print(live.render())
    return out.getvalue(), live


def operator_trace(folder: Path) -> Path:
    """The trace of a console run (tests/programs/exog_events.gpp, waiting for Start) in which an
    operator through a hub opened the back door (an exogenous event) and one at 127.0.0.1 then
    gave Start."""
    from gpp.check import check_program
    from gpp.console.control import ConsoleControl, Request, ground
    from gpp.console.state import ConsoleState
    from gpp.model.symbols import SymbolKind
    from gpp.run.runner import RunOptions, run_program

    program = Path(__file__).resolve().parents[1] / "programs" / "exog_events.gpp"
    checked = check_program(program)
    control = ConsoleControl(ConsoleState(), checked.model, wait=True)
    door = ground(checked.model, "door_opened", {"d": "back"}, SymbolKind.EXOG_ACTION)
    control.request(Request("exog", door, client="10.0.0.7 via 127.0.0.1"))
    control.request(Request("start", client="127.0.0.1"))
    trace = folder / "operator.jsonl"
    run_program(program, RunOptions(trace=trace, control=control), checked=checked)
    return trace
