"""Parse speed of gpp's front end: throughput for growing programs and growing nesting depth.

Run: .venv/bin/python bench/parse_speed.py [--quick] [--markdown]

Prints lines/s and the per-line cost relative to the smallest program (1.00 means perfectly
linear), and the same for nesting depth per token. For comparison it also times lark's own
LALR driver building a parse tree with positions from the same tokens (no AST), which is
what a plain lark front end would cost.
"""

from __future__ import annotations

import argparse
import gc
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program, nested_expression_program

from gpp.base.source import Source
from gpp.check import check_text
from gpp.syntax.lexer import tokenize
from gpp.syntax.parser import parse


def best_of(n: int, fn: Callable[[Source], object], source: Source) -> float:
    best = float("inf")
    for _ in range(n):
        t0 = time.perf_counter()
        fn(source)
        best = min(best, time.perf_counter() - t0)
    return best


def time_check(source: Source, runs: int, lint: bool) -> float:
    """Best time of `gpp check` (parse, resolve, type check, and lints if asked) in-process."""
    best = float("inf")
    for _ in range(runs):
        t0 = time.perf_counter()
        result = check_text(source.text, Path(source.path), lint=lint)
        best = min(best, time.perf_counter() - t0)
        assert not result.errors, result.diagnostics[:3]
    return best


def lark_baseline() -> Callable[[Source], object]:
    """lark's LALR parser with positions, fed gpp's tokens, building lark's parse tree."""
    from lark import Lark
    from lark import Token as LarkToken
    from lark.lexer import Lexer

    class GppTokens(Lexer):
        def __init__(self, conf: object) -> None:
            pass

        def lex(self, source: Source) -> Iterator[LarkToken]:  # type: ignore[override]
            for t in tokenize(source)[0]:
                yield LarkToken(t.type, t.value, t.start, 1, 1, 1, 1, t.end)

    from gpp.base.resources import grammar_path

    lark = Lark(
        grammar_path().read_text(encoding="utf-8"),
        parser="lalr",
        lexer=GppTokens,
        propagate_positions=True,
        keep_all_tokens=True,
    )
    return lambda source: lark.parse(source)  # type: ignore[arg-type]


def table(markdown: bool, header: list[str], caption: str) -> None:
    """Print a table's caption and header: Markdown, or aligned text (the columns' widths)."""
    print()
    print(caption)
    if markdown:
        print()
        print("| " + " | ".join(h for h in header) + " |")
        print("|" + "|".join("---:" for _ in header) + "|")
    else:
        print(" ".join(f"{h:>{max(9, len(h))}}" for h in header))


def row(markdown: bool, header: list[str], cells: list[str]) -> None:
    if markdown:
        print("| " + " | ".join(cells) + " |")
    else:
        print(" ".join(f"{c:>{max(9, len(h))}}" for c, h in zip(cells, header, strict=True)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="smaller sizes, for a smoke run")
    ap.add_argument("--markdown", action="store_true", help="print the tables as Markdown (docs/performance.md)")
    args = ap.parse_args()
    md = args.markdown
    sizes = [500, 2_000, 10_000] if args.quick else [500, 2_000, 10_000, 50_000]
    # Up to just below the nesting limit (gpp.syntax.depth.MAX_NESTING, 2,000 levels).
    depths = [10, 100, 1_000] if args.quick else [10, 100, 1_000, 1_900]
    repeat = 3
    baseline = lark_baseline()

    header = ["lines", "tokens", "parse s", "lines/s", "cost/line", "lark tree s", "lark / gpp"]
    caption = f"Parse (tokenize + LALR + syntax tree), best of {repeat}; lark's LALR and tree on the same tokens:"
    table(md, header, caption)
    first_cost = None
    checks: list[tuple[int, float, float]] = []
    for lines in sizes:
        text = generate_program(lines)
        source = Source(text, f"gen{lines}.gpp")
        n_lines = text.count("\n")
        n_tokens = len(tokenize(source)[0])
        result = parse(source)
        assert not result.diagnostics, result.diagnostics[:3]
        seconds = best_of(repeat, parse, source)
        cost = seconds / n_lines
        first_cost = first_cost or cost
        gc.disable()
        try:
            lark_seconds = best_of(1 if lines > 10_000 else repeat, baseline, source)
        finally:
            gc.enable()
        cells = [f"{n_lines:,}", f"{n_tokens:,}", f"{seconds:.3f}", f"{n_lines / seconds:,.0f}"]
        cells += [f"{cost / first_cost:.2f}", f"{lark_seconds:.3f}", f"{lark_seconds / seconds:.1f}x"]
        row(md, header, cells)
        runs = 1 if lines > 10_000 else repeat
        checks.append((n_lines, time_check(source, runs, lint=False), time_check(source, runs, lint=True)))

    header = ["lines", "check s", "lines/s", "cost/line", "+ lints s", "lines/s"]
    table(md, header, f"Parse + check (names, types), and with lints, best of {repeat}:")
    first_check = None
    for n_lines, check_seconds, lint_seconds in checks:
        per_line = check_seconds / n_lines
        first_check = first_check or per_line
        cells = [f"{n_lines:,}", f"{check_seconds:.3f}", f"{n_lines / check_seconds:,.0f}"]
        cells += [f"{per_line / first_check:.2f}", f"{lint_seconds:.3f}", f"{n_lines / lint_seconds:,.0f}"]
        row(md, header, cells)

    header = ["depth", "tokens", "parse s", "µs/token", "cost/token"]
    table(md, header, "Nesting depth: parentheses and blocks nested N deep:")
    first = None
    for depth in depths:
        source = Source(nested_expression_program(depth), f"deep{depth}.gpp")
        n_tokens = len(tokenize(source)[0])
        result = parse(source)
        assert not result.diagnostics, result.diagnostics[:3]
        seconds = best_of(repeat, parse, source)
        per_token = seconds / n_tokens
        first = first or per_token
        cells = [f"{depth:,}", f"{n_tokens:,}", f"{seconds:.4f}", f"{per_token * 1e6:.2f}", f"{per_token / first:.2f}"]
        row(md, header, cells)


if __name__ == "__main__":
    main()
