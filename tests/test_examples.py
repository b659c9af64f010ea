"""Every example program in examples/ parses without a single diagnostic and is listed in the
README; the receptionist, written once, runs on the dummy platform and on the sim."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.syntax import ast
from gpp.syntax.parser import parse_text
from tests.support.cli import run as gpp

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES_DIR = ROOT / "examples"
EXAMPLES = sorted(EXAMPLES_DIR.glob("*.gpp"))


def _describe(diagnostics: list[Diagnostic]) -> str:
    return "\n".join(f"{d.span}: {d.code} {d.message}" for d in diagnostics)


def test_examples_directory_is_not_empty() -> None:
    assert EXAMPLES, f"no *.gpp files found in {EXAMPLES_DIR}"


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_parses_without_diagnostics(path: Path) -> None:
    result = parse_text(path.read_text(encoding="utf-8"), str(path))
    assert result.diagnostics == [], "unexpected diagnostics:\n" + _describe(result.diagnostics)
    assert result.ok


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_declares_a_nullary_main_procedure(path: Path) -> None:
    program = parse_text(path.read_text(encoding="utf-8"), str(path)).program
    mains = [
        d
        for d in program.declarations
        if isinstance(d, ast.ProcedureDecl) and d.name.name == "main" and d.body is not None
    ]
    assert len(mains) == 1
    assert mains[0].params == ()


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_starts_with_an_explanatory_comment(path: Path) -> None:
    first_line = path.read_text(encoding="utf-8").splitlines()[0]
    assert first_line.startswith(f"// {path.name} ")


def test_the_readme_lists_every_example() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\| `examples/([\w.]+\.gpp)` \|", readme, re.MULTILINE))
    assert listed == {p.name for p in EXAMPLES}


@pytest.mark.parametrize(
    "platform", [["--platform", "dummy"], ["--platform", "sim", "--world", "examples/receptionist_world.toml"]]
)
def test_the_receptionist_runs_on_the_dummy_platform_and_on_the_sim(platform: list[str]) -> None:
    result = gpp("run", "-q", "examples/receptionist.gpp", *platform, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "actions executed   10 (1 failed)" in result.stdout
    assert "postcond()         holds" in result.stdout
