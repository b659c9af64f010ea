"""Legacy golog++ (the syntax of older public agents) is recognised: one error per construct
(E0040-E0045) with the modern form as a fix, no cascade of syntax errors; applying the fixes
gives a program that checks clean and runs."""

from __future__ import annotations

import re
import shutil
from collections import Counter
from pathlib import Path

import pytest

from gpp.check import check_paths, merged_diagnostics
from gpp.check.fixes import apply_fixes
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus
from tests.support.cli import Result, run

LEGACY = Path(__file__).resolve().parents[1] / "legacy"


def fix_file(path: Path) -> str:
    """Apply the safe fixes to the file at `path` as `gpp check --fix` does (of two that overlap, the
    second in the next round) until none is left; the new text."""
    for _ in range(10):
        fixes = [d.fix for d in merged_diagnostics(check_paths([path])) if d.fix is not None and d.fix.is_safe]
        if not fixes:
            break
        path.write_text(apply_fixes(path.read_text(), fixes)[0])
    return path.read_text()


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
    fix_file(path)
    assert [f"{d.code} {d.message}" for d in merged_diagnostics(check_paths([path]))] == []
    outcome = run_program(path, RunOptions(timeout=60))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.postcond is True, outcome.diagnostics


def test_the_fixes_write_the_modern_forms(tmp_path: Path) -> None:
    path = tmp_path / "forms.gpp"
    shutil.copy(LEGACY / "forms.gpp", path)
    fixed = fix_file(path)
    assert "number exog_function battery() ;" in fixed
    assert "action go(Room r) {\nprecondition:" in fixed
    assert '    "move_base" { target = r }' in fixed
    assert "number exog_function sensed_temperature();\naction read_thermometer() {" in fixed
    assert "    temperature() = sensed_temperature();" in fixed
    assert "number function warmth(number t) = if (t > 25) 2 else if (t > 15) 1 else 0\n" in fixed
    sigils = tmp_path / "sigils.gpp"
    shutil.copy(LEGACY / "sigils.gpp", sigils)
    fixed = fix_file(sigils)
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
    fixed = fix_file(path)
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
    fixed = fix_file(path)
    assert "bool function big(number x) = if (x > limit()) true else false\n" in fixed
    assert "number exog_function level(number x) ;\n" in fixed
    path.write_text(fixed)
    assert codes_of(path) == []


def test_fix_never_makes_a_damaged_legacy_program_worse(tmp_path: Path) -> None:
    """Mutated legacy programs: the fixes never leave more errors than there were, nor an error
    of a new code, except what a syntax error held back (the checker's codes, E01xx on)."""
    import random

    rng = random.Random(7)
    samples = [p.read_text() for p in sorted(LEGACY.glob("*.gpp"))]
    path = tmp_path / "damaged.gpp"
    for _ in range(30):
        parts = rng.choice(samples).split(" ")
        for _ in range(rng.randint(1, 4)):  # delete, repeat or swap words
            k, j = rng.randrange(len(parts)), rng.randrange(len(parts))
            action = rng.choice(("delete", "repeat", "swap"))
            if action == "delete" and len(parts) > 1:
                del parts[k]
            elif action == "repeat":
                parts.insert(k, parts[j])
            else:
                parts[k], parts[j] = parts[j], parts[k]
        damaged = " ".join(parts)
        path.write_text(damaged)
        before = [d.code for d in merged_diagnostics(check_paths([path])) if d.is_error]  # no internal error
        if not before:  # a fixture without legacy forms (start_effects.gpp), damaged only in a comment
            continue
        fix_file(path)
        after = [d.code for d in merged_diagnostics(check_paths([path])) if d.is_error]
        assert len(after) <= len(before), damaged
        held_back = any(code < "E0100" for code in before)
        assert {c for c in set(after) - set(before) if not (held_back and c >= "E0100")} == set(), damaged


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


# ---------------------------------------------------------------- the 2019 forms (issue 26)

# Each fixture of tests/legacy for a form of the 2019 syntax, with what it reports.
FORMS_2019 = {
    "blocks2019.gpp": ["E0040", "E0043", "E0043"],  # sigils; `domain:` with one entry a line
    "untyped.gpp": ["E0046", "E0046", "E0046", "E0046"],  # exists, forall, pick without a type
    "sensing.gpp": ["E0042", "E0042"],  # `senses: f()` without `;`, before `mapping:` and last
    "names.gpp": ["E0047", "E0013"],  # a name overloaded by arity; `string string`
}


def copy_fixture(name: str, folder: Path) -> Path:
    for given in LEGACY.glob(Path(name).stem + ".*"):
        shutil.copy(given, folder / given.name)
    return folder / name


@pytest.mark.parametrize("name", sorted(FORMS_2019))
def test_one_fix_run_leaves_a_program_that_checks_clean_runs_and_fixes_no_more(name: str, tmp_path: Path) -> None:
    path = copy_fixture(name, tmp_path)
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [d.code for d in diagnostics] == FORMS_2019[name]
    assert all((d.fix is not None and d.help and "gpp explain" in d.help) or d.code == "E0013" for d in diagnostics)
    assert run("check", "--fix", name, cwd=tmp_path).returncode == 0
    fixed = path.read_text()
    assert [d.code for d in merged_diagnostics(check_paths([path])) if d.is_error] == []
    again = run("check", "--fix", name, cwd=tmp_path)
    assert (again.returncode, path.read_text()) == (0, fixed)
    outcome = run_program(path, RunOptions(timeout=60))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.postcond is True, outcome.diagnostics


@pytest.mark.parametrize("name", sorted(FORMS_2019))
def test_each_fix_applied_alone_removes_its_problem_and_adds_none(name: str, tmp_path: Path) -> None:
    path = copy_fixture(name, tmp_path)
    text = path.read_text()
    before = merged_diagnostics(check_paths([path]))
    for d in before:
        assert d.fix is not None
        path.write_text(apply_fixes(text, [d.fix])[0])
        after = Counter((a.code, a.message) for a in merged_diagnostics(check_paths([path])))
        others = Counter((b.code, b.message) for b in before if b is not d)
        assert after[(d.code, d.message)] <= others[(d.code, d.message)], f"{d.code} {d.message}: still reported"
        assert after - others == Counter(), f"{d.code} {d.message}: adds {sorted(after - others)}"


def test_the_2019_fixes_write_the_modern_forms(tmp_path: Path) -> None:
    fixed = {}
    for name in FORMS_2019:
        path = copy_fixture(name, tmp_path)
        fixed[name] = fix_file(path)
    assert "symbol fluent loc(blocks x) {\ninitially:" in fixed["blocks2019.gpp"]
    assert "action stack(blocks x, places y) {\nprecondition:" in fixed["blocks2019.gpp"]
    assert "!(exists(blocks z) loc(z) == x)" in fixed["blocks2019.gpp"]
    assert "pick (blocks x in {a, b, c})\n                pick (places y in" in fixed["blocks2019.gpp"]
    assert "forall (Cell d) (d == c" in fixed["untyped.gpp"]  # compared with a parameter
    assert "!exists (Cell other) other == c" in fixed["untyped.gpp"]
    assert "pick (Cell cell in {c1, c2, c3})" in fixed["untyped.gpp"]  # an argument of `take`
    assert "pick (number n in {1, 2, 3})" in fixed["untyped.gpp"]  # the values it is picked from
    assert "    reply() = sensed_reply();\nmapping:" in fixed["sensing.gpp"]
    assert "    distance() = sensed_distance();\n}" in fixed["sensing.gpp"]
    assert "exog_action phase_event(number at, Phase p) {" in fixed["names.gpp"]
    assert "test(phase() == setup);" in fixed["names.gpp"]
    assert "action say(string string_) {\neffect:\n    said() = string_;" in fixed["names.gpp"]
    assert "text = string_\n" in fixed["names.gpp"]


def test_a_domain_section_of_many_entries_is_one_error(tmp_path: Path) -> None:
    path = tmp_path / "d.gpp"
    path.write_text(
        "symbol domain A = {a1, a2}\nsymbol domain B = {b1}\n"
        "action go(symbol x, symbol y) {\ndomain:\n    x in A;\n    symbol y in B;\n}\n"
        "procedure main() { go(a1, b1); }\n"
    )
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [(d.code, d.span.line) for d in diagnostics] == [("E0043", 4)]
    fix_file(path)
    assert "action go(A x, B y) {\n}" in path.read_text()
    assert codes_of(path) == []


def test_senses_before_another_section_without_its_semicolon(tmp_path: Path) -> None:
    path = tmp_path / "s.gpp"
    for following in ("effect:\n    n() = 1;\n", "precondition: true\n", 'mapping:\n    "/look" {}\n'):
        path.write_text(
            f"number fluent n() {{ initially: () = 0; }}\naction look() {{\nsenses:\n    n()\n{following}}}\n"
            "procedure main() { look(); }\n"
        )
        diagnostics = merged_diagnostics(check_paths([path]))
        assert [d.code for d in diagnostics] == ["E0042"], following
        fix_file(path)
        assert "    n() = sensed_n();\n" in path.read_text()
        assert codes_of(path) == [], following


def test_a_variable_that_nothing_types_is_one_error_without_a_fix(tmp_path: Path) -> None:
    path = tmp_path / "v.gpp"
    path.write_text("procedure main() { test(exists (z) true); }\n")
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [(d.code, d.fix) for d in diagnostics] == [("E0046", None)]
    assert diagnostics[0].help is not None and "exists (T z ...)" in diagnostics[0].help


def test_an_overloaded_name_with_a_use_that_cannot_be_told_apart_has_no_fix(tmp_path: Path) -> None:
    path = tmp_path / "o.gpp"
    base = "number fluent level() { initially: () = 0; }\nexog_action level(number v) {\neffect:\n    level() = v;\n}\n"
    path.write_text(base + "procedure main() { test(level(1, 2) == 0); }\n")  # no declaration has 2
    assert next((d.code, d.fix) for d in merged_diagnostics(check_paths([path]))) == ("E0047", None)
    # a declaration and its definition with different numbers of parameters are E0303, not E0047
    path.write_text("action go(number a);\naction go(number a, number b) {}\nprocedure main() { go(1, 2); }\n")
    assert "E0047" not in codes_of(path)


def test_a_type_word_naming_a_parameter_is_renamed_only_where_every_use_is_certain(tmp_path: Path) -> None:
    path = tmp_path / "r.gpp"
    path.write_text(
        'string fluent s() { initially: () = ""; }\naction say(string string) {\neffect:\n    s() = string + "!";\n}\n'
        'number function twice(number number) = number * 2\nprocedure main() { say("a"); test(twice(2) == 4); }\n'
    )
    diagnostics = merged_diagnostics(check_paths([path]))
    assert [d.code for d in diagnostics] == ["E0013", "E0013"]
    fixed = fix_file(path)
    assert 's() = string_ + "!";' in fixed and "twice(number number_) = number_ * 2\nprocedure" in fixed
    path.write_text(fixed)
    assert codes_of(path) == []
    # a mapped field named `string` is the field; its value is the parameter
    path.write_text('action say(string string) {\nmapping:\n    "/say" { string = string }\n}\n')
    assert '"/say" { string = string_ }' in fix_file(path)
    # a use that is neither a type nor a value: no rename is certain, the parser reports it
    path.write_text('string fluent s() { initially: () = ""; }\n' + "action say(string string) {\n")
    path.write_text(path.read_text() + "effect:\n    s() = string(1);\n}\n")
    assert [(d.code, d.fix) for d in merged_diagnostics(check_paths([path]))][:1] == [("E0013", None)]


def test_the_start_effect_forms_of_the_tacos_fork_check_clean_fix_nothing_and_run(tmp_path: Path) -> None:
    """`start_effect:` is a section of the language (issue 26 item 4), not a legacy form: the
    fixture of its forms checks clean as written, `--fix` leaves it alone and it runs to its end."""
    path = copy_fixture("start_effects.gpp", tmp_path)
    text = path.read_text()
    assert codes_of(path) == []
    assert run("check", "--fix", "start_effects.gpp", cwd=tmp_path).returncode == 0
    assert path.read_text() == text
    outcome = run_program(path, RunOptions(timeout=60))
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert outcome.postcond is True, outcome.diagnostics


def test_the_manifest_of_public_programs_names_each_and_its_result() -> None:
    """tests/legacy/manifest.tsv: the public programs measured (never copied into the project),
    each with where it is and whether one `gpp check --fix` left it clean, or why not."""
    lines = [line for line in (LEGACY / "manifest.tsv").read_text().splitlines() if not line.startswith("#")]
    assert lines[0].split("\t") == ["repository", "path", "commit", "blob", "result"]
    rows = [line.split("\t") for line in lines[1:]]
    assert rows and all(len(row) == 5 for row in rows)
    assert all(re.fullmatch(r"[0-9a-f]{40}", row[3]) and re.fullmatch(r"[0-9a-f]{40}|-", row[2]) for row in rows)
    assert all(row[4] == "clean" or row[4].startswith("not clean: ") for row in rows)
    assert len({row[3] for row in rows}) == len(rows)
