"""The golog++ tokenizer.

One regular expression with an alternative per token class, scanned with `finditer`.
Keywords are reserved words with word boundaries: a NAME whose text is a keyword becomes that
keyword's terminal. Three small pieces of context keep the language convenient:

* section words (`effect`, `initially`, ...) are keywords only when a ':' follows;
* the platform-model words (`state`, `next`, `until`, ...) are keywords only inside the braces
  of a `component` or `constraints` declaration;
* a keyword directly followed by a single '=' is a name (a mapping argument such as
  `"/nav" { start = x }`);
* a top-level '{' after the end of a declaration opens the legacy anonymous main block.

Lexical errors (a stray character, an unterminated string or comment) become diagnostics and
scanning goes on, so one bad character never hides the rest of the file.
"""

from __future__ import annotations

import re
import threading
from bisect import bisect_left, bisect_right
from dataclasses import dataclass
from functools import lru_cache

from gpp.base.numbers import RANGE_TEXT, literal_value
from gpp.base.source import Source, Span
from gpp.codes import E0001, E0002, E0003, E0004, E0005, Message


class Token:
    """A token: its terminal name (as in grammar/gpp.lark), its text and its offsets."""

    __slots__ = ("end", "start", "type", "value")

    def __init__(self, type: str, value: str, start: int, end: int) -> None:
        self.type = type
        self.value = value
        self.start = start
        self.end = end

    def __repr__(self) -> str:
        return f"Token({self.type}, {self.value!r}, {self.start})"


# A piece of a token sequence: the tokens `tokens[lo:hi]` of a list, each moved by `delta`.
Piece = tuple[list[Token], int, int, int]
# A sequence spliced from more pieces than this is made at once (each re-parse that reads the
# last one's pieces adds two, and the pieces keep the lists they cut from alive).
MAX_PIECES = 9
# Held while a sequence makes its list (rarely, briefly: one lock for all of them).
_MAKING = threading.Lock()


def _token_start(t: Token) -> int:
    return t.start


class Tokens:
    """A file's tokens, as a list (`as_list`) that may be made only when first asked for.

    An incremental re-parse (gpp.syntax.incremental) keeps the old parse's tokens: those before
    the edit as they are, those after it moved by the edit's change of length. Copying the
    latter for each keystroke costs milliseconds, and most checks read no tokens; so the
    re-parse's tokens are pieces of other token lists (`Piece`), and the list is made from them
    when first asked for, once: under a lock, since the language server reads the last check's
    tokens on its event loop while its analysis thread works. Token lists are never changed
    once parsed, so pieces read later (after more edits of the file) still read what they
    read at first. `len`, `at` and `bisect_start` answer from the pieces without making the
    list (the next re-parse finds its declaration boundaries with them), and `pieces` cuts
    pieces out of them for the next splice.
    """

    __slots__ = ("_bounds", "_length", "_state")

    def __init__(self, tokens: list[Token]) -> None:
        """Tokens already made."""
        # The list once made, else the pieces; one attribute, read once by each method, so
        # that a thread that reads it while another makes the list sees one or the other.
        self._state: list[Token] | tuple[Piece, ...] = tokens
        # Where each piece begins in the sequence, and its length at the end.
        self._bounds: list[int] = [0, len(tokens)]
        self._length = len(tokens)

    @classmethod
    def spliced(cls, pieces: list[Piece]) -> Tokens:
        """The tokens of `pieces`, one after the other (made when first asked for)."""
        kept = tuple(p for p in pieces if p[2] > p[1])
        made = cls([])
        bounds = [0]
        for _, lo, hi, _ in kept:
            bounds.append(bounds[-1] + hi - lo)
        made._bounds = bounds
        made._length = bounds[-1]
        made._state = _join(kept) if len(kept) > MAX_PIECES else kept
        return made

    def __len__(self) -> int:
        return self._length

    @property
    def made(self) -> bool:
        """Has the list been made?"""
        return isinstance(self._state, list)

    def as_list(self) -> list[Token]:
        """The tokens, made now if they were not (the same list every time; do not change it)."""
        state = self._state
        if isinstance(state, list):
            return state
        with _MAKING:
            state = self._state
            if isinstance(state, list):
                return state
            tokens = _join(state)
            self._state = tokens
            return tokens

    def at(self, k: int) -> Token:
        """Token `k` (0 <= k < len): a moved copy if the list is not made."""
        state = self._state
        if isinstance(state, list):
            return state[k]
        p = bisect_right(self._bounds, k) - 1
        tokens, lo, _, delta = state[p]
        t = tokens[lo + k - self._bounds[p]]
        return Token(t.type, t.value, t.start + delta, t.end + delta) if delta else t

    def bisect_start(self, offset: int) -> int:
        """The index of the first token that starts at or after `offset` (`bisect_left` by start)."""
        state = self._state
        if isinstance(state, list):
            return bisect_left(state, offset, key=_token_start)
        for p, (tokens, lo, hi, delta) in enumerate(state):
            if tokens[hi - 1].start + delta >= offset:
                return self._bounds[p] + bisect_left(tokens, offset - delta, lo, hi, key=_token_start) - lo
        return self._length

    def pieces(self, lo: int, hi: int, delta: int) -> list[Piece]:
        """Tokens [lo, hi) of this sequence moved by `delta`, as pieces."""
        state = self._state
        if isinstance(state, list):
            return [(state, lo, hi, delta)]
        out: list[Piece] = []
        bounds = self._bounds
        for p, (tokens, first, _, moved) in enumerate(state):
            a, b = max(lo, bounds[p]), min(hi, bounds[p + 1])
            if a < b:
                out.append((tokens, first + a - bounds[p], first + b - bounds[p], moved + delta))
        return out


def _join(pieces: tuple[Piece, ...]) -> list[Token]:
    """The tokens of `pieces` in one list (those not moved shared: tokens hold no Source)."""
    out: list[Token] = []
    # `object.__new__` and plain assignments to the slots: a call of `Token(...)` runs its
    # `__init__` as well, at about twice the cost.
    new = object.__new__
    append = out.append
    for tokens, lo, hi, delta in pieces:
        if not delta:
            out += tokens[lo:hi]
            continue
        for t in tokens[lo:hi]:
            moved = new(Token)
            moved.type = t.type
            moved.value = t.value
            moved.start = t.start + delta
            moved.end = t.end + delta
            append(moved)
    return out


@dataclass(frozen=True, slots=True)
class LexError:
    """A lexical problem, turned into a diagnostic by the parser."""

    message: Message
    start: int
    end: int
    label: str = ""
    help: str = ""
    # Whether the lexer dropped the text (the parser then sees a gap); a name with non-ASCII
    # letters is kept as a NAME token.
    dropped: bool = True


KEYWORDS: dict[str, str] = {
    "action": "ACTION",
    "exog_action": "EXOG_ACTION",
    "fluent": "FLUENT",
    "function": "FUNCTION",
    "exog_function": "EXOG_FUNCTION",
    "procedure": "PROCEDURE",
    "domain": "DOMAIN",
    "compound": "COMPOUND",
    "list": "LIST",
    "bool": "BOOL",
    "number": "NUMBER_KW",
    "string": "STRING_KW",
    "symbol": "SYMBOL",
    "void": "VOID",
    "if": "IF",
    "else": "ELSE",
    "while": "WHILE",
    "test": "TEST",
    "choose": "CHOOSE",
    "pick": "PICK",
    "in": "IN",
    "search": "SEARCH",
    "solve": "SOLVE",
    "concurrent": "CONCURRENT",
    "during": "DURING",
    "until": "UNTIL",
    "on_fail": "ON_FAIL",
    "on_cancel": "ON_CANCEL",
    "start": "HOOK",
    "end": "HOOK",
    "finish": "HOOK",
    "fail": "HOOK",
    "cancel": "HOOK",
    "push_back": "LIST_PUSH",
    "push_front": "LIST_PUSH",
    "pop_back": "LIST_POP",
    "pop_front": "LIST_POP",
    "true": "TRUE",
    "false": "FALSE",
    "null": "NULL",
    "exists": "QUANTIFIER",
    "forall": "QUANTIFIER",
    "length": "BUILTIN",
    "to_string": "BUILTIN",
    "component": "COMPONENT",
    "constraints": "CONSTRAINTS",
}

# Keywords only inside the braces of `component { }` and `constraints { }`.
PLATFORM_KEYWORDS: dict[str, str] = {
    "resets": "RESETS",
    "state": "STATE",
    "next": "TEMPORAL_UN",
    "previous": "TEMPORAL_UN",
    "future": "TEMPORAL_UN",
    "past": "TEMPORAL_UN",
    "until": "TEMPORAL_BIN",
    "since": "TEMPORAL_BIN",
}

SECTION_WORDS: dict[str, str] = {
    "initially": "INITIALLY",
    "precondition": "PRECONDITION",
    "effect": "EFFECT",
    "start_effect": "START_EFFECT",
    "senses": "SENSES",
    "mapping": "MAPPING",
    "silent": "SILENT",
    "duration": "DURATION",
    "clocks": "CLOCKS",
    "states": "STATES",
    "transitions": "TRANSITIONS",
}

PUNCTUATION: dict[str, str] = {
    "(": "LPAR",
    ")": "RPAR",
    "{": "LBRACE",
    "}": "RBRACE",
    "[": "LBRACKET",
    "]": "RBRACKET",
    ";": "SEMI",
    ",": "COMMA",
    ".": "DOT",
    ":": "COLON",
    "=": "EQ",
    "=>": "CONTROLLABLE",
    "*": "STAR",  # the wildcard inside `constraints { }`; elsewhere MUL_OP
    "->": "ARROW",
    "|": "BAR",
    "&": "AMP",
    "!": "BANG",
    "**": "POW",
    "==": "CMP_OP",
    "!=": "CMP_OP",
    "<=": "CMP_OP",
    ">=": "CMP_OP",
    "<": "CMP_OP",
    ">": "CMP_OP",
    "+": "ADD_OP",
    "-": "ADD_OP",
    "/": "MUL_OP",
    "%": "MUL_OP",
    "\\": "DOMAIN_OP",
}

_SECTION_RE = "|".join(SECTION_WORDS)
# The punctuation, longest first where one is the start of another; `.` before a digit starts a
# number and `/*` an unterminated comment, so neither is read as punctuation.
_PUNCT_RE = r"=>|->|\*\*|[=!<>]=|[(){}\[\];,:=*|&!<>+\-%\\]|\.(?![0-9])|/(?!\*)"
assert set(re.findall(_PUNCT_RE, " ".join(PUNCTUATION))) == set(PUNCTUATION)

# Whitespace and comments are skipped by the same match that reads the next token, so the
# scanner makes one regex step per token (whitespace first: comments are rare). The
# alternatives come most frequent first; a section
# word is tried only where a token starts with the letter of one.
_TOKEN_RE = re.compile(
    r"""
    [ \t\r\n\f\v]*(?:(?://[^\n]*|/\*(?:[^*]|\*(?!/))*\*/)[ \t\r\n\f\v]*)*
    (?:
      (?P<section>(?=["""
    + "".join(sorted({w[0] for w in SECTION_WORDS}))
    + r"""])(?:"""
    + _SECTION_RE
    + r""")\b[ \t\r\n\f\v]*:)
    | (?P<name>[A-Za-z][A-Za-z0-9_]*(?![^\W_]))
    | (?P<punct>"""
    + _PUNCT_RE
    + r""")
    | (?P<number>(?:[0-9]+\.[0-9]*|\.[0-9]+|[0-9]+)(?:[eE][+-]?[0-9]+)?)
    | (?P<underscore_name>_[A-Za-z0-9_]*(?![^\W_]))
    | (?P<wide_name>[^\W\d]\w*)
    | (?P<string>"(?:[^"\\]|\\[\s\S])*")
    | (?P<include>\#include\b)
    | (?P<open_comment>/\*)
    | (?P<sigil>[?$\u00a7](?=[A-Za-z]))
    | (?P<open_string>"[^\n]*)
    | (?P<eof>\Z)
    | (?P<bad>.)
    )
    """,
    re.VERBOSE | re.DOTALL,
)

# The number of the group of each kind of token (comparing numbers is faster than names).
_SECTION, _NAME, _PUNCT, _NUMBER, _UNDERSCORE_NAME, _WIDE_NAME, _STRING = (
    _TOKEN_RE.groupindex[kind]
    for kind in ("section", "name", "punct", "number", "underscore_name", "wide_name", "string")
)
_INCLUDE, _OPEN_COMMENT, _SIGIL, _OPEN_STRING, _EOF = (
    _TOKEN_RE.groupindex[kind] for kind in ("include", "open_comment", "sigil", "open_string", "eof")
)

# Token kinds after which a top-level '{' cannot continue the declaration, so it opens the
# legacy main block.
_ENDS_DECLARATION = frozenset({"SEMI", "RBRACE", "NUMBER", "STRING", "RBRACKET", "TRUE", "FALSE", "NULL"})


@lru_cache(maxsize=4096)
def number_value(text: str) -> int | float | None:
    """`gpp.base.numbers.literal_value` of a number literal, remembered: the lexer checks each
    literal's range and the builder takes its value."""
    return literal_value(text)


def tokenize(source: Source) -> tuple[list[Token], list[LexError]]:
    """Split a source into tokens (without whitespace and comments) and lexical errors."""
    text = source.text
    tokens: list[Token] = []
    errors: list[LexError] = []
    append = tokens.append
    keywords = KEYWORDS
    punctuation = PUNCTUATION
    platform_keywords = PLATFORM_KEYWORDS
    depth = 0
    # Brace depth at which a `component`/`constraints` body was opened, or -1 outside one.
    platform_depth = -1
    platform_pending = False
    wide_names: set[str] = set()
    for m in _TOKEN_RE.finditer(text):
        kind = m.lastindex
        start, pos = m.span(kind)  # type: ignore[arg-type]  # one alternative always matches
        if kind == _NAME:
            value = text[start:pos]
            ttype = keywords.get(value)
            if platform_depth >= 0 and value in platform_keywords:
                # Inside `component`/`constraints`, `until` is the temporal operator.
                ttype = platform_keywords[value]
            elif ttype is None:
                ttype = "NAME"
            elif ttype == "COMPONENT" or ttype == "CONSTRAINTS":
                platform_pending = True
        elif kind == _PUNCT:
            value = text[start:pos]
            ttype = punctuation[value]
            if value == "{":
                if depth == 0 and (not tokens or tokens[-1].type in _ENDS_DECLARATION):
                    ttype = "MAIN_LBRACE"
                if platform_pending:
                    platform_depth = depth
                    platform_pending = False
                depth += 1
            elif value == "}":
                depth = max(depth - 1, 0)
                if depth == platform_depth:
                    platform_depth = -1
            elif value == "*" and platform_depth < 0:
                ttype = "MUL_OP"
            elif value == "=" and tokens and tokens[-1].type in _NAMEABLE_KEYWORDS:
                # `start = x` in a mapping: the keyword is an argument name.
                tokens[-1].type = "NAME"
        elif kind == _NUMBER:
            value = text[start:pos]
            ttype = "NUMBER"
            if number_value(value) is None:
                errors.append(LexError(E0004.too_large(), start, pos, RANGE_TEXT))
        elif kind == _SECTION:
            value = text[start:pos]
            ttype = SECTION_WORDS[value.rstrip(":").rstrip()]
        elif kind == _STRING:
            value = text[start:pos]
            ttype = "STRING"
        elif kind == _EOF:
            break
        elif kind == _UNDERSCORE_NAME:
            value = text[start:pos]
            ttype = "NAME"
            errors.append(LexError(E0003.underscore_name(), start, pos, "names start with a letter"))
        elif kind == _WIDE_NAME:
            # Letters beyond ASCII: one error per distinct name, and the name stays a name so
            # that its declaration and its uses still fit together.
            value = text[start:pos]
            ttype = "NAME"
            if value not in wide_names:
                wide_names.add(value)
                errors.append(_non_ascii_name(value, start, pos))
        elif kind == _INCLUDE:
            value = text[start:pos]
            ttype = "INCLUDE"
        elif kind == _SIGIL:
            value = text[start:pos]
            ttype = "SIGIL"  # legacy `?function`, `$domain`, `§room`: gpp.syntax.legacy rewrites it
        elif kind == _OPEN_COMMENT:
            errors.append(LexError(E0002.comment(), start, start + 2, "comment opened here"))
            break
        elif kind == _OPEN_STRING:
            errors.append(LexError(E0002.string(), start, start + 1, "no closing '\"' on this line"))
            # Read the rest of the line as the string so that parsing can go on.
            ttype = "STRING"
            value = text[start:pos] + '"'
        else:
            last = errors[-1] if errors else None
            if last is not None and last.message.code == E0001.code and last.end == start:
                # A run of stray characters is one problem, not one per character.
                errors[-1] = LexError(E0001.unexpected_characters(), last.start, pos, "not valid here")
            else:
                errors.append(LexError(E0001.unexpected_character(text[start:pos]), start, pos, "not valid here"))
            continue
        append(Token(ttype, value, start, pos))
    return tokens, errors


def _non_ascii_name(name: str, start: int, end: int) -> LexError:
    ascii_name = ascii_spelling(name)
    return LexError(
        E0005.non_ascii(name),
        start,
        end,
        "names are written with the letters a-z, A-Z, digits and `_`",
        f"rename it, for example to `{ascii_name}` (everywhere it is used)" if ascii_name else "",
        dropped=False,
    )


def ascii_spelling(name: str) -> str:
    """A spelling of `name` in ASCII letters (accents dropped, ß as ss), or "" when the name
    has no ASCII letters left."""
    import unicodedata

    decomposed = unicodedata.normalize("NFKD", name.replace("ß", "ss").replace("ẞ", "SS"))
    spelled = "".join(c for c in decomposed if c.isascii() and (c.isalnum() or c == "_"))
    return spelled if spelled[:1].isalpha() else ""


_KEYWORD_TYPES = frozenset(KEYWORDS.values()) | frozenset(PLATFORM_KEYWORDS.values())
# Keywords that may name a mapping argument (`"/nav" { start = x }`); `true`, `false` and
# `null` stay values (`true = 1;` is an assignment to a literal, which the checker rejects).
_NAMEABLE_KEYWORDS = _KEYWORD_TYPES - {"TRUE", "FALSE", "NULL"}


def span_of(source: Source, token: Token) -> Span:
    return Span(source, token.start, token.end)


def unescape_string(literal: str) -> str:
    """The value of a string literal: verbatim but for the escapes \\" and \\\\."""
    body = literal[1:-1]
    if "\\" not in body:
        return body
    out: list[str] = []
    i = 0
    n = len(body)
    while i < n:
        c = body[i]
        if c == "\\" and i + 1 < n and body[i + 1] in '"\\':
            out.append(body[i + 1])
            i += 2
        else:
            out.append(c)
            i += 1
    return "".join(out)
