"""Incremental re-parsing (gpp.syntax.incremental, used by loader.ParseCache).

The property: after any sequence of edits, the cache's incremental parse equals a full parse
of the new text exactly: the same syntax tree with the same spans (AST `==` ignores spans, so
`assert_same_parse` compares them field by field, Source identity included), the same
tokens and the same diagnostics. Direct tests check that a simple edit takes the fast path
(only the touched declarations are parsed) and that each case that cannot be spliced exactly
falls back.
"""

from __future__ import annotations

import dataclasses
import threading
from bisect import bisect_left
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from bench.genprog import generate_program
from gpp.base.source import Source, Span
from gpp.syntax import ast
from gpp.syntax.fast import relocate
from gpp.syntax.incremental import fragment_text
from gpp.syntax.lexer import Token, Tokens
from gpp.syntax.loader import ParseCache
from gpp.syntax.parser import ParseResult, parse
from tests.support.budget import examples

ROOT = Path(__file__).resolve().parents[2]

CORPUS = sorted(
    [
        *ROOT.glob("examples/*.gpp"),
        *ROOT.glob("stdlib/**/*.gpp"),
        *ROOT.glob("tests/programs/*.gpp"),
        *ROOT.glob("tests/legacy/*.gpp"),
    ]
)
TEXTS = [p.read_text(encoding="utf-8") for p in CORPUS] + [generate_program(60)]
PATH = Path("/virtual/edited.gpp")


# ---------------------------------------------------------------- exact comparison


def assert_same_tree(got: Any, want: Any, where: str = "program") -> None:
    """Field by field, spans included (a Span compares its Source by identity), and a child node
    has its parent's span object itself exactly where the wanted tree's child has it."""
    assert type(got) is type(want), where
    if isinstance(want, ast.Node):
        for f in dataclasses.fields(want):
            assert_same_tree(getattr(got, f.name), getattr(want, f.name), f"{where}.{f.name}")
            child = getattr(want, f.name)
            if isinstance(child, ast.Node):
                assert (getattr(got, f.name).span is got.span) == (child.span is want.span), f"{where}.{f.name}"
    elif isinstance(want, tuple):
        assert len(got) == len(want), where
        for k, (g, w) in enumerate(zip(got, want, strict=True)):
            assert_same_tree(g, w, f"{where}[{k}]")
    elif isinstance(want, Span):
        assert got.source is want.source, where
        assert (got.start, got.end) == (want.start, want.end), where
    else:
        assert got == want, where


def assert_same_parse(got: ParseResult, want: ParseResult) -> None:
    assert got.program.span.source is want.program.span.source
    assert_same_tree(got.program, want.program)
    assert [(t.type, t.value, t.start, t.end) for t in got.tokens] == [
        (t.type, t.value, t.start, t.end) for t in want.tokens
    ]
    # Diagnostics are dataclasses down to their spans, whose Source compares by identity.
    assert got.diagnostics == want.diagnostics


def check_step(cache: ParseCache, text: str) -> ParseResult:
    """Parse `text` through the cache and compare with a full parse of the same Source."""
    got = cache.parse(PATH, text)
    source = got.program.span.source
    assert source.text == text
    assert_same_parse(got, parse(source))
    return got


# ---------------------------------------------------------------- random edit sequences

SNIPPETS = [
    " ",
    "\r\n",
    "\r",
    "\n",
    "x",
    "1",
    ";",
    "{",
    "}",
    "(",
    ")",
    '"',
    "/*",
    "*/",
    "//",
    "%",
    "=",
    '#include "x.gpp"\n',
    "action a() {}\n",
    "number fluent f() { initially: () = 1; }\n",
    "procedure p() { a(); }\n",
    "component c { }\n",
    "}\n{",
    "if (",
    "ö",
    "effectt(); ",
    "procedur ",
]
# Where edits are made: anywhere, or next to what changes lexing or nesting.
MARKS = ['"', "//", "/*", "*/", "{", "}", ";", "\n", "#include", "component"]


@st.composite
def edit(draw: st.DrawFn, text: str) -> str:
    mark = draw(st.sampled_from([None, *MARKS]))
    if mark is not None and mark in text:
        places = [i for i in range(len(text)) if text.startswith(mark, i)]
        pos = draw(st.sampled_from(places)) + draw(st.integers(-2, len(mark) + 2))
    else:
        pos = draw(st.integers(0, len(text)))
    pos = max(0, min(pos, len(text)))
    kind = draw(st.sampled_from(["insert", "delete", "replace", "paste"]))
    cut = draw(st.integers(0, 12)) if kind in ("delete", "replace") else 0
    if kind == "paste":
        other = draw(st.sampled_from(TEXTS))
        start = draw(st.integers(0, len(other)))
        piece = other[start : start + draw(st.integers(1, 200))]
    elif kind == "delete":
        piece = ""
    else:
        piece = draw(st.sampled_from(SNIPPETS))
    return text[:pos] + piece + text[pos + cut :]


@st.composite
def edit_sequence(draw: st.DrawFn) -> list[str]:
    text = draw(st.sampled_from(TEXTS))
    texts = [text]
    for _ in range(draw(st.integers(1, 5))):
        text = draw(edit(text))
        texts.append(text)
    return texts


@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(edit_sequence())
def test_incremental_parse_equals_full_parse(texts: list[str]) -> None:
    cache = ParseCache()
    for k, text in enumerate(texts):
        note(f"step {k}: {text!r}")
        check_step(cache, text)


def test_the_random_edits_reach_every_path() -> None:
    """The edits above are not all fallbacks: a fixed sample of them takes each path."""
    cache = ParseCache()
    for text in TEXTS[:12]:
        first = text.index(";") + 1 if ";" in text else 0
        last = text.rindex("}") if "}" in text else len(text)
        for new in (text, text[:last] + "\n" + text[last:], text[:first] + " x(" + text[first:]):
            check_step(cache, new)
    assert set(cache.reparses) >= {"splice", "tail"}


def fields(tokens: list[Token]) -> list[tuple[str, str, int, int]]:
    return [(t.type, t.value, t.start, t.end) for t in tokens]


def assert_same_tokens(got: Tokens, want: list[Token]) -> None:
    """What `got` answers before its list is made (length, each token, the bisection by start
    at and between the starts), then its list: those of `want`."""
    assert len(got) == len(want)
    assert fields([got.at(k) for k in range(len(want))]) == fields(want)
    offsets = sorted({o for t in want for o in (t.start - 1, t.start, t.start + 1)} | {0, 10**9})
    starts = [t.start for t in want]
    assert [got.bisect_start(o) for o in offsets] == [bisect_left(starts, o) for o in offsets]
    assert fields(got.as_list()) == fields(want)


@settings(
    max_examples=examples(25), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
@given(edit_sequence())
def test_tokens_read_after_later_edits_are_those_of_a_full_parse(texts: list[str]) -> None:
    """The cache's parses are kept and their tokens read only once every edit is made (a
    spliced parse's tokens are then made from pieces of the parses before it, themselves not
    made yet)."""
    cache = ParseCache()
    results = [cache.parse(PATH, text) for text in texts]
    for k, (text, got) in enumerate(zip(texts, results, strict=True)):
        note(f"step {k}: {text!r}")
        assert_same_tokens(got.lazy_tokens, parse(Source(text)).tokens)


def test_spliced_tokens_are_made_when_first_read() -> None:
    """A chain of splices, none of whose tokens is read, then read from the last one first:
    each is made from pieces of the ones before it, more of them than a sequence keeps."""
    cache = ParseCache()
    starts = Source(PROGRAM).line_starts
    texts = [PROGRAM]
    for k in range(1, 16):  # a space at the start of a line further down each time
        at = starts[k * (len(starts) - 2) // 16] + k - 1
        texts.append(texts[-1][:at] + " " + texts[-1][at:])
    results = [cache.parse(PATH, text) for text in texts]
    assert cache.reparses == {"splice": 15}
    assert [r.lazy_tokens.made for r in results[1:4]] == [False, False, False]
    for text, got in reversed(list(zip(texts, results, strict=True))):
        assert_same_tokens(got.lazy_tokens, parse(Source(text)).tokens)
        assert got.tokens is got.tokens  # made once


def test_tokens_read_on_many_threads_at_once_are_made_once() -> None:
    at = Source(PROGRAM).line_starts[5]
    cache = ParseCache()
    cache.parse(PATH, PROGRAM)
    for round in range(5):
        text = PROGRAM[:at] + " " * (round + 1) + PROGRAM[at:]
        lazy = cache.parse(PATH, text).lazy_tokens
        assert not lazy.made
        barrier = threading.Barrier(8)
        read: list[list[Token]] = []

        def reader(lazy: Tokens = lazy, barrier: threading.Barrier = barrier, read: list[list[Token]] = read) -> None:
            barrier.wait()
            read.append(lazy.as_list())

        threads = [threading.Thread(target=reader) for _ in range(8)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert len(read) == 8 and all(r is read[0] for r in read)
        assert fields(read[0]) == fields(parse(Source(text)).tokens)


# ---------------------------------------------------------------- which path an edit takes

PROGRAM = generate_program(60)


def reparse_how(old: str, new: str) -> str:
    cache = ParseCache()
    check_step(cache, old)
    check_step(cache, new)
    assert sum(cache.reparses.values()) == 1
    return next(iter(cache.reparses))


def test_an_edit_inside_one_declaration_is_spliced() -> None:
    at = PROGRAM.index("speed = 0.5") + len("speed = 0.")
    assert reparse_how(PROGRAM, PROGRAM[:at] + "75" + PROGRAM[at + 1 :]) == "splice"


@pytest.mark.parametrize("where", ["start", "middle", "end"])
def test_a_space_at_the_start_of_a_line_is_spliced(where: str) -> None:
    starts = Source(PROGRAM).line_starts
    at = {"start": starts[1], "middle": starts[len(starts) // 2], "end": starts[-2]}[where]
    assert reparse_how(PROGRAM, PROGRAM[:at] + " " + PROGRAM[at:]) == "splice"


def test_a_new_declaration_between_two_is_spliced() -> None:
    at = PROGRAM.index("\ncompound") + 1
    assert (
        reparse_how(PROGRAM, PROGRAM[:at] + "number fluent extra() { initially: () = 1; }\n" + PROGRAM[at:]) == "splice"
    )


def test_the_splice_parses_only_the_touched_declaration() -> None:
    cache = ParseCache()
    check_step(cache, PROGRAM)
    at = PROGRAM.index("speed = 0.5") + len("speed = 0.")
    got = check_step(cache, PROGRAM[:at] + "7" + PROGRAM[at + 1 :])
    assert cache.reparses == {"splice": 1}
    # The untouched declarations were moved into the new Source, not parsed again.
    assert got.program.declarations[0].span.source is got.program.span.source


def test_while_an_edit_is_under_way_the_last_clean_parse_is_spliced() -> None:
    """Typing `7;` after `speed = 0.5` in two steps: the first leaves a syntax error (parsed
    from the declaration before to the end), the second is spliced into the last parse that
    had no error."""
    cache = ParseCache()
    at = PROGRAM.index("speed = 0.5") + len("speed = 0.5")
    check_step(cache, PROGRAM)
    check_step(cache, PROGRAM[:at] + " +" + PROGRAM[at:])
    assert cache.reparses == {"tail": 1}
    check_step(cache, PROGRAM[:at] + " + 7" + PROGRAM[at:])
    assert cache.reparses == {"tail": 1, "splice": 1}


def test_without_incremental_every_change_is_parsed_whole() -> None:
    cache = ParseCache(incremental=False)
    cache.parse(PATH, PROGRAM)
    cache.parse(PATH, PROGRAM + "\n")
    assert (cache.misses, dict(cache.reparses)) == (2, {"full": 1})


# Each case that a splice cannot take: (old text, new text, the path it must take).
SIGIL_PROGRAM = "%fluent f() { initially: () = 1; }\naction a() { }\naction b() { }\n"
DEEP = "procedure deep() { x = " + "!" * 2100 + "true; }\n"
FALLBACKS = {
    # A syntax error in the edited declaration: parsed again from the declaration before it.
    "syntax error": (PROGRAM, PROGRAM.replace("speed = 0.5", "speed = = 0.5", 1), "tail"),
    "unterminated block comment": (PROGRAM, PROGRAM.replace("\ncompound", "\n/* compound", 1), "tail"),
    "block comment closed further on": (
        PROGRAM + "/* c */\n",
        PROGRAM.replace("\ncompound", "\n/*compound", 1) + "/* c */\n",
        "tail",
    ),
    "string opened": (PROGRAM, PROGRAM.replace('frame = "map"', 'frame = "map', 1), "tail"),
    "unbalanced brace": (PROGRAM, PROGRAM.replace("\ncompound", "\n{ compound", 1), "tail"),
    # An error in the first declaration: nothing before it to keep.
    "error in the first declaration": (PROGRAM, "x(" + PROGRAM, "full"),
    # An old error before the edit: its recovery may reach anywhere.
    "old error before the edit": ("x(" + PROGRAM, "x(" + PROGRAM + "\n", "full"),
    "legacy form": (SIGIL_PROGRAM, SIGIL_PROGRAM.replace("action b", "action bb"), "full"),
    "nesting limit": (DEEP + PROGRAM, DEEP + PROGRAM + "\n", "full"),
    "include changed": (
        PROGRAM + '#include "a.gpp"\n',
        PROGRAM + '#include "b.gpp"\n',
        "full",
    ),
}


@pytest.mark.parametrize("case", FALLBACKS)
def test_what_cannot_be_spliced_falls_back(case: str) -> None:
    old, new, how = FALLBACKS[case]
    assert reparse_how(old, new) == how


# ---------------------------------------------------------------- relocation


def test_relocate_moves_every_span_into_the_new_source() -> None:
    old = parse(Source(PROGRAM, "old.gpp"))
    target = Source(" " * 7 + PROGRAM, "new.gpp")
    want = parse(target)
    moved = ast.Program(
        span=Span(target, 0, len(target.text)),
        declarations=tuple(relocate(d, target, 7) for d in old.program.declarations),
    )
    assert_same_tree(moved, want.program)


def test_relocate_without_moving_puts_every_span_into_the_new_source() -> None:
    old = parse(Source(PROGRAM, "old.gpp"))
    target = Source(PROGRAM, "new.gpp")
    moved = ast.Program(
        span=Span(target, 0, len(target.text)),
        declarations=tuple(relocate(d, target, 0) for d in old.program.declarations),
    )
    assert_same_tree(moved, parse(target).program)


def test_a_relocated_main_block_shares_its_span_with_its_body() -> None:
    text = "action a() { }\n{ a(); }\n"
    old = parse(Source(text)).program.declarations[-1]
    target = Source("\n" + text, "new.gpp")
    moved = relocate(old, target, 1)
    assert type(moved) is ast.MainBlock and old.body.span is old.span
    assert moved.body.span is moved.span
    assert_same_tree(moved, parse(target).program.declarations[-1])


def test_the_comparison_sees_a_span_that_differs() -> None:
    source = Source(PROGRAM)
    a = parse(source).program
    b = ast.Program(span=a.span, declarations=tuple(relocate(d, source, 1) for d in a.declarations))
    assert a == b  # AST equality ignores spans...
    with pytest.raises(AssertionError):
        assert_same_tree(b, a)  # ...the comparison of the tests does not


def test_the_fragment_is_parsed_at_its_own_lines_and_columns() -> None:
    """The text a fragment is parsed in has the whole file's line and column at every offset of
    the fragment, whatever the line breaks before it (`\\n`, `\\r\\n`, a lone `\\r`)."""
    text = "action a() { }\r\n// one\rnumber fluent f() { initially: () = 1; }\n\n  action b() { }\r\n"
    source = Source(text)
    lo = text.index("  action b")
    padded = fragment_text(source, source, lo, len(text))
    assert len(padded) == len(text)
    assert padded[lo:] == text[lo:] and not padded[:lo].strip()
    assert [Source(padded).line_col(k) for k in range(lo, len(text) + 1)] == [
        source.line_col(k) for k in range(lo, len(text) + 1)
    ]


@pytest.mark.parametrize("edited", ["list[Pose1] fluent", "number fluent count1"])
def test_a_stray_token_before_the_edit_is_parsed_again(edited: str) -> None:
    """A stray `;` after a declaration (an error), then an error typed one or two declarations
    further: the tail starts at the declaration before the `;` (where the parser meets the `;`
    after the `}` as in the whole file), not between the `;` and the declaration after it."""
    at = PROGRAM.index("\n", PROGRAM.index("compound Pose1"))
    stray = PROGRAM[:at] + ";" + PROGRAM[at:]
    later = stray.index(edited, at) + len(edited) + 1
    assert reparse_how(stray, stray[:later] + "x(" + stray[later:]) == "tail"


@pytest.mark.parametrize("typo", ["effectt", "precondtion", "initialy"])
def test_an_old_error_whose_hint_reads_the_edited_declaration(typo: str) -> None:
    """The error in `q` says "did you mean `effect:`?" because of a name in `p` on the line
    before: renaming it changes the message, so the old error cannot be kept as it is."""
    old = f"action a() {{ }}\naction b() {{ }}\n\n\nprocedure p() {{ {typo}(); }}\nprocedure q() {{ x = ; }}\n"
    assert parse(Source(old)).diagnostics[0].help is not None
    assert reparse_how(old, old.replace(typo, "abc")) == "tail"
