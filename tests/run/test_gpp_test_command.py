"""`gpp test` through the real command: a table of results, the exit code, and the platform
chosen per program (sim for programs with a `// world:` line, dummy for the others)."""

from __future__ import annotations

from pathlib import Path

from tests.support.cli import Result, run

ROOT = Path(__file__).resolve().parents[2]


def gpp(*args: str, cwd: Path = ROOT) -> Result:
    return run(*args, cwd=cwd)


def test_every_example_passes_on_its_platform() -> None:
    result = gpp("test", "examples")
    assert result.returncode == 0, result.stdout + result.stderr
    examples = sorted((ROOT / "examples").rglob("*.gpp"))
    # examples/ros2/courier.gpp is run with arguments (its `main(x, y)`), by a launch file.
    assert result.stdout.strip().splitlines()[-1] == f"{len(examples) - 1} passed, 0 failed, 1 skipped"


def test_a_failing_postcond_fails_the_run(tmp_path: Path) -> None:
    (tmp_path / "bad.gpp").write_text(
        "number fluent n() { initially: () = 0; }\nprocedure main() { n() = 1; }\nbool function postcond() = n() == 2\n"
    )
    (tmp_path / "good.gpp").write_text("procedure main() { test(true); }\n")
    result = gpp("test", str(tmp_path))
    assert result.returncode == 1
    assert "postcond() does not hold" in result.stdout
    assert result.stdout.strip().splitlines()[-1] == "1 passed, 1 failed"


def test_explicit_platform_applies_to_every_program() -> None:
    # The physics agent cannot run on the dummy platform without a scenario for its sensing.
    result = gpp("test", "--platform", "dummy", "examples/blocksworld.gpp")
    assert result.returncode == 1
    assert "sensed_location" in result.stdout


def test_a_named_program_without_main_fails_and_one_found_in_a_folder_is_skipped(tmp_path: Path) -> None:
    library = tmp_path / "lib"
    library.mkdir()
    (library / "helpers.gpp").write_text("number function twice(number x) = 2 * x\n")
    named = gpp("test", "lib/helpers.gpp", cwd=tmp_path)
    assert named.returncode == 1, named.stdout + named.stderr
    assert "error[R0008]: the program has no `procedure main()` to run" in named.stdout
    assert named.stdout.strip().splitlines()[-1] == "0 passed, 1 failed"
    found = gpp("test", "lib", cwd=tmp_path)
    assert found.returncode == 0, found.stdout + found.stderr
    assert found.stdout.strip().splitlines()[-1] == "0 passed, 0 failed, 1 skipped"


def test_a_program_whose_main_takes_parameters_is_skipped_in_a_folder_and_fails_when_named(tmp_path: Path) -> None:
    """It is run with arguments (`gpp run --arg`, a launch file's parameters)."""
    folder = tmp_path / "agents"
    folder.mkdir()
    (folder / "go.gpp").write_text("action go(number n) { }\nprocedure main(number n) { go(n); }\n")
    found = gpp("test", "agents", cwd=tmp_path)
    assert found.returncode == 0, found.stdout + found.stderr
    assert found.stdout.strip().splitlines()[-1] == "0 passed, 0 failed, 1 skipped"
    named = gpp("test", "agents/go.gpp", cwd=tmp_path)
    assert named.returncode == 1, named.stdout + named.stderr
    assert named.stdout.strip().splitlines()[-1] == "0 passed, 1 failed"
