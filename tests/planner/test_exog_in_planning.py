"""While `solve` plans, each ground exogenous function is asked of the platform once per plan
(on a robot each question is a service call), and the plan uses that one answer throughout."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import pytest

from gpp.check import check_text
from gpp.model.types import Sym, Type
from gpp.planner.policy import OncePerPlan, PolicyPlanner
from gpp.platform.base import Activity
from gpp.platform.dummy import DummyPlatform, Scenario
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.contract import program_interface
from gpp.runtime.events import PlanEvent
from gpp.runtime.executor import Executor, RunStatus
from gpp.runtime.trace import Recording, Trace
from gpp.runtime.values import Value

PROGRAM = """
symbol domain Room = {hall, kitchen, office}
Room fluent at() { initially: () = hall; }
number exog_function temperature(Room r);
action go(Room r) { precondition: at() != r & temperature(r) < 25 effect: at() = r; }
number function reward() = if (at() == office) 10 - temperature(office) else 0 - temperature(at())
procedure main() {
    solve(3, reward()) while (at() != office) pick (Room r) go(r);
}
bool function postcond() = at() == office
"""


class Counting(DummyPlatform):
    """A dummy that counts the questions it is asked before the first activity starts (that
    is, while the program plans)."""

    def __init__(self, scenario: Scenario) -> None:
        super().__init__(scenario)
        self.asked: list[str] = []
        self.started = False

    def exog_function(
        self, name: str, args: Mapping[str, Value], return_type: Type, activity: Activity | None
    ) -> Value:
        if not self.started:
            room = args["r"]
            self.asked.append(room.name if isinstance(room, Sym) else str(room))
        return super().exog_function(name, args, return_type, activity)

    def start(self, activity: Activity) -> None:
        self.started = True
        super().start(activity)


SCENARIO = {
    "exog_function": [
        {"name": "temperature", "args": {"r": "hall"}, "value": 20},
        {"name": "temperature", "args": {"r": "kitchen"}, "value": 30},
        {"name": "temperature", "args": {"r": "office"}, "value": 21},
    ]
}


def _plan(tmp_path: Path) -> tuple[Counting, PlanEvent]:
    check = check_text(PROGRAM, tmp_path / "p.gpp", lint=False)
    assert not check.errors, [d.message for d in check.diagnostics]
    platform = Counting(Scenario.from_data(SCENARIO))
    program = CompiledProgram(check.model)
    trace = Recording()
    executor = Executor(program, platform, Trace(listeners=[trace]), timeout=100, planner=PolicyPlanner())
    assert platform.attach(program_interface(program)) == []
    result = executor.run()
    assert result.status is RunStatus.FINISHED, result.diagnostics
    [plan] = trace.of(PlanEvent)
    assert plan.feasible and plan.policy == ("go(office)",)
    return platform, plan


def test_one_plan_asks_each_ground_exogenous_function_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    platform, _ = _plan(tmp_path)
    # The plan asked about each room once; then the planned step was checked against the world
    # as it is (the step's `pick` and precondition, asked again) before it started.
    assert sorted(platform.asked[:3]) == ["hall", "kitchen", "office"]
    assert platform.asked[3:] == ["kitchen", "office"]
    # Without the one-question rule the planner would have asked again in every branch.
    monkeypatch.setattr(
        OncePerPlan, "exog_function", lambda self, name, args, t, span: self.ctx.exog_function(name, args, t, span)
    )
    uncached, _ = _plan(tmp_path)
    assert len(uncached.asked) > len(platform.asked)
