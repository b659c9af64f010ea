"""`start_effect:`: an action section of effects, parsed, printed, given at most once, typed as
`effect:` is, and read by the lints that read effects (W0104 per section)."""

from __future__ import annotations

from gpp.check import check_text
from gpp.syntax import ast
from gpp.syntax.format import format_text
from gpp.syntax.parser import parse_text

DECLARATIONS = """\
bool fluent busy() { initially: () = false; }
number fluent n() { initially: () = 0; }
"""


def codes(text: str) -> list[str]:
    """The codes `gpp check` reports for `text` after DECLARATIONS, but for W0101 (a fluent of
    DECLARATIONS that `text` does not use)."""
    return [d.code for d in check_text(DECLARATIONS + text).diagnostics if d.code != "W0101"]


def test_the_section_parses_into_its_own_node_and_prints_back() -> None:
    text = "action work() {\n  start_effect: busy() = true; if (n() > 1) n() = 0;\n  effect: busy() = false;\n}\n"
    [decl] = parse_text(text).program.declarations
    assert isinstance(decl, ast.ActionDecl)
    section = decl.section(ast.StartEffectSection)
    assert isinstance(section, ast.StartEffectSection)
    assert [e.condition is not None for e in section.effects] == [False, True]
    assert section.keyword.text == "start_effect:"
    formatted = format_text(text)
    assert formatted == (
        "action work() {\n"
        "start_effect:\n"
        "    busy() = true;\n"
        "    if (n() > 1) n() = 0;\n"
        "effect:\n"
        "    busy() = false;\n"
        "}\n"
    )
    assert format_text(formatted) == formatted


def test_start_effect_stays_a_name_without_its_colon() -> None:
    assert codes("number function start_effect() = 1\nprocedure main() { n() = start_effect(); }\n") == []


def test_the_section_given_twice_is_an_error() -> None:
    text = "action work() {\nstart_effect:\n    busy() = true;\nstart_effect:\n    n() = 1;\n}\n"
    assert codes(text) == ["E0020"]


def test_a_start_effect_is_typed_as_an_effect() -> None:
    [code] = codes("action work() {\nstart_effect:\n    busy() = 1;\n}\n")
    assert [code] == codes("action work() {\neffect:\n    busy() = 1;\n}\n")
    assert code == "E0202"  # a type mismatch


def test_an_action_without_duration_may_have_start_effects() -> None:
    assert codes("action work() {\nstart_effect:\n    busy() = true;\n}\nprocedure main() { work(); }\n") == []


def test_w0104_looks_at_each_section_alone() -> None:
    twice = "action work() {\nstart_effect:\n    n() = 1;\n    n() = 2;\n}\nprocedure main() { work(); }\n"
    assert codes(twice) == ["W0104"]
    apart = "action work() {\nstart_effect:\n    n() = 1;\neffect:\n    n() = 2;\n}\nprocedure main() { work(); }\n"
    assert codes(apart) == []
