"""Tests of the pretty-printer (gpp/syntax/printer.py).

Property tests generate random syntax trees over the whole language, only trees the parser can
produce, and check that printing then parsing gives the same tree back without diagnostics and
that printing is idempotent. Example tests pin the canonical text of tricky expressions and
statements.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gpp.syntax import ast
from gpp.syntax.parser import parse_text
from gpp.syntax.printer import format_expr, format_program, format_stmt, format_string, number_literal
from tests.support.budget import examples
from tests.support.syntax_trees import (
    NAMES,
    RESERVED,
    SPAN,
    binary,
    call,
    exprs,
    make_during,
    make_if,
    make_program,
    maybe_paren,
    n,
    negate,
    platform_declarations,
    programs,
    strings,
)

SETTINGS = settings(
    max_examples=examples(300),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def test_name_pool_has_no_keywords() -> None:
    assert not RESERVED & set(NAMES)


# ---------------------------------------------------------------- strategies: basics


# ---------------------------------------------------------------- strategies: expressions


_OPERATOR_LEAVES: st.SearchStrategy[ast.Expr] = maybe_paren(
    st.one_of(
        st.integers(-3, 3).map(lambda v: ast.NumberLit(span=SPAN, value=v)),
        st.sampled_from(NAMES[:3]).map(lambda n: ast.Name(span=SPAN, name=n)),
    )
)


@st.composite
def operator_exprs(draw: st.DrawFn, budget: int | None = None) -> ast.Expr:
    """Expressions made of operators and greedy forms (where precedence, associativity and the
    extent of quantifier bodies and else branches decide the parentheses), of about `budget`
    nodes; an explicit budget gives larger trees than recursion by depth, which mostly stops
    at a leaf early."""
    if budget is None:
        budget = draw(st.integers(1, 24))
    if budget <= 1:
        return draw(_OPERATOR_LEAVES)
    rest = budget - 1
    kinds = ["not", "neg", "exists", "field", "index"] + (["binary", "binary", "binary", "if"] if rest >= 2 else [])
    kind = draw(st.sampled_from(kinds))
    node: ast.Expr
    if kind == "binary":
        left = draw(st.integers(1, rest - 1))
        node = ast.Binary(
            span=SPAN,
            op=draw(st.sampled_from(ast.BinaryOp)),
            left=draw(operator_exprs(left)),
            right=draw(operator_exprs(rest - left)),
        )
    elif kind == "if":
        then = draw(st.integers(1, rest - 1))
        node = cond(draw(_OPERATOR_LEAVES), draw(operator_exprs(then)), draw(operator_exprs(rest - then)))
    elif kind == "not":
        node = not_(draw(operator_exprs(rest)))
    elif kind == "neg":
        node = negate(draw(operator_exprs(rest)))
    elif kind == "exists":
        node = replace(exists(draw(operator_exprs(rest))), quantifier=draw(st.sampled_from(ast.Quantifier)))
    elif kind == "field":
        node = ast.FieldAccess(span=SPAN, subject=draw(operator_exprs(rest)), field=ast.Ident(span=SPAN, name="f"))
    else:
        node = ast.Index(span=SPAN, subject=draw(operator_exprs(rest)), index=draw(_OPERATOR_LEAVES))
    return replace(node, parenthesized=True) if draw(st.integers(0, 7)) == 0 else node


# ---------------------------------------------------------------- strategies: statements


# ---------------------------------------------------------------- strategies: declarations


# ---------------------------------------------------------------- properties


def reparse(text: str) -> ast.Program:
    result = parse_text(text)
    assert not result.diagnostics, (text, [d.message for d in result.diagnostics])
    return result.program


@SETTINGS
@given(programs)
def test_program_round_trip(program: ast.Program) -> None:
    text = format_program(program)
    assert reparse(text) == program, text


@SETTINGS
@given(programs)
def test_program_formatting_is_idempotent(program: ast.Program) -> None:
    text = format_program(program)
    assert format_program(reparse(text)) == text


@SETTINGS
@given(exprs(4) | operator_exprs())
def test_expression_round_trip(expr: ast.Expr) -> None:
    text = format_program(make_program([function(expr)], None))
    decl = reparse(text).declarations[0]
    assert isinstance(decl, ast.FunctionDecl)
    assert decl.body == expr, text


@SETTINGS
@given(st.lists(platform_declarations(depth=4), min_size=1, max_size=2))
def test_platform_model_round_trip(decls: list[ast.Decl]) -> None:
    program = make_program(decls, None)
    text = format_program(program)
    assert reparse(text) == program, text
    assert format_program(reparse(text)) == text


@SETTINGS
@given(strings)
def test_string_literal_round_trip(value: str) -> None:
    decl = reparse(f"string function f() = {format_string(value)}").declarations[0]
    assert isinstance(decl, ast.FunctionDecl) and isinstance(decl.body, ast.StringLit)
    assert decl.body.value == value


# ---------------------------------------------------------------- example-based tests


def function(body: ast.Expr) -> ast.FunctionDecl:
    return ast.FunctionDecl(
        span=SPAN,
        type=ast.NamedType(span=SPAN, name="number"),
        name=ast.Ident(span=SPAN, name="f"),
        params=(),
        body=body,
    )


def parse_expr(text: str) -> ast.Expr:
    decl = reparse(f"number function f() = {text}").declarations[0]
    assert isinstance(decl, ast.FunctionDecl) and decl.body is not None
    return decl.body


def parse_stmt(text: str) -> ast.Statement:
    decl = reparse(f"procedure p() {text}").declarations[0]
    assert isinstance(decl, ast.ProcedureDecl) and decl.body is not None
    return decl.body


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("a*b + c*d", "a * b + c * d"),
        ("(a + b) * c", "(a + b) * c"),
        ("a + (b * c)", "a + (b * c)"),
        ("2 ** 3 ** 2", "2 ** 3 ** 2"),
        ("2 ** (3 ** 2)", "2 ** (3 ** 2)"),
        ("!exists(block z) p(z) | q()", "!exists(block z) p(z) | q()"),
        ("(exists(block z) p(z)) | q()", "(exists(block z) p(z)) | q()"),
        ("if (c) 1 else 2 > 0", "if (c) 1 else 2 > 0"),
        ("if (c) 1 else 2 + 3 > 0", "if (c) 1 else 2 + 3 > 0"),
        ("(if (c) 1 else 2) > 0", "(if (c) 1 else 2) > 0"),
        ("a + if (c) 1 else 2 > 0", "a + if (c) 1 else 2 > 0"),
        ("if (c) p else q & r -> s", "if (c) p else q & r -> s"),
        ("0 < if (c) 1 else 2", "0 < if (c) 1 else 2"),
        ("1 + (if (c) 1 else 2) * 3", "1 + (if (c) 1 else 2) * 3"),
        ("1 + if (c) 1 else 2 * 3", "1 + if (c) 1 else 2 * 3"),
        ("if (a) 1 else if (b) 2 else 3", "if (a) 1 else if (b) 2 else 3"),
        ("- -4", "- -4"),
        ("-(-4)", "-(-4)"),
        ("-(4)", "-(4)"),
        ("- 4", "-4"),
        ("+4", "4"),
        ("-x ** 2", "-x ** 2"),
        ("-(x ** 2)", "-(x ** 2)"),
        ("- -x", "- -x"),
        ("(l())[0]", "(l())[0]"),
        ("f().x[1]", "f().x[1]"),
        ("(a + b).x", "(a + b).x"),
        ("!p() == q()", "!p() == q()"),
        ("x()>0->b()", "x() > 0 -> b()"),
        ("p & q | r & s", "p & q | r & s"),
        ("a - (b - c)", "a - (b - c)"),
        ("1.5e-3 + .5 + 1. + 1e3", "0.0015 + 0.5 + 1.0 + 1000.0"),
        ("Pose { x = 1, start = 2 }", "Pose { x = 1, start = 2 }"),
        ("Pose {}", "Pose {}"),
        ("list[list[Item]] [list[Item] [], list[Item] [cup]]", "list[list[Item]] [list[Item] [], list[Item] [cup]]"),
        ("length(to_string(1))", "length(to_string(1))"),
        ('"x\\y" + "\\"" + "\\\\"', '"x\\y" + "\\"" + "\\\\"'),
    ],
)
def test_expression_canonical_text(source: str, expected: str) -> None:
    tree = parse_expr(source)
    assert format_expr(tree) == expected
    assert parse_expr(expected) == tree


def name(text: str) -> ast.Name:
    return ast.Name(span=SPAN, name=text)


def neg(operand: ast.Expr) -> ast.Unary:
    return ast.Unary(span=SPAN, op=ast.UnaryOp.NEG, operand=operand)


def not_(operand: ast.Expr) -> ast.Unary:
    return ast.Unary(span=SPAN, op=ast.UnaryOp.NOT, operand=operand)


def cond(c: ast.Expr, then: ast.Expr, otherwise: ast.Expr) -> ast.Conditional:
    return ast.Conditional(span=SPAN, condition=c, then=then, otherwise=otherwise)


def exists(body: ast.Expr) -> ast.Quantified:
    return ast.Quantified(
        span=SPAN,
        quantifier=ast.Quantifier.EXISTS,
        var_type=ast.NamedType(span=SPAN, name="T"),
        var=ast.Ident(span=SPAN, name="z"),
        body=body,
    )


@pytest.mark.parametrize(
    ("tree", "expected"),
    [
        # Parentheses the tree needs though no flag asks for them.
        (binary("**", n(2), binary("**", n(3), n(2))), "2 ** (3 ** 2)"),
        (binary("*", binary("+", name("a"), name("b")), name("c")), "(a + b) * c"),
        (binary("-", name("a"), binary("-", name("b"), name("c"))), "a - (b - c)"),
        # A conditional's else branch is a sum: it takes in `+` and tighter, nothing looser.
        (binary(">", cond(name("c"), n(1), n(2)), n(0)), "if (c) 1 else 2 > 0"),
        (binary("&", cond(name("c"), name("p"), name("q")), name("r")), "if (c) p else q & r"),
        (binary("+", cond(name("c"), n(1), n(2)), n(3)), "(if (c) 1 else 2) + 3"),
        (binary("**", cond(name("c"), n(1), n(2)), n(3)), "(if (c) 1 else 2) ** 3"),
        (cond(name("c"), n(1), binary("+", n(2), n(3))), "if (c) 1 else 2 + 3"),
        (binary(">", binary("+", name("a"), cond(name("c"), n(1), n(2))), n(0)), "a + if (c) 1 else 2 > 0"),
        (binary("+", binary("+", name("a"), cond(name("c"), n(1), n(2))), n(0)), "(a + if (c) 1 else 2) + 0"),
        (binary("&", not_(cond(name("c"), name("p"), name("q"))), name("r")), "!if (c) p else q & r"),
        (binary(">", not_(cond(name("c"), name("p"), name("q"))), n(0)), "(!if (c) p else q) > 0"),
        (cond(name("c"), n(1), binary(">", n(2), n(0))), "if (c) 1 else (2 > 0)"),
        (binary("*", binary("+", n(1), cond(name("c"), n(1), n(2))), n(3)), "(1 + if (c) 1 else 2) * 3"),
        (binary("|", binary("&", name("p"), exists(name("q"))), name("r")), "(p & exists(T z) q) | r"),
        (binary("&", exists(name("q")), name("r")), "(exists(T z) q) & r"),
        (exists(binary("&", name("q"), name("r"))), "exists(T z) q & r"),
        (not_(binary("&", name("p"), name("q"))), "!(p & q)"),
        (binary("==", not_(name("a")), name("b")), "(!a) == b"),
        (not_(binary("==", name("a"), name("b"))), "!a == b"),
        (binary("<", binary("<", n(1), n(2)), n(3)), "1 < 2 < 3"),
        (binary("<", n(1), binary("<", n(2), n(3))), "1 < (2 < 3)"),
        (neg(binary("+", name("a"), name("b"))), "-(a + b)"),
        (neg(cond(name("c"), n(1), n(2))), "-if (c) 1 else 2"),
        (binary("**", neg(name("x")), n(2)), "-x ** 2"),
        (binary("**", n(2), neg(name("x"))), "2 ** -x"),
        (binary("-", name("a"), n(-4)), "a - -4"),
        # Negative literals, and a minus the parser would otherwise fold into the literal.
        (n(-5), "-5"),
        (neg(n(4)), "-(4)"),
        (neg(n(-4)), "- -4"),
        (neg(neg(name("x"))), "- -x"),
        (neg(n(-0.0)), "-(-0.0)"),
        (ast.Index(span=SPAN, subject=n(-5), index=n(0)), "(-5)[0]"),
        (ast.FieldAccess(span=SPAN, subject=n(1), field=ast.Ident(span=SPAN, name="x")), "(1).x"),
        (ast.Index(span=SPAN, subject=call("l"), index=n(0)), "l()[0]"),
        (ast.Index(span=SPAN, subject=binary("+", name("a"), name("b")), index=n(0)), "(a + b)[0]"),
        (ast.Index(span=SPAN, subject=cond(name("c"), name("l"), name("m")), index=n(0)), "(if (c) l else m)[0]"),
        # The user's redundant parentheses are kept.
        (binary("+", name("a"), replace(binary("*", name("b"), name("c")), parenthesized=True)), "a + (b * c)"),
        (replace(name("a"), parenthesized=True), "(a)"),
        (n(1e16), "1e+16"),
        (n(0.1), "0.1"),
        (n(10**30), "1000000000000000000000000000000"),
    ],
)
def test_expression_tree_text(tree: ast.Expr, expected: str) -> None:
    assert format_expr(tree) == expected
    assert parse_expr(expected) == tree


def test_numbers_without_literal_are_rejected() -> None:
    with pytest.raises(ValueError):
        number_literal(float("inf"))
    with pytest.raises(ValueError):
        number_literal(float("nan"))


@pytest.mark.parametrize(
    ("value", "literal"),
    [
        ("plain", '"plain"'),
        ('say "hi"', '"say \\"hi\\""'),
        ("x\\y", '"x\\y"'),
        ("end\\", '"end\\\\"'),
        ("a\\\\b", '"a\\\\\\b"'),
        ('\\"', '"\\\\\\""'),
        ("two\nlines", '"two\nlines"'),
    ],
)
def test_string_literals(value: str, literal: str) -> None:
    assert format_string(value) == literal
    assert parse_expr(literal) == ast.StringLit(span=SPAN, value=value)


def stmt(text: str) -> ast.CallStmt:
    return ast.CallStmt(span=SPAN, call=call(text))


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        (
            "if (c) if (d) a(); else b();",
            "if (c)\n    if (d)\n        a();\n    else\n        b();",
        ),
        (
            "if (c) { if (d) a(); } else b();",
            "if (c) {\n    if (d)\n        a();\n} else\n    b();",
        ),
        (
            "if (c) { a(); } else if (d) { b(); } else { e(); }",
            "if (c) {\n    a();\n} else if (d) {\n    b();\n} else {\n    e();\n}",
        ),
        (
            "if (c) a(); else if (d) b(); else e();",
            "if (c)\n    a();\nelse if (d)\n    b();\nelse\n    e();",
        ),
        (
            "during (a()) { b(); } on_cancel { d(); } on_fail c();",
            "during (a()) {\n    b();\n} on_fail\n    c();\non_cancel {\n    d();\n}",
        ),
        ("during (d()) { d(); }", "during (d()) {\n    d();\n}"),
        (
            "during (a()) during (b()) c(); on_fail d();",
            "during (a())\n    during (b())\n        c();\n    on_fail\n        d();",
        ),
        (
            "{ while (x() < 3) { push_back(l(), 3); pop_front(l()); } test(p()); start(a(1)); (true) = 1; }",
            "{\n    while (x() < 3) {\n        push_back(l(), 3);\n        pop_front(l());\n    }\n    test(p());\n"
            "    start(a(1));\n    (true) = 1;\n}",
        ),
        (
            "{ choose { a(); concurrent { b(); c(); } } }",
            "{\n    choose {\n        a();\n        concurrent {\n            b();\n"
            "            c();\n        }\n    }\n}",
        ),
        (
            "search { pick (T x) a(x); pick (number y in {1, -2}) {} }",
            "search {\n    pick (T x)\n        a(x);\n    pick (number y in {1, -2}) {}\n}",
        ),
        ("solve(3, r()) {}", "solve(3, r()) {}"),
        ("{}", "{}"),
        ("f().x[0] = g(1).y;", "f().x[0] = g(1).y;"),
    ],
)
def test_statement_canonical_text(source: str, expected: str) -> None:
    tree = parse_stmt(source)
    assert format_stmt(tree) == expected
    assert parse_stmt(expected) == tree


def test_statement_indentation_level() -> None:
    tree = parse_stmt("while (c) { a(); }")
    assert format_stmt(tree, 2) == "        while (c) {\n            a();\n        }"


def test_dangling_trees_get_braces() -> None:
    # Trees the parser cannot produce: printed with the braces that keep the meaning.
    inner_if = ast.If(span=SPAN, condition=name("d"), then=stmt("a"), otherwise=None)
    tree: ast.Statement = ast.If(span=SPAN, condition=name("c"), then=inner_if, otherwise=stmt("b"))
    text = format_stmt(tree)
    assert text == "if (c) {\n    if (d)\n        a();\n} else\n    b();"
    assert parse_stmt(text) == make_if(name("c"), inner_if, stmt("b"))

    inner = ast.During(span=SPAN, action=call("b"), body=stmt("c"), on_fail=None, on_cancel=None)
    tree = ast.During(span=SPAN, action=call("a"), body=inner, on_fail=stmt("d"), on_cancel=None)
    text = format_stmt(tree)
    assert text == "during (a()) {\n    during (b())\n        c();\n} on_fail\n    d();"
    assert parse_stmt(text) == make_during(call("a"), inner, stmt("d"), None)

    # The on_fail handler must not take the outer on_cancel.
    tree = ast.During(span=SPAN, action=call("a"), body=stmt("b"), on_fail=inner, on_cancel=stmt("e"))
    text = format_stmt(tree)
    assert text == "during (a())\n    b();\non_fail {\n    during (b())\n        c();\n} on_cancel\n    e();"
    assert parse_stmt(text) == make_during(call("a"), stmt("b"), inner, stmt("e"))

    # An if whose then-branch ends in a handler-less while over an else-less if.
    loop = ast.While(span=SPAN, condition=name("w"), body=inner_if)
    tree = ast.If(span=SPAN, condition=name("c"), then=loop, otherwise=stmt("b"))
    assert parse_stmt(format_stmt(tree)) == make_if(name("c"), loop, stmt("b"))


def test_keyword_literal_targets_get_parentheses() -> None:
    # `true = 1;` would read as an assignment to a variable named `true`.
    for target in (ast.BoolLit(span=SPAN, value=True), ast.NullLit(span=SPAN)):
        tree = ast.Assign(span=SPAN, target=target, value=n(1))
        text = format_stmt(tree)
        assert text == f"({format_expr(target)}) = 1;"
        assert parse_stmt(text) == tree


def test_no_braces_when_nothing_dangles() -> None:
    # An else-less if inside a during body does not take the handler.
    inner_if = ast.If(span=SPAN, condition=name("d"), then=stmt("a"), otherwise=None)
    tree = ast.During(span=SPAN, action=call("a"), body=inner_if, on_fail=stmt("f"), on_cancel=None)
    text = format_stmt(tree)
    assert text == "during (a())\n    if (d)\n        a();\non_fail\n    f();"
    assert parse_stmt(text) == tree
    # A during without handlers inside the then-branch does not take the else.
    during = ast.During(span=SPAN, action=call("a"), body=stmt("b"), on_fail=None, on_cancel=None)
    tree2 = ast.If(span=SPAN, condition=name("c"), then=during, otherwise=stmt("e"))
    text = format_stmt(tree2)
    assert text == "if (c)\n    during (a())\n        b();\nelse\n    e();"
    assert parse_stmt(text) == tree2


PLATFORM = """\
component depth_cam {
clocks:
    bcl, c2
states:
    off, boot(bcl <= 4 & !(c2 > 1 | c2 < 0.5)), on
transitions:
    off => boot resets(bcl),
    boot -> (bcl >= 2) on,
    on => off,
    error => off
}

constraints {
    during(stack(*, *, -1, "s")): state(depth_cam) = on;
    during(go_to(*)): state(depth_cam) = off;
    start(a()) & end(b()) | fail(c(true)): next[, 3] state(x) = y until[1, ] (past state(x) = z | state(x) = y);
    (start(a()) | cancel(b())) & finish(c()): previous[1.5, 2] future state(x) = y since state(x) = z;
}
"""


def test_platform_model_canonical_text() -> None:
    program = reparse(PLATFORM)
    assert format_program(program) == PLATFORM


DOMAINS = """\
symbol domain E = A | B \\ {a}

symbol domain F = (A | B) \\ {a, b} & C

number domain G = {1, -2, 3.5}

list[string] domain H;

#include "lib/sub.gpp"
"""


def test_domains_group_to_the_right() -> None:
    program = reparse(DOMAINS)
    assert format_program(program) == DOMAINS
    e = program.declarations[0]
    assert isinstance(e, ast.DomainDecl) and isinstance(e.definition, ast.DomainBinary)
    assert e.definition.op is ast.DomainOp.UNION and isinstance(e.definition.right, ast.DomainBinary)
    # A left operand that is itself an operation needs parentheses.
    ref = [ast.DomainRef(span=SPAN, name=ast.Ident(span=SPAN, name=x)) for x in "ABC"]
    left = ast.DomainBinary(span=SPAN, op=ast.DomainOp.UNION, left=ref[0], right=ref[1])
    tree = ast.DomainDecl(
        span=SPAN,
        element_type=ast.NamedType(span=SPAN, name="symbol"),
        name=ast.Ident(span=SPAN, name="D"),
        definition=ast.DomainBinary(span=SPAN, op=ast.DomainOp.DIFFERENCE, left=left, right=ref[2]),
    )
    text = format_program(make_program([tree], None))
    assert text == "symbol domain D = (A | B) \\ C\n"
    assert reparse(text).declarations == (tree,)


FORWARDS_AND_LEGACY = """\
bool fluent p();

action a(number x);

exog_action e();

number function f(string s, list[number] l);

procedure q();

procedure r()
    a(1);

action b() {}

exog_action ev(number n, string s) {
precondition:
    exists(T z) p() & n > 0
senses:
    f("a", list[number] []).x = n;
silent: true
effect:
    if (n > 1) p() = false;
mapping:
    "t" {}
}

number fluent g() {
initially:
}

{
    a(1);
}
"""


def test_forward_declarations_and_legacy_main_block() -> None:
    program = reparse(FORWARDS_AND_LEGACY)
    assert format_program(program) == FORWARDS_AND_LEGACY
    assert isinstance(program.declarations[-1], ast.MainBlock)


EXAMPLE = """\
symbol domain Room = {kitchen, office, hall}
symbol domain Item = {cup, book}
compound Pose { number x, number y }
list[Item]
Room fluent robot_at() {
initially:
    () = hall;
}
Room fluent item_at(Item i) {
initially:
    (i) = kitchen;
    (book) = office;
}
list[Item] fluent carrying() { initially: () = list[Item] []; }
number fluent battery() { initially: () = 100; }
string exog_function heard_text(string source);
action goto(Room r) {
precondition:
    robot_at() != r & battery() > 10
effect:
    robot_at() = r;
    battery() = battery() - 5;
mapping:
    "navigate" { target = r, speed = 0.5 }
duration: [5, 60]
}
exog_action battery_report(number level) {
mapping:
    "/battery" { percentage = level }
effect:
    battery() = level;
}
bool function delivered(Item i) = item_at(i) == office
number function reward() = if (delivered(cup)) 100 else -1
procedure fetch(Item i) {
    if (robot_at() != item_at(i))
        goto(item_at(i));
    test(battery() > 20);
}
procedure main() {
    fetch(cup);
    solve(4, reward())
        pick (Room r in {kitchen, office, hall})
            goto(r);
}
"""

EXAMPLE_CANONICAL = """\
symbol domain Room = {kitchen, office, hall}

symbol domain Item = {cup, book}

compound Pose { number x, number y }

list[Item]

Room fluent robot_at() {
initially:
    () = hall;
}

Room fluent item_at(Item i) {
initially:
    (i) = kitchen;
    (book) = office;
}

list[Item] fluent carrying() {
initially:
    () = list[Item] [];
}

number fluent battery() {
initially:
    () = 100;
}

string exog_function heard_text(string source);

action goto(Room r) {
precondition:
    robot_at() != r & battery() > 10
effect:
    robot_at() = r;
    battery() = battery() - 5;
mapping:
    "navigate" { target = r, speed = 0.5 }
duration: [5, 60]
}

exog_action battery_report(number level) {
mapping:
    "/battery" { percentage = level }
effect:
    battery() = level;
}

bool function delivered(Item i) = item_at(i) == office

number function reward() = if (delivered(cup)) 100 else -1

procedure fetch(Item i) {
    if (robot_at() != item_at(i))
        goto(item_at(i));
    test(battery() > 20);
}

procedure main() {
    fetch(cup);
    solve(4, reward())
        pick (Room r in {kitchen, office, hall})
            goto(r);
}
"""


def test_example_program_round_trip() -> None:
    program = reparse(EXAMPLE)
    text = format_program(program)
    assert text == EXAMPLE_CANONICAL
    assert reparse(text) == program
    assert format_program(reparse(text)) == text


ROOT = Path(__file__).resolve().parents[2]
CORPUS = sorted(
    [*ROOT.glob("examples/*.gpp"), *ROOT.glob("stdlib/**/*.gpp"), *ROOT.glob("tests/programs/*.gpp")],
)


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: str(p.relative_to(ROOT)))
def test_corpus_round_trip(path: Path) -> None:
    result = parse_text(path.read_text(encoding="utf-8"), str(path))
    if result.diagnostics:
        pytest.skip("the file has syntax errors on purpose")
    text = format_program(result.program)
    assert reparse(text) == result.program
    assert format_program(reparse(text)) == text


def test_empty_program() -> None:
    assert format_program(reparse("")) == ""
