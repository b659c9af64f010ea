"""Lints after an edit (gpp.check.lintmemo): the warnings of the declarations an edit left alone
are taken over from the previous check, the others linted anew.

The property: after any sequence of edits, a `Session`'s check (reusing what it can) gives
exactly the diagnostics of a check from scratch (no memo, `run_lints` over the whole program):
the same list, every field, every span with its file and offsets. Direct tests check that the
reuse happens, and that a relocation off by one would be caught.
"""

from __future__ import annotations

import dataclasses
import re
from enum import Enum
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from bench.genprog import generate_program
from gpp.base import diagnostics as diag
from gpp.base.source import Source, Span
from gpp.check import CheckResult, check_loaded, lintmemo
from gpp.check.lints import LINTS
from gpp.check.session import Session
from gpp.syntax import ast
from gpp.syntax.loader import load
from gpp.syntax.parser import parse
from tests.support.budget import examples
from tests.support.lint_triggers import TRIGGERS

ROOT = Path(__file__).resolve().parents[2]

# Every lint fires on it; the triggers declare some names twice, which is a test too (only the
# first declaration of a name is its symbol).
EVERY_LINT = "\n".join(TRIGGERS[code] for code in sorted(TRIGGERS))
# Forward declarations: a global's span, parameters and declaration are its definition's.
FORWARD = """\
symbol domain Room = {hall, kitchen}
number fluent level(Room r);
action go(Room r, number speed);
procedure visit(Room r, number unused);
number function twice(number x, number y);
number fluent level(Room r) { initially: (hall) = 1; }
action go(Room r, number speed) {
mapping:
    "go" { target = r }
}
number function twice(number x, number y) = 2 * x
procedure visit(Room r, number unused) {
    go(r, twice(1, 2));
    pick (Room kitchen) go(kitchen, 1);
    if (level(r) > 1 + 2 * 3 - 1) go(r, 1);
}
procedure later(Room hall) { if (true) go(hall, 2); }
procedure later(Room hall);
procedure main() { visit(hall, 1); later(kitchen); }
"""
# Repository programs (at their own paths: includes resolve) and generated ones.
PATTERNS = ("examples/*.gpp", "stdlib/**/*.gpp", "tests/programs/*.gpp")
REPOSITORY = sorted(p for pattern in PATTERNS for p in ROOT.glob(pattern))
CORPUS: list[tuple[Path, str]] = [
    *((p, p.read_text(encoding="utf-8")) for p in REPOSITORY),
    (ROOT / "every_lint.gpp", EVERY_LINT),
    (ROOT / "forward.gpp", FORWARD),
    (ROOT / "generated.gpp", generate_program(150)),
    (ROOT / "generated_flat.gpp", generate_program(120, seed=2, nesting=1)),
]
PASTES = [text for _, text in CORPUS]


def plain(value: object) -> object:
    """A diagnostic as nested tuples, each span as (file identity, start, end)."""
    if isinstance(value, Span):
        return (value.source.identity, value.start, value.end)
    if isinstance(value, Enum):
        return value.name
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (type(value).__name__, *(plain(getattr(value, f.name)) for f in dataclasses.fields(value)))
    if isinstance(value, tuple | list):
        return tuple(plain(v) for v in value)
    return value


def from_scratch(path: Path, text: str) -> CheckResult:
    return check_loaded(load([path], {path: text}))


def assert_same(got: list[diag.Diagnostic], want: list[diag.Diagnostic]) -> None:
    assert [plain(d) for d in got] == [plain(d) for d in want]


# ---------------------------------------------------------------- random edit sequences

SNIPPETS = [" ", "\n", "x", "1", ";", "{", "}", "(", ")", "//", "/*", "*/", "=", "!", "&", "+", "*"]
# Statements typed into a procedure body (after a `{` or a `;`).
STATEMENTS = [
    " pick (bool b) ",
    " while (true) { }",
    " while (false) ",
    " if (true) ",
    " if (1 > 2) { } else ",
    " test(true);",
    " solve(2, 0) ",
    " search ",
    " choose { } ",
    " x;",
]
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


def body_places(text: str) -> list[int]:
    """Offsets just after a `{` or `;` inside the body of a procedure: statements go there."""
    places: list[int] = []
    for decl in parse(Source(text)).program.declarations:
        if isinstance(decl, ast.ProcedureDecl) and decl.body is not None:
            span = decl.body.span
            places.extend(k + 1 for k in range(span.start, span.end - 1) if text[k] in "{;")
    return places


@st.composite
def edit(draw: st.DrawFn, text: str) -> str:
    kind = draw(st.sampled_from(["insert", "delete", "paste", "statement", "name", "letter", "between"]))
    if kind in ("statement", "name", "letter") and not body_places(text):
        kind = "insert"
    pos = draw(st.integers(0, len(text)))
    cut = 0
    if kind == "insert":
        piece = draw(st.sampled_from(SNIPPETS))
    elif kind == "delete":
        piece, cut = "", draw(st.integers(1, 30))
    elif kind == "paste":
        other = draw(st.sampled_from(PASTES))
        start = draw(st.integers(0, len(other)))
        piece = other[start : start + draw(st.integers(1, 300))]
    elif kind == "between":
        # Whitespace or a comment between two declarations.
        places = [0, *(m.end() for m in re.finditer(r"\n(?=\S)", text))]
        pos = draw(st.sampled_from(places))
        piece = draw(st.sampled_from(["\n", "  ", "// note\n", "\n\n\n"]))
    else:
        pos = draw(st.sampled_from(body_places(text)))
        if kind == "statement":
            piece = draw(st.sampled_from(STATEMENTS))
        else:
            names = sorted(set(IDENTIFIER.findall(text)))
            name = draw(st.sampled_from(names))
            # A name typed as a call statement, or one letter typed into the name after `pos`.
            piece = f" {name}();" if kind == "name" else draw(st.sampled_from("aez"))
            if kind == "letter":
                m = IDENTIFIER.search(text, pos)
                pos = m.end() if m is not None else pos
    return text[:pos] + piece + text[pos + cut :]


@st.composite
def edit_sequence(draw: st.DrawFn) -> tuple[Path, list[str]]:
    path, text = draw(st.sampled_from(CORPUS))
    texts = [text]
    for _ in range(draw(st.integers(1, 6))):
        text = draw(edit(text))
        texts.append(text)
    return path, texts


@settings(
    max_examples=examples(60), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
@given(edit_sequence())
def test_a_session_lints_as_a_check_from_scratch_after_any_edits(case: tuple[Path, list[str]]) -> None:
    path, texts = case
    session = Session()
    for k, text in enumerate(texts):
        note(f"step {k}: {text!r}")
        got = session.check(path, {path: text})
        assert_same(got.diagnostics, from_scratch(path, text).diagnostics)


# The global lints: an edit in one procedure body changes what they say about another,
# unchanged declaration. (Program, the edit as (old, new), the declaration warned about after.)
ACROSS = {
    "W0101": (
        "action a() { }\nprocedure p() { a(); }\nprocedure main() { p(); }\n",
        ("{ a(); }", "{ }"),
        "action a() { }",
    ),
    "W0105": (
        "procedure q() { pick (bool b) test(b); }\nnumber function r() = 0\nprocedure main() { solve(2, r()) q(); }\n",
        ("solve(2, r()) q();", "q();"),
        "procedure q() { pick (bool b) test(b); }",
    ),
    "W0109": (
        "procedure c() { choose { test(true); test(true); } }\nnumber function r() = 0\n"
        "procedure main() { solve(2, r()) c(); }\n",
        ("choose { test(true); test(true); }", "test(true);"),
        "procedure main() { solve(2, r()) c(); }",
    ),
    "W0114": (
        "action act() { }\nprocedure e() { end(act()); }\nprocedure main() { start(act()); e(); }\n",
        ("end(act());", "test(true);"),
        "procedure main() { start(act()); e(); }",
    ),
}


@pytest.mark.parametrize("code", sorted(ACROSS))
def test_a_global_lint_sees_an_edit_in_another_body(code: str) -> None:
    text, (old, new), warned = ACROSS[code]
    path = ROOT / f"across_{code}.gpp"
    edited = text.replace(old, new)
    session = Session()
    before = session.check(path, {path: text})
    after = session.check(path, {path: edited})
    assert code not in {d.code for d in before.diagnostics}
    start = edited.index(warned)
    assert [d.code for d in after.diagnostics if start <= d.span.start < start + len(warned)] == [code]
    assert after.lint_memo is not None and after.lint_memo.reused > 0  # the warned one among them
    assert_same(after.diagnostics, from_scratch(path, edited).diagnostics)


def test_the_corpus_has_every_lint_fire() -> None:
    found = {d.code for d in from_scratch(ROOT / "every_lint.gpp", EVERY_LINT).diagnostics}
    assert set(LINTS) <= found
    assert {"W0102", "W0103", "W0111"} <= {d.code for d in from_scratch(ROOT / "forward.gpp", FORWARD).diagnostics}


# ---------------------------------------------------------------- the reuse happens

BENCH = generate_program(1000)
BENCH_PATH = ROOT / "generated-1000.gpp"


def middle_body_edit(text: str, letter: str) -> str:
    """A letter typed at the end of the name in an `if` condition, in the procedure body
    nearest the middle of the text."""
    bodies = [
        d.body.span
        for d in parse(Source(text)).program.declarations
        if isinstance(d, ast.ProcedureDecl) and d.body is not None and "if (" in d.body.span.text
    ]
    body = min(bodies, key=lambda b: abs(b.start - len(text) // 2))
    m = IDENTIFIER.match(text, text.index("if (", body.start) + len("if ("))
    assert m is not None and m.end() < body.end
    return text[: m.end()] + letter + text[m.end() :]


def test_a_body_edit_relints_one_declaration() -> None:
    session = Session()
    first = session.check(BENCH_PATH, {BENCH_PATH: BENCH})
    assert first.lint_memo is not None and first.lint_memo.reused == 0
    edited = middle_body_edit(BENCH, "x")
    second = session.check(BENCH_PATH, {BENCH_PATH: edited})
    declarations = second.loaded.files[0].program.declarations
    assert second.lint_memo is not None
    # Every declaration but the edited one: its text changed, and it is where the warnings
    # that cannot move with a single declaration would be.
    assert second.lint_memo.reused == len(declarations) - 1
    assert_same(second.diagnostics, from_scratch(BENCH_PATH, edited).diagnostics)
    # Typing the letter away again: the warnings of all declarations come back.
    third = session.check(BENCH_PATH, {BENCH_PATH: BENCH})
    assert third.lint_memo is not None and third.lint_memo.reused == len(declarations) - 1
    assert_same(third.diagnostics, first.diagnostics)


def test_another_environment_lints_everything() -> None:
    session = Session()
    session.check(BENCH_PATH, {BENCH_PATH: BENCH})
    # A new fluent between two declarations: the environment changed.
    at = BENCH.index("\nprocedure ") + 1
    edited = BENCH[:at] + "number fluent extra() { initially: () = 1; }\n" + BENCH[at:]
    result = session.check(BENCH_PATH, {BENCH_PATH: edited})
    assert result.lint_memo is not None and result.lint_memo.reused == 0
    assert_same(result.diagnostics, from_scratch(BENCH_PATH, edited).diagnostics)


def test_a_relocation_off_by_one_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """The comparison above sees a warning moved one character too far."""
    relocate = lintmemo.relocate_diagnostic

    def off_by_one(d: diag.Diagnostic, source: Source, delta: int) -> diag.Diagnostic:
        return relocate(d, source, delta + 1)

    session = Session()
    session.check(BENCH_PATH, {BENCH_PATH: BENCH})
    edited = middle_body_edit(BENCH, "x")
    monkeypatch.setattr(lintmemo, "relocate_diagnostic", off_by_one)
    got = session.check(BENCH_PATH, {BENCH_PATH: edited})
    want = from_scratch(BENCH_PATH, edited)
    assert len(got.diagnostics) == len(want.diagnostics)
    assert [plain(d) for d in got.diagnostics] != [plain(d) for d in want.diagnostics]
