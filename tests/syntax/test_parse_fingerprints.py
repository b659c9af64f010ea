"""The parser's results on a fixed corpus stay those pinned in tests/golden/parse_fingerprints.json.

Every token, node, span and diagnostic (code, message, labels, help, fix) of about 300
programs, well-formed and broken (see tests/support/parse_corpus.py), is compared through a
digest per program: a faster parser must find exactly what the parser before it found.
"""

from __future__ import annotations

import dataclasses
import functools
import json
from typing import Any

import pytest

from gpp.syntax import ast
from gpp.syntax.fast import fast_constructor
from gpp.syntax.parser import parse
from tests.support.parse_corpus import FINGERPRINTS, digest, dump, dumps, fingerprints


@functools.cache
def parsed() -> dict[str, tuple[str, dict[str, Any]]]:
    return dumps(parse)


@pytest.mark.slow
def test_the_corpus_has_well_formed_and_broken_programs_of_every_kind() -> None:
    codes: set[str] = set()
    clean = 0
    for _, data in parsed().values():
        found = {d["code"] for d in data["diagnostics"]}
        codes |= found
        clean += not found
    assert clean >= 40
    # lexical errors, syntax errors, end of file, legacy forms, too deep, a section twice
    assert {"E0001", "E0002", "E0004", "E0005", "E0010", "E0011", "E0012", "E0014", "E0020", "E0040"} <= codes


@pytest.mark.slow
def test_every_program_of_the_corpus_parses_as_pinned() -> None:
    pinned: dict[str, str] = json.loads(FINGERPRINTS.read_text(encoding="utf-8"))
    found = fingerprints(parsed())
    assert sorted(found) == sorted(pinned)
    changed = [name for name in found if found[name] != pinned[name]]
    assert changed == [], f"parsed differently (see tests/support/parse_corpus.py): {changed[:20]}"


def test_the_digest_sees_a_changed_span() -> None:
    text = "procedure p() { x = 1; }\n"
    data = dump(text, parse)
    assert digest(data) == digest(dump(text, parse))
    data["program"]["declarations"][0]["name"]["span"][1] += 1
    assert digest(data) != digest(dump(text, parse))


NODE_CLASSES = sorted(
    (c for c in vars(ast).values() if isinstance(c, type) and issubclass(c, ast.Node) and dataclasses.is_dataclass(c)),
    key=lambda c: c.__name__,
)


@pytest.mark.parametrize("cls", NODE_CLASSES, ids=lambda c: c.__name__)
def test_a_fast_constructor_makes_the_node_the_dataclass_makes(cls: type[ast.Node]) -> None:
    make = fast_constructor(cls)
    fields = dataclasses.fields(cls)
    given = {f.name: f"value of {f.name}" for f in fields}
    required = {f.name: f"value of {f.name}" for f in fields if f.default is dataclasses.MISSING}
    for kwargs in (given, required):
        fast, slow = make(**kwargs), cls(**kwargs)
        assert type(fast) is cls
        assert [getattr(fast, f.name) for f in fields] == [getattr(slow, f.name) for f in fields]
    with pytest.raises(TypeError):
        make(**required, unknown=1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(make(**required), fields[0].name, None)
