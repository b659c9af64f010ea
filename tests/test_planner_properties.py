"""Property-based tests of the planners on random small worlds and random programs.

Each example is golog++ source text: a world (a domain, bool fluents, maybe a bounded counter,
actions with random preconditions and effects, conditional ones included, and a reward that
sums random terms) and a program over it (action calls, assignments, tests, `if`, `while`,
`choose`, `pick` with and without `in`, blocks). The text must pass the checker; then it is
compiled and planned directly (gpp.planner.problem), without a platform.

What is checked (SEMANTICS §5, §6):
* the production planner returns exactly the reference planner's result: feasibility, value,
  policy, or the same error;
* every policy can be executed step by step from the start state with `trans`/`apply`, uses
  at most the horizon, ends the program unless it used the whole horizon, and its value is
  R(s0) plus the reward after every costed step;
* at every step the policy takes the first best option (stopping first, then textual order);
* a plan that ends the program before the horizon is still available with a larger horizon,
  so raising the horizon never lowers its value; infeasibility persists as the horizon grows;
* `search` returns executable plans that end the program, exactly when such an execution
  exists, and the first one a plain recursive depth-first search finds.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gpp.check import check_text
from gpp.planner.problem import PlanningProblem, first_solve
from gpp.planner.result import Plan, PolicyStep
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog
from gpp.runtime.state import Activities, State

PROPERTY = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ---------------------------------------------------------------- worlds


@dataclass(frozen=True)
class Fluent:
    name: str
    unary: bool


@dataclass(frozen=True)
class Action:
    name: str
    unary: bool


@dataclass(frozen=True)
class World:
    values: tuple[str, ...]  # of domain D
    fluents: tuple[Fluent, ...]
    counter: int | None  # the modulus of cnt(), or no counter
    actions: tuple[Action, ...]
    text: str


def _atom(draw: st.DrawFn, w: World, scope: list[str]) -> str:
    f = draw(st.sampled_from(w.fluents))
    if not f.unary:
        return f"{f.name}()"
    return f"{f.name}({draw(st.sampled_from([*w.values, *scope]))})"


@st.composite
def conditions(draw: st.DrawFn, w: World, scope: list[str], depth: int = 2) -> str:
    kind = draw(st.integers(0, 6 if depth > 0 else 2))
    if kind == 1 and w.counter is not None:
        op = draw(st.sampled_from(["<", "==", ">", "!="]))
        return f"cnt() {op} {draw(st.integers(0, w.counter - 1))}"
    if kind == 2:
        unary = [f for f in w.fluents if f.unary]
        if unary:
            f = draw(st.sampled_from(unary))
            quantifier = draw(st.sampled_from(["exists", "forall"]))
            z = f"z{len(scope)}{depth}"
            return f"{quantifier}(D {z}) {f.name}({z})"
    if kind == 3:
        return f"!{draw(conditions(w, scope, depth - 1))}"
    if kind in (4, 5):
        op = "&" if kind == 4 else "|"
        return f"({draw(conditions(w, scope, depth - 1))} {op} {draw(conditions(w, scope, depth - 1))})"
    if kind == 6:
        return draw(st.sampled_from(["true", "false"]))
    return _atom(draw, w, scope)


def _fluent_instance(draw: st.DrawFn, f: Fluent, w: World, scope: list[str]) -> str:
    return f"{f.name}({draw(st.sampled_from([*w.values, *scope]))})" if f.unary else f"{f.name}()"


def _bool_value(draw: st.DrawFn, w: World, scope: list[str]) -> str:
    if draw(st.booleans()):
        return draw(st.sampled_from(["true", "false"]))
    return draw(conditions(w, scope, 1))


@st.composite
def effects(draw: st.DrawFn, w: World, scope: list[str]) -> list[str]:
    out = []
    # Each fluent at most once per action: two effects on one instance could conflict.
    for f in draw(st.lists(st.sampled_from(w.fluents), max_size=2, unique=True)):
        line = f"{_fluent_instance(draw, f, w, scope)} = {_bool_value(draw, w, scope)};"
        if draw(st.integers(0, 3)) == 0:
            line = f"if ({draw(conditions(w, scope, 1))}) {line}"
        out.append(line)
    if w.counter is not None and draw(st.booleans()):
        out.append(f"cnt() = (cnt() + {draw(st.integers(1, 2))}) % {w.counter};")
    return out


@st.composite
def worlds(draw: st.DrawFn) -> World:
    values = tuple(f"d{i}" for i in range(draw(st.integers(2, 3))))
    fluents = tuple(Fluent(f"f{i}", draw(st.booleans())) for i in range(draw(st.integers(1, 3))))
    counter = draw(st.one_of(st.none(), st.integers(2, 3)))
    actions = tuple(Action(f"act{i}", draw(st.booleans())) for i in range(draw(st.integers(1, 3))))
    shell = World(values, fluents, counter, actions, "")
    lines = [f"symbol domain D = {{{', '.join(values)}}}"]
    for f in fluents:
        if f.unary:
            initial = [f"(x) = {draw(st.sampled_from(['true', 'false']))};"]
            initial += [f"({v}) = true;" for v in draw(st.lists(st.sampled_from(values), max_size=2, unique=True))]
            lines.append(f"bool fluent {f.name}(D x) {{ initially: {' '.join(initial)} }}")
        else:
            lines.append(f"bool fluent {f.name}() {{ initially: () = {draw(st.sampled_from(['true', 'false']))}; }}")
    if counter is not None:
        lines.append("number fluent cnt() { initially: () = 0; }")
    for a in actions:
        scope = ["p"] if a.unary else []
        body = []
        if draw(st.integers(0, 3)) > 0:
            body.append(f"precondition:\n    {draw(conditions(shell, scope))}")
        effect_lines = draw(effects(shell, scope))
        if effect_lines:
            body.append("effect:\n    " + "\n    ".join(effect_lines))
        lines.append(f"action {a.name}({'D p' if a.unary else ''}) {{\n" + "\n".join(body) + "\n}")
    terms = [
        f"(if ({draw(conditions(shell, [], 1))}) {draw(st.integers(-2, 6))} else {draw(st.integers(-2, 6))})"
        for _ in range(draw(st.integers(1, 3)))
    ]
    if counter is not None and draw(st.booleans()):
        terms.append("cnt()")
    lines.append(f"number function reward() = {' + '.join(terms)}")
    return World(values, fluents, counter, actions, "\n".join(lines) + "\n")


# ---------------------------------------------------------------- programs


def _action_call(draw: st.DrawFn, w: World, scope: list[str]) -> str:
    a = draw(st.sampled_from(w.actions))
    return f"{a.name}({draw(st.sampled_from([*w.values, *scope])) if a.unary else ''})"


# Statement kinds, weighted towards action calls so that plans do something.
KINDS = ("call",) * 6 + ("assign",) * 2 + ("choose",) * 3 + ("pick",) * 2 + ("test", "if", "while", "block", "hooks")


@st.composite
def statements(draw: st.DrawFn, w: World, scope: list[str], depth: int) -> str:
    kind = draw(st.sampled_from(KINDS if depth > 0 else ("call", "call", "call", "assign", "test")))
    if kind == "call":
        return f"{_action_call(draw, w, scope)};"
    if kind == "hooks":  # durative hooks: each one is a costed step while planning
        call = _action_call(draw, w, scope)
        hook = draw(st.sampled_from(["start", "end", "finish", "start-end", "during"]))
        if hook == "during":
            return f"during ({call}) {draw(statements(w, scope, depth - 1))}"
        if hook == "start-end":
            return f"{{ start({call}); {draw(statements(w, scope, depth - 1))} end({call}); }}"
        return f"{hook}({call});"
    if kind == "assign":
        if w.counter is not None and draw(st.booleans()):
            return f"cnt() = (cnt() + 1) % {w.counter};"
        f = draw(st.sampled_from(w.fluents))
        return f"{_fluent_instance(draw, f, w, scope)} = {_bool_value(draw, w, scope)};"
    if kind == "test":
        return f"test({draw(conditions(w, scope, 1))});"
    if kind == "if":
        then = draw(statements(w, scope, depth - 1))
        otherwise = f" else {draw(statements(w, scope, depth - 1))}" if draw(st.booleans()) else ""
        return f"if ({draw(conditions(w, scope, 1))}) {then}{otherwise}"
    if kind == "while":
        return f"while ({draw(conditions(w, scope, 1))}) {draw(statements(w, scope, depth - 1))}"
    if kind == "choose":
        alternatives = draw(st.lists(statements(w, scope, depth - 1), min_size=1, max_size=3))
        return "choose { " + " ".join(alternatives) + " }"
    if kind == "pick":
        v = f"v{len(scope)}"
        chosen = draw(st.one_of(st.none(), st.lists(st.sampled_from(w.values), min_size=1, max_size=3, unique=True)))
        in_values = f" in {{{', '.join(chosen)}}}" if chosen is not None else ""
        return f"pick (D {v}{in_values}) {draw(statements(w, [*scope, v], depth - 1))}"
    return draw(blocks(w, scope, depth - 1, 0))


@st.composite
def blocks(draw: st.DrawFn, w: World, scope: list[str], depth: int, min_size: int) -> str:
    body = draw(st.lists(statements(w, scope, depth), min_size=min_size, max_size=4))
    return "{ " + " ".join(body) + " }"


@dataclass(frozen=True)
class Case:
    world: World
    body: str
    horizon: int

    @property
    def text(self) -> str:
        return self.world.text + f"procedure main() {{\n    solve({self.horizon}, reward()) {self.body}\n}}\n"

    def problem(self) -> PlanningProblem:
        result = check_text(self.text, lint=False)
        assert result.errors == 0, (self.text, [d.message for d in result.diagnostics])
        return first_solve(result.model)

    def __repr__(self) -> str:  # what hypothesis prints for a failing example
        return "\n" + self.text


@st.composite
def cases(draw: st.DrawFn, max_horizon: int = 4, min_horizon: int = 1) -> Case:
    w = draw(worlds())
    body = draw(blocks(w, [], 3, 2))
    return Case(w, body, draw(st.integers(min_horizon, max_horizon)))


@st.composite
def looping_cases(draw: st.DrawFn, max_horizon: int = 5) -> Case:
    """A loop over a nondeterministic choice: configurations repeat, so the memo, the
    horizon-independent results and the duplicate options of the production planner all work."""
    w = draw(worlds())
    alternatives = draw(st.lists(statements(w, [], 1), min_size=2, max_size=4))
    condition = draw(st.one_of(st.just("true"), conditions(w, [], 1)))
    tail = " ".join(draw(st.lists(statements(w, [], 0), max_size=2)))
    body = f"{{ while ({condition}) choose {{ {' '.join(alternatives)} }} {tail} }}"
    return Case(w, body, draw(st.integers(1, max_horizon)))


@st.composite
def staggered_cases(draw: st.DrawFn, max_horizon: int = 5) -> Case:
    """Free tests and actions as alternatives before the rest of a program: the rest is met
    with several remaining horizons (reached early through the test, late through the action)."""
    w = draw(worlds())
    skips = [
        f"choose {{ test({draw(conditions(w, [], 0))}); {draw(statements(w, [], 0))} }}"
        for _ in range(draw(st.integers(1, 3)))
    ]
    rest = draw(st.lists(statements(w, [], 2), min_size=1, max_size=3))
    return Case(w, "{ " + " ".join(skips + rest) + " }", draw(st.integers(1, max_horizon)))


# ---------------------------------------------------------------- helpers


Outcome = tuple[object, ...]


def outcome(plan: Plan | GppRuntimeError) -> Outcome:
    if isinstance(plan, GppRuntimeError):
        return ("error", plan.code, plan.message, plan.span)
    return ("plan", plan.feasible, plan.value, plan.steps, [s.describe() for _, s, _ in plan.steps])


def attempt(pb: PlanningProblem, planner: str) -> Plan | GppRuntimeError:
    try:
        plan: Plan = getattr(pb, planner)()
    except GppRuntimeError as e:
        return e
    return plan


def replay(pb: PlanningProblem, steps: tuple[PolicyStep, ...]) -> tuple[Prog, State, Activities, int, float]:
    """Execute a policy with `trans`/`apply` from the start: the end configuration, the
    horizon used and R(s0) + the reward after every costed step."""
    p, s, a = pb.prog, pb.state, pb.acts
    used, total = 0, pb.reward(s)
    for before, step, after in steps:
        assert before == p
        assert (after, step) in pb.sem.trans(p, s, a), f"{step.describe()} is not possible"
        s, a = pb.sem.apply(step, s, a)
        p = after
        if step.cost:
            used += step.cost
            total += pb.reward(s)
    return p, s, a, used, total


# ---------------------------------------------------------------- solve


@given(st.one_of(cases(), looping_cases(), staggered_cases()))
@settings(PROPERTY, max_examples=1000)
def test_production_planner_returns_exactly_the_reference_result(case: Case) -> None:
    pb = case.problem()
    assert outcome(attempt(pb, "production")) == outcome(attempt(pb, "reference"))


@given(cases(max_horizon=5))
@settings(PROPERTY, max_examples=700)
def test_every_policy_is_executable_ends_the_program_or_the_horizon_and_is_worth_its_value(case: Case) -> None:
    pb = case.problem()
    plan = attempt(pb, "production")
    if isinstance(plan, GppRuntimeError) or not plan.feasible:
        return
    p, s, a, used, total = replay(pb, plan.steps)
    assert used == plan.cost <= pb.horizon
    assert used == pb.horizon or pb.sem.final(p, s, a)
    assert total == plan.value


def option_values(pb: PlanningProblem, p: Prog, s: State, a: Activities, h: int) -> list[tuple[bool, float]]:
    """The reference's (feasible, value) of every option at a configuration, stop first."""
    values: list[tuple[bool, float]] = []
    if pb.sem.final(p, s, a):
        values.append((True, 0.0))
    for q, step in pb.sem.trans(p, s, a):
        s2, a2 = pb.sem.apply(step, s, a)
        rest = PlanningProblem(pb.sem, q, s2, a2, h - step.cost, pb.reward, pb.span).reference()
        # A plan's value counts the reward of its start state; a free step does not earn it.
        values.append((rest.feasible, rest.value if step.cost else rest.value - pb.reward(s2)))
    return values


@given(cases(max_horizon=3))
@settings(PROPERTY, max_examples=300)
def test_the_policy_takes_the_first_best_option_at_every_step(case: Case) -> None:
    pb = case.problem()
    plan = attempt(pb, "reference")
    if isinstance(plan, GppRuntimeError) or not plan.feasible:
        return
    p, s, a, h = pb.prog, pb.state, pb.acts, pb.horizon
    for i in range(len(plan.steps) + 1):
        if h <= 0:
            assert i == len(plan.steps)
            break
        values = option_values(pb, p, s, a, h)
        offset = 1 if pb.sem.final(p, s, a) else 0
        if i == len(plan.steps):
            chosen = 0  # the policy stops: the stop option
            assert offset == 1
        else:
            _, step, after = plan.steps[i]
            chosen = offset + pb.sem.trans(p, s, a).index((after, step))
        feasible, value = values[chosen]
        assert feasible
        for j, (other_feasible, other) in enumerate(values):
            if other_feasible:
                assert other < value if j < chosen else other <= value
        if i < len(plan.steps):
            s, a = pb.sem.apply(step, s, a)
            p, h = after, h - step.cost


@given(cases(max_horizon=4, min_horizon=0), st.integers(1, 2))
@settings(PROPERTY, max_examples=500)
def test_raising_the_horizon_never_lowers_the_value_of_a_plan_that_ends_the_program(case: Case, more: int) -> None:
    pb = case.problem()
    low = attempt(pb, "production")
    high = attempt(pb.with_horizon(pb.horizon + more), "production")
    if isinstance(low, GppRuntimeError) or isinstance(high, GppRuntimeError):
        return
    if not low.feasible:
        assert not high.feasible  # infeasible stays infeasible
    elif low.cost < pb.horizon:  # the plan ends the program before the horizon
        assert high.feasible
        assert high.value >= low.value
    if high.feasible:
        assert low.feasible  # a branch feasible with more horizon is feasible with less


@st.composite
def blocks_worlds(draw: st.DrawFn) -> Case:
    """Larger instances: a blocks world of 3 or 4 blocks from a random arrangement to a random
    goal, with a random reward for the goal and per step, the whole `pick` program and a
    horizon up to 6 (3 blocks) or 4 (4 blocks): the shape the production planner is tuned for
    (pick guards, specialised successors, remembered quantifiers)."""
    blocks = draw(st.integers(3, 4))
    names = [f"b{i}" for i in range(blocks)]

    def arrangement() -> dict[str, str]:
        order = draw(st.permutations(names))
        on: dict[str, str] = {}
        for i, name in enumerate(order):
            # Each block on the table or on the block before it in the order (a stack).
            on[name] = order[i - 1] if i > 0 and draw(st.booleans()) else "table"
        return on

    start, goal = arrangement(), arrangement()
    initially = " ".join(f"({b}) = {start[b]};" for b in names)
    goal_text = " & ".join(f"loc({b}) == {goal[b]}" for b in names)
    win, step = draw(st.integers(1, 100)), draw(st.integers(-5, 2))
    world = World(
        tuple(names),
        (),
        None,
        (),
        f"""symbol domain block = {{{", ".join(names)}}}
symbol domain location = block | {{table}}
location fluent loc(block x) {{ initially: {initially} }}
action stack(block x, location y) {{
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}}
bool function goal() = {goal_text}
number function reward() = if (goal()) {win} else {step}
""",
    )
    body = draw(
        st.sampled_from(
            [
                "while (!goal()) pick (block x) pick (location y) stack(x, y);",
                "{ while (!goal()) pick (block x) pick (location y) stack(x, y); test(goal()); }",
                "while (true) choose { pick (block x) stack(x, table); pick (block x) pick (block y) stack(x, y); }",
            ]
        )
    )
    return Case(world, body, draw(st.integers(1, 6 if blocks == 3 else 4)))


@given(blocks_worlds())
@settings(PROPERTY, max_examples=30)
def test_production_planner_returns_exactly_the_reference_result_on_larger_blocks_worlds(case: Case) -> None:
    pb = case.problem()
    assert outcome(attempt(pb, "production")) == outcome(attempt(pb, "reference"))


# ---------------------------------------------------------------- search


def plain_search(pb: PlanningProblem) -> tuple[PolicyStep, ...] | None:
    """Depth-first search in textual order, skipping visited configurations, written plainly."""
    visited = {(pb.prog, pb.state, pb.acts)}

    def dfs(p: Prog, s: State, a: Activities) -> list[PolicyStep] | None:
        if pb.sem.final(p, s, a):
            return []
        for q, step in pb.sem.trans(p, s, a):
            s2, a2 = pb.sem.apply(step, s, a)
            if (q, s2, a2) in visited:
                continue
            visited.add((q, s2, a2))
            rest = dfs(q, s2, a2)
            if rest is not None:
                return [(p, step, q), *rest]
        return None

    found = dfs(pb.prog, pb.state, pb.acts)
    return tuple(found) if found is not None else None


def final_reachable(pb: PlanningProblem) -> bool:
    """Breadth-first: can the program reach a final configuration at all?"""
    start = (pb.prog, pb.state, pb.acts)
    seen, todo = {start}, deque([start])
    while todo:
        p, s, a = todo.popleft()
        if pb.sem.final(p, s, a):
            return True
        for q, step in pb.sem.trans(p, s, a):
            s2, a2 = pb.sem.apply(step, s, a)
            if (q, s2, a2) not in seen:
                seen.add((q, s2, a2))
                todo.append((q, s2, a2))
    return False


@given(cases(max_horizon=0, min_horizon=0))
@settings(PROPERTY, max_examples=800)
def test_search_finds_an_executable_complete_execution_exactly_when_one_exists(case: Case) -> None:
    pb = case.problem()
    try:
        plan = pb.search(10_000)
    except GppRuntimeError as e:  # only a runtime error of the program itself
        assert e.code != "R0010"
        return
    assert plan.feasible == final_reachable(pb)
    if plan.feasible:
        p, s, a, _, _ = replay(pb, plan.steps)
        assert pb.sem.final(p, s, a)
    assert (plan.steps if plan.feasible else None) == plain_search(pb)
