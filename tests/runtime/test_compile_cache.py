"""The cache of compiled generated source (gpp.runtime.codegen.CompileCache): a planning that
writes the same source as an earlier one compiles nothing, the constants of each build are
its own, and different source is compiled anew; and the `Successors` of a semantics object,
reused by its later plannings (gpp.planner.fast.successors.successors_of)."""

from __future__ import annotations

import pytest

from bench.planner import problem_of, tower_program
from gpp.planner.fast.successors import successors_of
from gpp.planner.problem import PlanningProblem
from gpp.runtime import codegen
from gpp.runtime.codegen import CompileCache, Unit, build_units


@pytest.fixture
def cache(monkeypatch: pytest.MonkeyPatch) -> CompileCache:
    fresh = CompileCache()
    monkeypatch.setattr(codegen, "COMPILE_CACHE", fresh)
    return fresh


def adder(name: str, constant: object) -> Unit:
    unit = Unit(name, "x")
    unit.emit(0, f"return x + {unit.const(constant, note='the addend')}")
    return unit


def test_the_same_source_is_compiled_once_and_each_build_gets_its_own_constants(cache: CompileCache) -> None:
    first = build_units([adder("f", 1)])[0]
    second = build_units([adder("f", 10)])[0]  # the same text: the constant is an argument
    assert (cache.misses, cache.hits, len(cache)) == (1, 1, 1)
    assert (first(5), second(5)) == (6, 15)
    other = build_units([adder("g", 1)])[0]  # another name, another text
    assert (cache.misses, cache.hits, len(cache)) == (2, 1, 2)
    assert other(1) == 2


def test_the_least_recently_used_source_goes_first() -> None:
    cache = CompileCache(limit=2)
    for name in ("a", "b", "a", "c", "b"):
        unit = adder(name, 1)
        unit.write()
        cache.factories([unit])
    # a, b compiled; a hit (now the most recent); c evicts b; b compiled again (evicts a).
    assert (cache.misses, cache.hits, len(cache)) == (4, 1, 2)


def plan_of(text: str) -> tuple[bool, float, list[str], int]:
    pb: PlanningProblem = problem_of(text)
    plan = pb.production(prune=False)
    return plan.feasible, plan.value, plan.actions(), plan.stats.nodes


def test_planning_a_program_again_compiles_nothing_and_plans_alike(cache: CompileCache) -> None:
    text = tower_program(4, 8)
    first = plan_of(text)
    compiled = cache.misses
    assert compiled > 0 and cache.hits == 0
    again = plan_of(text)  # checked anew: other model objects, the same source
    assert cache.misses == compiled
    assert cache.hits == compiled
    assert again == first
    assert first[:3] == (True, 96.0, ["stack(a,table)", "stack(b,a)", "stack(c,b)", "stack(d,c)"])


def test_a_program_that_differs_in_a_constant_plans_with_its_own_constant(cache: CompileCache) -> None:
    text = tower_program(3, 6)
    cheaper = text.replace("if (goal()) 100 else -1", "if (goal()) 40 else -7")
    assert cheaper != text
    assert plan_of(text)[:2] == (True, 97.0)
    assert plan_of(cheaper)[:2] == (True, 40.0 - 7 * 3)  # R(s0) and two moves: -7 each
    assert plan_of(text)[:2] == (True, 97.0)


def test_another_program_is_compiled_anew(cache: CompileCache) -> None:
    plan_of(tower_program(3, 6))
    compiled = cache.misses
    plan_of(tower_program(4, 6))  # more blocks: other source
    assert cache.misses > compiled


def test_the_same_problem_planned_again_reuses_what_its_first_planning_generated(cache: CompileCache) -> None:
    pb = problem_of(tower_program(4, 8))
    first = pb.production(prune=False)
    generated = list(successors_of(pb.sem).sources)
    assert any("def trans_" in source for source in generated)
    built = cache.misses + cache.hits
    again = pb.production(prune=False)
    assert cache.misses + cache.hits == built  # nothing written or compiled again
    assert successors_of(pb.sem).sources == generated
    assert (again.feasible, again.value, again.steps, again.stats.nodes) == (
        first.feasible,
        first.value,
        first.steps,
        first.stats.nodes,
    )


def test_another_semantics_object_gets_its_own_successors() -> None:
    pb = problem_of(tower_program(3, 6))
    other = pb.sem.with_context(pb.sem.ctx, True)  # another context in a real run (online)
    assert successors_of(pb.sem) is successors_of(pb.sem)
    assert successors_of(other) is not successors_of(pb.sem)
    assert successors_of(pb.sem, generate=False) is not successors_of(pb.sem)
    assert successors_of(pb.sem, generate=False).generate is False
