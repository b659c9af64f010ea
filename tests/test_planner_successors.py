"""The planner's specialised `final`/`trans` (gpp.planner.successors) against the semantics'
own (gpp.runtime.semantics), on every configuration reachable in random programs: the same
answer, the same successors in the same order, or the same error; and the specialised
effects of a ground action against the general evaluation."""

from __future__ import annotations

from collections import deque

from hypothesis import given, settings
from hypothesis import strategies as st
from test_planner_properties import PROPERTY, Case, cases, looping_cases, staggered_cases

from gpp.check import check_text
from gpp.planner.problem import first_solve
from gpp.planner.successors import Successors
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import DoStep, Prog, Semantics
from gpp.runtime.state import Activities, State

# Configurations compared per program (breadth-first from the start).
REACHED = 60


def answer(f: object, *args: object) -> object:
    try:
        return ("ok", f(*args))  # type: ignore[operator]
    except GppRuntimeError as e:
        return ("error", e.code, e.message, e.span)


def reachable(sem: Semantics, start: tuple[Prog, State, Activities]) -> list[tuple[Prog, State, Activities]]:
    seen, todo, out = {start}, deque([start]), []
    while todo and len(out) < REACHED:
        p, s, a = todo.popleft()
        out.append((p, s, a))
        try:
            successors = sem.trans(p, s, a)
        except GppRuntimeError:
            continue
        for q, step in successors:
            try:
                s2, a2 = sem.apply(step, s, a)
            except GppRuntimeError:
                continue
            if (q, s2, a2) not in seen:
                seen.add((q, s2, a2))
                todo.append((q, s2, a2))
    return out


def check_case(case: Case) -> None:
    pb = case.problem()
    sem = pb.sem
    fast = Successors(sem)
    # A fresh semantics for the general effects, so the one under test keeps its own caches.
    general = Semantics(sem.program, sem.ctx, planning=True)
    for p, s, a in reachable(sem, (pb.prog, pb.state, pb.acts)):
        # Twice: the second call uses the functions the first one built.
        for _ in range(2):
            assert answer(fast.final, p, s, a) == answer(sem.final, p, s, a)
            assert answer(fast.trans, p, s, a) == answer(sem.trans, p, s, a)
        for _, step in sem.trans(p, s, a):
            if isinstance(step, DoStep):
                assert answer(sem.effects, step.action, s) == answer(general._effects, step.action, s)


@given(st.one_of(cases(max_horizon=1), looping_cases(max_horizon=1), staggered_cases(max_horizon=1)))
@settings(PROPERTY, max_examples=120)
def test_specialised_final_and_trans_equal_the_semantics_on_every_reached_configuration(case: Case) -> None:
    check_case(case)


def test_a_pick_guard_over_a_tower_and_an_error_in_an_argument_stay_the_semantics_own() -> None:
    text = """
symbol domain block = {a, b, c}
symbol domain location = block | {table}
location fluent loc(block x) { initially: (a) = b; (b) = c; (c) = table; }
number fluent n() { initially: () = 0; }
action stack(block x, location y) {
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
    n() = n() + 1;
}
action bad(block x) {
precondition:
    n() != 2 | 1 / (n() - 2) > 0
}
number function reward() = n()
procedure main() {
    solve(3, reward()) while (n() < 3) choose { pick (block x) pick (location y) stack(x, y); pick (block x) bad(x); }
}
"""
    result = check_text(text, lint=False)
    assert result.errors == 0
    pb = first_solve(result.model)
    configurations = reachable(pb.sem, (pb.prog, pb.state, pb.acts))
    assert len(configurations) > 3
    fast = Successors(pb.sem)
    errors = 0
    for p, s, a in configurations:
        expected = answer(pb.sem.trans, p, s, a)
        errors += expected[0] == "error"  # type: ignore[index]
        assert answer(fast.trans, p, s, a) == expected
        assert answer(fast.final, p, s, a) == answer(pb.sem.final, p, s, a)
    assert errors > 0  # `bad` divides by zero when n() is 2


def test_procedures_recursion_nested_solve_and_pick_values_stay_the_semantics_own() -> None:
    """What the random programs do not use: procedure calls (with parameters, recursive, with a
    domain check of an argument), a `solve` inside the planned program, `pick ... in {...}`,
    `if` in the middle of a block, and `concurrent`."""
    text = """
symbol domain item = {p, q, r}
number fluent n() { initially: () = 0; }
bool fluent done(item i) { initially: (i) = false; }
action mark(item i) { precondition: !done(i) effect: done(i) = true; n() = n() + 1; }
action inc() { precondition: n() < 4 effect: n() = n() + 1; }
procedure walk(item i, number k) {
    if (k > 0) { choose { mark(i); inc(); } walk(i, k - 1); }
}
procedure each() { pick (item i in {q, r}) { test(!done(i)); mark(i); } }
number function reward() = n()
procedure main() {
    solve(6, reward()) {
        walk(p, 2);
        if (n() > 1) each(); else inc();
        solve(2, reward()) concurrent { inc(); pick (item i) mark(i); }
        while (n() < 5) choose { inc(); each(); }
    }
}
"""
    result = check_text(text, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    pb = first_solve(result.model)
    configurations = reachable(pb.sem, (pb.prog, pb.state, pb.acts))
    assert len(configurations) == 21  # all there are
    fast = Successors(pb.sem)
    for p, s, a in configurations:
        for _ in range(2):
            assert answer(fast.trans, p, s, a) == answer(pb.sem.trans, p, s, a)
            assert answer(fast.final, p, s, a) == answer(pb.sem.final, p, s, a)
    production, reference = pb.production(), pb.reference()
    assert production.actions() and (production.value, production.steps) == (reference.value, reference.steps)
