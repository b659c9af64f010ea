"""Builds the syntax tree from grammar reductions: one method per rule (or rule alias) of
grammar/gpp.lark, called by the parser with the rule's children (tokens and nodes).

Children of repetition helpers are spliced in, so a method sees the flat sequence of tokens
and nodes its rule matched; methods pick their parts by token type and node class.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, TypeVar

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.codes import E0020, E0021
from gpp.syntax import ast
from gpp.syntax.fast import SpanTwin, fast_constructor, make_span
from gpp.syntax.lexer import Token, number_value, unescape_string

Child = Any  # a Token, an ast.Node or (for a few helper rules) a tuple of them
N = TypeVar("N", bound=ast.Node)


# Constructors of the nodes a parse makes most of.
_Ident = fast_constructor(ast.Ident)
_Name = fast_constructor(ast.Name)
_Call = fast_constructor(ast.Call)
_NumberLit = fast_constructor(ast.NumberLit)
_StringLit = fast_constructor(ast.StringLit)
_Binary = fast_constructor(ast.Binary)
_Unary = fast_constructor(ast.Unary)
_FieldAccess = fast_constructor(ast.FieldAccess)
_Index = fast_constructor(ast.Index)
_NamedType = fast_constructor(ast.NamedType)
_Param = fast_constructor(ast.Param)
_FieldInit = fast_constructor(ast.FieldInit)
_MappingArg = fast_constructor(ast.MappingArg)
_CallStmt = fast_constructor(ast.CallStmt)
_Assign = fast_constructor(ast.Assign)
_Block = fast_constructor(ast.Block)

# The operators by their text (calling an Enum class to look a member up is slow).
_BINARY_OPS = {op.value: op for op in ast.BinaryOp}


def _nodes(children: Sequence[Child], kind: type[N]) -> tuple[N, ...]:
    return tuple([c for c in children if isinstance(c, kind)])


def _statements(children: Sequence[Child]) -> tuple[ast.Statement, ...]:
    return tuple([c for c in children if isinstance(c, ast.Statement)])


def _first(children: Sequence[Child], kind: type[N]) -> N:
    for c in children:
        if isinstance(c, kind):
            return c
    raise AssertionError(f"no {kind.__name__} among the children")


def _tokens(children: Sequence[Child], ttype: str) -> list[Token]:
    return [c for c in children if type(c) is Token and c.type == ttype]


@dataclass(frozen=True, slots=True)
class _Until:
    """The `until (e)` clause of a `during`, passed up to `during`."""

    condition: ast.Expr


class AstBuilder:
    """The reductions of one parse; `diagnostics` collects what the tree shape reveals
    (a section given twice, a handler given twice)."""

    def __init__(self, source: Source) -> None:
        self.source = source
        self.diagnostics: list[diag.Diagnostic] = []

    # ---------------------------------------------------------------- helpers

    def span(self, children: Sequence[Child]) -> Span:
        first = children[0]
        last = children[-1]
        # make_span (gpp.syntax.fast), inlined: the builder makes a span for almost every reduction.
        span: Any = SpanTwin()
        span.source = self.source
        span.start = first.start if type(first) is Token else first.span.start
        span.end = last.end if type(last) is Token else last.span.end
        span.__class__ = Span
        made: Span = span
        return made

    def tspan(self, token: Token) -> Span:
        return make_span(self.source, token.start, token.end)

    def ident(self, token: Token) -> ast.Ident:
        return _Ident(span=make_span(self.source, token.start, token.end), name=token.value)

    def idents(self, children: Sequence[Child]) -> tuple[ast.Ident, ...]:
        return tuple(self.ident(t) for t in _tokens(children, "NAME"))

    def exprs_between(self, children: Sequence[Child], open_type: str, close_type: str) -> tuple[ast.Expr, ...]:
        """The expressions between the first `open_type` token and the next `close_type`."""
        out: list[ast.Expr] = []
        inside = False
        for c in children:
            if type(c) is Token:
                if c.type == open_type and not inside:
                    inside = True
                elif c.type == close_type and inside:
                    break
            elif inside and isinstance(c, ast.Expr):
                out.append(c)
        return tuple(out)

    # ---------------------------------------------------------------- program

    def start(self, c: list[Child]) -> ast.Program:
        return ast.Program(span=Span(self.source, 0, len(self.source.text)), declarations=_nodes(c, ast.Decl))

    def include(self, c: list[Child]) -> ast.Include:
        return ast.Include(span=self.span(c), path=self.string([c[1]]))

    # ---------------------------------------------------------------- types

    def named_type(self, c: list[Child]) -> ast.NamedType:
        return _NamedType(span=self.span(c), name=c[0].value)

    builtin_type = named_type

    def list_type(self, c: list[Child]) -> ast.ListType:
        return ast.ListType(span=self.span(c), element=c[2])

    def params(self, c: list[Child]) -> tuple[ast.Param, ...]:
        return _nodes(c, ast.Param)

    def param(self, c: list[Child]) -> ast.Param:
        return _Param(span=self.span(c), type=c[0], name=self.ident(c[1]))

    # ---------------------------------------------------------------- declarations

    def domain_forward(self, c: list[Child]) -> ast.DomainDecl:
        return ast.DomainDecl(span=self.span(c), element_type=c[0], name=self.ident(c[2]), definition=None)

    def domain_def(self, c: list[Child]) -> ast.DomainDecl:
        return ast.DomainDecl(span=self.span(c), element_type=c[0], name=self.ident(c[2]), definition=c[4])

    def domain_binary(self, c: list[Child]) -> ast.DomainBinary:
        return ast.DomainBinary(span=self.span(c), op=ast.DomainOp(c[1].value), left=c[0], right=c[2])

    def domain_ref(self, c: list[Child]) -> ast.DomainRef:
        return ast.DomainRef(span=self.span(c), name=self.ident(c[0]))

    def domain_set(self, c: list[Child]) -> ast.DomainSet:
        return ast.DomainSet(span=self.span(c), elements=_nodes(c, ast.Expr))

    def domain_paren(self, c: list[Child]) -> ast.DomainExpr:
        inner: ast.DomainExpr = c[1]
        return replace(inner, span=self.span(c), parenthesized=True)

    def compound_decl(self, c: list[Child]) -> ast.CompoundDecl:
        return ast.CompoundDecl(span=self.span(c), name=self.ident(c[1]), fields=_nodes(c, ast.Param))

    def list_decl(self, c: list[Child]) -> ast.ListTypeDecl:
        return ast.ListTypeDecl(span=self.span(c), type=c[0])

    def fluent_forward(self, c: list[Child]) -> ast.FluentDecl:
        return ast.FluentDecl(span=self.span(c), type=c[0], name=self.ident(c[2]), params=c[3], initially=None)

    def fluent_def(self, c: list[Child]) -> ast.FluentDecl:
        initially = _nodes(c, ast.InitialValue)
        return ast.FluentDecl(span=self.span(c), type=c[0], name=self.ident(c[2]), params=c[3], initially=initially)

    def initial(self, c: list[Child]) -> ast.InitialValue:
        args = self.exprs_between(c, "LPAR", "RPAR")
        return ast.InitialValue(span=self.span(c), args=args, value=c[-2])

    def _action(
        self, c: list[Child], exogenous: bool, sections: tuple[ast.ActionSection, ...] | None
    ) -> ast.ActionDecl:
        if sections:
            seen: dict[type[ast.ActionSection], ast.ActionSection] = {}
            for s in sections:
                first = seen.get(type(s))
                if first is None:
                    seen[type(s)] = s
                    continue
                word = ast.SECTION_KINDS[type(s)].value
                self.diagnostics.append(
                    diag.error(
                        E0020.twice(word),
                        s.keyword,
                        "second section",
                        secondary=[diag.Label(first.keyword, "first given here")],
                        help=f"merge the two `{word}:` sections into one",
                    )
                )
        return ast.ActionDecl(
            span=self.span(c), exogenous=exogenous, name=self.ident(c[1]), params=c[2], sections=sections
        )

    def action_forward(self, c: list[Child]) -> ast.ActionDecl:
        return self._action(c, False, None)

    def action_def(self, c: list[Child]) -> ast.ActionDecl:
        return self._action(c, False, _nodes(c, ast.ActionSection))

    def exog_action_forward(self, c: list[Child]) -> ast.ActionDecl:
        return self._action(c, True, None)

    def exog_action_def(self, c: list[Child]) -> ast.ActionDecl:
        return self._action(c, True, _nodes(c, ast.ActionSection))

    def sec_precondition(self, c: list[Child]) -> ast.PreconditionSection:
        return ast.PreconditionSection(span=self.span(c), keyword=self.tspan(c[0]), condition=c[1])

    def sec_effect(self, c: list[Child]) -> ast.EffectSection:
        return ast.EffectSection(span=self.span(c), keyword=self.tspan(c[0]), effects=_nodes(c, ast.Effect))

    def sec_start_effect(self, c: list[Child]) -> ast.StartEffectSection:
        return ast.StartEffectSection(span=self.span(c), keyword=self.tspan(c[0]), effects=_nodes(c, ast.Effect))

    def sec_senses(self, c: list[Child]) -> ast.SensesSection:
        return ast.SensesSection(span=self.span(c), keyword=self.tspan(c[0]), target=c[1], value=c[3])

    def sec_mapping(self, c: list[Child]) -> ast.MappingSection:
        return ast.MappingSection(span=self.span(c), keyword=self.tspan(c[0]), mapping=c[1])

    def sec_silent(self, c: list[Child]) -> ast.SilentSection:
        return ast.SilentSection(span=self.span(c), keyword=self.tspan(c[0]), value=c[1])

    def sec_duration(self, c: list[Child]) -> ast.DurationSection:
        return ast.DurationSection(span=self.span(c), keyword=self.tspan(c[0]), low=c[2], high=c[4])

    def effect(self, c: list[Child]) -> ast.Effect:
        return ast.Effect(span=self.span(c), condition=None, target=c[0], value=c[2])

    def cond_effect(self, c: list[Child]) -> ast.Effect:
        return ast.Effect(span=self.span(c), condition=c[2], target=c[4], value=c[6])

    def mapping(self, c: list[Child]) -> ast.Mapping:
        return ast.Mapping(span=self.span(c), name=self.string([c[0]]), args=_nodes(c, ast.MappingArg))

    def mapping_arg(self, c: list[Child]) -> ast.MappingArg:
        return _MappingArg(span=self.span(c), name=self.ident(c[0]), value=c[2])

    def function_forward(self, c: list[Child]) -> ast.FunctionDecl:
        return ast.FunctionDecl(span=self.span(c), type=c[0], name=self.ident(c[2]), params=c[3], body=None)

    def function_def(self, c: list[Child]) -> ast.FunctionDecl:
        return ast.FunctionDecl(span=self.span(c), type=c[0], name=self.ident(c[2]), params=c[3], body=c[5])

    def exog_function_decl(self, c: list[Child]) -> ast.ExogFunctionDecl:
        return ast.ExogFunctionDecl(span=self.span(c), type=c[0], name=self.ident(c[2]), params=c[3])

    def procedure_forward(self, c: list[Child]) -> ast.ProcedureDecl:
        return ast.ProcedureDecl(span=self.span(c), name=self.ident(c[1]), params=c[2], body=None)

    def procedure_def(self, c: list[Child]) -> ast.ProcedureDecl:
        return ast.ProcedureDecl(span=self.span(c), name=self.ident(c[1]), params=c[2], body=c[3])

    def main_block(self, c: list[Child]) -> ast.MainBlock:
        span = self.span(c)
        return ast.MainBlock(span=span, body=_Block(span=span, body=_statements(c)))

    # ---------------------------------------------------------------- statements

    def block(self, c: list[Child]) -> ast.Block:
        return _Block(span=self.span(c), body=_statements(c))

    def choose(self, c: list[Child]) -> ast.Choose:
        return ast.Choose(span=self.span(c), alternatives=_statements(c))

    def concurrent(self, c: list[Child]) -> ast.Concurrent:
        return ast.Concurrent(span=self.span(c), branches=_statements(c))

    def if_stmt(self, c: list[Child]) -> ast.If:
        otherwise = c[6] if len(c) == 7 else None
        return ast.If(span=self.span(c), condition=c[2], then=c[4], otherwise=otherwise)

    def while_stmt(self, c: list[Child]) -> ast.While:
        return ast.While(span=self.span(c), condition=c[2], body=c[4])

    def pick(self, c: list[Child]) -> ast.Pick:
        values = self.exprs_between(c, "LBRACE", "RBRACE") if _tokens(c, "IN") else None
        return ast.Pick(span=self.span(c), var_type=c[2], var=self.ident(c[3]), values=values, body=c[-1])

    def solve(self, c: list[Child]) -> ast.Solve:
        return ast.Solve(span=self.span(c), horizon=c[2], reward=c[4], body=c[6])

    def search(self, c: list[Child]) -> ast.Search:
        return ast.Search(span=self.span(c), body=c[1])

    def handler(self, c: list[Child]) -> tuple[Token, ast.Statement]:
        return (c[0], c[1])

    def until_clause(self, c: list[Child]) -> _Until:
        return _Until(c[2])

    def during(self, c: list[Child]) -> ast.During:
        until = c[4].condition if isinstance(c[4], _Until) else None
        if until is not None:
            c = [*c[:4], *c[5:]]
        handlers: dict[str, tuple[Token, ast.Statement]] = {}
        for h in c[5:]:
            keyword = h[0]
            first = handlers.get(keyword.type)
            if first is not None:
                self.diagnostics.append(
                    diag.error(
                        E0021.twice(keyword.value),
                        self.tspan(keyword),
                        "second handler",
                        secondary=[diag.Label(self.tspan(first[0]), "first given here")],
                    )
                )
                continue
            handlers[keyword.type] = h
        last = c[-1][1] if len(c) > 5 else c[4]
        on_fail = handlers.get("ON_FAIL")
        on_cancel = handlers.get("ON_CANCEL")
        return ast.During(
            span=Span(self.source, c[0].start, last.span.end),
            action=c[2],
            until=until,
            body=c[4],
            on_fail=on_fail[1] if on_fail else None,
            on_cancel=on_cancel[1] if on_cancel else None,
        )

    def test(self, c: list[Child]) -> ast.Test:
        return ast.Test(span=self.span(c), condition=c[2])

    def hook(self, c: list[Child]) -> ast.HookStmt:
        return ast.HookStmt(span=self.span(c), hook=ast.Hook(c[0].value), action=c[2])

    def assign(self, c: list[Child]) -> ast.Assign:
        return _Assign(span=self.span(c), target=c[0], value=c[2])

    def list_pop(self, c: list[Child]) -> ast.ListStmt:
        return ast.ListStmt(span=self.span(c), op=ast.ListOp(c[0].value), target=c[2], value=None)

    def list_push(self, c: list[Child]) -> ast.ListStmt:
        return ast.ListStmt(span=self.span(c), op=ast.ListOp(c[0].value), target=c[2], value=c[4])

    def call_stmt(self, c: list[Child]) -> ast.CallStmt:
        return _CallStmt(span=self.span(c), call=c[0])

    # ---------------------------------------------------------------- expressions

    def binary(self, c: list[Child]) -> ast.Binary:
        left, op, right = c
        return _Binary(
            span=make_span(self.source, left.span.start, right.span.end),
            op=_BINARY_OPS[op.value],
            left=left,
            right=right,
        )

    def unary(self, c: list[Child]) -> ast.Expr:
        op, operand = c
        span = make_span(self.source, op.start, operand.span.end)
        if op.value == "+":
            result: ast.Expr = replace(operand, span=span) if type(operand) is ast.NumberLit else operand
            return result
        if op.value == "-":
            # A minus sign directly on a number literal is part of the literal: `-5`.
            if type(operand) is ast.NumberLit and not operand.parenthesized and math.copysign(1, operand.value) > 0:
                return _NumberLit(span=span, value=-operand.value)
            return _Unary(span=span, op=ast.UnaryOp.NEG, operand=operand)
        return _Unary(span=span, op=ast.UnaryOp.NOT, operand=operand)

    def quantifier(self, c: list[Child]) -> ast.Quantified:
        return ast.Quantified(
            span=self.span(c), quantifier=ast.Quantifier(c[0].value), var_type=c[2], var=self.ident(c[3]), body=c[5]
        )

    def conditional(self, c: list[Child]) -> ast.Conditional:
        return ast.Conditional(span=self.span(c), condition=c[2], then=c[4], otherwise=c[6])

    def field(self, c: list[Child]) -> ast.FieldAccess:
        return _FieldAccess(span=self.span(c), subject=c[0], field=self.ident(c[2]))

    def index(self, c: list[Child]) -> ast.Index:
        return _Index(span=self.span(c), subject=c[0], index=c[2])

    def number(self, c: list[Child]) -> ast.NumberLit:
        text: str = c[0].value
        # A literal beyond the range of numbers is an error already (E0004, from the lexer).
        literal = number_value(text)
        value: int | float = math.inf if literal is None else literal
        return _NumberLit(span=make_span(self.source, c[0].start, c[0].end), value=value)

    def string(self, c: list[Child]) -> ast.StringLit:
        return _StringLit(span=self.tspan(c[0]), value=unescape_string(c[0].value))

    def true(self, c: list[Child]) -> ast.BoolLit:
        return ast.BoolLit(span=self.tspan(c[0]), value=True)

    def false(self, c: list[Child]) -> ast.BoolLit:
        return ast.BoolLit(span=self.tspan(c[0]), value=False)

    def null(self, c: list[Child]) -> ast.NullLit:
        return ast.NullLit(span=self.tspan(c[0]))

    def name(self, c: list[Child]) -> ast.Name:
        token = c[0]
        return _Name(span=make_span(self.source, token.start, token.end), name=token.value)

    def call(self, c: list[Child]) -> ast.Call:
        # NAME ( [expr (, expr)*] ): the arguments are every other child
        return _Call(span=self.span(c), name=self.ident(c[0]), args=tuple(c[2:-1:2]))

    def paren(self, c: list[Child]) -> ast.Expr:
        inner: ast.Expr = c[1]
        return replace(inner, span=self.span(c), parenthesized=True)

    def compound_lit(self, c: list[Child]) -> ast.CompoundLit:
        return ast.CompoundLit(span=self.span(c), type_name=self.ident(c[0]), fields=_nodes(c, ast.FieldInit))

    def field_init(self, c: list[Child]) -> ast.FieldInit:
        return _FieldInit(span=self.span(c), name=self.ident(c[0]), value=c[2])

    def list_lit(self, c: list[Child]) -> ast.ListLit:
        return ast.ListLit(span=self.span(c), type=c[0], elements=_nodes(c[1:], ast.Expr))

    def builtin(self, c: list[Child]) -> ast.BuiltinCall:
        return ast.BuiltinCall(span=self.span(c), function=ast.Builtin(c[0].value), arg=c[2])

    # ---------------------------------------------------------------- platform model

    def component_decl(self, c: list[Child]) -> ast.ComponentDecl:
        return ast.ComponentDecl(span=self.span(c), name=self.ident(c[1]), sections=_nodes(c, ast.ComponentSection))

    def clocks(self, c: list[Child]) -> ast.ClocksSection:
        return ast.ClocksSection(span=self.span(c), keyword=self.tspan(c[0]), clocks=self.idents(c))

    def states(self, c: list[Child]) -> ast.StatesSection:
        return ast.StatesSection(span=self.span(c), keyword=self.tspan(c[0]), states=_nodes(c, ast.StateDef))

    def transitions(self, c: list[Child]) -> ast.TransitionsSection:
        return ast.TransitionsSection(
            span=self.span(c), keyword=self.tspan(c[0]), transitions=_nodes(c, ast.Transition)
        )

    def state_def(self, c: list[Child]) -> ast.StateDef:
        invariants = _nodes(c, ast.ClockFormula)
        return ast.StateDef(span=self.span(c), name=self.ident(c[0]), invariant=invariants[0] if invariants else None)

    def transition(self, c: list[Child]) -> ast.Transition:
        guards = _nodes(c, ast.ClockFormula)
        names = _tokens(c, "NAME")
        resets = tuple(self.ident(t) for t in names[2:]) if _tokens(c, "RESETS") else None
        return ast.Transition(
            span=self.span(c),
            source=self.ident(names[0]),
            controllable=c[1].type == "CONTROLLABLE",
            guard=guards[0] if guards else None,
            target=self.ident(names[1]),
            resets=resets,
        )

    def clock_binary(self, c: list[Child]) -> ast.ClockBinary:
        return ast.ClockBinary(span=self.span(c), op=_BINARY_OPS[c[1].value], left=c[0], right=c[2])

    def clock_bound(self, c: list[Child]) -> ast.ClockBound:
        return ast.ClockBound(
            span=self.span(c), clock=self.ident(c[0]), op=_BINARY_OPS[c[1].value], bound=self.number([c[2]])
        )

    def clock_not(self, c: list[Child]) -> ast.ClockNot:
        return ast.ClockNot(span=self.span(c), operand=c[1])

    def clock_paren(self, c: list[Child]) -> ast.ClockFormula:
        inner: ast.ClockFormula = c[1]
        return replace(inner, span=self.span(c), parenthesized=True)

    def constraints_decl(self, c: list[Child]) -> ast.ConstraintsDecl:
        return ast.ConstraintsDecl(span=self.span(c), constraints=_nodes(c, ast.Constraint))

    def constraint(self, c: list[Child]) -> ast.Constraint:
        return ast.Constraint(span=self.span(c), condition=c[0], requirement=c[2])

    def spec_binary(self, c: list[Child]) -> ast.SpecBinary:
        bound = c[2] if len(c) == 4 else None
        return ast.SpecBinary(span=self.span(c), op=ast.SpecOp(c[1].value), bound=bound, left=c[0], right=c[-1])

    def spec_paren(self, c: list[Child]) -> ast.Spec:
        inner: ast.Spec = c[1]
        return replace(inner, span=self.span(c), parenthesized=True)

    def spec_unary_op(self, c: list[Child]) -> ast.SpecUnary:
        bound = c[1] if len(c) == 3 else None
        return ast.SpecUnary(span=self.span(c), op=ast.TemporalOp(c[0].value), bound=bound, operand=c[-1])

    def action_atom(self, c: list[Child]) -> ast.ActionAtom:
        return ast.ActionAtom(span=self.span(c), hook=c[0].value, action=c[2])

    def state_atom(self, c: list[Child]) -> ast.StateAtom:
        return ast.StateAtom(span=self.span(c), component=self.ident(c[2]), state=self.ident(c[5]))

    def bound(self, c: list[Child]) -> ast.Bound:
        low: ast.NumberLit | None = None
        high: ast.NumberLit | None = None
        seen_comma = False
        for t in c:
            if t.type == "COMMA":
                seen_comma = True
            elif t.type == "NUMBER":
                if seen_comma:
                    high = self.number([t])
                else:
                    low = self.number([t])
        return ast.Bound(span=self.span(c), low=low, high=high)

    def ground_action(self, c: list[Child]) -> ast.GroundAction:
        return ast.GroundAction(span=self.span(c), name=self.ident(c[0]), args=_nodes(c, ast.Expr))

    def wildcard(self, c: list[Child]) -> ast.Wildcard:
        return ast.Wildcard(span=self.tspan(c[0]))
