"""A fixed corpus of programs, well-formed and broken, and a full dump of how each parses.

The dump holds everything `gpp.syntax.parser.parse` returns: every token (type, text,
offsets), every node of the tree with every field and its span (which the tree's equality
leaves out), and every diagnostic with its labels, notes, help and fix. Its digests, kept in
tests/golden/parse_fingerprints.json, pin the parser's results, so that a change meant only to
make parsing faster cannot change what it finds (tests/syntax/test_parse_fingerprints.py).

After a deliberate change of the parser's results (a new message, a new node field), write the
new digests with

    PYTHONPATH=. .venv/bin/python -m tests.support.parse_corpus --update

and say in the commit what changed and why.
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import hashlib
import json
import random
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from bench.fuzz import VOCABULARY, Generator, mutate, pieces
from bench.genprog import generate_program, nested_expression_program
from gpp.base.source import Source, Span

ROOT = Path(__file__).resolve().parents[2]

FINGERPRINTS = ROOT / "tests" / "golden" / "parse_fingerprints.json"
# Constructs the corpus writes by hand: the legacy forms, the platform model, lexical errors.
_HANDWRITTEN = [
    "symbol domain D = {a, b};\n?function f(D x) { return x; }\nprocedure main() { $x = 1; }\n",
    'action a(D x) {\nmapping: "/a" { x = x }\nsenses: f;\n}\nexog_function g(D x) { return 1; }\n',
    "symbol domain D = {a}\nfunction f() { if (true) return 1; else return 2; }\n",
    "component arm {\nstates: idle, busy;\nclocks: c;\ntransitions: idle -> busy resets c;\n}\n",
    "constraints {\nstart(a(*)) -> future[0, 5] end(a(*));\nstate(arm) == idle until[1,] true;\n}\n",
    'number fluent f() { initially: () = 1e999; }\nprocedure p() { x = "open\n}\n/* never closed',
    "procedure p() { x = 1 @ 2; y = é; _z = 3; x = 0x; }\nnumber function é() = 1\n",
    "procedure main() {\n    a = 1\n    b = 2;\n    if (a == 1 { c = 3; }\n}\n{ a = 1; }\n",
    "during (a()) { b(); } on_fail { c(); } on_fail { d(); }\nprocedure p() { during (a()) b(); on_cancel c(); }\n",
    "procedure p() { x = ((((((((1)))))))); y = - - -1; z = !!true; w = + 2; }\n",
    "action a() {\neffect: x = 1;\nprecondition: true\neffect: y = 2;\n}\n",
    "procedure p() { x = " + "(" * 2100 + "1" + ")" * 2100 + "; }\n",
    "number function f() = " + " + ".join(["1"] * 2100) + "\nprocedure q() { x = 1; }\n",
]


def corpus() -> Iterator[tuple[str, str]]:
    """(name, text) of every program of the corpus, always the same ones."""
    for lines in (40, 200, 1000):
        yield f"genprog-{lines}", generate_program(lines, seed=lines)
    for depth in (5, 60):
        yield f"nested-{depth}", nested_expression_program(depth)
    for k, text in enumerate(_HANDWRITTEN):
        yield f"handwritten-{k}", text
    base = pieces(generate_program(120, seed=7))
    for k in range(120):
        rnd = random.Random(k)
        yield f"mutated-{k}", mutate(base, rnd, rnd.choice((1, 1, 2, 3, 5, 12)))
    for k in range(120):
        rnd = random.Random(1000 + k)
        text = Generator(rnd).program()
        if k % 3 == 0:
            text = mutate(pieces(text), rnd, rnd.randint(1, 4))
        yield f"generated-{k}", text
    for k in range(60):
        rnd = random.Random(2000 + k)
        words = [rnd.choice(VOCABULARY) for _ in range(rnd.randint(0, 60))]
        yield f"soup-{k}", rnd.choice((" ", "", "\n")).join(words)


def _plain(value: Any) -> Any:
    """A value of the tree or of a diagnostic as JSON data, with every field (spans included)."""
    if isinstance(value, Span):
        return [value.start, value.end]
    if isinstance(value, enum.Enum):
        return value.value
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        out: dict[str, Any] = {"": type(value).__name__}
        for f in dataclasses.fields(value):
            out[f.name] = _plain(getattr(value, f.name))
        return out
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, float):
        return repr(value)
    return value


def dump(text: str, parse: Callable[[Source], Any]) -> dict[str, Any]:
    """Everything `parse` returns for `text`, as JSON data."""
    result = parse(Source(text, "corpus.gpp"))
    return {
        "tokens": [[t.type, t.value, t.start, t.end] for t in result.tokens],
        "program": _plain(result.program),
        "diagnostics": [_plain(d) for d in result.diagnostics],
    }


def digest(data: object) -> str:
    return hashlib.sha256(json.dumps(data, sort_keys=True, ensure_ascii=True).encode()).hexdigest()[:24]


def dumps(parse: Callable[[Source], Any]) -> dict[str, tuple[str, dict[str, Any]]]:
    """Each program's text and dump, by name."""
    return {name: (text, dump(text, parse)) for name, text in corpus()}


def fingerprints(dumped: dict[str, tuple[str, dict[str, Any]]]) -> dict[str, str]:
    """The digest of each program's text and of its dump, by name."""
    return {name: digest([digest(text), data]) for name, (text, data) in dumped.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description="Write the parse fingerprints of the corpus.")
    ap.add_argument("--update", action="store_true", help="write tests/golden/parse_fingerprints.json")
    args = ap.parse_args()
    from gpp.syntax.parser import parse

    found = fingerprints(dumps(parse))
    if args.update:
        FINGERPRINTS.write_text(json.dumps(found, indent=1, sort_keys=True) + "\n", encoding="utf-8")
        print(f"wrote {len(found)} fingerprints to {FINGERPRINTS.relative_to(ROOT)}")
    else:
        print(json.dumps(found, indent=1, sort_keys=True))


if __name__ == "__main__":
    main()
