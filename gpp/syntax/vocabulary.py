"""The words of golog++ by what they are, for the highlighters that cannot ask the language
server: the Vim syntax file (gpp.syntax.vim) and the grammars of other editors. One list, drawn
from the lexer's tables (gpp.syntax.lexer): each class names the lexer's token types it holds,
so a keyword added to the lexer lands in a class (or in `keyword`, the class of what is not
classified yet) and the generated files go stale until they are made again.

A highlighter-neutral description: each class has a TextMate scope, the name editors built on
TextMate grammars (VS Code, Sublime, ...) and many themes share, and each generator maps the
classes onto its own highlight groups.
"""

from __future__ import annotations

from dataclasses import dataclass

from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, SECTION_WORDS


@dataclass(frozen=True, slots=True)
class WordClass:
    """Words that are highlighted alike."""

    name: str
    description: str
    scope: str  # its TextMate scope
    words: tuple[str, ...]


# (class, description, TextMate scope, the lexer's token types it holds), most specific first.
_CLASSES: tuple[tuple[str, str, str, frozenset[str]], ...] = (
    (
        "declaration",
        "words that begin a declaration",
        "storage.type.declaration.golog",
        frozenset(
            {"ACTION", "EXOG_ACTION", "FLUENT", "FUNCTION", "EXOG_FUNCTION", "PROCEDURE", "DOMAIN", "COMPOUND"}
            | {"COMPONENT", "CONSTRAINTS"}
        ),
    ),
    (
        "type",
        "the built-in types",
        "support.type.builtin.golog",
        frozenset({"BOOL", "NUMBER_KW", "STRING_KW", "SYMBOL", "VOID", "LIST"}),
    ),
    (
        "statement",
        "the statements' keywords and the hooks of `during`",
        "keyword.control.golog",
        frozenset(
            {"IF", "ELSE", "WHILE", "TEST", "CHOOSE", "PICK", "IN", "SEARCH", "SOLVE", "CONCURRENT", "DURING"}
            | {"UNTIL", "ON_FAIL", "ON_CANCEL", "HOOK"}
        ),
    ),
    (
        "builtin",
        "the built-in functions and list operations",
        "support.function.builtin.golog",
        frozenset({"BUILTIN", "LIST_PUSH", "LIST_POP"}),
    ),
    ("constant", "the literal constants", "constant.language.golog", frozenset({"TRUE", "FALSE", "NULL"})),
    ("quantifier", "the quantifiers", "keyword.operator.quantifier.golog", frozenset({"QUANTIFIER"})),
    (
        "platform",
        "the words of `component` and `constraints` declarations",
        "keyword.other.platform.golog",
        frozenset(PLATFORM_KEYWORDS.values()),
    ),
)
# What no class above holds (a keyword the lexer gained since).
_OTHER = ("keyword", "other keywords", "keyword.other.golog")

SECTION_SCOPE = "entity.name.section.golog"


def word_classes() -> tuple[WordClass, ...]:
    """The keywords (of the whole language and of platform declarations) by class, each word
    once (in the first class that holds its token type), in the lexer's order."""
    words: dict[str, list[str]] = {name: [] for name, *_ in _CLASSES}
    other: list[str] = []
    for word, token_type in (*KEYWORDS.items(), *PLATFORM_KEYWORDS.items()):
        home = next((name for name, _, _, types in _CLASSES if token_type in types), None)
        bucket = other if home is None else words[home]
        if not any(word in found for found in (*words.values(), other)):
            bucket.append(word)
    out = [WordClass(name, description, scope, tuple(words[name])) for name, description, scope, _ in _CLASSES]
    if other:
        out.append(WordClass(*_OTHER, tuple(other)))
    return tuple(out)


def section_words() -> tuple[str, ...]:
    """The words of an action's, fluent's or component's sections, each followed by `:`
    (`precondition:`, `initially:`, ...): keywords only there."""
    return tuple(SECTION_WORDS)
