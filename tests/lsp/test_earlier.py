"""Answers from an earlier check (lsp.features.earlier): positions of the current text mapped to
the checked one and ranges of the checked text mapped back, on random texts and edits, and
hover and definition from the check before an edit equal to those from the check after it."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types

import lsp.features as F
from gpp.base.source import Source
from gpp.check import check_program
from lsp.features.earlier import EarlierText, Moved, Unplaced

texts = st.text(st.sampled_from("ab\n😀é"), max_size=30)


@st.composite
def edits(draw: st.DrawFn) -> tuple[str, str]:
    """A text and the text after one edit (a stretch replaced by another)."""
    text = draw(texts)
    start = draw(st.integers(0, len(text)))
    end = draw(st.integers(start, len(text)))
    return text, text[:start] + draw(texts) + text[end:]


@settings(max_examples=300, deadline=None)
@given(edits())
def test_what_is_mapped_holds_the_same_characters(edit: tuple[str, str]) -> None:
    checked, now = edit
    moved = Moved.between(checked, now)
    for offset in range(len(now)):
        then = moved.to_checked(offset)
        if then is not None:
            assert checked[then] == now[offset]
        else:
            assert moved.start <= offset < moved.now_end
    for start in range(len(checked) + 1):
        for end in range(start, len(checked) + 1):
            placed = moved.to_now(start, end)
            if placed is not None:
                assert now[placed[0] : placed[1]] == checked[start:end]
            else:
                assert start < moved.checked_end and end > moved.start


def test_a_range_in_the_edited_stretch_is_unplaced() -> None:
    text = EarlierText.of(Source("go(hall);\n"), Source("go(kitchen);\n"))
    assert text.offset_checked(types.Position(0, 1)) == 1
    assert text.offset_checked(types.Position(0, 5)) is None
    assert text.offset_checked(types.Position(0, 11)) == 8  # `;`
    with pytest.raises(Unplaced):
        text.range_now(types.Range(types.Position(0, 3), types.Position(0, 7)))
    moved = text.range_now(types.Range(types.Position(0, 8), types.Position(0, 9)))
    assert moved == types.Range(types.Position(0, 11), types.Position(0, 12))


PROGRAM = "symbol domain Loc = {kitchen, hall}\naction go(Loc to) { }\nprocedure main() {\n    go(hall);\n}\n"


def test_hover_and_definition_from_the_check_before_an_edit_are_those_after_it(tmp_path: Path) -> None:
    path = (tmp_path / "moved.gpp").resolve()
    after = "// a line\n" + PROGRAM
    before_check = check_program(path, overrides={path: PROGRAM})
    after_check = check_program(path, overrides={path: after})
    text = EarlierText.of(Source(PROGRAM), Source(after))
    where = types.Position(4, 5)  # `go` in main, one line down
    offset = text.offset_checked(where)
    assert offset == PROGRAM.index("go(hall)") + 1
    hover = F.hover(before_check, path, offset)
    [location] = F.definition(before_check, path, offset)
    assert hover is not None and hover.range is not None
    now = after_check.loaded.file(path)
    assert now is not None
    expected_hover = F.hover(after_check, path, now.source.lsp_offset(4, 5))
    assert expected_hover is not None
    assert text.range_now(hover.range) == expected_hover.range
    assert text.range_now(location.range) == F.definition(after_check, path, now.source.lsp_offset(4, 5))[0].range


def test_edits_on_both_sides_of_a_place_unplace_it() -> None:
    # Two edits between the checks are one changed stretch, from the first to the last.
    after = "// a line\n" + PROGRAM.replace("hall);", "hall); ")
    text = EarlierText.of(Source(PROGRAM), Source(after))
    with pytest.raises(Unplaced):
        text.range_now(types.Range(types.Position(1, 7), types.Position(1, 9)))  # `go` declared
    assert text.offset_checked(types.Position(0, 0)) is None
    assert text.offset_checked(types.Position(5, 0)) == PROGRAM.index("}\n", PROGRAM.index("hall);"))
