"""Tests of the formatter (gpp/syntax/format.py) and of `gpp fmt`.

Exact-output tests pin where comments and blank lines go and how long lines wrap. Property
tests format every program of the repository, programs of the benchmark generator and random
syntax trees, each with comments sprinkled between random tokens, and check that the result
parses to the same tree, keeps every comment in order, and is formatted already.
"""

from __future__ import annotations

import random
import subprocess
import sys
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from bench.fmtfuzz import FormatterFuzzer, formatting_problems, sprinkle, warnings
from bench.genprog import generate_program
from gpp.base.source import Source
from gpp.syntax import ast
from gpp.syntax.directives import directives
from gpp.syntax.format import FormatError, _token_map, format_text
from gpp.syntax.lexer import tokenize
from gpp.syntax.parser import parse_text
from gpp.syntax.printer import format_program
from tests.support import TYPO_CORPUS, disks
from tests.support.budget import examples
from tests.support.cli import Result, run
from tests.support.syntax_trees import programs

ROOT = Path(__file__).resolve().parents[2]

# Every program of the repository but those in the older syntax (tests/legacy: syntax errors
# until `gpp check --fix` upgrades them, so there is nothing to format) and the typos of the
# fix-it corpus.
LEGACY = ROOT / "tests" / "legacy"
REPO_PROGRAMS = sorted(
    p
    for p in ROOT.glob("**/*.gpp")
    if ".venv" not in p.parts and LEGACY not in p.parents and TYPO_CORPUS not in p.parents
)


# ---------------------------------------------------------------- where comments go

CASES: dict[str, tuple[str, str]] = {
    "directives and a header stay on top, blank lines kept": (
        '// world: blocksworld\n//scenario: s.toml\n\n\n// About this file.\n\n#include "time.gpp"\naction a();\n',
        '// world: blocksworld\n//scenario: s.toml\n\n// About this file.\n\n#include "time.gpp"\naction a();\n',
    ),
    "leading comments above declarations and statements": (
        "// the action\naction a();\n  // the main procedure\nprocedure main() {\n        // first a\n  a();\n}\n",
        "// the action\naction a();\n// the main procedure\nprocedure main() {\n    // first a\n    a();\n}\n",
    ),
    "trailing comments stay on their line, aligned when consecutive": (
        "symbol domain block;   // the blocks\nsymbol domain slot; // the slots\n\n"
        "procedure main() { a(); // one\n b(); }\n",
        "symbol domain block;  // the blocks\nsymbol domain slot;   // the slots\n\n"
        "procedure main() {\n    a();  // one\n    b();\n}\n",
    ),
    "comments between parameters lay the list out one per line": (
        "action stack(block x, // what\n  // where to\n  slot y) {}\n",
        "action stack(\n    block x,  // what\n    // where to\n    slot y\n) {}\n",
    ),
    "inline block comments stay between their tokens": (
        "procedure main() { f(1,/* the second */2); g( /* none */ ); }\n",
        "procedure main() {\n    f(1, /* the second */ 2);\n    g(/* none */);\n}\n",
    ),
    "a comment after the last statement of a block stays inside it": (
        "procedure main() {\n    a();\n    // done\n}\n",
        "procedure main() {\n    a();\n    // done\n}\n",
    ),
    "a comment in an empty block stays inside it": (
        "procedure p() { // nothing yet\n}\nprocedure q() {\n// nothing\n}\n",
        "procedure p() {  // nothing yet\n}\nprocedure q() {\n    // nothing\n}\n",
    ),
    "comments inside action sections": (
        "action a(number x) {\nprecondition: // always\n    true\neffect:\n    f() = x; // set\n"
        "    // nothing else\n}\n",
        "action a(number x) {\nprecondition:  // always\n    true\neffect:\n    f() = x;  // set\n"
        "    // nothing else\n}\n",
    ),
    "a comment before `else` keeps `else` at the statement's indentation": (
        "procedure main() {\n    if (c()) { d(); }\n    // otherwise\n    else { e(); }\n}\n",
        "procedure main() {\n    if (c()) {\n        d();\n    }\n    // otherwise\n"
        "    else {\n        e();\n    }\n}\n",
    ),
    "comments at the end of the file": (
        "action a();\n// the end\n\n/* really */\n",
        "action a();\n// the end\n\n/* really */\n",
    ),
    "suppression comments stay attached to their statement": (
        "procedure main() {\n// gpp: allow W0101\nunused_thing();\n  b(); // gpp: allow W0102\n}\n",
        "procedure main() {\n    // gpp: allow W0101\n    unused_thing();\n    b();  // gpp: allow W0102\n}\n",
    ),
    "a line comment inside an expression ends the line, the rest continues indented": (
        "bool function f() = a() & // the first\n b()\n",
        "bool function f() = a() &  // the first\n    b()\n",
    ),
    "an own-line comment inside an expression": (
        "number function g(number x) = f(x,\n// the second\n2)\n",
        "number function g(number x) = f(\n    x,\n    // the second\n    2\n)\n",
    ),
    "the further lines of a block comment move with it": (
        "procedure main() {\n            /* one\n               two */\n    a();\n}\n",
        "procedure main() {\n    /* one\n       two */\n    a();\n}\n",
    ),
    "blank lines: at most one, none after an opening brace or before a closing one": (
        "action a();\n\n\n\naction b();\nprocedure main() {\n\n    a();\n\n\n    b();\n\n}\n",
        "action a();\n\naction b();\nprocedure main() {\n    a();\n\n    b();\n}\n",
    ),
    "redundant parentheses go, their comments stay": (
        "number function f() = ((1 /* one */)) + (/* two */ (2))\n",
        "number function f() = (1 /* one */) + (/* two */ 2)\n",
    ),
    "comments and blank lines only": (
        "\n\n// just a note\n\n\n/* and another */\n",
        "// just a note\n\n/* and another */\n",
    ),
    "an empty file stays empty": ("\n\n", ""),
    "the until clause of a during, with its comments": (
        "procedure main() {\n    during(a())until(/* why */ p()) // watch\n    { b(); } on_fail c();\n}\n",
        "procedure main() {\n    during (a()) until (/* why */ p())  // watch\n    {\n        b();\n    } on_fail\n"
        "        c();\n}\n",
    ),
}


@pytest.mark.parametrize("source, expected", CASES.values(), ids=CASES.keys())
def test_comment_placement(source: str, expected: str) -> None:
    assert format_text(source) == expected
    assert format_text(expected) == expected


# ---------------------------------------------------------------- line breaks

WIDE = "x" * 30


def test_long_definition_breaks_after_its_equals_sign() -> None:
    source = f"bool function ordered(number a, number b) = {WIDE}(a) > {WIDE}(b) & b > 0\n"
    assert format_text(source) == f"bool function ordered(number a, number b) =\n    {WIDE}(a) > {WIDE}(b) & b > 0\n"


def test_long_argument_list_is_laid_out_one_argument_per_line() -> None:
    source = f"procedure main() {{ act({WIDE}1, {WIDE}2, {WIDE}3); }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    act(\n        {WIDE}1,\n        {WIDE}2,\n        {WIDE}3\n    );\n}}\n"
    )


def test_long_condition_breaks_before_its_loosest_operators() -> None:
    source = f"procedure main() {{ if (c({WIDE}) & d({WIDE}) & e({WIDE})) a(); }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    if (c({WIDE})\n            & d({WIDE})\n            & e({WIDE}))\n        a();\n}}\n"
    )


def test_long_sum_in_an_assignment_breaks_before_plus() -> None:
    source = f"procedure main() {{ x() = f({WIDE}) + g({WIDE}) + {WIDE}; }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    x() = f({WIDE})\n        + g({WIDE})\n        + {WIDE};\n}}\n"
    )


def test_line_breaks_before_boolean_operators_are_kept() -> None:
    source = "action a(number x) {\nprecondition:\n      x > 0\n    & x < 10 & x != 5\n}\n"
    assert format_text(source) == "action a(number x) {\nprecondition:\n    x > 0\n        & x < 10 & x != 5\n}\n"


def test_line_breaks_elsewhere_are_not_kept() -> None:
    source = "procedure main() {\n    a(\n    );\n    x() = 1 +\n    2;\n}\n"
    assert format_text(source) == "procedure main() {\n    a();\n    x() = 1 + 2;\n}\n"


def test_long_conditional_breaks_before_its_branches() -> None:
    source = f"procedure main() {{ y() = if (a > {WIDE}(a)) {WIDE}(a) * 2 else {WIDE}(a) * 3 + {WIDE}(1); }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    y() = if (a > {WIDE}(a))\n            {WIDE}(a) * 2\n"
        f"        else {WIDE}(a) * 3 + {WIDE}(1);\n}}\n"
    )


def test_long_else_if_chain_breaks_at_each_conditional() -> None:
    source = f"number function f() = if (a() > {WIDE}()) {WIDE}() else if (b() > 1) {WIDE}() * 3 else {WIDE}()\n"
    assert format_text(source) == (
        f"number function f() =\n    if (a() > {WIDE}())\n        {WIDE}()\n"
        f"    else if (b() > 1) {WIDE}() * 3 else {WIDE}()\n"
    )


def test_operators_outside_a_conditional_break_before_it() -> None:
    source = f"procedure main() {{ y() = {WIDE} & if ({WIDE}) {WIDE} + {WIDE} else {WIDE}; }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    y() = {WIDE}\n        & if ({WIDE})\n            {WIDE} + {WIDE}\n"
        f"        else {WIDE};\n}}\n"
    )


def test_long_comparisons_and_products_break_before_their_operators() -> None:
    compare = f"procedure main() {{ test({WIDE}(a) > {WIDE}(b) == {WIDE}(c) < {WIDE}(d)); }}\n"
    assert format_text(compare) == (
        f"procedure main() {{\n    test({WIDE}(a)\n            > {WIDE}(b)\n"
        f"            == {WIDE}(c)\n            < {WIDE}(d));\n}}\n"
    )
    product = f"procedure main() {{ y() = {WIDE}(a) * {WIDE}(b) / {WIDE}(c) % {WIDE}(d); }}\n"
    assert format_text(product) == (
        f"procedure main() {{\n    y() = {WIDE}(a)\n        * {WIDE}(b)\n"
        f"        / {WIDE}(c)\n        % {WIDE}(d);\n}}\n"
    )


def test_compound_literals_in_a_long_else_if_chain_stay_on_one_line() -> None:
    # The user's file, after an earlier format-on-save broke it after each field's `=`.
    broken = (
        "Pos function spot(Room visitor_destination) = if (visitor_destination == lobby) Pos { x =\n"
        "    0, y =\n    0 } else if (visitor_destination == room1) Pos { x = 4, y = 2 }"
        " else if (visitor_destination == room2) Pos { x = 8, y = 2 } else Pos { x = 1, y = 7 }\n"
    )
    formatted = (
        "Pos function spot(Room visitor_destination) =\n"
        "    if (visitor_destination == lobby)\n"
        "        Pos { x = 0, y = 0 }\n"
        "    else if (visitor_destination == room1)\n"
        "        Pos { x = 4, y = 2 }\n"
        "    else if (visitor_destination == room2) Pos { x = 8, y = 2 } else Pos { x = 1, y = 7 }\n"
    )
    assert format_text(broken) == formatted
    assert format_text(" ".join(broken.split())) == formatted
    assert format_text(formatted) == formatted


_LONG_LITERAL = f"Pos {{ x = if (r == lobby) {WIDE} else if (r == hall) 4 else 1, y = {WIDE} }}"


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        # A compound literal breaks at its commas, not after its fields' `=`.
        (
            f"Pos function where(Room r) = {_LONG_LITERAL}\n",
            "Pos function where(Room r) =\n    Pos {\n"
            f"        x = if (r == lobby) {WIDE} else if (r == hall) 4 else 1,\n        y = {WIDE}\n    }}\n",
        ),
        # Its parts are one level deeper than the line the bracket opens on, a continued one.
        (
            f"number function f() = g({WIDE}(1), {WIDE}(2), {WIDE}(3), {WIDE}(4))\n",
            f"number function f() =\n    g(\n        {WIDE}(1),\n        {WIDE}(2),\n"
            f"        {WIDE}(3),\n        {WIDE}(4)\n    )\n",
        ),
    ],
    ids=["compound literal", "argument list"],
)
def test_a_long_bracket_on_a_continued_line_is_laid_out_one_part_per_line(source: str, expected: str) -> None:
    assert format_text(source) == expected


def test_a_block_comment_inside_a_line_counts_towards_its_length() -> None:
    # 92 characters of code, 112 with the comment.
    source = f"procedure main() {{ y() = {WIDE}(a) + /* a comment of some length */ {WIDE}(b); }}\n"
    assert format_text(source) == (
        f"procedure main() {{\n    y() = {WIDE}(a)\n        + /* a comment of some length */ {WIDE}(b);\n}}\n"
    )
    short = f"procedure main() {{\n    y() = {WIDE}(a) + /* short */ {WIDE}(b);\n}}\n"
    assert format_text(short) == short


def test_a_line_without_a_break_point_stays_long() -> None:
    name = "n" * 120
    assert format_text(f"action {name}();\n") == f"action {name}();\n"


# ---------------------------------------------------------------- errors


def test_literals_keep_their_spelling() -> None:
    source = 'procedure main() {\n    x = 1e308 + 1.50 + 0.0 + f("caf\\u00e9 \\"x\\"");\n}\n'
    assert format_text(source) == source
    assert format_text(source.replace("    x = 1e308 ", "x=  1e308 ")) == source


def test_syntax_errors_raise_with_the_diagnostics() -> None:
    with pytest.raises(FormatError) as caught:
        format_text("procedure main() {\n    a()\n}\n", "agent.gpp")
    assert [(d.code, d.span.line, str(d.span.source.path)) for d in caught.value.diagnostics] == [
        ("E0011", 2, "agent.gpp")
    ]
    assert str(caught.value) == "expected `;` after this statement"


# ---------------------------------------------------------------- suppressions

# A suppression covers a line (gpp/check/suppress.py): the formatter keeps that line's code on
# one line of its own, however the layout would have split or joined it.
SUPPRESSIONS: dict[str, tuple[str, str]] = {
    "at the end of a line, the line's statements stay on it": (
        "procedure main() { a(); b(); // gpp: allow W0105\n c(); }\n",
        "procedure main() { a(); b();  // gpp: allow W0105\n    c();\n}\n",
    ),
    "at the end of the last line of an expression, that line stays apart": (
        "procedure main() {\n    x() = 1 +\n    2; // gpp: allow W0107\n}\n",
        "procedure main() {\n    x() = 1 +\n        2;  // gpp: allow W0107\n}\n",
    ),
    "after the last argument, the list is laid out to keep the line": (
        "procedure main() { f(a,\n b); // gpp: allow W0107\n}\n",
        "procedure main() {\n    f(\n        a,\n        b);  // gpp: allow W0107\n}\n",
    ),
    "above a line of statements, that line stays as it is": (
        "procedure main() {\n// gpp: allow W0107\n  a(); b();\n  c(); }\n",
        "procedure main() {\n    // gpp: allow W0107\n    a(); b();\n    c();\n}\n",
    ),
    "above a declaration, the declaration is laid out as any other": (
        "// gpp: allow W0101\naction a() { effect: x() = 1; }\n",
        "// gpp: allow W0101\naction a() {\neffect:\n    x() = 1;\n}\n",
    ),
    "after a comment on a line of its own, on that line": (
        "action a();\n  /* c */ // gpp: allow W0107\n /* d\n   e */ /* f */ // g\naction b();\n",
        "action a();\n/* c */ // gpp: allow W0107\n/* d\n  e */ /* f */ // g\naction b();\n",
    ),
}


@pytest.mark.parametrize("source, expected", SUPPRESSIONS.values(), ids=SUPPRESSIONS.keys())
def test_suppression_placement(source: str, expected: str) -> None:
    assert format_text(source) == expected
    assert format_text(expected) == expected


def test_a_suppression_allows_the_same_lints_after_formatting() -> None:
    # Both loops are busy waits (W0106); the suppression at the end of the line allows both.
    source = "procedure main() {\n    while (true) {} while (true) {}  // gpp: allow W0106\n}\n"
    path = ROOT / "tests" / "programs" / "busy.gpp"
    assert warnings(source, path) == Counter()
    assert warnings(format_text(source), path) == Counter()
    # Without the suppression: the same two warnings, at the same tokens, before and after.
    plain = source.replace("  // gpp: allow W0106", "")
    assert sorted(warnings(plain, path)) == [
        ("W0106", "this `...` loop never executes an action, a test or an assignment", n) for n in (3, 7)
    ]
    assert warnings(format_text(plain), path) == warnings(plain, path)


# The formatter's mutation corpus (bench/fmtfuzz.py, also run by `make fuzz`): programs laid
# out anew, with comments and suppressions of every kind at random places.
MUTANTS = FormatterFuzzer()


@settings(max_examples=examples(100), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.randoms(use_true_random=False))
def test_formatting_a_mutant_keeps_its_tree_comments_line_endings_and_warnings(rnd: random.Random) -> None:
    mutant = MUTANTS.mutant(rnd)
    note(f"mutant of {mutant.path}: {mutant.text!r}")
    assert formatting_problems(mutant.text, mutant.path) == []


# ---------------------------------------------------------------- byte-order mark and line endings


def test_a_byte_order_mark_is_kept_and_not_read_as_code() -> None:
    assert format_text("\ufeffaction a( );\n") == "\ufeffaction a();\n"
    assert format_text("\ufeffaction a();\n") == "\ufeffaction a();\n"
    assert format_text("\ufeff") == "\ufeff"
    assert format_text("action a();\n") == "action a();\n"  # none is added


def test_syntax_errors_after_a_byte_order_mark_are_where_gpp_check_puts_them(tmp_path: Path) -> None:
    path = tmp_path / "bom.gpp"
    path.write_bytes(b"\xef\xbb\xbfprocedure main() { a() }\n")
    with pytest.raises(FormatError) as caught:
        format_text(path.read_text(encoding="utf-8"))
    assert [(d.code, d.span.line, d.span.col) for d in caught.value.diagnostics] == [("E0011", 1, 23)]
    assert "bom.gpp:1:23" in run_gpp("check", "bom.gpp", cwd=tmp_path).stdout


CRLF = 'action go(); // c\r\nprocedure main() {go();\r\n  say("a\nb"); say("c\r\nd");}\r\n'
CRLF_FORMATTED = (
    'action go();  // c\r\nprocedure main() {\r\n    go();\r\n    say("a\nb");\r\n    say("c\r\nd");\r\n}\r\n'
)


def test_a_crlf_file_stays_crlf_but_inside_strings() -> None:
    assert format_text(CRLF) == CRLF_FORMATTED
    assert format_text(CRLF_FORMATTED) == CRLF_FORMATTED


def test_the_first_line_ending_is_the_files() -> None:
    assert format_text("action a();\r\naction b();\naction c();\n") == "action a();\r\naction b();\r\naction c();\r\n"
    assert format_text("action a();\naction b();\r\n") == "action a();\naction b();\n"
    assert format_text("\ufeffaction a();\r\n") == "\ufeffaction a();\r\n"


def test_fmt_formats_a_file_with_a_byte_order_mark_or_crlf_line_endings(tmp_path: Path) -> None:
    (tmp_path / "bom.gpp").write_bytes(b"\xef\xbb\xbfaction a( );\n")
    (tmp_path / "crlf.gpp").write_bytes(CRLF.encode())
    result = run_gpp("fmt", "bom.gpp", "crlf.gpp", cwd=tmp_path)
    assert (result.returncode, result.stdout, result.stderr) == (0, "2 files reformatted, 0 left unchanged\n", "")
    assert (tmp_path / "bom.gpp").read_bytes() == b"\xef\xbb\xbfaction a();\n"
    assert (tmp_path / "crlf.gpp").read_bytes() == CRLF_FORMATTED.encode()
    again = run_gpp("fmt", "--check", "bom.gpp", "crlf.gpp", cwd=tmp_path)
    assert (again.returncode, again.stdout) == (0, "0 files would be reformatted, 2 already formatted\n")


def test_fmt_keeps_the_line_endings_of_standard_input(tmp_path: Path) -> None:
    # A real process: the in-process runner reads its output in text mode.
    done = subprocess.run(
        [sys.executable, "-m", "gpp", "fmt", "-"], input=CRLF.encode(), capture_output=True, cwd=tmp_path, check=False
    )
    assert (done.returncode, done.stdout, done.stderr) == (0, CRLF_FORMATTED.encode(), b"")


# ---------------------------------------------------------------- properties


def reparse(text: str) -> ast.Program:
    result = parse_text(text)
    assert result.ok, [d.message for d in result.diagnostics]
    return result.program


def assert_formats_faithfully(text: str) -> None:
    """Formatting keeps the tree, the comments, the directives and the line endings, and
    formatted text is formatted already (bench/fmtfuzz.py, without the lints)."""
    assert formatting_problems(text, Path("<input>.gpp"), lints=False) == [], format_text(text)


@pytest.mark.parametrize("path", REPO_PROGRAMS, ids=lambda p: str(p.relative_to(ROOT)))
def test_repository_program_formats_faithfully(path: Path) -> None:
    assert_formats_faithfully(path.read_text(encoding="utf-8"))


def test_there_are_repository_programs() -> None:
    folders = {p.relative_to(ROOT).parts[0] for p in REPO_PROGRAMS}
    assert {"examples", "stdlib", "tests"} <= folders
    assert len(REPO_PROGRAMS) >= 60


SOURCES = [p.read_text(encoding="utf-8") for p in REPO_PROGRAMS] + [generate_program(70, seed=s) for s in (1, 2)]
PROPERTY = settings(max_examples=examples(40), deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPERTY
@given(st.sampled_from(SOURCES), st.randoms(use_true_random=False), st.integers(1, 40))
def test_program_with_sprinkled_comments_formats_faithfully(text: str, rnd: random.Random, count: int) -> None:
    assert_formats_faithfully(sprinkle(text, rnd, count))


@PROPERTY
@given(programs, st.randoms(use_true_random=False), st.integers(0, 12))
def test_generated_tree_with_sprinkled_comments_formats_faithfully(
    program: ast.Program, rnd: random.Random, count: int
) -> None:
    assert_formats_faithfully(sprinkle(format_program(program), rnd, count))


# ---------------------------------------------------------------- gpp fmt


def run_gpp(*args: str, cwd: Path, stdin: str | None = None) -> Result:
    return run(*args, cwd=cwd, input=stdin)


UGLY = "procedure main() {a(); // first\n b();}\n"
PRETTY = "procedure main() {\n    a();  // first\n    b();\n}\n"
BROKEN = "procedure main() {\n    a()\n}\n"


@pytest.fixture
def project(tmp_path: Path) -> Path:
    (tmp_path / "ugly.gpp").write_text(UGLY)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "pretty.gpp").write_text(PRETTY)
    (tmp_path / "sub" / "notes.txt").write_text("not golog++")
    return tmp_path


def test_fmt_rewrites_files_and_walks_folders(project: Path) -> None:
    result = run_gpp("fmt", ".", cwd=project)
    assert (result.returncode, result.stdout, result.stderr) == (0, "1 file reformatted, 1 left unchanged\n", "")
    assert (project / "ugly.gpp").read_text() == PRETTY
    assert (project / "sub" / "pretty.gpp").read_text() == PRETTY


def test_fmt_check_lists_files_that_would_change(project: Path) -> None:
    result = run_gpp("fmt", "--check", "ugly.gpp", "sub", cwd=project)
    assert result.returncode == 1
    assert result.stdout == "would reformat: ugly.gpp\n1 file would be reformatted, 1 already formatted\n"
    assert (project / "ugly.gpp").read_text() == UGLY


def test_fmt_diff_prints_a_unified_diff(project: Path) -> None:
    result = run_gpp("fmt", "--diff", "ugly.gpp", cwd=project)
    assert result.returncode == 1
    assert result.stdout == (
        "--- ugly.gpp (before)\n+++ ugly.gpp (formatted)\n@@ -1,2 +1,4 @@\n"
        "-procedure main() {a(); // first\n- b();}\n"
        "+procedure main() {\n+    a();  // first\n+    b();\n+}\n"
    )
    assert result.stderr == "1 file would be reformatted, 0 already formatted\n"
    assert (project / "ugly.gpp").read_text() == UGLY


def test_fmt_reads_standard_input(tmp_path: Path) -> None:
    result = run_gpp("fmt", "-", cwd=tmp_path, stdin=UGLY)
    assert (result.returncode, result.stdout, result.stderr) == (0, PRETTY, "")
    check = run_gpp("fmt", "--check", "-", cwd=tmp_path, stdin=UGLY)
    assert (check.returncode, check.stdout) == (1, "would reformat: -\n")


def test_fmt_leaves_a_file_with_syntax_errors_unchanged(project: Path) -> None:
    (project / "broken.gpp").write_text(BROKEN)
    result = run_gpp("fmt", "broken.gpp", "ugly.gpp", cwd=project)
    assert result.returncode == 1
    assert "error[E0011]: expected `;` after this statement\n --> broken.gpp:2:8" in result.stderr
    assert result.stdout == "1 file reformatted, 0 left unchanged, 1 file with syntax errors left unchanged\n"
    assert (project / "broken.gpp").read_text() == BROKEN
    assert (project / "ugly.gpp").read_text() == PRETTY
    piped = run_gpp("fmt", "-", cwd=project, stdin=BROKEN)
    assert (piped.returncode, piped.stdout) == (1, "")
    assert "error[E0011]" in piped.stderr


def test_fmt_unreadable_files_are_usage_errors(project: Path) -> None:
    missing = run_gpp("fmt", "ugly.gpp", "missing.gpp", cwd=project)
    assert (missing.returncode, missing.stdout) == (2, "")
    assert missing.stderr == "error: cannot read 'missing.gpp': No such file or directory\n"
    (project / "latin1.gpp").write_bytes("// caf\xe9\naction a();\n".encode("latin-1"))
    binary = run_gpp("fmt", "ugly.gpp", "latin1.gpp", cwd=project)
    assert (binary.returncode, binary.stderr) == (2, "error: cannot read 'latin1.gpp': it is not UTF-8 text\n")
    # Nothing is written when a file cannot be read.
    assert (project / "ugly.gpp").read_text() == UGLY


@pytest.fixture
def immutable(project: Path) -> Iterator[Path]:
    """sub/pretty.gpp made ugly and immutable."""
    path = project / "sub" / "pretty.gpp"
    path.write_text(UGLY)
    with disks.immutable(path):
        yield path


def test_fmt_writes_nothing_when_a_file_cannot_be_written(project: Path, immutable: Path) -> None:
    (project / "last.gpp").write_text(UGLY)
    result = run_gpp("fmt", "ugly.gpp", "sub/pretty.gpp", "last.gpp", cwd=project)
    assert (result.returncode, result.stdout) == (2, "")
    assert result.stderr == "error: cannot write 'sub/pretty.gpp': it is read-only: no file was changed\n"
    assert [(project / name).read_text() for name in ("ugly.gpp", "sub/pretty.gpp", "last.gpp")] == [UGLY] * 3


@pytest.fixture
def full_disk(tmp_path: Path) -> Iterator[Path]:
    with disks.full_disk(tmp_path / "disk", {"ugly.gpp": UGLY}) as disk:
        yield disk


def test_fmt_on_a_full_disk_leaves_the_file_as_it_was(full_disk: Path) -> None:
    result = run_gpp("fmt", "ugly.gpp", cwd=full_disk)
    assert result.returncode == 2
    assert result.stderr == "error: cannot write 'ugly.gpp': No space left on device\n"
    assert result.stdout == "0 files reformatted, 0 left unchanged, 1 file could not be written (left as they were)\n"
    assert (full_disk / "ugly.gpp").read_text() == UGLY
    assert sorted(p.name for p in full_disk.iterdir()) == ["filler", "ugly.gpp"]  # no temporary file left


def test_fmt_stdin_cannot_be_combined_with_files(project: Path) -> None:
    result = run_gpp("fmt", "-", "ugly.gpp", cwd=project, stdin=UGLY)
    assert (result.returncode, result.stderr) == (
        2,
        "error: `-` (standard input) cannot be combined with other paths\n",
    )


def test_fmt_folder_without_programs_is_a_usage_error(tmp_path: Path) -> None:
    (tmp_path / "empty").mkdir()
    result = run_gpp("fmt", "empty", cwd=tmp_path)
    assert (result.returncode, result.stderr) == (2, "error: no .gpp files found in 'empty'\n")


def test_fmt_without_paths_formats_the_project_as_configured(project: Path) -> None:
    (project / "gpp.toml").write_text('paths = ["."]\nexclude = ["sub"]\n')
    (project / "sub" / "ugly_too.gpp").write_text(UGLY)
    result = run_gpp("fmt", "--check", cwd=project)
    assert (result.returncode, result.stdout) == (
        1,
        "would reformat: ugly.gpp\n1 file would be reformatted, 0 already formatted\n",
    )
    (project / "gpp.toml").write_text('paths = ["."]\nexclud = ["sub"]\n')
    bad = run_gpp("fmt", cwd=project)
    assert bad.returncode == 2
    assert "did you mean `exclude`?" in bad.stderr
    assert (project / "ugly.gpp").read_text() == UGLY


def test_examples_and_stdlib_are_formatted() -> None:
    result = run_gpp("fmt", "--check", "examples", "stdlib", cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.endswith(" already formatted\n")


def test_tokens_the_printer_adds_are_bridged_by_a_diff() -> None:
    # Not from a parsed program (the printer adds braces only to trees the parser cannot
    # produce), but the comment mapping must not depend on that.
    original, _ = tokenize(Source("a(); b();", "x"))
    printed, _ = tokenize(Source("a(); { b(); }", "x"))
    assert _token_map(original, printed) == [0, 1, 2, 3, 5, 6, 7, 8, 10]


def test_directives_after_a_byte_order_mark_are_read() -> None:
    text = "\ufeff// world: rescue\n// scenario: s.toml\naction a();\n"
    assert directives(text) == {"world": "rescue", "scenario": "s.toml"}
    assert directives(format_text(text)) == directives(text)
