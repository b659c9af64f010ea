"""The parser: gpp's tokenizer, lark's LALR tables, the AST builder, and error recovery.

The loop below is lark's LALR algorithm written out so that gpp controls every step:

* reductions call AstBuilder methods directly (no parse tree is built first);
* chains of pass-through rules (`?sum: prod`, ...) are collapsed through a cache, which makes
  the expression precedence levels almost free;
* on a syntax error the parser reports it in the user's words and recovers: it inserts a
  missing `;` `)` `]` `}`, deletes a stray token, or skips to the next statement or
  declaration, and it does not report errors that follow from one it just reported.
"""

from __future__ import annotations

import difflib
from bisect import bisect_left
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from gpp.base import diagnostics as diag
from gpp.base.perf import paused_gc
from gpp.base.source import Source, Span
from gpp.codes import E0010, E0011, E0012, E0013
from gpp.syntax import ast
from gpp.syntax.build import AstBuilder
from gpp.syntax.depth import MAX_OPEN, limit_nesting, too_deep_error
from gpp.syntax.legacy import modernize
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, PUNCTUATION, SECTION_WORDS, Token, Tokens, tokenize
from gpp.syntax.tables import Rule, Tables, first_sets, load_tables


@dataclass(frozen=True, slots=True)
class ParseResult:
    program: ast.Program
    diagnostics: list[diag.Diagnostic]
    # The tokens; after an incremental re-parse, made when first read (`tokens`).
    lazy_tokens: Tokens

    @property
    def tokens(self) -> list[Token]:
        return self.lazy_tokens.as_list()

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


def parse(source: Source, _check_fixes: bool = True) -> ParseResult:
    """Parse one file. Always returns a Program (partial after syntax errors), which nests at
    most `depth.MAX_NESTING` levels deep (a declaration nested deeper is left out, with E0014).
    (`_check_fixes`: a guessed fix may be tried by parsing the file with it, not again there.)"""
    with paused_gc():
        tokens, lex_errors = tokenize(source)
        tokens, legacy_errors = modernize(source, tokens)
        parser = _Parser(source, tokens, load_tables())
        parser.fix_trials = _FIX_TRIALS if _check_fixes else 0
        parser.quiet_after_lex_errors([e.start for e in lex_errors if e.dropped])
        program, too_deep = limit_nesting(parser.run(), tokens)
    diagnostics = [
        diag.error(e.message, Span(source, e.start, e.end), e.label, help=e.help or None) for e in lex_errors
    ]
    diagnostics.extend(legacy_errors)
    diagnostics.extend(parser.diagnostics)
    diagnostics.extend(parser.builder.diagnostics)
    diagnostics.extend(too_deep)
    diagnostics.sort(key=diag.Diagnostic.sort_key)
    return ParseResult(program, diagnostics, Tokens(tokens))


def parse_text(text: str, path: str = "<input>") -> ParseResult:
    return parse(Source(text, path))


# ---------------------------------------------------------------- words for terminals

_TERMINAL_WORDS: dict[str, list[str]] = {}
for _table in (PUNCTUATION, KEYWORDS, PLATFORM_KEYWORDS):
    for _text, _type in _table.items():
        _TERMINAL_WORDS.setdefault(_type, []).append(f"`{_text}`")
for _word, _type in SECTION_WORDS.items():
    _TERMINAL_WORDS[_type] = [f"`{_word}:`"]
_TERMINAL_WORDS.update(
    {
        "NAME": ["a name"],
        "NUMBER": ["a number"],
        "STRING": ["a string"],
        "INCLUDE": ["`#include`"],
        "MAIN_LBRACE": ["`{`"],
        "STAR": ["`*`"],
        "$END": ["end of file"],
    }
)

_KEYWORD_TYPES = frozenset(KEYWORDS.values()) | frozenset(PLATFORM_KEYWORDS.values())
# What stands before a name that is being declared: a declaration's keyword or a type.
_DECLARING = frozenset(
    {"ACTION", "EXOG_ACTION", "FLUENT", "FUNCTION", "EXOG_FUNCTION", "PROCEDURE", "DOMAIN", "COMPOUND"}
    | {"BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "VOID", "NAME", "RBRACKET"}
)
# Brackets and what closes them. Not derived: the tables list the terminals of a rule, not
# which of them pair up as brackets.
_CLOSERS = {"LPAR": "RPAR", "LBRACKET": "RBRACKET", "LBRACE": "RBRACE", "MAIN_LBRACE": "RBRACE"}
# What a repair may insert, in order of preference: a policy, not a fact of the grammar.
_INSERTABLE = ("SEMI", "RPAR", "RBRACKET", "RBRACE", "COMMA")
# Ways to finish an unfinished statement (an operand, a closing parenthesis, the `;`).
_COMPLETIONS = (["NAME", "SEMI"], ["RPAR", "SEMI"], ["NAME", "RPAR", "SEMI"])
# A keyword that starts a statement or declaration comes after one of these (or first), for
# `did you mean` hints. Not derived: the grammar also lets `search`, `on_fail`, `on_cancel`
# and the end of any expression (a function body) come before one, and hinting after names
# and numbers would misfire.
_STARTS_AFTER = frozenset({"SEMI", "LBRACE", "RBRACE", "MAIN_LBRACE", "RPAR", "ELSE"})
# What a keyword read as a name is for, when that is not plain from the keyword.
_KEYWORD_NOTES = {
    "UNTIL": ("`until` watches an activity: it follows `during (...)`, as in `during (a) until (e) { }`",),
}
# How many tokens a repair must let the parser read to be believed.
_PROBE = 8
# Keywords whose condition or binding goes in parentheses (`if (c)`, `pick (T x)`), and the
# longest condition the repair that adds them tries.
_PARENTHESIZED = frozenset({"IF", "WHILE", "TEST", "PICK", "QUANTIFIER"})
_MAX_CONDITION = 40
# Type keywords a binding can name (`exists(bool b)`).
_BINDING_TYPES = frozenset({"BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL"})
# The parser's stack between declarations holds at most this many states.
_TOP_LEVEL_DEPTH = 4
# How many tokens of the file the parser loads at a time (see `_Parser.load_more`).
_CHUNK = 4096
# Where a statement or a declaration ends: the parser can resume after these when skipping.
_ENDS = frozenset({"SEMI", "RBRACE"})

# What a rule that ends in ';' is, by the nonterminal it produces, for "expected `;` after
# this ...". Rules ending in ';' of other nonterminals (forward declarations) get no phrase.
_SEMI_PHRASES = {
    "simple_stmt": "statement",
    "effect": "effect",
    "action_section": "sensing assignment",
    "initial": "initial value",
    "constraint": "constraint",
}


@dataclass(frozen=True, slots=True)
class TokenSets:
    """Sets of terminals the messages and the recovery use, derived from the grammar's rules
    (kept in the LALR tables) once per set of tables, so that a new statement, declaration,
    type or operator in grammar/gpp.lark is known to the recovery without listing it here."""

    # FIRST(primary): what an operand begins with; when one is missing, a placeholder operand
    # is inserted.
    primary_start: frozenset[str]
    expression_start: frozenset[str]  # FIRST(expr)
    statement_start: frozenset[str]  # FIRST(statement)
    type_start: frozenset[str]  # FIRST(type)
    # The keywords that begin a declaration and nothing else: FIRST of a top-level item, less
    # a type (typed declarations), `#include` and the legacy main block's `{`.
    declaration_start: frozenset[str]
    # The operator terminals of binary, field access and index expressions.
    operators: frozenset[str]
    # What follows the type in a declaration that begins with one (`fluent`, `domain`, ...).
    typed_declaration: frozenset[str]
    # Tokens where skipping stops: the parser resumes at a statement or a declaration: the end
    # of one, a statement keyword (what begins a statement but not an expression or a
    # block), a declaration keyword or `#include`.
    sync: frozenset[str]
    # Builder (or nonterminal) of each rule that ends in ';' -> what it is, in words.
    semi_context: dict[str, str]


def derive_token_sets(tables: Tables) -> TokenSets:
    first = first_sets(tables.rules)
    top_items = {symbol for r in tables.rules if r.origin == "_top" for symbol in r.symbols}
    declaration_start = first["_top"] - first["type"] - first["include"] - first["main_block"]
    statement_keywords = first["statement"] - first["postfix"] - first["block"]
    return TokenSets(
        primary_start=first["primary"],
        expression_start=first["expr"],
        statement_start=first["statement"],
        type_start=first["type"],
        declaration_start=declaration_start,
        operators=frozenset(r.symbols[1] for r in tables.rules if r.builder in ("binary", "field", "index")),
        typed_declaration=frozenset(
            r.symbols[1] for r in tables.rules if r.origin in top_items and r.symbols[:1] == ("type",)
        ),
        sync=_ENDS | declaration_start | statement_keywords | first["include"],
        semi_context={
            r.builder or r.origin: _SEMI_PHRASES[r.origin]
            for r in tables.rules
            if r.last == "SEMI" and r.origin in _SEMI_PHRASES
        },
    )


# Results of `derive_token_sets`, per table set (which they keep alive, so the id stays theirs).
_TOKEN_SETS: dict[int, tuple[Tables, TokenSets]] = {}


def token_sets(tables: Tables) -> TokenSets:
    """The token sets of `tables`, derived on first use."""
    cached = _TOKEN_SETS.get(id(tables))
    if cached is None:
        cached = _TOKEN_SETS[id(tables)] = (tables, derive_token_sets(tables))
    return cached[1]


_SUGGESTABLE_KEYWORDS = sorted(set(KEYWORDS) | set(SECTION_WORDS))
_SECTION_LIST = sorted(SECTION_WORDS)
_WORD_TYPES = {**KEYWORDS, **PLATFORM_KEYWORDS, **SECTION_WORDS}
# A guessed keyword before an error is tried by parsing the file with it: so many times per
# file at most, in files of at most so many characters.
_FIX_TRIALS = 2
_FIX_TRIAL_SIZE = 50_000


def describe_found(token: Token) -> str:
    if token.type == "$END":
        return "end of file"
    if token.type in _KEYWORD_TYPES:
        return f"keyword `{token.value}`"
    if token.type == "NAME":
        return f"`{token.value}`"
    if token.type == "NUMBER":
        return f"number `{token.value}`"
    if token.type == "STRING":
        return "a string"
    return f"`{token.value}`"


def describe_expected(expected: set[str], sets: TokenSets) -> str:
    """`expected` terminals in words: `;`, a name, an expression, ..."""
    phrases: list[str] = []
    rest = set(expected)
    if rest >= sets.declaration_start and rest >= sets.type_start:
        phrases.append("a declaration")
        rest -= sets.declaration_start | sets.type_start | {"INCLUDE", "MAIN_LBRACE", "$END"}
    if rest >= sets.statement_start:
        phrases.append("a statement")
        rest -= sets.statement_start | sets.expression_start
    elif rest >= sets.primary_start:
        phrases.append("an expression")
        rest -= sets.expression_start
    if {"BOOL", "NUMBER_KW", "STRING_KW"} <= rest:
        phrases.append("a type")
        rest -= sets.type_start
    if len(sets.operators & rest) >= 4:
        phrases.append("an operator")
        rest -= sets.operators
    words: list[str] = []
    for t in sorted(rest, key=_terminal_order):
        for w in _TERMINAL_WORDS.get(t, [t.lower()]):
            if w not in words:
                words.append(w)
    phrases.extend(words)
    if not phrases:
        return "nothing more"
    if len(phrases) == 1:
        return phrases[0]
    if len(phrases) > 8:
        phrases = [*phrases[:7], "..."]
        return "one of " + ", ".join(phrases)
    return "one of " + ", ".join(phrases[:-1]) + " or " + phrases[-1]


def _terminal_order(t: str) -> tuple[int, str]:
    priority = {"SEMI": 0, "RPAR": 1, "RBRACE": 2, "RBRACKET": 3, "COMMA": 4, "EQ": 5, "NAME": 6}
    return (priority.get(t, 10), t)


# A simulated parser stack: the lowest `height` states of the real stack, and the states
# pushed above them as a linked list (top first), which several simulations can share.
_Pushed = tuple[int, "_Pushed"] | None
_Overlay = tuple[int, _Pushed]

# Results of `_Parser.unit_chain`, per table set; they depend on the tables only. By the state
# below and the state reached (after a shift), or by the state below and the nonterminal
# reduced (after a reduction).
_UNIT_CHAINS: dict[int, dict[tuple[int, int, str], int]] = {}
_GOTO_CHAINS: dict[int, dict[tuple[int, str, str], int]] = {}


# How the parser reduces by a rule: a pass-through (`?rule` with one child), by calling its
# builder with the children as they are or with spliced children joined in (`_flatten`), or
# as an inlined helper rule whose children join the parent's (its own spliced ones first).
_UNIT, _BUILD, _BUILD_FLAT, _SPLICE, _SPLICE_FLAT = range(5)


def _reduction_kind(rule: Rule) -> int:
    if rule.unit:
        return _UNIT
    if rule.splice:
        return _SPLICE_FLAT if rule.has_splices else _SPLICE
    return _BUILD_FLAT if rule.has_splices else _BUILD


class _Splice(list[Any]):
    """The children of an inlined helper rule, joined into the parent's children."""


def _flatten(children: list[Any]) -> list[Any]:
    """Join spliced children into one list. A repetition `x*` reduces as `rep: rep x`, so
    its accumulated list comes first: it is extended in place (copying it would make long
    repetitions quadratic), which is safe because only the value stack refers to it."""
    first = children[0] if children else None
    if type(first) is _Splice:
        out: list[Any] = first
        rest = children[1:]
    else:
        out = []
        rest = children
    for c in rest:
        if type(c) is _Splice:
            out.extend(c)
        else:
            out.append(c)
    return out


def _match_brackets(tokens: Sequence[Token]) -> list[int]:
    """For each token, the index of the innermost bracket opened before it and not closed
    (-1 if none); a bracket's entry is the one it is inside. One forward scan: a closer
    closes the innermost open bracket if it matches it and is ignored otherwise."""
    open_before: list[int] = []
    top = -1
    for k, t in enumerate(tokens):
        open_before.append(top)
        if t.type in _CLOSERS:
            top = k
        elif top >= 0 and t.value and _CLOSERS[tokens[top].type] == t.type:
            top = open_before[top]
    return open_before


class _Parser:
    def __init__(self, source: Source, tokens: list[Token], tables: Tables) -> None:
        self.source = source
        end = len(source.text)
        # The tokens of the file; `tokens` holds those read so far (with what the recovery
        # inserted) and the next ones, a chunk at a time, up to a `$MORE` token that no state
        # accepts: a repair inserts at the current token, and so moves only the rest of the
        # chunk, never the rest of the file.
        self.original = [*tokens, Token("$END", "", end, end)]
        self.loaded = 0
        self.tokens: list[Token] = []
        self.load_more()
        self.tables = tables
        self.sets = token_sets(tables)
        self.builder = AstBuilder(source)
        self.diagnostics: list[diag.Diagnostic] = []
        # Index of the token up to which errors are not reported (cascade suppression).
        self.quiet_until = -1
        self.unit_cache = _UNIT_CHAINS.setdefault(id(tables), {})
        self.goto_cache = _GOTO_CHAINS.setdefault(id(tables), {})
        # Repairs tried at each token (by identity), to stop a repair that makes no progress.
        self.repairs: dict[int, int] = {}
        self.quiet_tokens: set[int] = set()
        # Where the tokens of the file start and, matched once on the first error that needs
        # them, the brackets open before each.
        self._starts: list[int] | None = None
        self.open_before: list[int] | None = None
        # How many guessed fixes may still be tried by parsing the file with them.
        self.fix_trials = 0

    # ---------------------------------------------------------------- the LALR loop

    def run(self) -> ast.Program:
        t = self.tables
        actions, end_state = t.actions, t.end_state
        # What to do for each reduce action x < 0, indexed by x itself (the list is reversed:
        # rules[-1 - r] is rule r): its size, what it produces, its builder and its kind.
        rules: list[tuple[int, str, Callable[[list[Any]], Any] | None, int]] = [
            (r.size, r.origin, getattr(self.builder, r.builder) if r.builder else None, _reduction_kind(r))
            for r in reversed(t.rules)
        ]
        unit_cache = self.unit_cache
        goto_cache = self.goto_cache
        max_stack = MAX_OPEN
        state = t.start_state
        ss: list[int] = [state]
        vs: list[Any] = []
        tokens = self.tokens
        i = 0
        while True:
            tok = tokens[i]
            tt = tok.type
            x = actions[state].get(tt)
            if x is None:
                recovered = self.recover(i, ss, vs)
                if recovered is None:
                    return self.partial_program(vs)
                i = recovered
                state = ss[-1]
                continue
            if x >= 0:
                if len(ss) > max_stack:
                    resumed = self.skip_too_deep(i, ss, vs)
                    if resumed is None:
                        return self.partial_program(vs)
                    i = resumed
                    state = ss[-1]
                    continue
                ss.append(x)
                vs.append(tok)
                state = x
                i += 1
                continue
            size, origin, callback, kind = rules[x]
            if kind == _UNIT:
                unit_key = (ss[-2], state, tt)
                state = unit_cache.get(unit_key, -1)
                if state < 0:
                    state = unit_cache[unit_key] = self.unit_chain(unit_key[0], origin, tt)
                ss[-1] = state
                continue
            if size:
                children = vs[-size:]
                del ss[-size:]
                del vs[-size:]
            else:
                children = []
            if kind == _BUILD:
                value = callback(children)  # type: ignore[misc]
            elif kind == _BUILD_FLAT:
                value = callback(_flatten(children))  # type: ignore[misc]
            elif kind == _SPLICE:
                value = _Splice(children)
            else:
                children = _flatten(children)
                value = children if type(children) is _Splice else _Splice(children)
            # The goto, and the pass-through reductions that follow it on this lookahead.
            key = (ss[-1], origin, tt)
            state = goto_cache.get(key, -1)
            if state < 0:
                state = goto_cache[key] = self.unit_chain(key[0], origin, tt)
            if state == end_state and tt == "$END":
                assert isinstance(value, ast.Program)
                return value
            ss.append(state)
            vs.append(value)

    def unit_chain(self, below: int, origin: str, tt: str) -> int:
        """The state reached from `below` after a chain of pass-through reductions on `tt`."""
        actions, gotos, rules = self.tables.actions, self.tables.gotos, self.tables.rules
        top = gotos[below][origin]
        while True:
            y = actions[top].get(tt)
            if y is None or y >= 0 or not rules[-1 - y].unit:
                return top
            top = gotos[below][rules[-1 - y].origin]

    def partial_program(self, vs: list[Any]) -> ast.Program:
        decls: list[ast.Decl] = []
        for v in vs:
            if isinstance(v, ast.Decl):
                decls.append(v)
            elif type(v) is _Splice:
                decls.extend(d for d in _flatten(v) if isinstance(d, ast.Decl))
        return ast.Program(span=Span(self.source, 0, len(self.source.text)), declarations=tuple(decls))

    # ---------------------------------------------------------------- simulation

    def simulate(
        self, ss: Sequence[int], types: Sequence[str], reduced: list[str] | None = None, height: int | None = None
    ) -> bool:
        """Would the parser in state stack `ss` (its lowest `height` states, all by default)
        accept the token types `types`?"""
        h = len(ss) if height is None else height
        return self.advance(ss, (h, None), types, reduced) is not None

    def advance(
        self, ss: Sequence[int], at: _Overlay, types: Sequence[str], reduced: list[str] | None = None
    ) -> _Overlay | None:
        """The stack after the parser, at `at` over `ss`, reads `types`; None if it cannot.

        `ss` is not changed nor copied: the simulated stack is its lowest states plus a chain
        of states pushed above them, so a simulation costs the tokens it reads, not the depth
        of the stack (recovery simulates often, and the stack of a deeply nested input is deep).
        """
        actions, gotos, rules, end_state = (
            self.tables.actions,
            self.tables.gotos,
            self.tables.rules,
            self.tables.end_state,
        )
        h, above = at
        for tt in types:
            while True:
                x = actions[above[0] if above is not None else ss[h - 1]].get(tt)
                if x is None:
                    return None
                if x >= 0:
                    above = (x, above)
                    break
                r = rules[-1 - x]
                if reduced is not None:
                    reduced.append(r.builder if r.builder else r.origin)
                n = r.size
                while n and above is not None:
                    above = above[1]
                    n -= 1
                h -= n
                g = gotos[above[0] if above is not None else ss[h - 1]][r.origin]
                if g == end_state and tt == "$END":
                    return (h, above)
                above = (g, above)
        return (h, above)

    def lookahead(self, i: int, count: int = 3) -> list[str]:
        return [t.type for t in self.tokens[i : i + count]]

    # ---------------------------------------------------------------- recovery

    def quiet_after_lex_errors(self, offsets: list[int]) -> None:
        """A token the lexer dropped leaves a gap the parser would report again: errors at the
        token that follows a lexical error are not reported."""
        for offset in offsets:
            at = bisect_left(self.starts(), offset)
            # The token at the error (an unterminated string read to the end of its line) and
            # the one after it.
            self.quiet_tokens.update((at, at + 1))

    def report(self, i: int, d: diag.Diagnostic) -> None:
        if i > self.quiet_until and i not in self.quiet_tokens:
            self.diagnostics.append(d)
        self.quiet_until = i + 3

    def acceptable(self, ss: list[int]) -> set[str]:
        """The terminals that can really come next. The LALR table of the top state also lists
        lookaheads merged from other contexts; simulating each one on the actual stack leaves
        only those that lead to a shift."""
        return {t for t in self.tables.actions[ss[-1]] if self.simulate(ss, [t])}

    def progress(self, ss: Sequence[int], types: Sequence[str]) -> int:
        """How many of `types` the parser in state `ss` accepts before it fails."""
        for n in range(len(types), 0, -1):
            if self.simulate(ss, types[:n]):
                return n
        return 0

    def load_more(self) -> None:
        """Read the next chunk of the file's tokens into `tokens`."""
        tokens = self.tokens
        if tokens and tokens[-1].type == "$MORE":
            tokens.pop()
        start, self.loaded = self.loaded, min(self.loaded + _CHUNK, len(self.original))
        tokens.extend(self.original[start : self.loaded])
        if self.loaded < len(self.original):
            at = self.original[self.loaded].start
            tokens.append(Token("$MORE", "", at, at))

    def load_until(self, k: int) -> None:
        """Make tokens 0..k (as far as the file goes) tokens of the file."""
        while self.loaded < len(self.original) and len(self.tokens) - 1 <= k:
            self.load_more()

    def recover(self, i: int, ss: list[int], vs: list[Any]) -> int | None:
        """Report the error at token i and repair the input; returns where to go on."""
        tokens = self.tokens
        if tokens[i].type == "$MORE":
            self.load_more()
            return i
        # Repairs read ahead, and report what they see, up to the probe's length.
        self.load_until(i + 2 * _PROBE)
        tok = tokens[i]
        expected = self.acceptable(ss)
        prev = tokens[i - 1] if i > 0 else None
        ahead = self.lookahead(i, _PROBE)

        # A keyword where a name must stand (`action test() {}`): say so, and read it as the name.
        # Not when the keyword reads as itself once the statement before it is completed
        # (`stack(a,` then `pick (...) ...` on the next line: the error is the unfinished call).
        if (
            "NAME" in expected
            and tok.type in _KEYWORD_TYPES
            and (as_name := self.progress(ss, ["NAME", *ahead[1:]])) >= min(3, len(ahead))
            and not any(self.simulate(ss, [c, *ahead[:2]]) for c in _INSERTABLE)
            and not any(self.progress(ss, [*fill, *ahead]) - len(fill) >= as_name for fill in _COMPLETIONS)
        ):
            # Another name is the help only where a name is declared (`action test()`, `number
            # string`); elsewhere the keyword may begin a form the recovery does not know.
            declared = prev is not None and prev.type in _DECLARING
            self.report(
                i,
                diag.error(
                    E0013.reserved(tok.value),
                    self.span(tok),
                    "reserved word",
                    help=f"choose another name, such as `{tok.value}_`" if declared else None,
                    notes=_KEYWORD_NOTES.get(tok.type, ()),
                ),
            )
            tok.type = "NAME"
            return i

        if tok.type == "$END":
            return self.recover_at_end(i, ss, expected)

        # A top-level `{` after `... = f()` opens the legacy main block; the tokenizer cannot
        # tell it from the `{` of a declaration, the parser state can.
        if tok.type == "LBRACE" and "MAIN_LBRACE" in expected:
            tok.type = "MAIN_LBRACE"
            return i

        # A repair that did not get the parser past this token is not tried again: skip instead.
        tries = self.repairs.get(id(tok), 0)
        self.repairs[id(tok)] = tries + 1
        if tries >= 2:
            return self.skip_to_sync(i + 1, ss, vs) if tries < 4 else None

        # `if c() == x go();`, `pick Room r go(r);`: the parentheses of a condition or binding.
        if "LPAR" in expected and prev is not None and prev.type in _PARENTHESIZED and tok.type != "$MORE":
            close = self.parenthesized(i, ss)
            if close is not None:
                return close
        # `pick (v in Room)`: the type and the variable swapped around `in`.
        if tok.type == "IN" and "NAME" in expected and self.report_binding_order(i):
            return i + 1
        # Candidate repairs, scored by how far the parse then gets.
        new_line = prev is not None and self.source.line_col(prev.end)[0] < self.source.line_col(tok.start)[0]
        # A keyword that starts a line after an unfinished statement (`stack(a,` then `pick ...`):
        # the statement before is what is wrong. Finish it unseen, and suggest no edit of the
        # keyword's line.
        if new_line and prev is not None and tok.type in _KEYWORD_TYPES:
            for fill in _COMPLETIONS:
                if self.progress(ss, [*fill, *ahead]) == len(fill) + len(ahead):
                    self.report_unfinished(i, expected)
                    tokens[i:i] = [Token(t, "", prev.end, prev.end) for t in fill]
                    return i
        candidates: list[tuple[int, float, str]] = []  # (progress, preference, repair)
        operand_start = self.sets.primary_start
        for order, inserted in enumerate(_INSERTABLE):
            if inserted in expected:
                gain = self.progress(ss, [inserted, *ahead]) - 1
                preference: float = 0 if inserted == "SEMI" and new_line else 1 + order
                if inserted == "COMMA" and tok.type in operand_start and not new_line:
                    # `stack(a b)`: a missing `,` between two operands, not an operand too many
                    preference = 0.25
                candidates.append((gain, -preference, inserted))
        if expected & operand_start and tok.type not in operand_start:
            gain = self.progress(ss, ["NAME", *ahead]) - 1
            candidates.append((gain, -7, "OPERAND"))
        # The deleted token counts as read, so that deleting and inserting compare fairly.
        deletion = self.progress(ss, self.lookahead(i + 1, _PROBE - 1)) + 1
        candidates.append((deletion, -0.5 if not new_line else -6, "DELETE"))
        candidates.sort(reverse=True)
        gain, _, repair = candidates[0]
        if gain >= min(2, len(ahead)):
            anchor = prev.end if prev is not None else tok.start
            if repair == "DELETE":
                self.report_unexpected(i, ss, expected, deleting=True)
                return i + 1
            if repair == "OPERAND":
                self.report_unexpected(i, ss, expected, deleting=False)
                # A placeholder operand (a name no one can write) completes the expression.
                tokens.insert(i, Token("NAME", "", tok.start, tok.start))
                return i
            self.report_insertion(i, ss, repair, expected)
            tokens.insert(i, Token(repair, "", anchor, anchor))
            return i
        self.report_unexpected(i, ss, expected, deleting=False)
        return self.skip_to_sync(i, ss, vs)

    def parenthesized(self, i: int, ss: list[int]) -> int | None:
        """Token i follows a keyword whose condition or binding goes in parentheses
        (`_PARENTHESIZED`) and is not `(`: if putting tokens i..j in parentheses lets the parse
        go on, report that as the fix (safe when only one such j is found before the end of
        the statement) and insert the parentheses; where to go on, or None."""
        tokens = self.tokens
        self.load_until(i + _MAX_CONDITION + 4)
        ends: list[int] = []
        depth = 0
        for j in range(i, min(i + _MAX_CONDITION, len(tokens))):
            t = tokens[j].type
            if t in ("$END", "$MORE", "SEMI") or (depth == 0 and t in ("LBRACE", "RBRACE", "MAIN_LBRACE")):
                break
            depth += (t in _CLOSERS) - (t in _CLOSERS.values())
            if depth < 0:
                break
            following = [u.type for u in tokens[j + 1 : j + 4] if u.type != "$MORE"]
            if depth == 0 and self.simulate(ss, ["LPAR", *(u.type for u in tokens[i : j + 1]), "RPAR", *following]):
                ends.append(j)
        if not ends:
            return None
        last = tokens[ends[0]]
        keyword = tokens[i - 1]
        text = self.source.text[tokens[i].start : last.end]
        what = f"`{text}`" if len(text) <= 40 and "\n" not in text else "it"
        safety = diag.Applicability.SAFE if len(ends) == 1 else diag.Applicability.UNSAFE
        edits = (
            diag.Edit(Span(self.source, tokens[i].start, tokens[i].start), "("),
            diag.Edit(Span(self.source, last.end, last.end), ")"),
        )
        self.report(
            i,
            diag.error(
                E0010.unparenthesized(keyword.value),
                self.span(tokens[i]),
                "`(` missing before this",
                fix=diag.Fix(f"put {what} in parentheses", edits, safety),
            ),
        )
        tokens.insert(ends[0] + 1, Token("RPAR", "", last.end, last.end))
        tokens.insert(i, Token("LPAR", "", tokens[i].start, tokens[i].start))
        return i

    def report_binding_order(self, i: int) -> bool:
        """`pick (v in Room)`, `exists(v in Room)`: report the swap as the fix and drop the `in`
        (the parser then reads `v` as the type: the declaration is damaged, its names are not
        checked). False when token i is not such an `in`."""
        tokens = self.tokens
        if i < 3 or i + 2 >= len(tokens):
            return False
        word, lpar, variable, type_name, rpar = (
            tokens[i - 3],
            tokens[i - 2],
            tokens[i - 1],
            tokens[i + 1],
            tokens[i + 2],
        )
        if not (
            word.type in ("PICK", "QUANTIFIER")
            and lpar.type == "LPAR"
            and variable.type == "NAME"
            and (type_name.type == "NAME" or type_name.type in _BINDING_TYPES)
            and rpar.type == "RPAR"
        ):
            return False
        fix = diag.Fix(
            f"write `{type_name.value} {variable.value}`",
            (diag.Edit(Span(self.source, variable.start, type_name.end), f"{type_name.value} {variable.value}"),),
            diag.Applicability.SAFE,
        )
        self.report(
            i,
            diag.error(
                E0010.binding_order(word.value, variable.value, type_name.value),
                Span(self.source, variable.start, type_name.end),
                "the variable before its type",
                fix=fix,
            ),
        )
        return True

    def is_sync(self, j: int) -> bool:
        """Can parsing resume at token j? At `;` and `}`, statement keywords, declaration
        keywords, and a type that starts a line or is followed by `fluent`/`function`/`domain`."""
        t = self.tokens[j]
        if t.type in self.sets.sync:
            return True
        if t.type in self.sets.type_start and j + 1 < len(self.tokens):
            if self.tokens[j + 1].type in self.sets.typed_declaration:
                return True
            prev = self.tokens[j - 1] if j > 0 else None
            starts_line = prev is None or self.source.line_col(prev.end)[0] < self.source.line_col(t.start)[0]
            return starts_line and t.type != "NAME"
        return False

    def skip_to_sync(self, i: int, ss: list[int], vs: list[Any]) -> int | None:
        """Panic mode: skip to a token where a statement or declaration can go on, and pop the
        parser back to a state that accepts it."""
        tokens = self.tokens
        j = i - 1
        while j + 1 < len(tokens):
            j += 1
            self.load_until(j + 4)
            if not (tokens[j].type == "$END" or self.is_sync(j)):
                continue
            resume = j + 1 if tokens[j].type == "SEMI" else j
            if resume >= len(tokens):
                return None
            ahead = self.lookahead(resume, 3)
            for depth in range(len(ss), 0, -1):
                if self.simulate(ss, ahead, height=depth):
                    del ss[depth:]
                    del vs[depth - 1 :]
                    self.quiet_until = max(self.quiet_until, resume + 2)
                    return resume
            if tokens[j].type == "$END":
                return None
        return None

    def skip_too_deep(self, i: int, ss: list[int], vs: list[Any]) -> int | None:
        """More than MAX_OPEN constructs are open at token i: report E0014 there and leave out
        the rest of the declaration, so that its tree is never built. Parsing goes on at the
        next declaration outside all brackets (found in one forward scan)."""
        self.report(i, too_deep_error(self.span(self.tokens[i])))
        open_before = self.brackets()
        original = self.original
        j = self.file_index(i) + 1
        while original[j].type != "$END" and not (open_before[j] < 0 and self.starts_declaration(j)):
            j += 1
        del self.tokens[i:]
        self.loaded = j
        self.load_more()
        self.load_until(i + 3)
        ahead = self.lookahead(i, 3)
        # Declarations are reduced into the program's list as soon as they end, so the one
        # left out began within the lowest few states of the stack: only those are tried
        # (from the top of the deep stack, each try would reduce through all of it).
        for depth in range(min(len(ss), _TOP_LEVEL_DEPTH), 0, -1):
            if self.simulate(ss, ahead, height=depth):
                del ss[depth:]
                del vs[depth - 1 :]
                self.quiet_until = max(self.quiet_until, i + 2)
                return i
        return None

    def starts_declaration(self, j: int) -> bool:
        """Can token j of the file (outside all brackets) begin a declaration?"""
        t = self.original[j]
        if t.type in self.sets.declaration_start or t.type == "INCLUDE":
            return True
        if t.type in self.sets.type_start:
            following = self.original[j + 1].type
            if following in self.sets.typed_declaration:
                return True
            if following == "LBRACKET" and t.type == "LIST":
                return self.line_of(t.start) > self.line_of(self.original[j - 1].end)
        return False

    def line_of(self, offset: int) -> int:
        return self.source.line_col(offset)[0]

    def recover_at_end(self, i: int, ss: list[int], expected: set[str]) -> int | None:
        """End of file inside a declaration: say what is open, then close it."""
        opener = self.innermost_unclosed(i)
        secondary = []
        if opener is not None:
            secondary.append(diag.Label(self.span(opener), f"this `{opener.value}` is not closed"))
        self.report(
            i,
            diag.error(
                E0012.unexpected_eof(describe_expected(expected, self.sets)),
                self.span(self.tokens[i]),
                "the file ends here",
                secondary=secondary,
            ),
        )
        self.quiet_until = len(self.tokens)
        # Close what is open, innermost first, completing a statement or operand where needed,
        # so that the declaration being written still reaches the model (an editor needs it).
        fillers: tuple[list[str], ...] = (
            [],
            ["SEMI"],
            ["NAME"],
            ["NAME", "SEMI"],
            ["RPAR", "SEMI"],
            ["NAME", "RPAR", "SEMI"],
        )
        inserted: list[str] = []
        # Each closer is simulated from the stack the ones before it left: the cost is the
        # number of unclosed brackets, however many.
        at: _Overlay = (len(ss), None)
        for opener in reversed(self.unclosed(i)):
            closer = _CLOSERS[opener.type]
            for filler in fillers:
                after = self.advance(ss, at, [*filler, closer])
                if after is not None:
                    inserted += [*filler, closer]
                    at = after
                    break
            else:
                break
        for filler in fillers[:4]:
            if self.advance(ss, at, [*filler, "$END"]) is not None:
                end = self.tokens[i].start
                self.tokens[i:i] = [Token(t, "", end, end) for t in [*inserted, *filler]]
                return i
        return None

    def unclosed(self, i: int) -> list[Token]:
        """The brackets opened before token i and not closed, outermost first."""
        open_before = self.brackets()
        k = open_before[self.file_index(i)]
        stack: list[Token] = []
        while k >= 0:
            stack.append(self.original[k])
            k = open_before[k]
        stack.reverse()
        return stack

    def innermost_unclosed(self, i: int) -> Token | None:
        k = self.brackets()[self.file_index(i)]
        return self.original[k] if k >= 0 else None

    def starts(self) -> list[int]:
        """Where each token of the file starts (computed on first use)."""
        if self._starts is None:
            self._starts = [t.start for t in self.original]
        return self._starts

    def brackets(self) -> list[int]:
        """`_match_brackets` of the file's tokens (matched on the first error that needs it)."""
        if self.open_before is None:
            self.open_before = _match_brackets(self.original)
        return self.open_before

    def file_index(self, i: int) -> int:
        """The index in the file's tokens of the first one at or after token i. Tokens the
        recovery inserted start where the next token of the file starts, or earlier, and
        close nothing, so the brackets open before i are those open before that token."""
        return bisect_left(self.starts(), self.tokens[i].start)

    def report_insertion(self, i: int, ss: list[int], inserted: str, expected: set[str]) -> None:
        tokens = self.tokens
        tok = tokens[i]
        prev = tokens[i - 1] if i > 0 else tok
        at = Span(self.source, prev.end, prev.end)
        text = _TERMINAL_WORDS[inserted][0]
        secondary: list[diag.Label] = []
        if inserted == "SEMI":
            reduced: list[str] = []
            self.simulate(ss, ["SEMI", tok.type], reduced)
            semi_context = self.sets.semi_context
            what = next((semi_context[r] for r in reduced if r in semi_context), None)
            message = E0011.missing_after(what)
        else:
            message = E0010.expected(text, describe_found(tok))
            opener = self.innermost_unclosed(i)
            if opener is not None and _CLOSERS.get(opener.type) == inserted:
                secondary.append(diag.Label(self.span(opener), f"to close this `{opener.value}`"))
        if tok.type != "$END" and self.source.line_col(tok.start)[0] == self.source.line_col(prev.end)[0]:
            secondary.append(diag.Label(self.span(tok), f"found {describe_found(tok)}"))
        # Only a missing `;` is certain; another inserted token is the parser's guess, offered
        # as a fix when the parse then reads on.
        safe = diag.Applicability.SAFE if inserted == "SEMI" else diag.Applicability.UNSAFE
        fix = None
        if inserted == "SEMI" or self.reads_on(ss, [inserted], i):
            fix = diag.Fix(f"insert {text}", (diag.Edit(at, _TERMINAL_WORDS[inserted][0].strip("`")),), safe)
        self.report(
            i,
            diag.error(
                message,
                at,
                f"add {text} here",
                secondary=secondary,
                help=self.keyword_hint(i, expected),
                fix=fix,
            ),
        )

    def report_unfinished(self, i: int, expected: set[str]) -> None:
        tok = self.tokens[i]
        prev = self.tokens[i - 1]
        self.report(
            i,
            diag.error(
                E0010.expected(describe_expected(expected, self.sets), describe_found(tok)),
                self.span(tok),
                "unexpected token",
                secondary=[diag.Label(Span(self.source, prev.end, prev.end), "the statement before is not finished")],
                help="finish the statement on the line before",
            ),
        )

    def reads_on(self, ss: list[int], replacement: list[str], i: int) -> bool:
        """Does the parser at `ss` read `replacement` and then every token of the probe from
        token i on? A fix that edits the token before i is offered only then: a fix after
        which the parse fails again a few tokens on cannot be right."""
        rest = self.lookahead(i, _PROBE - 1)
        return self.progress(ss, [*replacement, *rest]) == len(replacement) + len(rest)

    def report_unexpected(self, i: int, ss: list[int], expected: set[str], deleting: bool) -> None:
        tok = self.tokens[i]
        prev = self.tokens[i - 1] if i > 0 else None
        help = self.keyword_hint(i, expected)
        fix = None
        remove = diag.Fix("remove `;`", (diag.Edit(self.span(tok), ""),), diag.Applicability.SAFE)
        if tok.type == "SEMI" and prev is not None and prev.type == "RBRACE" and prev.value:
            message = E0010.semicolon_after_brace()
            help = "remove this `;`: a statement or declaration that ends with `}` takes no `;`"
            fix = remove
        elif tok.type == "SEMI" and "$END" in expected:
            message = E0010.semicolon_after_declaration()
            help = "remove this `;`: a function body is an expression and takes no `;`"
            fix = remove
        elif tok.type == "SEMI" and prev is not None and prev.type == "SEMI":
            message = E0010.semicolon()
            help = "remove this `;`: there is no empty statement (write `{}` for one that does nothing)"
            fix = remove
        else:
            message = E0010.expected(describe_expected(expected, self.sets), describe_found(tok))
            if tok.type == "EQ" and "CMP_OP" in expected and help is None:
                # In the condition of `if (x() = a)` (`while`, `test`), `==` is the one repair;
                # elsewhere a guess.
                help = "to compare two values write `==`"
                k = self.brackets()[self.file_index(i)]  # the innermost open bracket
                condition = k > 0 and self.original[k].type == "LPAR"
                safe = condition and self.original[k - 1].type in ("IF", "WHILE", "TEST")
                safety = diag.Applicability.SAFE if safe else diag.Applicability.UNSAFE
                if self.reads_on(ss, ["CMP_OP"], i + 1):
                    fix = diag.Fix("write `==`", (diag.Edit(self.span(tok), "=="),), safety)
            elif deleting and help is None:
                if self.reads_on(ss, [], i + 1):
                    fix = diag.Fix(f"remove {describe_found(tok)}", (diag.Edit(self.span(tok), ""),))
            else:
                fix = self.keyword_fix(i, ss, help, expected)
        self.report(
            i,
            diag.error(
                message,
                self.span(tok),
                "unexpected " + ("token" if tok.type != "$END" else "end of file"),
                help=help,
                fix=fix,
            ),
        )

    def keyword_hint(self, i: int, expected: set[str]) -> str | None:
        """`did you mean `procedure`?` when a name near the error looks like a keyword: of the
        names on the error's line (and the error token), the one most similar to a keyword."""
        found = self.keyword_guess(i, expected)
        if found is None:
            return None
        word = found[0]
        return f"did you mean `{word}:`?" if word in SECTION_WORDS else f"did you mean `{word}`?"

    def keyword_fix(self, i: int, ss: list[int], help: str | None, expected: set[str]) -> diag.Fix | None:
        """The keyword hint as a fix replacing the misspelled name (a guess: unsafe); its
        message is the hint, so the text output shows the hint once."""
        found = self.keyword_guess(i, expected)
        if found is None or help is None:
            return None
        word, tok = found
        if word in SECTION_WORDS:
            # `efect:` where a section can start: the name becomes the section word; anywhere
            # else the hint is a guess that no one edit makes right.
            at_section = tok is self.tokens[i] and SECTION_WORDS[word] in expected
            if not (at_section and i + 1 < len(self.tokens) and self.tokens[i + 1].type == "COLON"):
                return None
        if tok is self.tokens[i] and not self.reads_on(ss, [_WORD_TYPES[word]], i + 1):
            return None
        if tok is not self.tokens[i] and not self.fixes_up_to(tok, word, i):
            return None
        return diag.Fix(help, (diag.Edit(self.span(tok), word),), diag.Applicability.UNSAFE)

    def fixes_up_to(self, tok: Token, word: str, i: int) -> bool:
        """Does writing `word` for `tok` (a token before the error at token i, read already)
        leave no syntax error from `tok` to the end of the probe after token i? Tried by
        parsing the file so edited, at most `_FIX_TRIALS` times per file; past that, and in
        long files, the guess is not offered as a fix."""
        if self.fix_trials <= 0 or len(self.source.text) > _FIX_TRIAL_SIZE:
            return False
        self.fix_trials -= 1
        text = self.source.text
        edited = text[: tok.start] + word + text[tok.end :]
        end = self.tokens[min(i + _PROBE, len(self.tokens) - 1)].end + len(word) - (tok.end - tok.start)
        result = parse(Source(edited, self.source.path), _check_fixes=False)
        return not any(d.is_error and tok.start <= d.span.start <= end for d in result.diagnostics)

    def keyword_guess(self, i: int, expected: set[str]) -> tuple[str, Token] | None:
        """The keyword, and the name near token `i` it is most likely a misspelling of."""
        line = self.source.line_col(self.tokens[i].start)[0]
        best: tuple[float, str, Token] | None = None
        for k in range(max(0, i - 12), i + 1):
            t = self.tokens[k]
            if t.type != "NAME" or not t.value or self.source.line_col(t.start)[0] < line - 1:
                continue
            words = _SUGGESTABLE_KEYWORDS
            if k > 0 and self.tokens[k - 1].type not in _STARTS_AFTER:
                # A section word (`efect:`) follows the end of an expression too, where the
                # parser expects one.
                if k + 1 >= len(self.tokens) or self.tokens[k + 1].type != "COLON":
                    continue
                words = [w for w in _SECTION_LIST if SECTION_WORDS[w] in expected]
            for word in difflib.get_close_matches(t.value, words, n=1, cutoff=0.75):
                ratio = difflib.SequenceMatcher(None, t.value, word).ratio()
                if best is None or ratio > best[0]:
                    best = (ratio, word, t)
        return (best[1], best[2]) if best is not None else None

    def span(self, tok: Token) -> Span:
        return Span(self.source, tok.start, tok.end)
