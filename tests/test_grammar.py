"""The grammar is unambiguous except for the dangling-statement family, and the tokenizer
and the grammar agree on the set of terminals."""

from __future__ import annotations

import re

import pytest

from gpp.resources import grammar_path
from gpp.syntax import ast
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, PUNCTUATION, SECTION_WORDS
from gpp.syntax.parser import parse_text
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
    from gpp.source import Source
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
