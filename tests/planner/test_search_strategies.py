"""`search` with iterative deepening (gpp.planner.search.ITERATIVE_DEEPENING): a shortest
execution, the first in textual order among the shortest; none exactly when none exists; and
the depth-first step bound error pointing to it."""

from __future__ import annotations

from collections import deque
from pathlib import Path

import pytest
from hypothesis import given, settings

from gpp.check import check_text
from gpp.planner.problem import PlanningProblem
from gpp.planner.search import ITERATIVE_DEEPENING, STRATEGIES
from gpp.runtime.errors import GppRuntimeError
from gpp.syntax import ast
from gpp.syntax.walk import walk
from tests.support.budget import examples
from tests.support.cli import run
from tests.support.planner_worlds import PROPERTY, Case, cases, final_reachable, replay

COUNTER = """
number fluent n() { initially: () = 0; }
bool fluent done() { initially: () = false; }
action inc() { effect: n() = n() + 1; }
action jump() { effect: n() = 10; }
action wrap() { effect: done() = true; }
"""


def search_problem(text: str) -> PlanningProblem:
    from gpp.planner.problem import OfflineContext
    from gpp.runtime.compiled import CompiledProgram
    from gpp.runtime.semantics import EMPTY_FRAME, Code, Semantics
    from gpp.runtime.state import Activities, State

    result = check_text(text, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    program = CompiledProgram(result.model)
    sem = Semantics(program, OfflineContext(), planning=True)
    body = program.procedure("main")[1]
    assert body is not None
    search = next(n for n in walk(body) if isinstance(n, ast.Search))
    return PlanningProblem(sem, Code(search.body, EMPTY_FRAME), State(), Activities(), 0, lambda s: 0.0, search.span)


def test_iterative_deepening_finds_the_shortest_execution_where_depth_first_finds_the_first() -> None:
    pb = search_problem(COUNTER + "procedure main() { search while (n() < 10) choose { inc(); jump(); } }")
    assert pb.search(100).actions() == ["inc()"] * 10
    assert pb.search(100, ITERATIVE_DEEPENING).actions() == ["jump()"]


def test_iterative_deepening_among_the_shortest_takes_the_first_in_textual_order() -> None:
    pb = search_problem(COUNTER + "procedure main() { search { choose { jump(); inc(); } choose { inc(); wrap(); } } }")
    assert pb.search(10, ITERATIVE_DEEPENING).actions() == ["jump()", "inc()"]


def test_depth_first_runs_into_its_bound_on_an_endless_branch_and_suggests_iterative_deepening() -> None:
    pb = search_problem(COUNTER + "procedure main() { search while (!done()) choose { inc(); wrap(); } }")
    with pytest.raises(GppRuntimeError) as caught:
        pb.search(50)
    assert caught.value.message == "`search` exceeded its bound of 50 steps without finding an end"
    assert any("--search-strategy iterative-deepening" in note for note in caught.value.notes)
    plan = pb.search(50, ITERATIVE_DEEPENING)
    assert plan.actions() == ["wrap()"]


def test_iterative_deepening_reports_no_execution_on_a_finite_space_and_the_bound_on_an_endless_one() -> None:
    finite = search_problem(COUNTER + "procedure main() { search { while (n() < 3) inc(); test(false); } }")
    plan = finite.search(100, ITERATIVE_DEEPENING)
    assert not plan.feasible
    endless = search_problem(COUNTER + "procedure main() { search { while (true) inc(); } }")
    with pytest.raises(GppRuntimeError) as caught:
        endless.search(20, ITERATIVE_DEEPENING)
    assert caught.value.message == "`search` exceeded its bound of 20 steps without finding an end"
    assert not any("--search-strategy" in note for note in caught.value.notes)


def shortest(pb: PlanningProblem) -> int | None:
    """The fewest steps to a final configuration, breadth first."""
    start = (pb.prog, pb.state, pb.acts)
    seen, todo = {start}, deque([(start, 0)])
    while todo:
        (p, s, a), d = todo.popleft()
        if pb.sem.final(p, s, a):
            return d
        for q, step in pb.sem.trans(p, s, a):
            s2, a2 = pb.sem.apply(step, s, a)
            if (q, s2, a2) not in seen:
                seen.add((q, s2, a2))
                todo.append(((q, s2, a2), d + 1))
    return None


@given(cases(max_horizon=0, min_horizon=0))
@settings(PROPERTY, max_examples=examples(60))
def test_iterative_deepening_finds_an_executable_shortest_execution_exactly_when_one_exists(case: Case) -> None:
    pb = case.problem()
    try:
        plan = pb.search(10_000, ITERATIVE_DEEPENING)
    except GppRuntimeError as e:
        assert e.code != "R0010"
        return
    assert plan.feasible == final_reachable(pb)
    if plan.feasible:
        p, s, a, _, _ = replay(pb, plan.steps)
        assert pb.sem.final(p, s, a)
        assert len(plan.steps) == shortest(pb)


def test_gpp_run_takes_the_strategy_and_rejects_an_unknown_one(tmp_path: Path) -> None:
    program = tmp_path / "agent.gpp"
    program.write_text(COUNTER + "procedure main() { search while (n() < 10) choose { inc(); jump(); } }\n")
    trace = tmp_path / "trace.jsonl"
    options = ["run", "--quiet", "--trace", str(trace)]
    result = run(*options, "--search-strategy", ITERATIVE_DEEPENING, str(program))
    assert result.returncode == 0, result.stderr
    assert '"policy": ["jump()"]' in trace.read_text()
    result = run(*options, "--search-strategy", "widest", str(program))
    assert result.returncode == 2
    assert f"--search-strategy must be one of {', '.join(STRATEGIES)}, not `widest`" in result.stderr
