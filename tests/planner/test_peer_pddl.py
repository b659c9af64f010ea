"""The blocksworld instances of the planner bench (bench/blocksworld.py) as PDDL for Fast
Downward: the domain and the problem read back with their objects, start and goal; a plan in
a PDDL planner's format is read and checked against the instance; and where Fast Downward is
installed (the `bench` extra; `make test` never installs it) its plan has the length of gpp's."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest

from bench.blocksworld import (
    PDDL_DOMAIN,
    Instance,
    moves_of_pddl_plan,
    pddl_problem,
    program,
    random_instance,
    reaches_goal,
    tower,
)
from bench.peers import fast_downward, run_fast_downward
from gpp.check import check_text
from gpp.planner.problem import first_solve

SExpr = str | list["SExpr"]

# examples/blocks_planning.gpp: a on c, c on b, b on the table; to be c on b on a.
EXAMPLE = Instance("example", ("a", "b", "c"), ("c", "table", "b"), ("table", "a", "b"))


def read_sexpr(text: str) -> SExpr:
    """The one s-expression of `text` (PDDL's syntax, `;` comments), atoms lower-cased."""
    tokens = text.replace("(", " ( ").replace(")", " ) ").split()
    stack: list[list[SExpr]] = [[]]
    for token in tokens:
        if token == "(":
            stack.append([])
        elif token == ")":
            done = stack.pop()
            stack[-1].append(done)
        else:
            stack[-1].append(token.lower())
    assert len(stack) == 1 and len(stack[0]) == 1, "unbalanced parentheses or more than one expression"
    return stack[0][0]


def section(expr: SExpr, key: str) -> list[SExpr]:
    assert isinstance(expr, list)
    found = [part for part in expr if isinstance(part, list) and part and part[0] == key]
    assert len(found) == 1, f"{key}: {len(found)} sections"
    return found[0][1:]


def facts(exprs: list[SExpr]) -> set[tuple[str, ...]]:
    out = set()
    for e in exprs:
        assert isinstance(e, list) and all(isinstance(a, str) for a in e), e
        out.add(tuple(str(a) for a in e))
    return out


def test_the_pddl_of_a_three_block_tower_has_its_objects_start_and_goal() -> None:
    problem = read_sexpr(pddl_problem(tower(3)))
    assert isinstance(problem, list) and problem[:2] == ["define", ["problem", "tower-3"]]
    assert section(problem, ":domain") == ["gpp-blocksworld"]
    assert section(problem, ":objects") == ["a", "b", "c", "-", "block"]
    start = {("on", "a", "b"), ("on", "b", "c"), ("on", "c", "table"), ("clear", "a")}
    assert facts(section(problem, ":init")) == start
    (goal,) = section(problem, ":goal")
    assert isinstance(goal, list) and goal[0] == "and"
    assert facts(goal[1:]) == {("on", "a", "table"), ("on", "b", "a"), ("on", "c", "b")}


def test_the_domain_has_the_two_moves_of_stack() -> None:
    domain = read_sexpr(PDDL_DOMAIN)
    assert isinstance(domain, list) and domain[:2] == ["define", ["domain", "gpp-blocksworld"]]
    assert section(domain, ":constants") == ["table", "-", "location"]
    actions = {str(a[1]): a for a in domain if isinstance(a, list) and a[0] == ":action"}
    assert set(actions) == {"stack", "stack-table"}
    assert actions["stack"][2:4] == [":parameters", ["?x", "-", "block", "?from", "-", "location", "?y", "-", "block"]]
    assert actions["stack-table"][2:4] == [":parameters", ["?x", "-", "block", "?from", "-", "block"]]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_random_instance_is_the_same_problem_in_pddl_and_in_golog(seed: int) -> None:
    instance = random_instance(4, seed)
    assert instance == random_instance(4, seed) and instance.start != instance.goal
    problem = read_sexpr(pddl_problem(instance))
    on_start = {("on", b, on) for b, on in zip(instance.blocks, instance.start, strict=True)}
    clear = {("clear", b) for b in instance.blocks if b not in instance.start}
    assert facts(section(problem, ":init")) == on_start | clear
    (goal,) = section(problem, ":goal")
    assert isinstance(goal, list)
    assert facts(goal[1:]) == {("on", b, on) for b, on in zip(instance.blocks, instance.goal, strict=True)}
    # gpp's plan for the golog++ program is legal from the same start and ends in the same goal.
    result = check_text(program(instance, 8), lint=False)
    assert result.errors == 0
    plan = first_solve(result.model).production()
    moves = [tuple(m[len("stack(") : -1].split(",")) for m in plan.actions()]
    assert reaches_goal(instance, [(b, to) for b, to in moves])


def test_a_plan_file_is_read_and_checked_against_the_instance() -> None:
    text = "(stack-table a c)\n(stack c b table)\n; cost = 2 (unit cost)\n(stack b table a)\n(stack c table b)\n"
    moves = moves_of_pddl_plan(text)
    assert moves == [("a", "table"), ("c", "table"), ("b", "a"), ("c", "b")]
    assert reaches_goal(EXAMPLE, moves)
    assert not reaches_goal(EXAMPLE, moves[:3])  # not at the goal yet
    assert not reaches_goal(EXAMPLE, moves[1:])  # c is under a: not clear
    with pytest.raises(ValueError, match="not an action"):
        moves_of_pddl_plan("(pick-up a)\n")


@pytest.mark.parametrize("instance", [tower(3), EXAMPLE], ids=["tower 3", "examples/blocks_planning.gpp"])
def test_fast_downward_plans_as_many_moves_as_gpp(instance: Instance) -> None:
    driver = fast_downward()
    if driver is None:
        pytest.skip("Fast Downward is not installed (the `bench` extra: make bench-peers installs it)")
    with tempfile.TemporaryDirectory() as folder:
        fd = run_fast_downward(driver, instance, Path(folder), limit=60)
    assert fd is not None and reaches_goal(instance, fd.moves)
    plan = first_solve(check_text(program(instance, 8), lint=False).model).production()
    assert len(fd.moves) == len(plan.actions()) == {"tower 3": 3, "example": 4}[instance.name]
