"""Hypothesis strategies of random syntax trees over the whole language, only trees the parser
can produce: programs, declarations, statements, expressions (tests/syntax/test_printer.py,
tests/syntax/test_format.py, tests/check/test_lints_unchanged.py)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from functools import cache
from typing import TypeVar

from hypothesis import strategies as st

from gpp.base.source import Source, Span
from gpp.syntax import ast
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, SECTION_WORDS

SPAN = Span(Source("", "<generated>"), 0, 0)


# Nodes with a `parenthesized` flag.
P = TypeVar("P", ast.Expr, ast.DomainExpr, ast.ClockFormula, ast.Spec)


# Identifiers: a small pool of non-keywords, so that generated names collide often.
NAMES = ("a", "b", "c", "x", "y", "foo", "bar", "Room", "item_at", "p2")


# Field-initialiser and mapping-argument names may be keywords (`"/nav" { start = x }`), but
# not `true`, `false` or `null`, which stay values.
FIELD_NAMES = (*NAMES, "start", "if", "in", "length", "effect")


BUILTIN_TYPES = ("bool", "number", "string", "symbol", "void")


RESERVED = set(KEYWORDS) | set(SECTION_WORDS) | set(PLATFORM_KEYWORDS)


EXPR_DEPTH = 3


STMT_DEPTH = 3


def idents(names: tuple[str, ...] = NAMES) -> st.SearchStrategy[ast.Ident]:
    return st.sampled_from(names).map(lambda n: ast.Ident(span=SPAN, name=n))


def maybe_paren(strategy: st.SearchStrategy[P]) -> st.SearchStrategy[P]:
    """Sets the `parenthesized` flag now and then: the printer must keep the user's parentheses."""

    def apply(node: P, paren: bool) -> P:
        return replace(node, parenthesized=True) if paren else node

    return st.builds(apply, strategy, st.integers(0, 7).map(lambda i: i == 0))


@cache
def types(depth: int = 2) -> st.SearchStrategy[ast.TypeExpr]:
    named = st.sampled_from(BUILTIN_TYPES + NAMES).map(lambda n: ast.NamedType(span=SPAN, name=n))
    if depth == 0:
        return named
    return st.one_of(named, list_types(depth))


@cache
def list_types(depth: int = 2) -> st.SearchStrategy[ast.ListType]:
    return types(depth - 1).map(lambda t: ast.ListType(span=SPAN, element=t))


params = st.lists(st.builds(ast.Param, span=st.just(SPAN), type=types(), name=idents()), max_size=3).map(tuple)


numbers: st.SearchStrategy[int | float] = st.one_of(
    st.integers(-1000, 1000),
    st.integers(),
    st.floats(allow_nan=False, allow_infinity=False),
)


# Platform-model bounds are NUMBER tokens: no sign.
unsigned_numbers = st.one_of(
    st.integers(0, 10**6), st.floats(min_value=0, allow_nan=False, allow_infinity=False).map(abs)
).map(lambda v: ast.NumberLit(span=SPAN, value=v))


strings = st.one_of(
    st.text(st.sampled_from(list('ab \\"\n{}/*é')), max_size=8),
    st.text(max_size=4),
)


def _leaf_exprs() -> st.SearchStrategy[ast.Expr]:
    return maybe_paren(
        st.one_of(
            numbers.map(lambda v: ast.NumberLit(span=SPAN, value=v)),
            strings.map(lambda v: ast.StringLit(span=SPAN, value=v)),
            st.booleans().map(lambda v: ast.BoolLit(span=SPAN, value=v)),
            st.just(ast.NullLit(span=SPAN)),
            st.sampled_from(NAMES).map(lambda n: ast.Name(span=SPAN, name=n)),
        )
    )


def negate(operand: ast.Expr) -> ast.Unary:
    # The parser folds `-5` into one literal: `-` on a non-negative literal needs `-(5)`.
    if isinstance(operand, ast.NumberLit) and operand.value >= 0:
        operand = replace(operand, parenthesized=True)
    return ast.Unary(span=SPAN, op=ast.UnaryOp.NEG, operand=operand)


@cache
def exprs(depth: int = EXPR_DEPTH) -> st.SearchStrategy[ast.Expr]:
    if depth == 0:
        return _leaf_exprs()
    sub = exprs(depth - 1)
    args = st.lists(sub, max_size=3).map(tuple)
    field_inits = st.builds(ast.FieldInit, span=st.just(SPAN), name=idents(FIELD_NAMES), value=sub)
    binary = st.builds(ast.Binary, span=st.just(SPAN), op=st.sampled_from(ast.BinaryOp), left=sub, right=sub)
    composite: st.SearchStrategy[ast.Expr] = st.one_of(
        st.builds(ast.Call, span=st.just(SPAN), name=idents(), args=args),
        st.builds(ast.Unary, span=st.just(SPAN), op=st.just(ast.UnaryOp.NOT), operand=sub),
        sub.map(negate),
        # Operators are where precedence and greedy forms meet: give them more weight.
        binary,
        binary,
        binary,
        st.builds(
            ast.Quantified,
            span=st.just(SPAN),
            quantifier=st.sampled_from(ast.Quantifier),
            var_type=types(1),
            var=idents(),
            body=sub,
        ),
        st.builds(ast.Conditional, span=st.just(SPAN), condition=sub, then=sub, otherwise=sub),
        st.builds(ast.FieldAccess, span=st.just(SPAN), subject=sub, field=idents()),
        st.builds(ast.Index, span=st.just(SPAN), subject=sub, index=sub),
        st.builds(
            ast.CompoundLit,
            span=st.just(SPAN),
            type_name=idents(),
            fields=st.lists(field_inits, max_size=3).map(tuple),
        ),
        st.builds(ast.ListLit, span=st.just(SPAN), type=list_types(1), elements=args),
        st.builds(ast.BuiltinCall, span=st.just(SPAN), function=st.sampled_from(ast.Builtin), arg=sub),
    )
    return st.one_of(_leaf_exprs(), maybe_paren(composite))


@cache
def targets(depth: int = 2) -> st.SearchStrategy[ast.Expr]:
    """Assignment targets: mostly `f(..).x[i]` chains, sometimes any expression."""
    call = st.builds(ast.Call, span=st.just(SPAN), name=idents(), args=st.lists(exprs(1), max_size=2).map(tuple))
    if depth == 0:
        return st.one_of(call, exprs(1))
    sub = targets(depth - 1)
    return st.one_of(
        call,
        st.builds(ast.FieldAccess, span=st.just(SPAN), subject=sub, field=idents()),
        st.builds(ast.Index, span=st.just(SPAN), subject=sub, index=exprs(1)),
        exprs(1),
    )


def right_spine(s: ast.Statement) -> Iterator[ast.Statement]:
    """The statements that end where `s` ends, outermost first."""
    current: ast.Statement | None = s
    while current is not None:
        yield current
        match current:
            case ast.If():
                current = current.then if current.otherwise is None else current.otherwise
            case ast.While() | ast.Pick() | ast.Solve() | ast.Search():
                current = current.body
            case ast.During():
                current = current.on_cancel or current.on_fail or current.body
            case _:
                current = None


def takes_else(s: ast.Statement) -> bool:
    return any(isinstance(x, ast.If) and x.otherwise is None for x in right_spine(s))


def takes_handler(s: ast.Statement) -> bool:
    return any(isinstance(x, ast.During) for x in right_spine(s))


def block(*body: ast.Statement) -> ast.Block:
    return ast.Block(span=SPAN, body=body)


def make_if(condition: ast.Expr, then: ast.Statement, otherwise: ast.Statement | None) -> ast.If:
    # With an else branch, a then-branch that ends in an else-less `if` needs braces.
    if otherwise is not None and takes_else(then):
        then = block(then)
    return ast.If(span=SPAN, condition=condition, then=then, otherwise=otherwise)


def make_during(
    action: ast.Expr,
    body: ast.Statement,
    on_fail: ast.Statement | None,
    on_cancel: ast.Statement | None,
    until: ast.Expr | None = None,
) -> ast.During:
    # Handlers bind to the nearest `during`: what precedes a handler must not end in one.
    if (on_fail is not None or on_cancel is not None) and takes_handler(body):
        body = block(body)
    if on_fail is not None and on_cancel is not None and takes_handler(on_fail):
        on_fail = block(on_fail)
    return ast.During(span=SPAN, action=action, until=until, body=body, on_fail=on_fail, on_cancel=on_cancel)


def _list_stmt(op: ast.ListOp, target: ast.Expr, value: ast.Expr) -> ast.ListStmt:
    push = op in (ast.ListOp.PUSH_BACK, ast.ListOp.PUSH_FRONT)
    return ast.ListStmt(span=SPAN, op=op, target=target, value=value if push else None)


def _simple_stmts() -> st.SearchStrategy[ast.Statement]:
    e = exprs(2)
    return st.one_of(
        st.builds(ast.Test, span=st.just(SPAN), condition=e),
        st.builds(ast.HookStmt, span=st.just(SPAN), hook=st.sampled_from(ast.Hook), action=targets(1)),
        st.builds(ast.Assign, span=st.just(SPAN), target=targets(), value=e),
        st.builds(_list_stmt, st.sampled_from(ast.ListOp), e, e),
        st.builds(ast.CallStmt, span=st.just(SPAN), call=targets(1)),
    )


@cache
def stmts(depth: int = STMT_DEPTH) -> st.SearchStrategy[ast.Statement]:
    if depth == 0:
        return _simple_stmts()
    sub = stmts(depth - 1)
    e = exprs(2)
    optional = st.none() | sub
    composite: st.SearchStrategy[ast.Statement] = st.one_of(
        st.lists(sub, max_size=3).map(lambda b: ast.Block(span=SPAN, body=tuple(b))),
        st.lists(sub, min_size=1, max_size=3).map(lambda b: ast.Choose(span=SPAN, alternatives=tuple(b))),
        st.lists(sub, min_size=1, max_size=3).map(lambda b: ast.Concurrent(span=SPAN, branches=tuple(b))),
        st.builds(make_if, e, sub, optional),
        st.builds(ast.While, span=st.just(SPAN), condition=e, body=sub),
        st.builds(
            ast.Pick,
            span=st.just(SPAN),
            var_type=types(1),
            var=idents(),
            values=st.none() | st.lists(exprs(1), min_size=1, max_size=3).map(tuple),
            body=sub,
        ),
        st.builds(ast.Solve, span=st.just(SPAN), horizon=e, reward=e, body=sub),
        st.builds(ast.Search, span=st.just(SPAN), body=sub),
        st.builds(make_during, targets(1), sub, optional, optional, st.none() | e),
    )
    return st.one_of(_simple_stmts(), composite)


@cache
def domain_exprs(depth: int = 2) -> st.SearchStrategy[ast.DomainExpr]:
    leaves: st.SearchStrategy[ast.DomainExpr] = st.one_of(
        st.builds(ast.DomainRef, span=st.just(SPAN), name=idents()),
        st.builds(ast.DomainSet, span=st.just(SPAN), elements=st.lists(exprs(1), min_size=1, max_size=3).map(tuple)),
    )
    if depth == 0:
        return maybe_paren(leaves)
    sub = domain_exprs(depth - 1)
    binary = st.builds(ast.DomainBinary, span=st.just(SPAN), op=st.sampled_from(ast.DomainOp), left=sub, right=sub)
    return maybe_paren(st.one_of(leaves, binary))


def _effects() -> st.SearchStrategy[ast.Effect]:
    return st.builds(ast.Effect, span=st.just(SPAN), condition=st.none() | exprs(2), target=targets(), value=exprs())


def _section_strategies() -> tuple[st.SearchStrategy[ast.ActionSection], ...]:
    kw = st.just(SPAN)
    mapping = st.builds(
        ast.Mapping,
        span=st.just(SPAN),
        name=strings.map(lambda v: ast.StringLit(span=SPAN, value=v)),
        args=st.lists(
            st.builds(ast.MappingArg, span=st.just(SPAN), name=idents(FIELD_NAMES), value=exprs(2)), max_size=3
        ).map(tuple),
    )
    return (
        st.builds(ast.PreconditionSection, span=st.just(SPAN), keyword=kw, condition=exprs()),
        st.builds(
            ast.EffectSection,
            span=st.just(SPAN),
            keyword=kw,
            effects=st.lists(_effects(), min_size=1, max_size=3).map(tuple),
        ),
        st.builds(
            ast.StartEffectSection,
            span=st.just(SPAN),
            keyword=kw,
            effects=st.lists(_effects(), min_size=1, max_size=3).map(tuple),
        ),
        st.builds(ast.SensesSection, span=st.just(SPAN), keyword=kw, target=targets(), value=exprs(2)),
        st.builds(ast.MappingSection, span=st.just(SPAN), keyword=kw, mapping=mapping),
        st.builds(ast.SilentSection, span=st.just(SPAN), keyword=kw, value=exprs(1)),
        st.builds(ast.DurationSection, span=st.just(SPAN), keyword=kw, low=exprs(1), high=exprs(1)),
    )


def action_sections() -> st.SearchStrategy[tuple[ast.ActionSection, ...]]:
    """Distinct section kinds in any order (a kind given twice is an error)."""
    strategies = _section_strategies()
    # A random order of all kinds, cut at a random length (a list strategy would mostly give
    # few sections).
    kinds = st.builds(
        lambda order, k: order[:k], st.permutations(range(len(strategies))), st.integers(0, len(strategies))
    )
    return kinds.flatmap(lambda ks: st.tuples(*(strategies[k] for k in ks)))


@cache
def clock_formulas(depth: int = 2) -> st.SearchStrategy[ast.ClockFormula]:
    compare = st.sampled_from(sorted(ast.COMPARISON_OPS, key=lambda op: op.value))
    bound: st.SearchStrategy[ast.ClockFormula] = st.builds(
        ast.ClockBound, span=st.just(SPAN), clock=idents(), op=compare, bound=unsigned_numbers
    )
    if depth == 0:
        return maybe_paren(bound)
    sub = clock_formulas(depth - 1)
    return maybe_paren(
        st.one_of(
            bound,
            st.builds(ast.ClockNot, span=st.just(SPAN), operand=sub),
            st.builds(
                ast.ClockBinary,
                span=st.just(SPAN),
                op=st.sampled_from([ast.BinaryOp.AND, ast.BinaryOp.OR]),
                left=sub,
                right=sub,
            ),
        )
    )


bounds = st.none() | st.builds(
    ast.Bound, span=st.just(SPAN), low=st.none() | unsigned_numbers, high=st.none() | unsigned_numbers
)


# Arguments of a constraint's action pattern: literals, names and `*` (no `*` operator: inside
# `constraints { }` the lexer reads `*` as the wildcard).
ground_args: st.SearchStrategy[ast.Expr] = st.one_of(exprs(0), st.just(ast.Wildcard(span=SPAN)))


def _spec_binary(op: ast.SpecOp, bound: ast.Bound | None, left: ast.Spec, right: ast.Spec) -> ast.SpecBinary:
    temporal = op in (ast.SpecOp.UNTIL, ast.SpecOp.SINCE)
    return ast.SpecBinary(span=SPAN, op=op, bound=bound if temporal else None, left=left, right=right)


@cache
def specs(depth: int = 2) -> st.SearchStrategy[ast.Spec]:
    ground = st.builds(
        ast.GroundAction, span=st.just(SPAN), name=idents(), args=st.lists(ground_args, max_size=3).map(tuple)
    )
    atoms: st.SearchStrategy[ast.Spec] = st.one_of(
        st.builds(
            ast.ActionAtom,
            span=st.just(SPAN),
            hook=st.sampled_from(["start", "end", "finish", "fail", "cancel", "during"]),
            action=ground,
        ),
        st.builds(ast.StateAtom, span=st.just(SPAN), component=idents(), state=idents()),
    )
    if depth == 0:
        return maybe_paren(atoms)
    sub = specs(depth - 1)
    return maybe_paren(
        st.one_of(
            atoms,
            st.builds(_spec_binary, st.sampled_from(ast.SpecOp), bounds, sub, sub),
            st.builds(ast.SpecUnary, span=st.just(SPAN), op=st.sampled_from(ast.TemporalOp), bound=bounds, operand=sub),
        )
    )


def _component_sections(depth: int = 2) -> st.SearchStrategy[ast.ComponentSection]:
    kw = st.just(SPAN)
    state_def = st.builds(ast.StateDef, span=st.just(SPAN), name=idents(), invariant=st.none() | clock_formulas(depth))
    transition = st.builds(
        ast.Transition,
        span=st.just(SPAN),
        source=idents(),
        controllable=st.booleans(),
        guard=st.none() | clock_formulas(depth),
        target=idents(),
        resets=st.none() | st.lists(idents(), min_size=1, max_size=3).map(tuple),
    )
    return st.one_of(
        st.builds(
            ast.ClocksSection,
            span=st.just(SPAN),
            keyword=kw,
            clocks=st.lists(idents(), min_size=1, max_size=3).map(tuple),
        ),
        st.builds(
            ast.StatesSection,
            span=st.just(SPAN),
            keyword=kw,
            states=st.lists(state_def, min_size=1, max_size=3).map(tuple),
        ),
        st.builds(
            ast.TransitionsSection,
            span=st.just(SPAN),
            keyword=kw,
            transitions=st.lists(transition, min_size=1, max_size=3).map(tuple),
        ),
    )


def platform_declarations(depth: int = 2) -> st.SearchStrategy[ast.Decl]:
    s = st.just(SPAN)
    sections = st.lists(_component_sections(depth), max_size=3).map(tuple)
    constraint = st.builds(ast.Constraint, span=s, condition=specs(depth), requirement=specs(depth))
    return st.one_of(
        st.builds(ast.ComponentDecl, span=s, name=idents(), sections=sections),
        st.builds(ast.ConstraintsDecl, span=s, constraints=st.lists(constraint, min_size=1, max_size=3).map(tuple)),
    )


def declarations() -> st.SearchStrategy[ast.Decl]:
    s = st.just(SPAN)
    return st.one_of(
        st.builds(ast.Include, span=s, path=strings.map(lambda v: ast.StringLit(span=SPAN, value=v))),
        st.builds(ast.DomainDecl, span=s, element_type=types(1), name=idents(), definition=st.none() | domain_exprs()),
        st.builds(
            ast.CompoundDecl,
            span=s,
            name=idents(),
            fields=st.lists(st.builds(ast.Param, span=s, type=types(), name=idents()), min_size=1, max_size=3).map(
                tuple
            ),
        ),
        st.builds(ast.ListTypeDecl, span=s, type=list_types()),
        st.builds(
            ast.FluentDecl,
            span=s,
            type=types(),
            name=idents(),
            params=params,
            initially=st.none()
            | st.lists(
                st.builds(ast.InitialValue, span=s, args=st.lists(exprs(1), max_size=2).map(tuple), value=exprs(2)),
                max_size=3,
            ).map(tuple),
        ),
        st.builds(
            ast.ActionDecl,
            span=s,
            exogenous=st.booleans(),
            name=idents(),
            params=params,
            sections=st.none() | action_sections(),
        ),
        st.builds(ast.FunctionDecl, span=s, type=types(), name=idents(), params=params, body=st.none() | exprs()),
        st.builds(ast.ExogFunctionDecl, span=s, type=types(), name=idents(), params=params),
        st.builds(ast.ProcedureDecl, span=s, name=idents(), params=params, body=st.none() | stmts()),
        platform_declarations(),
    )


def not_overloaded(decls: list[ast.Decl]) -> list[ast.Decl]:
    """The declarations with a name given twice with different numbers of parameters (legacy
    golog++, E0047, which the parser renames) made distinct by the number."""
    arities: dict[str, int] = {}
    distinct: list[ast.Decl] = []
    for d in decls:
        params = getattr(d, "params", None)
        name = getattr(d, "name", None)
        if isinstance(params, tuple) and isinstance(name, ast.Ident) and not isinstance(d, ast.DomainDecl):
            text = name.name
            while arities.setdefault(text, len(params)) != len(params):
                text += str(len(params))
            if text != name.name:
                d = replace(d, name=replace(name, name=text))  # type: ignore[call-arg]
        distinct.append(d)
    return distinct


def make_program(decls: list[ast.Decl], main: ast.Block | None) -> ast.Program:
    if main is not None:
        # Lexer limitation (see the report): after a definition that can end in a name or `)`,
        # a top-level `{` is not recognised as the legacy main block.
        if decls and isinstance(decls[-1], ast.FunctionDecl | ast.DomainDecl):
            decls = [*decls, ast.ProcedureDecl(span=SPAN, name=ast.Ident(span=SPAN, name="p2"), params=(), body=None)]
        decls = [*decls, ast.MainBlock(span=SPAN, body=main)]
    return ast.Program(span=SPAN, declarations=tuple(not_overloaded(decls)))


programs = st.builds(
    make_program,
    st.lists(declarations(), max_size=5),
    st.none() | st.lists(stmts(2), max_size=3).map(lambda b: block(*b)),
)


def n(value: int | float) -> ast.NumberLit:
    return ast.NumberLit(span=SPAN, value=value)


def call(text: str, *args: ast.Expr) -> ast.Call:
    return ast.Call(span=SPAN, name=ast.Ident(span=SPAN, name=text), args=args)


def binary(op: str, left: ast.Expr, right: ast.Expr) -> ast.Binary:
    return ast.Binary(span=SPAN, op=ast.BinaryOp(op), left=left, right=right)
