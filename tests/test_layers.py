"""The packages of gpp form layers (docs/design.md): each imports only from its own layer or the
layers below, never up, so there is no import cycle between packages. Every import counts: at
module level, inside functions, and under TYPE_CHECKING (a cycle of types is a cycle too)."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Bottom to top. A unit is a folder of gpp (gpp.syntax), the package root `gpp` itself (its
# __init__ and __main__), or the `lsp` package; units in one layer may import each other unless
# listed in APART.
LAYERS: list[tuple[str, set[str]]] = [
    ("base", {"gpp", "gpp.base"}),
    ("codes", {"gpp.codes"}),
    ("reports and projects", {"gpp.report", "gpp.project"}),
    ("syntax", {"gpp.syntax"}),
    ("model", {"gpp.model"}),
    ("check", {"gpp.check"}),
    ("runtime", {"gpp.runtime"}),
    ("planner and platforms", {"gpp.planner", "gpp.platform"}),
    ("run", {"gpp.run", "gpp.traceview", "gpp.dap", "gpp.console"}),
    ("commands", {"gpp.cli", "gpp.__main__", "lsp"}),
]
# Units of one layer that must not import each other.
APART = {frozenset({"gpp.planner", "gpp.platform"})}
# Import circles between modules of one folder that are two halves of one thing, each with why.
# A circle across folders is always a fault.
HALVES: dict[frozenset[str], str] = {}


def unit(module: str) -> str:
    parts = module.split(".")
    if parts[0] == "lsp":
        return "lsp"
    return ".".join(parts[:2])


def folder(module: str, path: Path) -> str:
    """The folder a module's file lies in, as a dotted name (gpp.planner.fast)."""
    return module if path.name == "__init__.py" else module.rpartition(".")[0]


def modules() -> Iterator[tuple[str, Path]]:
    for folder in ("gpp", "lsp"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            yield ".".join(parts), path


MODULES = {name for name, _ in modules()}


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
            # `from gpp import codes` imports the module gpp.codes, not only the package gpp.
            submodules = [f"{target}.{alias.name}" for alias in node.names if f"{target}.{alias.name}" in MODULES]
            yield from ((s, node.lineno) for s in submodules)
            if len(submodules) < len(node.names):
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


def module_circles() -> list[list[str]]:
    """The import circles between modules (strongly connected components of more than one
    module; Tarjan's algorithm), each sorted."""
    paths = dict(modules())
    graph = {m: sorted({t for t, _ in imports(m, p) if t in paths and t != m}) for m, p in paths.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def connect(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in graph:
        if v not in index:
            connect(v)
    return sorted(circles)


def test_there_is_no_import_circle_between_folders() -> None:
    paths = dict(modules())
    across = [c for c in module_circles() if len({folder(m, paths[m]) for m in c}) > 1]
    assert across == []


def test_the_only_circles_inside_a_folder_are_two_halves_of_one_thing() -> None:
    circles = {frozenset(c) for c in module_circles()}
    assert sorted(sorted(c) for c in circles - set(HALVES)) == []
    assert sorted(sorted(c) for c in set(HALVES) - circles) == [], "a listed circle is gone: take it off HALVES"


def test_the_package_root_holds_only_packages() -> None:
    loose = sorted(p.name for p in (ROOT / "gpp").glob("*.py") if p.name not in ("__init__.py", "__main__.py"))
    assert loose == []


def test_there_is_no_import_cycle_between_packages() -> None:
    graph: dict[str, set[str]] = {}
    for a, b in edges():
        graph.setdefault(a, set()).add(b)
    cycles: list[list[str]] = []

    def visit(node: str, path: list[str]) -> None:
        for nxt in sorted(graph.get(node, ())):
            if nxt in path:
                cycles.append([*path[path.index(nxt) :], nxt])
            elif len(path) < 12:
                visit(nxt, [*path, nxt])

    for start in sorted(graph):
        visit(start, [start])
    assert cycles == []
