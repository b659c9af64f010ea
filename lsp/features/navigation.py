"""Go to definition, find references, document highlight and rename: queries on the model's
references (every occurrence of a name, with the symbol it means)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

from lsprotocol import types

from gpp.base.source import Span
from gpp.check import CheckResult
from gpp.model.symbols import Reference, Symbol, SymbolKind
from gpp.syntax import ast
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, SECTION_WORDS
from gpp.syntax.walk import walk
from lsp.features.common import (
    KEYWORD_TYPES,
    LOCAL_KINDS,
    Document,
    document,
    included_at,
    location,
    path_of,
    stdlib_sources,
)
from lsp.ranges import lsp_range


class RenameError(Exception):
    """A rename the server refuses; the message is shown to the user."""


_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
RESERVED = frozenset(KEYWORDS) | frozenset(PLATFORM_KEYWORDS) | frozenset(SECTION_WORDS)


def definition(result: CheckResult, path: Path, offset: int) -> list[types.Location]:
    doc = document(result, path)
    if doc is None:
        return []
    included = included_at(doc, offset)
    if included is not None:
        return [types.Location(uri=included.path.as_uri(), range=types.Range(start=_ZERO, end=_ZERO))]
    symbol = doc.model.symbol_at(doc.source, offset)
    if symbol is None or symbol.span is None:
        return []
    loc = location(result, symbol.span)
    return [] if loc is None else [loc]


_ZERO = types.Position(line=0, character=0)


def references(result: CheckResult, path: Path, offset: int, include_declaration: bool) -> list[types.Location]:
    found = _symbol_under(result, path, offset)
    if found is None:
        return []
    doc, symbol = found
    out: list[types.Location] = []
    for ref in _sorted(result, doc.model.references_to(symbol, include_declaration)):
        loc = location(result, ref.span)
        if loc is not None:
            out.append(loc)
    return out


def _symbol_under(result: CheckResult, path: Path, offset: int) -> tuple[Document, Symbol] | None:
    doc = document(result, path)
    symbol = None if doc is None else doc.model.symbol_at(doc.source, offset)
    return None if doc is None or symbol is None else (doc, symbol)


def _sorted(result: CheckResult, refs: list[Reference]) -> list[Reference]:
    order = {id(f.source): i for i, f in enumerate(result.loaded.files)}
    return sorted(refs, key=lambda r: (order.get(id(r.span.source), -1), r.span.start))


# ---------------------------------------------------------------- highlight

_READ_WRITE = frozenset({SymbolKind.FLUENT, SymbolKind.PARAMETER, SymbolKind.VARIABLE, SymbolKind.FIELD})


def document_highlight(result: CheckResult, path: Path, offset: int) -> list[types.DocumentHighlight]:
    found = _symbol_under(result, path, offset)
    if found is None:
        return []
    doc, symbol = found
    written = written_names(doc.file.program) if symbol.kind in _READ_WRITE else set()
    out: list[types.DocumentHighlight] = []
    for ref in _sorted(result, doc.model.references_to(symbol)):
        if ref.span.source is not doc.source:
            continue
        if ref.declaration or symbol.kind not in _READ_WRITE:
            kind = types.DocumentHighlightKind.Text
        elif ref.span.start in written:
            kind = types.DocumentHighlightKind.Write
        else:
            kind = types.DocumentHighlightKind.Read
        out.append(types.DocumentHighlight(range=lsp_range(ref.span), kind=kind))
    return out


def written_names(program: ast.Program) -> set[int]:
    """Start offsets of the names that are assigned to: the fluent or variable at the root of
    the target of an assignment, an effect, a `senses` section or a list operation."""
    out: set[int] = set()
    for node in walk(program):
        target: ast.Expr | None = None
        if isinstance(node, ast.Assign | ast.Effect | ast.SensesSection | ast.ListStmt):
            target = node.target
        while isinstance(target, ast.FieldAccess | ast.Index):
            target = target.subject
        if isinstance(target, ast.Call):
            out.add(target.name.span.start)
        elif isinstance(target, ast.Name):
            out.add(target.span.start)
    return out


# ---------------------------------------------------------------- rename


def prepare_rename(result: CheckResult, path: Path, offset: int) -> types.PrepareRenameResult | None:
    doc = document(result, path)
    if doc is None:
        return None
    ref, symbol = _renamable(doc, offset)
    return types.PrepareRenamePlaceholder(range=lsp_range(ref.span), placeholder=symbol.name)


def rename(
    result: CheckResult, path: Path, offset: int, new_name: str, others: Sequence[CheckResult] = ()
) -> types.WorkspaceEdit | None:
    """The edit that renames the symbol at `offset` of `path` (in the program `result`) to
    `new_name`, in that program and in the `others` that see its declaration too (the other
    programs that include the declaring file: see `rename_scope`). Raises RenameError when the
    name cannot be renamed, or not in one of the programs."""
    doc = document(result, path)
    if doc is None:
        return None
    _, symbol = _renamable(doc, offset)
    if new_name in RESERVED:
        raise RenameError(f"`{new_name}` is a keyword of golog++")
    if not _IDENTIFIER.match(new_name):
        raise RenameError(f"`{new_name}` is not a valid name (a letter, then letters, digits or '_')")
    places = [(doc, symbol)]
    if symbol.kind not in LOCAL_KINDS:
        declared = rename_scope(result, path, offset)
        if declared is not None:
            places += [found for other in others if (found := _same_declaration(other, *declared)) is not None]
    changes: dict[str, list[types.TextEdit]] = {}
    done: set[tuple[str, int, int]] = set()
    for place_doc, place_symbol in places:
        refs = place_doc.model.references_to(place_symbol)
        if new_name != place_symbol.name:
            _check_clash(place_doc, place_symbol, refs, new_name)
        for ref in _sorted(place_doc.result, refs):
            p = path_of(place_doc.result, ref.span.source)
            if p is None or (str(p), ref.span.start, ref.span.end) in done:
                continue
            done.add((str(p), ref.span.start, ref.span.end))
            changes.setdefault(p.as_uri(), []).append(types.TextEdit(range=lsp_range(ref.span), new_text=new_name))
    return types.WorkspaceEdit(changes=changes)


def rename_scope(result: CheckResult, path: Path, offset: int) -> tuple[Path, int] | None:
    """Where the symbol a rename at `offset` of `path` would rename is declared, (file,
    offset), when other programs can see it: a global declaration of a file of the program (a
    local one is seen only in its own declaration). None for a local symbol. Raises
    RenameError as `rename` does for a name that cannot be renamed."""
    doc = document(result, path)
    if doc is None:
        return None
    _, symbol = _renamable(doc, offset)
    span = symbol.span
    declaring = None if span is None else path_of(result, span.source)
    if symbol.kind in LOCAL_KINDS or span is None or declaring is None:
        return None
    return declaring, span.start


def _same_declaration(other: CheckResult, declaring: Path, start: int) -> tuple[Document, Symbol] | None:
    """The symbol declared at `start` of the file `declaring` in another program, with that
    file; None when the program does not contain the file. RenameError when the program has a
    syntax error (a use of the name there could be missed) or sees no declaration there."""
    doc = document(other, declaring)
    if doc is None:
        return None
    program = other.loaded.roots[0].name if other.loaded.roots else "a program"
    broken = next((d for d in other.loaded.diagnostics if d.is_error), None)
    if broken is not None:
        where = f"{Path(broken.span.source.path).name}:{broken.span.line}"
        raise RenameError(
            f"`{program}` also includes `{declaring.name}` and has a syntax error at {where}: "
            "fix it first, or the rename could miss a use there"
        )
    ref = doc.model.reference_at(doc.source, start)
    if ref is None or not ref.declaration or ref.symbol.span is None or ref.symbol.span.start != start:
        raise RenameError(f"`{program}` also includes `{declaring.name}` but does not see the same declaration there")
    return doc, ref.symbol


def _renamable(doc: Document, offset: int) -> tuple[Reference, Symbol]:
    ref = doc.model.reference_at(doc.source, offset)
    if ref is None:
        token = next((t for t in doc.file.tokens if t.start <= offset <= t.end and t.type in KEYWORD_TYPES), None)
        if token is not None:
            word = token.value.rstrip(": \t\r\n")
            raise RenameError(f"`{word}` is a keyword of golog++ and cannot be renamed")
        raise RenameError("there is no name to rename here")
    symbol = ref.symbol
    if symbol.predefined or symbol.span is None or symbol.kind is SymbolKind.BUILTIN_TYPE:
        raise RenameError(f"`{symbol.name}` is predefined and cannot be renamed")
    stdlib = stdlib_sources(doc.result)
    for r in doc.model.references_to(symbol):
        if id(r.span.source) in stdlib:
            raise RenameError(f"`{symbol.name}` is defined in the standard library and cannot be renamed")
    return ref, symbol


def _check_clash(doc: Document, symbol: Symbol, refs: list[Reference], new_name: str) -> None:
    model = doc.model
    if symbol.kind in LOCAL_KINDS:
        spots = [r.span for r in refs]
    else:
        existing = model.lookup(new_name)
        if existing is not None and existing is not symbol:
            raise RenameError(f"`{new_name}` is already declared as {existing.kind.article} {existing.kind.value}")
        spots = [r.span for r in refs if not r.declaration]
    owner = symbol.owner
    if owner is not None:
        siblings = [*owner.params, *owner.members.values()]
        clash = next((s for s in siblings if s.name == new_name and s is not symbol), None)
        if clash is not None:
            raise RenameError(f"`{owner.name}` already has a {clash.kind.value} named `{new_name}`")
    for span in spots:
        other = _visible(doc, span, new_name)
        if other is not None and other is not symbol:
            what = f"{other.kind.value} `{new_name}`"
            raise RenameError(f"renaming to `{new_name}` would clash with the {what} visible at {_at(doc, span)}")
    if symbol.kind in LOCAL_KINDS:
        # A use of another symbol of the new name inside the local's scope would now mean the
        # local (unless it is a variable of an inner scope, which shadows the local).
        for scope in model.scopes:
            if symbol not in scope.symbols:
                continue
            for r in model.references_in(scope.span.source):
                inner = r.symbol.span is not None and scope.span.contains(r.symbol.span.start)
                if scope.span.contains(r.span.start) and r.symbol.name == new_name and not inner:
                    what = f"{r.symbol.kind.value} `{new_name}`"
                    raise RenameError(f"renaming to `{new_name}` would hide the {what} used at {_at(doc, r.span)}")


def _at(doc: Document, span: Span) -> str:
    """Where `span` is, for a message: its line, and its file when that is another one."""
    return f"line {span.line}" if span.source is doc.source else f"{Path(span.source.path).name}:{span.line}"


def _visible(doc: Document, span: Span, name: str) -> Symbol | None:
    for s in doc.model.visible_at(span.source, span.start):
        if s.name == name and s.kind in LOCAL_KINDS:
            return s
    return None
