"""Context-aware completion.

What fits where the cursor is comes from the token stream (lsp.features.context), so that it
works inside a half-typed statement; what the names are comes from the model: actions and
procedures where a statement starts, fluents and functions in expressions, the elements of a
domain first where a value of that domain is expected, parameters and `pick`/quantifier
variables in scope, keywords, and declaration snippets at the top level.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from pathlib import Path

from lsprotocol import types

from gpp.base.resources import stdlib_dir
from gpp.check import CheckResult
from gpp.model.model import Model
from gpp.model.symbols import EXPRESSION_CALLABLE, STATEMENT_CALLABLE, Symbol, SymbolKind
from gpp.model.types import CompoundType, DomainType, ListType, Sym, Type, show_value
from gpp.syntax.incremental import changed_stretch
from gpp.syntax.lexer import Token
from lsp.features.common import COMPLETION_KIND, LOCAL_KINDS, Document, document, memo
from lsp.features.context import OPERAND_ENDS, Binder, Context, Position, context_at, opening
from lsp.features.info import CODE_LANGUAGE
from lsp.ranges import position

# Characters after which an editor should ask for completion without being told: a field
# after '.', an argument after '(' or ',', an include path after '"' or '/'.
COMPLETION_TRIGGER_CHARACTERS = [".", "(", ",", '"', "/"]

# Declaration snippets offered at the top level (label, detail, snippet).
DECLARATION_SNIPPETS: list[tuple[str, str, str]] = [
    ("procedure", "procedure declaration", "procedure ${1:name}($2) {\n\t$0\n}"),
    ("action", "action declaration", "action ${1:name}($2) {\nprecondition:\n\t${0:true}\n}"),
    ("exog_action", "exogenous action declaration", "exog_action ${1:name}($2) {\n\t$0\n}"),
    ("fluent", "fluent declaration", "${1:bool} fluent ${2:name}($3) {\ninitially:\n\t($4) = ${5:false};\n}"),
    ("function", "function declaration", "${1:bool} function ${2:name}($3) =\n\t${0:true}"),
    ("exog_function", "exogenous function declaration", "${1:number} exog_function ${2:name}($3);"),
    ("domain", "symbol domain declaration", "symbol domain ${1:name} = {${2:a, b}}"),
    ("compound", "compound type declaration", "compound ${1:Name} {\n\t${2:number} ${3:field}\n}"),
    ("main", "the main procedure", "procedure main() {\n\t$0\n}"),
    ("#include", "include a file", '#include "${1:file.gpp}"'),
]
TYPE_KEYWORDS = ["bool", "number", "string", "symbol", "void", "list"]
STATEMENT_KEYWORDS = [
    "if",
    "while",
    "test",
    "choose",
    "pick",
    "concurrent",
    "search",
    "solve",
    "during",
    "start",
    "end",
    "finish",
    "fail",
    "cancel",
    "push_back",
    "push_front",
    "pop_back",
    "pop_front",
]
EXPRESSION_KEYWORDS = ["true", "false", "null", "exists", "forall", "if", "length", "to_string"]
CONSTRAINT_KEYWORDS = ["state", "during", "start", "end", "finish", "fail", "cancel", "next", "previous", "future"]
CONSTRAINT_KEYWORDS += ["past", "until", "since"]
ACTION_SECTIONS = ["precondition", "effect", "start_effect", "senses", "mapping", "silent", "duration"]

_EXPECTED, _LOCAL, _GLOBAL, _KEYWORD = "0", "1", "2", "3"


def completion(result: CheckResult, path: Path, offset: int) -> list[types.CompletionItem]:
    return _complete(result, path, offset, "")[0]


def _complete(result: CheckResult, path: Path, offset: int, word: str) -> tuple[list[types.CompletionItem], bool]:
    """The items that fit at `offset`, only those holding `word` (its letters in order, see `_holder`), and whether
    any were left out for it."""
    doc = document(result, path)
    if doc is None:
        return [], False
    offset = max(0, min(offset, len(doc.text)))
    if any(start < offset <= end for start, end in memo(result).comments(doc.file)):
        return [], False
    ctx = context_at(doc.file.tokens, offset)
    completer = _Completer(doc, ctx, offset, word)
    items = completer.items()
    return items, completer.left_out


def completion_list(result: CheckResult, path: Path, offset: int) -> types.CompletionList:
    """`completion` as the language server answers it: only the items whose label holds the
    word typed before the cursor, its letters in order (what every editor's filter keeps), so
    that a large program's hundreds of names are not sent on every keystroke. When some were
    left out, the list says it is incomplete: the editor asks again as the word changes."""
    doc = document(result, path)
    word = typed_word(doc.text, offset) if doc is not None else ""
    items, left_out = _complete(result, path, offset, word)
    return types.CompletionList(is_incomplete=left_out, items=items)


def completion_after_edit(result: CheckResult, path: Path, text: str, offset: int) -> types.CompletionList | None:
    """Completion at `offset` in `text`, the document as it is now, from `result`, a check of
    it before its latest edits (the check of `text` is still running: an editor asks for
    completion as soon as a character is typed). This answers when what changed since the
    check is a part of the word before the cursor (letters typed or deleted) or lies after
    the cursor: what fits there is taken from the checked program at the same place, and
    filtered with the word typed in `text`; the list is marked incomplete, so that the editor
    asks again at the next keystroke. Otherwise (brackets typed, a line pasted, ...: the
    place may have changed) None: the caller waits for the current check."""
    doc = document(result, path)
    if doc is None:
        return None
    checked = doc.text
    offset = max(0, min(offset, len(text)))
    start, checked_end, now_end = changed_stretch(checked, text)
    word = typed_word(text, offset)
    if start >= offset:
        at = offset  # the text before the cursor is as checked
    elif start >= offset - len(word) and now_end <= offset and _is_name_part(checked[start:checked_end]):
        at = start  # in the word being typed: where it was checked
    else:
        return None
    items, _ = _complete(result, path, at, word)
    if any(i.text_edit is not None for i in items):
        return None  # (their ranges are positions in the checked text)
    return types.CompletionList(is_incomplete=True, items=items)


def _is_name_part(text: str) -> bool:
    return all(c.isalnum() or c == "_" for c in text)


def typed_word(text: str, offset: int) -> str:
    """The name typed before `offset` (letters, digits and `_`, not starting with a digit)."""
    offset = max(0, min(offset, len(text)))
    start = offset
    while start > 0 and (text[start - 1].isalnum() or text[start - 1] == "_"):
        start -= 1
    while start < offset and text[start].isdigit():
        start += 1
    return text[start:offset]


@functools.lru_cache(maxsize=64)
def _holder(word: str) -> Callable[[str], re.Match[str] | None]:
    """A search for the letters of `word` in order, ignoring case (`co` finds `sCOre`)."""
    return re.compile(".*?".join(re.escape(c) for c in word), re.IGNORECASE | re.DOTALL).search


class _Completer:
    def __init__(self, doc: Document, ctx: Context, offset: int, word: str = "") -> None:
        self.doc = doc
        # Only the items holding `word` are kept; `left_out` says whether any were not.
        self.word = word
        self.holds = _holder(word)
        self.left_out = False
        self.model: Model = doc.model
        self.ctx = ctx
        self.offset = offset
        self.out: dict[str, types.CompletionItem] = {}
        self.memo = memo(doc.result)

    def items(self) -> list[types.CompletionItem]:
        p = self.ctx.position
        if p is Position.TOP_LEVEL:
            self.snippets()
            self.types()
        elif p is Position.INCLUDE:
            self.include_paths()
        elif p is Position.TYPE:
            self.types()
        elif p is Position.FIELD:
            self.fields()
        elif p is Position.FIELD_INIT:
            self.literal_fields()
        elif p is Position.DOMAIN:
            for symbol in self.model.types.values():
                if symbol.kind is SymbolKind.DOMAIN:
                    self.symbol_item(symbol)
        elif p is Position.ELEMENT:
            self.elements(None)
        elif p is Position.COMPONENT_BODY:
            self.members(self.ctx.decl_name)
            self.sections(["clocks", "states", "transitions"])
            self.keywords(["resets"])
        elif p is Position.COMPONENT:
            self.globals({SymbolKind.COMPONENT})
        elif p is Position.STATE:
            self.members(self.ctx.component, {SymbolKind.STATE})
        elif p is Position.CONSTRAINT:
            self.keywords(CONSTRAINT_KEYWORDS)
        elif p is Position.AFTER_TYPE:
            self.keywords(["fluent", "function", "exog_function", "domain"])
        elif p is Position.SECTION:
            self.sections(ACTION_SECTIONS if self.in_action_body() else ["initially"])
        elif p is Position.STATEMENT:
            self.expected()
            self.locals()
            self.globals(STATEMENT_CALLABLE | {SymbolKind.FLUENT})
            if self.after_during_head():
                self.keywords(["until"])
            self.keywords(STATEMENT_KEYWORDS)
        elif p is Position.EFFECT:
            self.globals({SymbolKind.FLUENT})
            self.keywords(["if"])
        elif p is Position.ACTION:
            self.globals({SymbolKind.ACTION})
        elif p is Position.EXPRESSION:
            self.expected()
            self.locals()
            self.globals(EXPRESSION_CALLABLE)
            self.elements(None)
            self.keywords(EXPRESSION_KEYWORDS)
            if self.in_action_body() and self.after_operand():
                # A section's expression may be complete: the next section may start here.
                self.sections(ACTION_SECTIONS)
        return list(self.out.values())

    # ---------------------------------------------------------------- sources of items

    def add(self, item: types.CompletionItem, rank: str = _GLOBAL) -> None:
        # (The parser's recovery may invent a declaration without a name.)
        if item.label and item.label not in self.out:
            if self.word and not self.holds(item.filter_text or item.label):
                self.left_out = True
                return
            if item.sort_text is None:
                item.sort_text = f"{rank}{item.label}"
            self.out[item.label] = item

    def symbol_item(self, symbol: Symbol, rank: str = _GLOBAL) -> None:
        if self.word and not self.holds(symbol.name):
            self.left_out = True  # (not even looked up: a large program has thousands)
            return
        # Built once per checked program (the next request on it reuses the item).
        self.add(self.memo.item(symbol, rank, lambda: self._symbol_item(symbol, rank)), rank)

    def _symbol_item(self, symbol: Symbol, rank: str) -> types.CompletionItem:
        text = self.memo.docs.of(symbol)
        return types.CompletionItem(
            label=symbol.name,
            kind=COMPLETION_KIND[symbol.kind],
            detail=symbol.signature(),
            label_details=_label_details(symbol),
            documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text) if text else None,
            preselect=True if rank == _EXPECTED else None,
            sort_text=f"{rank}{symbol.name}",
        )

    def in_action_body(self) -> bool:
        return self.ctx.decl_keyword in ("action", "exog_action") and self.ctx.braces == 1

    def after_during_head(self) -> bool:
        """Is the cursor right after `during (..)`, where `until (..)` may come?"""
        tokens = self.doc.file.tokens
        i = self.ctx.previous_index
        if i < 0 or tokens[i].type != "RPAR":
            return False
        j = opening(tokens, i)
        return j is not None and j > 0 and tokens[j - 1].type == "DURING"

    def after_operand(self) -> bool:
        i = self.ctx.previous_index
        return i >= 0 and self.doc.file.tokens[i].type in OPERAND_ENDS

    def sections(self, words: list[str]) -> None:
        for w in words:
            self.add(_keyword_item(w, f"{w}:"), _KEYWORD)

    def keywords(self, words: list[str]) -> None:
        for w in words:
            self.add(_keyword_item(w, None), _KEYWORD)

    def snippets(self) -> None:
        for label, detail, body in DECLARATION_SNIPPETS:
            self.add(
                types.CompletionItem(
                    label=label,
                    kind=types.CompletionItemKind.Snippet,
                    detail=detail,
                    insert_text=body,
                    insert_text_format=types.InsertTextFormat.Snippet,
                    documentation=types.MarkupContent(
                        kind=types.MarkupKind.Markdown, value=f"```{CODE_LANGUAGE}\n{_plain(body)}\n```"
                    ),
                ),
                _KEYWORD,
            )

    def types(self) -> None:
        for symbol in self.model.types.values():
            if symbol.kind is not SymbolKind.BUILTIN_TYPE:
                self.symbol_item(symbol)
        self.keywords(TYPE_KEYWORDS)

    def globals(self, kinds: frozenset[SymbolKind] | set[SymbolKind]) -> None:
        for symbol in self.model.globals.values():
            if symbol.kind in kinds:
                self.symbol_item(symbol)

    def local_table(self) -> dict[str, Symbol | Binder]:
        """The variables in scope at the cursor: the model's, and those only the tokens show
        (in a statement the parser could not keep)."""
        known: dict[str, Symbol | Binder] = {}
        pending = {b.start for b in self.ctx.pending_binders}
        for s in self.model.visible_at(self.doc.source, self.offset):
            if s.kind in LOCAL_KINDS and (s.span is None or s.span.start not in pending):
                known[s.name] = s
        for b in self.ctx.binders:
            if b.name not in known or isinstance(known[b.name], Binder):
                known[b.name] = b
        return known

    def locals(self) -> None:
        for name, local in sorted(self.local_table().items()):
            self.local_item(name, local, _LOCAL)

    def local_item(self, name: str, local: Symbol | Binder, rank: str) -> None:
        if isinstance(local, Symbol):
            self.symbol_item(local, rank)
            return
        what = "parameter" if local.parameter else "variable"
        self.add(
            types.CompletionItem(
                label=name,
                kind=types.CompletionItemKind.Variable,
                detail=f"{local.type} {name}",
                documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=what),
                preselect=True if rank == _EXPECTED else None,
            ),
            rank,
        )

    def elements(self, domain: DomainType | None, rank: str = _GLOBAL) -> None:
        """The elements of `domain`, or every symbol of every domain."""
        if domain is None:
            for symbol in self.model.symbols.values():
                self.symbol_item(symbol, rank)
            return
        for v in domain.values:
            if isinstance(v, Sym):
                element = self.model.symbols.get(v.name)
                if element is not None:
                    self.symbol_item(element, rank)
            else:
                shown = show_value(v)
                self.add(
                    types.CompletionItem(
                        label=shown, kind=types.CompletionItemKind.Value, detail=f"element of {domain.name}"
                    ),
                    rank,
                )

    def fields(self) -> None:
        """The fields of the compound before the `.` (none if it is no compound), or of every
        compound when its type is not known."""
        subject = self.operand_type(self.doc.file.tokens, self.ctx.previous_index - 1)
        compounds = [subject] if subject is not None else [s.type for s in self.model.types.values()]
        for t in compounds:
            declaration = self.model.declaration(t) if isinstance(t, CompoundType) else None
            if declaration is not None:
                for member in declaration.members.values():
                    self.symbol_item(member)

    def include_paths(self) -> None:
        """The .gpp files an `#include` can name: beside the file (first) and in the standard
        library; the item replaces the path typed so far."""
        string = self.ctx.string
        if string is None:
            return
        source = self.doc.source
        closed = len(string.value) == string.end - string.start
        start, end = string.start + 1, string.end - 1 if closed else string.end
        if not start <= self.offset <= end:
            return
        edit_range = types.Range(start=position(source, start), end=position(source, end))
        for rank, folder in ((_LOCAL, self.doc.file.path.parent), (_GLOBAL, stdlib_dir())):
            for name in _gpp_files(folder):
                if folder / name != self.doc.file.path:
                    edit = types.TextEdit(range=edit_range, new_text=name)
                    self.add(types.CompletionItem(label=name, kind=types.CompletionItemKind.File, text_edit=edit), rank)

    def members(self, component: str, kinds: frozenset[SymbolKind] | set[SymbolKind] | None = None) -> None:
        """The states and clocks of a component (its implicit `error` state among them)."""
        symbol = self.model.globals.get(component)
        if symbol is not None and symbol.kind is SymbolKind.COMPONENT:
            for member in symbol.members.values():
                if kinds is None or member.kind in kinds:
                    self.symbol_item(member)

    def literal_fields(self) -> None:
        before = self.ctx.bracket_before
        compound = self.model.types.get(before.value) if before is not None else None
        if compound is not None:
            for member in compound.members.values():
                self.symbol_item(member)

    # ---------------------------------------------------------------- the expected type

    def expected(self) -> None:
        t = self.expected_type()
        if not isinstance(t, DomainType):
            return
        self.elements(t, _EXPECTED)
        # Variables whose values all fit.
        for name, local in self.local_table().items():
            local_type = local.type if isinstance(local, Symbol) else self.named_type(local.type)
            if isinstance(local_type, DomainType) and set(local_type.values) <= set(t.values):
                self.local_item(name, local, _EXPECTED)

    def expected_type(self) -> Type | None:
        """The type a value at the cursor should have: the parameter's type in a call's
        argument, the other side's type after `==`/`!=`, the fluent's type after `=`."""
        tokens = self.doc.file.tokens
        i = self.ctx.previous_index
        prev = tokens[i] if i >= 0 else None
        if prev is not None and (prev.type == "EQ" or (prev.type == "CMP_OP" and prev.value in ("==", "!="))):
            return self.operand_type(tokens, i - 1)
        before = self.ctx.bracket_before
        if before is not None and before.type == "IN" and prev is not None and prev.type in ("LBRACE", "COMMA"):
            # The values of `pick (T x in {...})`: of the pick variable's type.
            pick = self.ctx.pending_binders[-1] if self.ctx.pending_binders else None
            return self.named_type(pick.type) if pick is not None else None
        call = self.ctx.call
        if call is not None and (prev is None or prev.type in ("LPAR", "COMMA")):
            symbol = self.model.globals.get(call.name or self.ctx.decl_name)
            if symbol is not None and call.argument < len(symbol.params):
                return symbol.params[call.argument].type
        return None

    def operand_type(self, tokens: list[Token], i: int) -> Type | None:
        """The type of the operand that ends at tokens[i]: a name, a call `f(..)`, a field
        access `e.f` or an index `e[..]`."""
        if i < 0:
            return None
        t = tokens[i]
        if t.type == "NAME" and i > 0 and tokens[i - 1].type == "DOT":
            subject = self.operand_type(tokens, i - 2)
            return subject.fields.get(t.value) if isinstance(subject, CompoundType) else None
        if t.type == "NAME":
            for b in reversed(self.ctx.binders):
                if b.name == t.value:
                    return self.named_type(b.type)
            found = self.model.symbol_at(self.doc.source, t.end) or self.model.lookup(t.value)
            return found.type if found is not None and found.kind in LOCAL_KINDS | EXPRESSION_CALLABLE else None
        if t.type in ("RPAR", "RBRACKET"):
            j = opening(tokens, i)
            if j is None or j == 0:
                return None
            before = tokens[j - 1]
            if t.type == "RBRACKET":
                subject = self.operand_type(tokens, j - 1)
                return subject.element if isinstance(subject, ListType) else None
            symbol: Symbol | None = None
            if before.type == "NAME":
                symbol = self.model.globals.get(before.value)
            elif self.ctx.section == "initially" and before.type in ("INITIALLY", "SEMI"):
                symbol = self.model.globals.get(self.ctx.decl_name)
            return symbol.type if symbol is not None else None
        return None

    def named_type(self, name: str) -> Type | None:
        symbol = self.model.types.get(name)
        return symbol.type if symbol is not None else None


@functools.cache
def _keyword_item(word: str, insert_text: str | None) -> types.CompletionItem:
    """A keyword (or an action's section, inserted with its colon): built once, then shared
    by every answer (nobody changes it)."""
    return types.CompletionItem(
        label=word, kind=types.CompletionItemKind.Keyword, insert_text=insert_text, sort_text=f"{_KEYWORD}{word}"
    )


def _label_details(symbol: Symbol) -> types.CompletionItemLabelDetails:
    """Shown beside the name in the list: a callable's parameters, and what the symbol is."""
    params = f"({', '.join(f'{p.type} {p.name}' for p in symbol.params)})" if symbol.kind in _CALLABLE else None
    shown = symbol.type if symbol.kind in _TYPED else None
    return types.CompletionItemLabelDetails(detail=params, description=str(shown) if shown else symbol.kind.value)


_CALLABLE = EXPRESSION_CALLABLE | STATEMENT_CALLABLE | {SymbolKind.EXOG_ACTION}
# Kinds whose description in the list is their value type.
_TYPED = EXPRESSION_CALLABLE | LOCAL_KINDS | {SymbolKind.FIELD}


def _gpp_files(folder: Path, limit: int = 200) -> list[str]:
    """The .gpp files in `folder` and its subfolders (two levels), as relative paths."""
    found: list[str] = []
    try:
        for pattern in ("*.gpp", "*/*.gpp", "*/*/*.gpp"):
            found.extend(sorted(p.relative_to(folder).as_posix() for p in folder.glob(pattern)))
    except OSError:
        pass
    return found[:limit]


def _plain(snippet: str) -> str:
    """A snippet as the text it inserts with its default placeholders."""
    out: list[str] = []
    i = 0
    while i < len(snippet):
        c = snippet[i]
        if c == "$" and i + 1 < len(snippet):
            if snippet[i + 1] == "{":
                colon = snippet.find(":", i)
                close = snippet.find("}", i)
                out.append(snippet[colon + 1 : close] if 0 <= colon < close else "")
                i = close + 1
                continue
            j = i + 1
            while j < len(snippet) and snippet[j].isdigit():
                j += 1
            i = j
            continue
        out.append(c.replace("\t", "    "))
        i += 1
    return "".join(out)
