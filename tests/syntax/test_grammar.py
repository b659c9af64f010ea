"""The grammar is unambiguous except for the dangling-statement family, and the tokenizer
and the grammar agree on the set of terminals."""

from __future__ import annotations

import re
from typing import Any

import pytest

from gpp.base.resources import grammar_path
from gpp.base.source import Source
from gpp.syntax import ast
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, PUNCTUATION, SECTION_WORDS, tokenize
from gpp.syntax.parser import parse_text, token_sets
from gpp.syntax.tables import build_tables, load_tables


@pytest.fixture(scope="module")
def fresh_tables():
    return build_tables(grammar_path().read_text(encoding="utf-8"))


def test_only_conflicts_are_dangling_else_and_during_handlers(fresh_tables):
    # lark resolves these shift/reduce conflicts as shift: `else`, `on_fail` and `on_cancel`
    # bind to the nearest `if` / `during`, as in C. Any other conflict is a grammar bug.
    terminals = {terminal for terminal, _ in fresh_tables.conflicts}
    assert terminals == {"ELSE", "ON_FAIL", "ON_CANCEL"}
    for terminal, rule in fresh_tables.conflicts:
        expected_rule = "<if_stmt :" if terminal == "ELSE" else "<during :"
        assert rule.startswith(expected_rule), (terminal, rule)


def test_cached_tables_parse_like_fresh_tables(fresh_tables):
    # lark numbers states differently from run to run, so compare what the tables do.
    from gpp.base.source import Source
    from gpp.syntax.lexer import tokenize
    from gpp.syntax.parser import _Parser

    text = (grammar_path().parent.parent / "examples").glob("*.gpp")
    sources = [Source(p.read_text(encoding="utf-8"), str(p)) for p in sorted(text)]
    sources.append(Source("bool function f() = if (p()) 1 else 2 + 3 > 0 & !exists(b z) q(z) | r()"))
    for source in sources:
        trees = [_Parser(source, tokenize(source)[0], tables).run() for tables in (fresh_tables, load_tables())]
        assert trees[0] == trees[1]


def grammar_terminals() -> set[str]:
    text = grammar_path().read_text(encoding="utf-8")
    return set(re.findall(r"^([A-Z][A-Z_]*)\s*:", text, flags=re.MULTILINE))


def lexer_terminals() -> set[str]:
    produced = set(KEYWORDS.values()) | set(PLATFORM_KEYWORDS.values()) | set(SECTION_WORDS.values())
    produced |= set(PUNCTUATION.values())
    return produced | {"NAME", "NUMBER", "STRING", "INCLUDE", "MAIN_LBRACE"}


def test_tokenizer_produces_exactly_the_grammar_terminals():
    assert lexer_terminals() == grammar_terminals()


def test_else_binds_to_nearest_if():
    program = parse_text("procedure main() if (p()) if (q()) a(); else b();").program
    outer = program.declarations[0].body
    assert isinstance(outer, ast.If) and outer.otherwise is None
    inner = outer.then
    assert isinstance(inner, ast.If) and isinstance(inner.otherwise, ast.CallStmt)


def test_handlers_bind_to_nearest_during():
    program = parse_text("procedure main() during (a()) during (b()) c(); on_fail d(); on_cancel e();").program
    outer = program.declarations[0].body
    assert isinstance(outer, ast.During) and outer.on_fail is None and outer.on_cancel is None
    inner = outer.body
    assert isinstance(inner, ast.During)
    assert inner.on_fail is not None and inner.on_cancel is not None


def test_handlers_in_either_order():
    program = parse_text("procedure main() during (a()) { b(); } on_cancel c(); on_fail d();").program
    during = program.declarations[0].body
    assert isinstance(during, ast.During)
    assert isinstance(during.on_cancel, ast.CallStmt) and during.on_cancel.call.name.name == "c"
    assert isinstance(during.on_fail, ast.CallStmt) and during.on_fail.call.name.name == "d"


def test_quantifier_body_is_greedy():
    program = parse_text("bool function f() = !exists(block z) p(z) | q()").program
    body = program.declarations[0].body
    assert isinstance(body, ast.Unary) and body.op is ast.UnaryOp.NOT
    quantified = body.operand
    assert isinstance(quantified, ast.Quantified)
    assert isinstance(quantified.body, ast.Binary) and quantified.body.op is ast.BinaryOp.OR


def test_conditional_else_branch_stops_before_comparison():
    program = parse_text("bool function f() = if (p()) 1 else 2 + 3 > 0").program
    body = program.declarations[0].body
    assert isinstance(body, ast.Binary) and body.op is ast.BinaryOp.GT
    assert isinstance(body.left, ast.Conditional)
    assert isinstance(body.left.otherwise, ast.Binary) and body.left.otherwise.op is ast.BinaryOp.ADD


def test_legacy_main_block_after_declarations():
    program = parse_text("action a() {}\n{ a(); }\n").program
    assert isinstance(program.declarations[-1], ast.MainBlock)


def test_compound_literal_after_name_is_not_main_block():
    program = parse_text("compound P { number x }\nP function f() = P { x = 1 }\n").program
    body = program.declarations[1].body
    assert isinstance(body, ast.CompoundLit)


# ---------------------------------------------------------------- token sets derived from the grammar


def test_first_sets_agree_with_lark(fresh_tables):
    from lark import Lark
    from lark.parsers.grammar_analysis import calculate_sets

    from gpp.syntax.tables import first_sets

    make_parser: Any = Lark
    lark = make_parser(grammar_path().read_text(encoding="utf-8"), parser="lalr", lexer="basic", keep_all_tokens=True)
    lark_first, _, _ = calculate_sets(lark.rules)
    expected = {str(s.name): frozenset(str(t.name) for t in ts) for s, ts in lark_first.items() if not s.is_term}
    assert first_sets(fresh_tables.rules) == expected


# One statement of each kind, as the first thing in a procedure body.
STATEMENT_SAMPLES: dict[type[ast.StmtNode], str] = {
    ast.Block: "{ a(); }",
    ast.If: "if (true) a();",
    ast.While: "while (true) a();",
    ast.Test: "test(true);",
    ast.Choose: "choose { a(); }",
    ast.Concurrent: "concurrent { a(); }",
    ast.Pick: "pick (bool b) a();",
    ast.Solve: "solve(1, r()) a();",
    ast.Search: "search a();",
    ast.During: "during (a()) a();",
    ast.HookStmt: "start(a());",
    ast.Assign: "x() = 1;",
    ast.ListStmt: "push_back(l(), 1);",
    ast.CallStmt: "a();",
}
# Expression statements can begin with any operand.
STATEMENT_SAMPLES_MORE = ["pop_back(l());", "(a)();", "p.x = 1;", "end(a());", "finish(a());", "fail(a());"]


def test_statement_start_is_what_begins_each_statement_kind():
    sets = token_sets(load_tables())
    assert set(STATEMENT_SAMPLES) == set(ast.STATEMENT_KINDS)
    for kind, text in STATEMENT_SAMPLES.items():
        body = parse_text(f"procedure main() {text}").program.declarations[0].body
        assert type(body) is kind, text
    for text in [*STATEMENT_SAMPLES.values(), *STATEMENT_SAMPLES_MORE]:
        # `procedure main()` is four tokens; the lexer reads the statement's first one in context.
        first = tokenize(Source(f"procedure main() {text}"))[0][4].type
        assert first in sets.statement_start, text
        # A statement keyword (not an operand, not a block) is where skipping may stop.
        assert (first in sets.sync) == (first not in sets.primary_start | {"LBRACE"}), text
    keywords = {KEYWORDS[w] for w in ("if", "while", "test", "choose", "concurrent", "pick", "solve", "search")}
    keywords |= {KEYWORDS[w] for w in ("during", "start", "push_back", "pop_back")}
    assert keywords <= sets.statement_start & sets.sync
    assert sets.primary_start <= sets.expression_start
    assert sets.primary_start < sets.statement_start


def test_declaration_sets_are_what_begins_each_declaration():
    sets = token_sets(load_tables())
    samples = {
        "action a();": "declaration",
        "exog_action e();": "declaration",
        "procedure p();": "declaration",
        "compound c { number x }": "declaration",
        "component c { }": "declaration",
        "constraints { state(c) = s: state(c) = s; }": "declaration",
        "bool fluent f();": "typed",
        "number function g();": "typed",
        "string exog_function h();": "typed",
        "symbol domain d;": "typed",
        "list[number]": "type",
    }
    for text, what in samples.items():
        result = parse_text(text)
        assert result.ok, (text, result.diagnostics)
        tokens = tokenize(Source(text))[0]
        if what == "declaration":
            assert tokens[0].type in sets.declaration_start and tokens[0].type in sets.sync, text
        else:
            assert tokens[0].type in sets.type_start and tokens[0].type not in sets.declaration_start, text
        if what == "typed":
            assert tokens[1].type in sets.typed_declaration, text
    assert sets.declaration_start == {
        KEYWORDS[w] for w in ("action", "exog_action", "procedure", "compound", "component", "constraints")
    }


def test_derived_token_sets_are_the_former_hand_written_ones():
    # The recovery used these literal sets before they were derived; recovery must not change.
    sets = token_sets(load_tables())
    primary = {"NAME", "NUMBER", "STRING", "TRUE", "FALSE", "NULL", "LPAR", "LIST", "BUILTIN"}
    statement = {"LBRACE", "IF", "WHILE", "TEST", "CHOOSE", "PICK", "SOLVE", "SEARCH", "CONCURRENT", "DURING"}
    statement |= {"HOOK", "LIST_PUSH", "LIST_POP"} | primary
    declaration = {"ACTION", "EXOG_ACTION", "PROCEDURE", "COMPOUND", "COMPONENT", "CONSTRAINTS"}
    assert sets.primary_start == primary
    assert sets.expression_start == primary | {"BANG", "ADD_OP", "QUANTIFIER", "IF"}
    assert sets.statement_start == statement
    assert sets.declaration_start == declaration
    assert sets.type_start == {"NAME", "BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "VOID", "LIST"}
    assert sets.operators == {"ARROW", "BAR", "AMP", "CMP_OP", "ADD_OP", "MUL_OP", "POW", "DOT", "LBRACKET"}
    assert sets.typed_declaration == {"FLUENT", "FUNCTION", "EXOG_FUNCTION", "DOMAIN"}
    assert sets.sync == {"SEMI", "RBRACE", "INCLUDE"} | declaration | (statement - primary - {"LBRACE"})
    assert sets.semi_context == {
        "test": "statement",
        "hook": "statement",
        "assign": "statement",
        "list_pop": "statement",
        "list_push": "statement",
        "call_stmt": "statement",
        "effect": "effect",
        "cond_effect": "effect",
        "sec_senses": "sensing assignment",
        "initial": "initial value",
        "constraint": "constraint",
    }


def test_token_sets_of_fresh_and_cached_tables_agree(fresh_tables):
    assert token_sets(fresh_tables) == token_sets(load_tables())
