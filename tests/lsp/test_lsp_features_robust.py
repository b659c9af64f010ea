"""No editor feature raises, wherever the cursor is and whatever state the text is in: every
lsp.features function is called at offsets of the example and test programs, of the files they
include (the standard library among them), and of truncated and damaged versions of them. Only
`rename`/`prepare_rename` may raise, and only RenameError. Every range returned lies inside
its document, start before end."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st
from lsprotocol import types

import lsp.features as F
from gpp.check import CheckResult, check_program
from gpp.syntax.loader import ParsedFile, load
from lsp.features.common import comments
from tests.support.budget import examples

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS = sorted([*ROOT.glob("examples/*.gpp"), *ROOT.glob("tests/programs/*.gpp")])
# Pieces a half-typed edit leaves behind.
DAMAGE = ["(", ")", "{", "}", ";", ",", "pick (", "pick (block x) ", "if (", "==", "=", ".", "exists (", '"', "/*"]
DAMAGE += ["//", "é", "🤖", "\n", "action a(", "x.", "component c {", "constraints {", '#include "time.gpp"\n']


def check_ranges(text: str, ranges: list[types.Range]) -> None:
    lines = text.split("\n")
    for r in ranges:
        assert (r.start.line, r.start.character) <= (r.end.line, r.end.character), r
        for p in (r.start, r.end):
            assert 0 <= p.line < len(lines), r
            assert 0 <= p.character <= len(lines[p.line].encode("utf-16-le")) // 2, r


def check_semantic_tokens(lines: list[str], data: list[int]) -> None:
    """In order, not overlapping, each inside one line, types and modifiers in the legend."""
    assert len(data) % 5 == 0
    legend = F.SEMANTIC_TOKENS_LEGEND
    line = char = 0
    end = -1
    for i in range(0, len(data), 5):
        dl, dc, length, t, m = data[i : i + 5]
        assert dl >= 0 and length > 0
        if dl > 0:
            line, char, end = line + dl, dc, -1
        else:
            char += dc
        assert char >= end, "tokens overlap"
        end = char + length
        assert line < len(lines) and end <= len(lines[line].encode("utf-16-le")) // 2
        assert 0 <= t < len(legend.token_types) and 0 <= m < 1 << len(legend.token_modifiers)


def every_feature(result: CheckResult, path: Path, text: str, offsets: list[int]) -> None:
    for offset in offsets:
        ranges: list[types.Range] = []
        for item in F.completion(result, path, offset):
            assert item.label
            if isinstance(item.text_edit, types.TextEdit):
                ranges.append(item.text_edit.range)
        h = F.hover(result, path, offset)
        if h is not None and h.range is not None:
            ranges.append(h.range)
        ranges += [x.range for x in F.definition(result, path, offset) if x.uri == path.as_uri()]
        ranges += [x.range for x in F.references(result, path, offset, True) if x.uri == path.as_uri()]
        ranges += [x.range for x in F.document_highlight(result, path, offset)]
        s = F.signature_help(result, path, offset)
        assert s is None or len(s.signatures) == 1
        try:
            prepared = F.prepare_rename(result, path, offset)
            assert prepared is None or isinstance(prepared, types.PrepareRenamePlaceholder)
            if prepared is not None:
                ranges.append(prepared.range)
            F.rename(result, path, offset, "renamed_here")
        except F.RenameError as e:
            assert str(e)
        check_ranges(text, ranges)
    symbols = F.document_symbols(result, path)
    assert all(s.name for s in symbols)
    check_ranges(text, [s.range for s in symbols] + [s.selection_range for s in symbols])
    lines = text.split("\n")
    for fold in F.folding_ranges(result, path):
        assert 0 <= fold.start_line < fold.end_line < len(lines)
    check_semantic_tokens(lines, F.semantic_tokens(result, path))
    for hint in F.inlay_hints(result, path, 0, len(text)):
        assert isinstance(hint.position, types.Position)
    assert all(s.name for s in F.workspace_symbols([result], ""))


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_no_feature_raises_across_an_example_or_test_program(path: Path) -> None:
    path = path.resolve()
    text = path.read_text(encoding="utf-8")
    result = check_program(path)
    # Every 53rd offset (a prime, so that the offsets fall on every kind of place), and the end.
    every_feature(result, path, text, [*range(0, len(text), 53), len(text)])


@st.composite
def damaged_programs(draw: st.DrawFn) -> tuple[Path, str]:
    path = draw(st.sampled_from(PROGRAMS)).resolve()
    text = path.read_text(encoding="utf-8")
    for _ in range(draw(st.integers(0, 3))):
        at = draw(st.integers(0, len(text)))
        how = draw(st.sampled_from(["cut", "delete", "insert"]))
        if how == "cut":
            text = text[:at]
        elif how == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 40)) :]
        else:
            text = text[:at] + draw(st.sampled_from(DAMAGE)) + text[at:]
    return path, text


@settings(
    max_examples=examples(50), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)
@given(damaged_programs(), st.data())
def test_no_feature_raises_on_damaged_programs(damaged: tuple[Path, str], data: st.DataObject) -> None:
    path, text = damaged
    note(f"text of {path.name}:\n{text}")
    result = check_program(path, overrides={path: text})
    # The file itself, or one it includes (the standard library's among them).
    pf = data.draw(st.sampled_from(result.loaded.files))
    doc_text = pf.source.text
    offsets = data.draw(st.lists(st.integers(0, len(doc_text)), min_size=1, max_size=12))
    note(f"file {pf.path}, offsets {offsets}")
    every_feature(result, pf.path, doc_text, offsets)


def comments_by_scanning(file: ParsedFile) -> list[tuple[int, int]]:
    """The comments of a file, found character by character in every gap between tokens."""
    text = file.source.text
    out: list[tuple[int, int]] = []
    gap_start = 0
    for tok in [*file.tokens, None]:
        gap_end = len(text) if tok is None else tok.start
        i = gap_start
        while i < gap_end - 1:
            if text.startswith("//", i):
                j = text.find("\n", i)
                j = gap_end if j < 0 or j > gap_end else j
                out.append((i, j))
                i = j
            elif text.startswith("/*", i):
                j = text.find("*/", i + 2)
                j = gap_end if j < 0 or j + 2 > gap_end else j + 2
                out.append((i, j))
                i = j
            else:
                i += 1
        if tok is not None:
            gap_start = tok.end
    return out


COMMENTED = """\
// head // still head /* not a block
/* a block // with a slash pair */ action a() { } /* unterminated in a gap
string fluent s() { initially: () = "// not /* a comment"; } //tail"""


@settings(max_examples=examples(60), deadline=None)
@given(
    st.sampled_from([COMMENTED, *(p.read_text(encoding="utf-8") for p in PROGRAMS[:6])]),
    st.lists(st.tuples(st.floats(0, 1), st.sampled_from([*DAMAGE, "/", "*/", "/*/", "///", '"//"'])), max_size=4),
)
def test_comments_are_found_as_a_character_scan_finds_them(text: str, damage: list[tuple[float, str]]) -> None:
    for where, piece in damage:
        at = int(where * len(text))
        text = text[:at] + piece + text[at:]
    note(text)
    path = Path("/nonexistent/commented.gpp")
    file = load([path], {path: text}).files[0]
    assert comments(file) == comments_by_scanning(file)


def test_the_comments_of_a_file_with_strings_and_unterminated_blocks() -> None:
    path = Path("/nonexistent/commented.gpp")
    file = load([path], {path: COMMENTED}).files[0]
    found = [COMMENTED[s:e] for s, e in comments(file)]
    assert found == [
        "// head // still head /* not a block",
        "/* a block // with a slash pair */",
        '/* unterminated in a gap\nstring fluent s() { initially: () = "// not /* a comment"; } //tail',
    ]
