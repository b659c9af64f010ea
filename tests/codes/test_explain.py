"""`gpp explain CODE` and the registry of codes: every code is explained with an example that
does what it says, and the registry and the sources agree on which codes exist."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from gpp.check import check_paths, merged_diagnostics
from gpp.codes import CODES, RUN_TIME_WARNINGS, close_matches, lints, lookup
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus
from tests.support.cli import Result, run

REPO = Path(__file__).resolve().parents[2]
CODE_PATTERN = re.compile(r"\b[EWR]\d{4}\b")
# An internal error of the runtime: a bug in gpp, not a problem of the program, so not registered.
INTERNAL_ERROR = "R0099"


def run_gpp(*args: str, cwd: Path) -> Result:
    return run(*args, cwd=cwd)


def example_blocks(explanation: str) -> list[str]:
    """The indented (4 spaces) blocks of an explanation, unindented."""
    blocks: list[list[str]] = []
    previous_indented = False
    for line in explanation.splitlines():
        indented = line.startswith("    ")
        if indented:
            if not previous_indented:
                blocks.append([])
            blocks[-1].append(line[4:])
        previous_indented = indented
    return ["\n".join(b) + "\n" for b in blocks]


def program_files(block: str, folder: Path) -> list[Path]:
    """Write an example to `folder`: one file, or several introduced by `// name.gpp` lines
    (or `// name.toml` for a scenario of the dummy platform; `// name.gpp (latin-1)` writes the
    file in that encoding); returns the program files."""
    files: dict[str, list[str]] = {}
    encodings: dict[str, str] = {}
    name = "example.gpp"
    for line in block.splitlines():
        header = re.fullmatch(r"// (\w+\.(?:gpp|toml))( \(latin-1\))?", line)
        if header:
            name = header.group(1)
            encodings[name] = "latin-1" if header.group(2) else "utf-8"
            continue
        files.setdefault(name, []).append(line)
    folder.mkdir()
    paths = []
    for file_name, lines in files.items():
        path = folder / file_name
        path.write_text("\n".join(lines) + "\n", encoding=encodings.get(file_name, "utf-8"))
        if path.suffix == ".gpp":
            paths.append(path)
    return paths


def run_example(block: str, folder: Path) -> tuple[str, list[str]]:
    """Run an example (its first program file) on the dummy platform, with a time limit of 60 s
    of platform time (R0013's example) and a timeout: the status of the run ("" when it did not
    start) and its errors, as "CODE message"."""
    outcome = run_program(program_files(block, folder)[0], RunOptions(time_limit=60.0, timeout=60.0))
    status = outcome.result.status.value if outcome.result is not None else ""
    return status, [f"{d.code} {d.message}" for d in outcome.diagnostics if d.is_error]


# ---------------------------------------------------------------- the registry


@pytest.mark.parametrize("code", sorted(CODES))
def test_every_code_is_explained_with_an_example(code: str) -> None:
    info = CODES[code]
    assert info.code == code
    assert info.name and info.summary
    assert info.explanation.strip(), f"{code} has no explanation"
    blocks = example_blocks(info.explanation)
    assert len(blocks) >= 2, f"{code}: the explanation needs an example of the problem and of its fix"
    first_paragraph = info.explanation.split("\n\n")[0]
    assert not first_paragraph.startswith("    ")


@pytest.mark.parametrize("code", sorted(c for c in CODES if not c.startswith("R")))
def test_the_example_shows_the_problem_and_the_fix(code: str, tmp_path: Path) -> None:
    blocks = example_blocks(CODES[code].explanation)
    problem = check_paths(program_files(blocks[0], tmp_path / "problem"))
    reported = {d.code for d in merged_diagnostics(problem)}
    assert code in reported, f"{code}: the first example reports {sorted(reported)}"
    fixed = merged_diagnostics(check_paths(program_files(blocks[-1], tmp_path / "fixed")))
    remaining = [f"{d.code} {d.message}" for d in fixed if d.code == code or d.is_error]
    assert remaining == [], f"{code}: the fixed example still reports problems"


@pytest.mark.parametrize("code", sorted(c for c in CODES if c.startswith("R") and not CODES[c].is_warning))
def test_the_example_of_a_runtime_error_stops_the_run_and_the_fix_runs_to_its_end(code: str, tmp_path: Path) -> None:
    blocks = example_blocks(CODES[code].explanation)
    problem = program_files(blocks[0], tmp_path / "check")
    assert not [d for d in merged_diagnostics(check_paths(problem)) if d.is_error], f"{code}: not a run-time error"
    status, errors = run_example(blocks[0], tmp_path / "problem")
    assert status != RunStatus.FINISHED.value, f"{code}: the first example runs to its end"
    assert [e.split(" ")[0] for e in errors] == [code], f"{code}: the first example reports {errors}"
    status, errors = run_example(blocks[-1], tmp_path / "fixed")
    assert (status, errors) == (RunStatus.FINISHED.value, []), f"{code}: the fixed example does not run cleanly"


# Run-time warnings whose examples need a robot: their test runs them on one.
ON_A_ROBOT = {"R0015": "tests/platform/ros2/test_ros2_exog.py"}


@pytest.mark.parametrize("code", sorted(set(RUN_TIME_WARNINGS) - set(ON_A_ROBOT)))
def test_the_example_of_a_runtime_warning_warns_and_the_fix_does_not(code: str, tmp_path: Path) -> None:
    blocks = example_blocks(CODES[code].explanation)
    for block, folder, expected in ((blocks[0], "problem", [code]), (blocks[-1], "fixed", [])):
        outcome = run_program(program_files(block, tmp_path / folder)[0], RunOptions(timeout=60.0))
        assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED, folder
        assert [d.code for d in outcome.diagnostics if d.code.startswith("R")] == expected, folder


def test_only_warnings_are_lints() -> None:
    assert {c.code for c in lints()} == {code for code in CODES if code.startswith("W")}
    assert all(not CODES[code].is_lint for code in CODES if code.startswith(("E", "R")))


def test_names_are_unique_and_look_like_names() -> None:
    names = [c.name for c in CODES.values()]
    assert len(names) == len(set(names))
    assert all(re.fullmatch(r"[a-z]+(-[a-z]+)*", n) for n in names)


def test_lookup_takes_codes_and_names_in_any_case() -> None:
    assert lookup("e0011") is CODES["E0011"]
    assert lookup(" Unused ") is CODES["W0101"]
    assert lookup("W9999") is None
    assert lookup("r0001") is lookup("Bad-Arithmetic") is CODES["R0001"]
    assert lookup("blocked") is CODES["R0011"]


def test_internal_errors_are_not_registered() -> None:
    assert lookup(INTERNAL_ERROR) is None


def test_close_matches_suggest_codes_and_names() -> None:
    assert "unused" in close_matches("unsued")
    assert "E0312" in close_matches("E0112")
    suggested = [lookup(m) for m in close_matches("E0101", lints=True)]
    assert suggested and all(info is not None and info.is_lint for info in suggested)


def source_codes() -> dict[str, set[str]]:
    """Every code string in the sources (outside the registry), with the files it is in."""
    found: dict[str, set[str]] = {}
    for path in [*sorted((REPO / "gpp").rglob("*.py")), *sorted((REPO / "lsp").rglob("*.py"))]:
        if path == REPO / "gpp" / "codes.py":
            continue
        for code in CODE_PATTERN.findall(path.read_text(encoding="utf-8")):
            found.setdefault(code, set()).add(str(path.relative_to(REPO)))
    return found


def test_every_code_in_the_sources_is_registered() -> None:
    found = source_codes()
    unknown = {code: files for code, files in found.items() if code not in CODES and code != INTERNAL_ERROR}
    assert unknown == {}
    assert {code[0] for code in found} == {"E", "W", "R"}
    assert INTERNAL_ERROR in found


def test_every_registered_code_is_used_in_the_sources() -> None:
    used = source_codes()
    assert sorted(code for code in CODES if code not in used) == []


# ---------------------------------------------------------------- gpp explain


def test_explain_a_code(tmp_path: Path) -> None:
    result = run_gpp("explain", "E0011", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    info = CODES["E0011"]
    assert result.stdout.splitlines()[0] == f"E0011 (error `missing-semicolon`): {info.summary}"
    assert info.explanation in result.stdout
    assert result.stderr == ""


def test_explain_a_lint_by_name_in_any_case(tmp_path: Path) -> None:
    result = run_gpp("explain", "Unused", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"W0101 (lint `unused`): {CODES['W0101'].summary}\n\n")
    assert "    procedure main()" in result.stdout


def test_explain_a_lowercase_code(tmp_path: Path) -> None:
    result = run_gpp("explain", "w0110", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stdout.startswith("W0110 (lint `mixed-precedence`)")


def test_explain_an_unknown_code_is_a_usage_error(tmp_path: Path) -> None:
    result = run_gpp("explain", "E0112", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.startswith("error: unknown code `E0112`; did you mean ")
    assert "`E0312`" in result.stderr


def test_explain_an_unknown_name_suggests_names(tmp_path: Path) -> None:
    result = run_gpp("explain", "unsed", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == "error: unknown code `unsed`; did you mean `unused`?\n"


def test_explain_a_runtime_error_by_code_and_by_name(tmp_path: Path) -> None:
    info = CODES["R0001"]
    by_code = run_gpp("explain", "R0001", cwd=tmp_path)
    assert by_code.returncode == 0, by_code.stderr
    assert by_code.stdout.splitlines()[0] == f"R0001 (error `bad-arithmetic`): {info.summary}"
    assert info.explanation in by_code.stdout
    by_name = run_gpp("explain", "bad-arithmetic", cwd=tmp_path)
    assert by_name.returncode == 0, by_name.stderr
    assert by_name.stdout == by_code.stdout
    lowercase = run_gpp("explain", "r0013", cwd=tmp_path)
    assert lowercase.stdout.startswith("R0013 (error `timeout`)")


def test_explain_an_internal_error_code_is_a_usage_error(tmp_path: Path) -> None:
    result = run_gpp("explain", INTERNAL_ERROR, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith(f"error: unknown code `{INTERNAL_ERROR}`")


def test_runtime_errors_are_not_listed_as_lints(tmp_path: Path) -> None:
    result = run_gpp("check", "--list-lints", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "W0101" in result.stdout
    assert not re.search(r"\bR\d{4}\b", result.stdout)


def test_explain_needs_a_code(tmp_path: Path) -> None:
    result = run_gpp("explain", cwd=tmp_path)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
