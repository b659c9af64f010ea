"""The type checker: what type every expression has, and which statements and expressions are
type errors. golog++'s typing rules live here; the other phases ask it for types and check
only what is particular to a declaration (names given twice, sections, initial-value shapes).

Used by the later phases of the model builder (gpp.model.build): the domains phase types
literal members, the declarations phase types initial values, sections, function bodies and
procedure bodies, and everything in them goes through `stmt` and `expr`. It owns:

* statements (`stmt`, one case per kind): conditions are bool, only actions and procedures
  are executed, only fluents (and their fields and elements) are assigned, `pick`/`solve`/
  `during`/hooks/list operations take what they need;
* expressions (`expr`): the type of every literal, name, call, operator, quantifier,
  conditional, field access, index, compound and list literal and builtin, recorded in
  `model.expr_types`; an expression with an error gets the type ERROR, which fits everywhere,
  so a mistake is reported once;
* what fits where (`expect`, `check_fits`, `expect_literal`): assignability, domain
  membership of literals, literal-only slots;
* the scopes of parameters and variables (`scope`, `new_variable`).

Reads the symbols and types of phases 1 and 2; writes `model.expr_types`, `model.targets`,
`model.references`, `model.scopes` and `model.rewritten` (the chains gpp.model.regroup
rebuilt); reports into the shared state.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from typing import Any, assert_never

from gpp.base import diagnostics as diag
from gpp.base.source import Span
from gpp.base.suggest import NameIndex, suggestion, suggestion_among
from gpp.codes import (
    E0101,
    E0102,
    E0103,
    E0104,
    E0105,
    E0106,
    E0201,
    E0202,
    E0203,
    E0204,
    E0205,
    E0207,
    E0208,
    E0209,
    E0210,
    E0211,
    E0212,
    E0213,
    E0306,
)
from gpp.model.builder_state import BuilderState, new_tuple
from gpp.model.regroup import BOOL_CHAIN, CHAIN_OPS, EQUALITY, Regrouper, continues_chain
from gpp.model.resolve import TypeResolver
from gpp.model.symbols import EXPRESSION_CALLABLE, STATEMENT_CALLABLE, Reference, ScopeRecord, Symbol, SymbolKind
from gpp.model.types import (
    BOOL,
    ERROR,
    NULL,
    NUMBER,
    STRING,
    SYMBOL,
    VOID,
    CompoundType,
    DomainType,
    DomainValue,
    ListType,
    Sym,
    Type,
    assignable,
    base,
    common_type,
    equatable,
    is_finite,
    ordered,
    same_type,
    show_value,
)
from gpp.syntax import ast

Op = ast.BinaryOp

# Enum members read on every node, bound once: Python 3.11's enum class has a `__getattr__`,
# which makes reading any attribute of the class (`SymbolKind.SYMBOL`) several times slower
# than reading a global.
_SYMBOL_KIND = SymbolKind.SYMBOL
_VARIABLE = SymbolKind.VARIABLE
_FLUENT = SymbolKind.FLUENT
_FUNCTION = SymbolKind.FUNCTION
_COMPOUND = SymbolKind.COMPOUND
_NOT = ast.UnaryOp.NOT
_LENGTH = ast.Builtin.LENGTH
_ADD = Op.ADD

# (Kinds to test with `isinstance` as tuples, made once: `isinstance(x, A | B)` builds the
# union on every call, and a union is slower to test than a tuple.)
_SCALAR_LITERALS = (ast.NumberLit, ast.StringLit, ast.BoolLit, ast.NullLit, ast.Name)
_VALUE_LITERALS = (ast.NumberLit, ast.StringLit, ast.BoolLit)
_COLLECTION_LITERALS = (ast.CompoundLit, ast.ListLit)
_PATH_STEPS = (ast.FieldAccess, ast.Index)
_NOT_CONVERTIBLE = (CompoundType, ListType)


def is_literal(e: ast.Expr) -> bool:
    """A value written out: what initial values, `pick ... in`, domains and durations take."""
    if isinstance(e, _SCALAR_LITERALS):
        return True
    if isinstance(e, ast.CompoundLit):
        return all(is_literal(f.value) for f in e.fields)
    if isinstance(e, ast.ListLit):
        return all(is_literal(x) for x in e.elements)
    return False


def _names_in_literal(e: ast.Expr) -> Sequence[ast.Name]:
    """The bare names in a literal, in source order (most literals are a number or a name)."""
    if isinstance(e, ast.Name):
        return (e,)
    if isinstance(e, _COLLECTION_LITERALS):
        names: list[ast.Name] = []
        _collect_names(e, names)
        return names
    return ()


def _collect_names(e: ast.Expr, names: list[ast.Name]) -> None:
    """The names in a literal (`is_literal`), in source order (as a walk meets them)."""
    if isinstance(e, ast.Name):
        names.append(e)
    elif isinstance(e, ast.CompoundLit):
        for f in e.fields:
            _collect_names(f.value, names)
    elif isinstance(e, ast.ListLit):
        for x in e.elements:
            _collect_names(x, names)


def _text(op: str | Op) -> str:
    """An operator as written."""
    return op if isinstance(op, str) else op.value


def _written_by_legacy_rewrite(type_: ast.TypeExpr) -> bool:
    """Whether a variable's type is one the legacy rewrite wrote (no text: an empty span), for
    an `exists (%z)` that it reports itself (E0049)."""
    return type_.span.start == type_.span.end


def operator_span(e: ast.Binary) -> Span:
    """The span of a binary expression's operator token (found between its operands)."""
    source = e.span.source
    start, end = e.left.span.end, e.right.span.start
    text = source.text[start:end]
    at = text.find(e.op.value)
    if at < 0:
        return e.span
    return Span(source, start + at, start + at + len(e.op.value))


# Only an operator of `CHAIN_OPS` (gpp.model.regroup) may belong to a boolean chain the
# regrouping rebuilds; any other binary or unary operator starts no chain.
# (Tuples of operators and kinds, as there, not sets, where every expression asks: an enum
# member's hash is computed in Python, comparing identities is not.)
_COMPARISON = tuple(ast.COMPARISON_OPS)

# The kinds a call may name in an expression, as a statement, and (`_ACTION`) in a hook
# (`start`, `during`, ...).
_ACTION = (SymbolKind.ACTION,)
_CALLABLE_IN = {"expression": tuple(EXPRESSION_CALLABLE), "statement": tuple(STATEMENT_CALLABLE)}

_NAME, _CALL = ast.Name, ast.Call
_LITERAL_TYPES: dict[type[ast.Expr], Type] = {
    ast.NumberLit: NUMBER,
    ast.StringLit: STRING,
    ast.BoolLit: BOOL,
    ast.NullLit: NULL,
}


class _Scopes:
    """The variables visible at a point of a body: one table of the innermost symbol of each
    name (one look-up per name, however deep the scopes), and per open scope what it hid.
    Also what `TypeChecker.scope` returns, to end the innermost scope on leaving a `with`
    block (a class, not a generator: scopes are opened for every body and quantifier)."""

    __slots__ = ("hidden", "visible")

    def __init__(self) -> None:
        self.visible: dict[str, Symbol] = {}
        # Per open scope: (name, the symbol it hid or None), in the order they were declared.
        self.hidden: list[Sequence[tuple[str, Symbol | None]]] = []

    def open(self, symbols: Sequence[Symbol]) -> None:
        if not symbols:  # a body without parameters: nothing to hide
            self.hidden.append(())
            return
        visible = self.visible
        hidden: list[tuple[str, Symbol | None]] = []
        for s in symbols:
            name = s.name
            hidden.append((name, visible.get(name)))
            visible[name] = s
        self.hidden.append(hidden)

    def __enter__(self) -> None:
        return None

    def __exit__(self, exc_type: object, exc: object, traceback: object) -> None:
        hidden = self.hidden.pop()
        if hidden:
            visible = self.visible
            for name, symbol in reversed(hidden):
                if symbol is None:
                    del visible[name]
                else:
                    visible[name] = symbol


class TypeChecker(Regrouper):
    def __init__(self, state: BuilderState, resolver: TypeResolver) -> None:
        super().__init__(state)
        self.resolver = resolver
        self.scopes = _Scopes()
        self.variables = self.scopes.visible
        self.expr_types = self.model.expr_types
        self.add_reference = self.model.references.append
        self.targets = self.model.targets
        self.scope_records = self.model.scopes
        self.symbols = self.model.symbols
        self.globals = self.model.globals
        # One value per symbol name, for the domain membership of literals.
        self.symbol_values: dict[str, Sym] = {}

    # ---------------------------------------------------------------- scopes

    def scope(self, span: Span, symbols: Sequence[Symbol]) -> AbstractContextManager[None]:
        """Open a scope of `symbols` (parameters, a variable) for the `with` block around a
        body."""
        scopes = self.scopes
        scopes.open(symbols)
        if symbols and not self.state.silent:
            self.scope_records.append(new_tuple(ScopeRecord, (span, tuple(symbols))))  # ScopeRecord(...), faster
        return scopes

    def lookup_variable(self, name: str) -> Symbol | None:
        return self.variables.get(name)

    def visible_variables(self) -> set[str]:
        return set(self.variables)

    def new_variable(self, var_type: ast.TypeExpr, var: ast.Ident, decl: ast.Node) -> Symbol:
        symbol = Symbol(var.name, _VARIABLE, var.span, decl, self.resolver.resolve_type(var_type))
        self.refer(var.span, symbol, var, declaration=True)
        return symbol

    # ---------------------------------------------------------------- literal-only slots

    def expect_literal(
        self,
        e: ast.Expr,
        target: Type | None,
        rule: str,
        context: str,
        span: Span | None,
        help: str | None = None,
    ) -> None:
        """Check an expression where only a literal may stand (initial values, `pick ... in`,
        constraint patterns): written as a literal, and every bare name in it a symbol."""
        if not is_literal(e):
            self.error(E0213.not_literal(rule), e.span, "not a literal", help=help)
            self.expr(e)
            return
        if target is not None:
            self.expect(e, target, context, span)
        else:
            self.expr(e)
        for node in _names_in_literal(e):
            symbol = self.model.targets.get(id(node))
            if symbol is not None and symbol.kind is not _SYMBOL_KIND:
                self.error(
                    E0213.names_non_symbol(rule, node.name, symbol.kind),
                    node.span,
                    "not a literal",
                    help=help,
                )

    # ---------------------------------------------------------------- statements

    def stmt(self, s: ast.Statement) -> None:
        # By table first: a `match` tries its class patterns one after another (about 0.1 µs
        # each, 1.5 µs to reach the last). The `match` is the general path, for a kind the
        # table lacks; it ends in `assert_never`, so a new statement kind makes mypy name this
        # place (tests/syntax/test_statement_kinds.py).
        check = _STMT_KINDS.get(s.__class__)
        if check is not None:
            check(self, s)
            return
        match s:
            case ast.CallStmt():
                self.call_stmt(s)
            case ast.Block():
                self.block(s)
            case ast.Assign():
                self.assign(s)
            case ast.If():
                self.if_stmt(s)
            case ast.While():
                self.while_stmt(s)
            case ast.Test():
                self.test(s)
            case ast.Choose():
                self.choose(s)
            case ast.Concurrent():
                self.concurrent(s)
            case ast.Pick():
                self.pick(s)
            case ast.Solve():
                self.solve(s)
            case ast.Search():
                self.search(s)
            case ast.During():
                self.during(s)
            case ast.HookStmt():
                self.hook(s)
            case ast.ListStmt():
                self.list_stmt(s)
            case _:
                assert_never(s)

    def block(self, s: ast.Block) -> None:
        for x in s.body:
            self.stmt(x)

    def call_stmt(self, s: ast.CallStmt) -> None:
        if isinstance(s.call, ast.Call):
            self.call(s.call, "statement")
        elif isinstance(s.call, ast.Name) and self.bare_statement_call(s.call):
            return
        else:
            self.expr(s.call)
            self.error(
                E0104.not_a_statement(),
                s.call.span,
                "its value would be thrown away",
                help="statements call actions or procedures, assign fluents, or `test(...)` a condition",
            )

    def bare_statement_call(self, e: ast.Name) -> bool:
        """`wave;`: an action or procedure named without `()` as a statement. Reported as the
        missing call it is (with `()` as the fix when it takes no arguments); False when the
        name is something else."""
        g = self.model.globals.get(e.name)
        if e.name in self.variables or e.name in self.symbols or g is None or g.kind not in STATEMENT_CALLABLE:
            return False
        self.refer(e.span, g, e)
        self.missing_call(e, g)
        return True

    def missing_call(self, e: ast.Name, g: Symbol) -> None:
        """E0102 on a global named without `()`; `()` is the fix when it has no parameters."""
        self.error(
            E0102.missing_call(e.name, g.kind),
            e.span,
            "missing `(...)`",
            secondary=self.declared_here(g),
            help=f"write `{e.name}()`" if not g.params else f"write `{e.name}(...)` with its arguments",
            # Without parameters, `()` is the one repair; the fix's message is the help line.
            fix=diag.Fix(
                f"write `{e.name}()`",
                (diag.Edit(Span(e.span.source, e.span.end, e.span.end), "()"),),
                diag.Applicability.SAFE,
            )
            if not g.params
            else None,
        )

    def assign(self, s: ast.Assign) -> None:
        target = self.assign_target(s.target)
        self.expect(s.value, target, "the assigned fluent")

    def if_stmt(self, s: ast.If) -> None:
        self.expect(s.condition, BOOL, "an `if` condition")
        self.stmt(s.then)
        if s.otherwise is not None:
            self.stmt(s.otherwise)

    def while_stmt(self, s: ast.While) -> None:
        self.expect(s.condition, BOOL, "a `while` condition")
        self.stmt(s.body)

    def test(self, s: ast.Test) -> None:
        self.expect(s.condition, BOOL, "a `test`")

    def choose(self, s: ast.Choose) -> None:
        for x in s.alternatives:
            self.stmt(x)

    def concurrent(self, s: ast.Concurrent) -> None:
        for x in s.branches:
            self.stmt(x)

    def search(self, s: ast.Search) -> None:
        self.stmt(s.body)

    def during(self, s: ast.During) -> None:
        self.action_call(s.action, "during")
        if s.until is not None:
            self.expect(s.until, BOOL, "an `until` condition")
        self.stmt(s.body)
        if s.on_fail is not None:
            self.stmt(s.on_fail)
        if s.on_cancel is not None:
            self.stmt(s.on_cancel)

    def hook(self, s: ast.HookStmt) -> None:
        self.action_call(s.action, s.hook.value)

    def list_stmt(self, s: ast.ListStmt) -> None:
        target = self.assign_target(s.target)
        if target is not ERROR and not isinstance(target, ListType) and target is not NULL:
            self.error(E0204.needs_list(s.op.value, target), s.target.span, f"this is `{target}`")
            target = ERROR
        if s.value is not None:
            element = target.element if isinstance(target, ListType) else ERROR
            self.expect(s.value, element, "the list's element type")

    def action_call(self, e: ast.Expr, hook: str) -> None:
        if isinstance(e, ast.Call):
            self.call(e, hook)
        else:
            self.expr(e)
            self.error(E0104.hook_needs_action(hook), e.span)

    def pick(self, s: ast.Pick) -> None:
        variable = self.new_variable(s.var_type, s.var, s)
        var_type = variable.type or ERROR
        if s.values is None:
            if not is_finite(var_type) and not _written_by_legacy_rewrite(s.var_type):
                self.error(
                    E0210.pick(var_type),
                    s.var_type.span,
                    f"`{var_type}` has infinitely many values",
                    help=f"write `pick ({var_type} {s.var.name} in {{...}})` or use a domain type",
                )
        else:
            for v in s.values:
                self.expect_literal(v, var_type, E0213.PICK_VALUES, f"`{s.var.name}`", s.var_type.span)
        # The variable is visible in the body only (not in its own list of values).
        with self.scope(s.body.span, [variable]):
            self.stmt(s.body)

    def solve(self, s: ast.Solve) -> None:
        self.expect(s.horizon, NUMBER, "a `solve` horizon")
        reward = s.reward
        if isinstance(reward, ast.Call) and not reward.parenthesized:
            symbol = self.model.globals.get(reward.name.name)
            if symbol is not None and symbol.kind is not _FUNCTION:
                self.resolve_misused_call(reward, symbol)
                self.error(
                    E0212.reward_not_function(symbol.name, symbol.kind),
                    reward.span,
                    secondary=self.declared_here(symbol),
                    help="declare `number function reward() = ...` and call it here",
                )
            elif (t := self.expr(reward)) is not ERROR and base(t) is not NUMBER:
                self.error(E0212.reward_not_number(t), reward.span)
        else:
            t = self.expr(reward)
            # `solve(2, reward)`: the missing `()` is reported (E0102, with its fix).
            if not (isinstance(reward, ast.Name) and t is ERROR and self.names_function(reward)):
                self.error(E0212.reward_not_call(), reward.span)
        self.stmt(s.body)

    def names_function(self, e: ast.Name) -> bool:
        """Is `e` the name of a function (not a variable or symbol)?"""
        g = self.model.globals.get(e.name)
        return g is not None and g.kind is _FUNCTION and e.name not in self.variables and e.name not in self.symbols

    def not_assignable(self, root: ast.Expr, symbol: Symbol) -> Type:
        """E0306 on an assignment to a declaration that is not a fluent (`f() = 1`, `f = 1`)."""
        self.error(
            E0306.declaration(symbol.name, symbol.kind),
            root.span,
            "not a fluent",
            secondary=self.declared_here(symbol),
            help="only fluents (and their fields and elements) can be assigned",
        )
        return ERROR

    def assign_target(self, e: ast.Expr) -> Type:
        """Check an assignment's left side (a fluent, or a field/element path from one) and
        return its type."""
        root = e
        while isinstance(root, _PATH_STEPS) and not root.parenthesized:
            root = root.subject
        if isinstance(root, ast.Call) and not root.parenthesized:
            symbol = self.model.globals.get(root.name.name)
            if symbol is not None and symbol.kind is not _FLUENT:
                self.resolve_misused_call(root, symbol)
                return self.not_assignable(root, symbol)
            return self.expr(e)
        if isinstance(root, ast.Name):
            self.expr(root)
            target = self.model.target(root)
            if target is None:
                return ERROR  # an unknown name: already reported
            if target.kind is _FLUENT:
                # `robot_at = p`: the missing `()` is the error (E0102, reported with its fix),
                # not the assignment (after `robot_at() = p` it is a fluent's).
                return ERROR
            if target.kind in EXPRESSION_CALLABLE:
                return self.not_assignable(root, target)
            if target.kind is SymbolKind.SYMBOL:
                help = "a symbol is a constant; assign a fluent that holds symbols instead"
            else:
                help = "parameters and variables are immutable; declare a fluent to hold changing values"
            self.error(
                E0306.local(target.kind, root.name),
                root.span,
                "not a fluent",
                help=help,
            )
            return ERROR
        self.expr(e)
        self.error(E0306.expression(), e.span, "not a fluent")
        return ERROR

    # ---------------------------------------------------------------- expressions

    def expect(self, e: ast.Expr, target: Type, context: str, context_span: Span | None = None) -> Type:
        """Type `e` and check that a slot of type `target` accepts it."""
        t = self.expr(e)
        if t is not target:
            self.check_fits(e, t, target, context, context_span)
        # Of the same type, it fits, and there is no domain membership to check: a literal's
        # type is a builtin (a symbol's `symbol`), never a domain, so an expression of a
        # domain type is computed (a variable, a call, ...), and checked at run time.
        return t

    def check_fits(self, e: ast.Expr, t: Type, target: Type, context: str, context_span: Span | None) -> None:
        if not assignable(target, t):
            secondary = self.context_label(target, context, context_span)
            help = None
            if base(target) is STRING and base(t) in (NUMBER, BOOL, SYMBOL):
                help = "convert it with `to_string(...)`"
            elif isinstance(target, DomainType) and isinstance(t, DomainType):
                help = f"`{t}` and `{target}` hold different kinds of values"
            self.error(
                E0202.mismatch(target, t),
                e.span,
                f"expected `{target}` for {context}",
                secondary=secondary,
                help=help,
            )
            return
        if isinstance(target, DomainType):
            self.check_member(e, target, context, context_span)

    def fits(self, e: ast.Expr, t: Type, target: Type) -> bool:
        """Whether `check_fits` finds nothing to report: asked first where the context of its
        messages would have to be put together (a call's parameter)."""
        return assignable(target, t) and (not isinstance(target, DomainType) or self.outside(e, target) is None)

    def check_member(self, e: ast.Expr, target: DomainType, context: str, context_span: Span | None) -> None:
        """A literal in a slot of a domain type: is its value a member?"""
        value = self.outside(e, target)
        if value is not None:
            secondary = self.context_label(target, context, context_span)
            shown = ", ".join(show_value(v) for v in target.values[:10]) + (", ..." if len(target.values) > 10 else "")
            self.error(
                E0203.not_in_domain(show_value(value), target),
                e.span,
                f"not a member of `{target}`",
                secondary=secondary,
                notes=[f"`{target}` = {{{shown}}}"],
            )

    def outside(self, e: ast.Expr, target: DomainType) -> DomainValue | None:
        """The value of the literal `e` if it is not a member of the domain `target`; None if it
        is, if `e` is not a literal (computed values are checked at run time) or if the domain
        has no members yet (while the domains are being evaluated)."""
        if not target.defined:
            return None
        if e.__class__ is _NAME:  # a symbol, or a variable (no literal)
            name = e.name
            symbol = self.targets.get(id(e))
            if symbol is None or symbol.kind is not _SYMBOL_KIND or target.contains_symbol(name):
                return None
            return self.symbol_value(name)
        if isinstance(e, _VALUE_LITERALS) and not target.contains(e.value):
            return e.value
        return None

    @staticmethod
    def context_label(target: Type, context: str, context_span: Span | None) -> list[diag.Label]:
        return [diag.Label(context_span, f"{context} is `{target}`")] if context_span else []

    def symbol_value(self, name: str) -> Sym:
        """The value of the symbol `name`: one `Sym` per name, for the domains and the literals
        of a program alike."""
        value = self.symbol_values.get(name)
        if value is None:
            value = self.symbol_values[name] = Sym(name)
        return value

    def expr(self, e: ast.Expr) -> Type:
        """The type of `e` (recorded in `model.expr_types`), checking everything in it."""
        kind = e.__class__
        t: Type | None
        if kind is _NAME:
            # A name, here rather than in a method of its own: every third expression is one.
            # A variable (or parameter) has its type, a symbol of a domain `symbol`.
            name = e.name  # type: ignore[attr-defined]
            found = self.variables.get(name)
            if found is not None:
                t = found.type or ERROR
            else:
                found = self.symbols.get(name)
                if found is None:
                    t = self.not_a_value(e)  # type: ignore[arg-type]
                    self.expr_types[id(e)] = t
                    return t
                t = SYMBOL
            if not self.state.silent:  # self.refer(e.span, found, e), inline
                self.add_reference(new_tuple(Reference, (e.span, found, False)))
                self.targets[id(e)] = found
        elif kind is _CALL:  # the next commonest, without the look-ups below
            t = self.call(e)  # type: ignore[arg-type]
        else:
            t = _LITERAL_TYPES.get(kind)
            if t is None:
                t = _EXPR_KINDS[kind](self, e)
        self.expr_types[id(e)] = t
        return t

    type_of = expr  # how the regrouping (gpp.model.regroup) types an operand

    def _regrouped(self, e: ast.Binary | ast.Unary) -> Type | None:
        """The type of the chain `e` regrouped by gpp.model.regroup, or None when it stays."""
        replacement = self.reassociate(e)
        if replacement is None:
            return None
        if not self.state.silent:
            self.model.rewritten[id(e)] = replacement
        return self.expr(replacement)

    def unary(self, e: ast.Unary) -> Type:
        if e.op is _NOT:
            if continues_chain(e.operand) and id(e) not in self.reassociated:
                regrouped = self._regrouped(e)
                if regrouped is not None:
                    return regrouped
            self.expect_operand(e.operand, BOOL, "!")
            return BOOL
        self.expect_operand(e.operand, NUMBER, "-")
        return NUMBER

    def quantified(self, e: ast.Quantified) -> Type:
        variable = self.new_variable(e.var_type, e.var, e)
        vt = variable.type or ERROR
        if not is_finite(vt) and not _written_by_legacy_rewrite(e.var_type):
            self.error(
                E0210.quantifier(e.quantifier.value, vt),
                e.var_type.span,
                f"`{vt}` has infinitely many values",
                help="quantify over a domain, `bool` or `symbol`",
            )
        with self.scope(e.body.span, [variable]):
            # self.expect(e.body, BOOL, ...), inline: the context (an enum's `value`, read in
            # Python) only when the body is not a bool.
            t = self.expr(e.body)
            if t is not BOOL:
                self.check_fits(e.body, t, BOOL, f"the body of `{e.quantifier.value}`", None)
        return BOOL

    def conditional(self, e: ast.Conditional) -> Type:
        self.expect(e.condition, BOOL, "a condition")
        a = self.expr(e.then)
        b = self.expr(e.otherwise)
        common = common_type(a, b)
        if common is None:
            self.error(
                E0211.branches(a, b),
                e.span,
                secondary=[diag.Label(e.then.span, f"`{a}`"), diag.Label(e.otherwise.span, f"`{b}`")],
            )
            return ERROR
        return common

    def index(self, e: ast.Index) -> Type:
        subject = self.expr(e.subject)
        self.expect(e.index, NUMBER, "a list index")
        if subject is ERROR:
            return ERROR
        if isinstance(subject, ListType):
            return subject.element
        self.error(E0207.not_indexable(subject), e.subject.span, "not a list")
        return ERROR

    def list_literal(self, e: ast.ListLit) -> Type:
        list_type = self.resolver.resolve_type(e.type)
        element = list_type.element if isinstance(list_type, ListType) else ERROR
        for x in e.elements:
            self.expect(x, element, "the list's element type", e.type.span)
        return list_type

    def builtin_call(self, e: ast.BuiltinCall) -> Type:
        arg = self.expr(e.arg)
        if e.function is _LENGTH:
            if arg is not ERROR and not isinstance(arg, ListType):
                self.error(E0204.needs_list("length", arg), e.arg.span, f"this is `{arg}`")
            return NUMBER
        if isinstance(arg, _NOT_CONVERTIBLE) or arg is VOID:
            self.error(E0204.not_convertible(arg), e.arg.span)
        return STRING

    def wildcard(self, e: ast.Wildcard) -> Type:
        self.error(E0213.wildcard(), e.span)
        return ERROR

    def expect_operand(self, e: ast.Expr, want: Type, op: str | Op) -> Type:
        """The type of the operand `e` of the operator `op` (its text, or a binary operator,
        whose text an enum property gives: asked for only in a message)."""
        t = self.expr(e)
        if t is want and t is not NULL:
            return t
        if t is ERROR or assignable(want, t):
            if t is NULL:
                self.error(E0204.null_operand(_text(op)), e.span)
                return ERROR
            return t
        self.error(E0204.operand_type(_text(op), want, t), e.span, f"this is `{t}`")
        return ERROR

    def binary(self, e: ast.Binary) -> Type:
        op = e.op
        if op in CHAIN_OPS and (continues_chain(e.left) or continues_chain(e.right)) and id(e) not in self.reassociated:
            regrouped = self._regrouped(e)
            if regrouped is not None:
                return regrouped
        if op in BOOL_CHAIN:
            self.expect_operand(e.left, BOOL, op)
            self.expect_operand(e.right, BOOL, op)
            return BOOL
        if op in _COMPARISON:
            return self.comparison(e)
        left = self.expr(e.left)
        right = self.expr(e.right)
        if left is ERROR or right is ERROR:
            return ERROR
        if left is NULL or right is NULL:
            self.error(E0204.null_operand(op.value), (e.left if left is NULL else e.right).span)
            return ERROR
        if left is NUMBER and right is NUMBER:  # the commonest case first
            return NUMBER
        bl, br = base(left), base(right)
        if op is _ADD and bl is STRING and br is STRING:
            return STRING
        if bl is NUMBER and br is NUMBER:
            return NUMBER
        help = None
        if op is Op.ADD and STRING in (bl, br):
            help = "convert the other operand with `to_string(...)` to concatenate"
        self.error(
            E0204.arithmetic(op.value, left, right),
            operator_span(e),
            f"`{op.value}` needs two numbers" + (" or two strings" if op is Op.ADD else ""),
            secondary=[diag.Label(e.left.span, f"`{left}`"), diag.Label(e.right.span, f"`{right}`")],
            help=help,
        )
        return ERROR

    def comparison(self, e: ast.Binary) -> Type:
        left = self.expr(e.left)
        right = self.expr(e.right)
        if left is ERROR or right is ERROR:
            return BOOL
        chained = isinstance(e.left, ast.Binary) and e.left.op in _COMPARISON and not e.left.parenthesized
        if chained and not (e.op in EQUALITY and base(right) is BOOL):
            assert isinstance(e.left, ast.Binary)
            self.error(
                E0205.chained(),
                e.span,
                f"`{e.left.op.value}` then `{e.op.value}`",
                help=f"compare each pair and join them with `&`: `a {e.left.op.value} b & b {e.op.value} c`",
            )
            return BOOL
        if e.op in EQUALITY:
            if not equatable(left, right):
                if isinstance(base(left), CompoundType | ListType) or isinstance(base(right), CompoundType | ListType):
                    self.error(
                        E0209.not_comparable(left, e.op.value),
                        e.span,
                        help="compare their fields or elements instead",
                    )
                else:
                    self.error(
                        E0204.not_equatable(left, right),
                        operator_span(e),
                        secondary=[diag.Label(e.left.span, f"`{left}`"), diag.Label(e.right.span, f"`{right}`")],
                    )
            return BOOL
        if left is NUMBER and right is NUMBER:  # the commonest case: ordered, of one type
            return BOOL
        if left is NULL or right is NULL:
            self.error(E0204.order_null(e.op.value), e.span, help="test `x != null` first")
        elif not ordered(left) or not same_type(base(left), base(right)):
            self.error(
                E0204.not_ordered(left, right, e.op.value),
                operator_span(e),
                secondary=[diag.Label(e.left.span, f"`{left}`"), diag.Label(e.right.span, f"`{right}`")],
                notes=["`<`, `<=`, `>`, `>=` compare two numbers, two strings or two symbols"],
            )
        return BOOL

    def not_a_value(self, e: ast.Name) -> Type:
        """A name that is neither a variable nor a symbol: a global without `()`, or unknown."""
        g = self.model.globals.get(e.name)
        if g is not None and g.kind in EXPRESSION_CALLABLE:
            self.refer(e.span, g, e)
            self.missing_call(e, g)
            return ERROR
        symbols = self.state.name_index("symbols", self.model.symbols, self.model.symbols.keys)
        self.error(
            E0101.unknown(e.name),
            e.span,
            "not a variable, parameter or symbol",
            suggested=suggestion_among(e.name, (NameIndex(self.visible_variables()), symbols)),
        )
        return ERROR

    def call(self, e: ast.Call, context: str = "expression") -> Type:
        """A call in an expression, as a statement (`context` "statement") or in a hook
        (`context` the hook's word)."""
        name = e.name.name
        symbol = self.globals.get(name)
        if symbol is None:
            if context != "expression":
                allowed = STATEMENT_CALLABLE if context == "statement" else frozenset({SymbolKind.ACTION})
                what = "action or procedure" if context == "statement" else "action"
            else:
                allowed = EXPRESSION_CALLABLE
                what = "fluent or function"
            globals_ = self.model.globals
            pool = self.state.name_index(
                ("globals", allowed), globals_, lambda: (g.name for g in globals_.values() if g.kind in allowed)
            )
            everything = self.state.name_index("globals", globals_, globals_.keys)
            self.error(
                E0103.unknown(what, name),
                e.name.span,
                "not declared",
                suggested=pool.suggestion(name) or everything.suggestion(name),
            )
            for a in e.args:
                self.expr(a)
            return ERROR
        if symbol.kind not in _CALLABLE_IN.get(context, _ACTION) and not self.call_kind_ok(e, symbol, context):
            self.resolve_misused_call(e, symbol)
            return ERROR
        if not self.state.silent:  # self.refer(e.name.span, symbol, e), inline: calls are many
            self.add_reference(new_tuple(Reference, (e.name.span, symbol, False)))
            self.targets[id(e)] = symbol
        params = symbol.params
        args = e.args
        n = len(params)
        if len(args) != n:
            self.arity_error(symbol, e.span, len(args))
        expr = self.expr
        # More or fewer arguments: reported above. (`zip` without `strict=`: a keyword makes
        # the call pack a dict, 0.4 µs for every call checked.)
        misfits: list[tuple[ast.Expr, Type, Symbol]] = []
        for a, p in zip(args, params):  # noqa: B905
            # self.expect(a, p.type, f"parameter `{p.name}`", p.span), inline: the message only
            # when something does not fit.
            t = expr(a)
            want = p.type
            if t is not want and want is not None and not self.fits(a, t, want):
                misfits.append((a, t, p))
        if misfits and not self.swapped_arguments(misfits):
            for a, t, p in misfits:
                self.check_fits(a, t, p.type or ERROR, f"parameter `{p.name}`", p.span)
        if len(args) > n:
            for a in args[n:]:
                expr(a)
        return symbol.type or ERROR

    def swapped_arguments(self, misfits: list[tuple[ast.Expr, Type, Symbol]]) -> bool:
        """Two arguments that do not fit their parameters but would fit each other's
        (`carry(5, room1)` for `carry(Location from, number weight)`): one E0202 that says so,
        with the swap as a fix (a guess: unsafe). False, and nothing reported, otherwise."""
        if len(misfits) != 2:
            return False
        (a, ta, pa), (b, tb, pb) = misfits
        if pa.type is None or pb.type is None or not (assignable(pa.type, tb) and assignable(pb.type, ta)):
            return False
        text = a.span.source.text
        first, second = text[a.span.start : a.span.end], text[b.span.start : b.span.end]
        self.error(
            E0202.mismatch(pa.type, ta),
            a.span,
            f"expected `{pa.type}` for parameter `{pa.name}`",
            secondary=[diag.Label(b.span, f"expected `{pb.type}` for parameter `{pb.name}`, found `{tb}`")],
            help=f"the arguments for `{pa.name}` and `{pb.name}` look swapped",
            fix=diag.Fix(
                f"swap `{first}` and `{second}`",
                (diag.Edit(a.span, second), diag.Edit(b.span, first)),
                diag.Applicability.UNSAFE,
            ),
        )
        return True

    def resolve_misused_call(self, e: ast.Call, symbol: Symbol) -> None:
        """A call of the wrong kind of declaration (reported by the caller): the name still
        refers to it, and the arguments are checked on their own."""
        self.refer(e.name.span, symbol, e)
        for a in e.args:
            self.expr(a)

    def call_kind_ok(self, e: ast.Call, symbol: Symbol, context: str) -> bool:
        kind = symbol.kind
        if kind in _CALLABLE_IN.get(context, _ACTION):
            return True
        name = symbol.name
        secondary = self.declared_here(symbol)
        if context == "expression":
            self.error(
                E0104.in_expression(name, kind),
                e.span,
                f"{kind.value} call in an expression",
                secondary=secondary,
            )
            return False
        if context == "statement":
            help: str | None
            if kind is SymbolKind.EXOG_ACTION:
                help = "the platform reports exogenous actions; a program cannot execute them"
            elif kind is SymbolKind.FLUENT:
                help = f"to change the fluent, assign it: `{name}(...) = value;`"
            else:
                help = "to wait until a condition holds, write `test(...)`" if symbol.type is BOOL else None
            self.error(
                E0104.as_statement(name, kind),
                e.span,
                "not an action or procedure",
                secondary=secondary,
                help=help,
            )
            return False
        self.error(
            E0104.hook_of(name, kind, context),
            e.span,
            "not an action",
            secondary=secondary,
        )
        return False

    def arity_error(self, symbol: Symbol, span: Span, given: int) -> None:
        n = len(symbol.params)
        self.error(
            E0201.arity(symbol.name, n, given),
            span,
            f"expected {n} argument{'s' * (n != 1)}",
            secondary=self.declared_here(symbol),
            notes=[f"`{symbol.signature()}`"],
        )

    def field_access(self, e: ast.FieldAccess) -> Type:
        subject = self.expr(e.subject)
        if subject is ERROR:
            return ERROR
        if isinstance(subject, CompoundType):
            ftype = subject.fields.get(e.field.name)
            if ftype is None:
                self.error(
                    E0106.no_field(subject, e.field.name),
                    e.field.span,
                    "unknown field",
                    suggested=suggestion(e.field.name, subject.fields),
                    notes=[f"fields of `{subject}`: " + ", ".join(f"`{f}`" for f in subject.fields)],
                )
                return ERROR
            declaration = self.model.declaration(subject)
            if declaration is not None:
                member = declaration.members.get(e.field.name)
                if member is not None:
                    self.refer(e.field.span, member, e.field)
            return ftype
        self.error(E0207.no_fields(subject), e.subject.span, f"this is `{subject}`, not a compound")
        return ERROR

    def compound_literal(self, e: ast.CompoundLit) -> Type:
        symbol = self.model.types.get(e.type_name.name)
        if symbol is None or symbol.kind is not _COMPOUND:
            types = self.model.types
            compounds = self.state.name_index(
                ("types", _COMPOUND), types, lambda: (s.name for s in types.values() if s.kind is _COMPOUND)
            )
            name = e.type_name.name
            message = E0105.unknown_compound(name) if symbol is None else E0105.not_compound(name)
            self.error(message, e.type_name.span, suggested=compounds.suggestion(name))
            for f in e.fields:
                self.expr(f.value)
            return ERROR
        self.refer(e.type_name.span, symbol, e.type_name)
        ctype = symbol.type
        assert isinstance(ctype, CompoundType)
        given: dict[str, ast.FieldInit] = {}
        for f in e.fields:
            ftype = ctype.fields.get(f.name.name)
            if ftype is None:
                self.error(
                    E0106.no_field(ctype, f.name.name),
                    f.name.span,
                    "unknown field",
                    suggested=suggestion(f.name.name, ctype.fields),
                )
                self.expr(f.value)
                continue
            first = given.get(f.name.name)
            if first is not None:
                self.given_twice(E0208.field_twice(f.name.name), f.name.span, first.name.span)
            given[f.name.name] = f
            member = symbol.members.get(f.name.name)
            if member is not None:
                self.refer(f.name.span, member, f.name)
            # self.expect(f.value, ftype, ...), inline: the context only when it does not fit.
            t = self.expr(f.value)
            if t is not ftype:
                self.check_fits(f.value, t, ftype, f"field `{f.name.name}`", member.span if member else None)
        missing = [name for name in ctype.fields if name not in given]
        if missing:
            self.error(
                E0208.missing_fields(missing, ctype),
                e.span,
                secondary=self.declared_here(symbol, f"`{ctype}` declared here"),
                help="give every field a value; write `null` for a field without one",
            )
        return ctype


# One method per kind of statement (see `TypeChecker.stmt`).
_STMT_KINDS: dict[type[ast.Statement], Callable[[TypeChecker, Any], None]] = {
    ast.CallStmt: TypeChecker.call_stmt,
    ast.Block: TypeChecker.block,
    ast.Assign: TypeChecker.assign,
    ast.If: TypeChecker.if_stmt,
    ast.While: TypeChecker.while_stmt,
    ast.Test: TypeChecker.test,
    ast.Choose: TypeChecker.choose,
    ast.Concurrent: TypeChecker.concurrent,
    ast.Pick: TypeChecker.pick,
    ast.Solve: TypeChecker.solve,
    ast.Search: TypeChecker.search,
    ast.During: TypeChecker.during,
    ast.HookStmt: TypeChecker.hook,
    ast.ListStmt: TypeChecker.list_stmt,
}

# One method per kind of expression but names, calls and literals (`TypeChecker.expr` types
# those itself), instead of a chain of isinstance: plain functions, called
# with the checker (a table of its bound methods, kept by the checker, would be a reference cycle).
_EXPR_KINDS: dict[type[ast.Expr], Callable[[TypeChecker, Any], Type]] = {
    ast.Unary: TypeChecker.unary,
    ast.Binary: TypeChecker.binary,
    ast.Quantified: TypeChecker.quantified,
    ast.Conditional: TypeChecker.conditional,
    ast.FieldAccess: TypeChecker.field_access,
    ast.Index: TypeChecker.index,
    ast.CompoundLit: TypeChecker.compound_literal,
    ast.ListLit: TypeChecker.list_literal,
    ast.BuiltinCall: TypeChecker.builtin_call,
    ast.Wildcard: TypeChecker.wildcard,
}
