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
* E0045 an `exog_function` with a body.

Every fix is safe (`gpp check --fix` applies it): its edits write exactly the modern program
that the rewrite hands the parser, so the fixed file means what gpp already took the legacy one
to mean.

Everything here works on tokens (gpp.syntax.lexer.Token): the parser and the grammar do not
know about legacy syntax.
"""

from __future__ import annotations

from collections.abc import Iterator

from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.codes import E0040, E0041, E0042, E0043, E0044, E0045
from gpp.syntax.lexer import Token

SIGIL_TYPES = {
    "%": ("number", "NUMBER_KW"),
    "?": ("bool", "BOOL"),
    "$": ("string", "STRING_KW"),
    "§": ("symbol", "SYMBOL"),
}
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
    types = [t.type for t in tokens]
    has_sigils = "SIGIL" in types or ("MUL_OP" in types and _percent_sigil(tokens, types))
    if not has_sigils and not _structural_candidates(types):
        return tokens, []
    rewriter = _Rewriter(source)
    if has_sigils:
        tokens = rewriter.sigils(tokens)
    tokens = rewriter.structure(tokens)
    rewriter.report_sigils()
    return tokens, rewriter.diagnostics


def _positions(types: list[str], kind: str) -> Iterator[int]:
    i = -1
    while True:
        try:
            i = types.index(kind, i + 1)
        except ValueError:
            return
        yield i


def _percent_sigil(tokens: list[Token], types: list[str]) -> bool:
    return any(
        tokens[i].value == "%"
        and i + 1 < len(tokens)
        and tokens[i + 1].start == tokens[i].end
        and (types[i + 1] == "NAME" or types[i + 1] in _DECLARES)
        for i in _positions(types, "MUL_OP")
    )


def _structural_candidates(types: list[str]) -> bool:
    n = len(types)
    if any(i + 1 < n and types[i + 1] == "NAME" for i in _positions(types, "MAPPING")):
        return True
    for i in _positions(types, "SENSES"):
        # `senses: f(...) = ...;` is modern: an `=` before the `;` (or the section's end)
        j = i + 1
        while j < n and types[j] not in ("EQ", "SEMI", "RBRACE"):
            j += 1
        if j == n or types[j] != "EQ":
            return True
    if any(i + 1 < n and types[i + 1] == "COLON" for i in _positions(types, "DOMAIN")):
        return True
    for kind in ("FUNCTION", "EXOG_FUNCTION"):
        for i in _positions(types, kind):
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

    def replaced(self, start: int, end: int) -> None:
        """A fix replaces the text from `start` to `end` as a whole: the sigils inside it need no
        edit of their own (their edits would overlap)."""
        for offset in [k for k in self.sigil_edits if start <= k < end]:
            del self.sigil_edits[offset]

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
                and (nxt.type == "NAME" or nxt.type in _DECLARES)
                and (not out or out[-1].type not in _ENDS_OPERAND)
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
        edits = tuple(self.sigil_edits[k] for k in sorted(self.sigil_edits))
        more = len(edits) - 1
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
                end = self.statement_end(tokens, i + 1)
                if end is not None and not any(tok.type == "EQ" for tok in self.top_level(tokens, i + 1, end)):
                    out.append(t)
                    out.extend(self.senses(tokens, i + 1, end, out, declaration_start))
                    i = end + 1
                    continue
            if t.type == "DOMAIN" and i + 1 < n and tokens[i + 1].type == "COLON" and depth > 0:
                end = self.statement_end(tokens, i + 2)
                if end is not None:
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
        self, tokens: list[Token], start: int, end: int, out: list[Token], declaration_start: int
    ) -> list[Token]:
        """`senses: f(args);` becomes `senses: f(args) = sensed_f();` with a new exogenous
        function of the fluent's type declared before the action."""
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
                        self.edit(where.end, where.end, f" = {function}()"),
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
            tokens[end],
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
                if k < len(items) and items[k].type == "COMMA":
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
            self.replaced(removal_start, removal_end)  # the section's sigils go with it
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
        self.replaced(whole.start, whole.end)
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
        if len(body) >= 3 and body[0].value == "return" and body[0].type == "NAME" and body[-1].type == "SEMI":
            expr = body[1:-1]
            if any(t.type == "SEMI" for t in expr):
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
        self.replaced(whole.start, whole.end)
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
