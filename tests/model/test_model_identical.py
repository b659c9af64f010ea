"""The code model and the type check give exactly the same model and diagnostics as recorded.

For every program of the repository, programs of bench/genprog.py, random programs of
bench/fuzz.py's generator (names that may not resolve, types that may not fit) and mutations
of the examples (names and literals swapped) (kept when they still parse, so that every one is about the model
and not about the parser's repairs), the model and the diagnostics of `check_loaded` (without
lints) are described completely by tests/support/model_fingerprint.py (symbols, references, scopes,
the type of every expression, targets, rewritten expressions, every part of every diagnostic)
and compared with tests/golden/model/fingerprints.json. Written when the code model was made
faster: the faster builder had to give the same answers, to the character.

After an intended change of the model or of a message, regenerate with `GPP_UPDATE_GOLDEN=1`
and review what changed (the counts say where to look).
"""

from __future__ import annotations

import json
import random
from pathlib import Path

import pytest

from bench.fuzz import Generator
from bench.genprog import generate_program
from gpp.base.source import Source
from gpp.check import check_loaded
from gpp.syntax.lexer import tokenize
from gpp.syntax.loader import load
from tests.support import TYPO_CORPUS
from tests.support.golden import recorded
from tests.support.model_fingerprint import fingerprint

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "tests" / "golden" / "model" / "fingerprints.json"

PROGRAMS = sorted(
    p
    for p in ROOT.glob("**/*.gpp")
    if ".venv" not in p.parts and "build" not in p.parts and TYPO_CORPUS not in p.parents
)
MUTATED = sorted([*ROOT.glob("examples/*.gpp"), *ROOT.glob("tests/programs/*.gpp")])
MUTANTS_PER_PROGRAM = 6
VIRTUAL = ROOT / "tests" / "programs" / "virtual.gpp"


def _fingerprint_of(path: Path, text: str | None = None) -> tuple[dict[str, object], bool]:
    loaded = load([path], {path.resolve(): text} if text is not None else None)
    syntax_clean = not any(d.is_error for d in loaded.diagnostics)
    result = check_loaded(loaded, lint=False)
    return fingerprint(result.model, result.diagnostics), syntax_clean


def _mutants(path: Path) -> list[str]:
    """Deterministic mutations of `path` that swap names and literals for others of the program
    (unknown names, wrong kinds, arities, types and domain members), kept when they still parse."""
    text = path.read_text(encoding="utf-8")
    tokens, _ = tokenize(Source(text, "x.gpp"))
    swappable = [t for t in tokens if t.type in ("NAME", "NUMBER", "STRING", "TRUE", "FALSE", "NULL")]
    found: list[str] = []
    for seed in range(3 * MUTANTS_PER_PROGRAM):
        if not swappable or len(found) == MUTANTS_PER_PROGRAM:
            break
        rnd = random.Random(seed)
        chosen = sorted(rnd.sample(swappable, min(len(swappable), 1 + seed % 3)), key=lambda t: -t.start)
        mutant = text
        for t in chosen:
            replacement = rnd.choice([*(x.value for x in swappable), "zz", "1", '"s"', "true"])
            mutant = mutant[: t.start] + replacement + mutant[t.end :]
        loaded = load([VIRTUAL], {VIRTUAL.resolve(): mutant})
        if not any(d.is_error for d in loaded.diagnostics):
            found.append(mutant)
    return found


# Boolean `==`/`!=` beside `&`, `|`, `->`, `!` (regrouped), and mistakes inside such chains.
CHAINS = """\
bool fluent p() { initially: () = true; }
bool fluent q() { initially: () = false; }
number fluent x() { initially: () = 1; }
symbol domain D = {a, b}
bool function f1() = p() == q() & p()
bool function f2() = !p() != q() | x() > 1 == p() -> q()
bool function f3() = (p() == q() & !q()) == (x() == 2 | p())
bool function f4() = p() == q() & x() + "s" == 3
bool function f5() = exists(D d) d == a & p() != !q() == (d != b)
procedure main() {
    if (p() == q() & zz) test(p() != q() -> q() == p() & x());
    while (!p() == q() | p() & q() == p()) p() = q() == p() & true;
}
"""


def _generated(seed: int) -> str:
    rnd = random.Random(seed)
    return Generator(rnd).program()


def _cases() -> dict[str, tuple[Path, str | None]]:
    cases: dict[str, tuple[Path, str | None]] = {}
    for path in PROGRAMS:
        cases[path.relative_to(ROOT).as_posix()] = (path, None)
    for lines, seed, nesting in ((300, 1, 4), (300, 7, 1), (1000, 3, 6)):
        cases[f"genprog {lines} {seed} {nesting}"] = (VIRTUAL, generate_program(lines, seed, nesting))
    cases["regrouped chains"] = (VIRTUAL, CHAINS)
    for seed in range(40):
        cases[f"fuzz generator {seed}"] = (VIRTUAL, _generated(seed))
    for path in MUTATED:
        for k, text in enumerate(_mutants(path)):
            cases[f"mutant {path.name} {k}"] = (VIRTUAL, text)
    return cases


def _actual() -> dict[str, dict[str, object]]:
    return {name: _fingerprint_of(path, text)[0] for name, (path, text) in _cases().items()}


@pytest.mark.slow
def test_model_and_diagnostics_are_as_recorded() -> None:
    actual = _actual()
    expected = json.loads(recorded(GOLDEN, json.dumps(actual, indent=1, sort_keys=True) + "\n"))
    assert sorted(actual) == sorted(expected), "the set of programs changed"
    different = {name: (expected[name], actual[name]) for name in expected if expected[name] != actual[name]}
    assert not different, "\n".join(f"{name}:\n  was {was}\n  now {now}" for name, (was, now) in different.items())


def test_the_cases_cover_errors_and_clean_programs() -> None:
    """The recorded cases are not all clean (nor all broken): diagnostics of many kinds are
    compared, and most programs are about the model (they parse)."""
    expected = json.loads(GOLDEN.read_text(encoding="utf-8"))
    with_problems = [n for n, f in expected.items() if f["diagnostics"]]
    mutants = [n for n in expected if n.startswith("mutant ")]
    assert len(with_problems) >= 50, len(with_problems)
    assert len(expected) - len(with_problems) >= 30
    assert len(mutants) >= 100
    assert sum(1 for f in expected.values() if f["rewritten"]) >= 1
    assert expected["regrouped chains"]["rewritten"] >= 6
