"""Diagnostics at scale and inputs that are not text.

A long source line is shown shortened around its labels (`…` for the rest), with the real
column in the location line; after `max_per_code` diagnostics of one code in one file the text
report counts the rest in one line; a file with a byte-order mark checks like one without; a
file that is not UTF-8 text (NUL bytes, invalid UTF-8) gets one E0006, also through `#include`,
`gpp run` and `gpp test`; rendering is linear in the number of diagnostics and the line length.
"""

from __future__ import annotations

import time
from pathlib import Path

from gpp.base.diagnostics import Diagnostic, Edit, Fix, Label, Message, error
from gpp.base.source import Source, Span, decode_text
from gpp.check import check_program
from gpp.report.text import limit_diagnostics, render_plain, render_text
from tests.support.cli import Result, run

# One line of 818 characters: `oops` at character 405, `c` at 813.
LONG = "x = " + "a + " * 100 + "oops + " + "b + " * 100 + "c;\n"


def long_source() -> Source:
    return Source(LONG, "long.gpp")


def span_of(source: Source, needle: str, width: int | None = None) -> Span:
    start = source.text.index(needle)
    return Span(source, start, start + (len(needle) if width is None else width))


HELP = "  = help: gpp reads programs as UTF-8 text: convert the file to UTF-8, or check that it is the right file\n"


def run_gpp(*args: str, cwd: Path) -> Result:
    return run(*args, cwd=cwd)


# ---------------------------------------------------------------- long lines


def test_a_long_line_is_shown_around_its_label_with_the_real_column() -> None:
    src = long_source()
    text = render_plain(error(Message("E0101", "unknown name `oops`"), span_of(src, "oops"), "not declared"))
    shown = "…" + "a + " * 10 + "oops + " + "b + " * 9 + "b…"
    assert text == (
        "error[E0101]: unknown name `oops`\n"
        " --> long.gpp:1:405\n"
        "  |\n"
        f"1 | {shown}\n"
        f"  | {' ' * shown.index('oops')}^^^^ not declared\n"
    )


def test_labels_far_apart_on_a_long_line_each_get_a_part_of_it() -> None:
    src = long_source()
    diagnostic = error(
        Message("E0101", "two"),
        span_of(src, "oops"),
        "here",
        secondary=[Label(Span(src, 0, 1), "start"), Label(span_of(src, "c;", 1), "end")],
    )
    shown = "x = " + "a + " * 9 + "a…" + "a + " * 10 + "oops + " + "b + " * 9 + "b…" + "b + " * 10 + "c;"
    oops, c = shown.index("oops"), shown.index("c;")
    assert render_plain(diagnostic).splitlines()[3:] == [
        f"1 | {shown}",
        f"  | -{' ' * (oops - 1)}^^^^{' ' * (c - oops - 4)}- end",
        f"  | |{' ' * (oops - 1)}|",
        f"  | |{' ' * (oops - 1)}here",
        "  | start",
    ]


def test_a_fix_on_a_long_line_shows_the_edited_part() -> None:
    src = long_source()
    end = src.text.index("c;") + 1
    fix = Fix("rename it", (Edit(span_of(src, "oops"), "fine"),))
    text = render_plain(error(Message("E0011", "semi"), Span(src, end, end), "add", fix=fix))
    window = "…" + "a + " * 10 + "{} + " + "b + " * 9 + "b…"
    assert text.splitlines()[1:] == [
        " --> long.gpp:1:813",
        "  |",
        "1 | …" + " + b" * 9 + " + c;",
        "  |                                          ^ add",
        "  |",
        "help: rename it",
        "  |",
        "1 - " + window.format("oops"),
        "1 + " + window.format("fine"),
    ]


def test_a_short_line_is_shown_whole() -> None:
    src = Source("x = " + "a + " * 30 + "oops;\n", "short.gpp")
    lines = render_plain(error(Message("E0101", "unknown"), span_of(src, "oops"))).splitlines()
    assert lines[3] == "1 | " + src.text.rstrip("\n")
    assert lines[4] == "  | " + " " * src.text.index("oops") + "^^^^"


def test_rendering_is_linear_in_the_number_of_diagnostics_and_the_line_length() -> None:
    # One line, one diagnostic every 64 characters: 8 KB (128) against 64 KB (1,024).
    # Printing the whole line for each diagnostic made this 64 times slower, not 8.
    def seconds(size: int) -> float:
        src = Source("a();" * (size // 4) + "\n", "one-line.gpp")
        diagnostics = [error(Message("E0103", "unknown"), Span(src, k, k + 1), "here") for k in range(0, size, 64)]
        best = float("inf")
        for _ in range(3):  # the process's CPU time: a busy machine's other processes do not count
            started = time.process_time()
            out = render_text(diagnostics)
            best = min(best, time.process_time() - started)
        assert out.count("error[E0103]") == size // 64
        return best

    ratio = seconds(65_536) / seconds(8_192)
    assert ratio < 20, f"64 KB took {ratio:.1f} times as long as 8 KB"


# ---------------------------------------------------------------- many diagnostics


def many(n: int, code: str, source: Source) -> list[Diagnostic]:
    return [error(Message(code, f"number {k}"), Span(source, k, k + 1)) for k in range(n)]


def test_after_the_limit_the_rest_of_a_code_in_a_file_is_counted_in_one_line() -> None:
    src = Source("x" * 100 + "\n", "f.gpp")
    other = Source("y" * 100 + "\n", "g.gpp")
    diagnostics = [*many(60, "E0101", src), *many(3, "E0102", src), *many(55, "E0101", other)]
    text = render_text(diagnostics, max_per_code=50)
    assert text.count("error[E0101]") == 100
    assert text.count("error[E0102]") == 3
    assert "number 49\n" in text and "number 50\n" not in text
    assert text.endswith(
        "note: 10 more E0101 errors in f.gpp not shown (the first 50 of a code in a file are)\n"
        "note: 5 more E0101 errors in g.gpp not shown (the first 50 of a code in a file are)\n"
        "\n"
        "error: 118 errors\n"
    )
    shown, omitted = limit_diagnostics(diagnostics, 50)
    assert [(o.path, o.code, o.count) for o in omitted] == [("f.gpp", "E0101", 10), ("g.gpp", "E0101", 5)]
    assert len(shown) == 103


def test_one_more_than_the_limit_says_so_in_the_singular() -> None:
    text = render_text(many(3, "E0101", Source("xyz\n", "f.gpp")), max_per_code=2)
    assert "note: 1 more E0101 error in f.gpp not shown (the first 2 of a code in a file are)\n" in text


def test_no_limit_shows_everything() -> None:
    diagnostics = many(60, "E0101", Source("x" * 100 + "\n", "f.gpp"))
    text = render_text(diagnostics, max_per_code=0)
    assert text.count("error[E0101]") == 60
    assert "more" not in text


def test_cli_max_diagnostics(tmp_path: Path) -> None:
    (tmp_path / "many.gpp").write_text("procedure main() {\n" + "    zz();\n" * 60 + "}\n")
    default = run_gpp("check", "--color", "never", "many.gpp", cwd=tmp_path)
    assert default.returncode == 1, default.stderr
    assert default.stdout.count("error[E0103]") == 50
    assert default.stdout.endswith(
        "note: 10 more E0103 errors in many.gpp not shown (the first 50 of a code in a file are)\n\nerror: 60 errors\n"
    )
    everything = run_gpp("check", "--color", "never", "--max-diagnostics", "0", "many.gpp", cwd=tmp_path)
    assert everything.stdout.count("error[E0103]") == 60
    assert "not shown" not in everything.stdout
    refused = run_gpp("check", "--format", "json", "--max-diagnostics", "5", "many.gpp", cwd=tmp_path)
    assert (refused.returncode, refused.stdout) == (2, "")
    assert refused.stderr == (
        "error: --max-diagnostics applies to the text output only (json holds every diagnostic)\n"
    )


# ---------------------------------------------------------------- inputs that are not text


def test_decode_text() -> None:
    assert decode_text(b"\xef\xbb\xbfab") == ("ab", None)
    text, bad = decode_text(b"ab\ncd\xffe")
    assert text == "ab\ncd\ufffde"
    assert bad is not None and (bad.offset, bad.byte, bad.describe()) == (5, 0xFF, "invalid UTF-8 byte 0xff")
    text, bad = decode_text("é\x00".encode())
    assert bad is not None and (bad.offset, bad.byte, bad.describe()) == (1, 0, "a NUL byte (0x00)")
    _, bad = decode_text(b"ab\xe2\x82")  # a sequence cut short at the end
    assert bad is not None and (bad.offset, bad.byte) == (2, 0xE2)


def codes_at(path: Path) -> list[tuple[str, str, int, int, str]]:
    result = check_program(path)
    return [(d.code, d.span.source.path, d.span.line, d.span.col, d.message) for d in result.diagnostics]


def test_a_byte_order_mark_is_skipped_and_columns_stay_right(tmp_path: Path) -> None:
    body = "action go() {}\nprocedure main() { go() }\n"
    (tmp_path / "bom.gpp").write_bytes(b"\xef\xbb\xbf" + body.encode())
    (tmp_path / "plain.gpp").write_text(body)
    assert [c[2:] for c in codes_at(tmp_path / "bom.gpp")] == [c[2:] for c in codes_at(tmp_path / "plain.gpp")]
    assert [(c[0], c[2], c[3]) for c in codes_at(tmp_path / "bom.gpp")] == [("E0011", 2, 24)]
    (tmp_path / "clean.gpp").write_bytes(b"\xef\xbb\xbfaction go() {}\nprocedure main() { go(); }\n")
    assert codes_at(tmp_path / "clean.gpp") == []


def test_a_binary_file_gets_one_diagnostic_at_its_first_nul_byte(tmp_path: Path) -> None:
    path = tmp_path / "binary.gpp"
    path.write_bytes(b"\x7fELF\x02\x01\x01" + bytes(range(256)) * 40)
    assert codes_at(path) == [
        ("E0006", str(path), 1, 8, "this is not a UTF-8 text file: a NUL byte (0x00) at line 1, column 8")
    ]


def test_a_latin_1_file_gets_one_diagnostic_at_its_first_invalid_byte(tmp_path: Path) -> None:
    path = tmp_path / "latin.gpp"
    path.write_bytes("action go() {}\n// café crème\nprocedure main() { go(); ü }\n".encode("latin-1"))
    assert codes_at(path) == [
        ("E0006", str(path), 2, 7, "this is not a UTF-8 text file: invalid UTF-8 byte 0xe9 at line 2, column 7")
    ]


def test_an_included_binary_file_is_reported_at_the_include(tmp_path: Path) -> None:
    (tmp_path / "data.gpp").write_bytes(b"action a() {}\n\x00\x01\x02" * 100)
    main = tmp_path / "main.gpp"
    main.write_text('action go() {}\n#include "data.gpp"\nprocedure main() { go(); }\n')
    assert codes_at(main) == [
        (
            "E0006",
            str(main),
            2,
            10,
            "included file `data.gpp` is not a UTF-8 text file: a NUL byte (0x00) at line 2, column 1",
        )
    ]


def test_cli_check_run_and_test_on_files_that_are_not_text(tmp_path: Path) -> None:
    (tmp_path / "binary.gpp").write_bytes(bytes(range(256)) * 200)  # 51 KB, NUL first
    (tmp_path / "latin.gpp").write_bytes("procedure main() {\n    // größer\n}\n".encode("latin-1"))
    (tmp_path / "logo.gpp").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    # (A file given that another given file includes is checked as part of that program: the
    # included binary is one not given, so that each of the three errors shows.)
    (tmp_path / "main.gpp").write_text('#include "logo.gpp"\nprocedure main() { }\n')
    check = run_gpp("check", "--color", "never", "binary.gpp", "latin.gpp", "main.gpp", cwd=tmp_path)
    assert check.returncode == 1, check.stderr
    help_line = HELP.rstrip("\n")
    assert check.stdout.split("\n") == [
        "error[E0006]: this is not a UTF-8 text file: a NUL byte (0x00) at line 1, column 1",
        " --> binary.gpp:1:1",
        "  |",
        "1 | " + "\ufffd" * 9 + "    ",  # bytes 0 to 9: control characters shown as �, then a tab
        "  | ^ not UTF-8 text",
        "  |",
        help_line,
        "",
        "error[E0006]: this is not a UTF-8 text file: invalid UTF-8 byte 0xf6 at line 2, column 10",
        " --> latin.gpp:2:10",
        "  |",
        "2 |     // gr\ufffd\ufffder",
        "  |          ^ not UTF-8 text",
        "  |",
        help_line,
        "",
        "error[E0006]: included file `logo.gpp` is not a UTF-8 text file: invalid UTF-8 byte 0x89 at line 1, column 1",
        " --> main.gpp:1:10",
        "  |",
        '1 | #include "logo.gpp"',
        "  |          ^^^^^^^^^^ not UTF-8 text",
        "  |",
        "  = note: the included file is logo.gpp",
        help_line,
        "",
        "error: 3 errors",
        "",
    ]
    run = run_gpp("run", "main.gpp", cwd=tmp_path)
    assert run.returncode == 1, run.stderr
    assert run.stdout.startswith("error[E0006]: included file `logo.gpp` is not a UTF-8 text file")
    assert run.stdout.count("error[") == 1
    test = run_gpp("test", "binary.gpp", cwd=tmp_path)
    assert test.returncode == 1, test.stderr
    assert "E0006" in test.stdout and "Traceback" not in test.stdout + test.stderr
