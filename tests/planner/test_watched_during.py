"""A watched `during (a) until (e)` inside `solve` plans as its activity alone (while planning
the activity ends at once, before the condition or the body could matter), the same in the
production planner and the reference. Its execution online: tests/runtime/test_during_until.py."""

from __future__ import annotations

from gpp.check import check_text
from gpp.planner.problem import first_solve
from tests.support.planner_worlds import outcome

WATCHED = """
symbol domain block = {a, b}
number fluent n() { initially: () = 0; }
bool fluent stop() { initially: () = false; }
action act(block x) { effect: n() = n() + 1; }
number function reward() = n()
procedure main() {
    solve(4, reward()) while (n() < 2) pick (block x) during (act(x)) until (stop() | n() > 5) {
        stop() = true;
    } on_cancel n() = 0;
}
"""


def test_a_watched_during_plans_as_its_activity_alone_in_every_planner() -> None:
    result = check_text(WATCHED, lint=False)
    assert result.errors == 0
    problem = first_solve(result.model)
    production, reference = problem.production(), problem.reference()
    assert outcome(production) == outcome(reference)
    # The body is left when the activity ends, which while planning is at once: `stop()` is
    # never set, and each `during` is one costed step.
    assert [step.describe() for _, step, _ in production.steps] == ["start(act(a))", "end(act(a))"] * 2
    assert (production.value, production.cost) == (0 + 1 + 2, 2)  # R(s0) and after each end
