"""Robust on every input: pathological programs (deep nesting, long chains, unclosed brackets,
many declarations or errors) are checked in time linear in their size, and nesting beyond the
limit is one located error (E0014), never a RecursionError or an internal error.

Linearity is asserted as a ratio, not as a time: checking a program 8 times the size may take
at most 30 times as long (linear is 8, quadratic 64), the best of up to five runs each, in the
process's CPU time (a busy machine's other processes do not count, as they would in wall time).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from gpp.check import check_text
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus
from gpp.syntax.depth import MAX_NESTING, MAX_OPEN
from gpp.syntax.parser import parse_text
from tests.support.cli import Result, run
from tests.support.pathological import FAMILIES


def check_time(text: str) -> float:
    """The CPU time this process spent checking `text`."""
    start = time.process_time()
    check_text(text, Path("pathological.gpp"))
    return time.process_time() - start


@pytest.mark.slow
@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_checking_time_grows_linearly(family: str) -> None:
    generate, n = FAMILIES[family]
    small, large = generate(n), generate(8 * n)
    check_time(small)  # warm up (tables, imports)
    best_small = best_large = float("inf")
    for _ in range(5):
        best_small = min(best_small, check_time(small))
        best_large = min(best_large, check_time(large))
        if best_large < 30 * best_small:
            break
    assert best_large < 30 * best_small, f"{family}: 8x the size took {best_large / best_small:.0f}x as long"


# ---------------------------------------------------------------- the nesting limit


def negations(count: int) -> str:
    """`!` applied `count` times: the `true` under them is `count` + 1 levels deep."""
    return "bool function deep() =\n" + "!" * count + "true\n"


def codes_of(text: str) -> list[tuple[str, int, int, str]]:
    return [(d.code, d.span.line, d.span.col, d.message) for d in parse_text(text, "deep.gpp").diagnostics]


def test_an_expression_at_the_limit_parses() -> None:
    result = parse_text(negations(MAX_NESTING - 1), "deep.gpp")
    assert result.diagnostics == []
    assert [type(d).__name__ for d in result.program.declarations] == ["FunctionDecl"]


def test_an_expression_one_level_over_the_limit_is_e0014_at_that_level() -> None:
    message = f"this expression nests more than {MAX_NESTING} levels deep"
    assert codes_of(negations(MAX_NESTING)) == [("E0014", 2, MAX_NESTING + 1, message)]


def test_statements_one_level_over_the_limit_are_e0014_at_that_statement() -> None:
    def blocks(count: int) -> str:
        return "procedure main() " + "{" * count + "}" * count + "\nprocedure other() {}\n"

    assert codes_of(blocks(MAX_NESTING)) == []
    message = f"this statement nests more than {MAX_NESTING} levels deep"
    assert codes_of(blocks(MAX_NESTING + 1)) == [("E0014", 1, len("procedure main() ") + MAX_NESTING + 1, message)]
    # The declaration is left out, the others stay.
    names = [d.name.name for d in parse_text(blocks(MAX_NESTING + 1)).program.declarations]  # type: ignore[attr-defined]
    assert names == ["other"]


def test_too_many_open_brackets_stop_the_declaration_where_they_become_too_many() -> None:
    # Parentheses add no level to the tree, but the parser stops at MAX_OPEN open constructs.
    count = MAX_OPEN + 100
    head = "number function f() = "
    text = "number function e() = 1\n" + head + "(" * count + "1" + ")" * count + "\nnumber function g() = 1\n"
    [(code, line, col, message)] = codes_of(text)
    assert (code, line, message) == ("E0014", 2, f"this declaration nests more than {MAX_NESTING} levels deep")
    assert len(head) < col <= len(head) + MAX_OPEN
    names = [d.name.name for d in parse_text(text).program.declarations]  # type: ignore[attr-defined]
    assert names == ["e", "g"]


def test_the_explanation_states_the_limit() -> None:
    from gpp.codes import CODES

    assert f"{MAX_NESTING:,} levels" in CODES["E0014"].explanation
    assert f"{MAX_NESTING:,} levels" in CODES["E0014"].summary
    assert f"{MAX_OPEN:,} brackets" in CODES["E0014"].explanation


def run_text(text: str, folder: Path) -> tuple[str, list[str]]:
    path = folder / "deep.gpp"
    path.write_text(text)
    outcome = run_program(path, RunOptions(timeout=60.0))
    status = outcome.result.status.value if outcome.result is not None else ""
    return status, [d.code for d in outcome.diagnostics if d.is_error]


def test_a_program_at_the_limit_runs(tmp_path: Path) -> None:
    # An odd number of `!` on `false`: true; each level is evaluated by the interpreter.
    program = "bool function deep() =\n" + "!" * (MAX_NESTING - 1) + "false\nprocedure main() { test(deep()); }\n"
    assert run_text(program, tmp_path) == (RunStatus.FINISHED.value, [])


def test_statements_at_the_limit_run(tmp_path: Path) -> None:
    # The call's name is the deepest node: statement, call and name below the innermost block.
    depth = MAX_NESTING - 3
    program = "action a() {}\nprocedure main() " + "{" * depth + "a();" + "}" * depth + "\n"
    assert run_text(program, tmp_path) == (RunStatus.FINISHED.value, [])


def test_a_program_over_the_limit_does_not_run(tmp_path: Path) -> None:
    program = negations(MAX_NESTING) + "procedure main() { test(deep()); }\n"
    assert run_text(program, tmp_path) == ("", ["E0014"])


# ---------------------------------------------------------------- the command line, 1 MB


def gpp(*args: str, cwd: Path) -> Result:
    return run(*args, cwd=cwd)


@pytest.fixture(scope="module")
def megabyte(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """1 MB of nested `if` and unclosed braces, one per line, then a sound declaration."""
    folder = tmp_path_factory.mktemp("megabyte")
    path = folder / "deep.gpp"
    lines = ["procedure main() {", *(["if (true) {"] * 87_000), "number function f() = 1"]
    path.write_text("\n".join(lines) + "\n")
    assert 1_000_000 <= path.stat().st_size < 1_100_000
    return path


def expected_line() -> int:
    """Where the parser stops: `if (true) {` keeps five constructs open, after `main() {`."""
    return 1 + (MAX_OPEN - 3) // 5 + 1


@pytest.mark.slow
def test_cli_check_rejects_a_megabyte_of_nesting_with_e0014(megabyte: Path) -> None:
    proc = gpp("check", "--color", "never", megabyte.name, cwd=megabyte.parent)
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr == ""
    assert f"error[E0014]: this declaration nests more than {MAX_NESTING} levels deep" in proc.stdout
    assert f"--> {megabyte.name}:{expected_line()}:" in proc.stdout


@pytest.mark.slow
def test_cli_check_sarif_rejects_a_megabyte_of_nesting(megabyte: Path) -> None:
    proc = gpp("check", "--format", "sarif", megabyte.name, cwd=megabyte.parent)
    assert proc.returncode == 1, proc.stderr
    [run] = json.loads(proc.stdout)["runs"]
    [result] = run["results"]
    region = result["locations"][0]["physicalLocation"]["region"]
    assert (result["ruleId"], region["startLine"]) == ("E0014", expected_line())


@pytest.mark.slow
def test_cli_run_rejects_a_megabyte_of_nesting(megabyte: Path) -> None:
    proc = gpp("run", megabyte.name, cwd=megabyte.parent)
    assert proc.returncode == 1, proc.stderr
    assert "internal error" not in proc.stderr
    assert "error[E0014]" in proc.stdout
