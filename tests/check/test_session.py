"""gpp.check.session and the positions it relies on: LSP positions both ways (UTF-16, `\r`, `\r\n`,
characters beyond U+FFFF), incremental edits, the parse cache, the include index, the
analysis thread."""

from __future__ import annotations

import gc
import sys
import weakref
from collections.abc import Iterator
from pathlib import Path

import pytest

from gpp.base.source import Source
from gpp.check import check_program
from gpp.check.session import AnalysisThread, Session, apply_edits, diagnostics_in
from gpp.syntax.loader import ParseCache, load
from lsp.gc_policy import GcPolicy

MIXED = 'a\r\nbé\r"😀x"\nlast'


def test_lines_end_at_lf_crlf_and_a_lone_cr() -> None:
    src = Source(MIXED)
    assert src.line_starts == [0, 3, 6, 11]
    assert [src.line_text(n) for n in (1, 2, 3, 4)] == ["a", "bé", '"😀x"', "last"]
    assert src.line_col(7) == (3, 2)


@pytest.mark.parametrize(
    ("offset", "position"),
    [
        (0, (0, 0)),
        (1, (0, 1)),  # before `\r\n`
        (3, (1, 0)),
        (5, (1, 2)),  # after `é`: one UTF-16 unit
        (6, (2, 0)),  # after a lone `\r`
        (7, (2, 1)),
        (8, (2, 3)),  # after `😀`: two UTF-16 units
        (9, (2, 4)),
        (10, (2, 5)),  # before `\n`
        (11, (3, 0)),
        (15, (3, 4)),
    ],
)
def test_lsp_positions_both_ways(offset: int, position: tuple[int, int]) -> None:
    src = Source(MIXED)
    assert src.lsp_position(offset) == position
    assert src.lsp_offset(*position) == offset


def test_lsp_offsets_clamp_as_the_protocol_says() -> None:
    src = Source(MIXED)
    assert src.lsp_offset(0, 99) == 1  # past the end of a line: its end, before the break
    assert src.lsp_offset(1, 99) == 5
    assert src.lsp_offset(9, 0) == len(MIXED)  # past the last line: the end
    assert src.lsp_offset(2, 2) == 8  # inside the surrogate pair of `😀`: after it


def test_incremental_edits_apply_in_order() -> None:
    text = 'x = "é😀";\r\ny = 2;\n'
    # Replace `2` (line 1, char 4), then insert at the end of line 0 (after `;`: 4+1+1+2+1+1 units).
    after = apply_edits(text, [(((1, 4), (1, 5)), "42"), (((0, 10), (0, 10)), " // ok")])
    assert after == 'x = "é😀"; // ok\r\ny = 42;\n'
    assert apply_edits(text, [(((0, 0), (1, 0)), ""), (None, "z")]) == "z"
    # A deletion across a `\r\n` line end.
    assert apply_edits("ab\r\ncd", [(((0, 1), (1, 1)), "")]) == "ad"


def test_the_parse_cache_parses_an_unchanged_file_once(tmp_path: Path) -> None:
    lib = tmp_path / "lib.gpp"
    lib.write_text("action a() { }\n", encoding="utf-8")
    main = tmp_path / "main.gpp"
    cache = ParseCache()
    first = load([main], {main: '#include "lib.gpp"\nprocedure main() { a(); }\n'}, cache=cache)
    second = load([main], {main: '#include "lib.gpp"\nprocedure main() { a(); a(); }\n'}, cache=cache)
    assert (cache.misses, cache.hits) == (3, 1)  # main twice, lib once
    assert first.file(lib) is not None and second.file(lib) is not None
    assert first.file(lib).program is second.file(lib).program  # type: ignore[union-attr]
    # The source knows its file whatever the working directory; the display path is relative.
    assert second.file(lib).source.identity == str(lib.resolve())  # type: ignore[union-attr]


def test_an_included_file_is_checked_under_the_programs_that_include_it(tmp_path: Path) -> None:
    (tmp_path / "lib.gpp").write_text("action a() { }\nbool fluent f() { initially: () = true; }\n")
    (tmp_path / "main.gpp").write_text('#include "lib.gpp"\nprocedure main() { a(); f() = false; }\n')
    (tmp_path / "other.gpp").write_text("procedure main() { }\n")
    session = Session([tmp_path])
    lib = (tmp_path / "lib.gpp").resolve()
    assert session.programs_of(lib) == [(tmp_path / "main.gpp").resolve()]
    assert diagnostics_in(session.results_for(lib), lib) == []  # used by main: no lint
    alone = check_program(lib)
    assert {d.code for d in alone.diagnostics} == {"W0101"}  # checked alone: unused
    # An open buffer wins over the disk, for the programs that include it too.
    session.open(lib, "action a() { }\n", 1)
    [result] = session.results_for(lib)
    assert [(d.code, d.message) for d in result.diagnostics] == [("E0103", "unknown fluent or function `f`")]


def test_the_project_settings_apply_as_in_gpp_check(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "robot.gpp").write_text("action a() { }\n")
    program = '#include "robot.gpp"\naction unused() { }\nprocedure main() { a(); }\n'
    session = Session([tmp_path])
    path = (tmp_path / "agent.gpp").resolve()
    session.open(path, program, 1)
    assert [d.code for d in session.check(path).diagnostics] == ["E0030"]  # robot.gpp not found
    (tmp_path / "gpp.toml").write_text('include = ["lib"]\n[lint]\ndisable = ["unused"]\n')
    assert session.check(path).diagnostics == []
    (tmp_path / "gpp.toml").write_text('include = ["lib"]\n')
    assert [d.code for d in session.check(path).diagnostics] == ["W0101"]
    # The library, opened alone, is checked under the program that finds it in an include folder.
    assert session.programs_of((tmp_path / "lib" / "robot.gpp").resolve()) == [path]


def test_every_program_that_sees_a_file_is_found_for_a_rename(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from gpp.check import session as session_module

    ws, shared = tmp_path / "ws", tmp_path / "shared"
    (ws / "robot").mkdir(parents=True)
    shared.mkdir()
    (ws / "lib.gpp").write_text("action a() { }\n")
    tops = [ws / f"p{i}.gpp" for i in range(session_module.MAX_PROGRAMS + 2)]
    for top in tops:
        top.write_text('#include "lib.gpp"\nprocedure main() { a(); }\n')
    # A program of the robot's project, which finds lib.gpp in its include folder, and one of
    # a project outside the workspace folder that the workspace's gpp.toml lists.
    (ws / "robot" / "gpp.toml").write_text('include = [".."]\n')
    (ws / "robot" / "agent.gpp").write_text('#include "lib.gpp"\nprocedure main() { a(); }\n')
    (ws / "gpp.toml").write_text('paths = [".", "../shared"]\ninclude = ["."]\n')
    (shared / "far.gpp").write_text('#include "../ws/lib.gpp"\nprocedure main() { a(); }\n')
    session = Session([ws])
    lib = (ws / "lib.gpp").resolve()
    assert len(session.programs_of(lib)) == session_module.MAX_PROGRAMS  # enough for diagnostics
    seeing = session.programs_seeing(lib)
    assert sorted(seeing) == sorted(p.resolve() for p in [*tops, ws / "robot" / "agent.gpp", shared / "far.gpp"])
    # A file nothing includes is its own program.
    assert session.programs_seeing(tops[0]) == [tops[0].resolve()]
    # Without workspace folders, the project of the file still counts.
    assert (shared / "far.gpp").resolve() in Session().programs_seeing(lib)
    # A workspace larger than what is read: the answer would be incomplete.
    monkeypatch.setattr(session_module, "MAX_WORKSPACE_FILES", 3)
    with pytest.raises(session_module.IncompleteSearch, match=r"more than 3 \.gpp files"):
        Session([ws]).programs_seeing(lib)


def test_directives_are_read_from_the_buffer(tmp_path: Path) -> None:
    path = tmp_path / "agent.gpp"
    path.write_text("// world: blocks\nprocedure main() { }\n")
    doc = Session().open(path, "// world: rescue\nprocedure main() { }\n", 3)
    assert doc.directives == {"world": "rescue"}


def test_an_unchanged_program_is_not_checked_again(tmp_path: Path) -> None:
    session = Session()
    path = tmp_path / "a.gpp"
    session.open(path, "procedure main() { }\n", 1)
    first = session.check(path)
    assert session.check(path) is first
    session.edit(path, [(((0, 19), (0, 19)), " ")], 2)
    assert session.check(path) is not first


def test_the_analysis_thread_checks_deeply_nested_programs() -> None:
    depth = 5000
    text = "procedure main() { if (" + "(" * depth + "true" + ")" * depth + ") { } }\n"
    thread = AnalysisThread("test-analysis")
    limit = sys.getrecursionlimit()
    try:
        session = Session()
        path = Path("/nonexistent/deep.gpp")
        session.open(path, text, 1)
        result = thread.submit(lambda: session.check(path)).result(timeout=60)
        assert result.errors == 0
        assert thread.submit(lambda: 6 * 7).result(timeout=5) == 42
    finally:
        thread.close()
    assert sys.getrecursionlimit() >= limit


# ---------------------------------------------------------------- the include index


def test_the_include_index_follows_edits_and_files_that_change(tmp_path: Path) -> None:
    (tmp_path / "lib.gpp").write_text("action a() { }\n")
    (tmp_path / "main.gpp").write_text("procedure main() { }\n")
    session = Session([tmp_path])
    lib, main = (tmp_path / "lib.gpp").resolve(), (tmp_path / "main.gpp").resolve()
    assert session.programs_of(lib) == [lib]
    # The file on disk changes: its new include is seen (by its changed size and time).
    (tmp_path / "main.gpp").write_text('#include "lib.gpp"\nprocedure main() { a(); }\n')
    assert session.programs_of(lib) == [main]
    # An open buffer of it drops the include, then takes it back.
    session.open(main, "procedure main() { }\n", 1)
    assert session.programs_of(lib) == [lib]
    session.edit(main, [(((0, 0), (0, 0)), '#include "lib.gpp"\n')], 2)
    assert session.programs_of(lib) == [main]
    # A buffer naming a file that does not exist yet: found once it is created.
    session.edit(main, [(((0, 10), (0, 13)), "robot")], 3)
    assert session.programs_of(lib) == [lib]
    robot = tmp_path / "robot.gpp"
    robot.write_text("action a() { }\n")
    assert session.programs_of(robot) == [main]


# ---------------------------------------------------------------- the garbage collector


@pytest.fixture
def collector() -> Iterator[GcPolicy]:
    made = GcPolicy()
    try:
        yield made
    finally:
        made.release()
        gc.enable()


class _Cycle:
    def __init__(self) -> None:
        self.me = self


def _garbage() -> weakref.ref[_Cycle]:
    """A weak reference to an object that only a collection frees (it refers to itself)."""
    return weakref.ref(_Cycle())


def test_the_collector_waits_during_a_round_and_is_restored_after(collector: GcPolicy) -> None:
    thresholds = gc.get_threshold()
    gc.enable()
    collector.pause()
    assert not gc.isenabled() and collector.paused
    dead = _garbage()
    _ = [[i] for i in range(100_000)]  # allocations that would start collections
    assert dead() is not None  # none ran
    collector.settle()
    assert gc.isenabled() and gc.get_threshold() == thresholds and not collector.paused
    assert collector.rounds == 1 and collector.collections == 0
    # A process that had the collector off keeps it off.
    gc.disable()
    collector.pause()
    collector.settle()
    assert not gc.isenabled()


def test_the_garbage_of_a_round_waits_for_the_collection_after_the_rounds(collector: GcPolicy) -> None:
    """What a round made is frozen: no collection scans it (nor frees its cycles) until
    `collect`, which frees the cycles of all the rounds since the last one."""
    gc.enable()
    refs = []
    for _ in range(3):
        collector.pause()
        refs.append(_garbage())
        collector.settle()
        gc.collect()  # (as the collector would between rounds: the round's objects are not seen)
    assert [r() is not None for r in refs] == [True, True, True]
    assert collector.rounds == 3 and collector.collections == 0
    made_since = _garbage()  # between rounds: an ordinary collection frees it
    gc.collect()
    assert made_since() is None
    collector.collect()
    assert [r() is None for r in refs] == [True, True, True]
    assert collector.collections == 1 and not collector.pending
    assert gc.isenabled() and gc.get_freeze_count() > 0  # the rest is frozen again


@pytest.mark.slow
def test_a_collection_is_pending_after_min_rounds_and_due_after_max_rounds(collector: GcPolicy) -> None:
    collector.min_rounds, collector.max_rounds = 2, 3
    refs = []
    for rounds in range(3):
        assert (collector.pending, collector.due) == (rounds >= 2, False)
        collector.pause()
        refs.append(_garbage())
        collector.settle()
    assert collector.pending and collector.due and [r() is not None for r in refs] == [True, True, True]
    collector.collect()
    assert not collector.pending and not collector.due and [r() is None for r in refs] == [True, True, True]
    assert collector.freed >= 3  # (the three cycles, and whatever else the test process left)


@pytest.mark.slow
def test_collections_that_find_little_garbage_are_made_rarer(collector: GcPolicy) -> None:
    collector.first_min_rounds = collector.min_rounds = 2
    gc.collect()

    def rounds(n: int, cycles: int) -> None:
        for _ in range(n):
            collector.pause()
            for _ in range(cycles):
                _Cycle()
            collector.settle()

    rounds(2, 0)
    assert collector.pending
    collector.collect()
    assert collector.freed < 2 and collector.min_rounds == 4 and not collector.pending
    rounds(3, 0)
    assert not collector.pending
    rounds(1, 0)
    collector.collect()
    assert collector.min_rounds == 8
    rounds(8, 10)  # (80 cycles)
    collector.collect()
    assert collector.freed >= 80 and collector.min_rounds == 2


def _heap() -> int:
    """The objects the collector tracks, frozen or not."""
    return len(gc.get_objects()) + gc.get_freeze_count()


@pytest.mark.slow
def test_a_long_session_does_not_grow_the_heap(collector: GcPolicy, tmp_path: Path) -> None:
    """A burst of rounds, none collected: each round's check replaces the last one's, which
    dies by reference counting, frozen or not."""
    path = (tmp_path / "a.gpp").resolve()
    text = "".join(f"action a{i}(number n) {{ }}\nprocedure p{i}() {{ a{i}(1); }}\n" for i in range(40))
    session = Session()
    session.open(path, text + "procedure main() { }\n", 1)
    tracked = []
    for version in range(2, 32):
        collector.pause()
        session.edit(path, [(((80, 19), (80, 19)), " " if version % 2 else "")], version)
        [result] = session.results_for(path)
        assert result.errors == 0
        del result
        collector.settle()
        tracked.append(_heap())
    assert collector.collections == 0 and collector.rounds == 30
    # After the first rounds the heap stays as it was (a check of this program: thousands of objects).
    assert max(tracked[3:]) <= tracked[2] + 100, tracked
    collector.collect()
    assert _heap() <= tracked[-1]
