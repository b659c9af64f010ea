"""The language server's edit fuzzer of `make fuzz` (bench/lspfuzz.py), a short run: after each
random edit, the diagnostics the real server publishes for that version are those `gpp check`
finds in the same text."""

from __future__ import annotations

import asyncio

import pytest

from bench import lspfuzz


@pytest.mark.slow
def test_the_published_diagnostics_follow_random_edits_as_gpp_check_finds_them() -> None:
    report = asyncio.run(lspfuzz.fuzz(edits=80, seed=7))
    assert report.edits == 80
    assert report.diagnostics > 0  # the edits broke the programs: there was something to compare
    assert [(f.edit, f.what) for f in report.findings] == []


def test_a_random_edit_stays_inside_the_text() -> None:
    import random

    rnd = random.Random(3)
    text = "procedure main() { go(); }\n"
    for _ in range(500):
        start, end, new = lspfuzz.random_edit(text, rnd)
        assert 0 <= start <= end <= len(text)
        text = text[:start] + new + text[end:]
