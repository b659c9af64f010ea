"""Statement kinds are one closed set (`ast.Statement`): adding a kind makes mypy name every place
that must handle it. The test adds a statement kind to a copy of gpp and runs mypy on the copy:
every dispatch over statements (a `match` ending in `assert_never`) must be reported, and no
other place."""

from __future__ import annotations

import ast
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# Every function that handles each statement kind (docs/design.md, "Adding a statement kind").
DISPATCH_SITES = {
    "gpp/check/lints.py:_effectful",
    "gpp/model/typecheck.py:TypeChecker.stmt",
    "gpp/syntax/printer.py:_captures",
    "gpp/syntax/printer.py:_stmt",
    "gpp/syntax/walk.py:sub_statements",
    "gpp/runtime/blocked.py:_Explanation.why_code",
    "gpp/runtime/semantics.py:Semantics.final_code",
    "gpp/runtime/semantics.py:Semantics.trans_code",
}

NEW_KIND = '''

@dataclass(frozen=True, slots=True, kw_only=True)
class Pause(StmtNode):
    """A statement kind that no dispatch knows yet."""

'''


def _enclosing_functions(path: Path) -> list[tuple[int, int, str]]:
    """(first line, last line, qualified name) of every function in a file."""
    found: list[tuple[int, int, str]] = []

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                name = prefix + child.name
                found.append((child.lineno, child.end_lineno or child.lineno, name))
                visit(child, name + ".")
            elif isinstance(child, ast.ClassDef):
                visit(child, prefix + child.name + ".")

    visit(ast.parse(path.read_text(encoding="utf-8")), "")
    return found


def _site(copy: Path, file: str, line: int) -> str:
    inside = [(first, name) for first, last, name in _enclosing_functions(copy / file) if first <= line <= last]
    # The innermost function: the one that starts last.
    return f"{file}:{max(inside)[1]}" if inside else f"{file}:<module>"


@pytest.mark.slow
def test_a_new_statement_kind_makes_mypy_name_every_dispatch(tmp_path: Path) -> None:
    copy = tmp_path / "copy"
    shutil.copytree(ROOT / "gpp", copy / "gpp", ignore=shutil.ignore_patterns("__pycache__", "_data"))
    # The language server too: gpp's commands import it (gpp lsp).
    shutil.copytree(ROOT / "lsp", copy / "lsp", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", copy / "pyproject.toml")
    tree = copy / "gpp" / "syntax" / "ast.py"
    text = tree.read_text(encoding="utf-8")
    marker = "# Every statement kind."
    assert marker in text and "    | CallStmt\n" in text
    text = text.replace(marker, NEW_KIND + marker, 1).replace("    | CallStmt\n", "    | CallStmt\n    | Pause\n", 1)
    tree.write_text(text, encoding="utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--cache-dir", str(tmp_path / "cache"), "gpp"],
        cwd=copy,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    errors = re.findall(r"^(gpp/[\w/]+\.py):(\d+): error: (.*)$", result.stdout, re.MULTILINE)
    assert errors, result.stdout + result.stderr
    sites = {_site(copy, file, int(line)) for file, line, _ in errors}
    assert sites == DISPATCH_SITES, result.stdout
    # Each is reported as a missed case of `assert_never`.
    assert all("assert_never" in message for _, _, message in errors), result.stdout


def test_the_union_lists_every_statement_class() -> None:
    from gpp.syntax import ast as syntax

    classes = {c for c in vars(syntax).values() if isinstance(c, type) and issubclass(c, syntax.StmtNode)}
    classes.discard(syntax.StmtNode)
    assert classes == set(syntax.Statement.__args__)
    assert set(syntax.STATEMENT_KINDS) == classes
