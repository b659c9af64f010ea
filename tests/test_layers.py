"""The packages of gpp form layers (docs/design.md): each imports only from its own layer or the
layers below, never up, so there is no import cycle between packages. Every import counts: at
module level, inside functions, and under TYPE_CHECKING (a cycle of types is a cycle too)."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Bottom to top. A unit is a package of gpp (gpp.syntax), a top-level module (gpp.runner), or
# the `lsp` package; units in one layer may import each other unless listed in APART.
LAYERS: list[tuple[str, set[str]]] = [
    (
        "foundation",
        {
            "gpp",
            "gpp.source",
            "gpp.diagnostics",
            "gpp.render",
            "gpp.sarif",
            "gpp.codes",
            "gpp.perf",
            "gpp.resources",
            "gpp.suggest",
            "gpp.paths",
            "gpp.numbers",
            "gpp.config",
            "gpp.formats",
            "gpp.scaffold",
        },
    ),
    ("syntax", {"gpp.syntax"}),
    ("model", {"gpp.model"}),
    ("check", {"gpp.check"}),
    ("runtime", {"gpp.runtime"}),
    ("planner and platforms", {"gpp.planner", "gpp.platform"}),
    ("runner", {"gpp.runner", "gpp.testing", "gpp.runview", "gpp.traceview"}),
    (
        "commands",
        {
            "gpp.cli",
            "gpp.cli_run",
            "gpp.cli_trace",
            "gpp.cli_check",
            "gpp.cli_project",
            "gpp.cli_fmt",
            "gpp.__main__",
            "lsp",
        },
    ),
]
# Units of one layer that must not import each other.
APART = {frozenset({"gpp.planner", "gpp.platform"})}


def unit(module: str) -> str:
    parts = module.split(".")
    if parts[0] == "lsp":
        return "lsp"
    return ".".join(parts[:2])


def modules() -> Iterator[tuple[str, Path]]:
    for folder in ("gpp", "lsp"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            yield ".".join(parts), path


def imports(module: str, path: Path) -> Iterator[tuple[str, int]]:
    """(imported gpp/lsp module, line) for every import in a file."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            yield target, node.lineno


def layer_of(u: str) -> int:
    for i, (_, units) in enumerate(LAYERS):
        if u in units:
            return i
    raise AssertionError(f"unit {u} is in no layer: add it to LAYERS in tests/test_layers.py")


def edges() -> dict[tuple[str, str], list[str]]:
    """Unit -> unit imports, with where each happens."""
    found: dict[tuple[str, str], list[str]] = {}
    for module, path in modules():
        source = unit(module)
        for target, line in imports(module, path):
            if target.split(".")[0] not in ("gpp", "lsp"):
                continue
            dest = unit(target)
            if dest != source:
                found.setdefault((source, dest), []).append(f"{path.relative_to(ROOT)}:{line} imports {target}")
    return found


def test_every_unit_has_a_layer() -> None:
    for module, _ in modules():
        layer_of(unit(module))


def test_no_package_imports_a_layer_above_it() -> None:
    wrong = [
        f"{where} ({LAYERS[layer_of(a)][0]} -> {LAYERS[layer_of(b)][0]})"
        for (a, b), places in sorted(edges().items())
        if layer_of(b) > layer_of(a) or frozenset({a, b}) in APART
        for where in places
    ]
    assert wrong == []


def test_there_is_no_import_cycle_between_packages() -> None:
    graph: dict[str, set[str]] = {}
    for a, b in edges():
        graph.setdefault(a, set()).add(b)
    # The commands layer is one unit of wiring (gpp.cli registers gpp.cli_run's commands, which
    # use its helpers); every other cycle is a fault.
    commands = LAYERS[-1][1]
    cycles: list[list[str]] = []

    def visit(node: str, path: list[str]) -> None:
        for nxt in sorted(graph.get(node, ())):
            if nxt in path:
                cycle = [*path[path.index(nxt) :], nxt]
                if not set(cycle) <= commands:
                    cycles.append(cycle)
            elif len(path) < 12:
                visit(nxt, [*path, nxt])

    for start in sorted(graph):
        visit(start, [start])
    assert cycles == []


def test_the_layer_check_sees_an_upward_import(tmp_path: Path) -> None:
    # The checker itself: an import of the planner from the runtime is found.
    path = tmp_path / "semantics.py"
    path.write_text("from gpp.planner.policy import PlanHolder\n", encoding="utf-8")
    [(target, line)] = list(imports("gpp.runtime.semantics", path))
    assert (unit(target), line) == ("gpp.planner", 1)
    assert layer_of("gpp.planner") > layer_of("gpp.runtime")
