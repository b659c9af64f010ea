"""The test vectors of LANGUAGE.md Appendix D (§16, #1-#86) whose verdict the checker decides.

Each vector gets the recommended ("Rec") result, overruled by SEMANTICS.md where the two differ.
The vectors in the appendix omit their context declarations (fluents `p() q() r()` of type bool,
`x()` number, the domains, the actions called); here every vector is a complete program, so the
verdict is about the vector and not about a missing declaration.

A vector is either accepted (no error at all from loading, parsing and checking) or rejected with
exactly the listed errors (code, line, column). Vectors decided by the syntax alone (#10, #22,
#26, #58 rejected; #1, #2, #4, #5, #11, #12, #14, #15, #19, #23, #25, #55, #56, #77 about
precedence, literals and layout) are in tests/syntax/test_vectors.py.

SEMANTICS §2.4 overrules LANGUAGE.md §3.5 rule 4 in one place that matters here: domain
membership is checked statically for literals only and for computed values at run time, so an
expression of type `symbol` or of another symbol domain is accepted by a domain slot (#70), while
a literal that is not a member is an error (#34, #35, #69).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.check import CheckResult, check_text
from gpp.model.symbols import SymbolKind
from gpp.model.types import NUMBER, STRING, Sym
from gpp.syntax import ast

# ---------------------------------------------------------------- helpers


def check(text: str, path: Path = Path("vector.gpp")) -> CheckResult:
    return check_text(text, path, lint=False)


def errors(result: CheckResult) -> list[tuple[str, int, int]]:
    return [(d.code, d.span.line, d.span.col) for d in result.diagnostics if d.is_error]


def describe(result: CheckResult) -> str:
    return "\n".join(f"{d.span.line}:{d.span.col} {d.code} {d.message}" for d in result.diagnostics)


def accepted(text: str, path: Path = Path("vector.gpp")) -> CheckResult:
    result = check(text, path)
    assert [d for d in result.diagnostics if d.is_error] == [], "unexpected errors:\n" + describe(result)
    return result


BOOLS = """\
bool fluent p() { initially: () = true; }
bool fluent q() { initially: () = true; }
bool fluent r() { initially: () = false; }
bool fluent b() { initially: () = false; }
number fluent x() { initially: () = 1; }
"""

BLOCKS = """\
symbol domain block = {a, b, c}
symbol domain location = block | {table}
action stack(block x, location y) {}
"""


# ---------------------------------------------------------------- accepted


ACCEPTED = [
    # 3: a boolean `==` next to `&` (re-associated, see the test below).
    (3, BOOLS + "bool function f() = p() == q() & r()"),
    # 6-8: comparisons inside boolean chains type as bool.
    (6, BOOLS + "bool function f() = !x() > 3 & p()"),
    (7, BOOLS + "bool function f() = b() -> x() > 0"),
    (8, BOOLS + "bool function f() = x() > 0 -> b()"),
    # 9: unary minus on a number parameter.
    (9, "number function f(number x) = -x"),
    # 16: string concatenation.
    (16, 'string function f() = "a" + "b" + "c"'),
    # 17: a conditional expression in a boolean position.
    (17, BOOLS + "bool function f() = if (p()) true else false"),
    # 20, 21, 78: names that begin with a keyword are ordinary actions.
    (20, "action testing() {}\nprocedure main() { testing(); }"),
    (21, "action startx() {}\nprocedure main() { startx(); }"),
    (78, "action listen() {}\nprocedure main() { listen(); }"),
    # 24: a trailing anonymous block is `procedure main()`.
    (24, "bool fluent p() { initially: () = true; }\n{ test(p()); }"),
    # 27: a bare `list[T]` line is an idempotent no-op.
    (27, "list[number]\nlist[number]\nlist[number] fluent l() { initially: () = list[number] []; }"),
    # 44: self-recursion without a forward declaration (SEMANTICS §2.1).
    (44, "action a() {}\nprocedure p() { a(); p(); }"),
    # 49: `pick` without `in` ranges over the domain.
    (49, "symbol domain Blk = {a, b}\naction act(Blk x) {}\nprocedure main() { pick (Blk y) act(y); }"),
    # 50: push_back of an element of the list's type.
    (50, "list[number] fluent l() { initially: () = list[number] []; }\nprocedure main() { push_back(l(), 3); }"),
    # 52-54: `during` with optional handlers; the handlers are statements.
    (52, "action d() {}\nprocedure main() { during (d()) { d(); } }"),
    (
        53,
        "action a() {}\naction b() {}\naction c() {}\naction d(number n) {}\n"
        "procedure main() { during (d(2)) a(); on_fail b(); on_cancel c(); }",
    ),
    (
        54,
        "action a() {}\naction b() {}\naction d(number n) {}\n"
        "procedure main() { during (d(2)) { a(); } on_cancel b(); }",
    ),
    # 59, 60: mapping values are general expressions over the parameters.
    (
        59,
        "bool fluent f() { initially: () = true; }\n"
        "action a(number x, string s) {\n"
        '  mapping: "m" { gx = x * 2, label = s + "!", c = "c", flu = f(), b = (x > 1) }\n'
        "}",
    ),
    (60, 'action a(number x) { mapping: "m" { b = x > 1 } }'),
    # 63-66: names that begin like builtins, indexing a parenthesised list, to_string of a string.
    (63, "number fluent lengthy() { initially: () = 1; }\nbool function f() = lengthy() > 0"),
    (64, "number function info() = 1\nnumber function f() = info()"),
    (65, "list[number] fluent l() { initially: () = list[number] [1]; }\nnumber function f() = (l())[0]"),
    (66, 'string fluent s() { initially: () = "s"; }\nstring function f() = to_string(s())'),
    # 68: the parameter shadows the symbol `x` (see the test below).
    (68, "symbol domain D = {x, y}\naction act(D x) { precondition: x == y }"),
    # 70: a `symbol` variable passed to a `location` parameter: domain membership of computed
    # values is checked at run time (SEMANTICS §2.4), so it is accepted statically, although
    # LANGUAGE.md §3.5 rule 4 and the Rec column reject it.
    (70, BLOCKS + "procedure main() { pick (symbol s in {a}) stack(a, s); }"),
    # 71: proper lexical shadowing of a parameter by a pick variable of another type.
    (71, 'procedure main(number x) { pick (string x in {"a"}) test(x == "a"); test(x > 0); }'),
    # 73: component sections in any order; the clock is known before the state invariant uses it.
    (73, "component cam { states: off, boot(c1 <= 4), on clocks: c1 transitions: off => boot resets(c1) }"),
    # 74: a bounded `until` in a constraint.
    (
        74,
        "action a(number n) {}\ncomponent c { states: off, on }\n"
        "constraints { during(a(*)): state(c) = off until[, 3] state(c) = on; }",
    ),
    # 75: a recursive function through a conditional, forward-declared.
    (75, "number function fac(number n);\nnumber function fac(number n) = if (n <= 1) 1 else n * fac(n - 1)"),
    # 79, 80: a conditional expression as an operand of a comparison.
    (79, BOOLS + "bool function f() = if (p()) 1 else 2 > 0"),
    (80, BOOLS + "bool function k() = 0 < if (p()) 1 else 2"),
    # 81: `silent: null` means the default.
    (81, "action a() { silent: null }"),
    # 82: a fluent whose name begins with `list`.
    (
        82,
        "number fluent listing() { initially: () = 1; }\nprocedure main() { listing() = 2; test(listing() + 1 > 0); }",
    ),
    # 83: `searchX();` calls the procedure `searchX`, not `search X();`.
    (83, "procedure searchX();\naction X() {}\nprocedure main() { searchX(); }"),
    # 85: arithmetic with a parameter and negative literals.
    (85, "number function f(number x) = 5 -3 + x-1 + 2*-3 - -4"),
]


@pytest.mark.parametrize(("vector", "source"), ACCEPTED, ids=[f"#{v}" for v, _ in ACCEPTED])
def test_vector_is_accepted_by_the_checker(vector: int, source: str) -> None:
    accepted(source)


# ---------------------------------------------------------------- rejected


REJECTED = [
    # 13, 84: `inf`, `nan` and friends are not literals but names (SEMANTICS §1.3).
    (13, "number function f() = inf", [("E0101", 1, 23)]),
    (
        84,
        "number function f() = INF\nnumber function g() = -infinity\nnumber function h() = NaN",
        [("E0101", 1, 23), ("E0101", 2, 24), ("E0101", 3, 23)],
    ),
    # 18: comparisons do not chain.
    (18, "bool function f() = 1 < 2 < 3", [("E0205", 1, 21)]),
    # 28: literal list elements are checked against the element type.
    (
        28,
        'list[number] fluent l() { initially: () = list[number]["a", true]; }',
        [("E0202", 1, 56), ("E0202", 1, 61)],
    ),
    # 29, 30: every field of a compound literal is required, constant or not.
    (
        29,
        "compound Pose { number x, number y, string frame }\n"
        "Pose fluent p() { initially: () = Pose { x = 1, y = 2 }; }",
        [("E0208", 2, 35)],
    ),
    (
        30,
        "compound Pose { number x, number y, string frame }\nPose function mk(number a) = Pose { x = a, y = a }",
        [("E0208", 2, 30)],
    ),
    # 31: no such field (and the one field `x` is then missing).
    (31, "compound P { number x }\nP function f() = P { y = 1 }", [("E0208", 2, 18), ("E0106", 2, 22)]),
    # 32: a field value of the wrong type.
    (32, 'compound P { number x }\nP function f() = P { x = "a" }', [("E0202", 2, 26)]),
    # 33: compound values cannot be compared.
    (
        33,
        "compound P { number x }\nP fluent p() { initially: () = P { x = 1 }; }\n"
        "bool function c() = p() == P { x = 1 }",
        [("E0209", 3, 21)],
    ),
    # 34: an unknown symbol is a name error.
    (34, "symbol domain A = {a, b, c}\nA fluent f() { initially: () = zzz; }", [("E0101", 2, 32)]),
    # 35: a symbol of another domain is not a member of the fluent's domain.
    (
        35,
        "symbol domain block = {a, b, c}\nsymbol domain other = {table}\nblock fluent bf() { initially: () = table; }",
        [("E0203", 3, 37)],
    ),
    # 37: one global namespace: a fluent and an action cannot share a name.
    (37, "bool fluent x() { initially: () = true; }\naction x() {}", [("E0302", 2, 8)]),
    # 38, 39: a definition must agree with its forward declaration.
    (38, "action a(number x);\naction a(string x) {}", [("E0303", 2, 17)]),
    (39, "bool fluent f();\nnumber fluent f() { initially: () = 1; }", [("E0303", 2, 1)]),
    # 40, 41: initial values must fit the fluent's parameters.
    (40, "number fluent f(number x) { initially: () = 1; }", [("E0307", 1, 40)]),
    (41, "number fluent f(number x, number y) { initially: (y, 2) = 1; }", [("E0307", 1, 51)]),
    # 42, 43: only fluents (and paths into them) can be assigned.
    (42, "procedure main(number x) { x = 1; }", [("E0306", 1, 28)]),
    (43, "compound P { number x }\nprocedure main(P p) { p.x = 1; }", [("E0306", 2, 23)]),
    # 45, 46: functions and exogenous actions are not statements.
    (45, "bool function goal() = true\nprocedure main() { goal(); }", [("E0104", 2, 20)]),
    (46, "exog_action ev(number n) {}\nprocedure main() { ev(1); }", [("E0104", 2, 20)]),
    # 47: the reward of `solve` is a function, not a fluent.
    (
        47,
        "number fluent n() { initially: () = 1; }\naction a() {}\nprocedure main() { solve(4, n()) a(); }",
        [("E0212", 3, 29)],
    ),
    # 51: push_back of a list onto a list of numbers.
    (
        51,
        "list[number] fluent l() { initially: () = list[number] []; }\nprocedure main() { push_back(l(), l()); }",
        [("E0202", 2, 35)],
    ),
    # 57: arity.
    (57, "action a(number x) {}\nprocedure main() { a(1, 2); }", [("E0201", 2, 20)]),
    # 61: an exogenous action's mapping must bind every parameter.
    (61, 'exog_action ev(number n, string s) { mapping: "t" { nn = n } }', [("E0308", 1, 47)]),
    # 62: an exogenous mapping entry must be a plain parameter (so `n` is then unbound too).
    (62, 'exog_action ev(number n) { mapping: "t" { nn = n + 1 } }', [("E0308", 1, 37), ("E0308", 1, 48)]),
    # 67: a bare global name is not a call.
    (67, "bool fluent p() { initially: () = true; }\nbool function f() = p", [("E0102", 2, 21)]),
    # 69: a literal symbol that is not in the parameter's domain (`z` is in another domain).
    (
        69,
        BLOCKS + "symbol domain other = {z}\nprocedure main() { stack(z, a); }",
        [("E0203", 5, 26)],
    ),
    # 72: quantifiers need a finite range (SEMANTICS §2.5).
    (72, "bool function e() = exists(number n) n > 3", [("E0210", 1, 28)]),
]


@pytest.mark.parametrize(("vector", "source", "expected"), REJECTED, ids=[f"#{v}" for v, _, _ in REJECTED])
def test_vector_is_rejected_with_exactly_these_errors(
    vector: int, source: str, expected: list[tuple[str, int, int]]
) -> None:
    result = check(source)
    assert errors(result) == expected, describe(result)


def test_vector_48_variable_in_a_pick_value_list_is_rejected() -> None:
    result = check("action a(number x) {}\nprocedure main(number k) { pick (number x in {1, k}) a(x); }")
    assert errors(result) == [("E0213", 2, 50)], describe(result)


def test_vector_48_variable_of_an_enclosing_pick_in_a_value_list_is_rejected() -> None:
    result = check("action a(number x) {}\nprocedure main() { pick (number k in {1}) pick (number x in {k}) a(x); }")
    assert errors(result) == [("E0213", 2, 62)], describe(result)


def test_initial_value_naming_a_parameter_is_rejected() -> None:
    result = check("number fluent f(number x) { initially: (x) = x; }")
    assert errors(result) == [("E0213", 1, 46)], describe(result)


# ---------------------------------------------------------------- the details of some verdicts


def test_vector_3_boolean_equality_is_looser_than_and() -> None:
    result = accepted(BOOLS + "bool function f() = p() == q() & r()")
    model = result.model
    decl = model.globals["f"].decl
    assert isinstance(decl, ast.FunctionDecl) and decl.body is not None
    e = model.effective(decl.body)
    assert isinstance(e, ast.Binary) and e.op is ast.BinaryOp.EQ
    assert isinstance(e.right, ast.Binary) and e.right.op is ast.BinaryOp.AND
    assert model.target(e.left) is model.globals["p"]


def test_vector_13_inf_is_an_ordinary_name_when_declared() -> None:
    result = accepted("number function f(number inf) = inf")
    assert result.model.globals["f"].params[0].name == "inf"


def test_vector_13_unknown_inf_is_reported_as_an_unknown_name() -> None:
    result = check("number function f() = inf")
    (d,) = result.diagnostics
    assert d.message == "unknown name `inf`"


def test_vector_24_trailing_block_becomes_main_and_clashes_with_a_declared_main() -> None:
    result = accepted("bool fluent p() { initially: () = true; }\n{ test(p()); }")
    main = result.model.main
    assert main is not None
    assert (main.name, main.kind) == ("main", SymbolKind.PROCEDURE)
    result = check("procedure main() {}\n{ test(true); }")
    assert errors(result) == [("E0310", 2, 1)], describe(result)


def test_vector_36_domain_expression_groups_to_the_right() -> None:
    result = accepted(
        "symbol domain A = {a, b}\nsymbol domain B = {a, c}\nsymbol domain E = A | B \\ {a}\n"
        "symbol domain F = (A | B) \\ {a}"
    )
    e, f = result.model.domain("E"), result.model.domain("F")
    assert e is not None and f is not None
    assert e.values == (Sym("a"), Sym("b"), Sym("c"))  # A | (B \ {a})
    assert f.values == (Sym("b"), Sym("c"))


def test_vector_44_recursive_call_targets_the_procedure_itself() -> None:
    result = accepted("action a() {}\nprocedure p() { a(); p(); }")
    p = result.model.globals["p"]
    calls = result.model.references_to(p, include_declaration=False)
    assert [(r.span.line, r.span.col) for r in calls] == [(2, 22)]


def test_vector_49_pick_without_in_over_an_infinite_type_is_rejected() -> None:
    # The companion of #49: without `in`, the variable's type must be finite (SEMANTICS §2.5).
    result = check("action act(number x) {}\nprocedure main() { pick (number y) act(y); }")
    assert errors(result) == [("E0210", 2, 26)], describe(result)


def test_vector_68_parameter_shadows_the_symbol_of_the_same_name() -> None:
    result = accepted("symbol domain D = {x, y}\naction act(D x) { precondition: x == y }")
    model = result.model
    act = model.globals["act"]
    decl = act.decl
    assert isinstance(decl, ast.ActionDecl)
    precondition = decl.section(ast.PreconditionSection)
    assert isinstance(precondition, ast.PreconditionSection)
    condition = precondition.condition
    assert isinstance(condition, ast.Binary)
    assert model.target(condition.left) is act.params[0]
    assert model.target(condition.right) is model.symbols["y"]


def test_vector_68_shadowing_a_symbol_is_a_warning_not_an_error() -> None:
    # Rec: "`x` is the parameter (+ warning)"; SEMANTICS §2.2: shadowing a symbol is a lint warning.
    result = check_text("symbol domain D = {x, y}\naction act(D x) { precondition: x == y }", Path("vector.gpp"))
    assert [d for d in result.diagnostics if d.is_error] == [], describe(result)
    shadowing = [(d.code, d.span.line, d.span.col) for d in result.diagnostics if d.code == "W0111"]
    assert shadowing == [("W0111", 2, 14)], describe(result)


@pytest.mark.parametrize(
    "source",
    [
        # A `symbol` variable for a `location` parameter (the vector itself).
        BLOCKS + "procedure main() { pick (symbol s in {a}) stack(a, s); }",
        # A `symbol` fluent for a `block` parameter.
        BLOCKS + "symbol fluent held() { initially: () = a; }\nprocedure main() { stack(held(), table); }",
        # An expression of another domain (a superset) for a `block` parameter.
        BLOCKS + "location fluent spot() { initially: () = a; }\nprocedure main() { stack(spot(), table); }",
        # An expression of a disjoint domain: still a run-time check.
        BLOCKS + "symbol domain other = {z}\nother fluent o() { initially: () = z; }\n"
        "procedure main() { stack(o(), table); }",
    ],
    ids=["symbol-variable", "symbol-fluent", "superset-domain", "disjoint-domain"],
)
def test_vector_70_computed_values_for_a_domain_slot_are_checked_at_run_time(source: str) -> None:
    # SEMANTICS §2.4: membership of computed values is checked at run time, not statically.
    accepted(source)


def test_vector_70_a_value_of_another_element_type_is_still_a_type_error() -> None:
    result = check(BLOCKS + 'procedure main() { stack("a", table); }')
    assert errors(result) == [("E0202", 4, 26)], describe(result)


def test_vector_69_unknown_symbol_is_a_name_error() -> None:
    # Without any domain holding `z`, the literal is an unknown name (as in #34).
    result = check(BLOCKS + "procedure main() { stack(z, a); }")
    assert errors(result) == [("E0101", 4, 26)], describe(result)


def test_vector_69_not_in_domain_message_names_the_value_and_the_domain() -> None:
    result = check(BLOCKS + "symbol domain other = {z}\nprocedure main() { stack(z, a); }")
    (d,) = result.diagnostics
    assert d.message == "`z` is not in domain `block`"


def test_vector_71_pick_variable_shadows_the_parameter_only_inside_the_pick() -> None:
    result = accepted('procedure main(number x) { pick (string x in {"a"}) test(x == "a"); test(x > 0); }')
    model = result.model
    (param,) = model.globals["main"].params
    uses = [r for r in model.references if r.span.text == "x" and not r.declaration]
    assert [(r.span.col, r.symbol.kind, r.symbol.type) for r in uses] == [
        (58, SymbolKind.VARIABLE, STRING),
        (74, SymbolKind.PARAMETER, NUMBER),
    ]
    assert uses[1].symbol is param


def test_vector_75_recursive_function_resolves_to_the_one_symbol() -> None:
    result = accepted(
        "number function fac(number n);\nnumber function fac(number n) = if (n <= 1) 1 else n * fac(n - 1)"
    )
    fac = result.model.globals["fac"]
    assert fac.is_defined
    assert [(r.span.line, r.span.col, r.declaration) for r in result.model.references_to(fac)] == [
        (1, 17, True),
        (2, 17, True),
        (2, 56, False),
    ]


def test_vector_76_name_declared_in_an_included_file(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("bool fluent p() { initially: () = true; }\n")
    result = accepted('#include "sub.gpp"\nbool function g() = p()', tmp_path / "main.gpp")
    p = result.model.globals["p"]
    assert p.span is not None
    assert Path(p.span.source.path).name == "sub.gpp"


def test_vector_76_without_the_include_the_name_is_unknown(tmp_path: Path) -> None:
    result = check("bool function g() = p()", tmp_path / "main.gpp")
    assert errors(result) == [("E0103", 1, 21)], describe(result)


def test_vector_86_file_with_only_an_include_is_a_program(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("action a() {}\nprocedure main() { a(); }\n")
    result = accepted('#include "sub.gpp"\n', tmp_path / "main.gpp")
    assert result.model.main is result.model.globals["main"]


def test_vector_83_call_targets_the_procedure_named_with_a_keyword_prefix() -> None:
    result = accepted("procedure searchX();\naction X() {}\nprocedure main() { searchX(); }")
    search_x = result.model.globals["searchX"]
    calls = result.model.references_to(search_x, include_declaration=False)
    assert [(r.span.line, r.span.col) for r in calls] == [(3, 20)]
