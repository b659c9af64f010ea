"""The lints say exactly what they said before they were made fast.

* Golden files hold every warning (all of its fields, in order) that `run_lints` gives on every
  program of the repository and on generated ones (bench/genprog, the pathological families).
  They were written by the lints before the single-walk index; after an intended change of a
  lint, run `GPP_UPDATE_GOLDEN=1 .venv/bin/pytest tests/check/test_lints_unchanged.py` and review the
  diff.
* On random programs (the printer's generator, over the whole language), the lints over the
  one-walk node index give the same warnings as over a plain reading of the tree: every node
  found through its dataclass fields, every outermost expression searched for operator chains,
  every symbol's use asked of the model's reference index.
* On random call graphs, the procedures that run only while planning, and those that reach a
  choice, are those the fixed points the lints had first (one procedure per pass) find.
"""

from __future__ import annotations

import json
import os
from collections import defaultdict
from collections.abc import Callable, Iterator
from dataclasses import fields
from functools import cached_property, partial
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench.genprog import generate_program, nested_expression_program
from gpp.base import diagnostics as diag
from gpp.base.perf import with_deep_stack
from gpp.check import lints
from gpp.model.build import build_model
from gpp.model.model import Model
from gpp.model.symbols import Symbol
from gpp.report.text import diagnostic_to_json
from gpp.syntax import ast
from gpp.syntax.loader import load
from gpp.syntax.printer import format_program
from tests.support import TYPO_CORPUS
from tests.support.budget import examples
from tests.support.golden import recorded
from tests.support.lint_triggers import TRIGGERS
from tests.support.pathological import FAMILIES
from tests.support.syntax_trees import programs

ROOT = Path(__file__).resolve().parents[2]
GOLDEN_DIR = Path(__file__).parents[1] / "golden" / "lints"
REPOSITORY = sorted(
    p.relative_to(ROOT)
    for d in ("examples", "stdlib", "tests")
    for p in (ROOT / d).rglob("*.gpp")
    if TYPO_CORPUS not in p.parents
)
GENERATED: dict[str, Callable[[], str]] = {
    "genprog 400 lines": lambda: generate_program(400),
    "genprog 250 lines, seed 2, nesting 1": lambda: generate_program(250, seed=2, nesting=1),
    "genprog 120 lines, seed 3, nesting 9": lambda: generate_program(120, seed=3, nesting=9),
    "nested expression 60": lambda: nested_expression_program(60),
    # Used only in their own bodies: unused (W0101).
    "self-recursion": lambda: (
        "number function f(number n) = if (n > 0) f(n - 1) else 0\n"
        "procedure p() { p(); }\naction a() {}\nprocedure main() { a(); }\n"
    ),
    **{f"test_lints trigger {code}": partial(str, text) for code, text in sorted(TRIGGERS.items())},
    **{f"pathological: {name}": partial(make, min(n, 12)) for name, (make, n) in sorted(FAMILIES.items())},
}


def lint_lines(path: Path, overrides: dict[Path, str] | None = None) -> list[str]:
    """The lint warnings of the program at `path`, one JSON line each, paths relative to the
    repository."""
    loaded = load([path], overrides)
    roots = {f.path for f in loaded.files if f.path in loaded.roots}

    def lint() -> list[diag.Diagnostic]:
        model, _ = build_model(loaded.files)
        return lints.run_lints(model, roots)

    lines = []
    for d in with_deep_stack(lint):
        shown = json.dumps(diagnostic_to_json(d), ensure_ascii=False, sort_keys=True)
        lines.append(shown.replace(str(ROOT) + os.sep, ""))
    return lines


def generated_lines(name: str) -> list[str]:
    path = ROOT / "generated.gpp"
    return lint_lines(path, {path: GENERATED[name]()})


def compare(golden: str, found: dict[str, list[str]]) -> None:
    path = GOLDEN_DIR / golden
    text = "".join(f"== {name}\n" + "".join(line + "\n" for line in lines) for name, lines in found.items())
    expected = recorded(path, text).split("\n== ")
    got = text.split("\n== ")
    assert [e.split("\n", 1)[0] for e in expected] == [g.split("\n", 1)[0] for g in got]
    for e, g in zip(expected, got, strict=True):
        assert g == e


def test_the_repository_programs_get_the_same_lints() -> None:
    found = {str(p): lint_lines(ROOT / p) for p in REPOSITORY}
    assert sum(map(len, found.values())) > 10  # the programs exercise the lints
    compare("repository.txt", found)


def test_generated_programs_get_the_same_lints() -> None:
    found = {name: generated_lines(name) for name in GENERATED}
    codes = {json.loads(line)["code"] for lines in found.values() for line in lines}
    assert codes == set(lints.LINTS)
    compare("generated.txt", found)


# ---------------------------------------------------------------- the index against a plain reading


def field_children(node: ast.Node) -> Iterator[ast.Node]:
    """A node's children, found by testing the value of every dataclass field."""
    for f in fields(node):
        value = getattr(node, f.name)
        for item in value if isinstance(value, tuple) else (value,):
            if isinstance(item, ast.Node):
                yield item


def plain_walk(node: ast.Node) -> Iterator[ast.Node]:
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(list(field_children(n))))


def outermost_expressions(node: ast.Node) -> Iterator[ast.Expr]:
    for n in field_children(node):
        if isinstance(n, ast.Expr):
            yield n
        else:
            yield from outermost_expressions(n)


class PlainProgram(lints._Program):
    """The program as lints see it, read without the index: the reference."""

    @cached_property
    def _nodes(self) -> lints._Nodes:
        by_type: defaultdict[type[ast.Node], list[ast.Node]] = defaultdict(list)
        tops: list[ast.Expr] = []
        for f in self.root_files:
            for n in plain_walk(f.program):
                by_type[type(n)].append(n)
            tops.extend(outermost_expressions(f.program))
        return lints._Nodes(dict(by_type), tops)

    @cached_property
    def planning_only(self) -> set[int]:
        sites: dict[int, list[lints._CallSite]] = {}
        for site in self.call_sites:
            sites.setdefault(id(site.callee), []).append(site)
        candidates = set(sites)
        changed = True
        while changed:
            changed = False
            for callee in list(candidates):
                if any(not s.planning and (s.caller is None or id(s.caller) not in candidates) for s in sites[callee]):
                    candidates.discard(callee)
                    changed = True
        return candidates

    @cached_property
    def choosing(self) -> set[int]:
        found: set[int] = set()
        for caller, statements_ in self.body_statements(self.model.files):
            if caller is not None and any(isinstance(s, ast.Pick | ast.Choose) for s, _ in statements_):
                found.add(id(caller))
        changed = True
        while changed:
            changed = False
            for site in self.call_sites:
                if site.caller is not None and id(site.callee) in found and id(site.caller) not in found:
                    found.add(id(site.caller))
                    changed = True
        return found

    def used(self, symbol: Symbol) -> bool:
        own = symbol.decl.span if symbol.kind in lints._USABLE_KINDS and symbol.decl is not None else None
        for r in self.model.references_to(symbol, include_declaration=False):
            if own is None or r.span.source is not own.source or not own.start <= r.span.start < own.end:
                return True
        return False


def all_lints(program: lints._Program) -> list[diag.Diagnostic]:
    return [d for lint in lints.LINTS.values() for d in lint(program)]


@pytest.mark.slow
@settings(
    max_examples=examples(80), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
@given(programs)
def test_random_programs_get_the_same_lints_from_the_index(program: ast.Program) -> None:
    path = ROOT / "random.gpp"
    loaded = load([path], {path: format_program(program)})

    def both() -> tuple[list[diag.Diagnostic], list[diag.Diagnostic], Model]:
        model, _ = build_model(loaded.files)
        return all_lints(lints._Program(model, [path])), all_lints(PlainProgram(model, [path])), model

    fast, plain, model = with_deep_stack(both)
    assert fast == plain
    indexed = lints._Program(model, [path])
    reference = PlainProgram(model, [path])
    for kind, nodes in reference._nodes.by_type.items():
        assert [id(n) for n in indexed.nodes(kind)] == [id(n) for n in nodes], kind
    assert set(indexed._nodes.by_type) == set(reference._nodes.by_type)


@pytest.mark.parametrize(
    ("text", "chained", "warnings"),
    [
        ("number function f() = 2 * 3 + 4 * 5", True, 1),
        ("bool function g(bool p) = p & p | p & p", True, 1),
        ("number function f() = 2 * (3 + 4) * 5", True, 0),  # `*` twice: a chain, read alike
        ("number function f() = 2 * (3 + 4)", False, 0),  # two chains of one operator each
        ("bool function g(bool p) = !p == p", True, 0),  # regrouped by the model: `(!p) == p`
        ("bool function g(bool p) = !(p == p)", False, 0),
    ],
)
def test_the_index_lists_the_expressions_with_chains(text: str, chained: bool, warnings: int) -> None:
    path = ROOT / "chain.gpp"
    loaded = load([path], {path: text})
    model, _ = with_deep_stack(lambda: build_model(loaded.files))
    program = lints._Program(model, [path])
    expression = text.split(" = ", 1)[1]
    assert [e.span.text for e in program.chained_expressions()] == ([expression] if chained else [])
    assert len(list(lints.mixed_precedence(program))) == warnings


# A random call graph: each procedure calls some others, online or inside `search`; some pick.
call_graphs = st.lists(
    st.tuples(st.booleans(), st.lists(st.tuples(st.integers(0, 11), st.booleans()), max_size=4)),
    min_size=1,
    max_size=12,
)


def call_graph_program(graph: list[tuple[bool, list[tuple[int, bool]]]]) -> str:
    count = len(graph)
    lines = ["action a() {}", "number function r() = 1"]
    for i, (picks, calls) in enumerate(graph):
        body = ["pick (bool b) if (b) a();"] if picks else []
        for callee, planning in calls:
            call = f"p{callee % count}();"
            body.append(f"search {{ {call} }}" if planning else call)
        lines.append(f"procedure p{i}() {{ {' '.join(body)} }}")
    lines.append("procedure main() { p0(); solve (2, r()) p0(); }")
    return "\n".join(lines) + "\n"


@settings(max_examples=examples(200), deadline=None)
@given(call_graphs)
def test_planning_only_and_choosing_are_the_fixed_points(graph: list[tuple[bool, list[tuple[int, bool]]]]) -> None:
    path = ROOT / "calls.gpp"
    loaded = load([path], {path: call_graph_program(graph)})
    model, _ = with_deep_stack(lambda: build_model(loaded.files))
    fast, plain = lints._Program(model, [path]), PlainProgram(model, [path])
    assert fast.planning_only == plain.planning_only
    assert fast.choosing == plain.choosing
    assert all_lints(fast) == all_lints(plain)


def test_a_chain_called_only_while_planning_runs_only_while_planning() -> None:
    # p3 -> p2 -> p1 -> p0, p3 called inside `search` only: all four plan; called online: none.
    chain = "action a() {}\nprocedure p0() { pick (bool b) if (b) a(); }\n" + "".join(
        f"procedure p{i + 1}() {{ p{i}(); }}\n" for i in range(3)
    )
    for main, planning in [("search { p3(); }", 4), ("p3();", 0)]:
        path = ROOT / "chain.gpp"
        loaded = load([path], {path: chain + f"procedure main() {{ {main} }}\n"})
        model, _ = with_deep_stack(lambda: build_model(loaded.files))  # noqa: B023
        program = lints._Program(model, [path])
        assert len(program.planning_only) == planning
        assert len(program.choosing) == 5  # main too
        assert [d.code for d in lints.online_nondeterminism(program)] == ([] if planning else ["W0105"])
