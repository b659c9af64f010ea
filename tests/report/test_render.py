"""Tests for gpp.report.text: golden text for typical diagnostics, the JSON report, colour parity.

The goldens live in tests/golden/render/<case>.txt. To regenerate them after an intended change
of the layout, run `GPP_UPDATE_GOLDEN=1 .venv/bin/pytest tests/report/test_render.py` and review the diff.
"""

from __future__ import annotations

import io
import json
import os
from collections.abc import Callable
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gpp.base.diagnostics import Diagnostic, Edit, Fix, Label, Message, error, warning
from gpp.base.source import Source, Span
from gpp.report.text import (
    count_problems,
    layout_diagnostic,
    print_diagnostics,
    render_json,
    render_plain,
    render_text,
    to_rich_text,
)

GOLDEN_DIR = Path(__file__).parents[1] / "golden" / "render"
UPDATE_GOLDEN = os.environ.get("GPP_UPDATE_GOLDEN") == "1"


def span_of(source: Source, needle: str, occurrence: int = 0, *, width: int | None = None) -> Span:
    """The span of the `occurrence`-th `needle` in `source` (or of its first `width` characters)."""
    start = -1
    for _ in range(occurrence + 1):
        start = source.text.index(needle, start + 1)
    return Span(source, start, start + (len(needle) if width is None else width))


def point_after(source: Source, needle: str) -> Span:
    end = source.text.index(needle) + len(needle)
    return Span(source, end, end)


# ---------------------------------------------------------------- the golden cases


def missing_semicolon() -> Diagnostic:
    src = Source("procedure main() {\n    x() = 1\n    y() = 2;\n}\n", "agent.gpp")
    at = point_after(src, "x() = 1")
    return error(
        Message("E0011", "expected `;` after this statement"),
        at,
        "add `;` here",
        fix=Fix("insert `;`", (Edit(at, ";"),)),
    )


def unexpected_token_with_secondary() -> Diagnostic:
    src = Source("procedure main() {\n  if (done(\n    x = 1;\n  }\n}\n", "agent.gpp")
    return error(
        Message("E0010", "expected `)`, found `}`"),
        span_of(src, "}"),
        "unexpected token",
        secondary=[Label(span_of(src, "(", 2), "this `(` is not closed")],
    )


def multiline_span() -> Diagnostic:
    src = Source(
        "procedure main() {\n  while (true) {\n    wait();\n    step();\n    log();\n  }\n}\n",
        "loop.gpp",
    )
    start = src.text.index("while")
    end = src.text.index("  }\n}") + 3
    return error(
        Message("E0200", "this loop never ends"),
        Span(src, start, end),
        "the loop",
        secondary=[Label(span_of(src, "true"), "the condition is always true")],
    )


def multiline_span_mid_line() -> Diagnostic:
    src = Source("procedure main() { if (a) {\n  b();\n} }\n", "mid.gpp")
    start = src.text.index("{ if")
    return error(Message("E0201", "unbalanced block"), Span(src, start, len(src.text) - 1), "this block")


def zero_width_at_end_of_file() -> Diagnostic:
    src = Source("procedure main() {\n  x() = 1;\n", "eof.gpp")
    end = len(src.text)
    return error(
        Message("E0012", "unexpected end of file, expected `}`"),
        Span(src, end, end),
        "the file ends here",
        secondary=[Label(span_of(src, "{"), "this `{` is not closed")],
    )


def zero_width_at_end_of_file_without_newline() -> Diagnostic:
    src = Source("procedure main() {", "eof.gpp")
    end = len(src.text)
    return error(Message("E0012", "unexpected end of file, expected `}`"), Span(src, end, end), "the file ends here")


def tab_indented_line() -> Diagnostic:
    src = Source("procedure main() {\n\tif (x)\t{\n\t\tgoto(\tkitchen);\n\t}\n}\n", "tabs.gpp")
    return error(
        Message("E0300", "unknown location `kitchen`"),
        span_of(src, "kitchen"),
        "not declared",
        secondary=[Label(span_of(src, "goto"), "expects a `Location`")],
        help="did you mean `Kitchen`?",
    )


def warning_with_notes_and_help() -> Diagnostic:
    src = Source("bool fluent busy() {\ninitially:\n  () = false;\n}\nprocedure main() {\n  int n = 3;\n}\n", "w.gpp")
    return warning(
        Message("W0101", "variable `n` is never used"),
        span_of(src, "n =", width=1),
        "assigned but never read",
        notes=["unused variables are often typos", "this note has\ntwo lines"],
        help="prefix the name with `_` to silence this warning",
    )


def secondary_in_another_file() -> Diagnostic:
    main = Source('#include "lib.gpp"\nprocedure main() {\n  pick_up(a, b);\n}\n', "agent.gpp")
    lib = Source("action pick_up(Block x) {\n  effect: holding() = x;\n}\n", "lib/lib.gpp")
    return error(
        Message("E0400", "`pick_up` takes 1 argument but 2 were given"),
        span_of(main, "pick_up(a, b)"),
        "called with 2 arguments",
        secondary=[
            Label(span_of(main, "b)", width=1), "unexpected argument"),
            Label(span_of(lib, "pick_up(Block x)"), "declared here"),
        ],
    )


def replacement_fix() -> Diagnostic:
    src = Source("procedur main() {\n}\n", "typo.gpp")
    name = span_of(src, "procedur")
    return error(
        Message("E0101", "unknown keyword `procedur`"),
        name,
        "not a keyword",
        fix=Fix("did you mean `procedure`?", (Edit(name, "procedure"),)),
    )


def several_labels_on_one_line() -> Diagnostic:
    src = Source("procedure main() {\n  x = f(a, b, c);\n}\n", "labels.gpp")
    return error(
        Message("E0500", "mismatched types"),
        span_of(src, "c)", width=1),
        "expected `number`, found `symbol`",
        secondary=[Label(span_of(src, "a,", width=1), "first"), Label(span_of(src, "b,", width=1), "second")],
    )


CASES: dict[str, Callable[[], Diagnostic]] = {
    f.__name__: f
    for f in (
        missing_semicolon,
        unexpected_token_with_secondary,
        multiline_span,
        multiline_span_mid_line,
        zero_width_at_end_of_file,
        zero_width_at_end_of_file_without_newline,
        tab_indented_line,
        warning_with_notes_and_help,
        secondary_in_another_file,
        replacement_fix,
        several_labels_on_one_line,
    )
}


def check_golden(name: str, actual: str) -> None:
    path = GOLDEN_DIR / f"{name}.txt"
    if UPDATE_GOLDEN:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(actual, encoding="utf-8")
        return
    if not path.exists():
        pytest.fail(f"no golden file {path}; create it with GPP_UPDATE_GOLDEN=1")
    assert actual == path.read_text(encoding="utf-8")


@pytest.mark.parametrize("name", sorted(CASES))
def test_rendered_text_matches_golden(name: str) -> None:
    check_golden(name, render_plain(CASES[name]()))


def test_report_ends_with_summary_line() -> None:
    check_golden("report", render_text([missing_semicolon(), warning_with_notes_and_help(), replacement_fix()]))


# ---------------------------------------------------------------- exact expectations, spelled out


def test_missing_semicolon_caret_sits_right_after_the_previous_token() -> None:
    lines = render_plain(missing_semicolon()).splitlines()
    assert lines[:5] == [
        "error[E0011]: expected `;` after this statement",
        " --> agent.gpp:2:12",
        "  |",
        "2 |     x() = 1",
        "  |            ^ add `;` here",
    ]


def test_carets_cover_the_whole_primary_span() -> None:
    src = Source("procedure main() {\n  navigate(kitchen);\n}\n", "a.gpp")
    d = error(Message("E1", "m"), span_of(src, "navigate"), "here")
    assert "  |   ^^^^^^^^ here" in render_plain(d).splitlines()


def test_gutter_is_as_wide_as_the_largest_line_number() -> None:
    src = Source("\n" * 120 + "x;\n", "big.gpp")
    d = error(Message("E1", "m"), span_of(src, "x"), secondary=[Label(Span(src, 0, 0), "top")])
    lines = render_plain(d).splitlines()
    assert lines[1] == "   --> big.gpp:121:1"
    assert "121 | x;" in lines
    assert "  1 |" in lines
    assert "..." in lines


def test_tabs_keep_carets_aligned() -> None:
    text = render_plain(tab_indented_line())
    source_line = next(line for line in text.splitlines() if line.startswith("3 |"))
    caret_line = next(line for line in text.splitlines() if "^" in line)
    assert "\t" not in text
    assert caret_line.index("^") == source_line.index("kitchen")
    assert caret_line.count("^") == len("kitchen")


def test_wide_characters_keep_carets_aligned() -> None:
    src = Source('procedure main() { say("日本語"); x(); }\n', "wide.gpp")
    lines = render_plain(error(Message("E1", "m"), span_of(src, "x()"))).splitlines()
    # Each of the three CJK characters takes two terminal cells.
    assert lines[4].index("^") == lines[3].index("x()") + 3
    assert lines[4].count("^") == 3


def test_control_characters_are_not_echoed() -> None:
    src = Source("x\x1b[31m = 1;\n", "ctl.gpp")
    text = render_plain(error(Message("E1", "m"), span_of(src, "= 1")))
    assert "\x1b" not in text
    assert "x\ufffd[31m = 1;" in text


def test_warning_header_says_warning() -> None:
    assert render_plain(warning_with_notes_and_help()).startswith("warning[W0101]: variable `n` is never used\n")


def test_summary_counts_errors_and_warnings() -> None:
    diagnostics = [missing_semicolon(), replacement_fix(), warning_with_notes_and_help()]
    assert render_text(diagnostics).endswith("\nerror: 2 errors, 1 warning\n")
    assert render_text([warning_with_notes_and_help()]).endswith("\nwarning: 1 warning\n")
    assert render_text([]) == "no problems found\n"
    assert count_problems(diagnostics) == (2, 1)


def test_multiline_fix_falls_back_to_a_help_line() -> None:
    src = Source("a;\nb;\n", "f.gpp")
    d = error(Message("E1", "m"), span_of(src, "a"), fix=Fix("join the lines", (Edit(Span(src, 1, 4), ""),)))
    text = render_plain(d)
    assert "  = help: join the lines" in text
    assert "\nhelp:" not in text


@pytest.mark.parametrize(
    ("start", "end"),
    [(-5, 3), (0, 10_000), (10_000, 10_001), (5, 2)],
)
def test_out_of_range_spans_do_not_crash(start: int, end: int) -> None:
    src = Source("ab\ncd\n", "r.gpp")
    assert render_plain(error(Message("E1", "m"), Span(src, start, end), "l")).startswith("error[E1]: m\n")


@given(
    text=st.text(alphabet=st.sampled_from("ab \t\n\r{};日\x00é"), max_size=40),
    points=st.lists(st.integers(min_value=0, max_value=45), min_size=4, max_size=4),
    fix_text=st.text(alphabet="x;\n", max_size=3),
)
def test_any_span_renders(text: str, points: list[int], fix_text: str) -> None:
    src = Source(text, "p.gpp")
    a, b, c, d = (min(p, len(text)) for p in points)
    diagnostic = error(
        Message("E1", "m"),
        Span(src, min(a, b), max(a, b)),
        "primary",
        secondary=[Label(Span(src, min(c, d), max(c, d)), "secondary")],
        fix=Fix("fix", (Edit(Span(src, min(a, c), max(a, c)), fix_text),)),
    )
    rendered = render_plain(diagnostic)
    assert rendered.startswith("error[E1]: m\n")
    assert rendered.count("^") >= 1


# ---------------------------------------------------------------- colour


def test_rich_text_has_the_same_characters_as_plain_text() -> None:
    for make in CASES.values():
        d = make()
        assert to_rich_text(layout_diagnostic(d)).plain == render_plain(d)


def test_console_output_is_coloured_only_on_a_terminal() -> None:
    from rich.console import Console

    diagnostics = [missing_semicolon()]
    plain = io.StringIO()
    print_diagnostics(Console(file=plain, force_terminal=False, color_system=None, width=20), diagnostics)
    assert plain.getvalue() == render_text(diagnostics)  # also: narrow consoles do not wrap lines

    coloured = io.StringIO()
    print_diagnostics(Console(file=coloured, force_terminal=True, color_system="standard"), diagnostics)
    assert "\x1b[1;31merror[E0011]" in coloured.getvalue()


# ---------------------------------------------------------------- JSON


def test_json_report_structure() -> None:
    diagnostics = [missing_semicolon(), secondary_in_another_file(), warning_with_notes_and_help()]
    report = json.loads(render_json(diagnostics))
    assert report["version"] == 1
    assert report["summary"] == {"errors": 2, "warnings": 1}
    first, second, third = report["diagnostics"]
    assert first == {
        "code": "E0011",
        "severity": "error",
        "message": "expected `;` after this statement",
        "file": "agent.gpp",
        "line": 2,
        "column": 12,
        "end_line": 2,
        "end_column": 12,
        "offset": 30,
        "end_offset": 30,
        "label": "add `;` here",
        "secondary": [],
        "notes": [],
        "help": None,
        "fix": {
            "message": "insert `;`",
            "applicability": "unsafe",  # made by hand here; the parser marks its `;` safe
            "edits": [{"file": "agent.gpp", "line": 2, "column": 12, "end_line": 2, "end_column": 12, "text": ";"}],
        },
    }
    assert (second["line"], second["column"], second["end_line"], second["end_column"]) == (3, 3, 3, 16)
    assert second["secondary"] == [
        {
            "file": "agent.gpp",
            "line": 3,
            "column": 14,
            "end_line": 3,
            "end_column": 15,
            "message": "unexpected argument",
        },
        {"file": "lib/lib.gpp", "line": 1, "column": 8, "end_line": 1, "end_column": 24, "message": "declared here"},
    ]
    assert second["fix"] is None
    assert third["severity"] == "warning"
    assert third["notes"] == ["unused variables are often typos", "this note has\ntwo lines"]
    assert third["help"] == "prefix the name with `_` to silence this warning"


def test_json_offsets_agree_with_lines_and_columns() -> None:
    d = multiline_span()
    item = json.loads(render_json([d]))["diagnostics"][0]
    source = d.span.source
    assert source.line_col(item["offset"]) == (item["line"], item["column"])
    assert source.line_col(item["end_offset"]) == (item["end_line"], item["end_column"])


def test_json_report_without_diagnostics() -> None:
    assert json.loads(render_json([])) == {"version": 1, "diagnostics": [], "summary": {"errors": 0, "warnings": 0}}
