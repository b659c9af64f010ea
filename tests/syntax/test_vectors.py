"""The parser test vectors of LANGUAGE.md Appendix D (§16, #1-#86), decided at the syntax level.

Each vector gets the recommended ("Rec") result, overruled by SEMANTICS.md where the two differ
(keywords are reserved, `inf` is a plain name, a comment-only file is an empty program, ...).
Vectors whose verdict is a type or name error are syntactically fine: here they must parse
without diagnostics; the test of the verdict itself comes with the checker.

Expression trees are compared through `sx`, a fully parenthesised rendering of the tree, so
that `((1 * 2) + (3 * 4))` states the structure exactly.
"""

from __future__ import annotations

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.syntax import ast
from gpp.syntax.parser import ParseResult, parse_text

# ---------------------------------------------------------------- helpers


def describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(f"{d.span.line}:{d.span.col} {d.code} {d.message}" for d in diagnostics)


def parse_clean(text: str) -> ast.Program:
    """Parse `text` and require that not a single diagnostic is reported."""
    result = parse_text(text)
    assert result.diagnostics == [], "unexpected diagnostics:\n" + describe(result.diagnostics)
    assert result.ok
    return result.program


def last_decl(text: str) -> ast.Decl:
    return parse_clean(text).declarations[-1]


def function_body(text: str) -> ast.Expr:
    decl = last_decl(text)
    assert isinstance(decl, ast.FunctionDecl)
    assert decl.body is not None
    return decl.body


def main_body(text: str) -> tuple[ast.Statement, ...]:
    """The statements of the block of the last procedure in `text`."""
    decl = last_decl(text)
    assert isinstance(decl, ast.ProcedureDecl)
    assert isinstance(decl.body, ast.Block)
    return decl.body.body


def main_body_of(result: ParseResult) -> tuple[ast.Statement, ...]:
    """The statements of the last procedure of a parse that may have reported errors."""
    decl = result.program.declarations[-1]
    assert isinstance(decl, ast.ProcedureDecl)
    assert isinstance(decl.body, ast.Block)
    return decl.body.body


def only_statement(text: str) -> ast.Statement:
    body = main_body(text)
    assert len(body) == 1
    return body[0]


def tsx(t: ast.TypeExpr) -> str:
    if isinstance(t, ast.ListType):
        return f"list[{tsx(t.element)}]"
    return t.name


def sx(e: ast.Expr) -> str:
    """A fully parenthesised rendering of an expression tree."""
    match e:
        case ast.NumberLit(value=value):
            return repr(value)
        case ast.StringLit(value=value):
            return f'"{value}"'
        case ast.BoolLit(value=value):
            return "true" if value else "false"
        case ast.NullLit():
            return "null"
        case ast.Name(name=name):
            return name
        case ast.Call(name=name, args=args):
            return f"{name.name}({', '.join(sx(a) for a in args)})"
        case ast.Unary(op=op, operand=operand):
            return f"({op.value}{sx(operand)})"
        case ast.Binary(op=op, left=left, right=right):
            return f"({sx(left)} {op.value} {sx(right)})"
        case ast.Quantified(quantifier=q, var_type=t, var=var, body=body):
            return f"({q.value}({tsx(t)} {var.name}) {sx(body)})"
        case ast.Conditional(condition=c, then=then, otherwise=otherwise):
            return f"(if {sx(c)} then {sx(then)} else {sx(otherwise)})"
        case ast.FieldAccess(subject=subject, field=f):
            return f"{sx(subject)}.{f.name}"
        case ast.Index(subject=subject, index=index):
            return f"{sx(subject)}[{sx(index)}]"
        case ast.CompoundLit(type_name=t, fields=fields):
            return f"{t.name}{{{', '.join(f'{f.name.name} = {sx(f.value)}' for f in fields)}}}"
        case ast.ListLit(type=t, elements=elements):
            return f"{tsx(t)}[{', '.join(sx(x) for x in elements)}]"
        case ast.BuiltinCall(function=fn, arg=arg):
            return f"{fn.value}({sx(arg)})"
    raise AssertionError(f"sx: unexpected node {e!r}")


def ssx(s: ast.Statement) -> str:
    """A rendering of a statement tree that shows which statement owns which part."""
    match s:
        case ast.Block(body=body):
            return "{ " + " ".join(ssx(x) for x in body) + " }" if body else "{}"
        case ast.If(condition=c, then=then, otherwise=otherwise):
            text = f"if ({sx(c)}) {ssx(then)}"
            return text if otherwise is None else f"{text} else {ssx(otherwise)}"
        case ast.CallStmt(call=call):
            return f"{sx(call)};"
        case ast.Assign(target=target, value=value):
            return f"{sx(target)} = {sx(value)};"
        case ast.Test(condition=c):
            return f"test({sx(c)});"
        case ast.During(action=action, until=until, body=body, on_fail=on_fail, on_cancel=on_cancel):
            watch = "" if until is None else f" until ({sx(until)})"
            text = f"during ({sx(action)}){watch} {ssx(body)}"
            if on_fail is not None:
                text += f" on_fail {ssx(on_fail)}"
            if on_cancel is not None:
                text += f" on_cancel {ssx(on_cancel)}"
            return text
        case ast.Pick(var_type=t, var=var, values=values, body=body):
            domain = "" if values is None else " in {" + ", ".join(sx(v) for v in values) + "}"
            return f"pick ({tsx(t)} {var.name}{domain}) {ssx(body)}"
        case ast.Solve(horizon=h, reward=r, body=body):
            return f"solve({sx(h)}, {sx(r)}) {ssx(body)}"
        case ast.While(condition=c, body=body):
            return f"while ({sx(c)}) {ssx(body)}"
        case ast.ListStmt(op=op, target=target, value=value):
            args = sx(target) if value is None else f"{sx(target)}, {sx(value)}"
            return f"{op.value}({args});"
    raise AssertionError(f"ssx: unexpected node {s!r}")


def dsx(d: ast.DomainExpr) -> str:
    match d:
        case ast.DomainRef(name=name):
            return name.name
        case ast.DomainSet(elements=elements):
            return "{" + ", ".join(sx(x) for x in elements) + "}"
        case ast.DomainBinary(op=op, left=left, right=right):
            return f"({dsx(left)} {op.value} {dsx(right)})"
    raise AssertionError(f"dsx: unexpected node {d!r}")


def single_error(result: ParseResult) -> Diagnostic:
    assert len(result.diagnostics) == 1, describe(result.diagnostics)
    return result.diagnostics[0]


def assert_error(result: ParseResult, code: str, line: int, col: int, message_part: str) -> Diagnostic:
    """Exactly one diagnostic, with this code, at this line:col, whose message contains `message_part`."""
    d = single_error(result)
    assert (d.code, d.span.line, d.span.col) == (code, line, col), describe(result.diagnostics)
    assert message_part in d.message
    assert d.is_error
    return d


# ---------------------------------------------------------------- expression structure


@pytest.mark.parametrize(
    ("vector", "source", "tree"),
    [
        # 1: standard precedence, not the reference's ((1*2)+3)*4.
        (1, "number function f() = 1 * 2 + 3 * 4", "((1 * 2) + (3 * 4))"),
        # 2: `&` binds tighter than `|`.
        (2, "bool function f() = p() & q() | r() & s()", "((p() & q()) | (r() & s()))"),
        # 4: `**` is left-associative (as in the reference).
        (4, "number function f() = 2 ** 3 ** 2", "((2 ** 3) ** 2)"),
        # 5: `->` is left-associative.
        (5, "bool function f() = p() -> q() -> r()", "((p() -> q()) -> r())"),
        # 6: `!` takes one comparison, then `&`.
        (6, "bool function f() = !x() > 3 & p()", "((!(x() > 3)) & p())"),
        # 7: a comparison on the right of `->`.
        (7, "bool function f() = b() -> x() > 0", "(b() -> (x() > 0))"),
        # 8: longest match: `->` after a number is one token (the reference read `-` `>`).
        (8, "bool function f() = x() > 0 -> b()", "((x() > 0) -> b())"),
        # 9: unary minus on any numeric expression.
        (9, "number function f(number x) = -x", "(-x)"),
        # 16: string concatenation chains.
        (16, 'string function f() = "a" + "b" + "c"', '(("a" + "b") + "c")'),
        # 17: a conditional expression in a boolean position.
        (17, "bool function f() = if (p()) true else false", "(if p() then true else false)"),
        # 63: `lengthy` is a name, not the builtin `length` followed by `y`.
        (63, "bool function f() = lengthy() > 0", "(lengthy() > 0)"),
        # 64: `info` is a name, not the pseudo-literal `inf` followed by `o`.
        (64, "number function f() = info()", "info()"),
        # 65: any primary can be indexed, a parenthesised one included.
        (65, "number function f() = (l())[0]", "l()[0]"),
        # 66: `to_string` of a string parses (the checker treats it as the identity).
        (66, "string function f() = to_string(s())", "to_string(s())"),
        # 75: a recursive function through a conditional; the else branch extends to the right.
        (
            75,
            "number function fac(number n);\nnumber function fac(number n) = if (n <= 1) 1 else n * fac(n - 1)",
            "(if (n <= 1) then 1 else (n * fac((n - 1))))",
        ),
        # 80: a conditional as the right operand of a comparison.
        (80, "bool function k() = 0 < if (p()) 1 else 2", "(0 < (if p() then 1 else 2))"),
        # 85: standard precedence; `5 -3` is a subtraction, `2*-3` multiplies by the literal -3.
        (
            85,
            "number function f(number x) = 5 -3 + x-1 + 2*-3 - -4",
            "(((((5 - 3) + x) - 1) + (2 * -3)) - -4)",
        ),
    ],
    ids=lambda v: f"#{v}" if isinstance(v, int) else "",
)
def test_vector_expression_parses_to_standard_tree(vector: int, source: str, tree: str) -> None:
    assert sx(function_body(source)) == tree


@pytest.mark.parametrize(
    ("source", "tree"),
    [
        # LANGUAGE.md §2.6.1: a comparison's sides are whole arithmetic expressions.
        ("bool function f() = x() + 1 > y() * 2 & p()", "(((x() + 1) > (y() * 2)) & p())"),
        # The else branch of a conditional is additive: it stops before comparisons ...
        ("bool function f() = if (c()) 1 else 2 + 3 > 0", "((if c() then 1 else (2 + 3)) > 0)"),
        # ... and takes everything tighter than a comparison.
        ("number function f() = 1 + if (c()) 1 else 2 * 3", "(1 + (if c() then 1 else (2 * 3)))"),
        # A quantifier's body is the longest following expression.
        ("bool function f() = !exists(T z) a() | b()", "(!(exists(T z) (a() | b())))"),
        ("bool function f() = p() & exists(T z) a() & b()", "(p() & (exists(T z) (a() & b())))"),
        # Postfix chains on any primary.
        ("number function f() = ll()[0][1] + l1()[0].lhs[1]", "(ll()[0][1] + l1()[0].lhs[1])"),
        # `null` may be the left operand of `==` (SEMANTICS §1.5).
        ("bool function f() = null == e()", "(null == e())"),
    ],
)
def test_expression_structure_follows_the_documented_precedence(source: str, tree: str) -> None:
    assert sx(function_body(source)) == tree


def test_vector_3_boolean_equality_is_parsed_as_a_comparison_for_the_checker_to_reassociate() -> None:
    # Vector 3 (Rec: `p == (q & r)`). The grammar (gpp.lark header) parses boolean `==`/`!=`
    # at the comparison level, and the checker re-associates them by type to the loosest
    # level; the checker test for the final `p() == (q() & r())` comes with the checker.
    assert sx(function_body("bool function f() = p() == q() & r()")) == "((p() == q()) & r())"


def test_vector_18_comparison_chain_parses_for_the_checker_to_reject() -> None:
    # Vector 18 (Rec: error). Comparisons chain syntactically (so that boolean `==` chains
    # parse); the checker rejects a chain of non-boolean comparisons. Checker test: with the
    # type checker.
    assert sx(function_body("bool function f() = 1 < 2 < 3")) == "((1 < 2) < 3)"


def test_vector_79_conditional_is_the_left_operand_of_a_comparison() -> None:
    # gpp.lark: the else branch is an additive expression, so the conditional is the left
    # side of `>`.
    assert sx(function_body("bool function f() = if (p()) 1 else 2 > 0")) == "((if p() then 1 else 2) > 0)"


# ---------------------------------------------------------------- literals


def test_vector_11_integer_beyond_32_bits_is_a_python_int() -> None:
    body = function_body("number function f() = 3000000000")
    assert isinstance(body, ast.NumberLit)
    assert body.value == 3000000000
    assert type(body.value) is int


@pytest.mark.parametrize(
    ("literal", "value", "kind"),
    [
        ("-5", -5, int),
        ("+7", 7, int),
        (".5", 0.5, float),
        ("1.", 1.0, float),
        ("1e3", 1000.0, float),
        ("-1.5e-3", -0.0015, float),
    ],
)
def test_vector_12_number_literal_has_exact_value_and_kind(literal: str, value: float, kind: type) -> None:
    body = function_body(f"number function f() = {literal}")
    assert isinstance(body, ast.NumberLit), sx(body)
    assert body.value == value
    assert type(body.value) is kind


@pytest.mark.parametrize(
    ("vector", "source", "tree"),
    [
        (13, "number function f() = inf", "inf"),
        (84, "number function f() = INF", "INF"),
        (84, "number function f() = -infinity", "(-infinity)"),
        (84, "number function f() = NaN", "NaN"),
    ],
)
def test_vector_inf_and_nan_are_plain_names(vector: int, source: str, tree: str) -> None:
    # SEMANTICS §1.3: `inf`/`nan` are not literals. They parse as name references; the
    # checker rejects them as unknown names (checker test: with the type checker).
    body = function_body(source)
    assert sx(body) == tree
    name = body.operand if isinstance(body, ast.Unary) else body
    assert isinstance(name, ast.Name)


def test_vector_14_string_keeps_its_leading_blank() -> None:
    body = function_body('string function f() = " lead"')
    assert isinstance(body, ast.StringLit)
    assert body.value == " lead"


def test_vector_15_backslash_before_an_ordinary_character_is_literal() -> None:
    body = function_body(r'string function f() = "x\y"')
    assert isinstance(body, ast.StringLit)
    assert body.value == "x\\y"
    assert len(body.value) == 3


def test_string_escapes_for_quote_and_backslash() -> None:
    body = function_body(r'string function f() = "say \"hi\" \\ done"')
    assert isinstance(body, ast.StringLit)
    assert body.value == 'say "hi" \\ done'


def test_string_literal_may_span_lines() -> None:
    body = function_body('string function f() = "two\nlines"')
    assert isinstance(body, ast.StringLit)
    assert body.value == "two\nlines"


def test_non_ascii_digit_is_an_unexpected_character() -> None:
    # LANGUAGE.md §2.1: the grammar is ASCII-only; non-ASCII text may appear only in strings
    # and comments.
    result = parse_text("number function f() = \u0663")
    assert_error(result, "E0001", 1, 23, "unexpected character")


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1.7976931348623157e308", 1.7976931348623157e308),
        (
            "179769313486231570814527423731704356798070567525844996598917476803157260780028538760589558632766878171540458953514382464234321326889464182768467546703537516986049910576551282076245490090389328944075868508455133942304583236903222948165808559332123348274797826204144723168738177180919299881250404026184124858368",
            2**1024 - 2**971,
        ),
        (
            "0000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000001",
            1,
        ),
        ("1e-400", 0.0),
    ],
)
def test_number_literal_within_the_range_of_numbers_keeps_its_value(text: str, value: float) -> None:
    # docs/semantics.md, "Numbers": whole literals are exact up to the largest float.
    body = function_body(f"number function f() = {text}")
    assert isinstance(body, ast.NumberLit)
    assert body.value == value and type(body.value) is type(value)


@pytest.mark.parametrize(
    ("text", "col"),
    [("1e400", 23), ("1.7976931348623159e308", 23), ("1" + "0" * 309, 23), ("-" + "9" * 4301, 24)],
)
def test_number_literal_beyond_the_range_of_numbers_is_an_error(text: str, col: int) -> None:
    result = parse_text(f"number function f() = {text}")
    assert_error(result, "E0004", 1, col, "number literal is too large")


# ---------------------------------------------------------------- keywords and names


def test_vector_19_section_keyword_with_blank_before_colon() -> None:
    decl = last_decl("bool fluent p() { initially : () = true; }")
    assert isinstance(decl, ast.FluentDecl)
    assert decl.initially is not None
    assert [sx(i.value) for i in decl.initially] == ["true"]


def test_section_keyword_with_line_break_before_colon() -> None:
    decl = last_decl("action a() {\nprecondition\n    : p()\n}")
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.PreconditionSection)
    assert isinstance(section, ast.PreconditionSection)
    assert sx(section.condition) == "p()"


@pytest.mark.parametrize(
    ("vector", "name"),
    [(20, "testing"), (21, "startx"), (78, "listen"), (83, "searchX")],
)
def test_vector_name_beginning_with_a_keyword_is_called(vector: int, name: str) -> None:
    # Keywords are words: `testing();`, `startx();`, `listen();` and `searchX();` are calls.
    statement = only_statement(f"action {name}() {{}}\nprocedure main() {{ {name}(); }}")
    assert ssx(statement) == f"{name}();"


def test_vector_83_search_prefix_is_not_the_search_statement() -> None:
    statement = only_statement("procedure searchX();\naction X() {}\nprocedure main() { searchX(); }")
    assert isinstance(statement, ast.CallStmt)
    assert isinstance(statement.call, ast.Call)
    assert statement.call.name.name == "searchX"


def test_vector_22_keyword_as_fluent_name_is_rejected() -> None:
    # SEMANTICS §1.1: keywords are reserved. The declaration and the use are both reported.
    result = parse_text("bool fluent test() { initially: () = true; }\nprocedure main() { if (test()) a(); }")
    assert [(d.code, d.span.line, d.span.col) for d in result.diagnostics] == [("E0013", 1, 13), ("E0013", 2, 24)]
    first = result.diagnostics[0]
    assert first.message == "`test` is a reserved word and cannot be used as a name"
    assert first.help == "choose another name, such as `test_`"


def test_reserved_word_as_action_name_is_rejected() -> None:
    result = parse_text("action test() {}")
    assert_error(result, "E0013", 1, 8, "`test` is a reserved word")
    # The parser reads the keyword as the name and goes on.
    decl = result.program.declarations[0]
    assert isinstance(decl, ast.ActionDecl)
    assert decl.name.name == "test"


def test_name_starting_with_underscore_is_rejected() -> None:
    result = parse_text("number function _x() = 1")
    assert_error(result, "E0003", 1, 17, "cannot start with '_'")


def test_section_word_without_colon_is_an_ordinary_name() -> None:
    program = parse_clean(
        "bool fluent effect() { initially: () = true; }\n"
        "action a() {\nprecondition: effect()\neffect: effect() = false;\n}"
    )
    fluent, action = program.declarations
    assert isinstance(fluent, ast.FluentDecl)
    assert fluent.name.name == "effect"
    assert isinstance(action, ast.ActionDecl)
    effects = action.section(ast.EffectSection)
    assert isinstance(effects, ast.EffectSection)
    assert [sx(e.target) for e in effects.effects] == ["effect()"]


def test_keyword_as_mapping_argument_name() -> None:
    decl = last_decl('action go(number x) { mapping: "/nav" { start = x, end = x, test = 1 } }')
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.MappingSection)
    assert isinstance(section, ast.MappingSection)
    assert [(a.name.name, sx(a.value)) for a in section.mapping.args] == [("start", "x"), ("end", "x"), ("test", "1")]


# ---------------------------------------------------------------- files and top level


def test_vector_23_file_with_only_a_comment_is_an_empty_program() -> None:
    assert parse_clean("// nothing here yet\n/* still nothing */\n").declarations == ()


def test_vector_24_trailing_anonymous_block_is_main() -> None:
    decl = last_decl("bool fluent p() { initially: () = true; }\n{ test(p()); }")
    assert isinstance(decl, ast.MainBlock)
    assert ssx(decl.body) == "{ test(p()); }"


def test_vector_27_bare_list_type_declared_twice_parses() -> None:
    # Rec: idempotent; a repeated bare `list[T]` is a no-op for the checker.
    program = parse_clean("list[number]\nlist[number]")
    assert [tsx(d.type) for d in program.declarations if isinstance(d, ast.ListTypeDecl)] == [
        "list[number]",
        "list[number]",
    ]


def test_vector_76_include_then_declaration() -> None:
    program = parse_clean('#include "sub.gpp"\nbool function g() = p()')
    include, function = program.declarations
    assert isinstance(include, ast.Include)
    assert include.path.value == "sub.gpp"
    assert isinstance(function, ast.FunctionDecl)


def test_vector_77_include_inside_a_comment_is_ignored() -> None:
    program = parse_clean('// #include "nonexistent.gpp"\nbool function g() = true')
    assert [type(d) for d in program.declarations] == [ast.FunctionDecl]


def test_vector_86_file_with_only_an_include() -> None:
    program = parse_clean('#include "sub.gpp"\n')
    assert len(program.declarations) == 1
    include = program.declarations[0]
    assert isinstance(include, ast.Include)
    assert include.path.value == "sub.gpp"


# ---------------------------------------------------------------- declarations


def test_vector_36_domain_operators_group_to_the_right() -> None:
    decl = last_decl("symbol domain E = A | B \\ {a}")
    assert isinstance(decl, ast.DomainDecl)
    assert decl.definition is not None
    assert dsx(decl.definition) == "(A | (B \\ {a}))"


def test_domain_parentheses_override_the_right_grouping() -> None:
    decl = last_decl("symbol domain E = (A | B) \\ {a}")
    assert isinstance(decl, ast.DomainDecl)
    assert decl.definition is not None
    assert dsx(decl.definition) == "((A | B) \\ {a})"


def test_vector_58_action_section_given_twice_is_rejected() -> None:
    result = parse_text("action a() { effect: p() = true; effect: q() = true; }")
    d = assert_error(result, "E0020", 1, 34, "section `effect:` appears twice")
    assert [(label.span.line, label.span.col, label.message) for label in d.secondary] == [(1, 14, "first given here")]


def test_vector_59_mapping_values_are_general_expressions() -> None:
    decl = last_decl(
        'action a(number x, string s) { mapping: "m" { gx = x * 2, label = s + "!", c = "c", flu = f(), b = (x > 1) } }'
    )
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.MappingSection)
    assert isinstance(section, ast.MappingSection)
    assert section.mapping.name.value == "m"
    assert [(a.name.name, sx(a.value)) for a in section.mapping.args] == [
        ("gx", "(x * 2)"),
        ("label", '(s + "!")'),
        ("c", '"c"'),
        ("flu", "f()"),
        ("b", "(x > 1)"),
    ]


def test_vector_60_unparenthesised_comparison_in_mapping() -> None:
    decl = last_decl('action a(number x) { mapping: "m" { b = x > 1 } }')
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.MappingSection)
    assert isinstance(section, ast.MappingSection)
    assert [(a.name.name, sx(a.value)) for a in section.mapping.args] == [("b", "(x > 1)")]


def test_vector_73_component_sections_in_any_order() -> None:
    decl = last_decl("component c { states: off, boot(c1 <= 4), on clocks: c1 }")
    assert isinstance(decl, ast.ComponentDecl)
    assert [type(s) for s in decl.sections] == [ast.StatesSection, ast.ClocksSection]


def test_vector_74_bounded_until_in_constraint() -> None:
    decl = last_decl("constraints { during(a(*)): state(c) = off until[, 3] state(c) = on; }")
    assert isinstance(decl, ast.ConstraintsDecl)
    (constraint,) = decl.constraints
    requirement = constraint.requirement
    assert isinstance(requirement, ast.SpecBinary)
    assert requirement.op is ast.SpecOp.UNTIL
    assert requirement.bound is not None
    assert requirement.bound.low is None
    assert requirement.bound.high is not None
    assert requirement.bound.high.value == 3


def test_vector_81_silent_null_parses() -> None:
    decl = last_decl("action a() { silent: null }")
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.SilentSection)
    assert isinstance(section, ast.SilentSection)
    assert isinstance(section.value, ast.NullLit)


def test_vector_10_semicolon_after_function_body_is_rejected() -> None:
    result = parse_text("number function f() = 1;")
    d = assert_error(result, "E0010", 1, 24, "unexpected `;` after a declaration")
    assert d.help is not None
    assert "takes no `;`" in d.help
    assert d.fix is not None
    assert [e.text for e in d.fix.edits] == [""]


# ---------------------------------------------------------------- statements


def test_vector_25_empty_procedure_body() -> None:
    decl = last_decl("procedure main() {}")
    assert isinstance(decl, ast.ProcedureDecl)
    assert isinstance(decl.body, ast.Block)
    assert decl.body.body == ()


def test_vector_26_semicolon_after_a_block_statement_is_rejected() -> None:
    result = parse_text("procedure main() { while (true) { a(); }; }")
    d = assert_error(result, "E0010", 1, 41, "unexpected `;` after `}`")
    assert d.help is not None
    assert "remove this `;`" in d.help
    # Recovery drops the `;` and keeps the loop.
    assert [ssx(s) for s in main_body_of(result)] == ["while (true) { a(); }"]


def test_vector_49_pick_without_in_set() -> None:
    statement = only_statement("procedure main() { pick (Blk y) act(y); }")
    assert ssx(statement) == "pick (Blk y) act(y);"
    assert isinstance(statement, ast.Pick)
    assert statement.values is None


def test_vector_50_push_back_of_an_element() -> None:
    statement = only_statement("procedure main() { push_back(l(), 3); }")
    assert ssx(statement) == "push_back(l(), 3);"


@pytest.mark.parametrize(
    ("vector", "source", "tree"),
    [
        # 52: both handlers are optional.
        (52, "procedure main() { during (d()) { d(); } }", "during (d()) { d(); }"),
        # 53: a non-block body and both handlers.
        (
            53,
            "procedure main() { during (d(2)) a(); on_fail b(); on_cancel c(); }",
            "during (d(2)) a(); on_fail b(); on_cancel c();",
        ),
        # 54: only on_cancel.
        (54, "procedure main() { during (d(2)) { a(); } on_cancel b(); }", "during (d(2)) { a(); } on_cancel b();"),
    ],
)
def test_vector_during_forms(vector: int, source: str, tree: str) -> None:
    assert ssx(only_statement(source)) == tree


def test_vector_53_handlers_belong_to_during_not_to_its_body() -> None:
    statement = only_statement("procedure main() { during (d(2)) a(); on_fail b(); on_cancel c(); }")
    assert isinstance(statement, ast.During)
    assert ssx(statement.body) == "a();"
    assert statement.on_fail is not None
    assert ssx(statement.on_fail) == "b();"
    assert statement.on_cancel is not None
    assert ssx(statement.on_cancel) == "c();"


def test_during_until_keeps_its_condition_before_the_body() -> None:
    source = "procedure main() { during (d(2)) until (p() & q()) a(); on_fail b(); on_cancel c(); }"
    statement = only_statement(source)
    assert isinstance(statement, ast.During) and statement.until is not None
    assert statement.until.span.text == "p() & q()"
    assert ssx(statement) == "during (d(2)) until ((p() & q())) a(); on_fail b(); on_cancel c();"
    assert ssx(statement.body) == "a();"
    assert isinstance(only_statement("procedure main() { during (d()) {} }"), ast.During)


def test_until_outside_a_during_says_where_it_belongs() -> None:
    result = parse_text("procedure main() {\n    during (d()) {} until (p());\n}")
    d = assert_error(result, "E0013", 2, 21, "`until` is a reserved word")
    assert d.notes == ("`until` watches an activity: it follows `during (...)`, as in `during (a) until (e) { }`",)


def test_until_stays_the_temporal_operator_in_constraints() -> None:
    result = parse_text("constraints {\n    state(arm) = ready until[, 30] state(arm) = moving;\n}\n")
    assert [t.type for t in result.tokens if t.value == "until"] == ["TEMPORAL_BIN"]


def test_during_handler_given_twice_is_rejected() -> None:
    result = parse_text("procedure main() {\n    during (d()) a(); on_fail b(); on_fail c();\n}")
    d = assert_error(result, "E0021", 2, 36, "`on_fail` handler given twice")
    assert [(label.span.line, label.span.col) for label in d.secondary] == [(2, 23)]


def test_vector_55_dangling_else_binds_to_the_nearest_if() -> None:
    statement = only_statement("procedure main() { if (p()) a(); else if (!p()) b(); else { a(); b(); } }")
    assert ssx(statement) == "if (p()) a(); else if ((!p())) b(); else { a(); b(); }"
    assert isinstance(statement, ast.If)
    inner = statement.otherwise
    assert isinstance(inner, ast.If)
    assert isinstance(inner.otherwise, ast.Block)


def test_dangling_else_without_braces_binds_to_the_inner_if() -> None:
    statement = only_statement("procedure main() { if (p()) if (q()) a(); else b(); }")
    assert isinstance(statement, ast.If)
    assert statement.otherwise is None
    assert ssx(statement) == "if (p()) if (q()) a(); else b();"


def test_vector_56_procedure_body_is_a_single_statement() -> None:
    decl = last_decl("procedure q() a();")
    assert isinstance(decl, ast.ProcedureDecl)
    assert decl.body is not None
    assert ssx(decl.body) == "a();"


def test_vector_82_fluent_named_like_list_keyword_prefix() -> None:
    body = main_body(
        "number fluent listing() { initially: () = 1; }\nprocedure main() { listing() = 2; test(listing() + 1 > 0); }"
    )
    assert [ssx(s) for s in body] == ["listing() = 2;", "test(((listing() + 1) > 0));"]


# ---------------------------------------------------------------- decided by the checker


# Vectors whose verdict (Rec, or SEMANTICS) is a type, name, arity or other static error, or a
# run-time behaviour: the syntax is fine, so they must parse without any diagnostic. The
# checker test for each of them comes with the type checker.
CHECKER_VECTORS = [
    (28, 'list[number] fluent l() { initially: () = list[number]["a", true]; }'),
    (
        29,
        "compound Pose { number x, number y, string frame }\n"
        "Pose fluent p() { initially: () = Pose { x = 1, y = 2 }; }",
    ),
    (30, "compound Pose { number x, number y, string frame }\nPose function mk(number a) = Pose { x = a, y = a }"),
    (31, "compound P { number x }\nP function f() = P { y = 1 }"),
    (32, 'compound P { number x }\nP function f() = P { x = "a" }'),
    (
        33,
        "compound P { number x }\nP fluent p() { initially: () = P { x = 1 }; }\n"
        "bool function c() = p() == P { x = 1 }",
    ),
    (34, "symbol domain A = {a, b, c}\nA fluent f() { initially: () = zzz; }"),
    (
        35,
        "symbol domain block = {a, b, c}\nsymbol domain other = {table}\nblock fluent bf() { initially: () = table; }",
    ),
    (37, "bool fluent x() { initially: () = true; }\naction x() {}"),
    (38, "action a(number x);\naction a(string x) {}"),
    (39, "bool fluent f();\nnumber fluent f() { initially: () = 1; }"),
    (40, "number fluent f(number x) { initially: () = 1; }"),
    (41, "number fluent f(number x, number y) { initially: (y, 2) = 1; }"),
    (42, "procedure main(number x) { x = 1; }"),
    (43, "compound P { number x }\nprocedure main(P p) { p.x = 1; }"),
    (44, "action a() {}\nprocedure p() { a(); p(); }"),
    (45, "bool function goal() = true\nprocedure main() { goal(); }"),
    (46, "exog_action ev(number n) {}\nprocedure main() { ev(1); }"),
    (47, "number fluent n() { initially: () = 1; }\naction a() {}\nprocedure main() { solve(4, n()) a(); }"),
    (48, "action a(number x) {}\nprocedure main(number k) { pick (number x in {1, k}) a(x); }"),
    (51, "list[number] fluent l() { initially: () = list[number] []; }\nprocedure main() { push_back(l(), l()); }"),
    (57, "action a(number x) {}\nprocedure main() { a(1, 2); }"),
    (61, 'exog_action ev(number n, string s) { mapping: "t" { nn = n } }'),
    (62, 'exog_action ev(number n) { mapping: "t" { nn = n + 1 } }'),
    (67, "bool fluent p() { initially: () = true; }\nbool function f() = p"),
    (68, "symbol domain D = {x, y}\naction act(D x) { precondition: x == y }"),
    (
        69,
        "symbol domain block = {a, b, c}\nsymbol domain location = block | {table}\n"
        "action stack(block x, location y) {}\nprocedure main() { stack(z, a); }",
    ),
    (
        70,
        "symbol domain block = {a, b, c}\nsymbol domain location = block | {table}\n"
        "action stack(block x, location y) {}\nprocedure main() { pick (symbol s in {a}) stack(a, s); }",
    ),
    (71, 'procedure main(number x) { pick (string x in {"a"}) test(true); }'),
    (72, "bool function e() = exists(number n) n > 3"),
]


@pytest.mark.parametrize(("vector", "source"), CHECKER_VECTORS, ids=[f"#{v}" for v, _ in CHECKER_VECTORS])
def test_vector_decided_by_the_checker_parses_cleanly(vector: int, source: str) -> None:
    program = parse_clean(source)
    assert program.declarations


def test_vector_42_assignment_to_a_parameter_parses_as_an_assignment_to_a_name() -> None:
    # The checker reports "assignment to a non-fluent target" (SEMANTICS §2.6).
    assert [ssx(s) for s in main_body("procedure main(number x) { x = 1; }")] == ["x = 1;"]


def test_vector_48_variable_in_pick_set_parses_as_a_name() -> None:
    body = main_body("procedure main(number k) { pick (number x in {1, k}) a(x); }")
    assert [ssx(s) for s in body] == ["pick (number x in {1, k}) a(x);"]


def test_vector_67_bare_global_name_parses_as_a_name_reference() -> None:
    # `IDENT(` is always a call; a bare `p` is a variable or symbol, which the checker rejects here.
    body = function_body("bool function f() = p")
    assert isinstance(body, ast.Name)
    assert body.name == "p"


def test_vector_72_quantifier_over_number_parses() -> None:
    assert sx(function_body("bool function e() = exists(number n) n > 3")) == "(exists(number n) (n > 3))"


# ---------------------------------------------------------------- lexical errors


def test_nested_block_comments_are_not_supported() -> None:
    # The first `*/` closes the comment, leaving `c */` as tokens: `c` could start a
    # declaration (a type name), so the `*` is the unexpected token.
    result = parse_text("/* a /* b */ c */\nbool function g() = true")
    assert_error(result, "E0010", 1, 16, "found `*`")


def test_unterminated_string_is_reported_at_its_quote_and_parsing_goes_on() -> None:
    result = parse_text('string function f() = "abc\nbool function g() = true')
    d = assert_error(result, "E0002", 1, 23, "unterminated string literal")
    assert d.span.end - d.span.start == 1
    # The rest of the line is taken as the string; the next line is parsed normally.
    assert [d.name.name for d in result.program.declarations if isinstance(d, ast.FunctionDecl)] == ["f", "g"]


def test_unterminated_block_comment_is_reported_at_its_opening() -> None:
    result = parse_text("bool function g() = true\n/* never closed\nnumber function h() = 1")
    assert_error(result, "E0002", 2, 1, "unterminated block comment")
    assert [type(d) for d in result.program.declarations] == [ast.FunctionDecl]


def test_unexpected_character_is_reported_and_parsing_continues() -> None:
    result = parse_text("bool function g() = @ true\nprocedure main() { a() b(); }")
    assert [(d.code, d.span.line, d.span.col) for d in result.diagnostics] == [("E0001", 1, 21), ("E0011", 2, 23)]
    assert result.diagnostics[0].message == "unexpected character '@'"
    function = result.program.declarations[0]
    assert isinstance(function, ast.FunctionDecl)
    assert function.body is not None
    assert sx(function.body) == "true"
