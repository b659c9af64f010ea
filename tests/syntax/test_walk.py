"""The per-kind statement traversal (gpp.syntax.walk.sub_statements) agrees with the generic
one (`children`) on every statement of the examples, the test programs and the stdlib."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import pytest

from gpp.syntax import ast
from gpp.syntax.parser import parse_text
from gpp.syntax.walk import children, sub_statements, walk

ROOT = Path(__file__).resolve().parents[2]
SOURCES = sorted(p for d in ("examples", "tests/programs", "stdlib") for p in (ROOT / d).rglob("*.gpp"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_sub_statements_are_the_statement_children(path: Path) -> None:
    program = parse_text(path.read_text(encoding="utf-8"), str(path)).program
    for node in walk(program):
        if isinstance(node, ast.StmtNode):
            assert isinstance(node, ast.Statement)
            generic = tuple(c for c in children(node) if isinstance(c, ast.StmtNode))
            assert sub_statements(node) == generic
            assert all(a is b for a, b in zip(sub_statements(node), generic, strict=True))


def test_every_statement_kind_is_covered() -> None:
    text = """
    action a() {}
    procedure main() {
        if (true) a(); else { a(); }
        while (false) a();
        test(true);
        choose { a(); a(); }
        concurrent { a(); }
        pick (bool b) a();
        solve(1, r()) search a();
        during (a()) a(); on_fail a(); on_cancel a();
        start(a());
        pop_back(l());
        x() = 1;
        a();
    }
    """
    program = parse_text(text).program
    kinds = {type(n) for n in walk(program) if isinstance(n, ast.StmtNode)}
    assert kinds == set(ast.STATEMENT_KINDS)
    main = program.declarations[1]
    assert isinstance(main, ast.ProcedureDecl) and main.body is not None
    for node in walk(main):
        if isinstance(node, ast.StmtNode):
            assert isinstance(node, ast.Statement)
            assert sub_statements(node) == tuple(c for c in children(node) if isinstance(c, ast.StmtNode))


def _field_children(node: ast.Node) -> list[ast.Node]:
    """A node's children found by testing the value of every dataclass field (what `children`
    and `walk` read from the field annotations instead)."""
    found: list[ast.Node] = []
    for f in fields(node):
        value = getattr(node, f.name)
        found.extend(v for v in (value if isinstance(value, tuple) else (value,)) if isinstance(v, ast.Node))
    return found


def _field_walk(program: ast.Node) -> list[ast.Node]:
    found: list[ast.Node] = []
    stack = [program]
    while stack:
        node = stack.pop()
        found.append(node)
        stack.extend(reversed(_field_children(node)))
    return found


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_children_and_walk_agree_with_the_fields(path: Path) -> None:
    program = parse_text(path.read_text(encoding="utf-8"), str(path)).program
    expected = _field_walk(program)
    assert [id(n) for n in walk(program)] == [id(n) for n in expected]
    for node in expected:
        assert [id(c) for c in children(node)] == [id(c) for c in _field_children(node)]


@pytest.mark.parametrize(
    "text",
    ["procedure main() { if (x( { a(); ", "action a( { effect: x = ; }", "number function f() = (1 + ", "}}}{{"],
)
def test_walk_agrees_with_the_fields_after_syntax_errors(text: str) -> None:
    program = parse_text(text).program
    assert [id(n) for n in walk(program)] == [id(n) for n in _field_walk(program)]
