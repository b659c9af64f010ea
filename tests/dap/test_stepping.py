"""Stepping through a run with `gpp dap`: in, over, out, pause; inside `solve` the steps follow
the executed plan, and the planner's look-ahead never stops at a breakpoint."""

from __future__ import annotations

from pathlib import Path

from tests.support.dap_client import DapClient, line_of

ERRANDS_ARGS = {"first": "kitchen", "rounds": 2}


def step(dap: DapClient, how: str) -> tuple[str, int, int]:
    """Step, and where the run stopped: the innermost call, its line, the depth of the stack."""
    dap.ok(how, {"threadId": 1})
    assert dap.stopped()["reason"] == "step"
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    return frames[0]["name"], frames[0]["line"], len(frames)


def test_step_in_over_and_out_of_procedure_calls(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.start({"program": str(program), "args": ERRANDS_ARGS, "stopOnEntry": True})
    assert dap.stopped()["reason"] == "entry"
    at = {
        text: line_of(program, text)
        for text in ("go(r);", "push_back", "pick_up();", "collect(lab);", "pose().x", "go(office);")
    }
    # On entry: at main's first transition, inside the call it begins (a call is no
    # transition of its own).
    assert (dap.top()["name"], dap.top()["line"]) == ("collect(kitchen)", at["go(r);"])
    # Over the call of an action: its end is no step of its own.
    assert step(dap, "next") == ("collect(kitchen)", at["push_back"], 2)
    assert step(dap, "next") == ("collect(kitchen)", at["pick_up();"], 2)
    assert step(dap, "next") == ("collect(kitchen)", at["pick_up();"], 2)
    assert dap.evaluate("cups(r)")["result"] == "1"
    # Out: at the first transition of main's own (the next call's are inside that call).
    assert step(dap, "stepOut") == ("main(kitchen, 2)", at["pose().x"], 1)
    assert dap.evaluate("carried()")["result"] == "3"
    assert step(dap, "next") == ("main(kitchen, 2)", at["go(office);"], 1)
    dap.ok("next", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0


def test_a_breakpoint_on_a_call_stops_inside_the_callee(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.start(
        {"program": str(program), "args": ERRANDS_ARGS}, {str(program): [{"line": line_of(program, "collect(lab);")}]}
    )
    assert dap.stopped()["reason"] == "breakpoint"
    # A breakpoint on a call stops at the call's first transition, inside the callee, with
    # the caller at the call: the robot is in the kitchen, so collect(lab) begins with go(lab).
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("collect(lab)", line_of(program, "go(r);")),
        ("main(kitchen, 2)", line_of(program, "collect(lab);")),
    ]
    assert dap.evaluate("robot_at() != r")["result"] == "true"
    assert step(dap, "stepIn") == ("collect(lab)", line_of(program, "push_back"), 2)


def test_pause_stops_a_running_agent_at_its_next_transition(dap: DapClient, programs: Path) -> None:
    program = programs / "forever.gpp"
    dap.start({"program": str(program)})
    dap.ok("pause", {"threadId": 1})
    stop = dap.stopped()
    assert stop["reason"] == "pause"
    assert dap.top()["line"] in (line_of(program, "while (true)"), line_of(program, "tick();"))
    first = int(dap.evaluate("ticks()")["result"])
    # While stopped the virtual clock stands still and nothing happens.
    assert dap.evaluate("ticks()")["result"] == str(first)
    dap.ok("continue", {"threadId": 1})
    dap.ok("pause", {"threadId": 1})
    assert dap.stopped()["reason"] == "pause"
    assert int(dap.evaluate("ticks()")["result"]) > first
    # Pausing a stopped run changes nothing.
    dap.ok("pause", {"threadId": 1})
    assert dap.evaluate("ticks() >= 0")["result"] == "true"


def test_stepping_in_solve_follows_the_executed_plan(dap: DapClient, programs: Path) -> None:
    program = programs / "planned.gpp"
    slow, fast = line_of(program, "slow();"), line_of(program, "{ fast(); tidy(); }")
    # The planner looks at slow() (look-ahead) but the run never executes it: no stop there.
    dap.start({"program": str(program), "stopOnEntry": True}, {str(program): [{"line": slow}, {"line": fast}]})
    assert dap.stopped()["reason"] == "entry"
    assert dap.top()["line"] == line_of(program, "solve(2, reward())")
    # Planning is one transition: the next stop is the plan's first step.
    dap.ok("next", {"threadId": 1})
    stop = dap.stopped()
    assert (stop["reason"], dap.top()["line"]) == ("breakpoint", fast)
    plan = [(v["name"], v["value"]) for v in dap.scope("Plan")]
    assert plan[:3] == [("kind", "solve"), ("step", "1 of 2"), ("horizon", "2")]
    assert [value for _, value in plan[3:]] == ["fast()", "tidy()"]
    assert plan[3][0].startswith("→")
    assert step(dap, "next") == ("main()", fast, 1)
    assert [v["value"] for v in dap.scope("Plan")][1] == "2 of 2"
    assert dap.evaluate("cost()")["result"] == "1"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0
    assert [e["body"]["reason"] for e in dap.seen if e.get("event") == "stopped"] == ["entry", "breakpoint", "step"]
