"""Semantic tokens: every name classified by what the model resolved it to, plus keywords,
literals and comments from the token stream.

The legend (indexes are what the encoded tokens refer to):

token types
    fluent, action, procedure   custom types (gpp kinds with no LSP equivalent); editors that do
                                not know them may map them to variable, function and function
    function                    functions and exogenous functions
    parameter                   parameters of actions, procedures, fluents and functions
    variable                    `pick` and quantifier variables
    enumMember                  elements of symbol domains, component states
    type                        domains and compound types
    property                    compound fields and component clocks
    namespace                   components
    keyword, string, number, comment  (`number`, `bool`, ... are keywords)
modifiers
    declaration                 the name where it is declared
    defaultLibrary              declared in the standard library, or predefined
    exogenous                   exogenous actions and functions (custom)
"""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types

from gpp.base.source import Source
from gpp.check import CheckResult
from gpp.model.symbols import Symbol, SymbolKind
from lsp.features.common import KEYWORD_TYPES, document, memo, stdlib_sources

TOKEN_TYPES = [
    "fluent",
    "action",
    "procedure",
    "function",
    "parameter",
    "variable",
    "enumMember",
    "type",
    "property",
    "namespace",
    "keyword",
    "string",
    "number",
    "comment",
]
TOKEN_MODIFIERS = ["declaration", "defaultLibrary", "exogenous"]
SEMANTIC_TOKENS_LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=TOKEN_MODIFIERS)

_TYPE = {name: i for i, name in enumerate(TOKEN_TYPES)}
_KIND_TYPE: dict[SymbolKind, int] = {
    SymbolKind.FLUENT: _TYPE["fluent"],
    SymbolKind.ACTION: _TYPE["action"],
    SymbolKind.EXOG_ACTION: _TYPE["action"],
    SymbolKind.PROCEDURE: _TYPE["procedure"],
    SymbolKind.FUNCTION: _TYPE["function"],
    SymbolKind.EXOG_FUNCTION: _TYPE["function"],
    SymbolKind.PARAMETER: _TYPE["parameter"],
    SymbolKind.VARIABLE: _TYPE["variable"],
    SymbolKind.SYMBOL: _TYPE["enumMember"],
    SymbolKind.STATE: _TYPE["enumMember"],
    SymbolKind.DOMAIN: _TYPE["type"],
    SymbolKind.COMPOUND: _TYPE["type"],
    SymbolKind.BUILTIN_TYPE: _TYPE["type"],
    SymbolKind.FIELD: _TYPE["property"],
    SymbolKind.CLOCK: _TYPE["property"],
    SymbolKind.COMPONENT: _TYPE["namespace"],
}
DECLARATION, DEFAULT_LIBRARY, EXOGENOUS = 1, 2, 4


def semantic_tokens(result: CheckResult, path: Path) -> list[int]:
    doc = document(result, path)
    if doc is None:
        return []
    source = doc.source
    found: list[tuple[int, int, int, int]] = []  # start, end, type, modifiers
    stdlib = stdlib_sources(result)
    for ref in doc.model.references_in(source):
        found.append((ref.span.start, ref.span.end, _KIND_TYPE[ref.symbol.kind], _modifiers(ref.symbol, stdlib)))
        if ref.declaration:
            start, end, t, m = found[-1]
            found[-1] = (start, end, t, m | DECLARATION)
    for tok in doc.file.tokens:
        if tok.type in KEYWORD_TYPES:
            word = len(tok.value) - len(tok.value.lstrip("#abcdefghijklmnopqrstuvwxyz_"))
            found.append((tok.start, tok.start + word, _TYPE["keyword"], 0))
        elif tok.type == "STRING":
            found.append((tok.start, tok.end, _TYPE["string"], 0))
        elif tok.type == "NUMBER":
            found.append((tok.start, tok.end, _TYPE["number"], 0))
    for start, end in memo(doc.result).comments(doc.file):
        found.append((start, end, _TYPE["comment"], 0))
    found.sort(key=lambda f: (f[0], -f[1]))
    return encode(source, found)


def _modifiers(symbol: Symbol, stdlib: set[int]) -> int:
    m = 0
    if symbol.kind in (SymbolKind.EXOG_ACTION, SymbolKind.EXOG_FUNCTION):
        m |= EXOGENOUS
    if (
        symbol.predefined
        or symbol.kind is SymbolKind.BUILTIN_TYPE
        or (symbol.span is not None and id(symbol.span.source) in stdlib)
    ):
        m |= DEFAULT_LIBRARY
    return m


def encode(source: Source, found: list[tuple[int, int, int, int]]) -> list[int]:
    """The LSP relative encoding of sorted tokens: overlapping ones after the first are left
    out, one that spans lines is cut at each line end, lengths count UTF-16 units."""
    text = source.text
    starts = source.line_starts
    data: list[int] = []
    last_line = last_char = 0
    covered = line = 0
    for start, end, t, m in found:
        if start < covered or end <= start:
            continue
        covered = end
        while start < end:
            # Tokens come in order: the line only moves forward.
            while line + 1 < len(starts) and starts[line + 1] <= start:
                line += 1
            line_end = text.find("\n", start, end)
            piece_end = end if line_end < 0 else line_end
            piece = text[start:piece_end].rstrip("\r")
            char = _utf16(text, starts[line], start)
            length = _utf16(piece, 0, len(piece))
            if length > 0:
                data += [line - last_line, char - last_char if line == last_line else char, length, t, m]
                last_line, last_char = line, char
            start = piece_end + 1 if line_end >= 0 else end
    return data


def _utf16(text: str, start: int, end: int) -> int:
    """How many UTF-16 units text[start:end] takes."""
    piece = text[start:end]
    return len(piece) if piece.isascii() else len(piece.encode("utf-16-le")) // 2
