"""A check's result is freed by reference counting alone: nothing in it is a reference cycle.

The language server checks on every edit and drops the previous result. Whatever dies in a
cycle waits for the cyclic garbage collector, whose full collections over a large heap are the
language server's latency spikes (issue 10). So: check, drop the result, and the collector must
find nothing, for every program of the repository, a generated 1,000-line one, programs with
syntax errors, programs on which each lint fires, and through the language server's session
(parse cache, latest check per program).
"""

from __future__ import annotations

import gc
from collections import Counter
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from bench.genprog import generate_program
from gpp.check import check_program, check_text
from gpp.check.session import Session
from tests.support.lint_triggers import TRIGGERS

ROOT = Path(__file__).resolve().parents[2]
REPOSITORY = sorted(p.relative_to(ROOT) for d in ("examples", "stdlib", "tests") for p in (ROOT / d).rglob("*.gpp"))
BENCH = generate_program(1000)
# Syntax errors in the middle of declarations: the parser repairs them, the checker holds
# back what it would say about the repaired declarations.
BROKEN = BENCH.replace("procedure ", "procedure ( ", 3).replace(";", " + ;", 5)


@pytest.fixture(autouse=True, scope="module")
def frozen_heap() -> Iterator[None]:
    """What the test process holds already is frozen out of the collector's way: each test's
    collections then only look at what was made since (a full collection over the heap of a
    test process is a tenth of a second)."""
    gc.collect()
    gc.freeze()
    yield
    gc.unfreeze()


def cyclic_garbage(action: Callable[[], object]) -> Counter[str]:
    """The objects (by type) that only the cyclic collector frees once `action` has run and its
    result is dropped."""
    gc.collect()
    gc.disable()
    try:
        action()
        gc.set_debug(gc.DEBUG_SAVEALL)
        gc.collect()
        return Counter(type(o).__qualname__ for o in gc.garbage)
    finally:
        gc.set_debug(0)
        gc.garbage.clear()
        gc.enable()


def assert_no_cycles(action: Callable[[], object]) -> None:
    found = cyclic_garbage(action)
    assert not found, f"{sum(found.values())} objects freed only by the cyclic collector: " + ", ".join(
        f"{n} {name}" for name, n in found.most_common(20)
    )


def test_the_finder_finds_a_cycle() -> None:
    def cycle() -> None:
        a: list[object] = []
        a.append(a)

    assert cyclic_garbage(cycle) == Counter({"list": 1})


def test_bench_program() -> None:
    result = check_text(BENCH)
    assert result.diagnostics and not result.errors  # warnings only: lints ran
    del result
    assert_no_cycles(lambda: check_text(BENCH))


def test_program_with_syntax_errors() -> None:
    result = check_text(BROKEN)
    assert result.errors >= 3
    del result
    assert_no_cycles(lambda: check_text(BROKEN))


@pytest.mark.parametrize("path", REPOSITORY, ids=str)
def test_repository_program(path: Path) -> None:
    assert_no_cycles(lambda: check_program(ROOT / path))


@pytest.mark.parametrize("code", sorted(TRIGGERS))
def test_lint_firing(code: str) -> None:
    assert code in {d.code for d in check_text(TRIGGERS[code]).diagnostics}
    assert_no_cycles(lambda: check_text(TRIGGERS[code]))


def test_session_keeps_no_cycles(tmp_path: Path) -> None:
    """The session's parse cache and latest check: replacing them (an edit, closing the
    document) frees the old ones without the collector."""
    path = tmp_path / "prog.gpp"
    session = Session([tmp_path])
    session.open(path, BENCH, 1)
    session.check(path.resolve())
    lines = BENCH.splitlines(keepends=True)

    def edit(version: int) -> None:
        text = "".join(lines[:500]) + f"// edit {version}\n" + "".join(lines[500:])
        session.open(path, text, version)
        assert not session.check(path.resolve()).errors

    for version in (2, 3):
        assert_no_cycles(lambda: edit(version))  # noqa: B023 (called at once)
    assert_no_cycles(lambda: session.close(path))
