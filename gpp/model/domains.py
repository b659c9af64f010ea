"""Phase 2b of the model builder, domains: every domain evaluated to its set of members.

Runs after the types are resolved. Evaluates each domain definition (references to other
domains, literal sets, union / difference / intersection), reporting cycles, element-type
mismatches and non-literal members; the names listed in a `symbol` domain are declared here
as the program's symbols. Literal members are typed by the type checker.

Reads `model.types` and the domains' element types (from resolve); writes each DomainType's
`values`/`defined`, `model.symbols`, and the references and expression types of the members.
"""

from __future__ import annotations

from gpp.codes import E0105, E0202, E0213, E0311
from gpp.model.builder_state import BuilderState, Phase
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.typecheck import TypeChecker, is_literal
from gpp.model.types import ERROR, SYMBOL, DomainType, DomainValue, value_key
from gpp.syntax import ast

# Enum members read for every declaration, bound once: Python 3.11's enum class has a
# `__getattr__`, which makes reading any attribute of the class (`SymbolKind.DOMAIN`) several
# times slower than reading a global.
_DOMAIN, _SYMBOL_KIND = SymbolKind.DOMAIN, SymbolKind.SYMBOL
_UNION, _DIFFERENCE = ast.DomainOp.UNION, ast.DomainOp.DIFFERENCE

# Literals that are no member of a domain other than of symbols, and the literals with a value
# (tuples, made once: `isinstance(x, A | B)` builds the union on every call).
_NOT_MEMBERS = (ast.Name, ast.NullLit)
_VALUES = (ast.NumberLit, ast.StringLit, ast.BoolLit)


class DomainEvaluator(Phase):
    def __init__(self, state: BuilderState, checker: TypeChecker) -> None:
        super().__init__(state)
        self.checker = checker
        self.domains_in_progress: set[int] = set()

    def run(self) -> None:
        for symbol in list(self.model.types.values()):
            if symbol.kind is _DOMAIN:
                self.evaluate_domain(symbol)

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
                E0311.recursive(symbol.name),
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
            if other is None or other.kind is not _DOMAIN:
                types = self.model.types
                domains = self.state.name_index(
                    ("types", _DOMAIN), types, lambda: (s.name for s in types.values() if s.kind is _DOMAIN)
                )
                name = d.name.name
                message = E0105.not_domain(name) if other is not None else E0105.unknown_domain(name)
                self.error(message, d.name.span, suggested=domains.suggestion(name))
                return ()
            self.refer(d.name.span, other, d.name)
            values = self.evaluate_domain(other)
            assert isinstance(other.type, DomainType)
            if other.type.element != dtype.element:
                self.error(
                    E0311.mixed(other.name, other.type.element, dtype.name, dtype.element),
                    d.span,
                )
                return ()
            return values
        if isinstance(d, ast.DomainSet):
            out: list[DomainValue] = []
            seen: set[object] = set()
            for e in d.elements:
                v = self.domain_literal(e, dtype)
                if v is not None and value_key(v) not in seen:
                    seen.add(value_key(v))
                    out.append(v)
            return tuple(out)
        if isinstance(d, ast.DomainBinary):
            left = self.domain_values(d.left, dtype)
            right = self.domain_values(d.right, dtype)
            if d.op is _UNION:
                in_left = {value_key(x) for x in left}
                return left + tuple(v for v in right if value_key(v) not in in_left)
            in_right = {value_key(x) for x in right}
            if d.op is _DIFFERENCE:
                return tuple(v for v in left if value_key(v) not in in_right)
            return tuple(v for v in left if value_key(v) in in_right)
        return ()

    def domain_literal(self, e: ast.Expr, dtype: DomainType) -> DomainValue | None:
        element = dtype.element
        if element is SYMBOL:
            if isinstance(e, ast.Name):
                symbol = self.model.symbols.get(e.name)
                if symbol is None:
                    symbol = Symbol(e.name, _SYMBOL_KIND, e.span, e, SYMBOL)
                    self.model.symbols[e.name] = symbol
                    self.refer(e.span, symbol, e, declaration=True)
                else:
                    symbol.other_spans.append(e.span)
                    self.refer(e.span, symbol, e, declaration=True)
                self.model.expr_types[id(e)] = SYMBOL
                return self.checker.symbol_value(e.name)
            self.error(E0202.symbol_name_expected(), e.span, f"a `symbol` domain lists names like `{dtype.name}_a`")
            return None
        if not is_literal(e) or isinstance(e, _NOT_MEMBERS):
            self.error(E0213.domain_element(element), e.span, "not a literal")
            return None
        t = self.checker.expr(e)
        if t is not ERROR and t != element:
            self.error(E0202.mismatch(element, t), e.span, f"domain `{dtype.name}` holds `{element}` values")
            return None
        return _literal_value(e)


def _literal_value(e: ast.Expr) -> DomainValue | None:
    if isinstance(e, _VALUES):
        return e.value
    return None
