"""Names that older golog++ accepted and gpp does not, renamed on the tokens before the parser.

* E0047 a global name declared twice with different numbers of parameters (`symbol fluent
  game_state()` beside `exog_action game_state(number t, ...)`): golog++ before 2020 told the
  two apart by their arity, gpp gives a name one declaration. Every declaration but the
  first's arity gets a new name, and so does every call with its number of arguments.
* E0013 a type word naming a parameter (`action say(string string)`): the parameter and its
  uses in its declaration become `string_`.

Each rename is a fix only when every use is certain: a call whose number of arguments is one
of the declared arities; a use of the parameter where an expression stands. Otherwise the
error is reported without a fix (and the parser's own recovery takes over for E0013).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.codes import E0013, E0047
from gpp.syntax.lexer import Token

_DECLARES = frozenset({"FLUENT", "FUNCTION", "EXOG_FUNCTION", "ACTION", "EXOG_ACTION", "PROCEDURE"})
# The word a renamed declaration's new name ends with, by its kind.
_SUFFIXES = {
    "FLUENT": "fluent",
    "FUNCTION": "function",
    "EXOG_FUNCTION": "exog",
    "ACTION": "action",
    "EXOG_ACTION": "event",
    "PROCEDURE": "procedure",
}
# Type words that a legacy program used as parameter names.
_TYPE_WORDS = frozenset({"STRING_KW", "NUMBER_KW", "BOOL", "SYMBOL"})
_TYPE_ENDS = frozenset({"NAME", "BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "RBRACKET", "SIGIL"})
# What may follow a name that stands for a value (`text = string;`, `f(string, 1)`).
_AFTER_VALUE = frozenset(
    {
        "RPAR",
        "RBRACKET",
        "RBRACE",
        "COMMA",
        "SEMI",
        "CMP_OP",
        "ADD_OP",
        "MUL_OP",
        "POW",
        "AMP",
        "BAR",
        "DOT",
        "LBRACKET",
    }
)


@dataclass(frozen=True)
class _Declaration:
    keyword: Token
    name: Token
    arity: int
    open_: int  # the index of its parameter list's `(`
    forward: bool  # a declaration ended by `;` that a definition follows or precedes


def rename_legacy_names(source: Source, tokens: list[Token]) -> tuple[list[Token], list[diag.Diagnostic]]:
    """The tokens with overloaded globals and type words naming parameters renamed where that
    is certain, and an error for each."""
    types = [t.type for t in tokens]
    declared = [tokens[i + 1].value for kind in _DECLARES for i in positions(types, kind) if i + 1 < len(types)]
    overloaded = len(set(declared)) < len(declared)
    reserved = any(
        0 < i < len(types) - 1 and types[i - 1] in _TYPE_ENDS and types[i + 1] in ("COMMA", "RPAR")
        for kind in _TYPE_WORDS
        for i in positions(types, kind)
    )
    if not overloaded and not reserved:
        return tokens, []
    declarations = _declarations(tokens)
    names = {t.value for t in tokens if t.type == "NAME"}
    renamer = _Renamer(source, list(tokens), names)
    if overloaded:
        renamer.overloads(declarations)
    if reserved:
        for d in declarations:
            renamer.reserved_parameters(d)
    return renamer.tokens, renamer.diagnostics


def positions(types: list[str], kind: str) -> Iterator[int]:
    """The indices of `kind` in `types`, found by `list.index` (a scan in C)."""
    i = -1
    while True:
        try:
            i = types.index(kind, i + 1)
        except ValueError:
            return
        yield i


def _declarations(tokens: list[Token]) -> list[_Declaration]:
    """The top-level declarations with a parameter list, in order."""
    found: list[_Declaration] = []
    depth = 0
    for i, t in enumerate(tokens):
        kind = t.type
        if kind in ("LBRACE", "MAIN_LBRACE"):
            depth += 1
        elif kind == "RBRACE":
            depth = max(depth - 1, 0)
        elif (
            depth == 0
            and kind in _DECLARES
            and i + 2 < len(tokens)
            and tokens[i + 1].type == "NAME"
            and tokens[i + 2].type == "LPAR"
        ):
            params = _arguments(tokens, i + 2)
            if params is not None:
                close = params[1]
                forward = kind != "EXOG_FUNCTION" and close + 1 < len(tokens) and tokens[close + 1].type == "SEMI"
                found.append(_Declaration(t, tokens[i + 1], len(params[0]), i + 2, forward))
    return found


def _arguments(tokens: list[Token], open_: int) -> tuple[list[list[int]], int] | None:
    """The token indices of each argument (or parameter) of the list that opens at `open_`,
    and the index of its `)`; None when it is not closed."""
    items: list[list[int]] = [[]]
    depth = 0
    for j in range(open_ + 1, len(tokens)):
        kind = tokens[j].type
        if kind in ("LPAR", "LBRACKET", "LBRACE", "MAIN_LBRACE"):
            depth += 1
        elif kind in ("RPAR", "RBRACKET", "RBRACE"):
            if depth == 0:
                if kind != "RPAR":
                    return None
                return ([] if items == [[]] else items), j
            depth -= 1
        elif kind == "SEMI" and depth == 0:
            return None
        if kind == "COMMA" and depth == 0:
            items.append([])
        else:
            items[-1].append(j)
    return None


def _arity(tokens: list[Token], open_: int) -> int | None:
    found = _arguments(tokens, open_)
    return None if found is None else len(found[0])


class _Renamer:
    def __init__(self, source: Source, tokens: list[Token], names: set[str]) -> None:
        self.source = source
        self.tokens = tokens
        self.names = names
        self.diagnostics: list[diag.Diagnostic] = []

    def span(self, t: Token) -> Span:
        return Span(self.source, t.start, t.end)

    def fresh(self, name: str) -> str:
        while name in self.names:
            name += "_"
        self.names.add(name)
        return name

    def rename(self, at: Iterable[int], name: str) -> tuple[diag.Edit, ...]:
        edits = []
        for i in at:
            t = self.tokens[i]
            self.tokens[i] = Token("NAME", name, t.start, t.end)
            edits.append(diag.Edit(self.span(t), name))
        return tuple(edits)

    # E0047
    def overloads(self, declarations: list[_Declaration]) -> None:
        by_name: dict[str, list[_Declaration]] = {}
        for d in declarations:
            by_name.setdefault(d.name.value, []).append(d)
        for name, group in by_name.items():
            if any(d.forward for d in group) and len({d.keyword.type for d in group}) == 1:
                continue  # a declaration and its definition that disagree: E0303
            kept = group[0].arity
            renamed: dict[int, tuple[_Declaration, str]] = {}
            for d in group:
                if d.arity != kept and d.arity not in renamed:
                    suffix = _SUFFIXES[d.keyword.type]
                    if any(o.keyword.type == d.keyword.type for o in group if o.arity not in (d.arity, kept)):
                        suffix += str(d.arity)
                    renamed[d.arity] = (d, self.fresh(f"{name}_{suffix}"))
            if renamed:
                self.overload(name, kept, renamed)

    def overload(self, name: str, kept: int, renamed: dict[int, tuple[_Declaration, str]]) -> None:
        """Rename the declarations in `renamed` (by arity) and every call with their arity."""
        uses: dict[int, list[int]] = {arity: [] for arity in renamed}
        certain = True
        for i, t in enumerate(self.tokens):
            if t.type != "NAME" or t.value != name:
                continue
            called = i + 1 < len(self.tokens) and self.tokens[i + 1].type == "LPAR"
            arity = _arity(self.tokens, i + 1) if called else None
            if arity in uses:
                uses[arity].append(i)
            elif arity != kept:
                certain = False  # a bare name or a call that matches no declaration
        edits: list[diag.Edit] = []
        for arity, (_, new_name) in sorted(renamed.items()):
            edits.extend(self.rename(uses[arity], new_name))
        first, first_name = min(renamed.values(), key=lambda r: r[0].name.start)
        arities = " and ".join(str(a) for a in sorted({kept, *renamed}))
        new_names = ", ".join(f"`{new}`" for _, new in sorted(renamed.values(), key=lambda r: r[0].name.start))
        self.diagnostics.append(
            diag.error(
                E0047.overloaded(name, arities),
                self.span(first.name),
                f"a second `{name}`, with {first.arity} parameters",
                notes=[
                    "golog++ before 2020 told declarations apart by their number of parameters; "
                    "in gpp a name has one declaration"
                ],
                help=f"rename the {first.keyword.value} and the calls with {first.arity} arguments to "
                f"`{first_name}` (`gpp explain {E0047.code}`)"
                if len(renamed) == 1
                else f"rename the declarations with other numbers of parameters and their calls to {new_names} "
                f"(`gpp explain {E0047.code}`)",
                fix=diag.Fix(f"rename to {new_names}", tuple(edits), diag.Applicability.SAFE) if certain else None,
            )
        )

    # E0013
    def reserved_parameters(self, declaration: _Declaration) -> None:
        found = _arguments(self.tokens, declaration.open_)
        if found is None:
            return
        params, close = found
        for param in params:
            if len(param) < 2:
                continue
            word, before = self.tokens[param[-1]], self.tokens[param[-2]]
            if word.type not in _TYPE_WORDS or before.type not in _TYPE_ENDS:
                continue
            uses = self.parameter_uses(word, close)
            if uses is None:
                continue  # not certain: the parser reports it
            new_name = self.fresh(f"{word.value}_")
            edits = self.rename([param[-1], *uses], new_name)
            self.diagnostics.append(
                diag.error(
                    E0013.reserved(word.value),
                    self.span(word),
                    "reserved word",
                    help=f"rename the parameter and its uses to `{new_name}`",
                    fix=diag.Fix(f"rename the parameter to `{new_name}`", edits, diag.Applicability.SAFE),
                )
            )

    def parameter_uses(self, word: Token, close: int) -> list[int] | None:
        """The indices of the uses of the parameter `word` in the body of its declaration (whose
        parameter list ends at `close`), or None when one of them may not be the parameter."""
        end = self.declaration_end(close)
        uses = []
        for k in range(close + 1, end):
            t = self.tokens[k]
            if t.type != word.type:
                continue
            after = self.tokens[k + 1].type if k + 1 < len(self.tokens) else "$END"
            if after == "NAME" or (after == "LPAR" and t.type == "SYMBOL"):
                continue  # a type, `string s`
            if after not in _AFTER_VALUE:
                return None
            uses.append(k)
        return uses

    def declaration_end(self, close: int) -> int:
        """The index after the declaration whose parameter list closes at `close`: its block's
        `}`, or (a function's `= expression`) the type of the next declaration."""
        tokens = self.tokens
        depth = 0
        for k in range(close + 1, len(tokens)):
            kind = tokens[k].type
            if kind in ("LBRACE", "MAIN_LBRACE"):
                depth += 1
            elif kind == "RBRACE":
                depth -= 1
                if depth == 0:
                    return k + 1
            elif depth == 0 and kind in (*_DECLARES, "DOMAIN", "COMPOUND"):
                # the next declaration's type: `number`, `Room`, `list[number]`
                if tokens[k - 1].type == "RBRACKET":
                    while k > close + 1 and tokens[k - 1].type != "LIST":
                        k -= 1
                    return k - 1
                return k - 1 if tokens[k - 1].type in (*_TYPE_WORDS, "NAME") else k
        return len(tokens)
