"""Document symbols (the outline of a file), workspace symbols and folding ranges."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from lsprotocol import types

from gpp.check import CheckResult
from gpp.model.model import OutlineItem
from gpp.model.symbols import Symbol, SymbolKind
from gpp.model.types import DomainType, Sym
from gpp.syntax import ast
from gpp.syntax.walk import walk
from lsp.features.common import SYMBOL_KIND, comments_alone, document, location
from lsp.ranges import lsp_range


def document_symbols(result: CheckResult, path: Path) -> list[types.DocumentSymbol]:
    doc = document(result, path)
    if doc is None:
        return []
    return [_symbol(item) for item in doc.model.outline(doc.source) if item.name]


def _symbol(item: OutlineItem) -> types.DocumentSymbol:
    selection = item.selection
    if not (item.span.start <= selection.start and selection.end <= item.span.end):
        selection = item.span
    return types.DocumentSymbol(
        name=item.name,
        kind=SYMBOL_KIND[item.kind],
        range=lsp_range(item.span),
        selection_range=lsp_range(selection),
        detail=item.detail,
        children=[_symbol(c) for c in item.children if c.name],
    )


# ---------------------------------------------------------------- workspace symbols


def workspace_symbols(results: Sequence[CheckResult], query: str) -> list[types.WorkspaceSymbol]:
    """Every declared global, type and domain element of the programs whose name matches
    `query`: best matches first (same name, then prefix, substring, letters in order), each
    declaration once however many programs include its file."""
    seen: set[tuple[str, int]] = set()
    found: list[tuple[tuple[int, str, str, int], types.WorkspaceSymbol]] = []
    for result in results:
        model = result.model
        candidates: list[tuple[Symbol, str | None]] = [(s, None) for s in model.global_symbols()]
        candidates += [(s, None) for s in model.types.values()]
        for t in model.types.values():
            for s in _elements(result, t):
                candidates.append((s, t.name))
        for symbol, container in candidates:
            rank = match_rank(query, symbol.name)
            if rank is None or symbol.span is None or not symbol.name:
                continue
            loc = location(result, symbol.span)
            if loc is None or (loc.uri, symbol.span.start) in seen:
                continue
            seen.add((loc.uri, symbol.span.start))
            ws = types.WorkspaceSymbol(
                name=symbol.name, kind=SYMBOL_KIND[symbol.kind], location=loc, container_name=container
            )
            found.append(((rank, symbol.name.lower(), loc.uri, symbol.span.start), ws))
    found.sort(key=lambda x: x[0])
    return [ws for _, ws in found]


def _elements(result: CheckResult, domain: Symbol) -> list[Symbol]:
    t = domain.type
    if domain.kind is not SymbolKind.DOMAIN or not isinstance(t, DomainType):
        return []
    out: list[Symbol] = []
    for v in t.values:
        if isinstance(v, Sym):
            s = result.model.symbols.get(v.name)
            if s is not None:
                out.append(s)
    return out


def match_rank(query: str, name: str) -> int | None:
    """0 same name, 1 prefix, 2 substring, 3 the query's letters in order; None no match
    (case is ignored)."""
    q, n = query.lower(), name.lower()
    if not q:
        return 2
    if q == n:
        return 0
    if n.startswith(q):
        return 1
    if q in n:
        return 2
    it = iter(n)
    return 3 if all(c in it for c in q) else None


# ---------------------------------------------------------------- folding


def folding_ranges(result: CheckResult, path: Path) -> list[types.FoldingRange]:
    doc = document(result, path)
    if doc is None:
        return []
    source = doc.source
    ranges: dict[int, types.FoldingRange] = {}

    def add(start: int, end: int, kind: types.FoldingRangeKind | None, closer: bool) -> None:
        first = source.line_col(start)[0] - 1
        last = source.line_col(max(start, end))[0] - 1
        if closer and end > start and source.line_text(last + 1).strip().startswith(source.text[end - 1]):
            # Keep the closing brace visible: `{ ... }` folds up to the line before it.
            last -= 1
        if last > first and first not in ranges:
            ranges[first] = types.FoldingRange(start_line=first, end_line=last, kind=kind)

    program = doc.file.program
    # Runs of comments (a block comment or comments on adjacent lines), and runs of includes.
    groups: list[list[tuple[int, int]]] = []
    for start, end in comments_alone(doc.file):
        if groups and source.line_col(start)[0] <= source.line_col(groups[-1][-1][1])[0] + 1:
            groups[-1].append((start, end))
        else:
            groups.append([(start, end)])
    for group in groups:
        add(group[0][0], group[-1][1], types.FoldingRangeKind.Comment, False)
    includes = [d for d in program.declarations if isinstance(d, ast.Include)]
    if len(includes) > 1:
        add(includes[0].span.start, includes[-1].span.end, types.FoldingRangeKind.Imports, False)
    for node in walk(program):
        if isinstance(node, ast.Decl | ast.Block | ast.ActionSection | ast.ComponentSection | ast.DomainSet):
            if not isinstance(node, ast.Include):
                add(node.span.start, node.span.end, None, True)
        elif isinstance(node, ast.CompoundLit | ast.ListLit) or (
            isinstance(node, ast.Call) and node.span.line != node.span.end_line
        ):
            add(node.span.start, node.span.end, None, True)
    return [ranges[k] for k in sorted(ranges)]
