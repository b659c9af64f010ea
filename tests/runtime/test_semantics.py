"""The transition semantics, construct by construct (SEMANTICS §4, §5): `final` and `trans` of
each statement kind, online and while planning, and `apply` / `effects` on the state."""

from __future__ import annotations

import ast as pyast
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from gpp.base.source import Span
from gpp.check import check_text
from gpp.model.types import Sym, Type
from gpp.runtime import semantics
from gpp.runtime.compiled import CompiledProgram
from gpp.runtime.errors import GppRuntimeError
from gpp.runtime.semantics import (
    DONE,
    AssignStep,
    AwaitEnd,
    CancelStep,
    Code,
    Conc,
    DoStep,
    DuringEnd,
    EndStep,
    Frame,
    Prog,
    Rest,
    Semantics,
    Seq,
    StartStep,
    Step,
)
from gpp.runtime.state import Activities, ActivityStatus, GroundAction, State
from gpp.runtime.values import CompoundValue, Value
from gpp.syntax import ast

RUNNING, FINAL, FAILED, CANCELLED = (
    ActivityStatus.RUNNING,
    ActivityStatus.FINAL,
    ActivityStatus.FAILED,
    ActivityStatus.CANCELLED,
)

DECLARATIONS = """
symbol domain Room = {hall, kitchen, office}
compound Pose { number x, number y }

Room fluent at() { initially: () = hall; }
bool fluent door(Room r) { initially: (r) = true; (office) = false; }
number fluent n() { initially: () = 0; }
number fluent m() { initially: () = 1; }
list[number] fluent l() { initially: () = list[number] [1, 2, 3]; }
Pose fluent pose() { initially: () = Pose { x = 1, y = 2 }; }
list[Pose] fluent poses() { initially: () = list[Pose] [Pose { x = 0, y = 0 }]; }
number fluent seen(number i) { initially: (i) = null; }
bool fluent maybe() { initially: () = null; }

action go(Room r) {
precondition:
    at() != r & door(r)
effect:
    at() = r;
}
action a() { effect: n() = n() + 1; }
action b() { }
action swap() { effect: n() = m(); m() = n(); }
action clash() { effect: n() = 1; n() = 2; }
action agree() { effect: n() = 3; n() = 1 + 2; }
action parts() { effect: pose().x = 5; pose().y = 6; l()[0] = 7; l()[1] = 8; }
action part_clash() { effect: pose() = Pose { x = 1, y = 1 }; pose().x = 9; }
action part_agree() { effect: pose() = Pose { x = 4, y = 1 }; pose().x = 4; }
action cond_effect() { effect: if (n() == 0) m() = 10; n() = 5; if (n() == 5) m() = 20; }
action sense_arg(number i) { effect: seen(i) = i * 10; }

procedure twice(number v) { seen(0) = v; n() = n() + 5; seen(1) = v; }
procedure nothing() { }
procedure only_test() { test(n() > 0); }
"""


@dataclass
class FakeContext:
    answers: dict[str, Value] = field(default_factory=dict)
    asked: list[str] = field(default_factory=list)

    def exog_function(self, name: str, args: dict[str, Value], return_type: Type, span: Span) -> Value:
        self.asked.append(name)
        return self.answers[name]

    def now(self) -> float:
        return 0.0

    def wake_at(self, t: float) -> None:
        pass


@dataclass
class World:
    online: Semantics
    planning: Semantics
    program: CompiledProgram
    body: tuple[ast.Statement, ...]

    def code(self, i: int = 0) -> Code:
        """The i-th statement of `main` as a program continuation."""
        return Code(self.body[i], Frame())

    def state(self, **values: Value) -> State:
        """The initial state with nullary fluents set: state(n=3, at=Sym("kitchen"))."""
        updates = {self.program.slot(name, ()): v for name, v in values.items()}
        return State().updated(updates, self.program.initial)

    def read(self, state: State, fluent: str, *args: Value) -> Value:
        return self.program.read(state, fluent, tuple(args))


def world(main_body: str, extra: str = "") -> World:
    check = check_text(DECLARATIONS + extra + "\nprocedure main() {\n" + main_body + "\n}\n", lint=False)
    assert not check.errors, [d.message for d in check.diagnostics if d.is_error]
    program = CompiledProgram(check.model)
    ctx = FakeContext()
    main = check.model.globals["main"].decl
    assert isinstance(main, ast.ProcedureDecl) and isinstance(main.body, ast.Block)
    return World(
        Semantics(program, ctx, planning=False), Semantics(program, ctx, planning=True), program, main.body.body
    )


NO_ACTS = Activities()


def g(name: str, *args: Value) -> GroundAction:
    return GroundAction(name, tuple(args))


def acts(*items: tuple[GroundAction, ActivityStatus]) -> Activities:
    out = Activities()
    for action, status in items:
        out = out.with_status(action, status)
    return out


def describe(successors: list[tuple[Prog, Step]]) -> list[str]:
    return [step.describe() for _, step in successors]


def run_through(sem: Semantics, p: Prog, state: State, activities: Activities = NO_ACTS) -> tuple[list[str], State]:
    """Take the first successor until the program is final (activities end at once)."""
    done: list[str] = []
    for _ in range(100):
        if sem.final(p, state, activities):
            return done, state
        successors = sem.trans(p, state, activities)
        assert successors, f"stuck after {done}"
        p, step = successors[0]
        done.append(step.describe())
        state, activities = sem.apply(step, state, activities)
    raise AssertionError("did not end")


# ---------------------------------------------------------------- blocks


def test_empty_block_is_final_and_cannot_step() -> None:
    w = world("{}")
    assert w.online.final(w.code(), State(), NO_ACTS)
    assert w.online.trans(w.code(), State(), NO_ACTS) == []


def test_block_steps_its_first_statement_and_continues_with_the_rest() -> None:
    w = world("{ n() = 1; n() = 2; }")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert isinstance(step, AssignStep) and step.describe() == "n() = 1"
    assert not w.online.final(w.code(), State(), NO_ACTS)
    assert describe(w.online.trans(rest, State(), NO_ACTS)) == ["n() = 2"]


def test_block_of_final_statements_is_final() -> None:
    w = world("{ {} if (false) n() = 1; while (false) n() = 2; }")
    assert w.online.final(w.code(), State(), NO_ACTS)


def test_block_skips_a_final_statement_to_step_the_next() -> None:
    w = world("{ if (false) n() = 1; n() = 2; }")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS)) == ["n() = 2"]


# ---------------------------------------------------------------- if


def test_if_steps_the_branch_its_condition_selects() -> None:
    w = world("if (n() > 0) m() = 1; else m() = 2;")
    assert describe(w.online.trans(w.code(), w.state(n=1), NO_ACTS)) == ["m() = 1"]
    assert describe(w.online.trans(w.code(), w.state(n=0), NO_ACTS)) == ["m() = 2"]


def test_if_without_else_is_final_when_its_condition_is_false() -> None:
    w = world("if (n() > 0) m() = 1;")
    assert w.online.final(w.code(), w.state(n=0), NO_ACTS)
    assert w.online.trans(w.code(), w.state(n=0), NO_ACTS) == []
    assert not w.online.final(w.code(), w.state(n=1), NO_ACTS)


def test_if_with_a_null_condition_takes_the_else_branch() -> None:
    w = world("if (maybe()) m() = 1; else m() = 2;")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS)) == ["m() = 2"]


# ---------------------------------------------------------------- while


def test_while_is_final_when_its_condition_is_false() -> None:
    w = world("while (n() < 2) n() = n() + 1;")
    assert w.online.final(w.code(), w.state(n=2), NO_ACTS)
    assert w.online.trans(w.code(), w.state(n=2), NO_ACTS) == []


def test_while_is_final_when_its_body_is_final() -> None:
    w = world("while (true) {}")
    assert w.online.final(w.code(), State(), NO_ACTS)
    assert w.online.trans(w.code(), State(), NO_ACTS) == []


def test_while_repeats_its_body_and_rereads_the_condition() -> None:
    w = world("while (n() < 3) n() = n() + 1;")
    steps, state = run_through(w.online, w.code(), State())
    assert steps == ["n() = 1", "n() = 2", "n() = 3"]
    assert w.read(state, "n") == 3


def test_while_continuation_is_the_rest_of_the_body_then_the_loop() -> None:
    w = world("while (n() < 1) { n() = n() + 1; m() = 5; }")
    [(rest, _)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert isinstance(rest, Seq) and rest.rest == w.code()


# ---------------------------------------------------------------- test


def test_true_test_is_one_free_step() -> None:
    w = world("test(n() == 0);")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert rest is DONE and isinstance(step, semantics.TestStep) and step.cost == 0


def test_false_test_cannot_step_and_is_not_final() -> None:
    w = world("test(n() == 1);")
    assert w.online.trans(w.code(), State(), NO_ACTS) == []
    assert not w.online.final(w.code(), State(), NO_ACTS)
    assert w.planning.trans(w.code(), State(), NO_ACTS) == []


# ---------------------------------------------------------------- choose and pick


def test_choose_offers_every_alternative_that_can_step_in_textual_order() -> None:
    w = world("choose { go(office); go(kitchen); n() = 1; test(false); m() = 2; }")
    assert describe(w.planning.trans(w.code(), State(), NO_ACTS)) == ["go(kitchen)", "n() = 1", "m() = 2"]
    # Online the executor takes the first: the first alternative that can step now.
    assert describe(w.online.trans(w.code(), State(), NO_ACTS))[0] == "start(go(kitchen))"


def test_choose_is_final_when_an_alternative_is_final() -> None:
    w = world("choose { n() = 1; {} }")
    assert w.online.final(w.code(), State(), NO_ACTS)


def test_pick_offers_one_successor_per_value_in_the_order_of_its_list() -> None:
    w = world("pick (number i in {3, 1, 2}) seen(i) = i;")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS)) == ["seen(3) = 3", "seen(1) = 1", "seen(2) = 2"]


def test_pick_without_values_ranges_over_the_domain_in_declaration_order() -> None:
    w = world("pick (Room r) go(r);")
    # hall: already there; office: the door is closed.
    assert describe(w.planning.trans(w.code(), State(), NO_ACTS)) == ["go(kitchen)"]
    w = world("pick (bool v) if (v) n() = 1; else n() = 2;")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS)) == ["n() = 2", "n() = 1"]


def test_pick_binds_its_variable_for_the_whole_body() -> None:
    w = world("pick (number i in {4}) { seen(i) = i; seen(i + 1) = i; }")
    steps, _ = run_through(w.online, w.code(), State())
    assert steps == ["seen(4) = 4", "seen(5) = 4"]


# ---------------------------------------------------------------- concurrent


def test_concurrent_steps_the_first_branch_that_can_step() -> None:
    w = world("concurrent { { test(n() > 0); m() = 1; } n() = 1; }")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert step.describe() == "n() = 1"
    assert isinstance(rest, Conc)
    state = w.online.apply(step, State(), NO_ACTS)[0]
    # Now the first branch can step again and has priority.
    assert describe(w.online.trans(rest, state, NO_ACTS)) == ["test"]


def test_concurrent_gives_priority_to_earlier_branches() -> None:
    w = world("concurrent { { n() = 1; n() = 2; } m() = 3; }")
    steps, _ = run_through(w.online, w.code(), State())
    assert steps == ["n() = 1", "n() = 2", "m() = 3"]


def test_concurrent_ends_only_when_all_branches_ended() -> None:
    w = world("concurrent { n() = 1; test(n() == 5); }")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    state = w.online.apply(step, State(), NO_ACTS)[0]
    assert not w.online.final(rest, state, NO_ACTS)
    assert w.online.trans(rest, state, NO_ACTS) == []
    assert w.online.trans(rest, w.state(n=5), NO_ACTS) != []


def test_concurrent_of_final_branches_is_final() -> None:
    w = world("concurrent { {} if (false) n() = 1; }")
    assert w.online.final(w.code(), State(), NO_ACTS)


def test_concurrent_activities_overlap_online() -> None:
    w = world("concurrent { a(); b(); }")
    [(p1, s1)] = w.online.trans(w.code(), State(), NO_ACTS)
    running = acts((g("a"), RUNNING))
    [(p2, s2)] = w.online.trans(p1, State(), running)
    assert [s1.describe(), s2.describe()] == ["start(a())", "start(b())"]
    both = acts((g("a"), RUNNING), (g("b"), RUNNING))
    assert w.online.trans(p2, State(), both) == []
    [(_, s3)] = w.online.trans(p2, State(), acts((g("a"), RUNNING), (g("b"), FINAL)))
    assert s3.describe() == "end(b())"


# ---------------------------------------------------------------- action calls


def test_action_call_online_starts_and_then_awaits_the_end() -> None:
    w = world("go(kitchen);")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert isinstance(step, StartStep) and step.action == g("go", Sym("kitchen"))
    assert rest == AwaitEnd(g("go", Sym("kitchen")), step.span)
    assert step.cost == 1
    assert w.online.trans(rest, State(), acts((step.action, RUNNING))) == []
    for status in (FINAL, FAILED, CANCELLED):
        [(after, end)] = w.online.trans(rest, State(), acts((step.action, status)))
        assert after is DONE and isinstance(end, EndStep) and end.hook == "call" and end.cost == 0


def test_action_call_while_planning_is_one_step_that_ends_at_once() -> None:
    w = world("go(kitchen);")
    [(rest, step)] = w.planning.trans(w.code(), State(), NO_ACTS)
    assert rest is DONE and isinstance(step, DoStep) and step.cost == 1
    state, activities = w.planning.apply(step, State(), NO_ACTS)
    assert w.read(state, "at") == Sym("kitchen") and len(activities) == 0


def test_action_call_with_a_false_precondition_cannot_step() -> None:
    w = world("go(office);")
    assert w.online.trans(w.code(), State(), NO_ACTS) == []
    assert w.planning.trans(w.code(), State(), NO_ACTS) == []


def test_action_call_waits_while_an_identical_activity_runs() -> None:
    w = world("a();")
    assert w.online.trans(w.code(), State(), acts((g("a"), RUNNING))) == []
    assert describe(w.online.trans(w.code(), State(), NO_ACTS)) == ["start(a())"]


def test_action_arguments_are_evaluated_once_at_the_call() -> None:
    w = world("sense_arg(n());")
    [(rest, _)] = w.online.trans(w.code(), w.state(n=4), NO_ACTS)
    assert isinstance(rest, AwaitEnd) and rest.action == g("sense_arg", 4)
    # The end refers to the same activity, whatever n() is now.
    [(_, end)] = w.online.trans(rest, w.state(n=9), acts((g("sense_arg", 4), FINAL)))
    assert isinstance(end, EndStep) and end.action == g("sense_arg", 4)


# ---------------------------------------------------------------- hooks


def test_start_needs_the_precondition_and_no_identical_running_activity() -> None:
    w = world("start(go(kitchen));")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert rest is DONE and isinstance(step, StartStep)
    assert w.online.trans(w.code(), State(), acts((g("go", Sym("kitchen")), RUNNING))) == []
    assert w.online.trans(w.code(), w.state(at=Sym("kitchen")), NO_ACTS) == []


@pytest.mark.parametrize(
    ("hook", "steps_on"),
    [
        ("end", {FINAL, FAILED, CANCELLED}),
        ("finish", {FINAL}),
        ("fail", {FAILED}),
        ("cancel", {RUNNING}),
    ],
)
def test_each_hook_steps_only_in_its_activity_states(hook: str, steps_on: set[ActivityStatus]) -> None:
    w = world(f"{hook}(a());")
    assert w.online.trans(w.code(), State(), NO_ACTS) == []
    for status in (RUNNING, FINAL, FAILED, CANCELLED):
        successors = w.online.trans(w.code(), State(), acts((g("a"), status)))
        assert bool(successors) == (status in steps_on), (hook, status)
        if successors:
            [(rest, step)] = successors
            assert rest is DONE and step.cost == 1
            assert isinstance(step, CancelStep if hook == "cancel" else EndStep)


def test_while_planning_fail_and_cancel_are_impossible() -> None:
    w = world("{ start(a()); fail(a()); }")
    [(rest, start)] = w.planning.trans(w.code(), State(), NO_ACTS)
    state, activities = w.planning.apply(start, State(), NO_ACTS)
    assert activities.status(g("a")) is FINAL
    assert w.planning.trans(rest, state, activities) == []
    w = world("{ start(a()); cancel(a()); }")
    [(rest, start)] = w.planning.trans(w.code(), State(), NO_ACTS)
    state, activities = w.planning.apply(start, State(), NO_ACTS)
    assert w.planning.trans(rest, state, activities) == []


def test_end_applies_the_effects_only_when_the_activity_ended_final() -> None:
    w = world("end(a());")
    for status, expected in ((FINAL, 1), (FAILED, 0), (CANCELLED, 0)):
        before = acts((g("a"), status))
        [(_, step)] = w.online.trans(w.code(), State(), before)
        state, after = w.online.apply(step, State(), before)
        assert w.read(state, "n") == expected
        assert after.status(g("a")) is None  # consumed


# ---------------------------------------------------------------- during


def test_during_starts_the_action_runs_the_body_then_awaits_the_end() -> None:
    w = world("during (a()) { m() = 5; } on_fail n() = 10; on_cancel n() = 20;")
    [(rest, step)] = w.online.trans(w.code(), State(), NO_ACTS)
    assert isinstance(step, StartStep) and step.action == g("a")
    running = acts((g("a"), RUNNING))
    [(rest, body_step)] = w.online.trans(rest, State(), running)
    assert body_step.describe() == "m() = 5"
    assert isinstance(rest, DuringEnd)
    assert w.online.trans(rest, State(), running) == []


@pytest.mark.parametrize(
    ("status", "handler"),
    [(FINAL, None), (FAILED, "n() = 10"), (CANCELLED, "n() = 20")],
)
def test_during_runs_the_handler_of_the_terminal_state(status: ActivityStatus, handler: str | None) -> None:
    w = world("during (a()) { m() = 5; } on_fail n() = 10; on_cancel n() = 20;")
    [(rest, _)] = w.online.trans(w.code(), State(), NO_ACTS)
    [(end_prog, _)] = w.online.trans(rest, State(), acts((g("a"), RUNNING)))
    [(after, end)] = w.online.trans(end_prog, State(), acts((g("a"), status)))
    assert isinstance(end, EndStep) and end.hook == "during" and end.handles_failure
    if handler is None:
        assert after is DONE
    else:
        assert describe(w.online.trans(after, State(), NO_ACTS)) == [handler]


def test_during_without_handlers_ends_after_any_terminal_state() -> None:
    w = world("during (a()) m() = 5;")
    [(rest, _)] = w.online.trans(w.code(), State(), NO_ACTS)
    [(end_prog, _)] = w.online.trans(rest, State(), acts((g("a"), RUNNING)))
    for status in (FINAL, FAILED, CANCELLED):
        [(after, end)] = w.online.trans(end_prog, State(), acts((g("a"), status)))
        assert after is DONE and isinstance(end, EndStep) and not end.handles_failure


def test_during_while_planning_ends_in_final_and_applies_the_effects() -> None:
    w = world("during (a()) { m() = 5; } on_fail n() = 10;")
    steps, state = run_through(w.planning, w.code(), State())
    assert steps == ["start(a())", "m() = 5", "end(a())"]
    assert w.read(state, "n") == 1 and w.read(state, "m") == 5


# ---------------------------------------------------------------- assignments


def _updates(w: World, step: Step) -> dict[str, Value]:
    assert isinstance(step, AssignStep)
    return {w.program.instance_text(slot): value for slot, value in step.updates}


def test_assignment_to_a_fluent_instance_with_computed_arguments() -> None:
    w = world("seen(n() + 1) = n() * 10;")
    [(rest, step)] = w.online.trans(w.code(), w.state(n=2), NO_ACTS)
    assert rest is DONE and step.cost == 1
    assert _updates(w, step) == {"seen(3)": 20}


def test_field_and_element_assignments_replace_the_whole_value() -> None:
    w = world("{ pose().x = 7; l()[2] = 9; poses()[0].y = 4; }")
    _, state = run_through(w.online, w.code(), State())
    assert w.read(state, "pose") == CompoundValue("Pose", (("x", 7), ("y", 2)))
    assert w.read(state, "l") == (1, 2, 9)
    assert w.read(state, "poses") == (CompoundValue("Pose", (("x", 0), ("y", 4))),)


def test_push_and_pop_at_both_ends() -> None:
    w = world("{ push_back(l(), 4); push_front(l(), 0); pop_back(l()); pop_front(l()); pop_front(l()); }")
    steps, state = run_through(w.online, w.code(), State())
    assert steps[0] == "push_back(l())"
    assert w.read(state, "l") == (2, 3)


def test_an_assignment_back_to_the_initial_value_gives_the_initial_state() -> None:
    w = world("{ n() = 5; n() = 0; }")
    _, state = run_through(w.online, w.code(), State())
    assert state == State() and hash(state) == hash(State())


# ---------------------------------------------------------------- procedures


def test_procedure_call_is_transparent() -> None:
    w = world("twice(n());")
    [(rest, step)] = w.online.trans(w.code(), w.state(n=3), NO_ACTS)
    # The first step is the body's first statement; the call itself is no step.
    assert step.describe() == "seen(0) = 3"
    assert not w.online.final(w.code(), State(), NO_ACTS)
    # The continuation is the rest of the body, with the parameter bound to the value.
    assert isinstance(rest, Rest) and list(rest.frame.vars.values()) == [3]


def test_procedure_with_a_final_body_is_final() -> None:
    w = world("nothing();")
    assert w.online.final(w.code(), State(), NO_ACTS)
    w = world("only_test();")
    assert not w.online.final(w.code(), State(), NO_ACTS)
    assert w.online.trans(w.code(), State(), NO_ACTS) == []
    assert describe(w.online.trans(w.code(), w.state(n=1), NO_ACTS)) == ["test"]


def test_procedure_arguments_are_passed_by_value() -> None:
    w = world("twice(n());")
    steps, state = run_through(w.online, w.code(), w.state(n=3))
    assert steps == ["seen(0) = 3", "n() = 8", "seen(1) = 3"]
    assert w.read(state, "seen", 1) == 3


# ---------------------------------------------------------------- effects


def test_effects_are_evaluated_in_the_state_before_the_action() -> None:
    w = world("swap();")
    state = w.state(n=5, m=7)
    updates = w.online.effects(g("swap"), state)
    assert {w.program.instance_text(s): v for s, v in updates.items()} == {"n()": 7, "m()": 5}


def test_conditional_effects_test_the_state_before_the_action() -> None:
    w = world("cond_effect();")
    updates = w.online.effects(g("cond_effect"), State())
    assert {w.program.instance_text(s): v for s, v in updates.items()} == {"m()": 10, "n()": 5}


def test_two_effects_with_different_values_for_one_instance_are_an_error() -> None:
    w = world("clash();")
    with pytest.raises(GppRuntimeError) as caught:
        w.online.effects(g("clash"), State())
    e = caught.value
    assert e.code == "R0005"
    assert e.span is not None and e.span.text == "n() = 2;"
    assert "`clash()` assigns n() two different values" in e.message
    assert [label.span.text for label in e.secondary] == ["n() = 1;"]


def test_two_effects_with_the_same_value_agree() -> None:
    w = world("agree();")
    updates = w.online.effects(g("agree"), State())
    assert list(updates.values()) == [3]


def test_effects_on_different_fields_and_elements_of_one_instance_agree() -> None:
    w = world("parts();")
    state = State().updated(w.online.effects(g("parts"), State()), w.program.initial)
    assert w.read(state, "pose") == CompoundValue("Pose", (("x", 5), ("y", 6)))
    assert w.read(state, "l") == (7, 8, 3)


def test_effect_on_a_field_conflicting_with_an_effect_on_the_whole_value_is_an_error() -> None:
    w = world("part_clash();")
    with pytest.raises(GppRuntimeError) as caught:
        w.online.effects(g("part_clash"), State())
    assert caught.value.code == "R0005"
    assert "pose().x" in caught.value.message
    w = world("part_agree();")
    state = State().updated(w.online.effects(g("part_agree"), State()), w.program.initial)
    assert w.read(state, "pose") == CompoundValue("Pose", (("x", 4), ("y", 1)))


# ---------------------------------------------------------------- continuations


def test_sequences_stay_right_nested() -> None:
    w = world("n() = 1;")
    a, b, c = (Code(s, Frame()) for s in (w.body[0], w.body[0], w.body[0]))
    nested = Semantics.seq(Semantics.seq(Seq(a, b), c), DONE)
    assert nested == Seq(a, Seq(b, c))
    assert Semantics.seq(DONE, a) == a and Semantics.seq(a, DONE) == a


def test_deep_recursion_is_final_and_steps_in_linear_depth() -> None:
    extra = "procedure down(number k) { if (k > 0) { down(k - 1); n() = n() + 1; } }\n"
    w = world("down(300);", extra)
    steps, state = run_through_many(w.online, w.code(), State(), 400)
    assert len(steps) == 300 and w.read(state, "n") == 300


def run_through_many(sem: Semantics, p: Prog, state: State, limit: int) -> tuple[list[str], State]:
    from gpp.runtime.executor import raised_recursion_limit

    done: list[str] = []
    activities = NO_ACTS
    with raised_recursion_limit():
        for _ in range(limit):
            if sem.final(p, state, activities):
                return done, state
            p, step = sem.trans(p, state, activities)[0]
            done.append(step.describe())
            state, activities = sem.apply(step, state, activities)
    raise AssertionError("did not end")


def test_first_successor_only_does_not_evaluate_later_alternatives() -> None:
    w = world("choose { n() = 1; n() = 1 / n(); }")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS, first=True)) == ["n() = 1"]
    # Asked for every successor (as the planner does), the second alternative is evaluated.
    with pytest.raises(GppRuntimeError) as caught:
        w.online.trans(w.code(), State(), NO_ACTS)
    assert caught.value.code == "R0001"


def test_first_successor_only_stops_at_the_first_pick_value_that_steps() -> None:
    w = world("pick (number d in {2, 0}) seen(d) = 10 / d;")
    assert describe(w.online.trans(w.code(), State(), NO_ACTS, first=True)) == ["seen(2) = 5.0"]


def test_solve_online_without_a_planner_is_an_error() -> None:
    w = world("solve(2, r()) a();", "number function r() = 1")
    with pytest.raises(GppRuntimeError) as e:
        w.online.trans(w.code(), State(), NO_ACTS)
    assert e.value.code == "R0010" and e.value.message == "`solve` cannot plan: this run has no planner"
    # While planning, `solve` is transparent and needs no planner.
    assert describe(w.planning.trans(w.code(), State(), NO_ACTS)) == ["a()"]


def test_the_runtime_never_imports_the_planner() -> None:
    """The planner is reached only through the port of gpp.runtime.planning: no module of
    gpp/runtime imports gpp.planner, not even for type checking or inside a function."""
    runtime = Path(semantics.__file__).parent
    offending = []
    for path in sorted(runtime.glob("*.py")):
        for node in pyast.walk(pyast.parse(path.read_text(encoding="utf-8"))):
            names = [a.name for a in node.names] if isinstance(node, pyast.Import) else []
            if isinstance(node, pyast.ImportFrom) and node.module is not None:
                names = [node.module]
            offending += [f"{path.name}: {n}" for n in names if n == "gpp.planner" or n.startswith("gpp.planner.")]
    assert offending == []
