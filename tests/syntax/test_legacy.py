"""Legacy golog++ (the syntax of older public agents) is recognised: one error per construct
(E0040-E0045) with the modern form as a fix, no cascade of syntax errors; applying the fixes
gives a program that checks clean and runs."""

from __future__ import annotations

import itertools
import shutil
from pathlib import Path

import pytest

from gpp.base import diagnostics as diag
from gpp.check import check_paths, merged_diagnostics
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus
from tests.support.cli import Result, run

LEGACY = Path(__file__).resolve().parents[1] / "legacy"


def apply_fixes(text: str, diagnostics: list[diag.Diagnostic]) -> str:
    """The text with the edits of every fix applied (they must not overlap)."""
    edits = sorted((e for d in diagnostics if d.fix for e in d.fix.edits), key=lambda e: e.span.start)
    for a, b in itertools.pairwise(edits):
        assert a.span.end <= b.span.start, f"overlapping edits {a} and {b}"
    for e in reversed(edits):
        text = text[: e.span.start] + e.text + text[e.span.end :]
    return text


def codes_of(path: Path) -> list[str]:
    return [d.code for d in merged_diagnostics(check_paths([path]))]


@pytest.mark.parametrize(
    ("name", "expected"),
    [("sigils.gpp", ["E0040"]), ("forms.gpp", ["E0045", "E0043", "E0041", "E0042", "E0044"])],
)
def test_each_legacy_form_is_one_error_with_a_fix_and_the_fixed_program_runs(
    name: str, expected: list[str], tmp_path: Path
) -> None:
    path = tmp_path / name
    for given in LEGACY.glob(path.stem + ".*"):
        shutil.copy(given, tmp_path / given.name)
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [d.code for d in diagnostics] == expected
    assert all(d.fix is not None and d.help and "gpp explain" in d.help for d in diagnostics)
    path.write_text(apply_fixes(path.read_text(), diagnostics))
    assert [f"{d.code} {d.message}" for d in merged_diagnostics(check_paths([path]))] == []
    outcome = run_program(path, RunOptions(timeout=60))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.postcond is True, outcome.diagnostics


def test_the_fixes_write_the_modern_forms(tmp_path: Path) -> None:
    path = tmp_path / "forms.gpp"
    shutil.copy(LEGACY / "forms.gpp", path)
    fixed = apply_fixes(path.read_text(), merged_diagnostics(check_paths([path])))
    assert "number exog_function battery() ;" in fixed
    assert "action go(Room r) {\nprecondition:" in fixed
    assert '    "move_base" { target = r }' in fixed
    assert "number exog_function sensed_temperature();\naction read_thermometer() {" in fixed
    assert "    temperature() = sensed_temperature();" in fixed
    assert "number function warmth(number t) = if (t > 25) 2 else if (t > 15) 1 else 0\n" in fixed
    sigils = tmp_path / "sigils.gpp"
    shutil.copy(LEGACY / "sigils.gpp", sigils)
    fixed = apply_fixes(sigils.read_text(), merged_diagnostics(check_paths([sigils])))
    assert "symbol domain rooms = {kitchen, hall}" in fixed
    assert "number fluent count(symbol r) {" in fixed
    assert "bool function busy(symbol r) = count(r) > 1" in fixed
    assert "    count(r) = count(r) % 2;" in fixed  # `%` with a space is the remainder
    assert "action say(string text)" in fixed and "said() = text;" in fixed


def test_sigils_with_a_domain_section_become_the_domain(tmp_path: Path) -> None:
    path = tmp_path / "old.gpp"
    path.write_text(
        "§domain rooms = {kitchen, hall}\n"
        "%fluent visits(§room) {\ndomain:\n    §room in rooms;\ninitially:\n    (§room) = 0;\n}\n"
        "procedure main() { visits(kitchen) = 1; }\n"
    )
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [d.code for d in diagnostics] == ["E0040", "E0043"]
    fixed = apply_fixes(path.read_text(), diagnostics)
    assert "number fluent visits(rooms room) {\ninitially:\n    (room) = 0;\n}" in fixed
    path.write_text(fixed)
    assert codes_of(path) == []


def test_an_unconvertible_function_body_is_one_error_without_a_fix(tmp_path: Path) -> None:
    path = tmp_path / "loop.gpp"
    path.write_text(
        "number fluent n() { initially: () = 0; }\n"
        "number function f() {\n    while (n() < 3) n() = n() + 1;\n    return n();\n}\n"
        "procedure main() { n() = f(); }\n"
    )
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [(d.code, d.fix) for d in diagnostics] == [("E0044", None)]
    assert diagnostics[0].help is not None and "if (c) a else b" in diagnostics[0].help


def test_modern_remainder_and_unknown_characters_are_not_sigils(tmp_path: Path) -> None:
    path = tmp_path / "modern.gpp"
    path.write_text("number fluent n() { initially: () = 7; }\nprocedure main() { n() = n() %n(); n() = n()%2; }\n")
    assert codes_of(path) == []
    path.write_text("procedure main() { ?; }\n")
    assert codes_of(path)[:1] == ["E0001"]


def test_sigils_inside_a_rewritten_body_are_written_once(tmp_path: Path) -> None:
    path = tmp_path / "old.gpp"
    path.write_text(
        "%fluent limit() {\ninitially:\n    () = 3;\n}\n"
        "?function big(%x) {\n    if (%x > limit()) return true;\n    return false;\n}\n"
        "%exog_function level(%x) {\n    return %x;\n}\n"
        "procedure main() { test(big(level(5))); }\n"
    )
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [d.code for d in diagnostics] == ["E0040", "E0044", "E0045"]
    fixed = apply_fixes(path.read_text(), diagnostics)
    assert "bool function big(number x) = if (x > limit()) true else false\n" in fixed
    assert "number exog_function level(number x) ;\n" in fixed
    path.write_text(fixed)
    assert codes_of(path) == []


def test_damaged_legacy_files_give_diagnostics_and_fixes_that_do_not_overlap(tmp_path: Path) -> None:
    import random

    rng = random.Random(7)
    samples = [(LEGACY / name).read_text() for name in ("forms.gpp", "sigils.gpp")]
    path = tmp_path / "damaged.gpp"
    for _ in range(20):
        parts = rng.choice(samples).split(" ")
        for _ in range(rng.randint(1, 5)):  # delete, repeat or swap words
            k, j = rng.randrange(len(parts)), rng.randrange(len(parts))
            action = rng.choice(("delete", "repeat", "swap"))
            if action == "delete" and len(parts) > 1:
                del parts[k]
            elif action == "repeat":
                parts.insert(k, parts[j])
            else:
                parts[k], parts[j] = parts[j], parts[k]
        path.write_text(" ".join(parts))
        diagnostics = merged_diagnostics(check_paths([path]))  # no internal error
        assert diagnostics, " ".join(parts)
        apply_fixes(path.read_text(), [d for d in diagnostics if d.code.startswith("E004")])


def test_gpp_check_fix_upgrades_legacy_programs(tmp_path: Path) -> None:

    for name in ("forms.gpp", "forms.toml", "sigils.gpp"):
        shutil.copy(LEGACY / name, tmp_path / name)

    def gpp(*args: str) -> Result:
        return run(*args, cwd=tmp_path)

    before = gpp("check", "--format", "concise", "forms.gpp", "sigils.gpp")
    assert before.returncode == 1
    assert {"E0040", "E0041", "E0042", "E0043", "E0044", "E0045"} <= {
        line.split("[")[1].split("]")[0] for line in before.stdout.splitlines() if "error[" in line
    }
    fixed = gpp("check", "--fix", "forms.gpp", "sigils.gpp")
    assert (fixed.returncode, fixed.stdout.splitlines()[-1]) == (0, "fixed 6 problems in 2 files, 0 remaining")
    assert gpp("check", "forms.gpp", "sigils.gpp").returncode == 0
