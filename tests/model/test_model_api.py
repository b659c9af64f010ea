"""The code model's query API (gpp.model.model.Model), exercised on small realistic programs.

The model is what the checker, the interpreter and the language server read (DESIGN.md, "one
parse, one resolution"), so these tests ask it the questions an editor asks: what is under the
cursor, where is it defined, who refers to it, what type has this expression, what is visible
here, what is the outline of this file. Positions are computed with `text.index(...)` so that
each test says in words where it points.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.base.source import Source, Span
from gpp.check import check_text
from gpp.model.model import Model, OutlineItem
from gpp.model.regroup import BOOL_CHAIN, _climb, _Not
from gpp.model.symbols import Reference, Symbol, SymbolKind
from gpp.model.types import BOOL, NULL, NUMBER, STRING, SYMBOL, CompoundType, DomainType, ListType, Sym, Type
from gpp.syntax import ast

# ---------------------------------------------------------------- helpers


def describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(f"{d.span.source.path}:{d.span.line}:{d.span.col} {d.code} {d.message}" for d in diagnostics)


@dataclass
class Program:
    """A checked program and its root file, with position helpers for the root's text."""

    text: str
    model: Model
    source: Source

    @classmethod
    def check(cls, text: str, path: Path = Path("main.gpp")) -> Program:
        """Check `text` as the file `path` (includes resolve from its folder); no errors allowed."""
        result = check_text(text, path, lint=False)
        errors = [d for d in result.diagnostics if d.is_error]
        assert errors == [], "unexpected errors:\n" + describe(errors)
        root = result.loaded.file(path)
        assert root is not None
        return cls(text, result.model, root.source)

    def at(self, needle: str, nth: int = 0, delta: int = 0) -> int:
        """The offset of the `nth` (0-based) occurrence of `needle`, plus `delta`."""
        offset = -1
        for _ in range(nth + 1):
            offset = self.text.index(needle, offset + 1)
        return offset + delta

    def span(self, needle: str, nth: int = 0, length: int | None = None) -> Span:
        """The span of the `nth` occurrence of `needle` (or of its first `length` characters)."""
        begin = self.at(needle, nth)
        return Span(self.source, begin, begin + (len(needle) if length is None else length))

    def ref(self, needle: str, nth: int = 0, delta: int = 0) -> Reference | None:
        return self.model.reference_at(self.source, self.at(needle, nth, delta))

    def sym(self, needle: str, nth: int = 0, delta: int = 0) -> Symbol | None:
        return self.model.symbol_at(self.source, self.at(needle, nth, delta))

    def expr(self, needle: str, nth: int = 0, delta: int = 0) -> ast.Expr | None:
        return self.model.expression_at(self.source, self.at(needle, nth, delta))

    def body(self, function: str) -> ast.Expr:
        """The body expression of the function named `function`."""
        decl = self.model.globals[function].decl
        assert isinstance(decl, ast.FunctionDecl)
        assert decl.body is not None
        return decl.body

    def type_of_body(self, function: str) -> Type:
        return self.model.type_of(self.body(function))

    def domain(self, name: str) -> DomainType:
        domain = self.model.domain(name)
        assert domain is not None, f"no domain `{name}`"
        return domain


def where(span: Span | None) -> tuple[str, int, int] | None:
    """A span as (file name, line, column), readable in assertion messages."""
    if span is None:
        return None
    return Path(span.source.path).name, span.line, span.col


def refs_summary(refs: list[Reference]) -> list[tuple[str, int, int, str, bool]]:
    """References as sorted (file, line, column, text, declaration?) tuples."""
    return sorted((Path(r.span.source.path).name, r.span.line, r.span.col, r.span.text, r.declaration) for r in refs)


BOOL_FLUENTS = """\
bool fluent p() { initially: () = true; }
bool fluent q() { initially: () = true; }
bool fluent r() { initially: () = false; }
number fluent x() { initially: () = 1; }
number fluent y() { initially: () = 2; }
"""


def sx(e: ast.Expr) -> str:
    """A fully parenthesised rendering of a boolean/comparison tree (enough for `effective`)."""
    match e:
        case ast.NumberLit(value=value):
            return repr(value)
        case ast.BoolLit(value=value):
            return "true" if value else "false"
        case ast.Name(name=name):
            return name
        case ast.Call(name=name, args=args):
            return f"{name.name}({', '.join(sx(a) for a in args)})"
        case ast.Unary(op=op, operand=operand):
            return f"({op.value}{sx(operand)})"
        case ast.Binary(op=op, left=left, right=right):
            return f"({sx(left)} {op.value} {sx(right)})"
    raise AssertionError(f"sx: unexpected node {e!r}")


# ---------------------------------------------------------------- resolution across files and order


def test_fluent_declared_in_an_included_file_is_the_target_of_a_call_in_the_root(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("bool fluent ready() { initially: () = true; }\n")
    prog = Program.check('#include "sub.gpp"\nbool function g() = ready()\n', tmp_path / "main.gpp")
    ready = prog.model.globals["ready"]
    assert ready.kind is SymbolKind.FLUENT
    assert prog.model.target(prog.body("g")) is ready
    assert prog.sym("ready()") is ready
    assert where(prog.model.definition(ready)) == ("sub.gpp", 1, 13)
    assert [Path(f.path).name for f in prog.model.files] == ["sub.gpp", "main.gpp"]


def test_included_file_may_use_names_declared_in_the_including_file(tmp_path: Path) -> None:
    # All globals of all files are collected before any body is resolved (SEMANTICS §2.1).
    (tmp_path / "sub.gpp").write_text("procedure helper() { go(); }\n")
    prog = Program.check('#include "sub.gpp"\naction go() {}\nprocedure main() { helper(); }\n', tmp_path / "main.gpp")
    go = prog.model.globals["go"]
    calls = prog.model.references_to(go, include_declaration=False)
    assert [where(r.span) for r in calls] == [("sub.gpp", 1, 22)]
    assert prog.sym("helper()") is prog.model.globals["helper"]


def test_names_resolve_regardless_of_declaration_order() -> None:
    prog = Program.check(
        "procedure main() { ping(0); }\n"
        "bool function ok() = done()\n"
        "procedure ping(number n) { if (n < 3) pong(n + 1); }\n"
        "procedure pong(number n) { ping(n + 1); }\n"
        "number function fib(number n) = if (n < 2) n else fib(n - 1) + fib(n - 2)\n"
        "bool fluent done() { initially: () = false; }\n"
    )
    g = prog.model.globals
    assert prog.sym("ping(0)") is g["ping"]
    assert prog.sym("done()") is g["done"]
    assert prog.sym("pong(n + 1)") is g["pong"]
    assert prog.sym("ping(n + 1)") is g["ping"]
    assert prog.sym("fib(n - 1)") is g["fib"]
    assert prog.sym("fib(n - 2)") is g["fib"]
    assert prog.type_of_body("fib") == NUMBER
    # Every use of a procedure defined later is recorded against that one symbol.
    assert refs_summary(prog.model.references_to(g["ping"])) == [
        ("main.gpp", 1, 20, "ping", False),
        ("main.gpp", 3, 11, "ping", True),
        ("main.gpp", 4, 28, "ping", False),
    ]


# ---------------------------------------------------------------- forward declarations


def test_forward_declared_procedure_spans_the_definition_and_keeps_the_forward_name() -> None:
    prog = Program.check("procedure p();\naction a() {}\nprocedure p() { a(); p(); }\n")
    p = prog.model.globals["p"]
    assert p.is_defined
    assert isinstance(p.decl, ast.ProcedureDecl)
    assert p.decl.body is not None
    assert p.span == prog.span("p() {", length=1)  # the name in `procedure p() {`
    assert p.other_spans == [prog.span("p();", length=1)]  # the name in `procedure p();`
    assert prog.model.definition(p) == p.span
    assert refs_summary(prog.model.references_to(p)) == [
        ("main.gpp", 1, 11, "p", True),
        ("main.gpp", 3, 11, "p", True),
        ("main.gpp", 3, 22, "p", False),
    ]
    assert refs_summary(prog.model.references_to(p, include_declaration=False)) == [("main.gpp", 3, 22, "p", False)]


def test_forward_declaration_after_the_definition_does_not_move_the_symbol() -> None:
    prog = Program.check(
        "number function fac(number n) = if (n <= 1) 1 else n * fac(n - 1)\nnumber function fac(number n);\n"
    )
    fac = prog.model.globals["fac"]
    assert fac.span == prog.span("fac", 0)
    assert fac.other_spans == [prog.span("fac", 2)]
    assert prog.sym("fac(number n);") is fac
    assert prog.ref("fac(number n);") == Reference(prog.span("fac", 2), fac, declaration=True)


def test_forward_declared_fluent_takes_its_parameters_from_the_definition() -> None:
    prog = Program.check(
        "number fluent level(number k);\n"
        "number fluent level(number k) { initially: (k) = 0; }\n"
        "number function twice(number v) = level(v) * 2\n"
    )
    level = prog.model.globals["level"]
    assert [(q.name, q.type) for q in level.params] == [("k", NUMBER)]
    (k,) = level.params
    assert k.owner is level
    assert k.span == prog.span("k", 1)  # the definition's parameter
    assert prog.sym("k) = 0") is k
    assert prog.sym("level(v)") is level


def test_symbol_with_only_a_forward_declaration_is_not_defined() -> None:
    prog = Program.check("action later(number n);\nprocedure main() { later(1); }\n")
    later = prog.model.globals["later"]
    assert not later.is_defined
    assert later.span == prog.span("later", 0)
    assert later.other_spans == []


# ---------------------------------------------------------------- lexical scoping


SHADOWING = """\
symbol domain D = {x, y}
action act(D x) { precondition: x == y }
procedure main(number x) {
  pick (string x in {"a"}) test(x == "a");
  test(x > 0);
  test(exists(D v) v == y & x > 1);
}
bool function f(number x) = x > 0 & exists(D x) x == y
"""


def test_pick_variable_shadows_a_parameter_inside_its_body_only() -> None:
    prog = Program.check(SHADOWING)
    main = prog.model.globals["main"]
    (param,) = main.params
    variable = prog.sym('x in {"a"}')
    assert variable is not None
    assert (variable.kind, variable.type) == (SymbolKind.VARIABLE, STRING)
    assert isinstance(variable.decl, ast.Pick)
    assert prog.sym('x == "a"') is variable
    assert prog.sym("x > 0") is param
    assert prog.sym("x > 1") is param
    assert param.type == NUMBER


def test_quantifier_variable_is_visible_in_its_body_and_shadows_a_parameter() -> None:
    prog = Program.check(SHADOWING)
    v = prog.sym("v == y")
    assert v is not None
    assert (v.kind, v.type) == (SymbolKind.VARIABLE, prog.model.domain("D"))
    assert isinstance(v.decl, ast.Quantified)
    assert prog.sym("v)") is v  # the declaration
    f = prog.model.globals["f"]
    (param,) = f.params
    assert prog.sym("x > 0", nth=1) is param
    inner = prog.sym("x == y", nth=1)
    assert inner is not None and inner is not param
    assert (inner.kind, inner.type) == (SymbolKind.VARIABLE, prog.model.domain("D"))


def test_parameter_named_like_a_domain_symbol_shadows_the_symbol() -> None:
    # LANGUAGE.md Appendix D #68: recommended (and SEMANTICS §2.2): `x` is the parameter.
    prog = Program.check(SHADOWING)
    act = prog.model.globals["act"]
    (param,) = act.params
    x_use = prog.ref("x == y")
    assert x_use is not None
    assert x_use.symbol is param
    assert x_use.symbol is not prog.model.symbols["x"]
    assert prog.sym("y }") is prog.model.symbols["y"]
    decl = act.decl
    assert isinstance(decl, ast.ActionDecl)
    precondition = decl.section(ast.PreconditionSection)
    assert isinstance(precondition, ast.PreconditionSection)
    assert isinstance(precondition.condition, ast.Binary)
    assert prog.model.target(precondition.condition.left) is param


# ---------------------------------------------------------------- domains and symbols


DOMAINS = """\
symbol domain a = {x, y}
symbol domain b = a | {z}
symbol domain c = {y, x, w}
symbol domain d = b \\ {y}
symbol domain e = c & b
symbol domain g = a | c \\ {x}
number domain n = {3, 1, 2, 1}
"""


def test_symbol_in_several_domains_is_one_symbol() -> None:
    prog = Program.check(DOMAINS)
    x = prog.model.symbols["x"]
    assert x.kind is SymbolKind.SYMBOL
    assert prog.sym("x, y}") is x
    assert prog.sym("x, w}") is x
    assert x.span == prog.span("x", 0)
    # Its later occurrences in domain sets: in `c` and in `g`'s `{x}`.
    assert x.other_spans == [prog.span("x", 1), prog.span("x", 2)]
    assert refs_summary(prog.model.references_to(x)) == [
        ("main.gpp", 1, 20, "x", True),
        ("main.gpp", 3, 23, "x", True),
        ("main.gpp", 6, 28, "x", True),
    ]
    assert prog.model.lookup("x") is x


def test_domain_values_keep_declaration_order_through_set_operations() -> None:
    prog = Program.check(DOMAINS)

    def values(name: str) -> list[str]:
        domain = prog.domain(name)
        assert domain.defined
        return [str(v) for v in domain.values]

    assert values("a") == ["x", "y"]
    assert values("b") == ["x", "y", "z"]  # union: left values, then the new right ones
    assert values("c") == ["y", "x", "w"]
    assert values("d") == ["x", "z"]  # difference
    assert values("e") == ["y", "x"]  # intersection, in the left operand's order
    # Right grouping (LANGUAGE.md Appendix D #36): a | (c \ {x}), not (a | c) \ {x}.
    assert values("g") == ["x", "y", "w"]
    assert prog.domain("n").values == (3, 1, 2)  # a repeated value is kept once
    assert all(isinstance(v, Sym) for v in prog.domain("b").values)


def test_domain_is_a_type_and_its_name_resolves_in_a_domain_expression() -> None:
    prog = Program.check(DOMAINS)
    a = prog.model.types["a"]
    assert a.kind is SymbolKind.DOMAIN
    assert isinstance(a.type, DomainType)
    assert a.type.element == SYMBOL
    assert prog.domain("n").element == NUMBER
    assert prog.sym("a | {z}") is a
    assert prog.sym("b \\") is prog.model.types["b"]
    assert refs_summary(prog.model.references_to(a, include_declaration=False)) == [
        ("main.gpp", 2, 19, "a", False),
        ("main.gpp", 6, 19, "a", False),
    ]


# ---------------------------------------------------------------- list types


def test_list_type_is_usable_without_a_bare_declaration() -> None:
    prog = Program.check(
        "list[number] fluent l() { initially: () = list[number] [1, 2]; }\n"
        "list[list[number]] fluent ll() { initially: () = list[list[number]] []; }\n"
        "number function first() = l()[0]\n"
        "list[number] function row() = ll()[0]\n"
    )
    g = prog.model.globals
    assert g["l"].type == ListType(NUMBER)
    assert g["ll"].type == ListType(ListType(NUMBER))
    assert prog.type_of_body("first") == NUMBER
    assert prog.type_of_body("row") == ListType(NUMBER)


def test_bare_list_type_line_may_repeat() -> None:
    prog = Program.check("list[number]\nlist[number]\nlist[number] fluent l() { initially: () = list[number] []; }\n")
    assert prog.model.globals["l"].type == ListType(NUMBER)


# ---------------------------------------------------------------- symbol_at / reference_at


BLOCKS = """\
symbol domain block = {a, b}
symbol domain location = block | {table}
compound Pose { number x, string frame }
Pose function pose() = Pose { x = 1, frame = "map" }
location fluent loc(block o) { initially: (o) = table; }
action stack(block o, location t) { effect: loc(o) = t; }
procedure main() {
  stack(a, table);
  test(pose().x > 0);
}
"""


def test_symbol_at_a_declaration_name_is_the_declared_symbol() -> None:
    prog = Program.check(BLOCKS)
    ref = prog.ref("loc(block")
    assert ref is not None
    assert ref.declaration
    assert ref.symbol is prog.model.globals["loc"]
    assert ref.span == prog.span("loc(block", length=3)
    stack = prog.model.globals["stack"]
    assert prog.sym("stack(block") is stack
    t = prog.sym("t)")
    assert t is stack.params[1]
    assert (t.kind, t.owner) == (SymbolKind.PARAMETER, stack)


def test_symbol_at_a_call_is_the_called_global() -> None:
    prog = Program.check(BLOCKS)
    ref = prog.ref("stack(a")
    assert ref is not None
    assert not ref.declaration
    assert ref.symbol is prog.model.globals["stack"]
    assert ref.span == prog.span("stack", 1)
    assert prog.sym("loc(o) =") is prog.model.globals["loc"]


def test_symbol_at_a_bare_name_is_the_parameter_or_the_domain_symbol() -> None:
    prog = Program.check(BLOCKS)
    stack = prog.model.globals["stack"]
    assert prog.sym("o) = t;") is stack.params[0]
    assert prog.sym("t; }") is stack.params[1]
    assert prog.sym("table);") is prog.model.symbols["table"]
    assert prog.sym("a, table") is prog.model.symbols["a"]
    loc = prog.model.globals["loc"]
    assert prog.sym("o) = table") is loc.params[0]  # an initial value's argument names the parameter


def test_symbol_at_a_type_name_is_the_type() -> None:
    prog = Program.check(BLOCKS)
    assert prog.sym("block o)") is prog.model.types["block"]
    assert prog.sym("location t") is prog.model.types["location"]
    assert prog.sym("Pose function") is prog.model.types["Pose"]
    assert prog.sym("location fluent") is prog.model.types["location"]


def test_symbol_at_a_field_name_is_the_compound_field() -> None:
    prog = Program.check(BLOCKS)
    pose = prog.model.types["Pose"]
    x = pose.members["x"]
    assert (x.kind, x.type, x.owner) == (SymbolKind.FIELD, NUMBER, pose)
    assert prog.sym("x,") is x  # its declaration
    assert prog.sym(".x", delta=1) is x  # field access `pose().x`
    assert prog.sym("x = 1") is x  # compound literal
    assert prog.sym("frame = ") is pose.members["frame"]
    assert prog.sym("Pose {") is pose  # the literal's type name


def test_symbol_at_a_domain_name_in_a_domain_expression_is_the_domain() -> None:
    prog = Program.check(BLOCKS)
    ref = prog.ref("block | {")
    assert ref is not None
    assert ref.symbol is prog.model.types["block"]
    assert not ref.declaration
    assert prog.sym("table}") is prog.model.symbols["table"]


def test_symbol_at_covers_a_whole_name_including_the_position_just_after_it() -> None:
    prog = Program.check(BLOCKS)
    stack = prog.model.globals["stack"]
    assert prog.sym("stack(a", delta=2) is stack
    assert prog.sym("stack(a", delta=5) is stack  # cursor right after the name


def test_symbol_at_whitespace_or_keyword_is_none() -> None:
    prog = Program.check(BLOCKS)
    assert prog.ref("\n  stack", delta=2) is None  # inside the indentation
    assert prog.sym("\n  stack", delta=2) is None
    assert prog.sym("procedure") is None
    assert prog.sym("effect:", delta=2) is None
    assert prog.sym('"map"') is None


# ---------------------------------------------------------------- definition / references_to


def test_definition_is_the_span_of_the_defining_name() -> None:
    prog = Program.check(BLOCKS)
    m = prog.model
    assert m.definition(m.globals["loc"]) == prog.span("loc(block", length=3)
    assert m.definition(m.globals["stack"].params[0]) == prog.span("o, location", length=1)
    assert m.definition(m.types["block"]) == prog.span("block")
    assert m.definition(m.types["Pose"].members["frame"]) == prog.span("frame")
    assert m.definition(m.symbols["table"]) == prog.span("table}", length=5)
    # Predefined globals have no place in the source.
    assert m.definition(m.globals["context_time"]) is None


def test_references_to_lists_uses_with_or_without_declarations() -> None:
    prog = Program.check(BLOCKS)
    m = prog.model
    table = m.symbols["table"]
    assert refs_summary(m.references_to(table)) == [
        ("main.gpp", 2, 35, "table", True),
        ("main.gpp", 5, 49, "table", False),
        ("main.gpp", 8, 12, "table", False),
    ]
    assert refs_summary(m.references_to(table, include_declaration=False)) == [
        ("main.gpp", 5, 49, "table", False),
        ("main.gpp", 8, 12, "table", False),
    ]
    block = m.types["block"]
    assert sorted(r.span.line for r in m.references_to(block, include_declaration=False)) == [2, 5, 6]
    o = m.globals["stack"].params[0]
    assert refs_summary(m.references_to(o)) == [
        ("main.gpp", 6, 20, "o", True),
        ("main.gpp", 6, 49, "o", False),
    ]


def test_references_to_spans_every_file_that_uses_the_symbol(tmp_path: Path) -> None:
    (tmp_path / "world.gpp").write_text(
        "symbol domain block = {a, b}\n"
        "bool fluent clear(block o) { initially: (o) = true; }\n"
        "action grab(block o) { precondition: clear(o) effect: clear(o) = false; }\n"
    )
    prog = Program.check('#include "world.gpp"\nprocedure main() { if (clear(a)) grab(a); }\n', tmp_path / "main.gpp")
    m = prog.model
    clear = m.globals["clear"]
    assert refs_summary(m.references_to(clear)) == [
        ("main.gpp", 2, 24, "clear", False),
        ("world.gpp", 2, 13, "clear", True),
        ("world.gpp", 3, 38, "clear", False),
        ("world.gpp", 3, 55, "clear", False),
    ]
    a = m.symbols["a"]
    assert refs_summary(m.references_to(a, include_declaration=False)) == [
        ("main.gpp", 2, 30, "a", False),
        ("main.gpp", 2, 39, "a", False),
    ]
    assert where(m.definition(a)) == ("world.gpp", 1, 24)


# ---------------------------------------------------------------- type_of


TYPED = """\
symbol domain block = {a, b}
symbol domain location = block | {table}
compound Pose { number x, string frame }
bool fluent p() { initially: () = true; }
number fluent n() { initially: () = 1; }
location fluent loc(block o) { initially: (o) = table; }
list[number] fluent l() { initially: () = list[number] [1, 2]; }
Pose fluent pose() { initially: () = Pose { x = 1, frame = "map" }; }

number function num_lit() = 1.5
string function str_lit() = "s"
bool function bool_lit() = false
number function null_lit() = null
number function param(number k) = k
block function domain_param(block o) = o
symbol function symbol_lit() = a
number function fluent_call() = n()
location function domain_call() = loc(a)
number function negation() = -n()
bool function logical_not() = !p()
number function arithmetic() = n() * 2 + n() / 4 - n() % 3 ** 2
bool function comparison() = n() <= 2
bool function domain_equality() = loc(a) == table
bool function null_test() = n() == null
bool function boolean() = p() & p() | !p() -> p()
string function concat() = "a" + pose().frame + to_string(n())
bool function quantifier() = forall(block o) loc(o) != a
number function cond_null() = if (p()) 1 else null
location function cond_domain() = if (p()) loc(a) else loc(b)
symbol function cond_mixed() = if (p()) a else loc(b)
number function field() = pose().x
number function index() = l()[1]
Pose function record() = Pose { x = n(), frame = "base" }
list[number] function list_lit() = list[number] [n(), 2]
number function len() = length(l())
string function text() = to_string(loc(a))
"""


@pytest.fixture(scope="module")
def typed() -> Program:
    return Program.check(TYPED)


@pytest.mark.parametrize(
    ("function", "expected"),
    [
        ("num_lit", NUMBER),
        ("str_lit", STRING),
        ("bool_lit", BOOL),
        ("null_lit", NULL),
        ("param", NUMBER),
        ("symbol_lit", SYMBOL),
        ("fluent_call", NUMBER),
        ("negation", NUMBER),
        ("logical_not", BOOL),
        ("arithmetic", NUMBER),
        ("comparison", BOOL),
        ("domain_equality", BOOL),
        ("null_test", BOOL),
        ("boolean", BOOL),
        ("concat", STRING),
        ("quantifier", BOOL),
        ("cond_null", NUMBER),
        ("cond_mixed", SYMBOL),
        ("field", NUMBER),
        ("index", NUMBER),
        ("list_lit", ListType(NUMBER)),
        ("len", NUMBER),
        ("text", STRING),
    ],
)
def test_type_of_each_kind_of_expression(typed: Program, function: str, expected: Type) -> None:
    assert typed.type_of_body(function) == expected


def test_type_of_a_domain_typed_expression_is_the_domain(typed: Program) -> None:
    m = typed.model
    block, location = m.domain("block"), m.domain("location")
    assert block is not None and location is not None
    assert typed.type_of_body("domain_param") is block
    assert typed.type_of_body("domain_call") is location
    assert typed.type_of_body("cond_domain") is location
    variable = typed.expr("o) != a")  # the quantifier variable
    assert isinstance(variable, ast.Name)
    assert m.type_of(variable) is block


def test_type_of_a_compound_literal_is_the_compound_type(typed: Program) -> None:
    t = typed.type_of_body("record")
    assert isinstance(t, CompoundType)
    assert t is typed.model.types["Pose"].type
    assert dict(t.fields) == {"x": NUMBER, "frame": STRING}


def test_type_of_every_subexpression_is_recorded(typed: Program) -> None:
    m = typed.model
    arithmetic = typed.body("arithmetic")
    # n() * 2 + n() / 4 - n() % 3 ** 2  ==  ((n() * 2) + (n() / 4)) - (n() % (3 ** 2))
    assert isinstance(arithmetic, ast.Binary) and arithmetic.op is ast.BinaryOp.SUB
    assert isinstance(arithmetic.right, ast.Binary) and arithmetic.right.op is ast.BinaryOp.MOD
    for e in (arithmetic.left, arithmetic.right, arithmetic.right.right):
        assert m.type_of(e) == NUMBER
    compound = typed.body("record")
    assert isinstance(compound, ast.CompoundLit)
    assert [m.type_of(f.value) for f in compound.fields] == [NUMBER, STRING]
    concat = typed.body("concat")
    assert isinstance(concat, ast.Binary)
    assert m.type_of(concat.right) == STRING
    assert isinstance(concat.right, ast.BuiltinCall)
    assert m.type_of(concat.right.arg) == NUMBER


def test_type_of_a_symbol_literal_is_symbol_and_its_target_the_symbol(typed: Program) -> None:
    body = typed.body("symbol_lit")
    assert isinstance(body, ast.Name)
    assert typed.model.type_of(body) == SYMBOL
    assert typed.model.target(body) is typed.model.symbols["a"]


# ---------------------------------------------------------------- expression_at / node_path


def test_expression_at_is_the_innermost_expression(typed: Program) -> None:
    e = typed.expr("2 + n() / 4")
    assert isinstance(e, ast.NumberLit) and e.value == 2
    call = typed.expr("n() / 4", delta=1)  # on the `(` of the call
    assert isinstance(call, ast.Call) and call.name.name == "n"
    division = typed.expr("/ 4")
    assert isinstance(division, ast.Binary) and division.op is ast.BinaryOp.DIV
    field = typed.expr(".x", delta=1)
    assert isinstance(field, ast.FieldAccess) and field.field.name == "x"
    value = typed.expr("n(), frame")
    assert isinstance(value, ast.Call) and typed.model.type_of(value) == NUMBER


def test_expression_at_outside_any_expression_is_none(typed: Program) -> None:
    assert typed.expr("number function num_lit") is None
    assert typed.expr("num_lit") is None  # a declaration's name is not an expression
    assert typed.expr("\n\nnumber function num_lit", delta=1) is None  # a blank line between declarations


def test_node_path_runs_from_the_declaration_down_to_the_innermost_node(typed: Program) -> None:
    path = typed.model.node_path(typed.source, typed.at('frame = "base"', delta=10))
    assert [type(n).__name__ for n in path] == ["FunctionDecl", "CompoundLit", "FieldInit", "StringLit"]
    assert isinstance(path[0], ast.FunctionDecl) and path[0].name.name == "record"
    path = typed.model.node_path(typed.source, typed.at("l()[1]", delta=4))
    assert [type(n).__name__ for n in path] == ["FunctionDecl", "Index", "NumberLit"]
    assert typed.model.node_path(typed.source, typed.at("\n\nnumber function num_lit", delta=1)) == []


# ---------------------------------------------------------------- visible_at


VISIBLE = """\
symbol domain block = {a, b}
compound Pose { number x }
number fluent n() { initially: () = 0; }
action go(block to) {}

procedure tour(block origin, number rounds) {
  go(origin);
  pick (block next in {a, b}) {
    go(next);
  }
  test(exists(block q) q == origin);
}

"""


def visible_names(prog: Program, offset: int) -> dict[str, SymbolKind]:
    return {s.name: s.kind for s in prog.model.visible_at(prog.source, offset)}


def test_visible_at_in_a_procedure_body_includes_its_parameters() -> None:
    prog = Program.check(VISIBLE)
    seen = visible_names(prog, prog.at("go(origin)"))
    assert seen["origin"] is SymbolKind.PARAMETER
    assert seen["rounds"] is SymbolKind.PARAMETER
    assert "next" not in seen
    assert "q" not in seen
    tour = prog.model.globals["tour"]
    found = {s.name: s for s in prog.model.visible_at(prog.source, prog.at("go(origin)"))}
    assert found["origin"] is tour.params[0]


def test_visible_at_in_a_pick_body_includes_the_pick_variable() -> None:
    prog = Program.check(VISIBLE)
    seen = visible_names(prog, prog.at("go(next)"))
    assert seen["next"] is SymbolKind.VARIABLE
    assert seen["origin"] is SymbolKind.PARAMETER
    assert visible_names(prog, prog.at("q == origin"))["q"] is SymbolKind.VARIABLE
    # After the pick, its variable is gone.
    assert "next" not in visible_names(prog, prog.at("test(exists"))


def test_visible_at_outside_any_body_has_no_locals_but_all_globals() -> None:
    prog = Program.check(VISIBLE)
    offset = prog.at("\n\nprocedure tour", delta=1)  # the blank line before the procedure
    seen = visible_names(prog, offset)
    for local in ("origin", "rounds", "next", "q", "to"):
        assert local not in seen
    assert seen["block"] is SymbolKind.DOMAIN
    assert seen["Pose"] is SymbolKind.COMPOUND
    assert seen["a"] is SymbolKind.SYMBOL
    assert seen["b"] is SymbolKind.SYMBOL
    assert seen["n"] is SymbolKind.FLUENT
    assert seen["go"] is SymbolKind.ACTION
    assert seen["tour"] is SymbolKind.PROCEDURE
    assert seen["context_time"] is SymbolKind.FLUENT  # predefined


def test_visible_at_always_includes_globals_types_and_symbols() -> None:
    prog = Program.check(VISIBLE)
    everywhere = {"block", "Pose", "a", "b", "n", "go", "tour"}
    for offset in (prog.at("go(origin)"), prog.at("go(next)"), prog.at("q == origin"), len(prog.text)):
        assert everywhere <= set(visible_names(prog, offset))


# ---------------------------------------------------------------- outline


OUTLINE = """\
symbol domain block = {a, b}
symbol domain location = block | {table}
compound Pose { number x, number y }
location fluent loc(block o) { initially: (o) = table; }
action stack(block o, location t) { effect: loc(o) = t; }
component cam {
  clocks: c1
  states: off, on(c1 <= 4)
  transitions: off => on resets(c1), on => off
}
procedure main() { stack(a, table); }
"""


def outline_tree(items: tuple[OutlineItem, ...] | list[OutlineItem]) -> list[object]:
    return [(i.name, i.kind.value, outline_tree(i.children)) for i in items]


def test_outline_lists_declarations_in_order_with_kind_and_children() -> None:
    prog = Program.check(OUTLINE)
    outline = prog.model.outline(prog.source)
    assert outline_tree(outline) == [
        ("block", "domain", [("a", "symbol", []), ("b", "symbol", [])]),
        ("location", "domain", [("table", "symbol", [])]),
        ("Pose", "compound type", [("x", "field", []), ("y", "field", [])]),
        ("loc", "fluent", [("o", "parameter", [])]),
        ("stack", "action", [("o", "parameter", []), ("t", "parameter", [])]),
        ("cam", "component", [("c1", "clock", []), ("off", "state", []), ("on", "state", [])]),
        ("main", "procedure", []),
    ]


def test_outline_selection_is_the_name_and_span_the_whole_declaration() -> None:
    prog = Program.check(OUTLINE)
    outline = prog.model.outline(prog.source)
    by_name = {i.name: i for i in outline}
    stack = by_name["stack"]
    assert stack.selection == prog.span("stack")
    assert stack.span.text == "action stack(block o, location t) { effect: loc(o) = t; }"
    assert stack.detail == "action stack(block o, location t)"
    o, t = stack.children
    assert o.selection == prog.span("o, location", length=1)
    assert t.selection == prog.span("t)", length=1)
    assert by_name["block"].selection == prog.span("block")
    assert by_name["cam"].selection == prog.span("cam")
    assert by_name["loc"].detail == "location fluent loc(block o)"
    assert by_name["location"].detail == "symbol domain location = {a, b, table}"
    for item in outline:
        assert item.span.start <= item.selection.start and item.selection.end <= item.span.end
        for child in item.children:
            assert item.span.start <= child.span.start and child.span.end <= item.span.end
            # A child's range is its whole declaration (`block o`), its selection the name.
            assert child.span.start <= child.selection.start and child.selection.end <= child.span.end
            assert child.selection.text == child.name


def test_outline_is_per_file(tmp_path: Path) -> None:
    (tmp_path / "sub.gpp").write_text("bool fluent ready() { initially: () = true; }\n")
    prog = Program.check('#include "sub.gpp"\nprocedure main() { test(ready()); }\n', tmp_path / "main.gpp")
    assert [i.name for i in prog.model.outline(prog.source)] == ["main"]
    sub = prog.model.files[0].source
    assert [i.name for i in prog.model.outline(sub)] == ["ready"]


# ---------------------------------------------------------------- effective (boolean `==` precedence)


@pytest.mark.parametrize(
    ("body", "effective"),
    [
        # LANGUAGE.md Appendix D #3: boolean `==` (iff) is looser than `&`.
        ("p() == q() & r()", "(p() == (q() & r()))"),
        ("p() != q() & r()", "(p() != (q() & r()))"),
        ("p() & q() == r()", "((p() & q()) == r())"),
        # `!` binds tighter than a boolean `==`.
        ("!p() == p()", "((!p()) == p())"),
    ],
)
def test_effective_reassociates_boolean_equality_in_an_unparenthesised_chain(body: str, effective: str) -> None:
    prog = Program.check(BOOL_FLUENTS + f"bool function f() = {body}\n")
    e = prog.body("f")
    rewritten = prog.model.effective(e)
    assert rewritten is not e
    assert sx(rewritten) == effective
    assert prog.model.type_of(rewritten) == BOOL


@pytest.mark.parametrize(
    "body",
    [
        "x() > 0 == p()",  # a number comparison, then a boolean `==`: no `&`/`|`/`!` in the chain
        "(p() == q()) & r()",  # parenthesised
        "x() > 0 & y() < 2 & x() == y()",  # number comparisons joined with `&`
        "p() & q()",
        "x() == y()",
    ],
)
def test_effective_leaves_other_expressions_unchanged(body: str) -> None:
    prog = Program.check(BOOL_FLUENTS + f"bool function f() = {body}\n")
    e = prog.body("f")
    assert prog.model.effective(e) is e


def _chain_items(e: ast.Expr, root: bool = True) -> list[ast.Expr | ast.BinaryOp | _Not]:
    """The items of the chain `e` as `Regrouper.flatten_chain` makes them when no `==`/`!=`
    compares booleans: every comparison, and every parenthesised expression, is an operand."""
    inside = root or not e.parenthesized
    if inside and isinstance(e, ast.Binary) and e.op in BOOL_CHAIN:
        return [*_chain_items(e.left, False), e.op, *_chain_items(e.right, False)]
    if inside and isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
        return [_Not(e.span), *_chain_items(e.operand, False)]
    return [e]


@pytest.mark.parametrize(
    "body",
    [
        "p() -> q() -> r()",
        "p() | q() | r() & p()",
        "p() & q() | r() -> p() & !q()",
        "!!p() & !(q() | r()) -> !p()",
        "x() == 1 -> p() | x() != y() & !q()",
        "!x() == y() & (p() == q()) | x() > 0",
    ],
)
def test_a_chain_whose_equalities_compare_no_booleans_climbs_back_to_its_parse(body: str) -> None:
    """`Regrouper.reassociate` does not climb such a chain: it counts on the grammar building
    `&`, `|` and `->` left-associative, at the levels of the regrouping, and `!` on the one
    operand after it, so that climbing would give the parsed tree again."""
    prog = Program.check(BOOL_FLUENTS + f"bool function f() = {body}\n")
    e = prog.body("f")
    rebuilt, rest = _climb(_chain_items(e), 0)
    assert rest == []
    assert rebuilt == e
    assert sx(rebuilt) == sx(e)
    assert prog.model.effective(e) is e


def test_effective_tree_keeps_the_resolved_leaves() -> None:
    prog = Program.check(BOOL_FLUENTS + "bool function f() = p() == q() & r()\n")
    rewritten = prog.model.effective(prog.body("f"))
    assert isinstance(rewritten, ast.Binary)
    assert isinstance(rewritten.right, ast.Binary)
    assert prog.model.type_of(rewritten.right) == BOOL
    leaves = [rewritten.left, rewritten.right.left, rewritten.right.right]
    assert [prog.model.target(leaf) for leaf in leaves] == [prog.model.globals[n] for n in ("p", "q", "r")]
    # Each leaf is referenced once, not once per typing pass.
    assert len(prog.model.references_to(prog.model.globals["q"], include_declaration=False)) == 1


def test_type_of_the_expression_at_any_offset_of_a_reassociated_chain_is_known() -> None:
    prog = Program.check(BOOL_FLUENTS + "bool function f() = p() == q() & r()\n")
    e = prog.expr("==")
    assert e is not None
    assert prog.model.type_of(e) == BOOL


CHAIN = "p() == q() & r()"


@pytest.mark.parametrize(
    "statement",
    [
        f"test({CHAIN});",
        f"if ({CHAIN}) go({CHAIN});",
        f"while ({CHAIN}) go(true);",
        f"p() = {CHAIN};",
        f"test(same({CHAIN}));",
    ],
    ids=["test", "if-and-argument", "while", "assignment", "function-argument"],
)
def test_effective_reassociates_chains_in_every_statement_position(statement: str) -> None:
    prog = Program.check(
        BOOL_FLUENTS + f"action go(bool v) {{}}\nbool function same(bool v) = v\nprocedure main() {{ {statement} }}\n"
    )
    count = prog.text.count(CHAIN)
    assert count >= 1
    for nth in range(count):
        chain = prog.expr("&", nth=nth)
        assert chain is not None
        assert sx(prog.model.effective(chain)) == "(p() == (q() & r()))"


def test_effective_reassociates_a_precondition() -> None:
    prog = Program.check(BOOL_FLUENTS + f"action go() {{ precondition: {CHAIN} }}\n")
    chain = prog.expr("&")
    assert chain is not None
    assert sx(prog.model.effective(chain)) == "(p() == (q() & r()))"


def test_effective_reassociates_a_chain_that_is_parenthesised_as_a_whole() -> None:
    prog = Program.check(BOOL_FLUENTS + f"bool function f() = ({CHAIN})\n")
    assert sx(prog.model.effective(prog.body("f"))) == "(p() == (q() & r()))"


def test_effective_reassociates_a_parenthesised_chain_under_not() -> None:
    prog = Program.check(BOOL_FLUENTS + f"bool function f() = !({CHAIN})\n")
    body = prog.body("f")
    assert isinstance(body, ast.Unary)
    assert sx(prog.model.effective(body.operand)) == "(p() == (q() & r()))"


# ---------------------------------------------------------------- gaps found while testing


def test_visible_at_in_a_pick_value_list_agrees_with_name_resolution() -> None:
    prog = Program.check(
        "symbol domain block = {a, b}\naction go(block o) {}\nprocedure main() { pick (block b in {a, b}) go(b); }\n"
    )
    offset = prog.at("b}) go")
    resolved = prog.model.symbol_at(prog.source, offset)
    assert resolved is prog.model.symbols["b"]
    visible = {s.name: s for s in prog.model.visible_at(prog.source, offset)}
    assert visible["b"] is resolved


def test_references_to_a_parameter_include_its_forward_declaration() -> None:
    prog = Program.check("procedure p(number k);\nprocedure p(number k) { test(k > 0); }\n")
    k = prog.sym("k) {")
    assert k is not None and k.kind is SymbolKind.PARAMETER
    assert refs_summary(prog.model.references_to(k)) == [
        ("main.gpp", 1, 20, "k", True),
        ("main.gpp", 2, 20, "k", True),
        ("main.gpp", 2, 30, "k", False),
    ]


def test_outline_children_lie_inside_their_declaration() -> None:
    prog = Program.check("procedure p(number k);\nprocedure p(number k) { test(k > 0); }\n")
    outline = prog.model.outline(prog.source)
    assert [i.name for i in outline] == ["p", "p"]
    for item in outline:
        assert [c.name for c in item.children] == ["k"]
        for child in item.children:
            assert item.span.start <= child.span.start and child.span.end <= item.span.end


# ---------------------------------------------------------------- lookup / global_symbols


def test_lookup_finds_globals_types_and_symbols() -> None:
    prog = Program.check(BLOCKS)
    m = prog.model
    assert m.lookup("stack") is m.globals["stack"]
    assert m.lookup("block") is m.types["block"]
    assert m.lookup("table") is m.symbols["table"]
    assert m.lookup("o") is None  # parameters are not global
    assert m.lookup("nothing") is None


def test_global_symbols_are_the_callable_and_platform_globals() -> None:
    prog = Program.check(BLOCKS)
    names = {s.name for s in prog.model.global_symbols()}
    assert {"pose", "loc", "stack", "main"} <= names
    assert "block" not in names and "Pose" not in names and "a" not in names
    assert prog.model.main is prog.model.globals["main"]
