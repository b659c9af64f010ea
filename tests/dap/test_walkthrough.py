"""docs/debugging.md's walkthrough works as written: the tutorial's fetch agent, its lines as
the page shows them, and each stop, value and message the page says."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.dap.programs import tutorial_program
from tests.support.dap_client import ROOT, DapClient

PAGE = ROOT / "docs" / "debugging.md"


@pytest.fixture
def fetch(programs: Path) -> Path:
    return tutorial_program(programs, "take_sample();", "fetch.gpp")


def plan_step(dap: DapClient) -> str:
    return next(v["value"] for v in dap.scope("Plan") if v["name"] == "step")


def test_the_page_shows_the_lines_of_the_tutorials_agent(fetch: Path) -> None:
    excerpt = PAGE.read_text(encoding="utf-8").split("```text\n", 1)[1].split("```", 1)[0]
    lines = fetch.read_text(encoding="utf-8").splitlines()
    shown = [re.fullmatch(r"(\d+)  (.*)", row) for row in excerpt.splitlines()]
    assert shown and all(shown)
    for row in shown:
        assert row is not None
        assert lines[int(row.group(1)) - 1] == row.group(2)


def test_the_walkthrough_stops_steps_and_shows_what_the_page_says(dap: DapClient, fetch: Path) -> None:
    dap.start({"program": "fetch.gpp", "stopOnEntry": True}, {str(fetch): [{"line": 46}]})
    # Stop on entry.
    assert dap.stopped()["reason"] == "entry"
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [("main()", 39)]
    # A breakpoint in solve's body: after the failed drive, the re-plan and the second drive.
    dap.ok("continue", {"threadId": 1})
    assert dap.stopped()["reason"] == "breakpoint"
    assert dap.top()["line"] == 46
    assert dap.evaluate("context_time()")["result"] == "5.0"
    # The fluents view.
    scopes = [s["name"] for s in dap.ok("scopes", {"frameId": 0})["scopes"]]
    assert scopes == ["Arguments", "Locals", "Fluents", "Activities", "Plan", "Exogenous events"]
    fluents = {v["name"]: v["value"] for v in dap.scope("Fluents")}
    assert fluents == {"failures()": "1", "robot_at()": "lab", "has_sample()": "false"}
    plan = dap.scope("Plan")
    assert plan_step(dap) == "4 of 6"
    assert next(v["value"] for v in plan if v["name"].startswith("→")) == "take_sample()"
    # Hover and the debug console.
    assert dap.evaluate("robot_at() == lab & !has_sample()", context="hover")["result"] == "true"
    assert dap.error("evaluate", {"expression": "robot_at() == lb", "frameId": 0}) == (
        "column 15: unknown name `lb`: not a variable, parameter or symbol"
    )
    # Stepping over take_sample() to the drive back.
    dap.ok("next", {"threadId": 1})
    assert dap.stopped()["reason"] == "step"
    assert dap.top()["line"] == 43
    assert [(v["name"], v["value"]) for v in dap.scope("Locals")] == [("r", "office")]
    assert plan_step(dap) == "5 of 6"
    # A condition that does not check.
    placed = dap.ok(
        "setBreakpoints", {"source": {"path": str(fetch)}, "breakpoints": [{"line": 43, "condition": "r == ofice"}]}
    )
    assert placed["breakpoints"][0]["verified"] is False
    assert placed["breakpoints"][0]["message"] == (
        "the condition does not check: column 6: unknown name `ofice`: not a variable, parameter or symbol"
    )
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0


def test_the_walkthroughs_conditional_and_exception_breakpoints(dap: DapClient, fetch: Path) -> None:
    dap.start({"program": "fetch.gpp"}, {str(fetch): [{"line": 43, "condition": "r == office"}]}, exceptions=["failed"])
    # Action failed: before the on_fail handler runs.
    stop = dap.stopped()
    assert (stop["reason"], stop["description"]) == ("exception", "go(lab) failed: scenario")
    assert [v["value"] for v in dap.scope("Activities")] == ["failed, started at 0.000 s"]
    assert dap.evaluate("failures()")["result"] == "0"
    # r == office: only before the drive back.
    dap.ok("continue", {"threadId": 1})
    assert dap.stopped()["reason"] == "breakpoint"
    assert [(v["name"], v["value"]) for v in dap.scope("Locals")] == [("r", "office")]
    assert dap.evaluate("has_sample()")["result"] == "true"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0
    assert [e["body"]["reason"] for e in dap.seen if e.get("event") == "stopped"] == ["exception", "breakpoint"]
