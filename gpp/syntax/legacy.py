"""Older golog++ syntax, still found in public agents, recognised and rewritten to the modern form.

The tokenizer's output is rewritten before the parser sees it, so a legacy construct is one
error (E0040-E0045, each with a `Fix` whose edits write the modern form) and not a cascade of
syntax errors; the rest of the file is checked as if it were modern. The forms:

* E0040 type sigils: `%fluent`, `?function`, `$domain`, `§domain`, parameters `%x`, and a
  sigil before a name in an expression (`on(%x)`): `%` number, `?` bool, `$` string,
  `§` symbol;
* E0041 an unquoted mapping name: `mapping: move_base { ... }`;
* E0042 `senses: f()` without an assignment (the action's result went into the fluent);
* E0043 a `domain:` section restricting parameters (`domain: room in rooms;`);
* E0044 a function with a block body of `return` statements;
* E0045 an `exog_function` with a body;
* E0049 a variable of `exists`, `forall` or `pick` over every number (2018's `exists (%z)`):
  typed with a `number domain` of the numbers the program's fluents and literals give;
* E0051 a variable a 2018 procedure assigns (`%y = 1;`) that nothing declares: a fluent of no
  parameters, and each use of the variable in the procedure a call of it;
* E0046 a variable of `exists`, `forall` or `pick` without a type (`exists(z) loc(z) == x`,
  `pick (x in {a, b})`), as the 2019 sigil syntax leaves it once its sigils are removed: typed
  by its use (an argument of a fluent, function or action whose parameter has a type, or
  compared with a typed parameter), else by the values of a literal `in {...}` set.

Every fix is safe (`gpp check --fix` applies it): its edits write exactly the modern program
that the rewrite hands the parser, so the fixed file means what gpp already took the legacy one
to mean. Each fix is whole on its own: E0040 writes every sigil of the file, also those inside
a `domain:` section or a function body that E0043 or E0044 rewrites as a whole, so the fixes
overlap there and `--fix` applies the second in its next round.
E0047 (overloaded names) and E0013 (a type word as a parameter name) are in
gpp.syntax.legacy_names.

Everything here works on tokens (gpp.syntax.lexer.Token): the parser and the grammar do not
know about legacy syntax.
"""

from __future__ import annotations

from collections.abc import Iterator

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.codes import E0040, E0041, E0042, E0043, E0044, E0045, E0046, E0048, E0049, E0050, E0051
from gpp.syntax.legacy_names import positions, rename_legacy_names
from gpp.syntax.lexer import SECTION_WORDS, Token

SIGIL_TYPES = {
    "%": ("number", "NUMBER_KW"),
    "?": ("bool", "BOOL"),
    "$": ("string", "STRING_KW"),
    "§": ("symbol", "SYMBOL"),
}
_SECTIONS = frozenset(SECTION_WORDS.values())
_ENDS_SECTION = _SECTIONS | {"SEMI"}
_TYPE_TOKENS = frozenset({"NAME", "BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "VOID"})
_DECLARES = frozenset({"FLUENT", "FUNCTION", "EXOG_FUNCTION", "DOMAIN", "ACTION", "EXOG_ACTION", "PROCEDURE"})
# Declarations that start with a type.
_TYPED = frozenset({"FLUENT", "FUNCTION", "EXOG_FUNCTION", "DOMAIN"})
# Tokens after which `%` is the remainder operator, not a sigil.
_ENDS_OPERAND = frozenset({"NAME", "RPAR", "RBRACKET", "NUMBER", "STRING", "TRUE", "FALSE", "NULL"})


def modernize(source: Source, tokens: list[Token]) -> tuple[list[Token], list[diag.Diagnostic]]:
    """The tokens with every legacy construct rewritten, and one error per construct (one for
    all the sigils of a file). Modern files cost a scan of the token types for the few places
    a legacy form can start."""
    tokens, renamed = rename_legacy_names(source, tokens)
    types = [t.type for t in tokens]
    has_sigils = "SIGIL" in types or ("MUL_OP" in types and _percent_sigil(tokens, types))
    if not has_sigils and not _structural_candidates(types):
        return tokens, renamed
    rewriter = _Rewriter(source)
    if has_sigils:
        tokens = rewriter.sigils(tokens)
    tokens = rewriter.structure(tokens)
    if _untyped_variables(tokens):
        tokens = rewriter.variables(tokens)
    if has_sigils and "EQ" in types:
        tokens = rewriter.procedure_variables(tokens)
    if any(rewriter.text[k] == "§" for k in rewriter.sigil_edits) and "DOMAIN" not in types:
        tokens = rewriter.implicit_symbols(tokens)
    rewriter.report_sigils()
    return tokens, renamed + rewriter.diagnostics


def _percent_sigil(tokens: list[Token], types: list[str]) -> bool:
    return any(
        tokens[i].value == "%"
        and i + 1 < len(tokens)
        and tokens[i + 1].start == tokens[i].end
        and (types[i + 1] == "NAME" or types[i + 1] in _DECLARES)
        for i in positions(types, "MUL_OP")
    )


def _untyped_variables(tokens: list[Token]) -> bool:
    """Whether a variable of `exists`, `forall` or `pick` is written without a type."""
    return any(i > 0 and _untyped_variable(tokens, i) for i, t in enumerate(tokens) if t.type == "LPAR")


def _untyped_variable(tokens: list[Token], i: int) -> bool:
    """Whether the `(` at `i` opens `exists (z)`, `forall (z)`, `pick (x in ...)` or `pick (x)`."""
    before = tokens[i - 1].type
    if before not in ("QUANTIFIER", "PICK") or i + 2 >= len(tokens) or tokens[i + 1].type != "NAME":
        return False
    after = tokens[i + 2].type
    # `pick (x in {a, b})` over a literal set; `pick (x in D)` is the binding written the wrong
    # way round (`pick (D x)`), which the parser's recovery turns about
    return after == "RPAR" or (before == "PICK" and after == "IN" and _is_kind(tokens, i + 3, "LBRACE"))


def _structural_candidates(types: list[str]) -> bool:
    n = len(types)
    for i in positions(types, "LPAR"):
        # `exists (z)`, `pick (x in ...)`: a variable without a type
        if (
            i > 0
            and types[i - 1] in ("QUANTIFIER", "PICK")
            and i + 2 < n
            and types[i + 1] == "NAME"
            and (
                types[i + 2] == "RPAR"
                or (types[i - 1] == "PICK" and types[i + 2] == "IN" and i + 3 < n and types[i + 3] == "LBRACE")
            )
        ):
            return True
    for i in positions(types, "FLUENT"):
        # `number fluent on(number x) = 0;`: an initial value after the head
        close = types.index("RPAR", i) if "RPAR" in types[i:] else n
        if close + 1 < n and types[close + 1] == "EQ":
            return True
    if any(i + 1 < n and types[i + 1] == "NAME" for i in positions(types, "MAPPING")):
        return True
    for i in positions(types, "SENSES"):
        # `senses: f(...) = ...;` is modern: an `=` before the `;` (or the section's end)
        j = i + 1
        while j < n and types[j] not in ("EQ", "SEMI", "RBRACE") and types[j] not in _SECTIONS:
            j += 1
        if j == n or types[j] != "EQ":
            return True
    if any(i + 1 < n and types[i + 1] == "COLON" for i in positions(types, "DOMAIN")):
        return True
    for kind in ("FUNCTION", "EXOG_FUNCTION"):
        for i in positions(types, kind):
            j = i + 2
            if j < n and types[j] == "LPAR":
                try:
                    close = types.index("RPAR", j)
                except ValueError:
                    continue
                if close + 1 < n and types[close + 1] == "LBRACE":
                    return True
    return False


def _type_start(out: list[Token]) -> int:
    """Where the type that ends `out` starts (`number`, `Room`, `list[list[number]]`)."""
    if out and out[-1].type == "RBRACKET":
        j = len(out) - 1
        while j > 0 and out[j].type != "LIST":
            j -= 1
        while j > 1 and out[j - 1].type == "LBRACKET" and out[j - 2].type == "LIST":
            j -= 2
        return j
    return len(out) - 1 if out and out[-1].type in _TYPE_TOKENS else len(out)


def _declared_name(head: list[Token]) -> str:
    """The name a declaration's head declares: the name after its keyword."""
    for i, t in enumerate(head[:-1]):
        if t.type in _DECLARES:
            return head[i + 1].value
    return ""


def _synthetic(type: str, value: str, at: int, end: int | None = None) -> Token:
    return Token(type, value, at, at if end is None else end)


class _Rewriter:
    def __init__(self, source: Source) -> None:
        self.source = source
        self.text = source.text
        self.diagnostics: list[diag.Diagnostic] = []
        # The edits that write each sigil's type, by the sigil's offset; a `domain:` section
        # may replace one with its domain.
        self.sigil_edits: dict[int, diag.Edit] = {}
        self.first_sigil: Token | None = None
        # An edit that E0040's fix makes with its sigils: the declaration of the symbols that
        # the `§` sigils took for granted (E0050), which the file no longer says once they go.
        self.sigil_declarations: list[diag.Edit] = []

    def span(self, start: int, end: int) -> Span:
        return Span(self.source, start, end)

    def edit(self, start: int, end: int, text: str) -> diag.Edit:
        return diag.Edit(self.span(start, end), text)

    def modern_text(self, start: int, end: int) -> str:
        """The source text from `start` to `end` with the sigil edits inside it applied."""
        text = self.text[start:end]
        for offset in sorted((k for k in self.sigil_edits if start <= k < end), reverse=True):
            e = self.sigil_edits[offset]
            text = text[: e.span.start - start] + e.text + text[e.span.end - start :]
        return text

    # ---------------------------------------------------------------- E0040 sigils

    def sigils(self, tokens: list[Token]) -> list[Token]:
        out: list[Token] = []
        # Inside the parameter list of a declaration: a sigil there declares a parameter's type.
        params_depth = -1
        depth = 0
        for i, t in enumerate(tokens):
            if t.type == "LPAR":
                depth += 1
                if params_depth < 0 and len(out) >= 2 and out[-1].type == "NAME" and out[-2].type in _DECLARES:
                    params_depth = depth
            elif t.type == "RPAR":
                if depth == params_depth:
                    params_depth = -1
                depth -= 1
            nxt = tokens[i + 1] if i + 1 < len(tokens) else None
            is_sigil = t.type == "SIGIL" or (
                t.value == "%"
                and nxt is not None
                and nxt.start == t.end
                and (
                    nxt.type in _DECLARES  # `%function`: never a remainder, a keyword is no operand
                    or (nxt.type == "NAME" and (not out or out[-1].type not in _ENDS_OPERAND))
                )
            )
            if not is_sigil:
                out.append(t)
                continue
            self.first_sigil = self.first_sigil or t
            type_name, type_token = SIGIL_TYPES[t.value]
            if nxt is not None and (nxt.type in _DECLARES or params_depth == depth):
                out.append(Token(type_token, type_name, t.start, t.end))
                self.sigil_edits[t.start] = self.edit(t.start, t.end, type_name + " ")
            else:
                self.sigil_edits[t.start] = self.edit(t.start, t.end, "")
        return out

    def report_sigils(self) -> None:
        first = self.first_sigil
        if first is None:
            return
        edits = (*self.sigil_declarations, *(self.sigil_edits[k] for k in sorted(self.sigil_edits)))
        more = len(self.sigil_edits) - 1
        self.diagnostics.append(
            diag.error(
                E0040.sigil(first.value),
                self.span(first.start, first.end),
                "legacy type sigil",
                notes=[
                    "golog++ writes the type as a word: `%` is `number`, `?` `bool`, `$` `string`, `§` `symbol`"
                    + (f"; {more} more sigil{'s' if more > 1 else ''} in this file" if more else "")
                ],
                help=f"write the type names instead (`gpp explain {E0040.code}`)",
                fix=diag.Fix("write the types as words", edits, diag.Applicability.SAFE),
            )
        )

    # ---------------------------------------------------------------- the other forms

    def structure(self, tokens: list[Token]) -> list[Token]:
        out: list[Token] = []
        i = 0
        n = len(tokens)
        declaration_start = 0  # index in `out` where the current top-level declaration starts
        depth = 0
        while i < n:
            t = tokens[i]
            if depth == 0 and t.type in _DECLARES:
                declaration_start = _type_start(out) if t.type in _TYPED else len(out)
            if t.type == "MAPPING" and i + 2 < n and tokens[i + 1].type == "NAME" and tokens[i + 2].type == "LBRACE":
                out.append(t)
                out.append(self.mapping_name(tokens[i + 1]))
                i += 2
                continue
            if t.type == "SENSES":
                end = self.section_end(tokens, i + 1)
                # `senses: f(x)` without its `;`: the action's last item, or another section follows
                last = end is not None and tokens[end].type != "SEMI"
                if end is not None and not any(tok.type == "EQ" for tok in self.top_level(tokens, i + 1, end)):
                    out.append(t)
                    out.extend(self.senses(tokens, i + 1, end, out, declaration_start, last))
                    i = end if last else end + 1
                    continue
            if t.type == "DOMAIN" and i + 1 < n and tokens[i + 1].type == "COLON" and depth > 0:
                end = self.statement_end(tokens, i + 2)
                if end is not None:
                    end = self.domain_entries_end(tokens, end)
                    self.domain_section(tokens, i, end, out, declaration_start)
                    i = end + 1
                    continue
            if t.type == "LBRACE" and depth == 0 and out and out[-1].type == "RPAR":
                head = out[declaration_start:]
                kind = next((h.type for h in head if h.type in _DECLARES), None)
                close = self.matching(tokens, i) if kind in ("FUNCTION", "EXOG_FUNCTION") else None
                if close is not None:
                    if kind == "FUNCTION":
                        out.extend(self.function_body(tokens, i, close, _declared_name(head)))
                    else:
                        out.append(self.exog_function_body(tokens, i, close, _declared_name(head)))
                    i = close + 1
                    continue
            if (
                t.type == "EQ"
                and depth == 0
                and out
                and out[-1].type == "RPAR"
                and self.declaration_kind(out, declaration_start) == "FLUENT"
            ):
                end = _initial_value_end(tokens, i + 1)
                if end > i + 1:
                    out.extend(self.initial_value(tokens, i, end, out[declaration_start:]))
                    i = end + 1 if _is_kind(tokens, end, "SEMI") else end
                    continue
            if t.type in ("LBRACE", "MAIN_LBRACE"):
                depth += 1
            elif t.type == "RBRACE":
                depth = max(depth - 1, 0)
            out.append(t)
            i += 1
        return out

    def statement_end(self, tokens: list[Token], i: int) -> int | None:
        """The index of the `;` that ends the statement starting at `i` (outside brackets), or
        None when a `}` or the end comes first."""
        depth = 0
        for j in range(i, len(tokens)):
            kind = tokens[j].type
            if kind in ("LPAR", "LBRACKET", "LBRACE"):
                depth += 1
            elif kind in ("RPAR", "RBRACKET", "RBRACE"):
                if depth == 0:
                    return None
                depth -= 1
            elif kind == "SEMI" and depth == 0:
                return j
        return None

    def section_end(self, tokens: list[Token], i: int) -> int | None:
        """The index of the token that ends the section starting at `i`: its `;`, or, when it
        has none, the action's `}` or the next section's word (`mapping:`); None when nothing
        is there to end it."""
        depth = 0
        for j in range(i, len(tokens)):
            kind = tokens[j].type
            if kind in ("LPAR", "LBRACKET", "LBRACE"):
                depth += 1
            elif kind in ("RPAR", "RBRACKET"):
                depth -= 1
            elif kind == "RBRACE":
                if depth == 0:
                    return j if j > i else None
                depth -= 1
            elif depth == 0 and (kind in _ENDS_SECTION or (kind == "DOMAIN" and _is_kind(tokens, j + 1, "COLON"))):
                return j if j > i else None
            elif kind == "COLON" and depth == 0:
                return None
        return None

    def domain_entries_end(self, tokens: list[Token], end: int) -> int:
        """The `;` of the last entry of a `domain:` section whose first entry ends at `end`:
        `domain: x in blocks; y in locations;` has one entry a line, each ending in `;`."""
        while True:
            j = end + 1
            if j < len(tokens) and tokens[j].type in _TYPE_TOKENS - {"NAME"}:
                j += 1  # `symbol y in locations;`
            if not (j + 2 < len(tokens) and tokens[j].type == "NAME" and tokens[j + 1].type == "IN"):
                return end
            following = self.statement_end(tokens, j)
            if following is None:
                return end
            end = following

    def top_level(self, tokens: list[Token], start: int, end: int) -> Iterator[Token]:
        depth = 0
        for t in tokens[start:end]:
            if t.type in ("LPAR", "LBRACKET", "LBRACE"):
                depth += 1
            elif t.type in ("RPAR", "RBRACKET", "RBRACE"):
                depth -= 1
            elif depth == 0:
                yield t

    def matching(self, tokens: list[Token], i: int) -> int | None:
        """The index of the `}` that closes the brace at or after `i`."""
        return _closing(tokens, i, ("LBRACE", "MAIN_LBRACE"), "RBRACE")

    def declaration_kind(self, out: list[Token], start: int) -> str | None:
        return next((t.type for t in out[start:] if t.type in _DECLARES), None)

    # E0046
    def variables(self, tokens: list[Token]) -> list[Token]:
        """Each untyped variable of `exists`, `forall` and `pick` gets the type its use or its
        `in {...}` values give it (see `variable_type`); one without is an
        error without a fix, read on as `symbol`."""
        signatures = _signatures(tokens)
        numbers = _ProgramNumbers(tokens, signatures)
        out: list[Token] = []
        for i, t in enumerate(tokens):
            if t.type == "NAME" and i > 1 and tokens[i - 1].type == "LPAR" and _untyped_variable(tokens, i - 1):
                found = self.variable_type(tokens, i, signatures)
                unbounded = found is not None and tokens[i + 1].type != "IN"
                if unbounded and found is not None and _type_text(found[0]) == "number" and numbers.values:
                    # E0049 with a fix: the numbers the program's fluents and literals give
                    out.append(_synthetic("NAME", numbers.name, t.start))
                    numbers.variables.append((tokens[i - 2], t, found[1]))
                elif unbounded and found is not None and _type_text(found[0]) in ("number", "string"):
                    # E0049 without a fix: every number, as its use types it (its sigil's edit
                    # only removes the sigil, so the fixed file says the same)
                    out.extend(_synthetic(k.type, k.value, t.start) for k in found[0])
                    self.report_unbounded(tokens[i - 2], t, _type_text(found[0]), found[1])
                elif found is not None:
                    type_tokens, how = found
                    out.extend(_synthetic(k.type, k.value, t.start) for k in type_tokens)
                    self.report_variable(tokens[i - 2], t, _type_text(type_tokens), how)
                else:
                    # no fix; a type the parser reads on (a program with errors is not checked further)
                    out.append(_synthetic("SYMBOL", "symbol", t.start))
                    self.report_variable(tokens[i - 2], t, None, "")
            out.append(t)
        if not numbers.variables or not out:
            return out
        self.report_ranged(numbers)
        start = out[0].start
        sign = [_synthetic("ADD_OP", "-", start)]
        members = [
            sign * value.startswith("-") + [_synthetic("NUMBER", value.lstrip("-"), start)] for value in numbers.values
        ]
        return [*_domain_declaration("NUMBER_KW", "number", numbers.name, members, start), *out]

    def variable_type(
        self, tokens: list[Token], at: int, signatures: dict[str, list[list[Token] | None]]
    ) -> tuple[list[Token], str] | None:
        """The type of the variable at `at` and how it was found: the parameter type of the first
        fluent, function or action it is an argument of, else of a parameter it is compared with
        (`==`, `!=`), in the rest of the declaration; else, for `pick (x in {...})`, the type of
        the set's values (`number`, `string`, `bool`, `symbol`); else None."""
        name = tokens[at].value
        params = _enclosing_parameters(tokens, at)
        depth = 0
        for j in range(at + 1, len(tokens)):
            t = tokens[j]
            if t.type in ("LBRACE", "MAIN_LBRACE"):
                depth += 1
            elif t.type == "RBRACE":
                depth -= 1
                if depth < 0:
                    break
            elif depth == 0 and t.type in _DECLARES:
                break
            if t.type != "NAME" or t.value != name:
                continue
            call = _argument_of(tokens, j)
            if call is not None:
                callee, position = call
                declared = signatures.get(callee)
                if declared is not None and position < len(declared) and declared[position] is not None:
                    return list(declared[position] or ()), f"it is argument {position + 1} of `{callee}`"
            compared = [
                tokens[k]
                for k, op in ((j - 2, j - 1), (j + 2, j + 1))
                if 0 <= k < len(tokens) and tokens[op].type == "CMP_OP" and tokens[op].value in ("==", "!=")
            ]
            for other in compared:
                if other.type == "NAME" and other.value in params:
                    return params[other.value], f"it is compared with the parameter `{other.value}`"
        if tokens[at + 1].type == "IN":
            kinds = _set_value_types(tokens, at + 2)
            if kinds is not None:
                return kinds, "the values it is picked from"
        return None

    # E0049
    def report_unbounded(self, keyword: Token, name: Token, type_text: str, how: str) -> None:
        """E0049 for a variable that ranges over every number (or string) where the program names
        no number to range over (`_ProgramNumbers`): no fix, the values are the author's choice.
        The parser reads it with that type (the checker, seeing a type the legacy rewrite wrote,
        does not report E0210 as well)."""
        kind = keyword.value
        pick = "" if kind != "pick" else f", or pick from a list: `pick ({type_text} {name.value} in {{1, 2, 3}})`"
        why = (
            "the program names no number its fluents or literals could give it"
            if type_text == "number"
            else "a string ranges over no set the program could give"
        )
        self.diagnostics.append(
            diag.error(
                E0049.unbounded(kind, name.value, type_text),
                self.span(name.start, name.end),
                f"every {type_text}",
                notes=[f"`{type_text}`: {how}; it has infinitely many values, which cannot all be tried"],
                help=f"{why}, so name them: declare the values it ranges over as a domain, "
                f"`{type_text} domain D = {{...}}`, and write "
                f"`{kind} (D {name.value} ...)`{pick} (`gpp explain {E0049.code}`)",
            )
        )

    def report_ranged(self, numbers: _ProgramNumbers) -> None:
        """One E0049 for all the number variables of the file, with a fix: a `number domain` of
        the numbers the program's fluents and literals give (`_ProgramNumbers`), declared first
        in the file, as each variable's type. A variable that came with a sigil has its sigil's
        edit write the domain, and E0040's fix declares it too (the two fixes overlap, so
        `--fix` applies one of them)."""
        declaration = f"number domain {numbers.name} = {{{', '.join(numbers.values)}}}"
        at = self.text.rfind("\n", 0, numbers.first_start) + 1
        declare = self.edit(at, at, declaration + "\n\n")
        edits = [declare]
        for _, name, _ in numbers.variables:
            sigil_at = next((k for k, e in self.sigil_edits.items() if e.span.end == name.start), None)
            typed = self.edit(name.start if sigil_at is None else sigil_at, name.start, numbers.name + " ")
            if sigil_at is not None:
                self.sigil_edits[sigil_at] = typed
            edits.append(typed)
        if any(e.span.end == name.start for e in self.sigil_edits.values() for _, name, _ in numbers.variables):
            self.sigil_declarations.append(declare)
        keyword, first, how = numbers.variables[0]
        more = len(numbers.variables) - 1
        self.diagnostics.append(
            diag.error(
                E0049.unbounded(keyword.value, first.value, "number"),
                self.span(first.start, first.end),
                "every number",
                notes=[
                    f"`number`: {how}; the golog++ of 2018 tried the values the program's fluents and "
                    f"literals give it: {', '.join(numbers.values)}"
                    + (f"; {more} more such variable{'s' if more > 1 else ''} in this file" if more else "")
                ],
                help=f"declare them as a domain, `{declaration}`, and write "
                f"`{keyword.value} ({numbers.name} {first.value} ...)` (`gpp explain {E0049.code}`)",
                fix=diag.Fix(
                    f"declare the numbers in a domain `{numbers.name}` and type the variables with it",
                    tuple(sorted(edits, key=lambda e: e.span.start)),
                    diag.Applicability.SAFE,
                ),
            )
        )

    def report_variable(self, keyword: Token, name: Token, type_text: str | None, how: str) -> None:
        """E0046 for an untyped variable, with the type as a fix; a variable that came with a
        sigil has its sigil's edit write the type instead (E0040 reports it)."""
        sigil_at = next((k for k, e in self.sigil_edits.items() if e.span.end == name.start), None)
        if sigil_at is not None and type_text is not None:
            self.sigil_edits[sigil_at] = self.edit(sigil_at, name.start, type_text + " ")
            return
        kind = keyword.value
        where = self.span(name.start, name.end)
        if type_text is None:
            self.diagnostics.append(
                diag.error(
                    E0046.untyped(kind, name.value),
                    where,
                    "no type",
                    help=f"write its type before it: `{kind} (T {name.value} ...)` (`gpp explain {E0046.code}`)",
                )
            )
            return
        self.diagnostics.append(
            diag.error(
                E0046.untyped(kind, name.value),
                where,
                "no type",
                notes=[f"`{type_text}`: {how}"],
                help=f"write `{type_text} {name.value}` (`gpp explain {E0046.code}`)",
                fix=diag.Fix(
                    f"write its type `{type_text}`",
                    (self.edit(name.start, name.start, type_text + " "),),
                    diag.Applicability.SAFE,
                ),
            )
        )

    # E0051
    def procedure_variables(self, tokens: list[Token]) -> list[Token]:
        """A variable with a sigil that a procedure (or the main block) assigns, `%y = 1;`, and
        that is neither its parameter nor bound by `pick` or a quantifier: the golog++ of 2018
        made it a variable of the procedure on its first use. gpp has no variables a procedure
        assigns, so each becomes a fluent of no parameters with its type's zero as initial value
        (`number fluent y() { initially: () = 0; }`, before the procedure), and every use of it
        in the procedure is a call, `y()`: one error for each procedure, with that fix."""
        declared = {tokens[k + 1].value for k, t in enumerate(tokens[:-1]) if t.type in _DECLARES}
        inserts: dict[int, list[Token]] = {}
        replaced: dict[int, str] = {}
        for i, t in enumerate(tokens):
            if t.type == "MAIN_LBRACE":
                start, open_, params, where = i, i, set(), "the main block"
            elif t.type == "PROCEDURE" and _is_kind(tokens, i + 1, "NAME") and _is_kind(tokens, i + 2, "LPAR"):
                found = _parameters(tokens, i + 2)
                if found is None or not _is_kind(tokens, found[1] + 1, "LBRACE"):
                    continue
                start, open_, where = i, found[1] + 1, f"procedure `{tokens[i + 1].value}`"
                params = {name for _, name in found[0]}
                if start > 0 and tokens[start - 1].type in _TYPE_TOKENS - {"NAME"}:
                    start -= 1
            else:
                continue
            close = _closing(tokens, open_, ("LBRACE", "MAIN_LBRACE"), "RBRACE")
            if close is None:
                continue
            found_variables = self.assigned_variables(tokens, open_, close, params)
            if not found_variables:
                continue
            declarations: list[str] = []
            header: list[Token] = []
            at = tokens[start].start
            edits: list[diag.Edit] = []
            for name, (type_name, uses) in found_variables.items():
                fluent = name
                while fluent in declared:
                    fluent += "_"
                declared.add(fluent)
                zero = _ZEROS[type_name]
                declarations.append(f"{type_name} fluent {fluent}() {{\ninitially:\n    () = {zero[1]};\n}}")
                header += [
                    _synthetic(_TYPE_KEYWORDS[type_name], type_name, at),
                    _synthetic("FLUENT", "fluent", at),
                    _synthetic("NAME", fluent, at),
                    _synthetic("LPAR", "(", at),
                    _synthetic("RPAR", ")", at),
                    _synthetic("LBRACE", "{", at),
                    _synthetic("INITIALLY", "initially:", at),
                    _synthetic("LPAR", "(", at),
                    _synthetic("RPAR", ")", at),
                    _synthetic("EQ", "=", at),
                    _synthetic(zero[0], zero[1], at),
                    _synthetic("SEMI", ";", at),
                    _synthetic("RBRACE", "}", at),
                ]
                for k, sigil_at in uses:
                    use = tokens[k]
                    replaced[k] = fluent
                    self.sigil_edits[sigil_at] = self.edit(sigil_at, use.end, fluent + "()")
                    edits.append(self.sigil_edits[sigil_at])
            inserts[start] = header
            line = self.text.rfind("\n", 0, at) + 1
            declare = self.edit(line, line, "\n\n".join(declarations) + "\n\n")
            self.sigil_declarations.append(declare)
            first_name, (_, first_uses) = next(iter(found_variables.items()))
            first = tokens[first_uses[0][0]]
            others = len(found_variables) - 1
            self.diagnostics.append(
                diag.error(
                    E0051.assigned(first_name, where),
                    self.span(first.start, first.end),
                    "not declared",
                    notes=[
                        "the golog++ of 2018 made a variable of the procedure on its first use; gpp's "
                        "procedures assign fluents only, so it becomes a fluent that starts at its type's zero"
                        + (f"; {others} more such variable{'s' if others > 1 else ''} here" if others else "")
                    ],
                    help=f"declare `{' '.join(declarations[0].split())}` and write `{first_name}()` for "
                    f"`{first_name}` (`gpp explain {E0051.code}`)",
                    fix=diag.Fix(
                        "declare a fluent for each and call it where the variable was used",
                        (declare, *sorted(edits, key=lambda e: e.span.start)),
                        diag.Applicability.SAFE,
                    ),
                )
            )
        if not inserts:
            return tokens
        out: list[Token] = []
        for k, t in enumerate(tokens):
            out.extend(inserts.get(k, ()))
            if k in replaced:
                out += [_synthetic("NAME", replaced[k], t.start), _synthetic("LPAR", "(", t.end)]
                out.append(_synthetic("RPAR", ")", t.end))
            else:
                out.append(t)
        return out

    def assigned_variables(
        self, tokens: list[Token], open_: int, close: int, known: set[str]
    ) -> dict[str, tuple[str, list[tuple[int, int]]]]:
        """The variables with a number, bool or string sigil assigned as a statement between
        `open_` and `close` that `known` does not name and nothing there binds, by name: the
        sigil's type and every use (token index, sigil offset) there, calls excepted."""
        bound = {
            tokens[k].value
            for k in range(open_ + 2, close)
            if tokens[k].type == "NAME" and tokens[k - 1].type in _TYPE_TOKENS and tokens[k - 2].type == "LPAR"
        }
        sigils = {e.span.end: k for k, e in self.sigil_edits.items()}
        found: dict[str, tuple[str, list[tuple[int, int]]]] = {}
        for k in range(open_ + 1, close):
            t = tokens[k]
            sigil_at = sigils.get(t.start)
            if (
                t.type == "NAME"
                and _is_kind(tokens, k + 1, "EQ")
                and tokens[k - 1].type in ("LBRACE", "MAIN_LBRACE", "SEMI", "RBRACE", "RPAR", "ELSE")
                and sigil_at is not None
                and self.text[sigil_at] in "%?$"
                and t.value not in known | bound
            ):
                found.setdefault(t.value, (SIGIL_TYPES[self.text[sigil_at]][0], []))
        for k in range(open_ + 1, close):
            t = tokens[k]
            sigil_at = sigils.get(t.start)
            if t.type == "NAME" and t.value in found and sigil_at is not None and not _is_kind(tokens, k + 1, "LPAR"):
                found[t.value][1].append((k, sigil_at))
        return found

    # E0048
    def initial_value(self, tokens: list[Token], eq: int, end: int, head: list[Token]) -> list[Token]:
        """`%fluent on(%x) = 0;` (the tokens from its `=` up to `end`, its `;` or what follows
        when it has none) becomes `{ initially: (x) = 0; }`: one entry for every instance."""
        value = tokens[eq + 1 : end]
        open_ = next((k for k, h in enumerate(head) if h.type == "LPAR"), None)
        found = _parameters(head, open_) if open_ is not None else None
        names = [name for _, name in found[0]] if found is not None else []
        name = _declared_name(head)
        value_text = self.modern_text(value[0].start, value[-1].end)
        last = tokens[end] if _is_kind(tokens, end, "SEMI") else value[-1]
        entry = f"({', '.join(names)}) = {value_text};"
        self.diagnostics.append(
            diag.error(
                E0048.initial_value(name),
                self.span(tokens[eq].start, value[-1].end),
                "legacy initial value",
                notes=["the value is every instance's initial value: an `initially:` entry for all of them"],
                help=f"write `{{ initially: {entry} }}` (`gpp explain {E0048.code}`)",
                fix=diag.Fix(
                    "write an `initially:` section",
                    (self.edit(tokens[eq].start, last.end, f"{{\ninitially:\n    {entry}\n}}"),),
                    diag.Applicability.SAFE,
                ),
            )
        )
        at, after = tokens[eq].start, value[-1].end
        section = [
            _synthetic("LBRACE", "{", at),
            _synthetic("INITIALLY", "initially:", at),
            _synthetic("LPAR", "(", at),
        ]
        for k, parameter in enumerate(names):
            if k:
                section.append(_synthetic("COMMA", ",", at))
            section.append(_synthetic("NAME", parameter, at))
        section += [_synthetic("RPAR", ")", at), tokens[eq], *value]
        return [*section, _synthetic("SEMI", ";", after), _synthetic("RBRACE", "}", after)]

    # E0050
    def implicit_symbols(self, tokens: list[Token]) -> list[Token]:
        """In a file of the `§` sigils that declares no domain, the names used as values that
        nothing declares are symbols, as the golog++ of 2018 took them: one error, and a
        domain declaring them all, first in the file."""
        declared = {
            t.value
            for k, t in enumerate(tokens)
            if t.type == "NAME"
            and k > 0
            and (
                tokens[k - 1].type in _TYPE_TOKENS - {"NAME"}
                or tokens[k - 1].type in _DECLARES | {"COMPOUND"}
                or (k > 1 and tokens[k - 1].type == "NAME" and tokens[k - 2].type == "LPAR")  # `exists (numbers z)`
            )
        }
        used: dict[str, Token] = {}
        for k, t in enumerate(tokens):
            if (
                t.type == "NAME"
                and t.value not in declared
                and t.value != "return"
                and not _is_kind(tokens, k + 1, "LPAR")
                and not _is_kind(tokens, k + 1, "EQ")
                and not _is_kind(tokens, k + 1, "NAME")  # a type: `Pose p`
                and not (k > 0 and tokens[k - 1].type == "DOT")
                and not (k > 1 and tokens[k - 1].type == "LBRACKET" and tokens[k - 2].type == "LIST")
                and t.start < t.end
            ):
                used.setdefault(t.value, t)
        if not used or not tokens:
            return tokens
        names = list(used)
        domain = "symbols"
        while domain in declared or domain in used:
            domain += "_"
        first = next(iter(used.values()))
        declaration = f"symbol domain {domain} = {{{', '.join(names)}}}"
        at = self.text.rfind("\n", 0, tokens[0].start) + 1
        declare = self.edit(at, at, declaration + "\n\n")
        self.sigil_declarations.append(declare)
        self.diagnostics.append(
            diag.error(
                E0050.undeclared(first.value, len(names)),
                self.span(first.start, first.end),
                "not declared",
                notes=[
                    "golog++ of 2018 took a name it did not know for a symbol; used so here: "
                    + ", ".join(f"`{n}`" for n in names)
                ],
                help=f"declare them: `{declaration}` (`gpp explain {E0050.code}`)",
                fix=diag.Fix(
                    f"declare the symbols in a domain `{domain}`",
                    # the first use kept as it is: the fix reaches it, so it overlaps E0040's
                    # (which declares the symbols too) and `--fix` does not apply both at once
                    (declare, self.edit(first.start, first.end, first.value)),
                    diag.Applicability.SAFE,
                ),
            )
        )
        start = tokens[0].start
        members = [[_synthetic("NAME", name, start)] for name in names]
        return [*_domain_declaration("SYMBOL", "symbol", domain, members, start), *tokens]

    # E0041
    def mapping_name(self, name: Token) -> Token:
        quoted = f'"{name.value}"'
        self.diagnostics.append(
            diag.error(
                E0041.unquoted(name.value),
                self.span(name.start, name.end),
                "legacy unquoted mapping name",
                help=f"write it as a string: `{quoted}` (`gpp explain {E0041.code}`)",
                fix=diag.Fix(
                    f"quote `{name.value}`", (self.edit(name.start, name.end, quoted),), diag.Applicability.SAFE
                ),
            )
        )
        return Token("STRING", quoted, name.start, name.end)

    # E0042
    def senses(
        self, tokens: list[Token], start: int, end: int, out: list[Token], declaration_start: int, last: bool = False
    ) -> list[Token]:
        """`senses: f(args);` becomes `senses: f(args) = sensed_f();` with a new exogenous
        function of the fluent's type declared before the action. With `last`, the section is
        the action's last item and `end` is the action's `}`: no `;` ended it, one is added."""
        target = tokens[start:end]
        fluent = target[0].value if target and target[0].type == "NAME" else None
        fluent_type = self.fluent_type(tokens, fluent) if fluent else None
        where = self.span(target[0].start, target[-1].end) if target else self.span(tokens[end].start, tokens[end].end)
        if fluent is None or fluent_type is None or not out[declaration_start:]:
            self.diagnostics.append(
                diag.error(
                    E0042.senses(),
                    where,
                    "no value to assign",
                    help="assign the fluent an exogenous function of its type: `senses: f() = sensed_f();` "
                    f"(`gpp explain {E0042.code}`)",
                )
            )
            # Drop the section: the fluent is not sensed, and nothing else is reported.
            out.pop()
            return []
        names = {t.value for t in tokens if t.type == "NAME"}
        function = f"sensed_{fluent}"
        while function in names:
            function += "_"
        action = out[declaration_start]
        line_start = self.text.rfind("\n", 0, action.start) + 1
        type_text = " ".join(t.value for t in fluent_type).replace("[ ", "[").replace(" ]", "]").replace(" [", "[")
        declaration = f"{type_text} exog_function {function}();\n"
        self.diagnostics.append(
            diag.error(
                E0042.senses(),
                where,
                "no value to assign",
                notes=[
                    "the sensing result comes from an exogenous function: the platform answers it with the "
                    "action's result, whatever its name"
                ],
                help=f"write `senses: {self.modern_text(where.start, where.end)} = {function}();` and declare "
                f"`{declaration.strip()}` (`gpp explain {E0042.code}`)",
                fix=diag.Fix(
                    f"assign the result of a new exogenous function `{function}`",
                    (
                        self.edit(line_start, line_start, declaration),
                        self.edit(where.end, where.end, f" = {function}()" + (";" if last else "")),
                    ),
                    diag.Applicability.SAFE,
                ),
            )
        )
        # The declaration goes before the action, the assignment into the section.
        at = action.start
        declared = [_synthetic(t.type, t.value, at) for t in fluent_type] + [
            _synthetic("EXOG_FUNCTION", "exog_function", at),
            _synthetic("NAME", function, at),
            _synthetic("LPAR", "(", at),
            _synthetic("RPAR", ")", at),
            _synthetic("SEMI", ";", at),
        ]
        out[declaration_start:declaration_start] = declared
        e = where.end
        return [
            *target,
            _synthetic("EQ", "=", e),
            _synthetic("NAME", function, e),
            _synthetic("LPAR", "(", e),
            _synthetic("RPAR", ")", e),
            _synthetic("SEMI", ";", e) if last else tokens[end],
        ]

    def fluent_type(self, tokens: list[Token], fluent: str) -> list[Token] | None:
        """The type tokens of the fluent `fluent` declared in this file, or None."""
        for i, t in enumerate(tokens):
            if t.type == "FLUENT" and i + 1 < len(tokens) and tokens[i + 1].value == fluent and i > 0:
                before = tokens[i - 1]
                if before.type in _TYPE_TOKENS:
                    return [before]
                if before.type == "RBRACKET":
                    j = i - 1
                    while j > 0 and tokens[j].type != "LIST":
                        j -= 1
                    return tokens[j:i]
        return None

    # E0043
    def domain_section(
        self, tokens: list[Token], start: int, end: int, out: list[Token], declaration_start: int
    ) -> None:
        """`domain: x in D;` (after the parameters' types) becomes the parameter `D x`."""
        items = tokens[start + 2 : end]
        restrictions: list[tuple[Token, Token]] = []
        k = 0
        while k < len(items):
            if items[k].type in _TYPE_TOKENS - {"NAME"} and k + 1 < len(items):
                k += 1  # a type before the parameter, as in `domain: symbol room in rooms`
            if k + 2 < len(items) and items[k].type == "NAME" and items[k + 1].type == "IN":
                restrictions.append((items[k], items[k + 2]))
                k += 3
                if k < len(items) and items[k].type in ("COMMA", "SEMI"):
                    k += 1
                continue
            restrictions = []
            break
        section = self.span(tokens[start].start, tokens[end].end)
        edits: list[diag.Edit] = []
        declaration = out[declaration_start:]
        resolved = bool(restrictions)
        for param, domain in restrictions:
            for j in range(1, len(declaration)):
                if (
                    declaration[j].value == param.value
                    and declaration[j].type == "NAME"
                    and declaration[j - 1].type in _TYPE_TOKENS
                    and declaration[j - 1].end <= declaration[j].start
                ):
                    type_token = declaration[j - 1]
                    if type_token.start in self.sigil_edits:  # a type written as a sigil: write the domain
                        self.sigil_edits[type_token.start] = self.edit(
                            type_token.start, type_token.end, domain.value + " "
                        )
                        edits.append(self.sigil_edits[type_token.start])
                    else:
                        edits.append(self.edit(type_token.start, type_token.end, domain.value))
                    out[declaration_start + j - 1] = Token("NAME", domain.value, type_token.start, type_token.end)
                    break
            else:
                resolved = False
                break
        removal_start = self.text.rfind("\n", 0, section.start) + 1
        removal_end = section.end + 1 if self.text[section.end : section.end + 1] == "\n" else section.end
        if self.text[removal_start : section.start].strip():
            removal_start = section.start
        fix = None
        if resolved:
            edits.append(self.edit(removal_start, removal_end, ""))
            fix = diag.Fix("type the parameters with their domains", tuple(edits), diag.Applicability.SAFE)
        self.diagnostics.append(
            diag.error(
                E0043.domain_section(),
                section,
                "legacy parameter domains",
                help="give the parameter the domain as its type, `action go(Room r)`, and remove the section "
                f"(`gpp explain {E0043.code}`)",
                fix=fix,
            )
        )

    # E0044
    def function_body(self, tokens: list[Token], open_: int, close: int, name: str) -> list[Token]:
        body = tokens[open_ + 1 : close]
        converted = self.returns(body)
        brace = tokens[open_]
        whole = self.span(brace.start, tokens[close].end)
        if converted is None:
            self.diagnostics.append(
                diag.error(
                    E0044.block_body(name),
                    self.span(brace.start, brace.end),
                    "legacy function body",
                    help="a function is `= expression`: write its `return` values as one expression, choosing "
                    f"with `if (c) a else b` (`gpp explain {E0044.code}`)",
                )
            )
            return [_synthetic("EQ", "=", brace.start, brace.end), _synthetic("NULL", "null", brace.end)]
        new_tokens, text = converted
        self.diagnostics.append(
            diag.error(
                E0044.block_body(name),
                self.span(brace.start, brace.end),
                "legacy function body",
                help=f"write `= {text}` (`gpp explain {E0044.code}`)",
                fix=diag.Fix(
                    "write the body as one expression",
                    (self.edit(whole.start, whole.end, f"= {text}"),),
                    diag.Applicability.SAFE,
                ),
            )
        )
        return [_synthetic("EQ", "=", brace.start, brace.end), *new_tokens]

    def returns(self, body: list[Token]) -> tuple[list[Token], str] | None:
        """`return e;` and `if (c) ... else ...` chains of them as one expression: its tokens and
        its text; None for anything else."""
        if body and body[0].type == "LBRACE" and body[-1].type == "RBRACE":
            return self.returns(body[1:-1])
        if len(body) >= 2 and body[0].value == "return" and body[0].type == "NAME":
            # `return e;`, or the body's last `return e` without its `;` (2018)
            expr = body[1:-1] if body[-1].type == "SEMI" else body[1:]
            if not expr or any(t.type == "SEMI" for t in expr):
                return None
            return expr, self.modern_text(expr[0].start, expr[-1].end)
        if body and body[0].type == "IF" and len(body) > 3 and body[1].type == "LPAR":
            close = self.close_paren(body, 1)
            if close is None:
                return None
            condition = body[2:close]
            then_end = self.branch_end(body, close + 1)
            if then_end is None or not condition:
                return None
            then = self.returns(body[close + 1 : then_end])
            rest = body[then_end:]
            if rest and rest[0].type == "ELSE":
                rest = rest[1:]
            otherwise = self.returns(rest)
            if then is None or otherwise is None:
                return None
            then_tokens, then_text = then
            if then_tokens and then_tokens[0].type == "IF":
                at = then_tokens[0].start
                then_tokens = [_synthetic("LPAR", "(", at), *then_tokens, _synthetic("RPAR", ")", then_tokens[-1].end)]
                then_text = f"({then_text})"
            c = self.modern_text(condition[0].start, condition[-1].end)
            tokens = [body[0], body[1], *condition, body[close], *then_tokens]
            tokens += [_synthetic("ELSE", "else", then_tokens[-1].end), *otherwise[0]]
            return tokens, f"if ({c}) {then_text} else {otherwise[1]}"
        return None

    def close_paren(self, body: list[Token], i: int) -> int | None:
        """The index of the `)` that closes the parenthesis at or after `i`."""
        return _closing(body, i, ("LPAR",), "RPAR")

    def branch_end(self, body: list[Token], i: int) -> int | None:
        """The end (exclusive) of the statement that starts at `i`: a block or up to its `;`
        (a nested `if` with its `else`)."""
        if i >= len(body):
            return None
        if body[i].type == "LBRACE":
            close = self.matching(body, i)
            return None if close is None else close + 1
        if body[i].type == "IF":
            close = self.close_paren(body, i + 1)
            if close is None:
                return None
            end = self.branch_end(body, close + 1)
            if end is not None and end < len(body) and body[end].type == "ELSE":
                return self.branch_end(body, end + 1)
            return end
        semi = self.statement_end(body, i)
        return None if semi is None else semi + 1

    # E0045
    def exog_function_body(self, tokens: list[Token], open_: int, close: int, name: str) -> Token:
        brace = tokens[open_]
        whole = self.span(brace.start, tokens[close].end)
        self.diagnostics.append(
            diag.error(
                E0045.body(name),
                self.span(brace.start, brace.end),
                "legacy body",
                notes=["an exogenous function is answered by the platform: it is declared, never defined"],
                help=f"end the declaration with `;` (`gpp explain {E0045.code}`)",
                fix=diag.Fix("remove the body", (self.edit(whole.start, whole.end, ";"),), diag.Applicability.SAFE),
            )
        )
        return _synthetic("SEMI", ";", brace.start, brace.end)


# Where a declaration starts: after `%fluent on(%x) = 0` without its `;`, the next one.
_STARTS_DECLARATION = _DECLARES | {
    "BOOL",
    "NUMBER_KW",
    "STRING_KW",
    "SYMBOL",
    "VOID",
    "LBRACE",
    "MAIN_LBRACE",
    "RBRACE",
}


# The initial value of the fluent that stands for a 2018 procedure variable, by its type: token type, text.
_ZEROS = {"number": ("NUMBER", "0"), "bool": ("FALSE", "false"), "string": ("STRING", '""')}
_TYPE_KEYWORDS = {type_name: token for type_name, token in SIGIL_TYPES.values()}


class _ProgramNumbers:
    """The numbers a 2018 program's fluents and literals give a number variable, which the
    original's quantifier and `pick` ranged over (its Prolog backend bound the variable by
    unifying it with the fluents' instances and the program's constants): the numbers in the
    fluents' `initially:` sections, the number arguments of calls of the declared fluents,
    functions and actions, and the numbers compared (`==`, `!=`) or assigned. Empty when the
    program has none, and then there is no fix. `name` is the domain's name, one the file does
    not use; `variables` collects (keyword, variable, how its type was found)."""

    def __init__(self, tokens: list[Token], signatures: dict[str, list[list[Token] | None]]) -> None:
        found: dict[float, str] = {}
        initially = False
        for k, t in enumerate(tokens):
            if t.type == "INITIALLY":
                initially = True
            elif t.type in _SECTIONS or t.type == "RBRACE":
                initially = False
            if t.type != "NUMBER":
                continue
            negative = k > 1 and tokens[k - 1].value == "-" and tokens[k - 2].type in ("LPAR", "COMMA", "CMP_OP", "EQ")
            operand = k - 2 if negative else k - 1
            call = _argument_of(tokens, k) if not negative else None
            if (
                initially
                or (call is not None and call[0] in signatures)
                or tokens[operand].type == "EQ"
                or (tokens[operand].type == "CMP_OP" and tokens[operand].value in ("==", "!="))
                or (k + 1 < len(tokens) and tokens[k + 1].type == "CMP_OP" and tokens[k + 1].value in ("==", "!="))
            ):
                text = ("-" if negative else "") + t.value
                found.setdefault(float(text), text)
        self.values = [found[v] for v in sorted(found)]
        used = {t.value for t in tokens if t.type == "NAME"}
        self.name = "numbers"
        while self.name in used:
            self.name += "_"
        self.first_start = tokens[0].start if tokens else 0
        self.variables: list[tuple[Token, Token, str]] = []


def _domain_declaration(type_token: str, type_name: str, name: str, members: list[list[Token]], at: int) -> list[Token]:
    """The tokens of `type_name domain name = {members}`, all at the offset `at` (a declaration
    a legacy rewrite adds)."""
    out = [_synthetic(type_token, type_name, at), _synthetic("DOMAIN", "domain", at), _synthetic("NAME", name, at)]
    out += [_synthetic("EQ", "=", at), _synthetic("LBRACE", "{", at)]
    for k, member in enumerate(members):
        if k:
            out.append(_synthetic("COMMA", ",", at))
        out += member
    return [*out, _synthetic("RBRACE", "}", at)]


def _initial_value_end(tokens: list[Token], i: int) -> int:
    """The index of the `;` that ends the value starting at `i`, or, without one, of the first
    token of the next declaration."""
    depth = 0
    for j in range(i, len(tokens)):
        kind = tokens[j].type
        if kind in ("LPAR", "LBRACKET"):
            depth += 1
        elif kind in ("RPAR", "RBRACKET"):
            depth -= 1
        elif depth == 0 and (kind == "SEMI" or kind in _STARTS_DECLARATION or kind == "EOF"):
            return j
    return len(tokens)


def _type_text(type_tokens: list[Token]) -> str:
    return " ".join(t.value for t in type_tokens).replace("[ ", "[").replace(" ]", "]").replace(" [", "[")


def _parameters(tokens: list[Token], open_: int) -> tuple[list[tuple[list[Token] | None, str]], int] | None:
    """The parameters of the list that opens at `open_` (`(blocks x, symbol y)`): (type tokens,
    or None when untyped, name) each, and the index of its `)`; None when it is not a list of
    parameters."""
    params: list[tuple[list[Token] | None, str]] = []
    current: list[Token] = []
    depth = 0
    for j in range(open_ + 1, len(tokens)):
        t = tokens[j]
        if t.type == "LBRACKET":
            depth += 1
        elif t.type == "RBRACKET":
            depth -= 1
        if depth == 0 and t.type in ("COMMA", "RPAR"):
            if current:
                if current[-1].type != "NAME":
                    return None
                params.append((current[:-1] or None, current[-1].value))
            current = []
            if t.type == "RPAR":
                return params, j
            continue
        if t.type not in (*_TYPE_TOKENS, "LIST", "LBRACKET", "RBRACKET"):
            return None
        current.append(t)
    return None


def _signatures(tokens: list[Token]) -> dict[str, list[list[Token] | None]]:
    """The parameter types of every fluent, function, action and procedure declared in the
    tokens, by name (None for an untyped parameter)."""
    found: dict[str, list[list[Token] | None]] = {}
    for i, t in enumerate(tokens):
        if (
            t.type in _DECLARES
            and i + 2 < len(tokens)
            and tokens[i + 1].type == "NAME"
            and tokens[i + 2].type == "LPAR"
        ):
            params = _parameters(tokens, i + 2)
            if params is not None:
                found.setdefault(tokens[i + 1].value, [p for p, _ in params[0]])
    return found


def _enclosing_parameters(tokens: list[Token], at: int) -> dict[str, list[Token]]:
    """The typed parameters of the declaration the token at `at` is in, by name."""
    for i in range(at - 1, -1, -1):
        if tokens[i].type in _DECLARES and i + 2 < len(tokens) and tokens[i + 2].type == "LPAR":
            params = _parameters(tokens, i + 2)
            if params is None:
                return {}
            return {name: kind for kind, name in params[0] if kind is not None}
    return {}


def _argument_of(tokens: list[Token], j: int) -> tuple[str, int] | None:
    """(callee, argument position) when the name at `j` is a whole argument of a call
    (`loc(z)`, `stack(x, z)`), else None."""
    if not (
        0 < j < len(tokens) - 1 and tokens[j - 1].type in ("LPAR", "COMMA") and tokens[j + 1].type in ("COMMA", "RPAR")
    ):
        return None
    position = 0
    depth = 0
    for i in range(j - 1, 0, -1):
        kind = tokens[i].type
        if kind in ("RPAR", "RBRACKET", "RBRACE"):
            depth += 1
        elif kind in ("LBRACKET", "LBRACE") or (kind == "LPAR" and depth > 0):
            depth -= 1
        elif kind == "LPAR":
            return (tokens[i - 1].value, position) if tokens[i - 1].type == "NAME" else None
        elif kind == "COMMA" and depth == 0:
            position += 1
        elif kind == "SEMI":
            return None
    return None


_LITERAL_TYPES = {"NUMBER": "NUMBER_KW", "STRING": "STRING_KW", "TRUE": "BOOL", "FALSE": "BOOL", "NAME": "SYMBOL"}
_TYPE_WORDS = {"NUMBER_KW": "number", "STRING_KW": "string", "BOOL": "bool", "SYMBOL": "symbol"}


def _set_value_types(tokens: list[Token], i: int) -> list[Token] | None:
    """The type of the values of the literal set `{a, b}` at `i`, when they are all of one
    kind (numbers, strings, truth values, symbols), as type tokens; else None."""
    if i >= len(tokens) or tokens[i].type != "LBRACE":
        return None
    kinds: set[str] = set()
    expect_value = True
    for t in tokens[i + 1 :]:
        if t.type == "RBRACE":
            if len(kinds) != 1:
                return None
            (kind,) = kinds
            return [Token(kind, _TYPE_WORDS[kind], t.start, t.start)]
        if expect_value:
            literal = _LITERAL_TYPES.get(t.type)
            if literal is None:
                if t.type == "ADD_OP" and t.value == "-":
                    continue
                return None
            kinds.add(literal)
        elif t.type != "COMMA":
            return None
        expect_value = not expect_value
    return None


def _is_kind(tokens: list[Token], i: int, kind: str) -> bool:
    return i < len(tokens) and tokens[i].type == kind


def _closing(tokens: list[Token], i: int, openers: tuple[str, ...], closer: str) -> int | None:
    """The index of the `closer` that closes the first of `openers` from `i` on, or None."""
    depth = 0
    for j in range(i, len(tokens)):
        if tokens[j].type in openers:
            depth += 1
        elif tokens[j].type == closer:
            depth -= 1
            if depth == 0:
                return j
    return None
