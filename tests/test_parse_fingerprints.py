"""The parser's results on a fixed corpus stay those pinned in tests/golden/parse_fingerprints.json.

Every token, node, span and diagnostic (code, message, labels, help, fix) of about 300
programs, well-formed and broken (see tests/parse_corpus.py), is compared through a digest per
program: a faster parser must find exactly what the parser before it found.
"""

from __future__ import annotations

import json

from parse_corpus import FINGERPRINTS, corpus, digest, dump, fingerprints

from gpp.syntax.parser import parse


def test_the_corpus_has_well_formed_and_broken_programs_of_every_kind() -> None:
    codes: set[str] = set()
    clean = 0
    for _, text in corpus():
        found = {d["code"] for d in dump(text, parse)["diagnostics"]}
        codes |= found
        clean += not found
    assert clean >= 40
    # lexical errors, syntax errors, end of file, legacy forms, too deep, a section twice
    assert {"E0001", "E0002", "E0004", "E0005", "E0010", "E0011", "E0012", "E0014", "E0020", "E0040"} <= codes


def test_every_program_of_the_corpus_parses_as_pinned() -> None:
    pinned: dict[str, str] = json.loads(FINGERPRINTS.read_text(encoding="utf-8"))
    found = fingerprints(parse)
    assert sorted(found) == sorted(pinned)
    changed = [name for name in found if found[name] != pinned[name]]
    assert changed == [], f"parsed differently (see tests/parse_corpus.py): {changed[:20]}"


def test_the_digest_sees_a_changed_span() -> None:
    text = "procedure p() { x = 1; }\n"
    data = dump(text, parse)
    assert digest(data) == digest(dump(text, parse))
    data["program"]["declarations"][0]["name"]["span"][1] += 1
    assert digest(data) != digest(dump(text, parse))
