"""`gpp dap` on the simulator: the tutorial's tower agent (docs/tutorial.md, chapter 5) stopped
before it stacks, its sensed fluents looked at, a step, and the run to its end."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.dap.programs import tutorial_program
from tests.support.dap_client import DapClient, line_of


@pytest.mark.slow
def test_a_breakpoint_stepping_and_evaluate_on_the_sim(dap: DapClient, programs: Path) -> None:
    tower = tutorial_program(programs, "if (clear(t3)) stack(a, t3);", "tower.gpp")
    stack = line_of(tower, "if (clear(t3)) stack(a, t3);")
    dap.start({"program": str(tower), "platform": "sim"}, {str(tower): [{"line": stack, "condition": "clear(t3)"}]})
    stop = dap.stopped()
    assert (stop["reason"], dap.top()["line"]) == ("breakpoint", stack)
    # What the sensing found out, as the program sees it.
    assert dap.evaluate("loc(a) != t3 & clear(t3)")["result"] == "true"
    fluents = {v["name"]: v for v in dap.scope("Fluents")}
    assert fluents["robot_at()"]["value"] == "table"
    locations = dap.ok("variables", {"variablesReference": fluents["loc(x)"]["variablesReference"]})["variables"]
    assert {v["name"] for v in locations} >= {"loc(a)", "loc(c)"}
    # The sim's clock stands still while the run is stopped.
    before = dap.evaluate("context_time()")["result"]
    assert dap.evaluate("context_time()")["result"] == before
    dap.ok("next", {"threadId": 1})
    assert dap.stopped()["reason"] == "step"
    assert dap.top()["line"] == line_of(tower, "get_block_pose(a);", occurrence=2)
    assert dap.evaluate("loc(a)")["result"] == "t3"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0
