"""The parser of this tree against the parser of a git revision: same results, and how much faster.

Run: .venv/bin/python bench/parse_compare.py [--ref main] [--runs N] [--no-check]

The revision's syntax modules (lexer, parser, builder, tables, legacy rewriter, depth limit)
are loaded under another package name, beside this tree's, so both parse in the same process.
The check parses every .gpp file of the repository and the corpus of tests/support/parse_corpus.py
with both and compares everything they return (tokens, trees with spans, diagnostics). The
timing alternates the two parsers on the bench programs of bench/genprog.py and prints the
best of N for each, with their ratio and the load average.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from genprog import generate_program, nested_expression_program
from revision import modules_at

from gpp.base.source import Source
from gpp.syntax.parser import parse
from tests.support.parse_corpus import corpus, dump

ROOT = Path(__file__).resolve().parent.parent
# The modules of gpp.syntax that make up the parser (the others, such as the tree, are shared).
_MODULES = ("lexer", "tables", "build", "depth", "legacy", "parser")


def load_revision(ref: str, into: Path) -> Callable[[Source], Any]:
    """`parse` of revision `ref`, its parser modules loaded as package `gpp_at_ref`."""
    paths = [f"gpp/syntax/{module}.py" for module in _MODULES]
    parse_at_ref: Callable[[Source], Any] = modules_at(ref, paths, into, "gpp_at_ref")["parser"].parse
    return parse_at_ref


def check(old: Callable[[Source], Any]) -> int:
    """Compare the two parsers on the repository's programs and the corpus; the differences."""
    listed = subprocess.run(["git", "ls-files", "*.gpp"], cwd=ROOT, check=True, capture_output=True, text=True)
    files = [(p, (ROOT / p).read_text(encoding="utf-8", errors="replace")) for p in listed.stdout.split()]
    programs = [*files, *corpus()]
    differ = [name for name, text in programs if dump(text, old) != dump(text, parse)]
    print(f"compared {len(programs)} programs ({len(files)} files of the repository): {len(differ)} differ")
    for name in differ[:20]:
        print("  differs:", name)
    return len(differ)


def best_of_interleaved(runs: int, source: Source, old: Callable[[Source], Any]) -> tuple[float, float]:
    best_old = best_new = float("inf")
    for run in range(runs):
        for which in (old, parse) if run % 2 == 0 else (parse, old):
            t0 = time.perf_counter()
            result = which(source)
            seconds = time.perf_counter() - t0
            del result  # freeing the tree is not part of parsing
            if which is old:
                best_old = min(best_old, seconds)
            else:
                best_new = min(best_new, seconds)
    return best_old, best_new


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--ref", default="main", help="the git revision to compare with (default main)")
    ap.add_argument("--runs", type=int, default=15, help="runs of each parser per program (best counts)")
    ap.add_argument("--no-check", action="store_true", help="time only")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        old = load_revision(args.ref, Path(tmp))
        differ = 0 if args.no_check else check(old)
        print(f"\nparse time, best of {args.runs}, interleaved; load average {Path('/proc/loadavg').read_text()[:14]}")
        print(f"{'program':>18} {'tokens':>8} {args.ref + ' ms':>10} {'this ms':>9} {'speed-up':>9} {'µs/token':>9}")
        programs = [(f"{n:,} lines", generate_program(n)) for n in (1_000, 10_000)]
        programs.append(("nested 1,000", nested_expression_program(1_000)))
        for name, text in programs:
            source = Source(text, "bench.gpp")
            tokens = len(parse(source).tokens)
            runs = max(3, args.runs // 3) if len(text) > 200_000 else args.runs
            t_old, t_new = best_of_interleaved(runs, source, old)
            print(
                f"{name:>18} {tokens:>8,} {t_old * 1e3:>10.1f} {t_new * 1e3:>9.1f} {t_old / t_new:>8.2f}x "
                f"{t_new / tokens * 1e6:>9.2f}"
            )
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
