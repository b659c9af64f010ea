"""The formatter's mutation fuzzer, one of the fuzzers of `make fuzz` (bench/fuzz.py).

A mutant is a program of examples/, stdlib/, tests/programs/, of the lint tests (one per lint)
or of the benchmark generator, laid out anew at random (line breaks and spaces between tokens
joined or split), with comments of every kind and `// gpp: allow` suppressions of the three
kinds (at the end of a line, on a line of their own, `allow-file`) sprinkled between random
tokens, the suppressions allowing mostly the lints the program has; sometimes with `\r\n` line
endings or a byte-order mark. Every mutant parses.

The properties (`formatting_problems`): the formatted text parses to the same tree; it keeps
every comment, in order, and the directives; formatting it again changes nothing; its line
endings and byte-order mark are the input's; and `gpp check` reports the same warnings before
and after, each identified by its code, its message and the number of tokens before it
(not by line, which formatting changes): a suppression stays with what it suppressed. The one
exception is documented (docs/format.md): a suppression at the end of a line of nothing but
parentheses, which the formatter may drop; such mutants are not compared by their warnings.
"""

from __future__ import annotations

import random
import re
from bisect import bisect_left
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from bench.genprog import generate_program
from gpp.base.diagnostics import Diagnostic, Severity
from gpp.base.source import BOM
from gpp.check import check_text
from gpp.codes import CODES
from gpp.syntax.directives import SUPPRESSION, directives
from gpp.syntax.format import format_text
from gpp.syntax.lexer import Token
from gpp.syntax.parser import parse_text
from tests.support.lint_triggers import TRIGGERS

ROOT = Path(__file__).resolve().parent.parent
LINTS = sorted(info.code for info in CODES.values() if info.is_lint)

# Comments and line breaks that `sprinkle` inserts between tokens; {} is a number.
COMMENT_KINDS = (
    "// c{}\n",
    " // c{}\n",
    "/* c{} */",
    " /* c{} */ ",
    "\n/* c{}\n   more */\n",
    "\n\n// c{}\n\n",
    "\n// c{}\n",
    "/*c{}*/",
    "\n",
    "\n\n",
)
# Suppressions, by kind; {} is a list of codes.
SUPPRESSION_KINDS = (
    " // gpp: allow {}\n",  # the end of a line
    "  //gpp: allow {} -- a reason\n",
    "\n// gpp: allow {}\n",  # a line of its own: the next line, or the declaration below
    "\n\n// gpp: allow {}\n",
    "\n// gpp: allow-file {}\n",
)
# What `relayout` puts between two tokens.
SPACES = (" ", " ", "\n", "\n", "\n\n", "  ", "\n    ", "\t")
COMMENT = re.compile(r"//[^\n]*|/\*[\s\S]*?\*/")


def sources() -> list[tuple[Path, str]]:
    """The programs the mutants are made from: every program of the repository that parses,
    the programs that trigger each lint (tests/support/lint_triggers.py), and two of the
    benchmark generator's; each with the path it is checked at."""
    paths = sorted([*ROOT.glob("examples/**/*.gpp"), *ROOT.glob("stdlib/**/*.gpp"), *ROOT.glob("tests/programs/*.gpp")])
    found = [(path, path.read_text(encoding="utf-8")) for path in paths]
    found += [(ROOT / "tests" / "programs" / f"lint_{code}.gpp", text) for code, text in TRIGGERS.items()]
    found += [(ROOT / "tests" / "programs" / f"generated_{n}.gpp", generate_program(40, seed=n)) for n in (1, 2)]
    return [(path, text) for path, text in found if parse_text(text).ok]


def _cuts(tokens: Sequence[Token], rnd: random.Random, count: int) -> list[int]:
    return sorted(rnd.sample(range(len(tokens) + 1), min(count, len(tokens) + 1)))


def _insert(text: str, tokens: Sequence[Token], cuts: list[int], pieces: Sequence[str]) -> str:
    out: list[str] = []
    previous = 0
    for cut, piece in zip(cuts, pieces, strict=True):
        at = tokens[cut].start if cut < len(tokens) else len(text)
        out += [text[previous:at], piece]
        previous = at
    out.append(text[previous:])
    return "".join(out)


def sprinkle(text: str, rnd: random.Random, count: int) -> str:
    """`text` with comments (and line breaks) inserted at `count` random token boundaries."""
    tokens = parse_text(text).tokens
    cuts = _cuts(tokens, rnd, count)
    return _insert(text, tokens, cuts, [rnd.choice(COMMENT_KINDS).format(i) for i in range(len(cuts))])


def sprinkle_suppressions(text: str, rnd: random.Random, count: int, codes: Sequence[str]) -> str:
    """`text` with `count` suppressions of random kinds at random token boundaries, each
    allowing one or two of `codes` (the lints the program has, mostly) or any lint."""
    tokens = parse_text(text).tokens
    cuts = _cuts(tokens, rnd, count)
    pieces: list[str] = []
    for _ in cuts:
        allowed = [rnd.choice(codes) if codes and rnd.random() < 0.8 else rnd.choice(LINTS)]
        if rnd.random() < 0.2:
            allowed.append(rnd.choice(LINTS))
        pieces.append(rnd.choice(SUPPRESSION_KINDS).format(", ".join(allowed)))
    return _insert(text, tokens, cuts, pieces)


def relayout(text: str, rnd: random.Random, share: float) -> str:
    """`text` with the white space between a `share` of its pairs of tokens replaced by a
    random space or line break (gaps with comments are left alone)."""
    tokens = parse_text(text).tokens
    out: list[str] = []
    previous = 0
    for t in tokens:
        gap = text[previous : t.start]
        if previous and not gap.strip() and rnd.random() < share:
            gap = rnd.choice(SPACES)
        out += [gap, text[t.start : t.end]]
        previous = t.end
    out.append(text[previous:])
    return "".join(out)


def lint_codes(text: str, path: Path) -> list[str]:
    """The codes of the warnings `gpp check` reports on `text`."""
    return sorted({d.code for d in check_text(text, path).diagnostics if d.severity is Severity.WARNING})


@dataclass(frozen=True)
class Mutant:
    text: str
    path: Path  # where it is checked (its #includes resolve from there)


class FormatterFuzzer:
    """Formatter mutants of the repository's programs (`sources`)."""

    def __init__(self) -> None:
        self.sources = sources()
        self.codes = {path: lint_codes(text, path) for path, text in self.sources}

    def mutant(self, rnd: random.Random) -> Mutant:
        path, text = rnd.choice(self.sources)
        if rnd.random() < 0.7:
            text = relayout(text, rnd, rnd.choice((0.05, 0.2, 0.5, 1.0)))
        if rnd.random() < 0.6:
            text = sprinkle(text, rnd, rnd.randint(1, 30))
        text = sprinkle_suppressions(text, rnd, rnd.randint(1, 12), self.codes[path])
        if rnd.random() < 0.15:
            text = text.replace("\n", "\r\n")
        if rnd.random() < 0.05:
            text = BOM + text
        return Mutant(text, path)


# ---------------------------------------------------------------- the properties


def comments(text: str) -> list[str]:
    """The comments of a program (between its tokens), whitespace normalised."""
    found: list[str] = []
    previous = 0
    for token in [*parse_text(text).tokens, None]:
        end = token.start if token is not None else len(text)
        found.extend(" ".join(m.group().split()) for m in COMMENT.finditer(text, previous, end))
        if token is not None:
            previous = token.end
    return found


_PARENS = frozenset({"LPAR", "RPAR"})
_QUOTED = re.compile(r"`[^`]*`")


def warnings(text: str, path: Path) -> Counter[tuple[str, str, int]]:
    """The warnings of `gpp check` on `text`, each as its code, its message (without the code
    it quotes, which may have other spaces and comments) and the number of tokens before it
    (parentheses, which formatting may drop, not counted)."""
    starts = [t.start for t in parse_text(text.removeprefix(BOM)).tokens if t.type not in _PARENS]
    found: Counter[tuple[str, str, int]] = Counter()
    for d in check_text(text.removeprefix(BOM), path).diagnostics:
        if d.severity is Severity.WARNING and d.span.source.identity == str(path):
            message = _QUOTED.sub("`...`", d.message)
            found[(d.code, message, _before(starts, d))] += 1
    return found


def _before(starts: list[int], d: Diagnostic) -> int:
    return bisect_left(starts, d.span.start)


def _line_ending(text: str) -> str:
    at = text.find("\n")
    return "\r\n" if at > 0 and text[at - 1] == "\r" else "\n"


def _suppression_after_parentheses_only(text: str) -> bool:
    """Whether a suppression ends a line whose code is only parentheses: the formatter may drop
    them (`((x))` is `(x)`), and then no line can keep the code it covered (docs/format.md)."""
    tokens = parse_text(text).tokens
    starts = [t.start for t in tokens]
    for m in COMMENT.finditer(text):
        if SUPPRESSION.match(m.group()):
            line_start = text.rfind("\n", 0, m.start()) + 1
            on_line = tokens[bisect_left(starts, line_start) : bisect_left(starts, m.start())]
            if on_line and all(t.type in _PARENS for t in on_line):
                return True
    return False


def formatting_problems(text: str, path: Path, lints: bool = True) -> list[str]:
    """What formatting `text` (which parses) breaks; nothing when all is well."""
    formatted = format_text(text, str(path))
    problems: list[str] = []
    before, after = parse_text(text.removeprefix(BOM)), parse_text(formatted.removeprefix(BOM))
    if not after.ok:
        return ["the formatted text does not parse: " + "; ".join(d.message for d in after.diagnostics)]
    if after.program != before.program:
        problems.append("the formatted text parses to another tree")
    if comments(formatted.removeprefix(BOM)) != comments(text.removeprefix(BOM)):
        problems.append("comments lost, added or reordered")
    if directives(formatted.removeprefix(BOM)) != directives(text.removeprefix(BOM)):
        problems.append("directives changed")
    again = format_text(formatted, str(path))
    if again != formatted:
        problems.append("formatting is not idempotent")
    if text.startswith(BOM) != formatted.startswith(BOM):
        problems.append("the byte-order mark was not kept")
    if formatted and text.strip() and _line_ending(formatted) != _line_ending(text):
        problems.append("the line endings changed")
    if lints and not _suppression_after_parentheses_only(text.removeprefix(BOM)):
        old, new = warnings(text, path), warnings(formatted, path)
        if old != new:
            lost = sorted((old - new).elements())
            gained = sorted((new - old).elements())
            problems.append(f"the warnings changed: lost {lost}, gained {gained}")
    return problems
