"""The registry of codes (gpp/codes) is the one place that names a diagnostic code: code
elsewhere calls a code's message (`E0204.arithmetic(...)`) or reads `E0204.code`; every
registered code has its explanation file, and every message is used."""

from __future__ import annotations

import ast
import inspect
import re
from collections.abc import Iterator
from pathlib import Path

from gpp import codes
from gpp.codes.registry import Code

ROOT = Path(__file__).resolve().parents[2]
CODE_LITERAL = re.compile(r"\b[EWRI]\d{4}\b")
EXPLAIN = ROOT / "gpp" / "codes" / "explain"
# Calls whose `help=` is command-line help text: prose for the user, like a docstring.
HELP_CALLS = {"Option", "Argument", "add_argument"}


def sources() -> Iterator[Path]:
    """The Python files of gpp/ and lsp/ outside the registry."""
    for folder in ("gpp", "lsp"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            if (ROOT / "gpp" / "codes") not in path.parents:
                yield path


def prose(tree: ast.AST) -> set[int]:
    """The ids of the string constants that are prose: docstrings, and the help texts of
    command-line options (comments are not in the tree)."""
    found: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            first = node.body[0] if node.body else None
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                found.add(id(first.value))
        elif isinstance(node, ast.Call):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
            if name in HELP_CALLS:
                for keyword in node.keywords:
                    if keyword.arg == "help":
                        found.update(id(n) for n in ast.walk(keyword.value))
    return found


def code_literals(path: Path) -> list[tuple[int, str]]:
    """(line, text) of each string constant of the file that names a code and is not prose."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    allowed = prose(tree)
    return [
        (node.lineno, node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and id(node) not in allowed
        and CODE_LITERAL.search(node.value)
    ]


def test_no_code_literal_outside_the_registry() -> None:
    found = [f"{path.relative_to(ROOT)}:{line}: {text!r}" for path in sources() for line, text in code_literals(path)]
    assert found == [], "name codes through gpp.codes (`E0204.code`, a message of the code):\n" + "\n".join(found)


def test_the_check_finds_a_literal_and_allows_prose(tmp_path: Path) -> None:
    path = tmp_path / "example.py"
    path.write_text(
        '"""Reports E0204."""\n'
        "# W0101 in a comment\n"
        "def f() -> None:\n"
        '    """R0011 in a docstring."""\n'
        '    typer.Option(help="a code such as W0101")\n'
        '    error("E0204", f"cannot W0102 {x}")\n'
    )
    assert sorted(code_literals(path)) == [(6, "E0204"), (6, "cannot W0102 ")]


def code_classes() -> list[type[Code]]:
    return [c for c in vars(codes).values() if isinstance(c, type) and issubclass(c, Code) and c is not Code]


def test_every_registered_code_has_an_explanation_file_and_every_file_a_code() -> None:
    files = {p.stem for p in EXPLAIN.glob("*.md")}
    assert files == set(codes.CODES)
    for code, info in codes.CODES.items():
        assert info.explanation == (EXPLAIN / f"{code}.md").read_text(encoding="utf-8").strip()


def test_every_code_class_is_exported_and_named_as_its_code() -> None:
    classes = code_classes()
    assert {c.code for c in classes if c.registered} == set(codes.CODES)
    assert all(c.__name__ == c.code == c.info.code for c in classes)
    assert [c.code for c in classes if not c.registered] == ["R0099"]


def messages(cls: type[Code]) -> list[str]:
    return [
        name
        for name, member in vars(cls).items()
        if isinstance(member, classmethod) and inspect.signature(member.__func__).return_annotation == "Message"
    ]


def test_every_code_has_a_message_and_every_message_is_used() -> None:
    text = "\n".join(path.read_text(encoding="utf-8") for path in sources())
    unused = []
    for cls in code_classes():
        names = messages(cls)
        assert names, f"{cls.code} has no message"
        unused += [f"{cls.code}.{name}" for name in names if f"{cls.code}.{name}(" not in text]
    assert unused == []


def test_a_message_carries_its_code_and_text() -> None:
    message = codes.E0204.arithmetic("**", "string", "number")
    assert message == ("E0204", "cannot raise `string` to `number`")
    assert codes.E0204.arithmetic("+", "string", "number").text == "cannot add `string` and `number`"
