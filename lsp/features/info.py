"""Hover, signature help and inlay hints: what the model knows about a symbol, shown where
the cursor is."""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types

from gpp import codes
from gpp.base.source import Span
from gpp.check import CheckResult
from gpp.check.suppress import suppressed_code_at
from gpp.model.model import Model
from gpp.model.symbols import GLOBAL_KINDS, Symbol, SymbolKind
from gpp.model.types import DomainType, Sym, show_value
from gpp.syntax import ast
from gpp.syntax.printer import format_expr
from gpp.syntax.walk import walk
from lsp.features.common import LOCAL_KINDS, doc_comment, document, header_comment, included_at
from lsp.features.context import context_at
from lsp.ranges import lsp_range, position

# The language of code blocks in hover and completion documentation.
CODE_LANGUAGE = "gpp"
# At most this many initial values and domain elements are listed in a hover.
_LISTED = 20
# Symbol.signature() shows this many elements of a domain; a hover lists more.
_IN_SIGNATURE = 12


def hover(result: CheckResult, path: Path, offset: int) -> types.Hover | None:
    doc = document(result, path)
    if doc is None:
        return None
    ref = doc.model.reference_at(doc.source, offset)
    if ref is None:
        section = _action_section_at(doc.file.program, offset)
        if section is not None:
            word = ast.SECTION_KINDS[type(section)]
            text = f"`{word.value}:` {_SECTION_DOCS[word]}"
            markdown = types.MarkupContent(kind=types.MarkupKind.Markdown, value=text)
            return types.Hover(contents=markdown, range=lsp_range(section.keyword))
        allowed = suppressed_code_at(doc.source, offset)
        if allowed is not None:
            return _explain(*allowed)
        included = included_at(doc, offset)
        if included is None:
            return None
        # An `#include`: the file it loads, and what the file says about itself.
        header = header_comment(included)
        text = f"`{included.path}`" + (f"\n\n{header}" if header else "")
        return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))
    return types.Hover(
        contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=describe(result, ref.symbol)),
        range=lsp_range(ref.span),
    )


# What each section of an action does, for a hover on its keyword (docs/language.md says more).
_SECTION_DOCS = {
    ast.SectionKind.PRECONDITION: "the condition under which the action can start.",
    ast.SectionKind.EFFECT: "assignments applied when the action's activity ends `final`, evaluated "
    "together in the state at its end.",
    ast.SectionKind.START_EFFECT: "assignments applied when the action's activity starts, evaluated "
    "together in the state its precondition held in; they stay if the activity fails or is cancelled, "
    "and its `effect:` sees them.",
    ast.SectionKind.SENSES: "sets a fluent from the action's result when its activity ends `final`.",
    ast.SectionKind.MAPPING: "the name and arguments the platform knows the action by.",
    ast.SectionKind.SILENT: "`true`: console views leave the action's records out.",
    ast.SectionKind.DURATION: "`[min, max]` in seconds: how long the activity takes on the dummy platform.",
}


def _action_section_at(program: ast.Program, offset: int) -> ast.ActionSection | None:
    """The section of an action whose keyword (`start_effect:`, ...) is at `offset`."""
    for decl in program.declarations:
        if isinstance(decl, ast.ActionDecl) and decl.span.contains(offset):
            return next((s for s in decl.sections or () if s.keyword.contains(offset)), None)
    return None


def _explain(span: Span, written: str) -> types.Hover | None:
    """A code or lint name in a `// gpp: allow` comment: its summary and the explanation that
    `gpp explain` prints (the same file, gpp/codes/explain/CODE.md)."""
    info = codes.lookup(written)
    if info is None:
        return None
    text = f"**{info.code}** `{info.name}`: {info.summary}"
    if info.explanation:
        text += "\n\n" + info.explanation
    return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text), range=lsp_range(span))


def describe(result: CheckResult, symbol: Symbol) -> str:
    """Markdown: the signature in a code block, what the symbol belongs to, its doc comment,
    a fluent's initial values, a domain's elements."""
    parts = [f"```{CODE_LANGUAGE}\n{symbol.signature()}\n```"]
    note = _belongs_to(result.model, symbol)
    if note:
        parts.append(note)
    text = doc_comment(result, symbol)
    if text:
        parts.append(text)
    if symbol.kind is SymbolKind.FLUENT and isinstance(symbol.decl, ast.FluentDecl):
        lines = [_initial(v) for v in symbol.decl.initially or ()]
        if lines:
            extra = [f"// ... {len(lines) - _LISTED} more"] if len(lines) > _LISTED else []
            body = "\n".join(lines[:_LISTED] + extra)
            parts.append(f"Initially:\n```{CODE_LANGUAGE}\n{body}\n```")
    if symbol.kind is SymbolKind.DOMAIN and isinstance(symbol.type, DomainType):
        values = symbol.type.values
        if len(values) > _IN_SIGNATURE:
            shown = ", ".join(show_value(v) for v in values[: _LISTED * 5])
            more = ", ..." if len(values) > _LISTED * 5 else ""
            parts.append(f"{len(values)} elements: `{{{shown}{more}}}`")
    return "\n\n".join(parts)


def _initial(v: ast.InitialValue) -> str:
    return f"({', '.join(format_expr(a) for a in v.args)}) = {format_expr(v.value)};"


def _belongs_to(model: Model, symbol: Symbol) -> str:
    if symbol.kind is SymbolKind.PARAMETER and symbol.owner is not None:
        return f"parameter of {symbol.owner.kind.value} `{symbol.owner.name}`"
    if symbol.kind is SymbolKind.VARIABLE:
        what = "quantified" if isinstance(symbol.decl, ast.Quantified) else "pick"
        return f"{what} variable"
    if symbol.kind is SymbolKind.SYMBOL:
        domains = [
            f"`{s.name}`"
            for s in model.types.values()
            if isinstance(s.type, DomainType) and Sym(symbol.name) in s.type.values
        ]
        return "element of " + ", ".join(domains) if domains else ""
    if symbol.kind in (SymbolKind.FIELD, SymbolKind.STATE, SymbolKind.CLOCK) and symbol.owner is not None:
        return f"{symbol.kind.value} of `{symbol.owner.name}`"
    return ""


# ---------------------------------------------------------------- signature help

# What a call can name (a component is a global too, but not callable).
_CALLABLE = GLOBAL_KINDS - {SymbolKind.COMPONENT}


# Characters after which an editor should show signature help (and update it).
SIGNATURE_TRIGGER_CHARACTERS = ["(", ","]


def signature_help(result: CheckResult, path: Path, offset: int) -> types.SignatureHelp | None:
    doc = document(result, path)
    if doc is None:
        return None
    offset = max(0, min(offset, len(doc.text)))
    ctx = context_at(doc.file.tokens, offset)
    for call in reversed(ctx.calls):
        name = call.name or ctx.decl_name
        symbol = doc.model.globals.get(name)
        if symbol is None or symbol.kind not in _CALLABLE:
            continue
        return types.SignatureHelp(
            signatures=[signature_information(result, symbol)],
            active_signature=0,
            active_parameter=call.argument,
        )
    return None


def signature_information(result: CheckResult, symbol: Symbol) -> types.SignatureInformation:
    label = symbol.signature()
    at = label.find(f"{symbol.name}(") + len(symbol.name) + 1
    params: list[types.ParameterInformation] = []
    for p in symbol.params:
        text = f"{p.type} {p.name}"
        start = _utf16(label[:at])
        params.append(types.ParameterInformation(label=(start, start + _utf16(text))))
        at += len(text) + 2
    text = doc_comment(result, symbol)
    documentation = types.MarkupContent(kind=types.MarkupKind.Markdown, value=text) if text else None
    return types.SignatureInformation(label=label, parameters=params, documentation=documentation)


def _utf16(s: str) -> int:
    return len(s.encode("utf-16-le")) // 2


# ---------------------------------------------------------------- inlay hints


def inlay_hints(result: CheckResult, path: Path, start: int, end: int) -> list[types.InlayHint]:
    """Parameter names before the arguments of calls in [start, end], except where the
    argument is a variable of the parameter's name."""
    doc = document(result, path)
    if doc is None:
        return []
    model = doc.model
    out: list[types.InlayHint] = []
    for node in walk(doc.file.program):
        if node.span.end < start or node.span.start > end:
            continue
        symbol: Symbol | None = None
        args: tuple[ast.Expr, ...] = ()
        if isinstance(node, ast.Call):
            symbol, args = model.target(node), node.args
        elif isinstance(node, ast.GroundAction):
            symbol, args = model.target(node.name), node.args
        if symbol is None or not args:
            continue
        for arg, param in zip(args, symbol.params, strict=False):
            named = model.target(arg) if isinstance(arg, ast.Name) else None
            if named is not None and named.kind in LOCAL_KINDS and named.name == param.name:
                continue
            if isinstance(arg, ast.Wildcard) or not (start <= arg.span.start <= end):
                continue
            out.append(
                types.InlayHint(
                    position=position(doc.source, arg.span.start),
                    label=f"{param.name}:",
                    kind=types.InlayHintKind.Parameter,
                    padding_right=True,
                )
            )
    return out
