"""Builds the code model from parsed files, reporting every name, type and declaration error.

Phases (each over all files, so declaration order never matters, SEMANTICS §2.1):

1. collect: every global, type and domain by name; forward declarations merged with their
   definitions; clashes and second definitions reported;
2. resolve: parameter, field and value types; domains evaluated to their member sets (which
   also declares the symbols);
3. bodies: one typed walk over every expression and statement that records each reference
   and each expression's type, and reports what does not fit. An expression that already has
   an error gets the type ERROR, which fits everywhere, so a mistake is reported once.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace

from gpp import diagnostics as diag
from gpp.model.model import Model
from gpp.model.symbols import (
    EXPRESSION_CALLABLE,
    STATEMENT_CALLABLE,
    Reference,
    ScopeRecord,
    Symbol,
    SymbolKind,
)
from gpp.model.types import (
    BOOL,
    BUILTIN_TYPES,
    ERROR,
    NULL,
    NUMBER,
    STRING,
    SYMBOL,
    VOID,
    BuiltinType,
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
    same_value,
    show_value,
)
from gpp.perf import paused_gc
from gpp.source import Span
from gpp.syntax import ast
from gpp.syntax.loader import ParsedFile
from gpp.syntax.walk import walk

Op = ast.BinaryOp

_KIND_OF_DECL: dict[type[ast.Decl], SymbolKind] = {
    ast.FluentDecl: SymbolKind.FLUENT,
    ast.FunctionDecl: SymbolKind.FUNCTION,
    ast.ExogFunctionDecl: SymbolKind.EXOG_FUNCTION,
    ast.ProcedureDecl: SymbolKind.PROCEDURE,
    ast.ComponentDecl: SymbolKind.COMPONENT,
}

_BOOL_CHAIN = frozenset({Op.AND, Op.OR, Op.IMPLIES})
_INITIAL_LITERAL = "initial values must be literals"
_EQUALITY = frozenset({Op.EQ, Op.NE})


def suggest(name: str, candidates: Iterable[str]) -> str | None:
    """`did you mean ...?` for a misspelled name, or None."""
    pool = sorted(set(candidates) - {name})
    lowered = {c.lower(): c for c in pool}
    if name.lower() in lowered:
        return f"did you mean `{lowered[name.lower()]}`?"
    close = difflib.get_close_matches(name, pool, n=3, cutoff=0.6)
    if not close:
        return None
    if len(close) == 1:
        return f"did you mean `{close[0]}`?"
    return "did you mean " + ", ".join(f"`{c}`" for c in close[:-1]) + f" or `{close[-1]}`?"


def is_literal(e: ast.Expr) -> bool:
    """A value written out: what initial values, `pick ... in`, domains and durations take."""
    if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit | ast.NullLit | ast.Name):
        return True
    if isinstance(e, ast.CompoundLit):
        return all(is_literal(f.value) for f in e.fields)
    if isinstance(e, ast.ListLit):
        return all(is_literal(x) for x in e.elements)
    return False


def build_model(files: Sequence[ParsedFile]) -> tuple[Model, list[diag.Diagnostic]]:
    builder = ModelBuilder(files)
    with paused_gc():
        builder.run()
    return builder.model, builder.diagnostics


class ModelBuilder:
    def __init__(self, files: Sequence[ParsedFile]) -> None:
        self.model = Model(list(files))
        self.diagnostics: list[diag.Diagnostic] = []
        # Every declaration node of a global (forward ones included), in source order.
        self.declarations: dict[int, list[ast.Decl]] = {}
        # Parameters per declaration node (forward declarations have their own).
        self.decl_params: dict[int, tuple[Symbol, ...]] = {}
        self.decl_symbol: dict[int, Symbol] = {}
        self.main_blocks: list[ast.MainBlock] = []
        self.constraints: list[ast.ConstraintsDecl] = []
        self.scopes: list[dict[str, Symbol]] = []
        self.silent = 0
        self.reassociated: set[int] = set()
        self.domains_in_progress: set[int] = set()
        # Parameters of forward declarations -> the same parameter of the definition.
        self.merged: dict[int, Symbol] = {}

    # ---------------------------------------------------------------- reporting

    def report(self, d: diag.Diagnostic) -> None:
        if not self.silent:
            self.diagnostics.append(d)

    def error(
        self,
        code: str,
        message: str,
        span: Span,
        label: str = "",
        *,
        secondary: Iterable[diag.Label] = (),
        notes: Iterable[str] = (),
        help: str | None = None,
    ) -> None:
        self.report(diag.error(code, message, span, label, secondary=secondary, notes=notes, help=help))

    def refer(self, span: Span, symbol: Symbol, node: ast.Node | None = None, declaration: bool = False) -> None:
        if self.silent:
            return
        self.model.references.append(Reference(span, symbol, declaration))
        if node is not None:
            self.model.targets[id(node)] = symbol

    def given_twice(self, code: str, what: str, span: Span, first: Span) -> None:
        self.error(
            code, f"{what} is given twice", span, "given again", secondary=[diag.Label(first, "first given here")]
        )

    def declared_here(self, symbol: Symbol, what: str = "declared here") -> list[diag.Label]:
        return [diag.Label(symbol.span, what)] if symbol.span is not None else []

    # ---------------------------------------------------------------- driver

    def run(self) -> None:
        self.predefine()
        for pf in self.model.files:
            for decl in pf.program.declarations:
                self.collect(decl)
        self.collect_main()
        for pf in self.model.files:
            for decl in pf.program.declarations:
                self.resolve_declaration(decl)
        for symbol in list(self.model.types.values()):
            if symbol.kind is SymbolKind.DOMAIN:
                self.evaluate_domain(symbol)
        self.check_forward_declarations()
        for pf in self.model.files:
            for decl in pf.program.declarations:
                self.check_declaration(decl)
        if self.merged:
            self.model.references = [
                Reference(r.span, self.merged.get(id(r.symbol), r.symbol), r.declaration) for r in self.model.references
            ]
            for key, symbol in list(self.model.targets.items()):
                if id(symbol) in self.merged:
                    self.model.targets[key] = self.merged[id(symbol)]

    def predefine(self) -> None:
        g = self.model.globals
        g["context_time"] = Symbol("context_time", SymbolKind.FLUENT, None, type=NUMBER, predefined=True)
        step = Symbol("step_context_time", SymbolKind.EXOG_ACTION, None, type=VOID, predefined=True)
        step.params = (Symbol("next_time", SymbolKind.PARAMETER, None, type=NUMBER, owner=step, predefined=True),)
        g["step_context_time"] = step
        switch = Symbol("switch_state", SymbolKind.ACTION, None, type=VOID, predefined=True)
        switch.params = tuple(
            Symbol(n, SymbolKind.PARAMETER, None, type=STRING, owner=switch, predefined=True)
            for n in ("component", "from_state", "to_state")
        )
        g["switch_state"] = switch

    # ---------------------------------------------------------------- phase 1: collect

    def collect(self, decl: ast.Decl) -> None:
        if isinstance(decl, ast.DomainDecl):
            self.declare(self.model.types, decl.name, SymbolKind.DOMAIN, decl, decl.definition is not None)
        elif isinstance(decl, ast.CompoundDecl):
            self.declare(self.model.types, decl.name, SymbolKind.COMPOUND, decl, True)
        elif isinstance(decl, ast.ActionDecl):
            kind = SymbolKind.EXOG_ACTION if decl.exogenous else SymbolKind.ACTION
            self.declare(self.model.globals, decl.name, kind, decl, decl.sections is not None)
        elif isinstance(decl, ast.FluentDecl):
            self.declare(self.model.globals, decl.name, SymbolKind.FLUENT, decl, decl.initially is not None)
        elif isinstance(decl, ast.FunctionDecl):
            self.declare(self.model.globals, decl.name, SymbolKind.FUNCTION, decl, decl.body is not None)
        elif isinstance(decl, ast.ProcedureDecl):
            self.declare(self.model.globals, decl.name, SymbolKind.PROCEDURE, decl, decl.body is not None)
        elif isinstance(decl, ast.ExogFunctionDecl | ast.ComponentDecl):
            self.declare(self.model.globals, decl.name, _KIND_OF_DECL[type(decl)], decl, True)
        elif isinstance(decl, ast.MainBlock):
            self.main_blocks.append(decl)
        elif isinstance(decl, ast.ConstraintsDecl):
            self.constraints.append(decl)

    def declare(
        self, table: dict[str, Symbol], name: ast.Ident, kind: SymbolKind, decl: ast.Decl, definition: bool
    ) -> Symbol:
        existing = table.get(name.name)
        if existing is None:
            symbol = Symbol(name.name, kind, name.span, decl=decl)
            # Types exist from the start, so a use before the declaration resolves (§2.1).
            if kind is SymbolKind.DOMAIN:
                symbol.type = DomainType(name.name, SYMBOL, symbol)
            elif kind is SymbolKind.COMPOUND:
                symbol.type = CompoundType(name.name, symbol)
            table[name.name] = symbol
            return self.attach(symbol, name, decl)
        detached = Symbol(name.name, kind, name.span, decl=decl)
        if existing.predefined:
            self.error(
                "E0304",
                f"`{name.name}` is predefined and cannot be declared",
                name.span,
                "predefined name",
                notes=[f"gpp predefines `{existing.signature()}`"],
            )
            return self.attach(detached, name, decl)
        if existing.kind is not kind:
            self.error(
                "E0302",
                f"`{name.name}` is already declared as {existing.kind.article} {existing.kind.value}",
                name.span,
                f"declared again as {kind.article} {kind.value}",
                secondary=self.declared_here(existing, f"the {existing.kind.value} is declared here"),
            )
            return self.attach(detached, name, decl)
        if definition and existing.is_defined:
            self.error(
                "E0301",
                f"`{name.name}` is defined twice",
                name.span,
                "second definition",
                secondary=self.declared_here(existing, "first defined here"),
                help="remove one of the definitions, or rename one of them",
            )
            return self.attach(detached, name, decl)
        # A forward declaration and a definition (in either order), or two forward declarations.
        assert existing.span is not None
        if definition:
            existing.other_spans.append(existing.span)
            existing.span = name.span
            existing.decl = decl
        else:
            existing.other_spans.append(name.span)
        self.declarations.setdefault(id(existing), []).append(decl)
        self.decl_symbol[id(decl)] = existing
        self.refer(name.span, existing, name, declaration=True)
        return existing

    def attach(self, symbol: Symbol, name: ast.Ident, decl: ast.Decl) -> Symbol:
        self.declarations.setdefault(id(symbol), []).append(decl)
        self.decl_symbol[id(decl)] = symbol
        self.refer(name.span, symbol, name, declaration=True)
        return symbol

    def collect_main(self) -> None:
        for block in self.main_blocks:
            existing = self.model.globals.get("main")
            if existing is not None:
                self.error(
                    "E0310",
                    "a legacy main block and `main` in one program",
                    Span(block.span.source, block.span.start, block.span.start + 1),
                    "this block means `procedure main()`",
                    secondary=self.declared_here(existing, "`main` is declared here"),
                    help="put the block's statements into `procedure main()`, or remove one of them",
                )
                continue
            symbol = Symbol("main", SymbolKind.PROCEDURE, None, decl=block, type=VOID)
            self.model.globals["main"] = symbol
            self.decl_symbol[id(block)] = symbol
        self.model.main = self.model.globals.get("main")

    # ---------------------------------------------------------------- phase 2: resolve

    def resolve_type(self, t: ast.TypeExpr, data: bool = True) -> Type:
        """The type a type expression names; `data` types may not be void."""
        if isinstance(t, ast.ListType):
            element = self.resolve_type(t.element)
            return ERROR if element is ERROR else ListType(element)
        builtin = BUILTIN_TYPES.get(t.name)
        if builtin is not None:
            if builtin is VOID and data:
                self.error(
                    "E0206",
                    "`void` is not a type of data",
                    t.span,
                    "no value has type `void`",
                    help="actions and procedures have no type; data needs bool, number, string, symbol, "
                    "a domain, a compound or a list type",
                )
                return ERROR
            return builtin
        symbol = self.model.types.get(t.name)
        if symbol is None:
            candidates = [*self.model.types, *(n for n in BUILTIN_TYPES if n != "void")]
            self.error(
                "E0105", f"unknown type `{t.name}`", t.span, "not a declared type", help=suggest(t.name, candidates)
            )
            return ERROR
        self.refer(t.span, symbol, t)
        assert symbol.type is not None
        return symbol.type

    def resolve_params(self, owner: Symbol, params: Sequence[ast.Param], kind: SymbolKind) -> tuple[Symbol, ...]:
        out: list[Symbol] = []
        seen: dict[str, Symbol] = {}
        for p in params:
            symbol = Symbol(p.name.name, kind, p.name.span, decl=p, type=self.resolve_type(p.type), owner=owner)
            first = seen.get(p.name.name)
            if first is not None:
                self.error(
                    "E0305",
                    f"`{p.name.name}` is declared twice in this list",
                    p.name.span,
                    "second declaration",
                    secondary=self.declared_here(first, "first declared here"),
                )
            else:
                seen[p.name.name] = symbol
            self.refer(p.name.span, symbol, p.name, declaration=True)
            out.append(symbol)
        return tuple(out)

    def resolve_declaration(self, decl: ast.Decl) -> None:
        symbol = self.decl_symbol.get(id(decl))
        if isinstance(decl, ast.ListTypeDecl):
            self.resolve_type(decl.type)
            return
        if symbol is None:
            return
        if isinstance(decl, ast.DomainDecl):
            dtype = symbol.type
            if not isinstance(dtype, DomainType):
                return  # a clashing declaration, already reported
            element = self.resolve_type(decl.element_type)
            if element is ERROR:
                dtype.broken = True
            elif not (isinstance(element, BuiltinType) and element in (SYMBOL, NUMBER, STRING, BOOL)):
                self.error(
                    "E0311",
                    f"a domain's elements must be symbols, numbers, strings or bools, not `{element}`",
                    decl.element_type.span,
                )
                dtype.broken = True
            elif not dtype.element_known:
                dtype.element = element
                dtype.element_known = True
            elif dtype.element != element:
                self.error(
                    "E0303",
                    f"`{symbol.name}` has element type `{dtype.element}` in one declaration and `{element}` here",
                    decl.element_type.span,
                    "different element type",
                    secondary=self.declared_here(symbol),
                )
                dtype.broken = True
            return
        if isinstance(decl, ast.CompoundDecl):
            return
        if isinstance(decl, ast.FluentDecl | ast.FunctionDecl | ast.ExogFunctionDecl):
            value_type = self.resolve_type(decl.type)
            params = self.resolve_params(symbol, decl.params, SymbolKind.PARAMETER)
        elif isinstance(decl, ast.ActionDecl | ast.ProcedureDecl):
            value_type = VOID
            params = self.resolve_params(symbol, decl.params, SymbolKind.PARAMETER)
        elif isinstance(decl, ast.ComponentDecl):
            self.resolve_component(symbol, decl)
            return
        else:
            return
        self.decl_params[id(decl)] = params
        # The defining declaration's signature wins; a forward one serves until it comes.
        if symbol.decl is decl or symbol.type is None:
            symbol.type = value_type
            symbol.params = params

    def resolve_compound_fields(self) -> None:
        for symbol in self.model.types.values():
            decl = symbol.decl
            if symbol.kind is not SymbolKind.COMPOUND or not isinstance(decl, ast.CompoundDecl):
                continue
            ctype = symbol.type
            assert isinstance(ctype, CompoundType)
            fields = self.resolve_params(symbol, decl.fields, SymbolKind.FIELD)
            for f in fields:
                if f.name not in ctype.fields:
                    assert f.type is not None
                    ctype.fields[f.name] = f.type
                    symbol.members[f.name] = f

    def resolve_component(self, symbol: Symbol, decl: ast.ComponentDecl) -> None:
        for section in decl.sections:
            if isinstance(section, ast.ClocksSection):
                for c in section.clocks:
                    self.add_member(symbol, c, SymbolKind.CLOCK)
            elif isinstance(section, ast.StatesSection):
                for s in section.states:
                    self.add_member(symbol, s.name, SymbolKind.STATE)
        if "error" not in symbol.members:
            symbol.members["error"] = Symbol("error", SymbolKind.STATE, None, owner=symbol, predefined=True)

    def add_member(self, owner: Symbol, name: ast.Ident, kind: SymbolKind) -> None:
        first = owner.members.get(name.name)
        if first is not None:
            self.error(
                "E0305",
                f"`{name.name}` is declared twice in component `{owner.name}`",
                name.span,
                secondary=self.declared_here(first, "first declared here"),
            )
            return
        member = Symbol(name.name, kind, name.span, owner=owner)
        owner.members[name.name] = member
        self.refer(name.span, member, name, declaration=True)

    def evaluate_domain(self, symbol: Symbol) -> tuple[DomainValue, ...]:
        dtype = symbol.type
        if not isinstance(dtype, DomainType):
            return ()
        if dtype.defined:
            return dtype.values
        decl = symbol.decl
        if not isinstance(decl, ast.DomainDecl) or decl.definition is None or dtype.broken:
            dtype.defined = True
            return ()
        if id(symbol) in self.domains_in_progress:
            self.error(
                "E0311",
                f"domain `{symbol.name}` is defined in terms of itself",
                decl.name.span,
                "this definition refers back to itself",
            )
            return ()
        self.domains_in_progress.add(id(symbol))
        values = self.domain_values(decl.definition, dtype)
        self.domains_in_progress.discard(id(symbol))
        dtype.values = values
        dtype.defined = True
        return values

    def domain_values(self, d: ast.DomainExpr, dtype: DomainType) -> tuple[DomainValue, ...]:
        if isinstance(d, ast.DomainRef):
            other = self.model.types.get(d.name.name)
            if other is None or other.kind is not SymbolKind.DOMAIN:
                domains = [s.name for s in self.model.types.values() if s.kind is SymbolKind.DOMAIN]
                name = d.name.name
                message = f"`{name}` is not a domain" if other is not None else f"unknown domain `{name}`"
                self.error("E0105", message, d.name.span, help=suggest(name, domains))
                return ()
            self.refer(d.name.span, other, d.name)
            values = self.evaluate_domain(other)
            assert isinstance(other.type, DomainType)
            if other.type.element != dtype.element:
                self.error(
                    "E0311",
                    f"domain `{other.name}` has `{other.type.element}` elements, "
                    f"but `{dtype.name}` has `{dtype.element}` elements",
                    d.span,
                )
                return ()
            return values
        if isinstance(d, ast.DomainSet):
            out: list[DomainValue] = []
            for e in d.elements:
                v = self.domain_literal(e, dtype)
                if v is not None and not any(same_value(v, x) for x in out):
                    out.append(v)
            return tuple(out)
        if isinstance(d, ast.DomainBinary):
            left = self.domain_values(d.left, dtype)
            right = self.domain_values(d.right, dtype)
            if d.op is ast.DomainOp.UNION:
                return left + tuple(v for v in right if not any(same_value(v, x) for x in left))
            if d.op is ast.DomainOp.DIFFERENCE:
                return tuple(v for v in left if not any(same_value(v, x) for x in right))
            return tuple(v for v in left if any(same_value(v, x) for x in right))
        return ()

    def domain_literal(self, e: ast.Expr, dtype: DomainType) -> DomainValue | None:
        element = dtype.element
        if element is SYMBOL:
            if isinstance(e, ast.Name):
                symbol = self.model.symbols.get(e.name)
                if symbol is None:
                    symbol = Symbol(e.name, SymbolKind.SYMBOL, e.span, decl=e, type=SYMBOL)
                    self.model.symbols[e.name] = symbol
                    self.refer(e.span, symbol, e, declaration=True)
                else:
                    symbol.other_spans.append(e.span)
                    self.refer(e.span, symbol, e, declaration=True)
                self.model.expr_types[id(e)] = SYMBOL
                return Sym(e.name)
            self.error(
                "E0202", "expected a symbol name", e.span, f"a `symbol` domain lists names like `{dtype.name}_a`"
            )
            return None
        if not is_literal(e) or isinstance(e, ast.Name | ast.NullLit):
            self.error("E0213", f"a `{element}` domain lists {element} literals", e.span, "not a literal")
            return None
        t = self.expr(e)
        if t is not ERROR and t != element:
            self.error(
                "E0202", f"expected `{element}`, found `{t}`", e.span, f"domain `{dtype.name}` holds `{element}` values"
            )
            return None
        return _literal_value(e)

    def expect_literal(
        self,
        e: ast.Expr,
        target: Type | None,
        message: str,
        context: str,
        span: Span | None,
        help: str | None = None,
    ) -> None:
        """Check an expression where only a literal may stand (initial values, `pick ... in`,
        constraint patterns): written as a literal, and every bare name in it a symbol."""
        if not is_literal(e):
            self.error("E0213", message, e.span, "not a literal", help=help)
            self.expr(e)
            return
        if target is not None:
            self.expect(e, target, context, span)
        else:
            self.expr(e)
        for node in walk(e):
            if isinstance(node, ast.Name):
                symbol = self.model.target(node)
                if symbol is not None and symbol.kind is not SymbolKind.SYMBOL:
                    self.error(
                        "E0213",
                        f"{message}; `{node.name}` is {symbol.kind.article} {symbol.kind.value}",
                        node.span,
                        "not a literal",
                        help=help,
                    )

    def check_forward_declarations(self) -> None:
        self.resolve_compound_fields()
        for symbol in list(self.model.globals.values()):
            decls = self.declarations.get(id(symbol), [])
            if len(decls) < 2 or symbol.decl is None:
                continue
            main = symbol.decl
            assert isinstance(main, ast.Decl)
            for other in decls:
                if other is main:
                    continue
                self.compare_declarations(symbol, main, other)

    def compare_declarations(self, symbol: Symbol, main: ast.Decl, other: ast.Decl) -> None:
        mine = self.decl_params.get(id(main), ())
        theirs = self.decl_params.get(id(other), ())
        other_name: ast.Ident = other.name  # type: ignore[attr-defined]
        label = [diag.Label(other_name.span, "forward declaration here")]
        main_type = getattr(main, "type", None)
        other_type = getattr(other, "type", None)
        if main_type is not None and other_type is not None:
            a = self.resolve_type_quiet(main_type)
            b = self.resolve_type_quiet(other_type)
            if a is not ERROR and b is not ERROR and a != b:
                self.error(
                    "E0303",
                    f"`{symbol.name}` is declared with type `{b}` but defined with type `{a}`",
                    main_type.span,
                    secondary=label,
                )
                return
        if len(mine) != len(theirs):
            self.error(
                "E0303",
                f"`{symbol.name}` is declared with {len(theirs)} parameter{'s' * (len(theirs) != 1)} "
                f"but defined with {len(mine)}",
                symbol.span or other_name.span,
                secondary=label,
            )
            return
        for p, q in zip(mine, theirs, strict=True):
            if p.name == q.name and q.span is not None:
                # One parameter, declared twice: rename and references see both names.
                self.merged[id(q)] = p
                p.other_spans.append(q.span)
            if p.type is not ERROR and q.type is not ERROR and p.type != q.type:
                assert p.span is not None
                self.error(
                    "E0303",
                    f"parameter `{p.name}` has type `{p.type}` here but `{q.type}` in the forward declaration",
                    p.span,
                    secondary=[diag.Label(q.span, "declared here")] if q.span else [],
                )
            elif p.name != q.name:
                assert p.span is not None
                self.error(
                    "E0303",
                    f"parameter `{p.name}` is called `{q.name}` in the forward declaration",
                    p.span,
                    secondary=[diag.Label(q.span, "declared here")] if q.span else [],
                    help="use the same parameter names in both",
                )

    def resolve_type_quiet(self, t: ast.TypeExpr) -> Type:
        self.silent += 1
        try:
            return self.resolve_type(t)
        finally:
            self.silent -= 1

    # ---------------------------------------------------------------- scopes

    @contextmanager
    def scope(self, span: Span, symbols: Sequence[Symbol]) -> Iterator[None]:
        self.scopes.append({s.name: s for s in symbols})
        if not self.silent and symbols:
            self.model.scopes.append(ScopeRecord(span, tuple(symbols)))
        try:
            yield
        finally:
            self.scopes.pop()

    def lookup_variable(self, name: str) -> Symbol | None:
        for scope in reversed(self.scopes):
            s = scope.get(name)
            if s is not None:
                return s
        return None

    def visible_variables(self) -> set[str]:
        return {n for scope in self.scopes for n in scope}

    def new_variable(self, var_type: ast.TypeExpr, var: ast.Ident, decl: ast.Node) -> Symbol:
        symbol = Symbol(var.name, SymbolKind.VARIABLE, var.span, decl=decl, type=self.resolve_type(var_type))
        self.refer(var.span, symbol, var, declaration=True)
        return symbol

    # ---------------------------------------------------------------- phase 3: declarations

    def check_declaration(self, decl: ast.Decl) -> None:
        symbol = self.decl_symbol.get(id(decl))
        params = self.decl_params.get(id(decl), ())
        if isinstance(decl, ast.FluentDecl) and decl.initially is not None and symbol is not None:
            with self.scope(decl.span, params):
                for init in decl.initially:
                    self.check_initial_value(symbol, params, init)
        elif isinstance(decl, ast.ActionDecl) and decl.sections is not None and symbol is not None:
            with self.scope(decl.span, params):
                for section in decl.sections:
                    self.check_section(symbol, decl, params, section)
        elif isinstance(decl, ast.FunctionDecl) and decl.body is not None and symbol is not None:
            with self.scope(decl.span, params):
                assert symbol.type is not None
                value_type = self.decl_value_type(decl, symbol)
                self.expect(decl.body, value_type, "the function's type", decl.type.span)
        elif isinstance(decl, ast.ProcedureDecl) and decl.body is not None:
            with self.scope(decl.span, params):
                self.stmt(decl.body)
        elif isinstance(decl, ast.MainBlock):
            self.stmt(decl.body)
        elif isinstance(decl, ast.ComponentDecl) and symbol is not None:
            self.check_component(symbol, decl)
        elif isinstance(decl, ast.ConstraintsDecl):
            for c in decl.constraints:
                self.spec(c.condition)
                self.spec(c.requirement)

    def decl_value_type(self, decl: ast.FunctionDecl | ast.FluentDecl, symbol: Symbol) -> Type:
        if symbol.decl is decl and symbol.type is not None:
            return symbol.type
        return self.resolve_type_quiet(decl.type)

    def check_initial_value(self, fluent: Symbol, params: tuple[Symbol, ...], init: ast.InitialValue) -> None:
        if len(init.args) != len(params):
            self.error(
                "E0307",
                f"fluent `{fluent.name}` has {len(params)} parameter{'s' * (len(params) != 1)}, "
                f"but this initial value gives {len(init.args)} argument{'s' * (len(init.args) != 1)}",
                init.span,
                secondary=self.declared_here(fluent),
            )
        for i, arg in enumerate(init.args):
            param = params[i] if i < len(params) else None
            if isinstance(arg, ast.Name) and not arg.parenthesized:
                by_name = next((p for p in params if p.name == arg.name), None)
                if by_name is not None and by_name is param:
                    self.refer(arg.span, by_name, arg)
                    self.model.expr_types[id(arg)] = by_name.type or ERROR
                    continue
                if by_name is not None:
                    position = params.index(by_name) + 1
                    self.error(
                        "E0307",
                        f"`{arg.name}` is the parameter in position {position}; "
                        f"here only `{param.name if param else '?'}` or a literal can stand",
                        arg.span,
                        "parameter in the wrong position",
                        help="a parameter name stands for every value, and only in its own position",
                    )
                    continue
            if param is not None and param.type is not None:
                self.expect_literal(arg, param.type, _INITIAL_LITERAL, f"parameter `{param.name}`", param.span)
            else:
                self.expect_literal(arg, None, _INITIAL_LITERAL, "", None)
        self.expect_literal(
            init.value,
            fluent.type,
            _INITIAL_LITERAL,
            f"the type of `{fluent.name}`",
            fluent.span,
            help="compute the value in a procedure and assign it there",
        )

    def check_section(
        self, action: Symbol, decl: ast.ActionDecl, params: tuple[Symbol, ...], section: ast.ActionSection
    ) -> None:
        if decl.exogenous and isinstance(section, ast.SensesSection | ast.DurationSection):
            word = ast.SECTION_KINDS[type(section)].value
            self.error(
                "E0309",
                f"an exogenous action cannot have a `{word}:` section",
                section.keyword,
                help="exogenous actions are events the platform reports; they are not executed",
            )
        if isinstance(section, ast.PreconditionSection):
            self.expect(section.condition, BOOL, "a precondition")
        elif isinstance(section, ast.EffectSection):
            for effect in section.effects:
                if effect.condition is not None:
                    self.expect(effect.condition, BOOL, "an effect's condition")
                target = self.assign_target(effect.target)
                self.expect(effect.value, target, "the assigned fluent")
        elif isinstance(section, ast.SensesSection):
            target = self.assign_target(section.target)
            self.expect(section.value, target, "the sensed fluent")
        elif isinstance(section, ast.MappingSection):
            self.check_mapping(action, decl, params, section.mapping)
        elif isinstance(section, ast.SilentSection):
            v = section.value
            if not isinstance(v, ast.BoolLit | ast.NullLit):
                self.error("E0312", "`silent:` takes `true`, `false` or `null`", v.span)
        elif isinstance(section, ast.DurationSection):
            values: list[float] = []
            for v in (section.low, section.high):
                if isinstance(v, ast.NumberLit) and v.value >= 0:
                    values.append(float(v.value))
                else:
                    self.error("E0312", "a duration bound is a non-negative number literal (seconds)", v.span)
            if len(values) == 2 and values[0] > values[1]:
                self.error("E0312", "the lower duration bound is greater than the upper one", section.span)

    def check_mapping(
        self, action: Symbol, decl: ast.ActionDecl, params: tuple[Symbol, ...], mapping: ast.Mapping
    ) -> None:
        seen: dict[str, ast.MappingArg] = {}
        bound: set[str] = set()
        for arg in mapping.args:
            first = seen.get(arg.name.name)
            if first is not None:
                self.given_twice("E0305", f"mapping argument `{arg.name.name}`", arg.name.span, first.name.span)
            else:
                seen[arg.name.name] = arg
            self.expr(arg.value)
            if decl.exogenous:
                v = arg.value
                target = self.model.target(v) if isinstance(v, ast.Name) else None
                if target is not None and target.kind is SymbolKind.PARAMETER and not v.parenthesized:
                    bound.add(target.name)
                else:
                    self.error(
                        "E0308",
                        "an exogenous action's mapping entry must be one of its parameters",
                        v.span,
                        "not a parameter",
                        notes=["the mapping is read backwards: incoming event fields set the parameters"],
                    )
        if decl.exogenous:
            missing = [p.name for p in params if p.name not in bound]
            if missing:
                names = ", ".join(f"`{m}`" for m in missing)
                self.error(
                    "E0308",
                    f"the mapping of exogenous action `{action.name}` does not bind {names}",
                    mapping.span,
                    help="add " + ", ".join(f"`{m} = {m}`" for m in missing),
                )

    def check_component(self, component: Symbol, decl: ast.ComponentDecl) -> None:
        for section in decl.sections:
            if isinstance(section, ast.StatesSection):
                for s in section.states:
                    if s.invariant is not None:
                        self.clock_formula(component, s.invariant)
            elif isinstance(section, ast.TransitionsSection):
                for t in section.transitions:
                    for state in (t.source, t.target):
                        self.component_member(component, state, SymbolKind.STATE)
                    if t.guard is not None:
                        self.clock_formula(component, t.guard)
                    for c in t.resets or ():
                        self.component_member(component, c, SymbolKind.CLOCK)

    def component_member(self, component: Symbol, name: ast.Ident, kind: SymbolKind) -> Symbol | None:
        member = component.members.get(name.name)
        if member is None or member.kind is not kind:
            names = [m.name for m in component.members.values() if m.kind is kind]
            self.error(
                "E0107",
                f"component `{component.name}` has no {kind.value} `{name.name}`",
                name.span,
                help=suggest(name.name, names),
            )
            return None
        self.refer(name.span, member, name)
        return member

    def clock_formula(self, component: Symbol, f: ast.ClockFormula) -> None:
        if isinstance(f, ast.ClockBound):
            self.component_member(component, f.clock, SymbolKind.CLOCK)
            if f.op not in (Op.LE, Op.GE):
                self.error("E0204", "a clock bound uses `<=` or `>=`", f.span)
        elif isinstance(f, ast.ClockNot):
            self.clock_formula(component, f.operand)
        elif isinstance(f, ast.ClockBinary):
            self.clock_formula(component, f.left)
            self.clock_formula(component, f.right)

    def spec(self, s: ast.Spec) -> None:
        if isinstance(s, ast.SpecBinary):
            self.spec(s.left)
            self.spec(s.right)
        elif isinstance(s, ast.SpecUnary):
            self.spec(s.operand)
        elif isinstance(s, ast.StateAtom):
            component = self.model.globals.get(s.component.name)
            if component is None or component.kind is not SymbolKind.COMPONENT:
                components = [g.name for g in self.model.globals.values() if g.kind is SymbolKind.COMPONENT]
                self.error(
                    "E0107",
                    f"unknown component `{s.component.name}`",
                    s.component.span,
                    help=suggest(s.component.name, components),
                )
                return
            self.refer(s.component.span, component, s.component)
            self.component_member(component, s.state, SymbolKind.STATE)
        elif isinstance(s, ast.ActionAtom):
            g = s.action
            action = self.model.globals.get(g.name.name)
            if action is None or action.kind is not SymbolKind.ACTION:
                actions = [x.name for x in self.model.globals.values() if x.kind is SymbolKind.ACTION]
                self.error("E0103", f"unknown action `{g.name.name}`", g.name.span, help=suggest(g.name.name, actions))
                return
            self.refer(g.name.span, action, g.name)
            if len(g.args) != len(action.params):
                self.arity_error(action, g.span, len(g.args))
                return
            for arg, p in zip(g.args, action.params, strict=True):
                if isinstance(arg, ast.Wildcard):
                    continue
                self.expect_literal(
                    arg, p.type, "constraint patterns take literals or `*`", f"parameter `{p.name}`", p.span
                )

    # ---------------------------------------------------------------- statements

    def stmt(self, s: ast.Statement) -> None:
        if isinstance(s, ast.Block):
            for x in s.body:
                self.stmt(x)
        elif isinstance(s, ast.CallStmt):
            if isinstance(s.call, ast.Call):
                self.call(s.call, "statement")
            else:
                self.expr(s.call)
                self.error(
                    "E0104",
                    "this expression is not a statement",
                    s.call.span,
                    "its value would be thrown away",
                    help="statements call actions or procedures, assign fluents, or `test(...)` a condition",
                )
        elif isinstance(s, ast.Assign):
            target = self.assign_target(s.target)
            self.expect(s.value, target, "the assigned fluent")
        elif isinstance(s, ast.If):
            self.expect(s.condition, BOOL, "an `if` condition")
            self.stmt(s.then)
            if s.otherwise is not None:
                self.stmt(s.otherwise)
        elif isinstance(s, ast.While):
            self.expect(s.condition, BOOL, "a `while` condition")
            self.stmt(s.body)
        elif isinstance(s, ast.Test):
            self.expect(s.condition, BOOL, "a `test`")
        elif isinstance(s, ast.Choose):
            for x in s.alternatives:
                self.stmt(x)
        elif isinstance(s, ast.Concurrent):
            for x in s.branches:
                self.stmt(x)
        elif isinstance(s, ast.Pick):
            self.pick(s)
        elif isinstance(s, ast.Solve):
            self.solve(s)
        elif isinstance(s, ast.Search):
            self.stmt(s.body)
        elif isinstance(s, ast.During):
            self.action_call(s.action, "during")
            self.stmt(s.body)
            if s.on_fail is not None:
                self.stmt(s.on_fail)
            if s.on_cancel is not None:
                self.stmt(s.on_cancel)
        elif isinstance(s, ast.HookStmt):
            self.action_call(s.action, s.hook.value)
        elif isinstance(s, ast.ListStmt):
            target = self.assign_target(s.target)
            if target is not ERROR and not isinstance(target, ListType) and target is not NULL:
                self.error(
                    "E0204", f"`{s.op.value}` needs a list, found `{target}`", s.target.span, f"this is `{target}`"
                )
                target = ERROR
            if s.value is not None:
                element = target.element if isinstance(target, ListType) else ERROR
                self.expect(s.value, element, "the list's element type")

    def action_call(self, e: ast.Expr, hook: str) -> None:
        if isinstance(e, ast.Call):
            self.call(e, hook)
        else:
            self.expr(e)
            self.error("E0104", f"`{hook}` needs an action call such as `{hook}(go(kitchen))`", e.span)

    def pick(self, s: ast.Pick) -> None:
        variable = self.new_variable(s.var_type, s.var, s)
        var_type = variable.type or ERROR
        if s.values is None:
            if not is_finite(var_type):
                self.error(
                    "E0210",
                    f"`pick` over `{var_type}` needs a list of values",
                    s.var_type.span,
                    f"`{var_type}` has infinitely many values",
                    help=f"write `pick ({var_type} {s.var.name} in {{...}})` or use a domain type",
                )
        else:
            for v in s.values:
                self.expect_literal(
                    v, var_type, "`pick ... in {...}` lists literal values", f"`{s.var.name}`", s.var_type.span
                )
        # The variable is visible in the body only (not in its own list of values).
        with self.scope(s.body.span, [variable]):
            self.stmt(s.body)

    def solve(self, s: ast.Solve) -> None:
        self.expect(s.horizon, NUMBER, "a `solve` horizon")
        reward = s.reward
        if isinstance(reward, ast.Call) and not reward.parenthesized:
            symbol = self.model.globals.get(reward.name.name)
            if symbol is not None and symbol.kind is not SymbolKind.FUNCTION:
                self.resolve_misused_call(reward, symbol)
                self.error(
                    "E0212",
                    f"the reward of `solve` must be a function, but `{symbol.name}` is "
                    f"{symbol.kind.article} {symbol.kind.value}",
                    reward.span,
                    secondary=self.declared_here(symbol),
                    help="declare `number function reward() = ...` and call it here",
                )
            elif (t := self.expr(reward)) is not ERROR and base(t) is not NUMBER:
                self.error("E0212", f"the reward of `solve` must be a number, found `{t}`", reward.span)
        else:
            self.expr(reward)
            self.error("E0212", "the reward of `solve` is a call of a number function", reward.span)
        self.stmt(s.body)

    def assign_target(self, e: ast.Expr) -> Type:
        """Check an assignment's left side (a fluent, or a field/element path from one) and
        return its type."""
        root = e
        while isinstance(root, ast.FieldAccess | ast.Index) and not root.parenthesized:
            root = root.subject
        if isinstance(root, ast.Call) and not root.parenthesized:
            symbol = self.model.globals.get(root.name.name)
            if symbol is not None and symbol.kind is not SymbolKind.FLUENT:
                self.resolve_misused_call(root, symbol)
                self.error(
                    "E0306",
                    f"cannot assign to `{symbol.name}`: it is {symbol.kind.article} {symbol.kind.value}",
                    root.span,
                    "not a fluent",
                    secondary=self.declared_here(symbol),
                    help="only fluents (and their fields and elements) can be assigned",
                )
                return ERROR
            return self.expr(e)
        if isinstance(root, ast.Name):
            self.expr(root)
            target = self.model.target(root)
            if target is None:
                return ERROR  # an unknown name: already reported
            if target.kind is SymbolKind.SYMBOL:
                help = "a symbol is a constant; assign a fluent that holds symbols instead"
            else:
                help = "parameters and variables are immutable; declare a fluent to hold changing values"
            self.error(
                "E0306",
                f"cannot assign to {target.kind.value} `{root.name}`",
                root.span,
                "not a fluent",
                help=help,
            )
            return ERROR
        self.expr(e)
        self.error("E0306", "cannot assign to this expression", e.span, "not a fluent")
        return ERROR

    # ---------------------------------------------------------------- expressions

    def expect(self, e: ast.Expr, target: Type, context: str, context_span: Span | None = None) -> Type:
        """Type `e` and check that a slot of type `target` accepts it."""
        t = self.expr(e)
        self.check_fits(e, t, target, context, context_span)
        return t

    def check_fits(self, e: ast.Expr, t: Type, target: Type, context: str, context_span: Span | None) -> None:
        secondary = [diag.Label(context_span, f"{context} is `{target}`")] if context_span else []
        if not assignable(target, t):
            help = None
            if base(target) is STRING and base(t) in (NUMBER, BOOL, SYMBOL):
                help = "convert it with `to_string(...)`"
            elif isinstance(target, DomainType) and isinstance(t, DomainType):
                help = f"`{t}` and `{target}` hold different kinds of values"
            self.error(
                "E0202",
                f"expected `{target}`, found `{t}`",
                e.span,
                f"expected `{target}` for {context}",
                secondary=secondary,
                help=help,
            )
            return
        if isinstance(target, DomainType) and target.defined:
            value = self.literal_value(e)
            if value is not None and not target.contains(value):
                shown = ", ".join(show_value(v) for v in target.values[:10]) + (
                    ", ..." if len(target.values) > 10 else ""
                )
                self.error(
                    "E0203",
                    f"`{show_value(value)}` is not in domain `{target}`",
                    e.span,
                    f"not a member of `{target}`",
                    secondary=secondary,
                    notes=[f"`{target}` = {{{shown}}}"],
                )
        elif isinstance(target, ListType) and isinstance(e, ast.ListLit):
            pass  # elements were checked against the literal's own element type
        elif isinstance(target, CompoundType | ListType):
            return

    def literal_value(self, e: ast.Expr) -> DomainValue | None:
        if isinstance(e, ast.Name):
            target = self.model.target(e)
            return Sym(e.name) if target is not None and target.kind is SymbolKind.SYMBOL else None
        if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit):
            return e.value
        return None

    def expr(self, e: ast.Expr) -> Type:
        t = self._expr(e)
        self.model.expr_types[id(e)] = t
        return t

    def _expr(self, e: ast.Expr) -> Type:
        if isinstance(e, ast.NumberLit):
            return NUMBER
        if isinstance(e, ast.StringLit):
            return STRING
        if isinstance(e, ast.BoolLit):
            return BOOL
        if isinstance(e, ast.NullLit):
            return NULL
        if isinstance(e, ast.Name):
            return self.name(e)
        if isinstance(e, ast.Call):
            return self.call(e, "expression")
        if isinstance(e, ast.Binary | ast.Unary) and id(e) not in self.reassociated:
            replacement = self.reassociate(e)
            if replacement is not None:
                if not self.silent:
                    self.model.rewritten[id(e)] = replacement
                return self.expr(replacement)
        if isinstance(e, ast.Unary):
            if e.op is ast.UnaryOp.NOT:
                self.expect_operand(e.operand, BOOL, "!")
                return BOOL
            self.expect_operand(e.operand, NUMBER, "-")
            return NUMBER
        if isinstance(e, ast.Binary):
            return self.binary(e)
        if isinstance(e, ast.Quantified):
            variable = self.new_variable(e.var_type, e.var, e)
            vt = variable.type or ERROR
            if not is_finite(vt):
                self.error(
                    "E0210",
                    f"`{e.quantifier.value}` over `{vt}` cannot be evaluated",
                    e.var_type.span,
                    f"`{vt}` has infinitely many values",
                    help="quantify over a domain (or bool)",
                )
            with self.scope(e.body.span, [variable]):
                self.expect(e.body, BOOL, f"the body of `{e.quantifier.value}`")
            return BOOL
        if isinstance(e, ast.Conditional):
            self.expect(e.condition, BOOL, "a condition")
            a = self.expr(e.then)
            b = self.expr(e.otherwise)
            common = common_type(a, b)
            if common is None:
                self.error(
                    "E0211",
                    f"the branches of this conditional have different types: `{a}` and `{b}`",
                    e.span,
                    secondary=[diag.Label(e.then.span, f"`{a}`"), diag.Label(e.otherwise.span, f"`{b}`")],
                )
                return ERROR
            return common
        if isinstance(e, ast.FieldAccess):
            return self.field_access(e)
        if isinstance(e, ast.Index):
            subject = self.expr(e.subject)
            self.expect(e.index, NUMBER, "a list index")
            if subject is ERROR:
                return ERROR
            if isinstance(subject, ListType):
                return subject.element
            self.error("E0207", f"`{subject}` cannot be indexed", e.subject.span, "not a list")
            return ERROR
        if isinstance(e, ast.CompoundLit):
            return self.compound_literal(e)
        if isinstance(e, ast.ListLit):
            list_type = self.resolve_type(e.type)
            element = list_type.element if isinstance(list_type, ListType) else ERROR
            for x in e.elements:
                self.expect(x, element, "the list's element type", e.type.span)
            return list_type
        if isinstance(e, ast.BuiltinCall):
            arg = self.expr(e.arg)
            if e.function is ast.Builtin.LENGTH:
                if arg is not ERROR and not isinstance(arg, ListType):
                    self.error("E0204", f"`length` needs a list, found `{arg}`", e.arg.span, f"this is `{arg}`")
                return NUMBER
            if isinstance(arg, CompoundType | ListType) or arg is VOID:
                self.error(
                    "E0204", f"`to_string` converts numbers, bools, symbols and strings, not `{arg}`", e.arg.span
                )
            return STRING
        if isinstance(e, ast.Wildcard):
            self.error("E0213", "`*` stands only in constraint patterns", e.span)
            return ERROR
        raise AssertionError(f"unhandled expression {type(e).__name__}")

    def expect_operand(self, e: ast.Expr, want: Type, op: str) -> Type:
        t = self.expr(e)
        if t is ERROR or assignable(want, t):
            if t is NULL:
                self.error("E0204", f"`{op}` cannot be applied to `null`", e.span)
                return ERROR
            return t
        self.error("E0204", f"`{op}` needs `{want}` operands, found `{t}`", e.span, f"this is `{t}`")
        return ERROR

    def binary(self, e: ast.Binary) -> Type:
        op = e.op
        if op in _BOOL_CHAIN:
            self.expect_operand(e.left, BOOL, op.value)
            self.expect_operand(e.right, BOOL, op.value)
            return BOOL
        if op in ast.COMPARISON_OPS:
            return self.comparison(e)
        left = self.expr(e.left)
        right = self.expr(e.right)
        if left is ERROR or right is ERROR:
            return ERROR
        if left is NULL or right is NULL:
            self.error("E0204", f"`{op.value}` cannot be applied to `null`", (e.left if left is NULL else e.right).span)
            return ERROR
        bl, br = base(left), base(right)
        if op is Op.ADD and bl is STRING and br is STRING:
            return STRING
        if bl is NUMBER and br is NUMBER:
            return NUMBER
        verb = {
            Op.ADD: "add",
            Op.SUB: "subtract",
            Op.MUL: "multiply",
            Op.DIV: "divide",
            Op.MOD: "take the remainder of",
        }
        help = None
        if op is Op.ADD and STRING in (bl, br):
            help = "convert the other operand with `to_string(...)` to concatenate"
        what = verb.get(op, "raise")
        self.error(
            "E0204",
            f"cannot {what} `{left}` and `{right}`" if op is not Op.POW else f"cannot raise `{left}` to `{right}`",
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
        chained = isinstance(e.left, ast.Binary) and e.left.op in ast.COMPARISON_OPS and not e.left.parenthesized
        if chained and not (e.op in _EQUALITY and base(right) is BOOL):
            assert isinstance(e.left, ast.Binary)
            self.error(
                "E0205",
                "comparison operators cannot be chained",
                e.span,
                f"`{e.left.op.value}` then `{e.op.value}`",
                help=f"compare each pair and join them with `&`: `a {e.left.op.value} b & b {e.op.value} c`",
            )
            return BOOL
        if e.op in _EQUALITY:
            if not equatable(left, right):
                if isinstance(base(left), CompoundType | ListType) or isinstance(base(right), CompoundType | ListType):
                    self.error(
                        "E0209",
                        f"values of type `{left}` cannot be compared with `{e.op.value}`",
                        e.span,
                        help="compare their fields or elements instead",
                    )
                else:
                    self.error(
                        "E0204",
                        f"cannot compare `{left}` with `{right}`",
                        operator_span(e),
                        secondary=[diag.Label(e.left.span, f"`{left}`"), diag.Label(e.right.span, f"`{right}`")],
                    )
            return BOOL
        if left is NULL or right is NULL:
            self.error("E0204", f"`{e.op.value}` cannot compare with `null`", e.span, help="test `x != null` first")
        elif not ordered(left) or base(left) != base(right):
            self.error(
                "E0204",
                f"cannot order `{left}` and `{right}` with `{e.op.value}`",
                operator_span(e),
                secondary=[diag.Label(e.left.span, f"`{left}`"), diag.Label(e.right.span, f"`{right}`")],
                notes=["`<`, `<=`, `>`, `>=` compare two numbers, two strings or two symbols"],
            )
        return BOOL

    def name(self, e: ast.Name) -> Type:
        variable = self.lookup_variable(e.name)
        if variable is not None:
            self.refer(e.span, variable, e)
            return variable.type or ERROR
        symbol = self.model.symbols.get(e.name)
        if symbol is not None:
            self.refer(e.span, symbol, e)
            return SYMBOL
        g = self.model.globals.get(e.name)
        if g is not None and g.kind in EXPRESSION_CALLABLE:
            self.refer(e.span, g, e)
            self.error(
                "E0102",
                f"`{e.name}` is {g.kind.article} {g.kind.value}; call it with `{e.name}(...)`",
                e.span,
                "missing `(...)`",
                secondary=self.declared_here(g),
                help=f"write `{e.name}()`" if not g.params else f"write `{e.name}(...)` with its arguments",
            )
            return ERROR
        candidates = [*self.visible_variables(), *self.model.symbols]
        self.error(
            "E0101",
            f"unknown name `{e.name}`",
            e.span,
            "not a variable, parameter or symbol",
            help=suggest(e.name, candidates),
        )
        return ERROR

    def call(self, e: ast.Call, context: str) -> Type:
        name = e.name.name
        symbol = self.model.globals.get(name)
        statement = context != "expression"
        if symbol is None:
            if statement:
                allowed = STATEMENT_CALLABLE if context == "statement" else frozenset({SymbolKind.ACTION})
                what = "action or procedure" if context == "statement" else "action"
            else:
                allowed = EXPRESSION_CALLABLE
                what = "fluent or function"
            pool = [g.name for g in self.model.globals.values() if g.kind in allowed]
            self.error(
                "E0103",
                f"unknown {what} `{name}`",
                e.name.span,
                "not declared",
                help=suggest(name, pool) or suggest(name, self.model.globals),
            )
            for a in e.args:
                self.expr(a)
            return ERROR
        if not self.call_kind_ok(e, symbol, context):
            self.resolve_misused_call(e, symbol)
            return ERROR
        self.refer(e.name.span, symbol, e)
        params = symbol.params
        if len(e.args) != len(params):
            self.arity_error(symbol, e.span, len(e.args))
        for i, a in enumerate(e.args):
            if i < len(params) and params[i].type is not None:
                p = params[i]
                self.expect(a, p.type or ERROR, f"parameter `{p.name}`", p.span)
            else:
                self.expr(a)
        return symbol.type or ERROR

    def resolve_misused_call(self, e: ast.Call, symbol: Symbol) -> None:
        """A call of the wrong kind of declaration (reported by the caller): the name still
        refers to it, and the arguments are checked on their own."""
        self.refer(e.name.span, symbol, e)
        for a in e.args:
            self.expr(a)

    def call_kind_ok(self, e: ast.Call, symbol: Symbol, context: str) -> bool:
        kind = symbol.kind
        name = symbol.name
        described = f"`{name}` is {kind.article} {kind.value}"
        secondary = self.declared_here(symbol)
        if context == "expression":
            if kind in EXPRESSION_CALLABLE:
                return True
            self.error(
                "E0104",
                f"{described}; only fluents and functions can be used in expressions",
                e.span,
                f"{kind.value} call in an expression",
                secondary=secondary,
            )
            return False
        if context == "statement":
            if kind in STATEMENT_CALLABLE:
                return True
            help: str | None
            if kind is SymbolKind.EXOG_ACTION:
                help = "the platform reports exogenous actions; a program cannot execute them"
            elif kind is SymbolKind.FLUENT:
                help = f"to change the fluent, assign it: `{name}(...) = value;`"
            else:
                help = "to wait until a condition holds, write `test(...)`" if symbol.type is BOOL else None
            self.error(
                "E0104",
                f"{described} and cannot be executed as a statement",
                e.span,
                "not an action or procedure",
                secondary=secondary,
                help=help,
            )
            return False
        if kind is SymbolKind.ACTION:
            return True
        self.error(
            "E0104",
            f"{described}; `{context}` needs an action",
            e.span,
            "not an action",
            secondary=secondary,
        )
        return False

    def arity_error(self, symbol: Symbol, span: Span, given: int) -> None:
        n = len(symbol.params)
        self.error(
            "E0201",
            f"`{symbol.name}` takes {n} argument{'s' * (n != 1)} but {given} {'were' if given != 1 else 'was'} given",
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
                    "E0106",
                    f"`{subject}` has no field `{e.field.name}`",
                    e.field.span,
                    "unknown field",
                    help=suggest(e.field.name, subject.fields),
                    notes=[f"fields of `{subject}`: " + ", ".join(f"`{f}`" for f in subject.fields)],
                )
                return ERROR
            if subject.symbol is not None:
                member = subject.symbol.members.get(e.field.name)
                if member is not None:
                    self.refer(e.field.span, member, e.field)
            return ftype
        self.error("E0207", f"`{subject}` has no fields", e.subject.span, f"this is `{subject}`, not a compound")
        return ERROR

    def compound_literal(self, e: ast.CompoundLit) -> Type:
        symbol = self.model.types.get(e.type_name.name)
        if symbol is None or symbol.kind is not SymbolKind.COMPOUND:
            compounds = [s.name for s in self.model.types.values() if s.kind is SymbolKind.COMPOUND]
            name = e.type_name.name
            message = f"unknown compound type `{name}`" if symbol is None else f"`{name}` is not a compound type"
            self.error("E0105", message, e.type_name.span, help=suggest(name, compounds))
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
                    "E0106",
                    f"`{ctype}` has no field `{f.name.name}`",
                    f.name.span,
                    "unknown field",
                    help=suggest(f.name.name, ctype.fields),
                )
                self.expr(f.value)
                continue
            first = given.get(f.name.name)
            if first is not None:
                self.given_twice("E0208", f"field `{f.name.name}`", f.name.span, first.name.span)
            given[f.name.name] = f
            member = symbol.members.get(f.name.name)
            if member is not None:
                self.refer(f.name.span, member, f.name)
            self.expect(f.value, ftype, f"field `{f.name.name}`", member.span if member else None)
        missing = [name for name in ctype.fields if name not in given]
        if missing:
            names = ", ".join(f"`{m}`" for m in missing)
            self.error(
                "E0208",
                f"missing field{'s' * (len(missing) != 1)} {names} in `{ctype}` literal",
                e.span,
                secondary=self.declared_here(symbol, f"`{ctype}` declared here"),
                help="give every field a value; write `null` for a field without one",
            )
        return ctype

    # ---------------------------------------------------------------- boolean `==` precedence

    def reassociate(self, e: ast.Binary | ast.Unary) -> ast.Expr | None:
        """Give boolean `==`/`!=` (iff/xor) their golog++ precedence, the loosest beside `->`.

        The grammar parses every `==` as a comparison, tighter than `&`; once the operand types
        are known, an unparenthesised chain that mixes a boolean `==` with `&`, `|`, `->` or `!`
        is rebuilt: `p() == q() & r()` means `p() == (q() & r())`. Returns None when nothing
        changes (almost always, and cheaply: the operand types are only computed when the chain
        has both kinds of operator)."""
        ops: set[object] = set()
        members: list[int] = []
        _chain_ops(e, ops, members, root=True)
        if not (ops & _EQUALITY) or not (ops - _EQUALITY):
            # Nothing to re-associate here, nor in any sub-chain: do not look again.
            self.reassociated.update(members)
            return None
        items: list[ast.Expr | Op | _Not] = []
        self.silent += 1
        try:
            self.flatten_chain(e, items, root=True)
        finally:
            self.silent -= 1
        rebuilt, rest = _climb(items, 0)
        assert not rest
        if rebuilt == e:
            return None
        if e.parenthesized:
            rebuilt = replace(rebuilt, span=e.span, parenthesized=True)
        _mark(rebuilt, self.reassociated)
        # The parsed chain's own nodes are all boolean; an editor pointing at one asks its type.
        _mark_types(e, self.model.expr_types)
        return rebuilt

    def flatten_chain(self, e: ast.Expr, out: list[ast.Expr | Op | _Not], root: bool = False) -> None:
        inside = root or not e.parenthesized
        if inside and isinstance(e, ast.Binary) and e.op in _BOOL_CHAIN:
            self.flatten_chain(e.left, out)
            out.append(e.op)
            self.flatten_chain(e.right, out)
        elif inside and isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
            out.append(_Not(e.span))
            self.flatten_chain(e.operand, out)
        elif inside and isinstance(e, ast.Binary) and e.op in _EQUALITY and self.is_boolean_pair(e):
            self.flatten_chain(e.left, out)
            out.append(e.op)
            self.flatten_chain(e.right, out)
        else:
            out.append(e)

    def is_boolean_pair(self, e: ast.Binary) -> bool:
        return base(self.expr(e.left)) is BOOL and base(self.expr(e.right)) is BOOL


def _chain_ops(e: ast.Expr, ops: set[object], members: list[int], root: bool = False) -> None:
    """The operators of the unparenthesised boolean/equality chain rooted at `e` (parentheses
    around the whole chain do not end it), and the ids of the chain's nodes. Iterative: a
    chain of thousands of `&` is a deep tree."""
    stack = [(e, root)]
    while stack:
        node, is_root = stack.pop()
        if node.parenthesized and not is_root:
            continue
        if isinstance(node, ast.Binary) and (node.op in _BOOL_CHAIN or node.op in _EQUALITY):
            ops.add(node.op)
            members.append(id(node))
            stack.append((node.left, False))
            stack.append((node.right, False))
        elif isinstance(node, ast.Unary) and node.op is ast.UnaryOp.NOT:
            ops.add(ast.UnaryOp.NOT)
            members.append(id(node))
            stack.append((node.operand, False))


_LEVELS: tuple[frozenset[Op], ...] = (
    frozenset({Op.IMPLIES, Op.EQ, Op.NE}),
    frozenset({Op.OR}),
    frozenset({Op.AND}),
)


@dataclass(frozen=True, slots=True)
class _Not:
    """A prefix `!` in a flattened chain (it applies to the next operand)."""

    span: Span


def _climb(items: list[ast.Expr | Op | _Not], level: int) -> tuple[ast.Expr, list[ast.Expr | Op | _Not]]:
    """Precedence climbing over a flattened chain; returns the tree and the unread items."""
    if level == len(_LEVELS):
        head = items[0]
        if isinstance(head, _Not):
            operand, rest = _climb(items[1:], level)
            span = Span(head.span.source, head.span.start, operand.span.end)
            return ast.Unary(span=span, op=ast.UnaryOp.NOT, operand=operand), rest
        assert isinstance(head, ast.Expr)
        return head, items[1:]
    left, rest = _climb(items, level + 1)
    while rest and isinstance(rest[0], Op) and rest[0] in _LEVELS[level]:
        op = rest[0]
        right, rest = _climb(rest[1:], level + 1)
        span = Span(left.span.source, left.span.start, right.span.end)
        left = ast.Binary(span=span, op=op, left=left, right=right)
    return left, rest


def _mark(e: ast.Expr, done: set[int]) -> None:
    if isinstance(e, ast.Binary) and (e.op in _BOOL_CHAIN or e.op in _EQUALITY):
        done.add(id(e))
        _mark(e.left, done)
        _mark(e.right, done)
    elif isinstance(e, ast.Unary):
        done.add(id(e))
        _mark(e.operand, done)


def operator_span(e: ast.Binary) -> Span:
    """The span of a binary expression's operator token (found between its operands)."""
    source = e.span.source
    start, end = e.left.span.end, e.right.span.start
    text = source.text[start:end]
    at = text.find(e.op.value)
    if at < 0:
        return e.span
    return Span(source, start + at, start + at + len(e.op.value))


def _mark_types(e: ast.Expr, types: dict[int, Type]) -> None:
    if e.parenthesized and id(e) in types:
        return
    if isinstance(e, ast.Binary) and (e.op in _BOOL_CHAIN or e.op in _EQUALITY):
        types.setdefault(id(e), BOOL)
        _mark_types(e.left, types)
        _mark_types(e.right, types)
    elif isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
        types.setdefault(id(e), BOOL)
        _mark_types(e.operand, types)


def _literal_value(e: ast.Expr) -> DomainValue | None:
    if isinstance(e, ast.NumberLit | ast.StringLit | ast.BoolLit):
        return e.value
    return None
