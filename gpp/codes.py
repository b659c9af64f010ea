"""Every diagnostic code gpp reports, defined in one place.

Each code has a short name (used by `--allow NAME` for lints), a one-line summary and, for
`gpp explain CODE`, an explanation with a small example. Codes are stable: a code keeps its
meaning forever; retired codes are not reused.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class CodeInfo:
    code: str
    name: str
    summary: str
    explanation: str = ""

    @property
    def is_lint(self) -> bool:
        return self.code.startswith("W")


_CODES: list[CodeInfo] = [
    # ---------------------------------------------------------------- syntax
    CodeInfo("E0001", "unexpected-character", "a character that cannot start any token"),
    CodeInfo("E0002", "unterminated", "a string literal or block comment that is never closed"),
    CodeInfo("E0003", "underscore-name", "a name that starts with '_'"),
    CodeInfo("E0010", "unexpected-token", "a token where the grammar does not allow it"),
    CodeInfo("E0011", "missing-semicolon", "a statement or declaration that is not ended by ';'"),
    CodeInfo("E0012", "unexpected-eof", "the file ends inside a declaration"),
    CodeInfo("E0013", "reserved-word", "a reserved word used as a name"),
    CodeInfo("E0020", "duplicate-section", "an action section (`effect:`, ...) given twice"),
    CodeInfo("E0021", "duplicate-handler", "a `during` handler given twice"),
    CodeInfo("E0030", "include-not-found", "an `#include` whose file cannot be found or read"),
    CodeInfo("E0031", "include-cycle", "files that include each other"),
    # ---------------------------------------------------------------- names
    CodeInfo("E0101", "unknown-name", "a name that is neither a variable nor a symbol"),
    CodeInfo("E0102", "missing-call", "a fluent or function used without `()`"),
    CodeInfo("E0103", "unknown-callable", "a call of something that is not declared"),
    CodeInfo("E0104", "wrong-kind", "a declaration used where its kind is not allowed"),
    CodeInfo("E0105", "unknown-type", "a type name that is not declared"),
    CodeInfo("E0106", "unknown-field", "a field that the compound type does not have"),
    CodeInfo("E0107", "unknown-platform-name", "an unknown component, state or clock in the platform model"),
    # ---------------------------------------------------------------- types
    CodeInfo("E0201", "wrong-arity", "a call with the wrong number of arguments"),
    CodeInfo("E0202", "type-mismatch", "an expression of the wrong type"),
    CodeInfo("E0203", "not-in-domain", "a literal that is not a member of the domain it must belong to"),
    CodeInfo("E0204", "bad-operands", "an operator applied to operands of the wrong types"),
    CodeInfo("E0205", "chained-comparison", "comparisons written as a chain, such as `a < b < c`"),
    CodeInfo("E0206", "void-data", "`void` used as the type of data"),
    CodeInfo("E0207", "not-indexable", "a field taken of a non-compound, or an index of a non-list"),
    CodeInfo("E0208", "compound-fields", "a compound literal with missing or repeated fields"),
    CodeInfo("E0209", "not-comparable", "compound or list values compared"),
    CodeInfo("E0210", "infinite-range", "a quantifier or `pick` over a type with infinitely many values"),
    CodeInfo("E0211", "branch-types", "a conditional expression whose branches have different types"),
    CodeInfo("E0212", "solve-arguments", "a `solve` whose horizon or reward is not what it needs"),
    CodeInfo("E0213", "literal-required", "an expression where only a literal value may stand"),
    # ---------------------------------------------------------------- declarations
    CodeInfo("E0301", "redefinition", "a second definition of the same name"),
    CodeInfo("E0302", "kind-clash", "one name declared as two different kinds of things"),
    CodeInfo("E0303", "forward-mismatch", "a definition that does not match its forward declaration"),
    CodeInfo("E0304", "predefined-name", "a declaration of a name gpp predefines"),
    CodeInfo("E0305", "duplicate-name", "a parameter, field, mapping argument or variable declared twice in one list"),
    CodeInfo("E0306", "bad-assignment-target", "an assignment to something that is not a fluent"),
    CodeInfo("E0307", "bad-initial-value", "an `initially:` entry that does not fit the fluent's parameters"),
    CodeInfo("E0308", "exog-mapping", "an exogenous action mapping that does not bind every parameter to itself"),
    CodeInfo("E0309", "section-not-allowed", "a section an exogenous action cannot have"),
    CodeInfo("E0310", "main-twice", "a legacy main block and a `procedure main` in one program"),
    CodeInfo("E0311", "bad-domain", "a domain definition that refers to itself or mixes element types"),
    CodeInfo("E0312", "bad-duration", "a `duration:` or `silent:` section with values it cannot have"),
    # ---------------------------------------------------------------- lints
    CodeInfo("W0101", "unused", "a fluent, action, function or procedure that is never used"),
    CodeInfo("W0102", "unused-variable", "a parameter or variable that is never used"),
    CodeInfo("W0103", "uninitialized-fluent", "fluent instances that have no initial value"),
    CodeInfo("W0104", "double-effect", "an action that assigns the same fluent instance twice"),
    CodeInfo("W0105", "online-nondeterminism", "a `pick` or `choose` outside `solve`/`search`"),
    CodeInfo("W0106", "busy-loop", "a `while (true)` loop whose body executes no action"),
    CodeInfo("W0107", "constant-condition", "a condition that is always true or always false"),
    CodeInfo("W0108", "unreachable-else", "an `else` branch that can never run"),
    CodeInfo("W0109", "solve-without-choice", "a `solve` whose program has no `pick` or `choose`"),
    CodeInfo("W0110", "mixed-precedence", "an operator chain that the original golog++ reads differently"),
    CodeInfo("W0111", "shadowed-symbol", "a parameter or variable named like a domain symbol"),
]

CODES: dict[str, CodeInfo] = {c.code: c for c in _CODES}
BY_NAME: dict[str, CodeInfo] = {c.name: c for c in _CODES}


def lookup(code_or_name: str) -> CodeInfo | None:
    key = code_or_name.strip()
    return CODES.get(key.upper()) or BY_NAME.get(key.lower())


def lints() -> list[CodeInfo]:
    return [c for c in _CODES if c.is_lint]
