"""Fuzzing `gpp check`: many random inputs, any internal error written out as a reproducer.

Run: .venv/bin/python bench/fuzz.py [--count N] [--seconds S] [--seed K] [--out DIR] [--only KIND]
(`make fuzz` runs 100,000 inputs; the test suite runs a few seconds' worth.)

Five fuzzers take turns (`--only` runs one of them):

* mutation: a program of examples/ or tests/programs/ with 1 to 25 random token-level edits
  (delete, duplicate, swap, replace by a keyword or punctuation, insert odd characters, cut);
* generation: a random program from a small generator of golog++ declarations, statements and
  expressions (nested a few levels), sometimes mutated too;
* soup: keywords, punctuation and odd Unicode in random order;
* bytes: random bytes in a file on disk, read through the loader like `gpp check FILE`;
* formatter: a program of the repository laid out anew, with comments and `// gpp: allow`
  suppressions at random places (bench/fmtfuzz.py); formatted, it must parse to the same
  tree, keep its comments, directives, line endings and byte-order mark, be formatted already,
  and give the same warnings (a suppression stays with what it suppressed).

Each input of the first four is checked with lints in-process and its diagnostics rendered as text, JSON and
SARIF. An internal error is any exception, or a diagnostic that is malformed (an unregistered
code, an empty message, a span outside its source). Each one is written to DIR (default
fuzz-findings/) as the input that caused it plus a .txt with the traceback, at most three per
distinct place of failure; a formatter mutant that breaks a property is a finding too, its
.txt saying which. The report gives inputs/s, the slowest inputs, and the findings.
Exit code 1 when an internal error was found, else 0.
"""

from __future__ import annotations

import argparse
import hashlib
import random
import sys
import tempfile
import time
import traceback
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from gpp.base.diagnostics import Diagnostic
from gpp.base.source import Source, Span
from gpp.check import check_program, check_text
from gpp.codes import CODES
from gpp.report.sarif import render_sarif
from gpp.report.text import render_json, render_text
from gpp.syntax.lexer import KEYWORDS, PLATFORM_KEYWORDS, PUNCTUATION, SECTION_WORDS, tokenize

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # run as a script: bench.fmtfuzz and the tests' programs

from bench.fmtfuzz import FormatterFuzzer, Mutant, formatting_problems  # noqa: E402

KINDS = ("mutation", "generation", "soup", "bytes", "formatter")
# A folder that does not exist: `#include`s in fuzzed text resolve there (nothing) or in stdlib/.
FUZZ_PATH = Path("/nonexistent-gpp-fuzz-dir/fuzz.gpp")
ODD = "(){}[];,.:=<>!&|+-*/%\\\"'#_aZ09 \t\n\r\x00\x0bé€\u2028\ufeff\u200b日🤖"
VOCABULARY = sorted(
    {
        *KEYWORDS,
        *PLATFORM_KEYWORDS,
        *(f"{w}:" for w in SECTION_WORDS),
        *PUNCTUATION,
        *("x", "main", "_hidden", "0", "1.5e3", ".5", "1e999", '"text"', '"unterminated', '"esc\\"aped"'),
        *("/*", "*/"),
        *("// comment\n", '#include "missing.gpp"', '#include "stdlib.gpp"', "#include", "@", "$", "\n"),
        *("list[number]", "()", "{}", "\x00"),
    }
)


# ---------------------------------------------------------------- the fuzzers


def pieces(text: str) -> list[str]:
    """The text cut into tokens, each with the whitespace and comments before it."""
    tokens, _ = tokenize(Source(text, "x.gpp"))
    out: list[str] = []
    last = 0
    for t in tokens:
        out.append(text[last : t.end])
        last = t.end
    out.append(text[last:])
    return out


def mutate(parts: list[str], rnd: random.Random, steps: int) -> str:
    """Apply `steps` random token-level mutations; returns the new text."""
    parts = list(parts)
    for _ in range(steps):
        op = rnd.choice(("delete", "duplicate", "swap", "replace", "insert", "truncate"))
        if not parts:
            parts.append(rnd.choice(VOCABULARY))
            continue
        i = rnd.randrange(len(parts))
        if op == "delete":
            del parts[i]
        elif op == "duplicate":
            parts.insert(i, parts[i])
        elif op == "swap" and i + 1 < len(parts):
            parts[i], parts[i + 1] = parts[i + 1], parts[i]
        elif op == "replace":
            parts[i] = rnd.choice(("", " ", "\n")) + rnd.choice(VOCABULARY)
        elif op == "insert":
            parts.insert(i, "".join(rnd.choice(ODD) for _ in range(rnd.randint(1, 6))))
        elif op == "truncate":
            text = "".join(parts)
            return text[: rnd.randrange(len(text) + 1)]
    return "".join(parts)


class Generator:
    """Random golog++ programs: mostly well-formed, with names that may or may not resolve."""

    TYPES = ("number", "bool", "string", "D", "P", "list[number]", "E")
    BINARY = ("+", "-", "*", "/", "%", "**", "==", "!=", "<", "<=", ">", ">=", "&", "|", "->", "<=>")

    def __init__(self, rnd: random.Random) -> None:
        self.rnd = rnd

    def name(self) -> str:
        return self.rnd.choice(("x", "y", "n", "f", "g", "a", "go", "p", "d1", "d2", "main", "undeclared"))

    def expr(self, depth: int) -> str:
        r = self.rnd
        if depth <= 0 or r.random() < 0.25:
            return r.choice(("1", "0", "2.5", "true", "false", "null", '"s"', "d1", "x", "n()", "f(1)", "p.x"))
        kind = r.randrange(12)
        sub = lambda: self.expr(depth - 1)  # noqa: E731
        if kind == 0:
            return f"{sub()} {r.choice(self.BINARY)} {sub()}"
        if kind == 1:
            return r.choice(("-", "!")) + sub()
        if kind == 2:
            return f"({sub()})"
        if kind == 3:
            return f"{self.name()}({', '.join(sub() for _ in range(r.randint(0, 3)))})"
        if kind == 4:
            return f"if ({sub()}) {sub()} else {sub()}"
        if kind == 5:
            return f"{r.choice(('exists', 'forall'))} ({r.choice(self.TYPES)} {self.name()}) {sub()}"
        if kind == 6:
            return f"{sub()}.{r.choice(('x', 'y', 'z'))}"
        if kind == 7:
            return f"{sub()}[{sub()}]"
        if kind == 8:
            return f"list[number] [{', '.join(sub() for _ in range(r.randint(0, 3)))}]"
        if kind == 9:
            return f"P {{ x = {sub()}, y = {sub()} }}"
        if kind == 10:
            return r.choice(("length", "to_string", "pop_front", "pop_back")) + f"({sub()})"
        return f"{r.choice(('n', 'l', 's'))}() {r.choice(('==', '+', '&'))} {sub()}"

    def stmt(self, depth: int) -> str:
        r = self.rnd
        e = lambda: self.expr(2)  # noqa: E731
        if depth <= 0 or r.random() < 0.3:
            return r.choice((f"{self.name()}({e()});", f"n() = {e()};", f"test({e()});", "go();", "a(1);"))
        s = lambda: self.stmt(depth - 1)  # noqa: E731
        kind = r.randrange(11)
        if kind == 0:
            return f"if ({e()}) {s()}" + (f" else {s()}" if r.random() < 0.5 else "")
        if kind == 1:
            return f"while ({e()}) {s()}"
        if kind == 2:
            return "{ " + " ".join(s() for _ in range(r.randint(0, 3))) + " }"
        if kind == 3:
            return "choose { " + " ".join(s() for _ in range(r.randint(1, 3))) + " }"
        if kind == 4:
            return (
                f"pick ({r.choice(self.TYPES)} {self.name()}"
                + (" in {d1, d2}" if r.random() < 0.5 else "")
                + f") {s()}"
            )
        if kind == 5:
            return "concurrent { " + " ".join(s() for _ in range(r.randint(1, 3))) + " }"
        if kind == 6:
            return f"solve({r.randint(0, 4)}, {e()}) {s()}"
        if kind == 7:
            return f"search {s()}"
        if kind == 8:
            return f"during (go()) {s()} on_fail {s()} on_cancel {s()}"
        if kind == 9:
            return r.choice(("start", "end", "cancel", "finish", "fail")) + "(go());"
        return r.choice(("push_back", "push_front")) + f"(l(), {e()});"

    def decl(self) -> str:
        r = self.rnd
        kind = r.randrange(10)
        t = r.choice(self.TYPES)
        if kind == 0:
            return "symbol domain D = {d1, d2}" + r.choice(("", " | {d3}", " \\ {d1}"))
        if kind == 1:
            return "compound P { number x, number y }"
        if kind == 2:
            name = r.choice(("n", "l", "s", "b"))
            return f"{t} fluent {name}({r.choice(('', 'D d'))}) {{ initially: () = {self.expr(2)}; }}"
        if kind == 3:
            return (
                f"action {r.choice(('go', 'a'))}({r.choice(('', 'number k', 'D d'))}) {{ precondition: {self.expr(2)} "
                f"effect: n() = {self.expr(2)}; }}"
            )
        if kind == 4:
            return f"{t} function {r.choice(('f', 'g'))}({r.choice(('', 'number k'))}) = {self.expr(3)}"
        if kind == 5:
            return (
                f"procedure {r.choice(('p', 'main'))}() {{ {' '.join(self.stmt(3) for _ in range(r.randint(1, 4)))} }}"
            )
        if kind == 6:
            return f"exog_action e({r.choice(('', 'number k'))}) {{ effect: n() = 1; }}"
        if kind == 7:
            return f"{t} exog_function s(string topic);"
        if kind == 8:
            return r.choice(('#include "missing.gpp"', "symbol domain E = D", "D domain E = {d1}"))
        return "bool function goal() = " + self.expr(4)

    def program(self) -> str:
        decls = [self.decl() for _ in range(self.rnd.randint(1, 12))]
        return "\n".join(decls) + "\n"


@dataclass
class Fuzzers:
    rnd: random.Random
    programs: dict[str, list[str]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        paths = sorted([*ROOT.glob("examples/*.gpp"), *ROOT.glob("tests/programs/*.gpp")])
        self.programs = {p.name: pieces(p.read_text(encoding="utf-8")) for p in paths}
        self.names = sorted(self.programs)

    def mutation(self) -> str:
        steps = self.rnd.choice((1, 1, 2, 3, 4, 8, 25))
        return mutate(self.programs[self.rnd.choice(self.names)], self.rnd, steps)

    def generation(self) -> str:
        text = Generator(self.rnd).program()
        if self.rnd.random() < 0.3:
            text = mutate(pieces(text), self.rnd, self.rnd.randint(1, 4))
        return text

    def soup(self) -> str:
        words = [
            self.rnd.choice(VOCABULARY) if self.rnd.random() < 0.8 else "".join(self.rnd.sample(ODD, 2))
            for _ in range(self.rnd.randint(0, 80))
        ]
        return self.rnd.choice((" ", "", "\n")).join(words)

    def bytes(self) -> bytes:
        n = self.rnd.randint(0, 400)
        if self.rnd.random() < 0.5:
            return bytes(self.rnd.randrange(256) for _ in range(n))
        text = self.mutation()[:n].encode("utf-8")  # text with a bad byte or two
        k = self.rnd.randint(1, 2)
        spots = sorted(self.rnd.randrange(len(text) + 1) for _ in range(k))
        for spot in reversed(spots):
            text = text[:spot] + bytes([self.rnd.choice((0, 0x80, 0xC3, 0xE9, 0xFF))]) + text[spot:]
        return text


# ---------------------------------------------------------------- the property


class Malformed(AssertionError):
    pass


def check_span(span: Span) -> None:
    if not 0 <= span.start <= span.end <= len(span.source.text):
        raise Malformed(f"span {span.start}..{span.end} outside a text of {len(span.source.text)} characters")


def check_diagnostic(d: Diagnostic) -> None:
    if d.code not in CODES:
        raise Malformed(f"unregistered code {d.code!r}: {d.message}")
    if not d.message.strip():
        raise Malformed(f"{d.code} without a message")
    check_span(d.span)
    for label in d.secondary:
        check_span(label.span)
    if d.fix is not None:
        for edit in d.fix.edits:
            check_span(edit.span)


def check_and_render(diagnostics: list[Diagnostic], machine_formats: bool) -> None:
    """Check every diagnostic and render them as text (and, when asked, as JSON and SARIF,
    which are slower to write and simpler: every eighth input)."""
    for d in diagnostics:
        check_diagnostic(d)
    render_text(diagnostics, max_per_code=50)
    if machine_formats:
        render_json(diagnostics)
        render_sarif(diagnostics)


class FormattingProblem(AssertionError):
    """A formatter mutant whose formatting breaks a property (bench/fmtfuzz.py)."""


def check_formatting(mutant: Mutant) -> None:
    problems = formatting_problems(mutant.text, mutant.path)
    if problems:
        raise FormattingProblem(f"{mutant.path.name}: " + "; ".join(problems))


# ---------------------------------------------------------------- the run


@dataclass
class Finding:
    where: str
    kind: str
    files: list[Path]
    count: int = 1


def place_of(e: BaseException) -> str:
    """The exception type and innermost gpp frame: the identity of a bug."""
    if isinstance(e, FormattingProblem):
        return "formatting: " + str(e).partition(": ")[2].partition(":")[0]
    frames = [f for f in traceback.extract_tb(e.__traceback__) if "/gpp/" in f.filename]
    frame = frames[-1] if frames else None
    where = f"{Path(frame.filename).name}:{frame.name}" if frame else "?"
    return f"{type(e).__name__} in {where}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--count", type=int, default=100_000, help="inputs to try (default 100,000)")
    ap.add_argument("--seconds", type=float, help="stop after this many seconds, even before --count")
    ap.add_argument("--seed", type=int, default=1, help="random seed (the same seed gives the same inputs)")
    ap.add_argument("--out", type=Path, default=Path("fuzz-findings"), help="folder for reproducers")
    ap.add_argument("--only", choices=KINDS, help="run only this fuzzer")
    args = ap.parse_args(argv)
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))  # as the gpp command does
    rnd = random.Random(args.seed)
    fuzzers = Fuzzers(rnd)
    formatter = FormatterFuzzer()
    kinds: list[tuple[str, Callable[[], str | bytes | Mutant]]] = [
        ("mutation", fuzzers.mutation),
        ("mutation", fuzzers.mutation),
        ("generation", fuzzers.generation),
        ("generation", fuzzers.generation),
        ("soup", fuzzers.soup),
        ("bytes", fuzzers.bytes),
        ("formatter", lambda: formatter.mutant(rnd)),
    ]
    if args.only:
        kinds = [(kind, make) for kind, make in kinds if kind == args.only][:1]
    findings: dict[str, Finding] = {}
    counts: Counter[str] = Counter()
    codes: Counter[str] = Counter()
    slowest: list[tuple[float, str, str | bytes | Mutant]] = []
    started = time.perf_counter()
    done = 0
    with tempfile.TemporaryDirectory() as folder:
        disk = Path(folder) / "fuzz.gpp"
        for done in range(1, args.count + 1):
            kind, make = kinds[done % len(kinds)]
            data = make()
            counts[kind] += 1
            t0 = time.perf_counter()
            try:
                if isinstance(data, Mutant):
                    check_formatting(data)
                elif isinstance(data, bytes):
                    disk.write_bytes(data)
                    diagnostics = check_program(disk).diagnostics
                else:
                    diagnostics = check_text(data, FUZZ_PATH).diagnostics
                if not isinstance(data, Mutant):
                    check_and_render(diagnostics, done % 8 == 0)
                    codes.update(d.code for d in diagnostics)
            except Exception as e:  # an internal error: what the fuzzer looks for
                where = place_of(e)
                finding = findings.get(where)
                if finding is None:
                    finding = findings[where] = Finding(where, kind, [])
                else:
                    finding.count += 1
                if len(finding.files) < 3:
                    finding.files.append(write_reproducer(args.out, data, e))
            seconds = time.perf_counter() - t0
            slowest.append((seconds, kind, data))
            if len(slowest) > 20:
                slowest.sort(key=lambda s: -s[0])
                del slowest[5:]
            if args.seconds is not None and time.perf_counter() - started > args.seconds:
                break
            if done % 10_000 == 0:
                elapsed = time.perf_counter() - started
                print(f"  {done:,} inputs, {done / elapsed:,.0f}/s, {len(findings)} internal errors", flush=True)
    elapsed = time.perf_counter() - started
    slowest.sort(key=lambda s: -s[0])
    print(f"{done:,} inputs in {elapsed:.1f} s: {done / elapsed:,.0f} inputs/s (seed {args.seed})")
    print("  by fuzzer: " + ", ".join(f"{k} {n:,}" for k, n in sorted(counts.items())))
    print("  most frequent codes: " + ", ".join(f"{c} {n:,}" for c, n in codes.most_common(8)))
    for seconds, kind, data in slowest[:3]:
        path = write_input(args.out, "slow", data) if seconds > 1.0 else None
        raw = data.text if isinstance(data, Mutant) else data
        shown = path if path else repr(raw[:60]) + ("..." if len(raw) > 60 else "")
        print(f"  slow: {seconds:.3f} s, {kind}, {len(raw):,} characters: {shown}")
    if not findings:
        print("no internal errors")
        return 0
    print(f"{sum(f.count for f in findings.values())} inputs hit {len(findings)} internal errors:")
    for f in findings.values():
        print(
            f"  {f.where}: {f.count} inputs (first from the {f.kind} fuzzer), reproducers: "
            + ", ".join(map(str, f.files))
        )
    return 1


def write_input(out: Path, prefix: str, data: str | bytes | Mutant) -> Path:
    if isinstance(data, Mutant):
        data = data.text
    raw = data.encode("utf-8", errors="surrogatepass") if isinstance(data, str) else data
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{prefix}-{hashlib.sha256(raw).hexdigest()[:12]}.gpp"
    path.write_bytes(raw)
    return path


def write_reproducer(out: Path, data: str | bytes | Mutant, e: BaseException) -> Path:
    """The input as a file (`gpp check FILE` or, for a formatter mutant, `gpp fmt --diff FILE`
    beside the program it was made from reproduces it) and the traceback or problem beside it."""
    path = write_input(out, "crash", data)
    if isinstance(data, Mutant):
        why = f"a mutant of {data.path}: {e}\n"
    else:
        why = "".join(traceback.format_exception(e))
    path.with_suffix(".txt").write_text(why, encoding="utf-8")
    return path


if __name__ == "__main__":
    sys.exit(main())
