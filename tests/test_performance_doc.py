"""docs/performance.md and its driver (bench/performance.py), without running a bench: every
marker is closed and names a bench the driver knows, and the driver's replacement leaves
everything outside the markers byte for byte."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.performance import BENCHES, DOC, MarkerError, body, command_line, replace_section, sections

SAMPLE = (
    "# Title\r\n\nProse quoting a marker: `<!-- bench: NAME -->`.\n\n"
    "<!-- bench: soak -->\n| old | table |\n|---|---|\n<!-- /bench: soak -->\n"
    "between, with trailing spaces   \n\n<!-- bench: sim -->\n<!-- /bench: sim -->\n"
    "<details>\n\n<!-- bench: pathological -->\nold\n<!-- /bench: pathological -->\n\n</details>\n"
)


def outside(text: str) -> list[str]:
    """The pieces of `text` outside its bench sections, in order."""
    pieces, at = [], 0
    for start, end in sorted(sections(text).values()):
        pieces.append(text[at:start])
        at = end
    return [*pieces, text[at:]]


def test_every_marker_of_the_page_is_closed_and_names_a_bench_of_the_driver() -> None:
    found = sections(DOC.read_bytes().decode("utf-8"))
    assert set(found) <= set(BENCHES), f"unknown benches: {set(found) - set(BENCHES)}"
    assert set(found) == set(BENCHES), f"benches without a section: {set(BENCHES) - set(found)}"


def test_the_driver_runs_the_benches_of_make_bench() -> None:
    makefile = (DOC.parent.parent / "Makefile").read_text(encoding="utf-8")
    assert "bench/performance.py\n" in makefile
    for name, bench in BENCHES.items():
        assert (DOC.parent.parent / "bench" / bench.script).is_file(), name
        assert command_line(name, quick=False)[0] == f"bench/{bench.script}"
        if not bench.default:  # run by a target of its own
            assert f"bench/performance.py --only {name}\n" in makefile, name


@pytest.mark.parametrize("name", ["soak", "sim", "pathological"])
def test_a_replacement_keeps_everything_outside_the_markers(name: str) -> None:
    new = body("| a | b |\n|---|---|\n| 1 | 2 |\n", markdown=True, stamp="<sub>stamp</sub>")
    replaced = replace_section(SAMPLE, name, new)
    assert outside(replaced) == outside(SAMPLE)
    start, end = sections(replaced)[name]
    assert replaced[start:end] == new
    assert replace_section(replaced, name, new) == replaced  # running it again changes nothing
    others = {n: SAMPLE[s:e] for n, (s, e) in sections(SAMPLE).items() if n != name}
    assert {n: replaced[s:e] for n, (s, e) in sections(replaced).items() if n != name} == others


def test_text_output_goes_into_a_text_block() -> None:
    assert body("a  b\n1  2\n", markdown=False, stamp="S") == "```text\na  b\n1  2\n```\n\nS\n"


@pytest.mark.parametrize(
    "text",
    [
        "<!-- bench: soak -->\nopen\n",
        "<!-- /bench: soak -->\n",
        "<!-- bench: soak -->\n<!-- bench: sim -->\n<!-- /bench: sim -->\n<!-- /bench: soak -->\n",
        "<!-- bench: soak -->\n<!-- /bench: sim -->\n",
        "<!-- bench: soak -->\n<!-- /bench: soak -->\n<!-- bench: soak -->\n<!-- /bench: soak -->\n",
    ],
)
def test_a_broken_marker_is_refused(text: str) -> None:
    with pytest.raises(MarkerError):
        sections(text)


def test_a_bench_without_a_section_is_refused(tmp_path: Path) -> None:
    with pytest.raises(MarkerError):
        replace_section("no markers\n", "soak", "x\n")
