"""The code model: every declaration, every reference with its target, every expression with
its type. Built once by gpp.model.build; the checker, the interpreter and the language server
all read it. The query methods are what an editor needs (hover, definition, references,
completion, outline)."""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass, field

from gpp.base.source import Source, Span
from gpp.model.symbols import GLOBAL_KINDS, Reference, ScopeRecord, Symbol, SymbolKind
from gpp.model.types import ERROR, CompoundType, DomainType, Sym, Type
from gpp.syntax import ast
from gpp.syntax.loader import ParsedFile
from gpp.syntax.walk import path_to, walk


@dataclass(frozen=True, slots=True)
class OutlineItem:
    name: str
    kind: SymbolKind
    span: Span  # the whole declaration
    selection: Span  # its name
    detail: str
    children: tuple[OutlineItem, ...] = ()


@dataclass
class Model:
    files: list[ParsedFile]
    globals: dict[str, Symbol] = field(default_factory=dict)
    types: dict[str, Symbol] = field(default_factory=dict)
    # Domain elements by name.
    symbols: dict[str, Symbol] = field(default_factory=dict)
    references: list[Reference] = field(default_factory=list)
    scopes: list[ScopeRecord] = field(default_factory=list)
    # id(ast node) -> its type / the symbol it names. Nodes are kept alive by `files`.
    expr_types: dict[int, Type] = field(default_factory=dict)
    targets: dict[int, Symbol] = field(default_factory=dict)
    # id(expression) -> the expression it stands for after boolean `==`/`!=` were given their
    # golog++ precedence (see gpp.model.regroup); consumers use `effective()`.
    rewritten: dict[int, ast.Expr] = field(default_factory=dict)
    main: Symbol | None = None

    def __post_init__(self) -> None:
        self._refs_by_source: dict[int, list[Reference]] | None = None
        self._refs_by_symbol: dict[int, list[Reference]] | None = None
        # Per source (by id): where its references start, in the order of `references_in`.
        self._starts_by_source: dict[int, list[int]] = {}
        self._declared_symbols: tuple[Sym, ...] | None = None

    # ---------------------------------------------------------------- facts

    def type_of(self, expr: ast.Expr) -> Type:
        return self.expr_types.get(id(expr), ERROR)

    def target(self, node: ast.Node) -> Symbol | None:
        """The symbol a Name, Call, Ident or NamedType refers to."""
        return self.targets.get(id(node))

    def effective(self, expr: ast.Expr) -> ast.Expr:
        return self.rewritten.get(id(expr), expr)

    def lookup(self, name: str) -> Symbol | None:
        return self.globals.get(name) or self.types.get(name) or self.symbols.get(name)

    def file_of(self, source: Source) -> ParsedFile | None:
        return next((f for f in self.files if f.source is source), None)

    def declaration(self, t: DomainType | CompoundType) -> Symbol | None:
        """The symbol that declares a domain or compound type (a type names its declaration
        only by its name)."""
        s = self.types.get(t.name)
        return s if s is not None and s.type is t else None

    def domain(self, name: str) -> DomainType | None:
        s = self.types.get(name)
        return s.type if s is not None and isinstance(s.type, DomainType) else None

    # ---------------------------------------------------------------- indexes

    # Two indexes, each built on first use: the checker's lints ask only which references a
    # symbol has, an editor also which references a file has.

    def _index_by_source(self) -> dict[int, list[Reference]]:
        by_source: dict[int, list[Reference]] = {}
        for r in self.references:
            key = id(r.span.source)
            refs = by_source.get(key)
            if refs is None:
                by_source[key] = [r]
            else:
                refs.append(r)
        for refs in by_source.values():
            refs.sort(key=_position)
        self._refs_by_source = by_source
        return by_source

    def _index_by_symbol(self) -> dict[int, list[Reference]]:
        by_symbol: dict[int, list[Reference]] = {}
        for r in self.references:
            key = id(r.symbol)
            refs = by_symbol.get(key)
            if refs is None:
                by_symbol[key] = [r]
            else:
                refs.append(r)
        self._refs_by_symbol = by_symbol
        return by_symbol

    def references_in(self, source: Source) -> list[Reference]:
        by_source = self._refs_by_source
        if by_source is None:
            by_source = self._index_by_source()
        return by_source.get(id(source), [])

    # ---------------------------------------------------------------- editor queries

    def reference_at(self, source: Source, offset: int) -> Reference | None:
        """The name occurrence (declaration or use) under `offset`."""
        refs = self.references_in(source)
        starts = self._starts_by_source.get(id(source))
        if starts is None:
            starts = self._starts_by_source[id(source)] = [r.span.start for r in refs]
        i = bisect_right(starts, offset)
        best: Reference | None = None
        for r in refs[max(0, i - 8) : i]:
            if r.span.start <= offset <= r.span.end and (best is None or r.span.start >= best.span.start):
                best = r
        return best

    def symbol_at(self, source: Source, offset: int) -> Symbol | None:
        ref = self.reference_at(source, offset)
        return ref.symbol if ref else None

    def definition(self, symbol: Symbol) -> Span | None:
        return symbol.span

    def references_to(self, symbol: Symbol, include_declaration: bool = True) -> list[Reference]:
        by_symbol = self._refs_by_symbol
        if by_symbol is None:
            by_symbol = self._index_by_symbol()
        refs = by_symbol.get(id(symbol), [])
        return [r for r in refs if include_declaration or not r.declaration]

    def node_path(self, source: Source, offset: int) -> list[ast.Node]:
        """Syntax nodes from the declaration down to the innermost node at `offset`."""
        pf = self.file_of(source)
        if pf is None:
            return []
        return path_to(pf.program, offset)[1:]

    def expression_at(self, source: Source, offset: int) -> ast.Expr | None:
        for node in reversed(self.node_path(source, offset)):
            if isinstance(node, ast.Expr):
                return node
        return None

    def visible_at(self, source: Source, offset: int) -> list[Symbol]:
        """Names usable at `offset`: globals, domain symbols, types, and the local variables of
        every scope around it (inner ones last, so they shadow)."""
        out: dict[str, Symbol] = {}
        for table in (self.types, self.symbols, self.globals):
            out.update(table)
        for scope in self.scopes:
            if scope.span.source is source and scope.span.start <= offset <= scope.span.end:
                for s in scope.symbols:
                    out[s.name] = s
        return list(out.values())

    def outline(self, source: Source) -> list[OutlineItem]:
        pf = self.file_of(source)
        if pf is None:
            return []
        items: list[OutlineItem] = []
        for decl in pf.program.declarations:
            item = self._outline_item(decl)
            if item is not None:
                items.append(item)
        return items

    def _outline_item(self, decl: ast.Decl) -> OutlineItem | None:
        if isinstance(decl, ast.MainBlock):
            return OutlineItem("main", SymbolKind.PROCEDURE, decl.span, decl.span, "legacy main block")
        name_node = getattr(decl, "name", None)
        if not isinstance(name_node, ast.Ident):
            return None
        sym = self.target(name_node)
        if sym is None:
            return None
        # Children come from this declaration's own text, so that they lie inside it (a forward
        # declaration lists its own parameters, not the definition's).
        children: list[OutlineItem] = []
        params: tuple[ast.Param, ...] = getattr(decl, "params", ())
        kind = SymbolKind.PARAMETER
        if isinstance(decl, ast.CompoundDecl):
            params, kind = decl.fields, SymbolKind.FIELD
        for p in params:
            children.append(OutlineItem(p.name.name, kind, p.span, p.name.span, f"{_type_text(p.type)} {p.name.name}"))
        if isinstance(decl, ast.ComponentDecl):
            for section in decl.sections:
                names: tuple[ast.Ident, ...] = ()
                member_kind = SymbolKind.CLOCK
                if isinstance(section, ast.ClocksSection):
                    names = section.clocks
                elif isinstance(section, ast.StatesSection):
                    names, member_kind = tuple(st.name for st in section.states), SymbolKind.STATE
                for n in names:
                    children.append(OutlineItem(n.name, member_kind, n.span, n.span, member_kind.value))
        if isinstance(decl, ast.DomainDecl) and decl.definition is not None:
            for node in walk(decl.definition):
                if isinstance(node, ast.Name):
                    element = self.target(node)
                    if element is not None and element.span is node.span:
                        children.append(OutlineItem(node.name, SymbolKind.SYMBOL, node.span, node.span, "symbol"))
        return OutlineItem(sym.name, sym.kind, decl.span, name_node.span, sym.signature(), tuple(children))

    def global_symbols(self) -> list[Symbol]:
        return [s for s in self.globals.values() if s.kind in GLOBAL_KINDS]

    def declared_symbols(self) -> tuple[Sym, ...]:
        """The values of the type `symbol`, which `exists`, `forall` and `pick` range over:
        every symbol named in a `symbol` domain of the program, in the order the program first
        names them (files in the order they are loaded, the root file first)."""
        if self._declared_symbols is None:
            order = {id(f.source): i for i, f in enumerate(self.files)}

            def first_named(s: Symbol) -> tuple[int, int]:
                return (order.get(id(s.span.source), len(order)), s.span.start) if s.span else (len(order), 0)

            self._declared_symbols = tuple(Sym(s.name) for s in sorted(self.symbols.values(), key=first_named))
        return self._declared_symbols


def _position(r: Reference) -> tuple[int, int]:
    """References of a file in order: by start, the longer one first."""
    return (r.span.start, -r.span.end)


def _type_text(t: ast.TypeExpr) -> str:
    return f"list[{_type_text(t.element)}]" if isinstance(t, ast.ListType) else t.name
