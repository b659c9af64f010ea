"""Phase 2 of the model builder, resolve: what the type expressions of the declarations name.

Resolves every declaration's parameter, value and element types (and list type
declarations), gives globals their signature (the defining declaration's signature wins; a
forward one serves until it comes), declares component clocks and states and, once the
domains are evaluated (gpp.model.domains), compound fields; then compares each forward
declaration with its definition. `resolve_type` is also what the later phases use to read a
type written in a body (`pick`, quantifiers, list literals).

Reads `state.decl_symbol`, `state.declarations` and `model.types`; writes the symbols' `type`,
`params` and `members`, `state.decl_params`, `state.merged` and the references of type names
and parameters.
"""

from __future__ import annotations

from collections.abc import Sequence

from gpp.base import diagnostics as diag
from gpp.codes import E0105, E0206, E0303, E0305, E0311
from gpp.model.builder_state import Phase
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import (
    BOOL,
    BUILTIN_TYPES,
    ERROR,
    NUMBER,
    STRING,
    SYMBOL,
    VOID,
    BuiltinType,
    CompoundType,
    DomainType,
    ListType,
    Type,
)
from gpp.syntax import ast

# Enum members read for every declaration, bound once: Python 3.11's enum class has a
# `__getattr__`, which makes reading any attribute of the class (`SymbolKind.DOMAIN`) several
# times slower than reading a global.
_PARAMETER, _FIELD, _COMPOUND = SymbolKind.PARAMETER, SymbolKind.FIELD, SymbolKind.COMPOUND

# The declarations with a value type and parameters, and those with parameters only (tuples,
# made once: `isinstance(x, A | B)` builds the union on every call).
_VALUED = (ast.FluentDecl, ast.FunctionDecl, ast.ExogFunctionDecl)
_VOID = (ast.ActionDecl, ast.ProcedureDecl)


class TypeResolver(Phase):
    def run(self) -> None:
        """Resolve the types of every declaration (not yet the fields of compound types)."""
        for pf in self.model.files:
            for decl in pf.program.declarations:
                self.resolve_declaration(decl)

    def resolve_type(self, t: ast.TypeExpr, data: bool = True) -> Type:
        """The type a type expression names; `data` types may not be void."""
        if isinstance(t, ast.ListType):
            element = self.resolve_type(t.element)
            return ERROR if element is ERROR else ListType(element)
        builtin = BUILTIN_TYPES.get(t.name)
        if builtin is not None:
            if builtin is VOID and data:
                self.error(
                    E0206.void_data(),
                    t.span,
                    "no value has type `void`",
                    help="actions and procedures have no type; data needs bool, number, string, symbol, "
                    "a domain, a compound or a list type",
                )
                return ERROR
            return builtin
        symbol = self.model.types.get(t.name)
        if symbol is None:
            types = self.model.types
            candidates = self.state.name_index(
                "types", types, lambda: [*types, *(n for n in BUILTIN_TYPES if n != "void")]
            )
            self.error(
                E0105.unknown_type(t.name),
                t.span,
                "not a declared type",
                suggested=candidates.suggestion(t.name),
            )
            return ERROR
        self.refer(t.span, symbol, t)
        assert symbol.type is not None
        return symbol.type

    def name_first(self, p: ast.Param, kind: SymbolKind, owner: Symbol) -> Symbol | None:
        """`goto(p Location)`: a parameter written name first, where the type is not a type and
        the name is one. Reported (E0105) with the swap as its fix; the parameter is then the
        one meant (`p`, a `Location`), so its uses are not reported too. None for any other."""
        t = p.type
        if not isinstance(t, ast.NamedType) or t.name in BUILTIN_TYPES or t.name in self.model.types:
            return None
        meant = self.model.types.get(p.name.name)
        if meant is None or meant.type is None:
            return None
        self.error(
            E0105.unknown_type(t.name),
            t.span,
            "not a declared type",
            help=f"the type comes first: `{p.name.name} {t.name}`",
            fix=diag.Fix(
                f"write `{p.name.name} {t.name}`",
                (diag.Edit(t.span, p.name.name), diag.Edit(p.name.span, t.name)),
                diag.Applicability.SAFE,
            ),
        )
        self.refer(p.name.span, meant, p.name)
        return Symbol(t.name, kind, t.span, p, meant.type, owner)

    def resolve_params(self, owner: Symbol, params: Sequence[ast.Param], kind: SymbolKind) -> tuple[Symbol, ...]:
        if not params:
            return ()
        out: list[Symbol] = []
        seen: dict[str, Symbol] = {}
        for p in params:
            symbol = self.name_first(p, kind, owner) or Symbol(
                p.name.name, kind, p.name.span, p, self.resolve_type(p.type), owner
            )
            first = seen.get(p.name.name)
            if first is not None:
                self.error(
                    E0305.in_list(p.name.name),
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
        symbol = self.state.decl_symbol.get(id(decl))
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
                    E0311.element_kind(element),
                    decl.element_type.span,
                )
                dtype.broken = True
            elif not dtype.element_known:
                dtype.element = element
                dtype.element_known = True
            elif dtype.element != element:
                self.error(
                    E0303.element_type(symbol.name, dtype.element, element),
                    decl.element_type.span,
                    "different element type",
                    secondary=self.declared_here(symbol),
                )
                dtype.broken = True
            return
        if isinstance(decl, ast.CompoundDecl):
            return
        if isinstance(decl, _VALUED):
            value_type = self.resolve_type(decl.type)
            params = self.resolve_params(symbol, decl.params, _PARAMETER)
        elif isinstance(decl, _VOID):
            value_type = VOID
            params = self.resolve_params(symbol, decl.params, _PARAMETER)
        elif isinstance(decl, ast.ComponentDecl):
            self.resolve_component(symbol, decl)
            return
        else:
            return
        self.state.decl_params[id(decl)] = params
        # The defining declaration's signature wins; a forward one serves until it comes.
        if symbol.decl is decl or symbol.type is None:
            symbol.type = value_type
            symbol.params = params

    def resolve_compound_fields(self) -> None:
        """Declare the fields of every compound type (the builder runs this after the domains)."""
        for symbol in self.model.types.values():
            decl = symbol.decl
            if symbol.kind is not _COMPOUND or not isinstance(decl, ast.CompoundDecl):
                continue
            ctype = symbol.type
            assert isinstance(ctype, CompoundType)
            fields = self.resolve_params(symbol, decl.fields, _FIELD)
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
                E0305.in_component(name.name, owner.name),
                name.span,
                secondary=self.declared_here(first, "first declared here"),
            )
            return
        member = Symbol(name.name, kind, name.span, owner=owner)
        owner.members[name.name] = member
        self.refer(name.span, member, name, declaration=True)

    def check_forward_declarations(self) -> None:
        for symbol in list(self.model.globals.values()):
            decls = self.state.declarations.get(id(symbol), [])
            if len(decls) < 2 or symbol.decl is None:
                continue
            main = symbol.decl
            assert isinstance(main, ast.Decl)
            for other in decls:
                if other is main:
                    continue
                self.compare_declarations(symbol, main, other)

    def compare_declarations(self, symbol: Symbol, main: ast.Decl, other: ast.Decl) -> None:
        mine = self.state.decl_params.get(id(main), ())
        theirs = self.state.decl_params.get(id(other), ())
        other_name: ast.Ident = other.name  # type: ignore[attr-defined]
        label = [diag.Label(other_name.span, "forward declaration here")]
        main_type = getattr(main, "type", None)
        other_type = getattr(other, "type", None)
        if main_type is not None and other_type is not None:
            a = self.resolve_type_quiet(main_type)
            b = self.resolve_type_quiet(other_type)
            if a is not ERROR and b is not ERROR and a != b:
                self.error(
                    E0303.type_(symbol.name, b, a),
                    main_type.span,
                    secondary=label,
                )
                return
        if len(mine) != len(theirs):
            self.error(
                E0303.parameter_count(symbol.name, len(theirs), len(mine)),
                symbol.span or other_name.span,
                secondary=label,
            )
            return
        for p, q in zip(mine, theirs, strict=True):
            if p.name == q.name and q.span is not None:
                # One parameter, declared twice: rename and references see both names.
                self.state.merged[id(q)] = p
                p.other_spans.append(q.span)
            if p.type is not ERROR and q.type is not ERROR and p.type != q.type:
                assert p.span is not None
                self.error(
                    E0303.parameter_type(p.name, p.type, q.type),
                    p.span,
                    secondary=[diag.Label(q.span, "declared here")] if q.span else [],
                )
            elif p.name != q.name:
                assert p.span is not None
                self.error(
                    E0303.parameter_name(p.name, q.name),
                    p.span,
                    secondary=[diag.Label(q.span, "declared here")] if q.span else [],
                    help="use the same parameter names in both",
                )

    def resolve_type_quiet(self, t: ast.TypeExpr) -> Type:
        self.state.silent += 1
        try:
            return self.resolve_type(t)
        finally:
            self.state.silent -= 1
