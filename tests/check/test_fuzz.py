"""Robustness of `gpp check`: whatever the input, it reports diagnostics and never crashes.

Property: `check_text` returns Diagnostic objects, each with a registered code, a non-empty
message and spans that lie inside their source text, and the report renders; nothing raises.
Inputs: (a) the example programs with random token-level mutations, (b) random text and bytes,
odd unicode, token soup, very long lines and deep nesting, (c) the real CLI on mutated files
(exit code 0 or 1, never 3, no traceback), (d) the fuzzers of `make fuzz` (bench/fuzz.py, whose
mutations and well-formedness check these tests share) for a few seconds.

Failing inputs are reproducible: hypothesis prints the falsifying example and, through `note`,
the exact text that was checked. Deep nesting (2,000 levels of every construct) must check
cleanly too: the checker runs on a thread with a deep stack.
"""

from __future__ import annotations

import os
import random
import subprocess
import sys
import traceback
from collections.abc import Callable
from pathlib import Path

import pytest
from hypothesis import HealthCheck, currently_in_test_context, given, note, reject, settings
from hypothesis import strategies as st

from bench.fuzz import FUZZ_PATH, VOCABULARY, check_diagnostic, mutate, pieces
from gpp.base.diagnostics import Diagnostic
from gpp.check import check_text
from gpp.report.text import render_text
from tests.support.budget import examples
from tests.support.cli import Result, run

ROOT = Path(__file__).resolve().parents[2]
# The token-level mutations and the vocabulary are those of `make fuzz` (bench/fuzz.py).

PROGRAMS = sorted([*ROOT.glob("examples/*.gpp"), *ROOT.glob("tests/programs/*.gpp")])

FUZZ = settings(max_examples=examples(500), deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ---------------------------------------------------------------- the property


# Crashes found by fuzzing and not yet fixed, as (exception type, file, function of the
# innermost gpp frame): the random tests skip inputs that hit one, so that they go on finding
# new ones. Each needs its own test below. None at the moment.
KNOWN_CRASHES: set[tuple[type[BaseException], str, str]] = set()


def known_crash(e: BaseException) -> bool:
    frames = [f for f in traceback.extract_tb(e.__traceback__) if f"{os.sep}gpp{os.sep}" in f.filename]
    if not frames:
        return False
    where = (Path(frames[-1].filename).name, frames[-1].name)
    return any(isinstance(e, kind) and where == (module, function) for kind, module, function in KNOWN_CRASHES)


def assert_checks_cleanly(text: str) -> list[Diagnostic]:
    """Check `text`: every diagnostic well formed, the report renders, nothing raises."""
    if currently_in_test_context():
        note(f"checked text: {text!r}")
    try:
        result = check_text(text, FUZZ_PATH, lint=False)
    except Exception as e:
        if currently_in_test_context() and known_crash(e):
            reject()  # a bug captured by an xfail test below; keep looking for other ones
        raise
    assert isinstance(result.diagnostics, list)
    for d in result.diagnostics:
        check_diagnostic(d)  # registered code, a message, spans inside the text
        if d.span.source.path == result.loaded.files[-1].source.path:
            assert d.span.source.text == text
    render_text(result.diagnostics)
    return result.diagnostics


# ---------------------------------------------------------------- (a) mutated valid programs


PIECES = {p.name: pieces(p.read_text(encoding="utf-8")) for p in PROGRAMS}


def test_there_are_programs_to_mutate() -> None:
    assert PROGRAMS, "examples/*.gpp should exist"
    for path in PROGRAMS:
        assert "".join(PIECES[path.name]) == path.read_text(encoding="utf-8")


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_unmutated_program_checks_cleanly(path: Path) -> None:
    assert_checks_cleanly(path.read_text(encoding="utf-8"))


@FUZZ
@given(name=st.sampled_from(sorted(PIECES)), rnd=st.randoms(use_true_random=False), steps=st.integers(1, 4))
def test_mutated_program_never_crashes_the_checker(name: str, rnd: random.Random, steps: int) -> None:
    note(f"program: {name}")
    assert_checks_cleanly(mutate(PIECES[name], rnd, steps))


@FUZZ
@given(name=st.sampled_from(sorted(PIECES)), rnd=st.randoms(use_true_random=False))
def test_heavily_mutated_program_never_crashes_the_checker(name: str, rnd: random.Random) -> None:
    note(f"program: {name}")
    assert_checks_cleanly(mutate(PIECES[name], rnd, 25))


@settings(max_examples=examples(60), deadline=None)
@given(name=st.sampled_from(sorted(PIECES)), data=st.data())
def test_every_prefix_of_a_program_checks_cleanly(name: str, data: st.DataObject) -> None:
    text = "".join(PIECES[name])
    cut = data.draw(st.integers(0, len(text)), label="cut")
    assert_checks_cleanly(text[:cut])


# ---------------------------------------------------------------- (b) random text


@FUZZ
@given(st.text(max_size=300))
def test_random_text_never_crashes_the_checker(text: str) -> None:
    assert_checks_cleanly(text)


@FUZZ
@given(st.binary(max_size=300))
def test_random_bytes_decoded_like_the_loader_never_crash_the_checker(raw: bytes) -> None:
    assert_checks_cleanly(raw.decode("utf-8", errors="replace"))
    assert_checks_cleanly(raw.decode("latin-1"))


ODD_CHARACTERS = st.characters(categories=["Cc", "Cf", "Co", "Zs", "Zl", "Zp", "Mn", "Me", "So", "Lo", "Nd", "Nl"])


@FUZZ
@given(st.lists(st.one_of(st.sampled_from(VOCABULARY), st.text(ODD_CHARACTERS, min_size=1, max_size=3)), max_size=80))
def test_keyword_soup_with_odd_unicode_never_crashes_the_checker(words: list[str]) -> None:
    assert_checks_cleanly(" ".join(words))


@FUZZ
@given(st.lists(st.sampled_from(VOCABULARY), max_size=120), st.sampled_from(["", " ", "\n"]))
def test_token_soup_never_crashes_the_checker(words: list[str], separator: str) -> None:
    assert_checks_cleanly(separator.join(words))


@pytest.mark.parametrize(
    "text",
    [
        pytest.param("// " + "x" * 200_000 + "\naction go() {}\n", id="long-comment"),
        pytest.param("action " + "a" * 100_000 + "() {}\n", id="long-name"),
        pytest.param('string fluent s() {\ninitially:\n    () = "' + "y" * 100_000 + '";\n}\n', id="long-string"),
        pytest.param("action go() {}\nprocedure main() {" + " go();" * 20_000 + "}\n", id="long-statement-line"),
        pytest.param(")" * 20_000, id="closing-parentheses"),
        pytest.param(";" * 20_000, id="semicolons"),
        pytest.param("(]{)" * 5_000, id="bracket-garbage"),
        # One diagnostic per bad character, each rendering the whole line: keep these short.
        pytest.param("@" * 500, id="bad-characters"),
        pytest.param("\x00" * 500, id="nul-characters"),
        pytest.param("\ufeffaction go() {}\n", id="byte-order-mark"),
        pytest.param("action go() {}\r\nprocedure main() {\r\n    go()\r\n}\r\n", id="crlf-missing-semicolon"),
        pytest.param("action go() {}\rprocedure main() {\r    go()\r}\r", id="cr-only-lines"),
        pytest.param("action go() {}\u2028procedure main() {\u2028    go()\u2028}", id="unicode-line-separators"),
        pytest.param("procedure main() {\n\tgo(\t\t\x0b\x0c);\n}\n", id="tabs-and-form-feeds"),
        pytest.param("action gö() {}\nprocedure main() {\n    gö();\n}\n", id="non-ascii-name"),
        pytest.param('action say(string s) {}\nprocedure main() {\n    say("日本語 🤖");\n}\n', id="wide-characters"),
        pytest.param("procedure p() {}\n" * 3_000, id="many-redefinitions"),
        pytest.param("", id="empty"),
        pytest.param("\n\n\n", id="only-newlines"),
    ],
)
def test_unusual_input_checks_cleanly(text: str) -> None:
    assert_checks_cleanly(text)


# ---------------------------------------------------------------- deep nesting

NestingBuilder = Callable[[int], str]

NESTING: dict[str, NestingBuilder] = {
    "parentheses": lambda n: "number function f() = " + "(" * n + "1" + ")" * n + "\n",
    "unclosed-parentheses": lambda n: "(" * n,
    "unclosed-braces": lambda n: "procedure main() " + "{" * n,
    "blocks": lambda n: "procedure main() " + "{" * n + "}" * n + "\n",
    "if": lambda n: "procedure main() {" + "if (true) " * n + "{}}\n",
    "else-if": lambda n: "procedure main() {" + "if (true) {} else " * n + "{}}\n",
    "while": lambda n: "procedure main() {" + "while (true) " * n + "{}}\n",
    "choose": lambda n: "procedure main() " + "choose {" * n + "{}" + "}" * n + "\n",
    "concurrent": lambda n: "procedure main() " + "concurrent {" * n + "{}" + "}" * n + "\n",
    "pick": lambda n: "symbol domain D = {a}\nprocedure main() {" + "pick (D x) " * n + "{}}\n",
    "unary-minus": lambda n: "number function f() = " + "-" * n + "1\n",
    "negation": lambda n: "bool function f() = " + "!" * n + "true\n",
    "sum": lambda n: "number function f() = " + " + ".join(["1"] * n) + "\n",
    "conjunction": lambda n: "bool function f() = " + " & ".join(["true"] * n) + "\n",
    "conditional": lambda n: "number function f() = " + "if (true) " * n + "1" + " else 2" * n + "\n",
    "exists": lambda n: "bool function f() = " + "exists (bool b) " * n + "true\n",
    "calls": lambda n: "number function f(number k) = " + "f(" * n + "1" + ")" * n + "\n",
    "fields": lambda n: "compound P { number x }\nnumber function f(P p) = p" + ".x" * n + "\n",
    "indexes": lambda n: "list[number] fluent l();\nnumber function f() = l()" + "[0]" * n + "\n",
    "list-types": lambda n: "list" + "[list" * n + "[number]" + "]" * n + " fluent l();\n",
    "domain-unions": lambda n: "symbol domain D = " + " | ".join(["{a}"] * n) + "\n",
}

DEEP = 2_000


@pytest.mark.parametrize("construct", sorted(NESTING))
def test_moderate_nesting_checks_cleanly(construct: str) -> None:
    assert_checks_cleanly(NESTING[construct](100))


@pytest.mark.parametrize("construct", sorted(NESTING))
def test_deep_nesting_checks_cleanly(construct: str) -> None:
    assert_checks_cleanly(NESTING[construct](DEEP))


# A sum of a few hundred terms or a goal that is a conjunction over a few hundred objects is a
# plausible generated program, not an attack: these are the most urgent of the recursion bugs.
def test_sum_of_five_hundred_terms_checks_cleanly() -> None:
    assert_checks_cleanly(
        "number fluent n(number k);\nnumber function total() = " + " + ".join(f"n({i})" for i in range(500))
    )


def test_goal_conjunction_of_three_hundred_conditions_checks_cleanly() -> None:
    assert_checks_cleanly(
        "bool fluent done(number k);\nbool function goal() = " + " & ".join(f"done({i})" for i in range(300))
    )


# ---------------------------------------------------------------- (c) the real CLI


def run_check(*files: Path, cwd: Path) -> Result:
    return run("check", "--color", "never", *(str(f) for f in files), cwd=cwd)


def assert_clean_exit(proc: Result) -> None:
    report = f"exit {proc.returncode}\nstdout:\n{proc.stdout[-3000:]}\nstderr:\n{proc.stderr[-3000:]}"
    assert proc.returncode in (0, 1), report
    assert "Traceback" not in proc.stderr, report
    assert "internal error" not in proc.stdout + proc.stderr, report


def test_cli_check_on_mutated_files_exits_cleanly(tmp_path: Path) -> None:
    rnd = random.Random(20240611)
    files: list[Path] = []
    for n in range(24):
        name = sorted(PIECES)[n % len(PIECES)]
        path = tmp_path / f"mutant_{n:02d}_{name}"
        path.write_text(mutate(PIECES[name], rnd, 1 + n % 6), encoding="utf-8")
        files.append(path)
    raw = tmp_path / "random_bytes.gpp"
    raw.write_bytes(bytes(rnd.randrange(256) for _ in range(2_000)))
    files.append(raw)
    # One process for all files, then a few on their own (a crash in one must not hide behind another).
    assert_clean_exit(run_check(*files, cwd=tmp_path))
    for path in (files[0], files[7], raw):
        assert_clean_exit(run_check(path, cwd=tmp_path))


def test_cli_check_on_a_long_sum_exits_cleanly(tmp_path: Path) -> None:
    path = tmp_path / "sum.gpp"
    path.write_text("number function total() = " + " + ".join(["1"] * 500) + "\n")
    proc = run_check(path, cwd=tmp_path)
    if proc.returncode == 3:
        raise RecursionError(proc.stdout + proc.stderr)  # the CLI turns it into exit code 3
    assert_clean_exit(proc)


# ---------------------------------------------------------------- crashes found by fuzzing


def diagnostics_of(text: str) -> list[tuple[str, int, int]]:
    return [(d.code, d.span.line, d.span.col) for d in assert_checks_cleanly(text)]


def test_domain_used_as_a_parameter_type_before_its_declaration_is_fine() -> None:
    # SEMANTICS §2.1: declaration order does not matter.
    assert diagnostics_of("action go(Room r) {}\nsymbol domain Room = {kitchen, hall}\n") == []


def test_fluent_typed_by_a_later_domain_is_fine() -> None:
    text = "Room fluent at() {\ninitially:\n    () = hall;\n}\nsymbol domain Room = {kitchen, hall}\n"
    assert diagnostics_of(text) == []


def test_bare_list_type_of_a_later_domain_is_fine() -> None:
    assert diagnostics_of("list[Room]\nsymbol domain Room = {kitchen}\n") == []


def test_domain_of_a_later_compound_type_is_an_error_not_a_crash() -> None:
    assert "E0311" in [code for code, _, _ in diagnostics_of("Pose domain D = {a}\ncompound Pose { number x }\n")]


def test_domain_whose_element_type_is_itself_is_an_error_not_a_crash() -> None:
    assert diagnostics_of("D domain D;\n") != []


def test_include_path_with_a_nul_character_is_an_include_error() -> None:
    assert diagnostics_of('#include "a\x00b.gpp"\n') == [("E0030", 1, 10)]


def test_include_path_that_is_too_long_is_an_include_error() -> None:
    assert diagnostics_of('#include "' + "a" * 5_000 + '.gpp"\n') == [("E0030", 1, 10)]


# ---------------------------------------------------------------- bench/fuzz.py, on a small budget


@pytest.mark.slow
def test_the_fuzzers_of_make_fuzz_find_no_internal_error_in_a_few_seconds(tmp_path: Path) -> None:
    # `make fuzz` runs bench/fuzz.py on 100,000 inputs; here the same fuzzers run for 4 seconds.
    proc = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "fuzz.py"), "--seconds", "4", "--seed", "7", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "no internal errors" in proc.stdout, proc.stdout
    assert "by fuzzer: bytes " in proc.stdout and " generation " in proc.stdout, proc.stdout
    assert " formatter " in proc.stdout, proc.stdout
    assert list(tmp_path.glob("crash-*")) == []


@pytest.mark.slow
def test_the_formatter_fuzzer_of_make_fuzz_finds_no_problem_in_a_few_seconds(tmp_path: Path) -> None:
    # Formatter mutants (bench/fmtfuzz.py): suppressions stay with what they suppressed, the
    # tree, the comments and the line endings are kept, and formatting is idempotent.
    command = [sys.executable, str(ROOT / "bench" / "fuzz.py"), "--only", "formatter", "--seconds", "4"]
    proc = subprocess.run(
        [*command, "--seed", "7", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "no internal errors" in proc.stdout, proc.stdout
    assert "by fuzzer: formatter " in proc.stdout, proc.stdout
    assert list(tmp_path.glob("crash-*")) == []
