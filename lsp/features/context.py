"""The cursor's context read from the token stream: which call's argument list it is in, which
local variables are in scope, what kind of position it is (declaration, statement,
expression, type). Completion and signature help work on half-typed code, where the parser's
recovery may have dropped the statement under the cursor; the tokens are all still there.

The scan runs over the tokens of the declaration around the cursor, up to the cursor, and
tracks the open brackets, the declaration's parameters and the `pick`/`exists`/`forall`
variables whose scope is still open.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

from gpp.syntax.lexer import Token

# Tokens that start a top-level declaration (at brace depth 0).
_DECL_KEYWORDS = {
    "ACTION": "action",
    "EXOG_ACTION": "exog_action",
    "FLUENT": "fluent",
    "FUNCTION": "function",
    "EXOG_FUNCTION": "exog_function",
    "PROCEDURE": "procedure",
    "DOMAIN": "domain",
    "COMPOUND": "compound",
    "COMPONENT": "component",
    "CONSTRAINTS": "constraints",
    "INCLUDE": "include",
    "MAIN_LBRACE": "main",
}
# Tokens after which an operand is complete: a name after one starts something new.
OPERAND_ENDS = frozenset({"NAME", "RPAR", "RBRACKET", "NUMBER", "STRING", "TRUE", "FALSE", "NULL", "RBRACE"})
_OPENERS = {"LPAR": "RPAR", "LBRACE": "RBRACE", "MAIN_LBRACE": "RBRACE", "LBRACKET": "RBRACKET"}
_STATEMENT_HEADS = frozenset({"IF", "WHILE", "PICK", "SOLVE", "DURING", "UNTIL"})
_HAS_PARAMETERS = frozenset({"action", "exog_action", "fluent", "function", "exog_function", "procedure"})
_SECTIONS = frozenset(
    {"INITIALLY", "PRECONDITION", "EFFECT", "START_EFFECT", "SENSES", "MAPPING", "SILENT", "DURATION"}
)


class Position(Enum):
    TOP_LEVEL = "top level"  # where a declaration may start
    STATEMENT = "statement"  # where a statement may start
    EFFECT = "effect"  # where an effect may start (its target is a fluent)
    SECTION = "section"  # inside an action's braces, where a section keyword may come
    EXPRESSION = "expression"
    ACTION = "action"  # the action of `start(`, `end(`, ..., `during (`
    TYPE = "type"  # where a type name is expected (parameters, pick and quantifier variables)
    NAME = "name"  # where a new name is being declared
    FIELD = "field"  # after `.`
    FIELD_INIT = "field initialiser"  # a field's name in a compound literal `Pose{x = 1, ...}`
    DOMAIN = "domain"  # a domain's name in a domain's definition
    ELEMENT = "element"  # an element in a domain's definition
    COMPONENT_BODY = "component body"  # the states, clocks and transitions of a component
    COMPONENT = "component"  # the component of `state(`
    STATE = "state"  # a state of the component in `state(c) =`
    CONSTRAINT = "constraint"  # where a temporal formula of `constraints` goes on
    AFTER_TYPE = "after a type"  # at the top level after a type: `fluent`, `function`, ... follow
    INCLUDE = "include"  # inside the path of an `#include`
    NONE = "none"  # inside a string or a comment, or nowhere completion helps


@dataclass(frozen=True, slots=True)
class Binder:
    """A variable the tokens declare: a parameter, or a pick or quantifier variable."""

    name: str
    type: str
    parameter: bool
    start: int  # offset of the name


@dataclass(frozen=True, slots=True)
class CallSite:
    name: str  # the called name ('' for the tuple of an `initially:` line)
    argument: int  # 0-based index of the argument the cursor is in


@dataclass
class Context:
    position: Position
    decl_keyword: str  # 'procedure', 'action', 'fluent', ... ('' outside a declaration)
    decl_name: str
    section: str  # the last action/fluent section keyword seen ('' if none)
    binders: list[Binder] = field(default_factory=list)
    # Where the variables whose header the cursor is in are declared (not in scope yet).
    pending_binders: list[Binder] = field(default_factory=list)
    calls: list[CallSite] = field(default_factory=list)  # innermost last
    previous_index: int = -1  # index of the token before the word being typed (-1: none)
    braces: int = 0  # how many braces are open at the cursor
    bracket_before: Token | None = None  # the token before the innermost open bracket
    string: Token | None = None  # the string literal the cursor is in
    component: str = ""  # the component whose state is asked for (Position.STATE)

    @property
    def call(self) -> CallSite | None:
        return self.calls[-1] if self.calls else None


@dataclass
class _Open:
    token: Token
    index: int
    commas: int = 0


@dataclass
class _Scope:
    binder: Binder
    level: int  # bracket depth at the binder's keyword
    braced: bool | None = None  # None until the body starts
    header_done: bool = False
    quantifier: bool = False


def _decl_starts(tokens: list[Token]) -> list[int]:
    """Indexes of the tokens that begin top-level declarations (a type before `fluent` or
    `function` belongs to it)."""
    starts: list[int] = []
    depth = 0
    for i, t in enumerate(tokens):
        if t.type in ("LBRACE", "MAIN_LBRACE"):
            if depth == 0 and t.type == "MAIN_LBRACE":
                starts.append(i)
            depth += 1
        elif t.type == "RBRACE":
            depth = max(0, depth - 1)
        elif depth == 0 and t.type in _DECL_KEYWORDS and t.type != "MAIN_LBRACE":
            j = i
            if t.type in ("FLUENT", "FUNCTION", "EXOG_FUNCTION", "DOMAIN"):
                # `list[number] fluent`, `bool function`: back over the type.
                while j > 0 and (starts == [] or j - 1 > starts[-1]) and tokens[j - 1].type not in _ENDERS:
                    j -= 1
            starts.append(j)
    return starts


_ENDERS = frozenset({"SEMI", "RBRACE", "RPAR", "NUMBER", "STRING", "TRUE", "FALSE", "NULL"})


def context_at(tokens: list[Token], offset: int) -> Context:
    """The context of the cursor at `offset` in the file of `tokens`."""
    # The word being typed: a name or keyword the cursor is inside or just after.
    n = 0
    while n < len(tokens) and tokens[n].end < offset:
        n += 1
    if n < len(tokens):
        t = tokens[n]
        word = t.value[:1].isalpha() or t.value[:1] == "_"
        # (The tokenizer closes an unterminated string at the end of its line.)
        unterminated = t.type == "STRING" and len(t.value) != t.end - t.start
        if t.start < offset and (offset < t.end or (unterminated and offset == t.end)) and not word:
            # Inside a string (the path of an `#include`?) or a number.
            including = t.type == "STRING" and n > 0 and tokens[n - 1].type == "INCLUDE"
            ctx = Context(Position.INCLUDE if including else Position.NONE, "", "", "")
            ctx.string = t
            return ctx
        if t.end <= offset and not (word and t.start < offset):
            n += 1
    # tokens[:n] are before the word being typed.
    starts = _decl_starts(tokens[:n])
    first = starts[-1] if starts else 0
    ctx = Context(Position.EXPRESSION, "", "", "")
    _scan(tokens, first, n, ctx)
    return ctx


def _scan(tokens: list[Token], first: int, n: int, ctx: Context) -> None:
    opens: list[_Open] = []
    scopes: list[_Scope] = []
    params: list[Binder] = []
    header: _Open | None = None  # the declaration's parameter list while it is open
    name_seen = header_seen = False
    for i in range(first, n):
        t = tokens[i]
        tt = t.type
        if tt in _DECL_KEYWORDS and not opens and not ctx.decl_keyword:
            ctx.decl_keyword = _DECL_KEYWORDS[tt]
        elif tt == "NAME" and ctx.decl_keyword and not name_seen and not opens:
            ctx.decl_name, name_seen = t.value, True
        elif tt in _SECTIONS and len(opens) <= 1:
            ctx.section = tt.lower()
        if tt in _OPENERS:
            # A scope's unbraced body that starts with '{' is braced after all.
            for s in scopes:
                if s.header_done and s.braced is None and not s.quantifier:
                    s.braced = tt in ("LBRACE", "MAIN_LBRACE") and len(opens) == s.level
            o = _Open(t, i)
            opens.append(o)
            first_paren = name_seen and not header_seen and len(opens) == 1
            if tt == "LPAR" and first_paren and ctx.decl_keyword in _HAS_PARAMETERS:
                header, header_seen = o, True
            continue
        if tt in ("RPAR", "RBRACE", "RBRACKET"):
            # Pop to the matching opener (a stray closer pops nothing).
            k = len(opens) - 1
            while k >= 0 and _OPENERS[opens[k].token.type] != tt:
                k -= 1
            if k >= 0:
                closed = opens[k]
                del opens[k:]
                if closed is header:
                    header = None
                    # (A fluent's parameters stand for every value in its `initially:` lines.)
                    params.extend(_params(tokens, closed.index + 1, i))
            for s in scopes:
                if not s.header_done and len(opens) == s.level and tt == "RPAR":
                    s.header_done = True
            scopes = [s for s in scopes if len(opens) >= s.level]
            if tt == "RBRACE":
                scopes = [s for s in scopes if not (s.braced and len(opens) == s.level)]
            continue
        if tt == "COMMA" and opens:
            opens[-1].commas += 1
            scopes = [s for s in scopes if not (s.quantifier and len(opens) == s.level)]
        elif tt == "SEMI":
            # A ';' ends the statement: brackets left open in it were never closed.
            while opens and opens[-1].token.type in ("LPAR", "LBRACKET"):
                opens.pop()
            keep_if = i + 1 < len(tokens) and tokens[i + 1].type == "ELSE"
            scopes = [
                s
                for s in scopes
                if len(opens) > s.level or (len(opens) == s.level and (s.braced or keep_if) and not s.quantifier)
            ]
        elif tt in ("PICK", "QUANTIFIER"):
            binder = _binder_after(tokens, i, n)
            if binder is not None:
                scopes.append(_Scope(binder, len(opens), quantifier=tt == "QUANTIFIER", header_done=False))
    # A variable is in scope in the body, after its header (`pick (T x in {..})`, `exists (T x)`).
    ctx.binders = params + [s.binder for s in scopes if s.header_done]
    ctx.pending_binders = [s.binder for s in scopes if not s.header_done]
    if header is not None:
        # The cursor is in the declaration's own parameter list.
        ctx.position = _in_parameter_list(tokens, header.index + 1, n)
        return
    ctx.calls = _calls(tokens, opens, n, ctx)
    ctx.previous_index = n - 1
    ctx.braces = sum(1 for o in opens if o.token.type in ("LBRACE", "MAIN_LBRACE"))
    if opens and opens[-1].index > 0:
        ctx.bracket_before = tokens[opens[-1].index - 1]
    ctx.position = _position(tokens, opens, n, ctx)


def _binder_after(tokens: list[Token], i: int, n: int) -> Binder | None:
    """The variable of `pick (T x ...)` or `exists (T x)` at tokens[i], if its name is typed."""
    if i + 1 >= len(tokens) or tokens[i + 1].type != "LPAR":
        return None
    j = i + 2
    depth = 0
    while j < len(tokens) and j < n + 8:
        t = tokens[j]
        if t.type == "LBRACKET":
            depth += 1
        elif t.type == "RBRACKET":
            depth -= 1
        elif t.type == "NAME" and depth == 0 and j > i + 2:
            # Only a name typed before the cursor (not the word being typed) declares.
            if j >= n:
                return None
            return Binder(t.value, "".join(x.value for x in tokens[i + 2 : j]), False, t.start)
        elif t.type in ("RPAR", "IN", "SEMI", "LBRACE", "RBRACE"):
            return None
        j += 1
    return None


def _params(tokens: list[Token], begin: int, end: int) -> list[Binder]:
    """`T a, T b` in tokens[begin:end]: the last name of each comma-separated group."""
    out: list[Binder] = []
    group: list[Token] = []
    for t in [*tokens[begin:end], None]:
        if t is None or t.type == "COMMA":
            if len(group) >= 2 and group[-1].type == "NAME":
                type_text = "".join(x.value for x in group[:-1])
                out.append(Binder(group[-1].value, type_text, True, group[-1].start))
            group = []
        else:
            group.append(t)
    return out


def _in_parameter_list(tokens: list[Token], begin: int, n: int) -> Position:
    prev = tokens[n - 1] if n > begin else None
    if prev is None or prev.type in ("LPAR", "COMMA", "LBRACKET"):
        return Position.TYPE
    return Position.NAME


def _calls(tokens: list[Token], opens: list[_Open], n: int, ctx: Context) -> list[CallSite]:
    out: list[CallSite] = []
    for o in opens:
        if o.token.type in ("LBRACE", "MAIN_LBRACE"):
            out = []  # a call cannot span a block
            continue
        if o.token.type != "LPAR":
            continue
        before = tokens[o.index - 1] if o.index > 0 else None
        if before is not None and before.type == "NAME":
            out.append(CallSite(before.value, o.commas))
        elif ctx.section == "initially" and before is not None and before.type in ("INITIALLY", "SEMI"):
            out.append(CallSite("", o.commas))
    return out


def _position(tokens: list[Token], opens: list[_Open], n: int, ctx: Context) -> Position:
    prev = tokens[n - 1] if n > 0 else None
    if prev is None:
        return Position.TOP_LEVEL
    pt = prev.type
    braces = [o for o in opens if o.token.type in ("LBRACE", "MAIN_LBRACE")]
    innermost = opens[-1] if opens else None
    if pt == "DOT":
        return Position.FIELD
    if not opens:
        return _top_level(tokens, n, ctx)
    if ctx.decl_keyword in ("component", "constraints"):
        return _platform_model(tokens, opens, n, ctx)
    if innermost is not None and innermost.token.type == "LPAR":
        before = tokens[innermost.index - 1] if innermost.index > 0 else None
        if before is not None and before.type in ("HOOK", "DURING") and pt == "LPAR":
            return Position.ACTION
        if before is not None and before.type in ("PICK", "QUANTIFIER"):
            # `pick (T x in {..})`, `exists (T x)`: a type, then the variable's new name.
            if pt == "LPAR":
                return Position.TYPE
            if pt in _TYPE_WORDS or pt in ("NAME", "RBRACKET"):
                return Position.NAME
        return Position.EXPRESSION
    if innermost is not None and innermost.token.type == "LBRACKET":
        return Position.TYPE if pt == "LBRACKET" and tokens[innermost.index - 1].type == "LIST" else Position.EXPRESSION
    if innermost is not None and innermost.token.type == "LBRACE" and innermost.index > 0:
        before = tokens[innermost.index - 1]
        if ctx.decl_keyword == "compound" and len(braces) == 1:
            return Position.TYPE if pt in ("LBRACE", "COMMA") else Position.NAME
        if before.type == "NAME" and ctx.decl_keyword != "component":
            # A compound literal `Pose{x = 1, ...}`.
            return Position.FIELD_INIT if pt in ("LBRACE", "COMMA") else Position.EXPRESSION
        if ctx.decl_keyword == "domain":
            return Position.ELEMENT
        if before.type == "IN":
            return Position.EXPRESSION  # the values of a pick
    # Inside braces: of an action (sections), a fluent (initially), a procedure (statements).
    statement_start = pt in ("LBRACE", "MAIN_LBRACE", "SEMI", "RBRACE", "ELSE", "ON_FAIL", "ON_CANCEL") or (
        pt in _SECTIONS
    )
    if pt == "RPAR":
        statement_start = _closes_statement_head(tokens, n - 1)
    if ctx.decl_keyword in ("action", "exog_action") and len(braces) == 1:
        if ctx.section in ("effect", "start_effect") and statement_start:
            return Position.EFFECT
        if pt in ("LBRACE", "SEMI", "RBRACE"):
            return Position.SECTION
        return Position.EXPRESSION
    if ctx.decl_keyword in ("procedure", "main"):
        return Position.STATEMENT if statement_start else Position.EXPRESSION
    if ctx.decl_keyword in ("fluent",) and pt in ("LBRACE", "SEMI"):
        return Position.SECTION
    return Position.EXPRESSION


def _platform_model(tokens: list[Token], opens: list[_Open], n: int, ctx: Context) -> Position:
    """In the braces of a `component` (its states and clocks) or of `constraints`."""
    if ctx.decl_keyword == "component":
        return Position.COMPONENT_BODY
    innermost = opens[-1]
    before = tokens[innermost.index - 1] if innermost.index > 0 else None
    pt = tokens[n - 1].type
    if innermost.token.type == "LPAR" and before is not None:
        if before.type == "STATE":
            return Position.COMPONENT if pt == "LPAR" else Position.NONE
        if before.type in ("HOOK", "DURING"):
            return Position.ACTION if pt == "LPAR" else Position.NONE
        if before.type == "NAME":
            return Position.EXPRESSION  # an argument of an action
    # `state(c) = s`: a state of c.
    if pt == "EQ" and n >= 5 and [t.type for t in tokens[n - 5 : n - 1]] == ["STATE", "LPAR", "NAME", "RPAR"]:
        ctx.component = tokens[n - 3].value
        return Position.STATE
    return Position.CONSTRAINT


def _top_level(tokens: list[Token], n: int, ctx: Context) -> Position:
    """The position outside any bracket, after tokens[n - 1]."""
    pt = tokens[n - 1].type
    if pt in _DECLARATION_WORDS:
        return Position.NAME
    if ctx.decl_keyword == "domain" and pt in ("EQ", "BAR", "AMP", "DOMAIN_OP"):
        return Position.DOMAIN
    if pt in _TYPE_WORDS or (pt in ("NAME", "RBRACKET") and _starts_declaration(tokens, n - 1, ctx)):
        return Position.AFTER_TYPE
    if pt == "INCLUDE":
        return Position.NONE
    if pt in ("SEMI", "RBRACE") or ctx.decl_keyword in ("", "include"):
        return Position.TOP_LEVEL
    # A function's body: an identifier after a complete operand starts the next declaration.
    return Position.TOP_LEVEL if pt in OPERAND_ENDS else Position.EXPRESSION


def _starts_declaration(tokens: list[Token], i: int, ctx: Context) -> bool:
    """Is tokens[i] (a name or the `]` of `list[T]`) a type at the start of a declaration?"""
    if tokens[i].type == "RBRACKET":
        while i > 0 and tokens[i].type != "LBRACKET":
            i -= 1
        i -= 1
        if i < 0 or tokens[i].type != "LIST":
            return False
    return ctx.decl_keyword == "" or i == 0 or tokens[i - 1].type in ("SEMI", "RBRACE", "STRING")


_DECLARATION_WORDS = frozenset(
    {"FLUENT", "FUNCTION", "EXOG_FUNCTION", "ACTION", "EXOG_ACTION", "PROCEDURE", "DOMAIN", "COMPOUND", "COMPONENT"}
)
_TYPE_WORDS = frozenset({"BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "VOID"})


def _closes_statement_head(tokens: list[Token], i: int) -> bool:
    """Does the ')' at tokens[i] close the head of `if (..)`, `while (..)`, `pick (..)`,
    `solve (..)`, `during (..)` or its `until (..)`, so that a statement follows?"""
    j = opening(tokens, i)
    return j is not None and j > 0 and tokens[j - 1].type in _STATEMENT_HEADS


def opening(tokens: list[Token], i: int) -> int | None:
    """The index of the '(' or '[' that the ')' or ']' at tokens[i] closes, within the
    statement (None if there is none)."""
    closer = tokens[i].type
    opener = "LPAR" if closer == "RPAR" else "LBRACKET"
    depth = braces = 0
    for j in range(i, -1, -1):
        t = tokens[j].type
        if t == closer:
            depth += 1
        elif t == opener:
            depth -= 1
            if depth == 0:
                return j
        elif t == "RBRACE":
            braces += 1  # a compound literal inside the brackets
        elif t in ("LBRACE", "MAIN_LBRACE"):
            braces -= 1
            if braces < 0:
                return None
        elif t == "SEMI" and braces == 0:
            return None
    return None
