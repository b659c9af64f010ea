"""Phase 1 of the model builder, collect: every global, type and domain by name.

Predefines the built-in globals, then declares the name of every declaration of every file
(order never matters, SEMANTICS §2.1): forward declarations are merged with their
definitions; clashes, predefined names and second definitions are reported; a legacy main
block becomes `procedure main()`. Domains and compound types get their (still empty) type
here, so a use before the declaration resolves.

Reads the files of `state.model`; writes `model.globals`, `model.types`, `model.main`, the
declarations' references, `state.declarations` and `state.decl_symbol`.
"""

from __future__ import annotations

from gpp.base.source import Span
from gpp.codes import E0301, E0302, E0304, E0310
from gpp.model.builder_state import BuilderState, Phase
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import NUMBER, STRING, SYMBOL, VOID, CompoundType, DomainType
from gpp.syntax import ast

# Enum members read for every declaration, bound once: Python 3.11's enum class has a
# `__getattr__`, which makes reading any attribute of the class (`SymbolKind.DOMAIN`) several
# times slower than reading a global.
_DOMAIN, _COMPOUND = SymbolKind.DOMAIN, SymbolKind.COMPOUND
_ACTION, _EXOG_ACTION = SymbolKind.ACTION, SymbolKind.EXOG_ACTION
_FLUENT, _FUNCTION, _PROCEDURE = SymbolKind.FLUENT, SymbolKind.FUNCTION, SymbolKind.PROCEDURE

_KIND_OF_DECL: dict[type[ast.Decl], SymbolKind] = {
    ast.FluentDecl: SymbolKind.FLUENT,
    ast.FunctionDecl: SymbolKind.FUNCTION,
    ast.ExogFunctionDecl: SymbolKind.EXOG_FUNCTION,
    ast.ProcedureDecl: SymbolKind.PROCEDURE,
    ast.ComponentDecl: SymbolKind.COMPONENT,
}


# The declarations that are always definitions (a tuple, made once: `isinstance(x, A | B)`
# builds the union on every call).
_ALWAYS_DEFINED = (ast.ExogFunctionDecl, ast.ComponentDecl)


class Collector(Phase):
    def __init__(self, state: BuilderState) -> None:
        super().__init__(state)
        self.main_blocks: list[ast.MainBlock] = []

    def run(self) -> None:
        self.predefine()
        for pf in self.model.files:
            for decl in pf.program.declarations:
                self.collect(decl)
        self.collect_main()

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

    def collect(self, decl: ast.Decl) -> None:
        if isinstance(decl, ast.DomainDecl):
            self.declare(self.model.types, decl.name, _DOMAIN, decl, decl.definition is not None)
        elif isinstance(decl, ast.CompoundDecl):
            self.declare(self.model.types, decl.name, _COMPOUND, decl, True)
        elif isinstance(decl, ast.ActionDecl):
            kind = _EXOG_ACTION if decl.exogenous else _ACTION
            self.declare(self.model.globals, decl.name, kind, decl, decl.sections is not None)
        elif isinstance(decl, ast.FluentDecl):
            self.declare(self.model.globals, decl.name, _FLUENT, decl, decl.initially is not None)
        elif isinstance(decl, ast.FunctionDecl):
            self.declare(self.model.globals, decl.name, _FUNCTION, decl, decl.body is not None)
        elif isinstance(decl, ast.ProcedureDecl):
            self.declare(self.model.globals, decl.name, _PROCEDURE, decl, decl.body is not None)
        elif isinstance(decl, _ALWAYS_DEFINED):
            self.declare(self.model.globals, decl.name, _KIND_OF_DECL[type(decl)], decl, True)
        elif isinstance(decl, ast.MainBlock):
            self.main_blocks.append(decl)

    def declare(
        self, table: dict[str, Symbol], name: ast.Ident, kind: SymbolKind, decl: ast.Decl, definition: bool
    ) -> Symbol:
        existing = table.get(name.name)
        if existing is None:
            symbol = Symbol(name.name, kind, name.span, decl)
            # Types exist from the start, so a use before the declaration resolves (§2.1).
            if kind is _DOMAIN:
                symbol.type = DomainType(name.name, SYMBOL)
            elif kind is _COMPOUND:
                symbol.type = CompoundType(name.name)
            table[name.name] = symbol
            return self.attach(symbol, name, decl)
        detached = Symbol(name.name, kind, name.span, decl=decl)
        if existing.predefined:
            self.error(
                E0304.predefined(name.name),
                name.span,
                "predefined name",
                notes=[f"gpp predefines `{existing.signature()}`"],
            )
            return self.attach(detached, name, decl)
        if existing.kind is not kind:
            self.error(
                E0302.kind_clash(name.name, existing.kind),
                name.span,
                f"declared again as {kind.article} {kind.value}",
                secondary=self.declared_here(existing, f"the {existing.kind.value} is declared here"),
            )
            return self.attach(detached, name, decl)
        if definition and existing.is_defined:
            self.error(
                E0301.defined_twice(name.name),
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
        self.state.declarations.setdefault(id(existing), []).append(decl)
        self.state.decl_symbol[id(decl)] = existing
        self.refer(name.span, existing, name, declaration=True)
        return existing

    def attach(self, symbol: Symbol, name: ast.Ident, decl: ast.Decl) -> Symbol:
        self.state.declarations.setdefault(id(symbol), []).append(decl)
        self.state.decl_symbol[id(decl)] = symbol
        self.refer(name.span, symbol, name, declaration=True)
        return symbol

    def collect_main(self) -> None:
        for block in self.main_blocks:
            existing = self.model.globals.get("main")
            if existing is not None:
                self.error(
                    E0310.main_twice(),
                    Span(block.span.source, block.span.start, block.span.start + 1),
                    "this block means `procedure main()`",
                    secondary=self.declared_here(existing, "`main` is declared here"),
                    help="put the block's statements into `procedure main()`, or remove one of them",
                )
                continue
            symbol = Symbol("main", SymbolKind.PROCEDURE, None, decl=block, type=VOID)
            self.model.globals["main"] = symbol
            self.state.decl_symbol[id(block)] = symbol
        self.model.main = self.model.globals.get("main")
