"""The fix-it property over the corpus of real typos (tests/check/fixits/corpus, its convention in
the README beside this file): every fix offered, applied alone, removes its problem and adds none
(a safe fix) or no error (an unsafe one); `gpp check --fix` says how many problems it fixed, and
that is how many went away."""

from __future__ import annotations

import dataclasses
import re
import shutil
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic, Edit, Fix
from gpp.base.source import Span
from gpp.check import check_text
from gpp.check.fixes import apply_fixes
from gpp.codes import CODES
from tests.support.cli import run

CORPUS = Path(__file__).parent / "corpus"
FILES = sorted(CORPUS.glob("*.gpp"))
# The typo families (file name prefixes) and how many places each is tried in at least.
FAMILIES = {
    "missing_call_parens_": 6,
    "missing_parens_": 5,
    "quantifier_in_": 3,
    "swapped_": 3,
    "missing_semicolon_": 4,
    "misspelled_": 6,
    "legacy_": 6,
    "lint_": 4,  # the lints with a fix
}
# What a legacy recogniser (gpp.syntax.legacy) reports: every one has a file.
LEGACY_CODES = {
    "E0040",
    "E0041",
    "E0042",
    "E0043",
    "E0044",
    "E0045",
    "E0046",
    "E0047",
    "E0048",
    "E0049",
    "E0050",
    "E0051",
}

Key = tuple[str, str, bool]  # code, message, is an error


@dataclass(frozen=True)
class Expected:
    """The header of a corpus file: `expect:`, `remains:` and `reveals:` codes."""

    expect: frozenset[str]
    remains: frozenset[str]
    reveals: frozenset[str]

    @staticmethod
    def of(text: str) -> Expected:
        found: dict[str, frozenset[str]] = {}
        for line in text.splitlines():
            if not line.startswith("//"):
                break
            m = re.match(r"//\s*(expect|remains|reveals):(.*)", line)
            if m:
                found[m.group(1)] = frozenset(m.group(2).split())
        return Expected(
            found.get("expect", frozenset()), found.get("remains", frozenset()), found.get("reveals", frozenset())
        )


def diagnostics(text: str, path: Path) -> list[Diagnostic]:
    return check_text(text, path).diagnostics


def key(d: Diagnostic) -> Key:
    return (d.code, d.message, d.is_error)


def keys(found: list[Diagnostic]) -> Counter[Key]:
    return Counter(key(d) for d in found)


def fix_violations(text: str, path: Path, reveals: frozenset[str], before: list[Diagnostic] | None = None) -> list[str]:
    """What is wrong with the fixes offered on `text` (`before`: its diagnostics), each applied
    alone: one line each."""
    before = diagnostics(text, path) if before is None else before
    syntax_errors = any(d.is_error and d.code < "E0100" for d in before)
    problems: list[str] = []
    for d in before:
        if d.fix is None:
            continue
        line = d.span.source.line_col(d.span.start)[0]
        what = f"{d.code} at line {line} ({d.message}), fix `{d.fix.message}` ({d.fix.applicability.value})"
        fixed, count = apply_fixes(text, [d.fix])
        if count != 1 or fixed == text:
            problems.append(f"{what}: changes nothing")
            continue
        after = keys(diagnostics(fixed, path))
        others = keys(before)
        others[key(d)] -= 1
        if after[key(d)] > others[key(d)]:
            problems.append(f"{what}: the problem is still reported")
        added = after - others
        if syntax_errors:  # what a syntax error held back may come to light
            added = Counter({k: n for k, n in added.items() if k[0] not in reveals})
        if not d.fix.is_safe:
            added = Counter({k: n for k, n in added.items() if k[2]})
        if added:
            problems.append(f"{what}: adds {sorted(added)}")
    return problems


def test_the_corpus_tries_every_family_in_several_places() -> None:
    names = [p.stem for p in FILES]
    for prefix, places in FAMILIES.items():
        assert sum(n.startswith(prefix) for n in names) >= places, prefix
    legacy = set().union(*(Expected.of(p.read_text()).expect for p in FILES if p.stem.startswith("legacy_")))
    assert legacy >= LEGACY_CODES


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_the_typo_is_reported(path: Path) -> None:
    expected = Expected.of(path.read_text())
    assert expected.expect, f"{path.name} has no `// expect:` line"
    assert expected.expect | expected.remains | expected.reveals <= set(CODES)
    assert {d.code for d in diagnostics(path.read_text(), path)} >= expected.expect


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_each_fix_alone_removes_its_problem_and_adds_none(path: Path) -> None:
    text = path.read_text()
    assert fix_violations(text, path, Expected.of(text).reveals) == []


# The legacy programs of tests/legacy hold several legacy forms each: the property holds there too.
LEGACY_PROGRAMS = sorted((Path(__file__).parents[2] / "legacy").glob("*.gpp"))


@pytest.mark.parametrize("path", LEGACY_PROGRAMS, ids=lambda p: p.stem)
def test_the_fixes_of_the_legacy_programs_remove_their_problems(path: Path) -> None:
    assert fix_violations(path.read_text(), path, frozenset()) == []


_REPORT = re.compile(
    r"(?:fixed (\d+) problems?"
    r"(?: \((?:(\d+) of them )?(hidden by a syntax error|found after the first fixes).*?\))?"
    r" in \d+ files?, (\d+) remaining|nothing to fix, (\d+) problems? remaining)$"
)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_check_fix_counts_what_went_away(path: Path, tmp_path: Path) -> None:
    expected = Expected.of(path.read_text())
    copy = tmp_path / path.name
    shutil.copy(path, copy)
    result = run("check", "--fix", "--color", "never", str(copy))
    report = result.stdout.strip().splitlines()[-1]
    m = _REPORT.match(report)
    assert m, report
    fixed_text = copy.read_text()
    final = diagnostics(fixed_text, copy)
    assert {d.code for d in final} == expected.remains
    assert result.returncode == (1 if any(d.is_error for d in final) else 0)
    if m.group(5) is not None:  # nothing to fix
        assert fixed_text == path.read_text()
        assert int(m.group(5)) == len(final)
        return
    fixed, later, why, remaining = int(m.group(1)), m.group(2), m.group(3), int(m.group(4))
    hidden = 0 if why is None else int(later or 1)
    gone = keys(diagnostics(path.read_text(), path)) - keys(final)
    assert fixed == gone.total() + hidden
    assert remaining == len(final)
    if expected.reveals:
        assert hidden and why == "hidden by a syntax error"
    else:
        assert not hidden, report


def test_a_syntax_error_that_hid_a_misspelled_name_is_said_so(tmp_path: Path) -> None:
    copy = tmp_path / "agent.gpp"
    shutil.copy(CORPUS / "syntax_error_hides_misspelled_name.gpp", copy)
    shown = run("check", "--color", "never", str(copy))
    assert [line for line in shown.stdout.splitlines() if line.startswith("error[")] == [
        "error[E0011]: expected `;` after this effect"
    ]
    fixed = run("check", "--fix", "--color", "never", str(copy))
    assert fixed.stdout.strip().splitlines()[-1] == (
        "fixed 2 problems (1 of them hidden by a syntax error) in 1 file, 0 remaining"
    )


def test_a_problem_that_a_fix_brings_about_and_the_next_round_fixes_is_said_so(tmp_path: Path) -> None:
    """Calling `patrol` makes the suppression of its `unused` warning unused (W0116), which the
    second round removes: the check showed one problem, two were fixed."""
    agent = tmp_path / "agent.gpp"
    agent.write_text(
        "action go() {\n}\n// gpp: allow unused\nprocedure patrol() {\n    go();\n}\n"
        "procedure main() {\n    patrl();\n}\n"
    )
    shown = run("check", "--color", "never", str(agent))
    assert shown.stdout.strip().splitlines()[-1] == "error: 1 error"
    fixed = run("check", "--fix", "--color", "never", str(agent))
    assert fixed.stdout.strip().splitlines()[-1] == (
        "fixed 2 problems (1 of them found after the first fixes) in 1 file, 0 remaining"
    )
    assert "// gpp: allow" not in agent.read_text() and "    patrol();" in agent.read_text()


def test_the_issue_typos_get_the_fixes_that_fix_them() -> None:
    """The three typos of issue 24: each fix is the one a person would make."""
    cases = {
        "missing_call_parens_effect": "    robot_at() = p;",
        "missing_parens_if": "    if (robot_at() == lobby) goto(room1);",
        "quantifier_in_pick": "        pick (Location v) goto(v);",
    }
    for name, line in cases.items():
        path = CORPUS / f"{name}.gpp"
        text = path.read_text()
        (d,) = [d for d in diagnostics(text, path) if d.fix is not None]
        assert d.fix is not None and d.fix.is_safe
        assert d.code != "E0306" and "declare a fluent" not in (d.help or "")
        assert line in apply_fixes(text, [d.fix])[0].splitlines()


def test_the_property_finds_a_fix_that_cannot_be_right() -> None:
    """What the issue's `remove keyword in` did (`pick (v  Location)`, an unsafe fix) is a
    violation: its result is still wrong."""
    path = CORPUS / "quantifier_in_pick.gpp"
    text = path.read_text()
    found = diagnostics(text, path)
    (d,) = [d for d in found if d.fix is not None]
    at = text.index(" in Location") + 1
    remove_in = Fix("remove keyword `in`", (Edit(Span(d.span.source, at, at + 2), ""),))
    wrong = [dataclasses.replace(x, fix=remove_in) if x is d else x for x in found]
    assert fix_violations(text, path, frozenset(), wrong) != []
