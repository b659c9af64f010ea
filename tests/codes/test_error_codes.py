"""Every error code gpp reports, each triggered by a tiny realistic program (SEMANTICS §2.6).

The table `CASES` holds one row per case: an id, the program and the exact diagnostics it must
produce: code, line and column of the primary span (1-based), message and, where it matters,
the help line (did-you-mean suggestions above all). Adding a case is adding one row. A program
must produce exactly the listed diagnostics and nothing else; lints are not part of this file
(`lint=False`).

Also here: the include errors (files in tmp_path), golden files of the full rendered text
(tests/golden/check/*.txt, regenerate with `GPP_UPDATE_GOLDEN=1`, as in tests/report/test_render.py),
the "four independent mistakes" acceptance test (also through the real CLI), and tests that one
root mistake gives one diagnostic (no cascades).
"""

from __future__ import annotations

import os
import pathlib
from pathlib import Path
from typing import Any, NamedTuple

import pytest

from gpp.base.diagnostics import Diagnostic, Severity
from gpp.check import CheckResult, check_program, check_text
from gpp.codes import CODES
from gpp.report.text import render_text
from tests.support.cli import run

GOLDEN_DIR = Path(__file__).parents[1] / "golden" / "check"
UPDATE_GOLDEN = os.environ.get("GPP_UPDATE_GOLDEN") == "1"

UNCHECKED: Any = object()


class E(NamedTuple):
    """An expected diagnostic. `help` is compared only when given (None: no help line)."""

    code: str
    line: int
    col: int
    message: str
    help: str | None = UNCHECKED


def case(case_id: str, program: str, *expected: E) -> Any:
    return pytest.param(program, list(expected), id=case_id)


def describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(f"{d.span.line}:{d.span.col} {d.code} {d.message} | help: {d.help}" for d in diagnostics)


def check(program: str) -> CheckResult:
    return check_text(program, Path("agent.gpp"), lint=False)


def assert_diagnostics(diagnostics: list[Diagnostic], expected: list[E]) -> None:
    actual = [
        E(d.code, d.span.line, d.span.col, d.message, d.help if e.help is not UNCHECKED else UNCHECKED)
        for d, e in zip(diagnostics, expected, strict=False)
    ]
    assert len(diagnostics) == len(expected), describe(diagnostics)
    assert actual == expected, describe(diagnostics)


# Shared declarations, written out in each program where they are needed so that every case
# reads on its own and its line numbers are those of the text.
FLUENT_N = "number fluent n() {\ninitially:\n    () = 0;\n}\n"  # lines 1-4
ROOMS = "symbol domain Room = {kitchen, hall}\n"  # line 1
POSE = "compound Pose { number x, number y }\n"  # line 1

CASES = [
    # ------------------------------------------------------------ syntax (E00xx)
    case(
        "E0001-unexpected-character",
        FLUENT_N + "procedure main() {\n    n() = n() @ 2;\n}\n",
        E("E0001", 6, 15, "unexpected character '@'"),
    ),
    case(
        "E0002-unterminated-string",
        'action say(string s) {}\nprocedure main() {\n    say("hello\n    );\n}\n',
        E("E0002", 3, 9, "unterminated string literal"),
    ),
    case(
        "E0002-unterminated-comment",
        "action go() {}\nprocedure main() {\n    go(); /* never closed\n}\n",
        E("E0002", 3, 11, "unterminated block comment"),
    ),
    case(
        "E0003-underscore-name",
        "action _go() {}\n",
        E("E0003", 1, 8, "a name cannot start with '_'"),
    ),
    case(
        "E0004-float-literal-too-large",
        FLUENT_N + "procedure main() {\n    n() = 1e400 - 1e400;\n}\n",
        E("E0004", 6, 11, "number literal is too large"),
        E("E0004", 6, 19, "number literal is too large"),
    ),
    case(
        "E0004-whole-literal-too-large",
        FLUENT_N + "procedure main() {\n    n() = -" + "1" * 4301 + ";\n}\n",
        E("E0004", 6, 12, "number literal is too large"),
    ),
    case(
        "E0005-non-ascii-name-once-per-name",
        "number fluent größe() {\ninitially:\n    () = 0;\n}\nprocedure main() {\n"
        "    größe() = größe() + 1;\n    pick (number ñ in {1, 2}) größe() = ñ;\n}\n",
        E(
            "E0005",
            1,
            15,
            "the name `größe` has letters outside ASCII",
            "rename it, for example to `grosse` (everywhere it is used)",
        ),
        E(
            "E0005",
            7,
            18,
            "the name `ñ` has letters outside ASCII",
            "rename it, for example to `n` (everywhere it is used)",
        ),
    ),
    case(
        "E0005-non-ascii-name-without-ascii-spelling",
        "action 移動() {}\nprocedure main() {\n    移動();\n}\n",
        E("E0005", 1, 8, "the name `移動` has letters outside ASCII", None),
    ),
    case(
        "E0010-assignment-for-comparison",
        FLUENT_N + "procedure main() {\n    if (n() = 1) {}\n}\n",
        E("E0010", 6, 13, "expected one of an operator or `)`, found `=`", "to compare two values write `==`"),
    ),
    case(
        "E0010-missing-closing-parenthesis",
        "action go() {}\nprocedure main() {\n    if (true {\n        go();\n    }\n}\n",
        E("E0010", 3, 13, "expected `)`, found `{`", None),
    ),
    case(
        "E0010-misspelled-keyword",
        "procedur main() {}\n",
        E(
            "E0010",
            1,
            10,
            "expected one of `domain`, `exog_function`, `fluent` or `function`, found `main`",
            "did you mean `procedure`?",
        ),
    ),
    case(
        "E0011-missing-semicolon",
        FLUENT_N + "procedure main() {\n    n() = 1\n    n() = 2;\n}\n",
        E("E0011", 6, 12, "expected `;` after this statement"),
    ),
    case(
        "E0012-unexpected-eof",
        FLUENT_N + "procedure main() {\n    n() = 1;\n",
        E("E0012", 7, 1, "unexpected end of file, expected one of a statement or `}`"),
    ),
    case(
        "E0013-reserved-word",
        "action test() {}\n",
        E(
            "E0013",
            1,
            8,
            "`test` is a reserved word and cannot be used as a name",
            "choose another name, such as `test_`",
        ),
    ),
    case(
        "E0014-nesting-too-deep",
        "bool function deep() =\n" + "!" * 2_000 + "true\n",
        E(
            "E0014",
            2,
            2_001,
            "this expression nests more than 2000 levels deep",
            "move the inner part into a function or procedure of its own, or split the chain",
        ),
    ),
    case(
        "E0020-duplicate-section",
        "action go() {\nprecondition: true\nprecondition: false\n}\n",
        E("E0020", 3, 1, "section `precondition:` appears twice", "merge the two `precondition:` sections into one"),
    ),
    case(
        "E0021-duplicate-handler",
        "action go() {}\nprocedure main() {\n    during(go()) {} on_fail {} on_fail {}\n}\n",
        E("E0021", 3, 32, "`on_fail` handler given twice"),
    ),
    # ------------------------------------------------------------ legacy golog++ (E004x)
    case(
        "E0040-type-sigils-one-error-per-file",
        "%fluent n() {\ninitially:\n    () = 0;\n}\n?function big(%x) = %x > n()\nprocedure main() { test(big(1)); }\n",
        E(
            "E0040",
            1,
            1,
            "`%` before a name is the legacy way of writing a type",
            "write the type names instead (`gpp explain E0040`)",
        ),
    ),
    case(
        "E0041-unquoted-mapping-name",
        "action go() {\nmapping:\n    move_base {}\n}\nprocedure main() { go(); }\n",
        E(
            "E0041",
            3,
            5,
            "the mapped name `move_base` is not quoted",
            'write it as a string: `"move_base"` (`gpp explain E0041`)',
        ),
    ),
    case(
        "E0042-senses-without-assignment",
        FLUENT_N + "action look() {\nsenses:\n    n();\n}\nprocedure main() { look(); }\n",
        E("E0042", 7, 5, "`senses:` without `= ...` is legacy golog++", UNCHECKED),
    ),
    case(
        "E0043-domain-section",
        ROOMS + "action go(symbol r) {\ndomain:\n    r in Room;\n}\nprocedure main() { go(hall); }\n",
        E("E0043", 3, 1, "a `domain:` section is legacy golog++", UNCHECKED),
    ),
    case(
        "E0044-function-with-returns",
        "number function one() {\n    return 1;\n}\nprocedure main() { test(one() == 1); }\n",
        E(
            "E0044",
            1,
            23,
            "function `one` has a block body, which is legacy golog++",
            "write `= 1` (`gpp explain E0044`)",
        ),
    ),
    case(
        "E0045-exog-function-with-body",
        "number exog_function level() { }\nprocedure main() { test(level() > 0); }\n",
        E(
            "E0045",
            1,
            30,
            "exogenous function `level` has a body, which is legacy golog++",
            "end the declaration with `;` (`gpp explain E0045`)",
        ),
    ),
    case(
        "E0046-untyped-quantifier-variable",
        "number fluent at(symbol r) { initially: (r) = 0; }\nprocedure main() { test(exists (z) at(z) == 0); }\n",
        E("E0046", 2, 33, "the `exists` variable `z` has no type", "write `symbol z` (`gpp explain E0046`)"),
    ),
    case(
        "E0047-name-overloaded-by-arity",
        "number fluent level() { initially: () = 0; }\nexog_action level(number v) {\neffect:\n    level() = v;\n}\n"
        "procedure main() { test(level() == 0); }\n",
        E(
            "E0047",
            2,
            13,
            "`level` is declared with 0 and 1 parameters",
            "rename the exog_action and the calls with 1 arguments to `level_event` (`gpp explain E0047`)",
        ),
    ),
    # ------------------------------------------------------------ names (E01xx)
    case(
        "E0101-misspelled-symbol",
        ROOMS + "Room fluent at() {\ninitially:\n    () = hall;\n}\nprocedure main() {\n    at() = kitchn;\n}\n",
        E("E0101", 7, 12, "unknown name `kitchn`", "did you mean `kitchen`?"),
    ),
    case(
        "E0101-misspelled-parameter",
        "number fluent n() {\ninitially:\n    () = 0;\n}\nprocedure wait_for(number count) {\n"
        "    test(n() > cont);\n}\n",
        E("E0101", 6, 16, "unknown name `cont`", "did you mean `count`?"),
    ),
    case(
        "E0101-unknown-symbol-without-suggestion",
        ROOMS + "action go(Room r) {}\nprocedure main() {\n    go(garage);\n}\n",
        E("E0101", 4, 8, "unknown name `garage`", None),
    ),
    case(
        "E0102-fluent-without-call",
        "bool fluent ready() {\ninitially:\n    () = false;\n}\nprocedure main() {\n    test(ready);\n}\n",
        E("E0102", 6, 10, "`ready` is a fluent; call it with `ready(...)`", "write `ready()`"),
    ),
    case(
        "E0102-function-with-parameters-without-call",
        "number function twice(number k) = 2 * k\nprocedure main() {\n    test(twice == 2);\n}\n",
        E("E0102", 3, 10, "`twice` is a function; call it with `twice(...)`", "write `twice(...)` with its arguments"),
    ),
    case(
        "E0103-misspelled-action",
        "action goto() {}\nprocedure main() {\n    gotoo();\n}\n",
        E("E0103", 3, 5, "unknown action or procedure `gotoo`", "did you mean `goto`?"),
    ),
    case(
        "E0103-misspelled-fluent",
        "bool fluent ready() {\ninitially:\n    () = false;\n}\nprocedure main() {\n    test(redy());\n}\n",
        E("E0103", 6, 10, "unknown fluent or function `redy`", "did you mean `ready`?"),
    ),
    case(
        "E0103-unknown-action-in-constraint",
        "action goto() {}\ncomponent cam {\nstates:\n    on\n}\nconstraints {\n"
        "    during(got(*)): state(cam) = on;\n}\n",
        E("E0103", 7, 12, "unknown action `got`", "did you mean `goto`?"),
    ),
    case(
        "E0104-action-in-expression",
        "action go() {}\nprocedure main() {\n    test(go());\n}\n",
        E("E0104", 3, 10, "`go` is an action; only fluents and functions can be used in expressions"),
    ),
    case(
        "E0104-function-as-statement",
        "bool function done() = true\nprocedure main() {\n    done();\n}\n",
        E(
            "E0104",
            3,
            5,
            "`done` is a function and cannot be executed as a statement",
            "to wait until a condition holds, write `test(...)`",
        ),
    ),
    case(
        "E0104-fluent-as-statement",
        "bool fluent ready() {\ninitially:\n    () = false;\n}\nprocedure main() {\n    ready();\n}\n",
        E(
            "E0104",
            6,
            5,
            "`ready` is a fluent and cannot be executed as a statement",
            "to change the fluent, assign it: `ready(...) = value;`",
        ),
    ),
    case(
        "E0104-exog-action-called",
        "exog_action bump() {}\nprocedure main() {\n    bump();\n}\n",
        E(
            "E0104",
            3,
            5,
            "`bump` is an exogenous action and cannot be executed as a statement",
            "the platform reports exogenous actions; a program cannot execute them",
        ),
    ),
    case(
        "E0104-procedure-in-start",
        "procedure p() {}\nprocedure main() {\n    start(p());\n}\n",
        E("E0104", 3, 11, "`p` is a procedure; `start` needs an action"),
    ),
    case(
        "E0104-expression-as-statement",
        "number fluent n() {\ninitially:\n    () = 0;\n}\nprocedure main() {\n    (n() + 1);\n}\n",
        E(
            "E0104",
            6,
            5,
            "this expression is not a statement",
            "statements call actions or procedures, assign fluents, or `test(...)` a condition",
        ),
    ),
    case(
        "E0105-misspelled-type",
        ROOMS + "Rom fluent at() {\ninitially:\n    () = null;\n}\n",
        E("E0105", 2, 1, "unknown type `Rom`", "did you mean `Room`?"),
    ),
    case(
        "E0105-unknown-parameter-type",
        "action go(Place p) {}\n",
        E("E0105", 1, 11, "unknown type `Place`", None),
    ),
    case(
        "E0105-misspelled-compound-in-literal",
        POSE + "Pose function origin() = Pos { x = 0, y = 0 }\n",
        E("E0105", 2, 26, "unknown compound type `Pos`", "did you mean `Pose`?"),
    ),
    case(
        "E0105-compound-in-domain-expression",
        POSE + "symbol domain Place = Pose | {garden}\n",
        E("E0105", 2, 23, "`Pose` is not a domain"),
    ),
    case(
        "E0106-misspelled-field-access",
        POSE + "number function f(Pose p) = p.yy\n",
        E("E0106", 2, 31, "`Pose` has no field `yy`", "did you mean `y`?"),
    ),
    case(
        "E0106-unknown-field-in-literal",
        POSE + "Pose function origin() = Pose { x = 0, y = 0, z = 0 }\n",
        E("E0106", 2, 47, "`Pose` has no field `z`", None),
    ),
    case(
        "E0107-misspelled-state",
        "component cam {\nstates:\n    off, on\ntransitions:\n    off => onn\n}\n",
        E("E0107", 5, 12, "component `cam` has no state `onn`", "did you mean `on`?"),
    ),
    case(
        "E0107-misspelled-clock",
        "component cam {\nclocks:\n    t\nstates:\n    off, on(tt <= 5)\n}\n",
        E("E0107", 5, 13, "component `cam` has no clock `tt`", "did you mean `t`?"),
    ),
    case(
        "E0107-misspelled-component",
        "action go() {}\ncomponent cam {\nstates:\n    on\n}\nconstraints {\n    during(go()): state(camm) = on;\n}\n",
        E("E0107", 7, 25, "unknown component `camm`", "did you mean `cam`?"),
    ),
    # ------------------------------------------------------------ types (E02xx)
    case(
        "E0201-too-many-arguments",
        "action go(number k) {}\nprocedure main() {\n    go(1, 2);\n}\n",
        E("E0201", 3, 5, "`go` takes 1 argument but 2 were given"),
    ),
    case(
        "E0201-too-few-arguments",
        "number fluent dist(number k) {\ninitially:\n    (k) = 0;\n}\nprocedure main() {\n    dist() = 1;\n}\n",
        E("E0201", 6, 5, "`dist` takes 1 argument but 0 were given"),
    ),
    case(
        "E0202-assignment",
        FLUENT_N + 'procedure main() {\n    n() = "five";\n}\n',
        E("E0202", 6, 11, "expected `number`, found `string`", None),
    ),
    case(
        "E0202-assignment-to-string-suggests-to-string",
        'string fluent s() {\ninitially:\n    () = "";\n}\nprocedure main() {\n    s() = 5;\n}\n',
        E("E0202", 6, 11, "expected `string`, found `number`", "convert it with `to_string(...)`"),
    ),
    case(
        "E0202-argument",
        'action go(number k) {}\nprocedure main() {\n    go("far");\n}\n',
        E("E0202", 3, 8, "expected `number`, found `string`"),
    ),
    case(
        "E0202-initial-value",
        'number fluent n() {\ninitially:\n    () = "zero";\n}\n',
        E("E0202", 3, 10, "expected `number`, found `string`"),
    ),
    case(
        "E0202-function-body",
        'number function f() = "one"\n',
        E("E0202", 1, 23, "expected `number`, found `string`"),
    ),
    case(
        "E0202-if-condition",
        FLUENT_N + "procedure main() {\n    if (n()) {}\n}\n",
        E("E0202", 6, 9, "expected `bool`, found `number`"),
    ),
    case(
        "E0202-while-condition",
        'procedure main() {\n    while ("yes") {}\n}\n',
        E("E0202", 2, 12, "expected `bool`, found `string`"),
    ),
    case(
        "E0202-precondition",
        "action go() {\nprecondition: 1\n}\n",
        E("E0202", 2, 15, "expected `bool`, found `number`"),
    ),
    case(
        "E0202-effect-condition",
        FLUENT_N + "action go() {\neffect:\n    if (n()) n() = 1;\n}\n",
        E("E0202", 7, 9, "expected `bool`, found `number`"),
    ),
    case(
        "E0202-sensed-value",
        FLUENT_N + 'action go() {\nsenses:\n    n() = "x";\n}\n',
        E("E0202", 7, 11, "expected `number`, found `string`"),
    ),
    case(
        "E0202-list-element",
        'list[number] fluent l() {\ninitially:\n    () = list[number] [1, "two"];\n}\n',
        E("E0202", 3, 27, "expected `number`, found `string`"),
    ),
    case(
        "E0202-solve-horizon",
        'number function r() = 1\nprocedure main() {\n    solve("three", r()) {}\n}\n',
        E("E0202", 3, 11, "expected `number`, found `string`"),
    ),
    case(
        "E0202-number-domain-element",
        'number domain N = {1, "two"}\n',
        E("E0202", 1, 23, "expected `number`, found `string`"),
    ),
    case(
        "E0202-symbol-domain-element",
        "symbol domain Room = {kitchen, 1}\n",
        E("E0202", 1, 32, "expected a symbol name"),
    ),
    case(
        "E0203-initial-value-not-in-domain",
        ROOMS + "symbol domain Item = {cup}\nRoom fluent at() {\ninitially:\n    () = cup;\n}\n",
        E("E0203", 5, 10, "`cup` is not in domain `Room`"),
    ),
    case(
        "E0203-argument-not-in-number-domain",
        "number domain Small = {1, 2}\naction go(Small s) {}\nprocedure main() {\n    go(3);\n}\n",
        E("E0203", 4, 8, "`3` is not in domain `Small`"),
    ),
    case(
        "E0204-string-added-to-number",
        'number function f() = 1 + "a"\n',
        E(
            "E0204",
            1,
            25,
            "cannot add `number` and `string`",
            "convert the other operand with `to_string(...)` to concatenate",
        ),
    ),
    case(
        "E0204-subtract-string",
        'number function f() = "a" - 1\n',
        E("E0204", 1, 27, "cannot subtract `string` and `number`", None),
    ),
    case(
        "E0204-power-of-string",
        'number function f() = 2 ** "x"\n',
        E("E0204", 1, 25, "cannot raise `number` to `string`"),
    ),
    case(
        "E0204-order-number-and-string",
        'bool function f() = 1 < "a"\n',
        E("E0204", 1, 23, "cannot order `number` and `string` with `<`"),
    ),
    case(
        "E0204-compare-number-and-string",
        'bool function f() = 1 == "a"\n',
        E("E0204", 1, 23, "cannot compare `number` with `string`"),
    ),
    case(
        "E0204-not-of-number",
        "bool function f() = !1\n",
        E("E0204", 1, 22, "`!` needs `bool` operands, found `number`"),
    ),
    case(
        "E0204-minus-of-bool",
        "number function f() = -true\n",
        E("E0204", 1, 24, "`-` needs `number` operands, found `bool`"),
    ),
    case(
        "E0204-and-of-number",
        "bool function f() = 1 & true\n",
        E("E0204", 1, 21, "`&` needs `bool` operands, found `number`"),
    ),
    case(
        "E0204-arithmetic-on-null",
        "number function f() = null + 1\n",
        E("E0204", 1, 23, "`+` cannot be applied to `null`"),
    ),
    case(
        "E0204-ordering-with-null",
        "bool function f() = null < 1\n",
        E("E0204", 1, 21, "`<` cannot compare with `null`", "test `x != null` first"),
    ),
    case(
        "E0204-length-of-number",
        "number function f() = length(3)\n",
        E("E0204", 1, 30, "`length` needs a list, found `number`"),
    ),
    case(
        "E0204-to-string-of-compound",
        POSE + "string function f(Pose p) = to_string(p)\n",
        E("E0204", 2, 39, "`to_string` converts numbers, bools, symbols and strings, not `Pose`"),
    ),
    case(
        "E0204-push-back-on-number",
        FLUENT_N + "procedure main() {\n    push_back(n(), 1);\n}\n",
        E("E0204", 6, 15, "`push_back` needs a list, found `number`"),
    ),
    case(
        "E0204-clock-bound-operator",
        "component cam {\nclocks:\n    t\nstates:\n    off, on(t < 5)\n}\n",
        E("E0204", 5, 13, "a clock bound uses `<=` or `>=`"),
    ),
    case(
        "E0205-chained-comparison",
        "bool function between(number a) = 1 < a < 3\n",
        E(
            "E0205",
            1,
            35,
            "comparison operators cannot be chained",
            "compare each pair and join them with `&`: `a < b & b < c`",
        ),
    ),
    case(
        "E0206-void-fluent",
        "void fluent v() {\ninitially:\n    () = null;\n}\n",
        E("E0206", 1, 1, "`void` is not a type of data"),
    ),
    case(
        "E0207-field-of-number",
        "number function f(number k) = k.x\n",
        E("E0207", 1, 31, "`number` has no fields"),
    ),
    case(
        "E0207-index-of-number",
        FLUENT_N + "procedure main() {\n    n()[0] = 1;\n}\n",
        E("E0207", 6, 5, "`number` cannot be indexed"),
    ),
    case(
        "E0208-missing-field",
        POSE + "Pose function origin() = Pose { x = 0 }\n",
        E(
            "E0208",
            2,
            26,
            "missing field `y` in `Pose` literal",
            "give every field a value; write `null` for a field without one",
        ),
    ),
    case(
        "E0208-field-given-twice",
        POSE + "Pose function origin() = Pose { x = 0, x = 1, y = 0 }\n",
        E("E0208", 2, 40, "field `x` is given twice"),
    ),
    case(
        "E0209-compound-comparison",
        POSE + "bool function same(Pose a, Pose b) = a == b\n",
        E(
            "E0209",
            2,
            38,
            "values of type `Pose` cannot be compared with `==`",
            "compare their fields or elements instead",
        ),
    ),
    case(
        "E0210-pick-over-number",
        "action go(number k) {}\nprocedure main() {\n    pick (number k) go(k);\n}\n",
        E(
            "E0210",
            3,
            11,
            "`pick` over `number` needs a list of values",
            "write `pick (number k in {...})` or use a domain type",
        ),
    ),
    case(
        "E0210-exists-over-string",
        'bool function f() = exists(string s) s == "a"\n',
        E("E0210", 1, 28, "`exists` over `string` cannot be evaluated", "quantify over a domain, `bool` or `symbol`"),
    ),
    case(
        "E0211-branch-types",
        'number function f(bool c) = if (c) 1 else "one"\n',
        E("E0211", 1, 29, "the branches of this conditional have different types: `number` and `string`"),
    ),
    case(
        "E0212-reward-not-a-number",
        "bool function win() = true\nprocedure main() {\n    solve(3, win()) {}\n}\n",
        E("E0212", 3, 14, "the reward of `solve` must be a number, found `bool`"),
    ),
    case(
        "E0212-reward-not-a-call",
        "procedure main() {\n    solve(3, 1 + 1) {}\n}\n",
        E("E0212", 2, 14, "the reward of `solve` is a call of a number function"),
    ),
    case(
        "E0213-initial-value-argument",
        "number fluent n(number k) {\ninitially:\n    (1 + 1) = 0;\n}\n",
        E("E0213", 3, 6, "initial values must be literals"),
    ),
    case(
        "E0213-initial-value",
        "number fluent n() {\ninitially:\n    () = 1 + 1;\n}\n",
        E("E0213", 3, 10, "initial values must be literals", "compute the value in a procedure and assign it there"),
    ),
    case(
        "E0213-pick-values",
        "symbol domain D = {a, b}\nbool fluent f() {\ninitially:\n    () = false;\n}\n"
        "procedure main() {\n    pick (D x in {a, f()}) {}\n}\n",
        E("E0213", 7, 22, "`pick ... in {...}` lists literal values"),
    ),
    case(
        "E0213-number-domain",
        "number domain N = {1 + 1}\n",
        E("E0213", 1, 20, "a `number` domain lists number literals"),
    ),
    case(
        "E0213-constraint-pattern",
        "action go(number k) {}\ncomponent cam {\nstates:\n    on\n}\nconstraints {\n"
        "    during(go(1 + 1)): state(cam) = on;\n}\n",
        E("E0213", 7, 15, "constraint patterns take literals or `*`"),
    ),
    # ------------------------------------------------------------ declarations (E03xx)
    case(
        "E0301-redefinition",
        "action go() {}\naction go() {}\n",
        E("E0301", 2, 8, "`go` is defined twice", "remove one of the definitions, or rename one of them"),
    ),
    case(
        "E0302-kind-clash",
        "action go() {}\nbool fluent go() {\ninitially:\n    () = false;\n}\n",
        E("E0302", 2, 13, "`go` is already declared as an action"),
    ),
    case(
        "E0303-parameter-type",
        "action go(number k);\naction go(string k) {}\n",
        E("E0303", 2, 18, "parameter `k` has type `string` here but `number` in the forward declaration"),
    ),
    case(
        "E0303-parameter-name",
        "action go(number k);\naction go(number m) {}\n",
        E(
            "E0303",
            2,
            18,
            "parameter `m` is called `k` in the forward declaration",
            "use the same parameter names in both",
        ),
    ),
    case(
        "E0303-parameter-count",
        "action go(number k);\naction go(number k, number m) {}\n",
        E("E0303", 2, 8, "`go` is declared with 1 parameter but defined with 2"),
    ),
    case(
        "E0303-function-type",
        'number function f();\nstring function f() = "a"\n',
        E("E0303", 2, 1, "`f` is declared with type `number` but defined with type `string`"),
    ),
    case(
        "E0304-predefined-action",
        "action switch_state() {}\n",
        E("E0304", 1, 8, "`switch_state` is predefined and cannot be declared"),
    ),
    case(
        "E0304-predefined-fluent",
        "number fluent context_time() {\ninitially:\n    () = 0;\n}\n",
        E("E0304", 1, 15, "`context_time` is predefined and cannot be declared"),
    ),
    case(
        "E0305-parameter",
        "action go(number k, string k) {}\n",
        E("E0305", 1, 28, "`k` is declared twice in this list"),
    ),
    case(
        "E0305-compound-field",
        "compound Pose { number x, number x }\n",
        E("E0305", 1, 34, "`x` is declared twice in this list"),
    ),
    case(
        "E0305-mapping-argument",
        'action go() {\nmapping:\n    "go" { a = 1, a = 2 }\n}\n',
        E("E0305", 3, 19, "mapping argument `a` is given twice"),
    ),
    case(
        "E0305-component-clock",
        "component cam {\nclocks:\n    t, t\nstates:\n    on\n}\n",
        E("E0305", 3, 8, "`t` is declared twice in component `cam`"),
    ),
    case(
        "E0306-parameter-target",
        "action go(number k) {\neffect:\n    k = 1;\n}\n",
        E(
            "E0306",
            3,
            5,
            "cannot assign to parameter `k`",
            "parameters and variables are immutable; declare a fluent to hold changing values",
        ),
    ),
    case(
        "E0306-variable-target",
        "symbol domain D = {a, b}\nprocedure main() {\n    pick (D x) x = a;\n}\n",
        E("E0306", 3, 16, "cannot assign to variable `x`"),
    ),
    case(
        "E0306-function-target",
        "number function f() = 1\nprocedure main() {\n    f() = 2;\n}\n",
        E(
            "E0306",
            3,
            5,
            "cannot assign to `f`: it is a function",
            "only fluents (and their fields and elements) can be assigned",
        ),
    ),
    case(
        "E0306-expression-target",
        FLUENT_N + "procedure main() {\n    (n()) = 2;\n}\n",
        E("E0306", 6, 5, "cannot assign to this expression"),
    ),
    case(
        "E0307-initial-value-arity",
        "number fluent n(number a, number b) {\ninitially:\n    (1) = 0;\n}\n",
        E("E0307", 3, 5, "fluent `n` has 2 parameters, but this initial value gives 1 argument"),
    ),
    case(
        "E0307-parameter-in-wrong-position",
        "number fluent n(number a, number b) {\ninitially:\n    (b, 0) = 0;\n}\n",
        E(
            "E0307",
            3,
            6,
            "`b` is the parameter in position 2; here only `a` or a literal can stand",
            "a parameter name stands for every value, and only in its own position",
        ),
    ),
    case(
        "E0308-missing-parameter",
        'exog_action heard(string text, number volume) {\nmapping:\n    "/speech" { words = text }\n}\n',
        E("E0308", 3, 5, "the mapping of exogenous action `heard` does not bind `volume`", "add `volume = volume`"),
    ),
    case(
        "E0308-entry-not-a-parameter",
        'exog_action heard(string text) {\nmapping:\n    "/speech" { words = text, lang = "en" }\n}\n',
        E("E0308", 3, 38, "an exogenous action's mapping entry must be one of its parameters"),
    ),
    case(
        "E0309-exog-senses",
        FLUENT_N + "exog_action tick() {\nsenses:\n    n() = 1;\n}\n",
        E("E0309", 6, 1, "an exogenous action cannot have a `senses:` section"),
    ),
    case(
        "E0309-exog-duration",
        "exog_action tick() {\nduration: [1, 2]\n}\n",
        E(
            "E0309",
            2,
            1,
            "an exogenous action cannot have a `duration:` section",
            "exogenous actions are events the platform reports; they are not executed",
        ),
    ),
    case(
        "E0309-exog-start-effect",
        FLUENT_N + "exog_action tick() {\nstart_effect:\n    n() = 1;\n}\n",
        E("E0309", 6, 1, "an exogenous action cannot have a `start_effect:` section"),
    ),
    case(
        "E0310-main-twice",
        "action go() {}\nprocedure main() {\n    go();\n}\n{\n    go();\n}\n",
        E("E0310", 5, 1, "a legacy main block and `main` in one program"),
    ),
    case(
        "E0311-self-reference",
        "symbol domain D = D | {a}\n",
        E("E0311", 1, 15, "domain `D` is defined in terms of itself"),
    ),
    case(
        "E0311-element-types-mixed",
        "symbol domain A = {a}\nnumber domain B = A\n",
        E("E0311", 2, 19, "domain `A` has `symbol` elements, but `B` has `number` elements"),
    ),
    case(
        "E0312-silent-value",
        "action go() {\nsilent: 1\n}\n",
        E("E0312", 2, 9, "`silent:` takes `true`, `false` or `null`"),
    ),
    case(
        "E0312-bounds-reversed",
        "action go() {\nduration: [3, 1]\n}\n",
        E("E0312", 2, 1, "the lower duration bound is greater than the upper one"),
    ),
    case(
        "E0312-negative-bound",
        "action go() {\nduration: [-1, 1]\n}\n",
        E("E0312", 2, 12, "a duration bound is a non-negative number literal (seconds)"),
    ),
]


@pytest.mark.parametrize(("program", "expected"), CASES)
def test_program_reports_exactly_the_expected_diagnostics(program: str, expected: list[E]) -> None:
    result = check(program)
    assert_diagnostics(result.diagnostics, expected)
    assert all(d.severity is Severity.ERROR for d in result.diagnostics)


def test_every_error_code_has_a_case() -> None:
    covered = {e.code for param in CASES for e in param.values[1]} | {"E0006", "E0030", "E0031"}
    errors = {code for code in CODES if code.startswith("E")}
    assert errors - covered == set()


def test_every_code_in_the_table_is_registered() -> None:
    used = {e.code for param in CASES for e in param.values[1]}
    assert used <= set(CODES)


# ---------------------------------------------------------------- include errors


def test_missing_include_is_reported_at_the_path(tmp_path: Path) -> None:
    main = tmp_path / "main.gpp"
    main.write_text('#include "helpers.gpp"\nprocedure main() {}\n')
    result = check_program(main, lint=False)
    assert_diagnostics(result.diagnostics, [E("E0030", 1, 10, "cannot find included file `helpers.gpp`")])
    d = result.diagnostics[0]
    assert d.span.text == '"helpers.gpp"'
    assert len(d.notes) == 2
    assert d.notes[0].startswith("looked in ") and d.notes[0].endswith(f"{tmp_path.name}/")
    assert d.notes[1].startswith("looked in ") and d.notes[1].endswith("stdlib/")


def test_unreadable_include_is_reported_with_the_os_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    main = tmp_path / "main.gpp"
    main.write_text('#include "locked.gpp"\nprocedure main() {}\n')
    locked = tmp_path / "locked.gpp"
    locked.write_text("action go() {}\n")
    real_read_bytes = pathlib.Path.read_bytes

    def read_bytes(self: Path) -> bytes:
        if self.name == "locked.gpp":
            raise PermissionError(13, "Permission denied", str(self))
        return real_read_bytes(self)

    # Tests may run as root, where file permissions do not stop reading: fake the failure.
    monkeypatch.setattr(pathlib.Path, "read_bytes", read_bytes)
    result = check_program(main, lint=False)
    assert_diagnostics(
        result.diagnostics, [E("E0030", 1, 10, "cannot read included file `locked.gpp`: Permission denied")]
    )


def test_a_file_that_is_not_text_is_one_error_at_its_first_bad_byte(tmp_path: Path) -> None:
    main = tmp_path / "main.gpp"
    main.write_bytes(b'procedure main() {\n    say("\xa1hola!");\n}\n\xff\xfe')  # Latin-1
    result = check_program(main, lint=False)
    message = "this is not a UTF-8 text file: invalid UTF-8 byte 0xa1 at line 2, column 10"
    assert_diagnostics(result.diagnostics, [E("E0006", 2, 10, message)])
    (tmp_path / "other.gpp").write_text('#include "main.gpp"\n')
    result = check_program(tmp_path / "other.gpp", lint=False)
    message = "included file `main.gpp` is not a UTF-8 text file: invalid UTF-8 byte 0xa1 at line 2, column 10"
    assert_diagnostics(result.diagnostics, [E("E0006", 1, 10, message)])


def test_include_cycle_is_reported_in_the_file_that_closes_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "robot.gpp").write_text('#include "skills.gpp"\nprocedure main() {\n    grasp();\n}\n')
    (tmp_path / "skills.gpp").write_text('#include "robot.gpp"\naction grasp() {}\n')
    result = check_program(tmp_path / "robot.gpp", lint=False)
    assert_diagnostics(result.diagnostics, [E("E0031", 1, 10, "include cycle: robot.gpp -> skills.gpp -> robot.gpp")])
    d = result.diagnostics[0]
    assert d.span.source.path == "skills.gpp"
    assert [(s.span.source.path, s.span.line, s.span.col, s.message) for s in d.secondary] == [
        ("robot.gpp", 1, 10, "included from here")
    ]


def test_file_including_itself_is_a_cycle(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "loop.gpp").write_text('action go() {}\n#include "loop.gpp"\n')
    result = check_program(tmp_path / "loop.gpp", lint=False)
    assert_diagnostics(result.diagnostics, [E("E0031", 2, 10, "include cycle: loop.gpp -> loop.gpp")])


def test_diamond_include_is_not_a_cycle(tmp_path: Path) -> None:
    (tmp_path / "base.gpp").write_text("action go() {}\n")
    (tmp_path / "a.gpp").write_text('#include "base.gpp"\n')
    (tmp_path / "b.gpp").write_text('#include "base.gpp"\n')
    (tmp_path / "main.gpp").write_text('#include "a.gpp"\n#include "b.gpp"\nprocedure main() {\n    go();\n}\n')
    assert check_program(tmp_path / "main.gpp", lint=False).diagnostics == []


# ---------------------------------------------------------------- the four independent mistakes

FOUR_MISTAKES = """\
symbol domain Room = {kitchen, hall}

Room fluent robot_at() {
initially:
    () = hall;
}

number fluent battery() {
initially:
    () = 100;
}

string fluent status() {
initially:
    () = "";
}

action goto(Room r) {
precondition:
    robot_at() != r
effect:
    robot_at() = r;
}

procedure main() {
    goto(kitchn);
    gotoo(hall);
    battery() = "full";
    status() = "battery: " + battery();
    test(status() != "");
}
"""

FOUR_MISTAKES_EXPECTED = [
    E("E0101", 26, 10, "unknown name `kitchn`", "did you mean `kitchen`?"),
    E("E0103", 27, 5, "unknown action or procedure `gotoo`", "did you mean `goto`?"),
    E("E0202", 28, 17, "expected `number`, found `string`", None),
    E(
        "E0204",
        29,
        28,
        "cannot add `string` and `number`",
        "convert the other operand with `to_string(...)` to concatenate",
    ),
]


def test_four_independent_mistakes_are_all_reported_with_suggestions_and_nothing_else() -> None:
    result = check(FOUR_MISTAKES)
    assert_diagnostics(result.diagnostics, FOUR_MISTAKES_EXPECTED)
    assert result.errors == 4


def test_four_independent_mistakes_through_the_cli(tmp_path: Path) -> None:
    (tmp_path / "agent.gpp").write_text(FOUR_MISTAKES)
    proc = run("check", "agent.gpp", cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr
    out = proc.stdout + proc.stderr
    headers = [line for line in out.splitlines() if line.startswith(("error[", "warning["))]
    assert headers == [f"error[{e.code}]: {e.message}" for e in FOUR_MISTAKES_EXPECTED]
    locations = [line.strip() for line in out.splitlines() if line.strip().startswith("--> ")]
    assert locations == [f"--> agent.gpp:{e.line}:{e.col}" for e in FOUR_MISTAKES_EXPECTED]
    for e in FOUR_MISTAKES_EXPECTED:
        if e.help:
            assert f"= help: {e.help}" in out
    assert out.rstrip().splitlines()[-1] == "error: 4 errors"


# ---------------------------------------------------------------- golden rendered text


def check_golden(name: str, actual: str) -> None:
    path = GOLDEN_DIR / f"{name}.txt"
    if UPDATE_GOLDEN:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(actual, encoding="utf-8")
        return
    if not path.exists():
        pytest.fail(f"no golden file {path}; create it with GPP_UPDATE_GOLDEN=1")
    assert actual == path.read_text(encoding="utf-8")


GOLDEN_PROGRAMS = {
    "four_mistakes": FOUR_MISTAKES,
    "missing_semicolon": FLUENT_N + "procedure main() {\n    n() = 1\n    n() = 2;\n}\n",
    "wrong_arity": "action go(number x, number y) {}\nprocedure main() {\n    go(1);\n}\n",
    "forward_mismatch": "action go(number speed);\n\naction go(string speed) {}\n",
    "unknown_field": POSE + "number function f(Pose p) = p.yy + p.x\n",
    "exog_mapping": ('exog_action heard(string text, number volume) {\nmapping:\n    "/speech" { words = text }\n}\n'),
    "missing_compound_fields": POSE + "Pose function origin() = Pose { x = 0 }\n",
}


@pytest.mark.parametrize("name", sorted(GOLDEN_PROGRAMS))
def test_rendered_report_matches_golden(name: str) -> None:
    result = check(GOLDEN_PROGRAMS[name])
    assert result.diagnostics, "a golden case must report something"
    check_golden(name, render_text(result.diagnostics))


def test_rendered_include_cycle_matches_golden(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "robot.gpp").write_text('#include "skills.gpp"\nprocedure main() {\n    grasp();\n}\n')
    (tmp_path / "skills.gpp").write_text('#include "robot.gpp"\naction grasp() {}\n')
    result = check_program(tmp_path / "robot.gpp", lint=False)
    check_golden("include_cycle", render_text(result.diagnostics))


# ---------------------------------------------------------------- one root mistake, one diagnostic


def codes(program: str) -> list[str]:
    return [d.code for d in check(program).diagnostics]


def test_unknown_parameter_type_is_reported_once_not_at_every_use() -> None:
    program = (
        ROOMS + "Room fluent at() {\ninitially:\n    () = hall;\n}\n"
        "action go(Rom r) {\nprecondition:\n    at() != r & r != kitchen\neffect:\n    at() = r;\n}\n"
        "procedure main() {\n    go(kitchen);\n    go(hall);\n}\n"
    )
    assert_diagnostics(check(program).diagnostics, [E("E0105", 6, 11, "unknown type `Rom`", "did you mean `Room`?")])


def test_unknown_variable_type_in_pick_is_reported_once() -> None:
    program = (
        ROOMS + "action go(Room r) {}\nprocedure main() {\n    pick (Rom r in {kitchen, hall}) {\n"
        "        go(r);\n        if (r == hall) go(r);\n    }\n}\n"
    )
    assert_diagnostics(check(program).diagnostics, [E("E0105", 4, 11, "unknown type `Rom`", "did you mean `Room`?")])


def test_unknown_fluent_in_a_condition_gives_one_error() -> None:
    program = "action go() {}\nprocedure main() {\n    if (redy() & true) go();\n    while (!redy()) go();\n}\n"
    assert codes(program) == ["E0103", "E0103"]  # one per written call, nothing about `&` or `!`


def test_unknown_fluent_compared_with_a_number_gives_one_error() -> None:
    program = "action go() {}\nprocedure main() {\n    if (level() > 3 + 4) go();\n}\n"
    assert_diagnostics(check(program).diagnostics, [E("E0103", 3, 9, "unknown fluent or function `level`")])


def test_wrong_arity_call_still_checks_each_argument_once() -> None:
    program = 'action go(number k) {}\nprocedure main() {\n    go(1 + "a", 2, 3);\n}\n'
    assert_diagnostics(
        check(program).diagnostics,
        [
            E("E0201", 3, 5, "`go` takes 1 argument but 3 were given"),
            E("E0204", 3, 10, "cannot add `number` and `string`"),
        ],
    )


def test_wrong_arity_call_in_an_expression_gives_one_error() -> None:
    program = "number function sq(number k) = k * k\nbool function f() = sq(1, 2) > 3 & sq(4, 5) < 6\n"
    assert codes(program) == ["E0201", "E0201"]


def test_undefined_compound_type_in_a_literal_gives_one_error_per_literal() -> None:
    program = (
        POSE + "Pose fluent p() {\ninitially:\n    () = Pos { x = 0, y = 0 };\n}\n"
        "procedure main() {\n    p() = Pos { x = 1, y = 2 };\n    test(Pos { x = 1, y = 2 }.x > 0);\n}\n"
    )
    assert codes(program) == ["E0105", "E0105", "E0105"]


def test_undefined_compound_type_in_a_list_literal_gives_one_error() -> None:
    program = POSE + "list[Pose] fluent ps() {\ninitially:\n    () = list[Pose] [Pos { x = 0, y = 0 }];\n}\n"
    assert_diagnostics(check(program).diagnostics, [E("E0105", 4, 22, "unknown compound type `Pos`")])


def test_syntax_error_in_one_procedure_gives_no_unknown_name_errors_for_skipped_declarations() -> None:
    program = (
        FLUENT_N + "action go() {\neffect:\n    n() = n() + 1;\n}\n"
        "procedure broken() {\n    if (n() > 0 {\n        go();\n    }\n}\n"
        "procedure main() {\n    broken();\n    go();\n}\n"
    )
    assert_diagnostics(check(program).diagnostics, [E("E0010", 10, 16, "expected `)`, found `{`")])


def test_garbled_declaration_does_not_make_its_uses_unknown() -> None:
    program = (
        "number fluent battery() {\ninitially\n    () = 100;\n}\n"
        "action charge() {\neffect:\n    battery() = battery() + 10;\n}\n"
        "procedure main() {\n    charge();\n    test(battery() > 50);\n}\n"
    )
    assert codes(program) == ["E0010"]


def test_type_error_in_an_operand_is_not_reported_again_by_the_enclosing_expression() -> None:
    program = 'bool function f(number k) = (k + "a") * 2 > 3 & k > 0\n'
    assert codes(program) == ["E0204"]


def test_unknown_name_as_an_argument_is_not_also_a_type_mismatch() -> None:
    program = ROOMS + "action go(Room r) {}\nprocedure main() {\n    go(kitchn);\n}\n"
    assert codes(program) == ["E0101"]


def test_redefinition_does_not_also_report_its_body() -> None:
    program = FLUENT_N + "action go() {\neffect:\n    n() = 1;\n}\naction go() {\neffect:\n    n() = 2;\n}\n"
    assert codes(program) == ["E0301"]


# One mistake, one diagnostic: cascades found earlier, now fixed.


def test_action_as_solve_reward_gives_one_error() -> None:
    program = "action go() {}\nprocedure main() {\n    solve(3, go()) {}\n}\n"
    assert_diagnostics(
        check(program).diagnostics,
        [E("E0212", 3, 14, "the reward of `solve` must be a function, but `go` is an action")],
    )


def test_assignment_to_unknown_name_gives_one_error() -> None:
    program = "procedure main() {\n    x = 1;\n}\n"
    assert len(check(program).diagnostics) == 1, describe(check(program).diagnostics)


def test_parenthesised_action_call_statement_is_the_call() -> None:
    program = "action go() {}\nprocedure main() {\n    (go());\n}\n"
    assert codes(program) == []


def test_parenthesised_action_in_during_is_the_call() -> None:
    program = "action go() {}\nprocedure main() {\n    during((go())) {}\n}\n"
    assert codes(program) == []


def test_conflicting_domain_forward_declaration_gives_one_error() -> None:
    program = 'number domain D;\nstring domain D = {"a"}\n'
    assert codes(program) == ["E0303"]


def test_domain_of_list_type_gives_one_error() -> None:
    program = "list[number] domain L = {1}\n"
    assert_diagnostics(
        check(program).diagnostics,
        [E("E0311", 1, 1, "a domain's elements must be symbols, numbers, strings or bools, not `list[number]`")],
    )


def test_unterminated_string_before_semicolon_gives_one_error() -> None:
    program = 'string fluent s() {\ninitially:\n    () = "";\n}\nprocedure main() {\n    s() = "abc;\n}\n'
    assert codes(program) == ["E0002"]


def test_unterminated_string_in_a_call_gives_one_error() -> None:
    program = 'action say(string s) {}\nprocedure main() {\n    say("abc);\n}\n'
    assert codes(program) == ["E0002"]


def test_missing_comma_in_arguments_gives_no_arity_error() -> None:
    program = 'action go(number k, string s) {}\nprocedure main() {\n    go(1 "a");\n}\n'
    assert codes(program) == ["E0010"]


def test_missing_comma_in_initial_value_gives_no_arity_error() -> None:
    program = "number fluent n(number a, number b) {\ninitially:\n    (a b) = 0;\n}\n"
    assert codes(program) == ["E0010"]


def test_assignment_for_comparison_in_function_body_gives_one_error() -> None:
    program = "number fluent n() {\ninitially:\n    () = 0;\n}\nbool function f() = n() = 1\n"
    assert codes(program) == ["E0010"]


# Wording bugs.


def test_non_compound_type_in_a_literal_message() -> None:
    program = "symbol domain D = {a}\nD function f() = D { x = 1 }\n"
    assert_diagnostics(check(program).diagnostics, [E("E0105", 2, 18, "`D` is not a compound type")])


def test_unknown_domain_in_domain_expression_message() -> None:
    program = ROOMS + "symbol domain Place = Rooms | {garden}\n"
    assert_diagnostics(
        check(program).diagnostics, [E("E0105", 2, 23, "unknown domain `Rooms`", "did you mean `Room`?")]
    )
