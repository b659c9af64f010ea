"""What the editor features share: finding the document in a checked program, turning spans
into LSP ranges and locations, the comments of a file (which the syntax tree leaves out), and
the doc comment of a declaration."""

from __future__ import annotations

import re
import weakref
from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass
from operator import attrgetter
from pathlib import Path

from lsprotocol import types

from gpp.base.resources import stdlib_dir
from gpp.base.source import Source, Span
from gpp.check import CheckResult
from gpp.model.model import Model
from gpp.model.symbols import Symbol, SymbolKind
from gpp.syntax import ast
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, SECTION_WORDS
from gpp.syntax.loader import ParsedFile
from lsp.ranges import lsp_range


@dataclass(frozen=True, slots=True)
class Document:
    """One file of a checked program, with the model that covers it."""

    result: CheckResult
    file: ParsedFile

    @property
    def model(self) -> Model:
        return self.result.model

    @property
    def source(self) -> Source:
        return self.file.source

    @property
    def text(self) -> str:
        return self.file.source.text


def document(result: CheckResult, path: Path) -> Document | None:
    """The file `path` of `result`, or None when the program does not contain it."""
    for f in result.loaded.files:
        if f.path == path:
            return Document(result, f)
    try:
        f2 = result.loaded.file(path)
    except (OSError, ValueError, RuntimeError):
        return None
    return None if f2 is None else Document(result, f2)


def path_of(result: CheckResult, source: Source) -> Path | None:
    for f in result.loaded.files:
        if f.source is source:
            return f.path
    return None


def uri_of(result: CheckResult, source: Source) -> str | None:
    p = path_of(result, source)
    return None if p is None else p.as_uri()


def location(result: CheckResult, span: Span) -> types.Location | None:
    uri = uri_of(result, span.source)
    return None if uri is None else types.Location(uri=uri, range=lsp_range(span))


def in_stdlib(path: Path) -> bool:
    try:
        return path.is_relative_to(stdlib_dir().resolve())
    except (OSError, RuntimeError):
        return False


def stdlib_sources(result: CheckResult) -> set[int]:
    """The ids of the Sources of the program's standard library files."""
    return {id(f.source) for f in result.loaded.files if in_stdlib(f.path)}


def included_at(doc: Document, offset: int) -> ParsedFile | None:
    """The file that the `#include` under the cursor loads (found as the loader finds it)."""
    for decl in doc.file.program.declarations:
        if isinstance(decl, ast.Include) and decl.span.contains(offset):
            name = decl.path.value
            for candidate in (doc.file.path.parent / name, stdlib_dir() / name):
                try:
                    resolved = candidate.resolve()
                except (OSError, RuntimeError, ValueError):
                    continue
                found = next((f for f in doc.result.loaded.files if f.path == resolved), None)
                if found is not None:
                    return found
    return None


# ---------------------------------------------------------------- comments


def comments(file: ParsedFile) -> list[tuple[int, int]]:
    """The comments of a file as (start, end) offsets, in order. They lie in the gaps between
    tokens, the only places the tokenizer skips: each `//` or `/*` of the text that is in a gap
    (found by bisection among the tokens) and not in an earlier comment begins one, which ends
    at the end of its line (`//`) or after its `*/`, and at the latest where the gap does."""
    text = file.source.text
    tokens = file.tokens
    out: list[tuple[int, int]] = []
    at = 0  # where to look for the next one (after the last comment: `/*/*//` has `//` at 4)
    while (match := _COMMENT_START.search(text, at)) is not None:
        i = match.start()
        at = i + 1
        k = bisect_right(tokens, i, key=_start) - 1
        if k >= 0 and tokens[k].end > i:
            at = tokens[k].end
            continue  # in a token (a string, say)
        gap_end = tokens[k + 1].start if k + 1 < len(tokens) else len(text)
        if i + 2 > gap_end:
            continue
        if match.group() == "//":
            j = text.find("\n", i)
            j = gap_end if j < 0 or j > gap_end else j
        else:
            j = text.find("*/", i + 2)
            j = gap_end if j < 0 or j + 2 > gap_end else j + 2
        out.append((i, j))
        at = j
    return out


_COMMENT_START = re.compile(r"//|/\*")
_start = attrgetter("start")


def comments_alone(file: ParsedFile) -> list[tuple[int, int]]:
    """The comments that begin their line (no code before them)."""
    source = file.source
    out: list[tuple[int, int]] = []
    for start, end in comments(file):
        line, col = source.line_col(start)
        if not source.line_text(line)[: col - 1].strip():
            out.append((start, end))
    return out


class DocComments:
    """Finds the doc comments of declarations: the comments that stand alone on their lines,
    by the line they end on. One per checked program (`memo(result).docs`), so that each file
    is scanned once."""

    def __init__(self, result: CheckResult) -> None:
        # (Not the result itself: the memo that keeps this must not keep the result alive.)
        self.program_files = result.loaded.files
        self.files: dict[int, dict[int, tuple[int, int]]] = {}

    def of(self, symbol: Symbol) -> str:
        """The `//` lines directly above the symbol's declaration (or a forward declaration),
        or a `/* */` comment ending on the line above; '' when there is none."""
        decl = symbol.decl
        starts: list[Span] = []
        if isinstance(decl, ast.Decl):
            starts.append(Span(decl.span.source, decl.span.start, decl.span.start))
        starts.extend(symbol.other_spans)
        for at in starts:
            text = self._above(at.source, at.start)
            if text:
                return text
        return ""

    def _alone(self, source: Source) -> dict[int, tuple[int, int]]:
        found = self.files.get(id(source))
        if found is None:
            pf = next((f for f in self.program_files if f.source is source), None)
            alone = comments_alone(pf) if pf is not None else []
            found = {source.line_col(max(start, end - 1))[0]: (start, end) for start, end in alone}
            self.files[id(source)] = found
        return found

    def _above(self, source: Source, offset: int) -> str:
        alone = self._alone(source)
        lines: list[str] = []
        current = source.line_col(offset)[0] - 1
        while current in alone:
            start, end = alone[current]
            body = source.text[start:end]
            if not body.startswith("//"):
                lines[0:0] = [_strip_line(s.strip().lstrip("*")) for s in body[2:-2].splitlines()]
                break
            lines.insert(0, _strip_line(body[2:]))
            current -= 1
        return "\n".join(lines).strip("\n")


def header_comment(file: ParsedFile) -> str:
    """The comment lines a file begins with."""
    source = file.source
    lines: list[str] = []
    for start, end in comments_alone(file):
        if source.line_col(start)[0] != len(lines) + 1 or not source.text.startswith("//", start):
            break
        lines.append(_strip_line(source.text[start + 2 : end]))
    return "\n".join(lines).strip("\n")


def doc_comment(result: CheckResult, symbol: Symbol) -> str:
    return memo(result).docs.of(symbol)


# ---------------------------------------------------------------- what requests reuse


class Memo:
    """What the features derive from one checked program and may reuse for the next request
    on it (the language server answers many requests from one check): the comments of its
    files, their doc comments, completion items. Kept while the check lives (see `memo`); it
    holds nothing that keeps the check alive."""

    def __init__(self, result: CheckResult) -> None:
        self.docs = DocComments(result)
        self._comments: dict[int, tuple[ParsedFile, list[tuple[int, int]]]] = {}
        self._items: dict[tuple[int, str], tuple[object, types.CompletionItem]] = {}

    def comments(self, file: ParsedFile) -> list[tuple[int, int]]:
        """`comments(file)`, scanned once."""
        known = self._comments.get(id(file.source))
        if known is None or known[0] is not file:
            known = self._comments[id(file.source)] = (file, comments(file))
        return known[1]

    def item(self, of: object, variant: str, make: Callable[[], types.CompletionItem]) -> types.CompletionItem:
        """The completion item `make()` builds for `of` (a symbol of the program) and `variant`
        (its rank in the list), built once. The item is shared: nobody changes it."""
        known = self._items.get((id(of), variant))
        if known is None or known[0] is not of:
            known = self._items[(id(of), variant)] = (of, make())
        return known[1]


# By the id of the check. (No lock: a dictionary's get, set and pop are atomic, and a lock
# would deadlock when a collection on the thread that holds it runs `forget`.)
_memos: dict[int, tuple[weakref.ref[CheckResult], Memo]] = {}


def memo(result: CheckResult) -> Memo:
    """The Memo of a checked program, forgotten when the program's check is."""
    key = id(result)
    known = _memos.get(key)
    if known is not None and known[0]() is result:
        return known[1]

    def forget(_: object, key: int = key) -> None:
        _memos.pop(key, None)

    made = Memo(result)
    _memos[key] = (weakref.ref(result, forget), made)
    return made


def _strip_line(s: str) -> str:
    return s[1:].rstrip() if s.startswith(" ") else s.rstrip()


# ---------------------------------------------------------------- kinds

COMPLETION_KIND: dict[SymbolKind, types.CompletionItemKind] = {
    SymbolKind.DOMAIN: types.CompletionItemKind.Enum,
    SymbolKind.COMPOUND: types.CompletionItemKind.Struct,
    SymbolKind.BUILTIN_TYPE: types.CompletionItemKind.Keyword,
    SymbolKind.FLUENT: types.CompletionItemKind.Property,
    SymbolKind.ACTION: types.CompletionItemKind.Event,
    SymbolKind.EXOG_ACTION: types.CompletionItemKind.Event,
    SymbolKind.FUNCTION: types.CompletionItemKind.Function,
    SymbolKind.EXOG_FUNCTION: types.CompletionItemKind.Function,
    SymbolKind.PROCEDURE: types.CompletionItemKind.Method,
    SymbolKind.COMPONENT: types.CompletionItemKind.Module,
    SymbolKind.PARAMETER: types.CompletionItemKind.Variable,
    SymbolKind.VARIABLE: types.CompletionItemKind.Variable,
    SymbolKind.SYMBOL: types.CompletionItemKind.EnumMember,
    SymbolKind.FIELD: types.CompletionItemKind.Field,
    SymbolKind.CLOCK: types.CompletionItemKind.Constant,
    SymbolKind.STATE: types.CompletionItemKind.EnumMember,
}

SYMBOL_KIND: dict[SymbolKind, types.SymbolKind] = {
    SymbolKind.DOMAIN: types.SymbolKind.Enum,
    SymbolKind.COMPOUND: types.SymbolKind.Struct,
    SymbolKind.BUILTIN_TYPE: types.SymbolKind.TypeParameter,
    SymbolKind.FLUENT: types.SymbolKind.Property,
    SymbolKind.ACTION: types.SymbolKind.Event,
    SymbolKind.EXOG_ACTION: types.SymbolKind.Event,
    SymbolKind.FUNCTION: types.SymbolKind.Function,
    SymbolKind.EXOG_FUNCTION: types.SymbolKind.Function,
    SymbolKind.PROCEDURE: types.SymbolKind.Method,
    SymbolKind.COMPONENT: types.SymbolKind.Module,
    SymbolKind.PARAMETER: types.SymbolKind.Variable,
    SymbolKind.VARIABLE: types.SymbolKind.Variable,
    SymbolKind.SYMBOL: types.SymbolKind.EnumMember,
    SymbolKind.FIELD: types.SymbolKind.Field,
    SymbolKind.CLOCK: types.SymbolKind.Constant,
    SymbolKind.STATE: types.SymbolKind.EnumMember,
}

LOCAL_KINDS = frozenset({SymbolKind.PARAMETER, SymbolKind.VARIABLE})

# The token types of keywords (in every context) and of `#include`.
KEYWORD_TYPES = (
    frozenset(KEYWORDS.values())
    | frozenset(PLATFORM_KEYWORDS.values())
    | frozenset(SECTION_WORDS.values())
    | {"INCLUDE"}
)
