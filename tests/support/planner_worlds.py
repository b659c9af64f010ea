"""Random small planning worlds and programs over them, as golog++ source text, for the
planners' property tests (tests/planner).

A world has a domain, bool fluents, maybe a bounded counter, actions with random preconditions
and effects (conditional ones included; at the end, and on some actions at the start too) and
a reward that sums random terms; a program over it has action calls, assignments, tests,
`if`, `while`, `choose`, `pick` and blocks. `attempt`, `outcome` and `replay` run and compare
the planners' results."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from gpp.check import check_text
from gpp.planner.problem import PlanningProblem, first_solve
from gpp.planner.result import Plan, PolicyStep
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import Prog
from gpp.runtime.state import Activities, State

PROPERTY = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])


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
        # Start effects on one action in three: applied at its start, before its end effects.
        start_lines = draw(effects(shell, scope)) if draw(st.integers(0, 2)) == 0 else []
        if start_lines:
            body.append("start_effect:\n    " + "\n    ".join(start_lines))
        lines.append(f"action {a.name}({'D p' if a.unary else ''}) {{\n" + "\n".join(body) + "\n}")
    terms = [
        f"(if ({draw(conditions(shell, [], 1))}) {draw(st.integers(-2, 6))} else {draw(st.integers(-2, 6))})"
        for _ in range(draw(st.integers(1, 3)))
    ]
    if counter is not None and draw(st.booleans()):
        terms.append("cnt()")
    lines.append(f"number function reward() = {' + '.join(terms)}")
    return World(values, fluents, counter, actions, "\n".join(lines) + "\n")


def action_call(draw: st.DrawFn, w: World, scope: list[str]) -> str:
    a = draw(st.sampled_from(w.actions))
    return f"{a.name}({draw(st.sampled_from([*w.values, *scope])) if a.unary else ''})"


# Statement kinds, weighted towards action calls so that plans do something.
KINDS = ("call",) * 6 + ("assign",) * 2 + ("choose",) * 3 + ("pick",) * 2 + ("test", "if", "while", "block", "hooks")


@st.composite
def statements(draw: st.DrawFn, w: World, scope: list[str], depth: int) -> str:
    kind = draw(st.sampled_from(KINDS if depth > 0 else ("call", "call", "call", "assign", "test")))
    if kind == "call":
        return f"{action_call(draw, w, scope)};"
    if kind == "hooks":  # durative hooks: each one is a costed step while planning
        call = action_call(draw, w, scope)
        hook = draw(st.sampled_from(["start", "end", "finish", "start-end", "during", "during-until"]))
        if hook == "during":
            return f"during ({call}) {draw(statements(w, scope, depth - 1))}"
        if hook == "during-until":
            until = draw(conditions(w, scope, 1))
            return f"during ({call}) until ({until}) {draw(statements(w, scope, depth - 1))}"
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
