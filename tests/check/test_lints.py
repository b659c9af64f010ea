"""The lints (W0101-W0120): for each, a tiny program that triggers it, with the exact code,
position and message, and a clean counterpart that does not; `allow` suppresses a lint by code
or by name; declarations of included files are never linted."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic, Severity
from gpp.check import check_program
from gpp.check.lints import LINTS
from gpp.check.suppress import SUPPRESSION_LINTS
from gpp.codes import CODES, lints
from tests.support.lint_triggers import (
    CONSTANT,
    DOUBLE_EFFECT,
    FLUENTS,
    GOAL_PAID_AGAIN,
    ONLINE,
    QUANTIFIER,
    SHADOWED,
    SHARED_SENSING,
    SOLVE,
    TRIGGERS,
    UNENDED,
    UNREACHABLE,
    UNRUN_WATCH_BODY,
    UNUSED,
    UNUSED_VARIABLES,
    UNWATCHED,
    looping,
    scoped,
    sensing,
)

PATH = Path("lint_test.gpp")
EXAMPLES_DIR = Path(__file__).resolve().parents[2] / "examples"


def lint(text: str, *allow: str) -> list[Diagnostic]:
    """The warnings of a program that must have no errors."""
    result = check_program(PATH, allow=allow, overrides={PATH: text})
    errors = [f"{d.span.line}:{d.span.col} {d.code} {d.message}" for d in result.diagnostics if d.is_error]
    assert errors == [], "the test program has errors"
    assert all(d.severity is Severity.WARNING for d in result.diagnostics)
    return result.diagnostics


def found(text: str, code: str, *allow: str) -> list[str]:
    """`line:col message` of every warning with `code`."""
    return [f"{d.span.line}:{d.span.col} {d.message}" for d in lint(text, *allow) if d.code == code]


def the(text: str, code: str) -> Diagnostic:
    [d] = [d for d in lint(text) if d.code == code]
    return d


# ---------------------------------------------------------------- the registry


def test_every_lint_code_has_a_lint() -> None:
    # The suppression comments' own lints are reported by gpp.check.suppress.
    assert sorted([*LINTS, *SUPPRESSION_LINTS]) == [c.code for c in lints()]
    assert all(CODES[code].is_lint for code in LINTS)


# ---------------------------------------------------------------- W0101 unused


def test_unused_declarations_are_reported() -> None:
    assert found(UNUSED, "W0101") == [
        "1:15 fluent `count` is never used",
        "2:8 action `beep` is never used",
        "3:17 function `fact` is never used",  # calls from its own body do not count
    ]


def test_used_declarations_and_entry_points_are_not_reported() -> None:
    text = """\
number fluent count() { initially: () = 0; }
action beep() { effect: count() = count() + 1; }
number function reward() = count()
procedure twice() { beep(); beep(); }
procedure main() { solve(2, reward()) choose { twice(); beep(); } }
bool function postcond() = count() > 0
exog_action bell() { }
"""
    assert found(text, "W0101") == []


# ---------------------------------------------------------------- W0102 unused parameter / variable


def test_unused_parameters_and_variables_are_reported() -> None:
    assert found(UNUSED_VARIABLES, "W0102") == [
        "2:40 parameter `y` of function `twice` is never used",
        "3:26 parameter `speed` of action `go` is never used",
        "12:23 variable `r` is never used",
        "13:22 variable `q` is never used",
    ]


def test_used_parameters_are_not_reported() -> None:
    text = """\
symbol domain Room = {hall, kitchen}
Room fluent at() { initially: () = hall; }
action go(Room r, number speed) {
precondition: at() != r
mapping:
    "go" { velocity = speed }
}
procedure main() {
    search pick (Room r) go(r, 1);
    test(exists(Room q) at() == q);
}
"""
    assert found(text, "W0102") == []


# ---------------------------------------------------------------- W0103 uninitialised fluent instances


@pytest.mark.parametrize(
    ("declaration", "message"),
    [
        (
            "symbol domain Room = {hall, kitchen, office}\nbool fluent lit(Room r) { initially: (hall) = true; }",
            "2:13 fluent `lit` has no initial value for `lit(kitchen)` and `lit(office)`",
        ),
        (
            "symbol domain B = {a, b}\nbool fluent on(B x, B y) { initially: (a, y) = true; (b, b) = false; }",
            "2:13 fluent `on` has no initial value for `on(b, a)`",
        ),
        (
            "bool fluent f(bool p, bool q) { initially: (true, q) = true; }",
            "1:13 fluent `f` has no initial value for `f(false, false)` and `f(false, true)`",
        ),
        (
            "number domain D = {1, 2, 3, 4, 5}\nnumber fluent f(D d) { initially: (1) = 0; }",
            "2:15 fluent `f` has no initial value for `f(2)`, `f(3)`, `f(4)` and 1 more instance",
        ),
        (
            "number fluent count(number n) { initially: (1) = 0; }",
            "1:15 fluent `count` has no initial value for `count(n)` with `n` not listed in `initially:`",
        ),
        (
            'string domain Name = {"ann", "bob"}\nnumber fluent f(Name who, number n) { initially: ("ann", n) = 0; }',
            '2:15 fluent `f` has no initial value for `f("bob", n)` with `n` not listed in `initially:`',
        ),
        ("number fluent f();", "1:15 fluent `f` has no initial values"),
    ],
)
def test_uninitialized_fluent_instances_are_reported(declaration: str, message: str) -> None:
    assert found(declaration + "\n", "W0103") == [message]


@pytest.mark.parametrize(
    "declaration",
    [
        "symbol domain Room = {hall, kitchen}\nbool fluent lit(Room r) { initially: (r) = false; (hall) = true; }",
        "symbol domain Room = {hall, kitchen}\nbool fluent lit(Room r) { initially: (hall) = true; (kitchen) = null; }",
        "bool fluent f(bool p) { initially: (true) = true; (false) = false; }",
        "number domain D = {1, 2}\nnumber fluent f(D d) { initially: (1.0) = 0; (2) = 0; }",
        "number fluent count(number n) { initially: (n) = 0; (1) = 5; }",
        "symbol domain B = {a, b}\nnumber fluent f(B x, string s) { initially: (a, s) = 0; (x, s) = 1; }",
        "number fluent f();\nnumber fluent f() { initially: () = 0; }",
        "number fluent f() { initially: () = null; }",
    ],
)
def test_fully_initialized_fluents_are_not_reported(declaration: str) -> None:
    assert found(declaration + "\n", "W0103") == []


def test_uninitialized_fluent_has_a_default_entry_help() -> None:
    d = the("symbol domain B = {a, b}\nbool fluent on(B x, B y) { initially: (a, b) = true; }\n", "W0103")
    assert d.label == "some instances start as `null`"
    assert d.help == "add a default entry `(x, y) = ...;` before the others (later entries override earlier ones)"


# ---------------------------------------------------------------- W0104 double effect


def test_double_effect_is_reported() -> None:
    assert found(DOUBLE_EFFECT, "W0104") == ["9:5 action `step` assigns `count()` twice"]
    d = the(DOUBLE_EFFECT, "W0104")
    assert [(label.span.line, label.span.col, label.message) for label in d.secondary] == [
        (6, 5, "first assigned here")
    ]


def test_different_and_guarded_effects_are_not_reported() -> None:
    text = DOUBLE_EFFECT.replace("    count() = 0;\n", "")
    assert found(text, "W0104") == []


# ---------------------------------------------------------------- W0105 pick/choose online


def test_pick_and_choose_outside_planning_are_reported() -> None:
    assert found(ONLINE, "W0105") == [
        "4:24 `pick` outside `solve` or `search` takes the first value that works now",
        "7:5 `pick` outside `solve` or `search` takes the first value that works now",
        "11:5 `choose` outside `solve` or `search` takes the first alternative that works now",
    ]


def test_procedures_called_only_while_planning_are_not_reported() -> None:
    text = """\
symbol domain Room = {hall, kitchen}
action go(Room r) { }
number function reward() = 0
procedure leaf() { pick (Room r) go(r); }
procedure middle() { leaf(); middle(); }
procedure main() { search middle(); }
"""
    assert found(text, "W0105") == []


def test_a_choose_that_waits_in_every_alternative_is_not_reported() -> None:
    text = """\
action scan() { }
action say(string text) { }
bool fluent ready() { initially: () = false; }
procedure main() {
    start(scan());
    choose {
        { finish(scan()); say("done"); }
        { fail(scan()); say("failed"); }
        test(ready());
    }
}
"""
    assert found(text, "W0105") == []


# ---------------------------------------------------------------- W0106 busy loop


def test_busy_loop_is_reported() -> None:
    text = """\
bool fluent busy() { initially: () = false; }
procedure main() {
    while (true) {
        if (busy()) { }
    }
}
"""
    d = the(text, "W0106")
    assert (d.span.line, d.span.col, d.span.text) == (3, 5, "while (true)")
    assert d.message == "this `while (true)` loop never executes an action, a test or an assignment"


@pytest.mark.parametrize("body", ["beep();", "test(busy());", "busy() = false;", "{ if (busy()) step(); }"])
def test_loops_that_act_are_not_reported(body: str) -> None:
    text = f"""\
bool fluent busy() {{ initially: () = false; }}
action beep() {{ }}
procedure step() {{ beep(); }}
procedure main() {{ while (true) {body} }}
"""
    assert found(text, "W0106") == []


# ---------------------------------------------------------------- W0107 constant condition


def test_constant_conditions_are_reported() -> None:
    assert found(CONSTANT, "W0107") == [
        "4:15 precondition is always false",
        "6:9 effect condition is always true",
        "9:9 `if` condition is always true",
        "10:12 `while` condition is always false",
        "11:12 `while` condition is always false",
        "12:10 `test` condition is always false",
        "13:12 `while` condition is always true",
    ]


def test_idioms_and_state_dependent_conditions_are_not_reported() -> None:
    text = """\
symbol domain Room = {hall, kitchen}
number fluent count() { initially: () = 0; }
action beep() {
precondition: true
effect:
    if (count() > 1) count() = 1;
}
procedure pace(Room hall) {
    if (hall == kitchen) beep();
}
procedure main() {
    while (true) beep();
    test(true);
    if (count() < 2) beep();
    pace(kitchen);
}
"""
    assert found(text, "W0107") == []


# ---------------------------------------------------------------- W0108 unreachable else


def test_unreachable_branches_are_reported() -> None:
    assert found(UNREACHABLE, "W0108") == [
        "4:23 the `else` branch can never run",
        "5:9 the `if` branch can never run, only the `else` branch",
    ]
    first = next(d for d in lint(UNREACHABLE) if d.code == "W0108")
    assert first.span.text == "else"
    assert [(label.span.text, label.message) for label in first.secondary] == [
        ("true", "this condition is always true")
    ]


def test_an_if_with_a_real_condition_is_not_reported() -> None:
    text = "bool fluent p() { initially: () = true; }\naction beep() { }\n"
    text += "procedure main() { if (p()) beep(); else { } }\n"
    assert found(text, "W0108") == []


# ---------------------------------------------------------------- W0109 solve without choice


def test_solve_without_choice_is_reported() -> None:
    assert found(SOLVE, "W0109") == ["7:5 `solve` has nothing to decide: its program has no `pick` or `choose`"]
    assert the(SOLVE, "W0109").span.text == "solve"


# ---------------------------------------------------------------- W0110 mixed precedence


def precedence(expression: str, type_: str = "number") -> list[tuple[str, tuple[str, ...], str]]:
    """(message, notes, the line after the fix) of the W0110 warnings about `expression`."""
    use = "f() > 0" if type_ == "number" else "f()"
    text = FLUENTS + f"{type_} function f() = {expression}\nprocedure main() {{ test({use}); }}\n"
    out = []
    for d in lint(text):
        if d.code == "W0110":
            assert d.fix is not None
            fixed = text
            for edit in sorted(d.fix.edits, key=lambda e: -e.span.start):
                fixed = fixed[: edit.span.start] + edit.text + fixed[edit.span.end :]
            out.append((d.message, d.notes, fixed.splitlines()[5]))
    return out


@pytest.mark.parametrize(
    ("expression", "golog", "standard"),
    [
        # LANGUAGE.md §2.6.2
        ("1 * 2 + 3 * 4", "((1 * 2) + 3) * 4", "(1 * 2) + (3 * 4)"),
        ("1 + 2 * 3 ** 2 - 4 / 2 % 3", "1 + (((2 * (3 ** 2)) - 4) / 2 % 3)", "1 + (2 * (3 ** 2)) - (4 / 2 % 3)"),
        ("5 - 3 + x() - 1 + 2 * -3 - -4", "((5 - 3 + x() - 1 + 2) * -3) - -4", "5 - 3 + x() - 1 + (2 * -3) - -4"),
        ("(x() - 1) ** 2 + x() ** 2", "(((x() - 1) ** 2) + x()) ** 2", "((x() - 1) ** 2) + (x() ** 2)"),
    ],
)
def test_arithmetic_chains_read_differently_are_reported(expression: str, golog: str, standard: str) -> None:
    [(message, notes, fixed)] = precedence(expression)
    assert message == f"the original C++ golog++ reads this as `{golog}`"
    assert notes == (f"gpp uses standard precedence: `{standard}`",)
    assert fixed == f"number function f() = {standard}"


@pytest.mark.parametrize(
    ("expression", "golog", "standard"),
    [
        ("p() & q() | r() & s()", "((p() & q()) | r()) & s()", "(p() & q()) | (r() & s())"),
        ("p() & q() -> r() | s()", "((p() & q()) -> r()) | s()", "(p() & q()) -> (r() | s())"),
        ("p() & x() > 1 | q() & !r()", "((p() & x() > 1) | q()) & !r()", "(p() & x() > 1) | (q() & !r())"),
    ],
)
def test_boolean_chains_read_differently_are_reported(expression: str, golog: str, standard: str) -> None:
    [(message, notes, fixed)] = precedence(expression, "bool")
    assert message == f"the original C++ golog++ reads this as `{golog}`"
    assert notes == (f"gpp uses standard precedence: `{standard}`",)
    assert fixed == f"bool function f() = {standard}"


@pytest.mark.parametrize(
    "expression",
    [
        "1 + 2 * 3",
        "1 * 2 + 3",
        "1 - 2 - 3 + 4",
        "2 ** 3 ** 2",
        "8 / 2 / 2 * 3 % 5",
        "(1 * 2) + (3 * 4)",
        "1 * 2 + (3 * 4)",
    ],
)
def test_arithmetic_chains_read_alike_are_not_reported(expression: str) -> None:
    assert precedence(expression) == []


@pytest.mark.parametrize(
    "expression",
    [
        "p() | q() & r() | s()",
        "p() -> q() -> r()",
        "p() & q() & r() | s()",
        "(p() & q()) | (r() & s())",
        "p() & q() == r()",
        "x() * 2 + 1 > x() + 2 * 3 & p()",
    ],
)
def test_boolean_chains_read_alike_are_not_reported(expression: str) -> None:
    assert precedence(expression, "bool") == []


def test_boolean_equality_takes_part_in_the_chain() -> None:
    # `==` between bools is iff, at the loosest level: gpp reads `(p & q) == (r | s)`.
    [(message, notes, _)] = precedence("p() & q() == r() | s()", "bool")
    assert message == "the original C++ golog++ reads this as `((p() & q()) == r()) | s()`"
    assert notes == ("gpp uses standard precedence: `(p() & q()) == (r() | s())`",)


# ---------------------------------------------------------------- W0111 shadowed symbol


def test_shadowed_symbols_are_reported() -> None:
    assert found(SHADOWED, "W0111") == [
        "2:16 parameter `hall` shadows the symbol `hall`",
        "5:23 variable `kitchen` shadows the symbol `kitchen`",
    ]
    first = next(d for d in lint(SHADOWED) if d.code == "W0111")
    assert [(label.span.line, label.span.col, label.message) for label in first.secondary] == [
        (1, 23, "the symbol is declared here")
    ]


def test_names_unlike_symbols_are_not_reported() -> None:
    assert found(SHADOWED.replace("Room hall", "Room to").replace("Room kitchen", "Room r"), "W0111") == []


def fixed(text: str, d: Diagnostic) -> str:
    """`text` with the edits of `d`'s fix applied."""
    assert d.fix is not None
    for edit in sorted(d.fix.edits, key=lambda e: -e.span.start):
        text = text[: edit.span.start] + edit.text + text[edit.span.end :]
    return text


# ---------------------------------------------------------------- W0112 quantifier scope


def test_quantifier_body_running_on_is_reported() -> None:
    assert found(QUANTIFIER, "W0112") == ["4:56 `clear(x)` is part of the `exists(Block z)` body but does not use `z`"]
    d = the(QUANTIFIER, "W0112")
    assert d.notes == (
        "a quantifier's body extends as far right as it can: this reads `exists(Block z) (on(z, x) & clear(x))`",
    )
    assert d.help == "put the quantifier in parentheses, `(exists(Block z) ...)`, to end it before `clear(x)`"
    assert d.fix is not None and d.fix.message == "end the `exists` before `clear(x)`"
    repaired = fixed(QUANTIFIER, d)
    assert repaired.splitlines()[3] == "bool function f(Block x) = !(exists(Block z) on(z, x)) & clear(x)"
    assert found(repaired, "W0112") == []


@pytest.mark.parametrize(
    ("expression", "outside", "repaired"),
    [
        (
            "exists(Block z) on(z, x) & clear(x) | clear(b)",
            "clear(x) | clear(b)",
            "(exists(Block z) on(z, x)) & clear(x) | clear(b)",
        ),
        ("forall(Block z) on(z, x) -> clear(x)", "clear(x)", "(forall(Block z) on(z, x)) -> clear(x)"),
        (
            "exists(Block z) on(z, x) & on(x, z) & clear(x)",
            "clear(x)",
            "(exists(Block z) on(z, x) & on(x, z)) & clear(x)",
        ),
        (
            "clear(a) & (exists(Block z) on(z, x) | clear(x))",
            "clear(x)",
            "clear(a) & ((exists(Block z) on(z, x)) | clear(x))",
        ),
        # The operands that use `z` are not one subtree: no certain fix.
        ("exists(Block z) clear(a) | on(z, x) & clear(x)", "clear(x)", None),
    ],
)
def test_quantifier_scope_fixes(expression: str, outside: str, repaired: str | None) -> None:
    text = scoped(expression)
    d = the(text, "W0112")
    assert d.span.text == outside
    if repaired is None:
        assert d.fix is None
    else:
        assert fixed(text, d).splitlines()[3] == f"bool function f(Block x) = {repaired}"


@pytest.mark.parametrize(
    "expression",
    [
        "!exists(Block z) on(z, x) & clear(z)",
        "!exists(Block z) clear(x) & on(z, x)",
        "!exists(Block z) (on(z, x) & clear(x))",  # the body is parenthesised: meant
        "!(exists(Block z) on(z, x)) & clear(x)",
        "forall(Block z) on(z, x) == clear(x)",  # not an `&`/`|`/`->` chain
        "exists(Block z) on(z, x)",
    ],
)
def test_quantifiers_whose_body_uses_the_variable_to_the_end_are_not_reported(expression: str) -> None:
    assert found(scoped(expression), "W0112") == []


# ---------------------------------------------------------------- W0113 shared sensing result


def test_two_exogenous_functions_in_one_senses_section_are_reported() -> None:
    assert found(SHARED_SENSING, "W0113") == [
        '7:41 `sensed("y")` gets the same value as `sensed_x()` in this `senses:` section'
    ]
    d = the(SHARED_SENSING, "W0113")
    assert [(label.span.line, label.span.col, label.message) for label in d.secondary] == [
        (7, 25, "the first exogenous function here")
    ]


@pytest.mark.parametrize(
    ("senses", "messages"),
    [
        (
            'pose() = Pose { x = sensed("x"), y = sensed("y") };',
            ['7:42 `sensed("y")` gets the same value as `sensed("x")` in this `senses:` section'],
        ),
        (
            'pose() = Pose { x = sensed_x(), y = sensed_x() + sensed("y") };',
            ['7:54 `sensed("y")` gets the same value as `sensed_x()` in this `senses:` section'],
        ),
        # The same call twice is meant to give the same value.
        ("pose() = Pose { x = if (sensed_x() > 0) sensed_x() else 0, y = 0 };", []),
        ("pose() = Pose { x = sensed_x(), y = pose().y };", []),
    ],
)
def test_each_exogenous_function_call_unlike_the_first_is_reported(senses: str, messages: list[str]) -> None:
    assert found(sensing(senses), "W0113") == messages


# ---------------------------------------------------------------- W0114 unended activity


def test_activities_started_and_never_ended_are_reported() -> None:
    assert found(UNENDED, "W0114") == [
        "7:5 `scan()` is started, but the program has no `end`, `finish`, `fail` or `cancel` of `scan`",
        "11:5 `beep()` is started, but the program has no `end`, `finish`, `fail` or `cancel` of `beep`",
    ]
    d = the(UNENDED.replace("    start(beep());\n", ""), "W0114")
    assert d.help == "wait for it with `end(scan());`, or call `scan();` to start it and wait in one step"


@pytest.mark.parametrize("hook", ["end", "finish", "fail", "cancel"])
def test_an_activity_any_hook_refers_to_is_not_reported(hook: str) -> None:
    text = f"""\
action scan(number range) {{ }}
procedure watch() {{ {hook}(scan(5)); }}
procedure main() {{ start(scan(1)); watch(); }}
"""
    assert found(text, "W0114") == []


def test_a_hook_in_an_included_file_counts(tmp_path: Path) -> None:
    (tmp_path / "lib.gpp").write_text("action scan() { }\nprocedure await_scan() { end(scan()); }\n")
    main = tmp_path / "main.gpp"
    main.write_text('#include "lib.gpp"\nprocedure main() { start(scan()); await_scan(); }\n')
    assert [d.code for d in check_program(main).diagnostics] == []


# ---------------------------------------------------------------- W0115 busy wait


NO_WAIT = "this `while` loop does not wait for its condition: its body does nothing, so it ends at once"
BUSY = "this `while` loop busy-waits: nothing in its body changes what its condition reads"


@pytest.mark.parametrize(
    ("condition", "body", "message", "replacement"),
    [
        ("!done()", "{ }", NO_WAIT, "test(done());"),
        ("!done()", "{ if (finished()) { } else { } }", NO_WAIT, "test(done());"),
        ("!(done() | finished())", "{ }", NO_WAIT, "test(done() | finished());"),
        ("done() == finished()", "{ }", NO_WAIT, "test(!(done() == finished()));"),
        ("n() < 3", "{ { } }", NO_WAIT, "test(!(n() < 3));"),
        ("!done()", "{ test(true); }", BUSY, "test(done());"),
        ("!finished()", "test(1 < 2);", BUSY, "test(finished());"),
        ("!(done() | finished())", "{ other() = other() + 1; }", BUSY, None),
        ("!finished()", "{ push_back(queue(), 1); done() = true; }", BUSY, None),
        ("other() == 0 & !done()", "{ n() = 1; }", BUSY, None),
    ],
)
def test_loops_that_cannot_change_their_condition_are_reported(
    condition: str, body: str, message: str, replacement: str | None
) -> None:
    text = looping(condition, body)
    d = the(text, "W0115")
    assert (d.span.line, d.span.col, d.message) == (9, 5, message)
    assert d.span.text == f"while ({condition})"
    if replacement is None:
        assert d.fix is None
    else:
        assert fixed(text, d).splitlines()[8] == f"    {replacement}"
        assert d.help == f"to wait until `{replacement[5:-2]}` holds, write `{replacement}`"


@pytest.mark.parametrize(
    ("condition", "body"),
    [
        ("n() < 3", "{ n() = n() + 1; }"),
        ("!finished()", "n() = n() + 1;"),  # through the function
        ("length(queue()) < 3", "push_back(queue(), 1);"),
        ("!done()", "beep();"),
        ("!finished()", "step();"),
        ("!done()", "{ start(beep()); end(beep()); }"),
        ("!done()", "{ test(done() | finished()); other() = 1; }"),  # waits for the world
        ("!done()", "search { other() = 1; }"),
        ("true", "{ }"),  # W0106's
        ("false", "{ }"),  # W0107's
    ],
)
def test_loops_that_can_change_their_condition_are_not_reported(condition: str, body: str) -> None:
    assert found(looping(condition, body), "W0115") == []


# ---------------------------------------------------------------- W0118 goal paid again


def test_a_step_after_the_goal_is_reported() -> None:
    d = the(GOAL_PAID_AGAIN, "W0118")
    assert (d.span.line, d.span.col, d.span.text) == (11, 9, "visits() = visits() + 1;")
    assert d.message == "the reward pays `100` again after this step: `served()` still holds in the state it makes"
    assert [label.span.text for label in d.secondary] == ["served() = at_desk() == room1;", "served_reward()"]
    assert d.fix is None


def goal_solve(reward: str, body: str) -> str:
    return GOAL_PAID_AGAIN.replace("if (served()) 100 else -1", reward).replace(
        """        pick (Desk r) drive(r);
        served() = at_desk() == room1;
        visits() = visits() + 1;
""",
        body,
    )


def test_a_step_after_the_goal_in_a_loop_body_is_reported_once() -> None:
    body = """        while (!served()) { { pick (Desk r) drive(r); served() = at_desk() == room1; } visits() = 1; }
"""
    text = goal_solve("if (served()) 100 else -1", body)
    assert [m.split(" ", 1)[0] for m in found(text, "W0118")] == ["9:88"]  # `visits() = 1;`


@pytest.mark.parametrize(
    ("reward", "body"),
    [
        # through a procedure and a function with a sum
        ("visits() + (if (served()) 50 else 0)", "pick (Desk r) drive(r); served() = true; count();"),
        # a bonus less a cost
        ("if (served()) 1000 - visits() else 0", "pick (Desk r) drive(r); served() = true; count();"),
        # an action whose effect does not touch the goal
        ("if (at_desk() == room1) 10 else 0", "pick (Desk r) drive(r); tick();"),
    ],
)
def test_steps_after_the_goal_are_found_through_calls(reward: str, body: str) -> None:
    text = goal_solve(reward, body).replace(
        "procedure main()",
        "action tick() { effect: visits() = visits() + 1; }\n"
        "procedure count() { visits() = visits() + 1; }\nprocedure main()",
    )
    assert len(found(text, "W0118")) == 1


@pytest.mark.parametrize(
    ("reward", "body"),
    [
        ("if (served()) 100 else -1", "pick (Desk r) drive(r); visits() = 1; served() = at_desk() == room1;"),
        ("if (served()) 0 else -1", "pick (Desk r) drive(r); served() = true; visits() = 1;"),  # no bonus
        ("if (served()) -5 + visits() else 0", "served() = true; visits() = 1;"),  # no bonus
        ("if (served()) (100 - visits()) * 2 else 0", "served() = true; visits() = 1;"),  # not a plain sum
        ("if (at_desk() == room1) 10 else 0", "while (at_desk() != room1) pick (Desk r) drive(r);"),  # ends at the goal
        ("visits()", "pick (Desk r) drive(r); served() = true; visits() = 1;"),  # no goal
        ("if (served()) 10 else 0", "visits() = 1; test(true);"),  # nothing reaches the goal
        ("if (served()) 10 else 0", "served() = true; test(served());"),  # a test costs nothing
    ],
)
def test_rewards_that_pay_a_goal_once_are_not_reported(reward: str, body: str) -> None:
    assert found(goal_solve(reward, body), "W0118") == []


# ---------------------------------------------------------------- W0119 unwatched activity


def test_a_during_that_waits_and_cancels_is_reported_with_the_until_form() -> None:
    d = the(UNWATCHED, "W0119")
    assert (d.span.line, d.span.col, d.span.text) == (7, 9, "test(guest_left());")
    assert d.message == (
        "this `during` waits for `guest_left()` even after `roll(1)` has ended: "
        "if the activity ends or fails first, the program waits for ever"
    )
    assert d.fix is not None and d.fix.is_safe
    assert fixed(UNWATCHED, d).splitlines()[5:] == [
        "    during (roll(1)) until (guest_left()) {} on_fail {",
        "        say_sorry();",
        "    }",
        "}",
    ]
    after = lint(fixed(UNWATCHED, d))
    assert [x.code for x in after] == []


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("test(guest_left());", "say_sorry();\n        test(guest_left());"),  # a longer body
        ("test(guest_left());", "test(true);"),  # a constant condition would be W0107's as `until`
        ("procedure main() {", "procedure main() {\n    start(roll(1));"),  # its `start` would lose its end
    ],
)
def test_other_hanging_bodies_are_reported_without_a_fix(old: str, new: str) -> None:
    d = the(UNWATCHED.replace(old, new), "W0119")
    assert d.fix is None


@pytest.mark.parametrize(
    "body",
    [
        "{ test(guest_left()); cancel(roll(2)); }",  # another activity
        "{ cancel(roll(1)); }",
        "{ test(guest_left()); say_sorry(); }",
        "{ test(guest_left()); cancel(roll(1)); say_sorry(); }",
    ],
)
def test_other_bodies_are_not_reported(body: str) -> None:
    text = UNWATCHED.replace(
        """{
        test(guest_left());
        cancel(roll(1));
    }""",
        body,
    )
    assert found(text, "W0119") == []


@pytest.mark.parametrize(
    ("condition", "message"),
    [("true", "`until` condition is always true"), ("1 > 2", "`until` condition is always false")],
)
def test_a_constant_until_condition_is_reported(condition: str, message: str) -> None:
    text = UNWATCHED.replace("during (roll(1)) {", f"during (roll(1)) until ({condition}) {{")
    assert found(text, "W0107") == [f"6:29 {message}"]


def test_the_until_form_is_not_reported() -> None:
    text = UNWATCHED.replace("during (roll(1)) {", "during (roll(1)) until (guest_left()) {")
    assert found(text, "W0119") == []


# ---------------------------------------------------------------- W0120 unrun watch body


def test_a_watched_body_in_a_plan_is_reported() -> None:
    d = the(UNRUN_WATCH_BODY, "W0120")
    assert (d.span.line, d.span.col) == (7, 49)
    assert d.message == "the body of this `during ... until` never runs: it is planned by `solve` or `search`"


def test_a_watched_body_in_a_procedure_only_plans_call_is_reported() -> None:
    text = UNRUN_WATCH_BODY.replace(
        """        during (ride(1)) until (path_blocked()) {
            announce_ride();
        }
""",
        "        watch();\n",
    ).replace(
        "procedure main()",
        "procedure watch() { during (ride(2)) until (path_blocked()) test(true); }\nprocedure main()",
    )
    assert found(text, "W0120") == [
        "5:61 the body of this `during ... until` never runs: it is planned by `solve` or `search`"
    ]


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("announce_ride();", ""),  # an empty body
        ("solve(2, zero_reward()) {", "{"),  # online: the body runs while the activity does
        ("until (path_blocked()) ", ""),  # a plain `during` runs its body while planning too
    ],
)
def test_watched_bodies_that_run_or_do_nothing_are_not_reported(old: str, new: str) -> None:
    assert found(UNRUN_WATCH_BODY.replace(old, new), "W0120") == []


# ---------------------------------------------------------------- allow, no-lint, includes


def test_every_lint_has_a_trigger_here() -> None:
    assert sorted(TRIGGERS) == sorted(LINTS)


@pytest.mark.parametrize("code", sorted(TRIGGERS))
def test_allow_suppresses_a_lint_by_code_or_name(code: str) -> None:
    text = TRIGGERS[code]
    assert found(text, code) != []
    assert found(text, code, code) == []
    assert found(text, code, CODES[code].name.upper()) == []
    assert found(text, code, code.lower()) == []


def test_allow_leaves_the_other_lints_alone() -> None:
    codes = {d.code for d in lint(ONLINE, "W0105")}
    assert "W0105" not in codes
    assert "W0111" not in codes
    assert {d.code for d in lint(UNUSED, "W0105")} == {"W0101"}


def test_no_lint_reports_no_warnings() -> None:
    result = check_program(PATH, lint=False, overrides={PATH: UNUSED})
    assert result.diagnostics == []


def test_lints_do_not_report_included_files(tmp_path: Path) -> None:
    (tmp_path / "lib.gpp").write_text(
        "symbol domain Room = {hall, kitchen}\n"
        "number fluent unused_in_lib(Room r) { initially: (hall) = 0; }\n"
        "action go(Room hall) { }\n"
        "procedure wander() { pick (Room r) go(r); }\n"
    )
    main = tmp_path / "main.gpp"
    main.write_text('#include "lib.gpp"\nnumber fluent unused_here() { initially: () = 0; }\nprocedure main() { }\n')
    result = check_program(main)
    assert [(Path(d.span.source.path).name, d.code, d.message) for d in result.diagnostics] == [
        ("main.gpp", "W0101", "fluent `unused_here` is never used")
    ]
    # Checked as a root file of its own, the library gets its warnings.
    codes = sorted(d.code for d in check_program(tmp_path / "lib.gpp").diagnostics)
    assert codes == ["W0101", "W0101", "W0103", "W0105", "W0111"]


def test_lints_run_on_programs_with_model_errors() -> None:
    result = check_program(PATH, overrides={PATH: "procedure main() { undefined(); }\nnumber fluent f();\n"})
    assert [d.code for d in result.diagnostics] == ["E0103", "W0101", "W0103"]


# Lint warnings the shipped examples are allowed to have (none: examples are written clean).
KNOWN_EXAMPLE_WARNINGS: set[tuple[str, int, str]] = set()


@pytest.mark.parametrize("path", sorted(EXAMPLES_DIR.glob("*.gpp")), ids=lambda p: p.name)
def test_examples_have_no_unexpected_lint_warnings(path: Path) -> None:
    result = check_program(path)
    unexpected = [
        f"{d.span.line}:{d.span.col} {d.code} {d.message}"
        for d in result.diagnostics
        if (path.name, d.span.line, d.code) not in KNOWN_EXAMPLE_WARNINGS
    ]
    assert unexpected == []
