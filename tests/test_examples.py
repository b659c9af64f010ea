"""Every example program in examples/ parses without a single diagnostic."""

from __future__ import annotations

from pathlib import Path

import pytest

from gpp.base.diagnostics import Diagnostic
from gpp.syntax import ast
from gpp.syntax.parser import parse_text

EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "examples"
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
