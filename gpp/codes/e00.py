"""E00xx: syntax (the lexer, the parser, includes, legacy golog++)."""

from __future__ import annotations

from gpp.codes.registry import Code, Message


class E0001(Code, name="unexpected-character", summary="a character that cannot start any token"):
    @classmethod
    def unexpected_character(cls, text: str) -> Message:
        return Message(cls.code, f"unexpected character {text!r}")

    @classmethod
    def unexpected_characters(cls) -> Message:
        """A run of stray characters, reported once."""
        return Message(cls.code, "unexpected characters")


class E0002(Code, name="unterminated", summary="a string literal or block comment that is never closed"):
    @classmethod
    def comment(cls) -> Message:
        return Message(cls.code, "unterminated block comment")

    @classmethod
    def string(cls) -> Message:
        return Message(cls.code, "unterminated string literal")


class E0003(Code, name="underscore-name", summary="a name that starts with '_'"):
    @classmethod
    def underscore_name(cls) -> Message:
        return Message(cls.code, "a name cannot start with '_'")


class E0004(Code, name="number-too-large", summary="a number literal beyond the range of numbers (about ±1.8e308)"):
    @classmethod
    def too_large(cls) -> Message:
        return Message(cls.code, "number literal is too large")


class E0005(Code, name="non-ascii-name", summary="a name with letters outside ASCII (names are ASCII in golog++)"):
    @classmethod
    def non_ascii(cls, name: str) -> Message:
        return Message(cls.code, f"the name `{name}` has letters outside ASCII")


class E0006(Code, name="not-text", summary="a file that is not UTF-8 text: a NUL byte, or bytes that are not UTF-8"):
    @classmethod
    def not_text(cls, what: str, line: int, column: int) -> Message:
        """The file itself; `what` describes the bad byte."""
        return Message(cls.code, f"this is not a UTF-8 text file: {what} at line {line}, column {column}")

    @classmethod
    def included_not_text(cls, name: str, what: str, line: int, column: int) -> Message:
        return Message(
            cls.code, f"included file `{name}` is not a UTF-8 text file: {what} at line {line}, column {column}"
        )


class E0010(Code, name="unexpected-token", summary="a token where the grammar does not allow it"):
    @classmethod
    def expected(cls, expected: str, found: str) -> Message:
        return Message(cls.code, f"expected {expected}, found {found}")

    @classmethod
    def semicolon_after_brace(cls) -> Message:
        return Message(cls.code, "unexpected `;` after `}`")

    @classmethod
    def semicolon_after_declaration(cls) -> Message:
        return Message(cls.code, "unexpected `;` after a declaration")

    @classmethod
    def semicolon(cls) -> Message:
        return Message(cls.code, "unexpected `;`")

    @classmethod
    def unparenthesized(cls, word: str) -> Message:
        """`if x() == a go();`: `word` is the keyword whose parentheses are missing."""
        return Message(cls.code, f"expected `(` after `{word}`: its {_HEADS.get(word, 'part')} goes in parentheses")

    @classmethod
    def binding_order(cls, word: str, variable: str, type_name: str) -> Message:
        """`pick (v in Room)`: the type comes first."""
        space = " " if word == "pick" else ""
        return Message(cls.code, f"`{word}` names the type first: `{word}{space}({type_name} {variable})`")


# What goes in parentheses after a keyword, for `E0010.unparenthesized`.
_HEADS = {
    "if": "condition",
    "while": "condition",
    "test": "condition",
    "pick": "variable",
    "exists": "variable",
    "forall": "variable",
}


class E0011(Code, name="missing-semicolon", summary="a statement or declaration that is not ended by ';'"):
    @classmethod
    def missing_after(cls, what: str | None) -> Message:
        """`what` is the construct the `;` ends (None when the parser cannot tell)."""
        return Message(cls.code, f"expected `;` after this {what}" if what else "expected `;`")


class E0012(Code, name="unexpected-eof", summary="the file ends inside a declaration"):
    @classmethod
    def unexpected_eof(cls, expected: str) -> Message:
        return Message(cls.code, f"unexpected end of file, expected {expected}")


class E0013(Code, name="reserved-word", summary="a reserved word used as a name"):
    @classmethod
    def reserved(cls, word: str) -> Message:
        return Message(cls.code, f"`{word}` is a reserved word and cannot be used as a name")


class E0014(Code, name="nesting-too-deep", summary="a declaration nested more than 2,000 levels deep"):
    @classmethod
    def too_deep(cls, what: str, levels: int) -> Message:
        return Message(cls.code, f"this {what} nests more than {levels} levels deep")


class E0020(Code, name="duplicate-section", summary="an action section (`effect:`, ...) given twice"):
    @classmethod
    def twice(cls, word: str) -> Message:
        return Message(cls.code, f"section `{word}:` appears twice")


class E0021(Code, name="duplicate-handler", summary="a `during` handler given twice"):
    @classmethod
    def twice(cls, keyword: str) -> Message:
        return Message(cls.code, f"`{keyword}` handler given twice")


class E0040(
    Code,
    name="legacy-type-sigil",
    summary="a type written as a sigil (`%fluent`, `?function`, `§x`): legacy golog++",
):
    @classmethod
    def sigil(cls, sigil: str) -> Message:
        return Message(cls.code, f"`{sigil}` before a name is the legacy way of writing a type")


class E0041(Code, name="legacy-mapping-name", summary="an unquoted mapped name (`move_base { ... }`): legacy golog++"):
    @classmethod
    def unquoted(cls, name: str) -> Message:
        return Message(cls.code, f"the mapped name `{name}` is not quoted")


class E0042(Code, name="legacy-senses", summary="`senses: f()` without an assignment: legacy golog++"):
    @classmethod
    def senses(cls) -> Message:
        return Message(cls.code, "`senses:` without `= ...` is legacy golog++")


class E0043(Code, name="legacy-domain-section", summary="a `domain:` section restricting parameters: legacy golog++"):
    @classmethod
    def domain_section(cls) -> Message:
        return Message(cls.code, "a `domain:` section is legacy golog++")


class E0044(Code, name="legacy-function-body", summary="a function with a block body of `return`s: legacy golog++"):
    @classmethod
    def block_body(cls, name: str) -> Message:
        return Message(cls.code, f"function `{name}` has a block body, which is legacy golog++")


class E0045(Code, name="legacy-exog-function-body", summary="an `exog_function` with a body: legacy golog++"):
    @classmethod
    def body(cls, name: str) -> Message:
        return Message(cls.code, f"exogenous function `{name}` has a body, which is legacy golog++")


class E0046(
    Code,
    name="legacy-untyped-variable",
    summary="a variable of `exists`, `forall` or `pick` without a type: legacy golog++",
):
    @classmethod
    def untyped(cls, keyword: str, name: str) -> Message:
        return Message(cls.code, f"the `{keyword}` variable `{name}` has no type")


class E0047(
    Code,
    name="legacy-overloaded-name",
    summary="one global name declared twice with different numbers of parameters: legacy golog++",
):
    @classmethod
    def overloaded(cls, name: str, arities: str) -> Message:
        return Message(cls.code, f"`{name}` is declared with {arities} parameters")


class E0048(
    Code,
    name="legacy-fluent-initial-value",
    summary="a fluent's initial value written after its head (`%fluent on(%x) = 0`): legacy golog++",
):
    @classmethod
    def initial_value(cls, name: str) -> Message:
        return Message(cls.code, f"fluent `{name}` is given its initial value after its head")


class E0049(
    Code,
    name="legacy-number-quantifier",
    summary="a variable of `exists`, `forall` or `pick` over all numbers (`exists (%z)`): legacy golog++",
):
    @classmethod
    def unbounded(cls, keyword: str, name: str, type_: str) -> Message:
        return Message(cls.code, f"the `{keyword}` variable `{name}` ranges over every {type_}")


class E0050(
    Code,
    name="legacy-undeclared-symbol",
    summary="symbols used without being declared (`loc(a) == table`): legacy golog++",
):
    @classmethod
    def undeclared(cls, name: str, count: int) -> Message:
        more = f" (and {count - 1} more)" if count > 1 else ""
        return Message(cls.code, f"the symbol `{name}`{more} is used without being declared")


class E0051(
    Code,
    name="legacy-procedure-variable",
    summary="a variable a procedure assigns without declaring it (`%y = 1;`): legacy golog++",
):
    @classmethod
    def assigned(cls, name: str, where: str) -> Message:
        return Message(cls.code, f"`{name}` is assigned in {where}, but nothing declares it")


class E0030(Code, name="include-not-found", summary="an `#include` whose file cannot be found or read"):
    @classmethod
    def not_found(cls, name: str) -> Message:
        return Message(cls.code, f"cannot find included file `{name}`")

    @classmethod
    def unreadable(cls, name: str, reason: str | None) -> Message:
        return Message(cls.code, f"cannot read included file `{name}`: {reason}")


class E0031(Code, name="include-cycle", summary="files that include each other"):
    @classmethod
    def cycle(cls, files: list[str]) -> Message:
        return Message(cls.code, "include cycle: " + " -> ".join(files))
