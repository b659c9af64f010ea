"""Syntax error reporting and recovery: several independent errors, no cascades, precise positions.

TOOLING.md §2.1: point to the right place (a missing `;` just after the previous token),
report several independent errors but suppress those that follow from an earlier one, use
the user's words, and offer a help line such as "did you mean `procedure`?".

"""

from __future__ import annotations

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.syntax import ast
from gpp.syntax.parser import ParseResult, parse_text


def describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(f"{d.span.line}:{d.span.col} {d.code} {d.message}" for d in diagnostics)


def positions(result: ParseResult) -> list[tuple[str, int, int]]:
    """(code, line, column) of every diagnostic, in order."""
    return [(d.code, d.span.line, d.span.col) for d in result.diagnostics]


def single(result: ParseResult) -> Diagnostic:
    assert len(result.diagnostics) == 1, describe(result.diagnostics)
    return result.diagnostics[0]


def labels(d: Diagnostic) -> list[tuple[int, int, str]]:
    """(line, column, message) of every secondary label."""
    return [(label.span.line, label.span.col, label.message) for label in d.secondary]


def declared_names(result: ParseResult) -> list[str]:
    return [d.name.name for d in result.program.declarations if hasattr(d, "name")]


def procedure_calls(result: ParseResult, name: str) -> list[str]:
    """Names called by the statements of procedure `name` (one level deep)."""
    for d in result.program.declarations:
        if isinstance(d, ast.ProcedureDecl) and d.name.name == name:
            assert isinstance(d.body, ast.Block)
            return [
                s.call.name.name for s in d.body.body if isinstance(s, ast.CallStmt) and isinstance(s.call, ast.Call)
            ]
    raise AssertionError(f"procedure {name} not in the program")


# ---------------------------------------------------------------- several independent errors


THREE_MISTAKES = """\
procedure patrol() {
    go_to(hall;
    go_to(kitchen);
}

procedure greet(string name) {
    say("hello " + name));
}

procedure main() {
    patrol()
    greet("Ada");
}
"""


def test_three_independent_mistakes_give_exactly_three_diagnostics() -> None:
    result = parse_text(THREE_MISTAKES)
    assert positions(result) == [
        ("E0010", 2, 15),  # missing `)`: reported right after `hall`
        ("E0010", 7, 25),  # the stray second `)`
        ("E0011", 11, 13),  # missing `;` right after `patrol()`
    ], describe(result.diagnostics)
    missing_paren, stray, missing_semi = result.diagnostics
    assert missing_paren.message == "expected `)`, found `;`"
    assert labels(missing_paren) == [(2, 10, "to close this `(`"), (2, 15, "found `;`")]
    assert stray.message.endswith("found `)`")
    assert missing_semi.message == "expected `;` after this statement"


def test_three_independent_mistakes_keep_every_declaration_and_statement() -> None:
    result = parse_text(THREE_MISTAKES)
    assert declared_names(result) == ["patrol", "greet", "main"]
    assert procedure_calls(result, "patrol") == ["go_to", "go_to"]
    assert procedure_calls(result, "greet") == ["say"]
    assert procedure_calls(result, "main") == ["patrol", "greet"]


def test_errors_in_consecutive_typed_declarations_are_all_reported() -> None:
    result = parse_text("number function f() = 1 2 3\nbool function g() = true &\nprocedure main() { a() }\n")
    assert positions(result) == [("E0010", 1, 25), ("E0010", 3, 1), ("E0011", 3, 23)], describe(result.diagnostics)
    assert declared_names(result) == ["f", "g", "main"]


def test_declarations_after_a_nested_comment_error_are_still_parsed() -> None:
    result = parse_text("/* a /* b */ c */\nbool function g() = true\nnumber function h() = 1\n")
    assert positions(result) == [("E0010", 1, 16)]
    assert declared_names(result) == ["g", "h"]


def test_keyword_used_as_name_is_reported_and_parsing_goes_on() -> None:
    result = parse_text("action test() {}\nprocedure main() { a() }")
    assert positions(result) == [("E0013", 1, 8), ("E0011", 2, 23)]


def test_stray_closing_brace_at_top_level_is_one_error() -> None:
    result = parse_text("procedure main() { a(); }\n}\nprocedure b() { c(); }\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 2, 1)
    assert d.message == "expected a declaration, found `}`"
    assert declared_names(result) == ["main", "b"]


def test_incomplete_precondition_does_not_swallow_the_next_section() -> None:
    result = parse_text("action a() {\nprecondition: x() >\neffect:\n    p() = true;\n}\nprocedure main() { a() }\n")
    assert positions(result) == [("E0010", 3, 1), ("E0011", 6, 23)], describe(result.diagnostics)


def test_missing_comma_in_solve_does_not_cascade() -> None:
    result = parse_text("procedure main() {\n    solve(8 reward()) a();\n    b()\n}\n")
    assert len(result.diagnostics) == 2, describe(result.diagnostics)
    missing_comma, missing_semi = result.diagnostics
    assert (missing_comma.code, missing_comma.span.line) == ("E0010", 2)
    assert missing_comma.message == "expected `,`, found `reward`"
    assert (missing_semi.code, missing_semi.span.line, missing_semi.span.col) == ("E0011", 3, 8)


# ---------------------------------------------------------------- missing `;`


def test_missing_semicolon_at_end_of_line_is_reported_right_after_the_previous_token() -> None:
    text = "procedure main() {\n    a()\n    b();\n}\n"
    result = parse_text(text)
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0011", 2, 8)
    assert d.message == "expected `;` after this statement"
    assert d.label == "add `;` here"
    # The span is empty, right after `a()`; the fix inserts the `;` there.
    assert d.span.start == d.span.end == text.index("a()") + 3
    assert d.fix is not None
    assert [(e.span.start, e.text) for e in d.fix.edits] == [(d.span.start, ";")]
    # A missing `;` at the end of a line has no "found" label on the next line.
    assert d.secondary == ()
    assert procedure_calls(result, "main") == ["a", "b"]


def test_missing_semicolon_between_statements_on_one_line_labels_the_next_token() -> None:
    result = parse_text("procedure a() { go(1) go(2); }")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0011", 1, 22)
    assert labels(d) == [(1, 23, "found `go`")]


@pytest.mark.parametrize(
    ("source", "line", "col", "what"),
    [
        ("action a(number x) {\neffect:\n    pos() = x\n}\n", 3, 14, "effect"),
        ("action a() {\nsenses:\n    s() = r()\n}\n", 3, 14, "sensing assignment"),
        ("bool fluent p() {\ninitially:\n    () = true\n}\n", 3, 14, "initial value"),
        ("constraints {\n    during(a(*)): state(c) = on\n}\n", 2, 32, "constraint"),
    ],
)
def test_missing_semicolon_names_what_it_ends(source: str, line: int, col: int, what: str) -> None:
    d = single(parse_text(source))
    assert (d.code, d.span.line, d.span.col) == ("E0011", line, col)
    assert d.message == f"expected `;` after this {what}"


# ---------------------------------------------------------------- unclosed brackets


def test_unclosed_brace_at_end_of_file_is_one_error_pointing_at_the_brace() -> None:
    result = parse_text("procedure main() {\n    a();\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0012", 3, 1)
    assert d.message.startswith("unexpected end of file, expected ")
    assert d.label == "the file ends here"
    assert labels(d) == [(1, 18, "this `{` is not closed")]
    assert procedure_calls(result, "main") == ["a"]


def test_unclosed_nested_braces_point_at_the_innermost_one() -> None:
    d = single(parse_text("procedure main() {\n    while (p()) {\n        if (q()) {\n            a();\n"))
    assert (d.code, d.span.line, d.span.col) == ("E0012", 5, 1)
    assert [(label.span.line, label.span.col) for label in d.secondary] == [(3, 18)]


def test_missing_closing_parenthesis_before_a_brace() -> None:
    d = single(parse_text("action a(number x {\n}\n"))
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 18)
    assert d.message == "expected `)`, found `{`"
    assert (1, 9, "to close this `(`") in labels(d)


def test_unclosed_parenthesis_in_function_body_before_next_declaration() -> None:
    result = parse_text("bool function f() = (p() & q()\nprocedure main() { a(); }\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 31)
    assert d.message == "expected `)`, found keyword `procedure`"
    assert declared_names(result) == ["f", "main"]


def test_missing_closing_brace_before_next_procedure_is_one_error() -> None:
    result = parse_text("procedure a() {\n    x();\nprocedure b() { y(); }\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 2, 9)
    assert d.message == "expected `}`, found keyword `procedure`"
    assert (1, 15, "to close this `{`") in labels(d)
    assert declared_names(result) == ["a", "b"]


# ---------------------------------------------------------------- one line, one error


def test_two_values_in_a_row_is_one_error_at_the_second() -> None:
    result = parse_text("procedure main() { x() = 1 2; b(); }\nprocedure c() { a(); }\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 28)
    assert d.message.endswith("found number `2`")
    assert procedure_calls(result, "main") == ["b"]
    assert declared_names(result) == ["main", "c"]


def test_two_values_in_a_row_lists_only_what_can_follow() -> None:
    d = single(parse_text("procedure main() { x() = 1 2; }"))
    assert d.message == "expected one of an operator or `;`, found number `2`"


def test_assignment_in_condition_suggests_double_equals() -> None:
    d = single(parse_text("procedure main() { if (x() = 1) a(); }"))
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 28)
    assert d.message.endswith("found `=`")
    assert d.help == "to compare two values write `==`"


def test_assignment_in_condition_lists_only_what_can_follow() -> None:
    d = single(parse_text("procedure main() { if (x() = 1) a(); }"))
    assert d.message == "expected one of an operator or `)`, found `=`"


def test_stray_semicolon_after_a_statement_is_not_blamed_on_a_function_body() -> None:
    d = single(parse_text("procedure main() { a(); ; }"))
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 25)
    assert "declaration" not in d.message
    assert d.help is not None
    assert "remove this `;`" in d.help
    assert "function body" not in d.help


# ---------------------------------------------------------------- expected-token messages


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("procedure main() {\n    a();\n", "unexpected end of file, expected one of a statement or `}`"),
        ("procedure main() {\n    concurrent { }\n}\n", "expected a statement, found `}`"),
    ],
)
def test_expected_statement_is_said_in_words(source: str, message: str) -> None:
    assert single(parse_text(source)).message == message


def test_missing_operand_at_end_of_file_says_expression() -> None:
    d = single(parse_text("number function f() = 1 +"))
    assert (d.code, d.span.line, d.span.col) == ("E0012", 1, 26)
    assert d.message == "unexpected end of file, expected an expression"


def test_missing_operand_before_semicolon_says_expression() -> None:
    d = single(parse_text("procedure main() {\n    a() = ;\n    b();\n}\n"))
    assert (d.code, d.span.line, d.span.col) == ("E0010", 2, 11)
    assert d.message == "expected an expression, found `;`"


# ---------------------------------------------------------------- misspelled keywords


def test_misspelled_procedure_keyword_suggests_procedure() -> None:
    d = single(parse_text("procedur main() { a(); }"))
    assert (d.code, d.span.line, d.span.col) == ("E0010", 1, 10)
    assert d.help == "did you mean `procedure`?"


def test_misspelled_procedure_keyword_does_not_hide_later_declarations() -> None:
    result = parse_text("procedur main() { a(); }\nprocedure b() { c(); }\n")
    assert len(result.diagnostics) == 1
    assert "b" in declared_names(result)


@pytest.mark.parametrize(
    ("source", "line", "col", "hint"),
    [
        ("action a() {\nprecondtion: p()\n}\n", 2, 1, "did you mean `precondition:`?"),
        ("bool fluent p() {\ninitialy: () = true;\n}\n", 2, 1, "did you mean `initially:`?"),
    ],
)
def test_misspelled_section_keyword_suggests_the_section(source: str, line: int, col: int, hint: str) -> None:
    d = single(parse_text(source))
    assert (d.code, d.span.line, d.span.col) == ("E0010", line, col)
    assert d.help == hint


def test_misspelled_while_suggests_while() -> None:
    d = single(parse_text("procedure main() {\n    whlie (p()) a();\n}\n"))
    assert d.help == "did you mean `while`?"


def test_missing_parenthesis_after_if_is_one_error() -> None:
    result = parse_text("procedure main() {\n    if p() a();\n    b();\n}\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 2, 8)
    assert d.message == "expected `(` after `if`: its condition goes in parentheses"
    assert d.fix is not None and d.fix.is_safe
    assert fixed_text("procedure main() {\n    if p() a();\n    b();\n}\n", d) == (
        "procedure main() {\n    if (p()) a();\n    b();\n}\n"
    )


# ---------------------------------------------------------------- follow-on errors with wrong fixes

BLOCKS = "symbol domain Block = {a, b, c}\naction stack(Block x, Block y) { }\nprocedure main() {\n"


def fixed_text(text: str, d: Diagnostic) -> str:
    assert d.fix is not None
    for e in sorted(d.fix.edits, key=lambda e: e.span.start, reverse=True):
        text = text[: e.span.start] + e.text + text[e.span.end :]
    return text


def test_a_missing_comma_between_arguments_is_inserted_not_an_argument_deleted() -> None:
    text = BLOCKS + "    stack(a b);\n    pick (Block x in {a, b}) stack(x, c);\n}\n"
    d = single(parse_text(text))
    assert (d.code, d.span.line, d.span.col, d.message) == ("E0010", 4, 12, "expected `,`, found `b`")
    assert "    stack(a, b);\n" in fixed_text(text, d)
    assert parse_text(fixed_text(text, d)).diagnostics == []


@pytest.mark.parametrize("unfinished", ["stack(a,", "x =", "stack(a, b"])
def test_a_keyword_after_an_unfinished_statement_is_not_called_a_reserved_word(unfinished: str) -> None:
    result = parse_text(BLOCKS + f"    {unfinished}\n    pick (Block x) stack(x, c);\n}}\n")
    d = single(result)
    assert (d.code, d.span.line, d.span.col) == ("E0010", 5, 5)
    assert "reserved word" not in d.message and d.message.endswith("found keyword `pick`")
    assert d.fix is None  # nothing to delete or insert on the `pick` line
    assert labels(d) == [(4, 5 + len(unfinished), "the statement before is not finished")]
    # and the `pick` statement is still parsed as one
    main = result.program.declarations[-1]
    assert isinstance(main, ast.ProcedureDecl) and main.body is not None
    assert any(isinstance(s, ast.Pick) for s in main.body.body)


def test_a_keyword_used_as_a_name_is_still_a_reserved_word() -> None:
    d = single(parse_text("action pick() {}\n"))
    assert (d.code, d.message) == ("E0013", "`pick` is a reserved word and cannot be used as a name")
