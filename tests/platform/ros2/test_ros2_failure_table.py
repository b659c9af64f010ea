"""The failure table of the ros2 platform (docs/platforms.md, "Failures") is checked against
the tests: every test a row names exists, and every fault test (`@pytest.mark.fault` in
tests/platform/ros2) is named by a row. Read from the source, so it runs without ROS."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
HERE = Path(__file__).resolve().parent
DOC = ROOT / "docs" / "platforms.md"
COLUMNS = ["fault", "what the program sees", "bound", "tests"]


def table() -> list[list[str]]:
    """The rows of the table under `#### Failures`, as cells."""
    text = DOC.read_text(encoding="utf-8")
    section = text.split("#### Failures\n", 1)[1].split("\n#### ", 1)[0]
    lines = [line for line in section.splitlines() if line.startswith("|")]
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    assert header == COLUMNS, header
    return [[c.strip() for c in line.strip("|").split(" | ")] for line in lines[2:]]


def _is_fault_mark(decorator: ast.expr) -> bool:
    return (
        isinstance(decorator, ast.Attribute)
        and decorator.attr == "fault"
        and ast.unparse(decorator) == ("pytest.mark.fault")
    )


def functions_here() -> dict[str, bool]:
    """`file.py::name` of every test function in tests/platform/ros2 -> is it a fault test?"""
    found: dict[str, bool] = {}
    for path in sorted(HERE.glob("test_*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                found[f"{path.name}::{node.name}"] = any(_is_fault_mark(d) for d in node.decorator_list)
    return found


def test_every_row_names_tests_that_exist() -> None:
    tests = functions_here()
    rows = table()
    assert len(rows) >= 10
    for row in rows:
        assert len(row) == len(COLUMNS) and all(row), row
        named = re.findall(r"`([^`]+)`", row[3])
        assert named, f"the row `{row[0]}` names no test"
        for test in named:
            assert test in tests, f"the row `{row[0]}` names `{test}`, which is not a test in {HERE.name}"
            assert tests[test], f"`{test}` (the row `{row[0]}`) is not marked @pytest.mark.fault"


def test_every_fault_test_is_in_the_table() -> None:
    named = {test for row in table() for test in re.findall(r"`([^`]+)`", row[3])}
    missing = sorted(t for t, fault in functions_here().items() if fault and t not in named)
    assert not missing, f"fault tests that no row of the failure table in {DOC.name} names: {missing}"
