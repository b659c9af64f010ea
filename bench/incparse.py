"""Incremental re-parsing: what re-parsing a file after a small edit costs, against a full parse.

Run: .venv/bin/python bench/incparse.py [--lines N] [--runs N] [--clock wall|cpu]

On a generated program (bench/genprog.py), in-process, best of `runs`, the incremental parse
(gpp.syntax.incremental.reparse, as loader.ParseCache uses it) and the full parse of the same
new text are timed one after the other in each run, for:
* a space typed at the start of a line near the start, in the middle and at the end of the file
  (the edited declaration is parsed again and spliced in);
* an unfinished call typed at the same places (a syntax error: the file is parsed again from the
  declaration before the edit to its end);
and the relocation alone: every declaration of the old parse moved into a new Source.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program

from gpp.perf import paused_gc
from gpp.source import Source
from gpp.syntax.incremental import relocate, reparse
from gpp.syntax.parser import parse

# The clock the runs are timed with: wall time, or the process's CPU time (steadier when other
# processes compete for the cores: time spent waiting for one is not counted).
clock = time.perf_counter


def best(fn: Callable[[], None], runs: int) -> float:
    times = []
    for _ in range(runs):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=1000)
    ap.add_argument("--runs", type=int, default=15)
    ap.add_argument("--clock", choices=["wall", "cpu"], default="wall")
    args = ap.parse_args()
    global clock
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    text = generate_program(args.lines)
    old = parse(Source(text, "bench.gpp"))
    starts = Source(text).line_starts
    places = {"start": starts[1], "middle": starts[len(starts) // 2], "end": starts[-2]}
    print(f"program: {args.lines} lines, {len(text)} characters, {len(old.tokens)} tokens ({args.clock} time)")
    print(f"{'edit':<24} {'how':<7} {'parsed chars':>12} {'incremental':>12} {'full parse':>11} {'speed-up':>9}")
    for kind, typed in (("space", " "), ("unfinished call", "x(")):
        for where, at in places.items():
            new = text[:at] + typed + text[at:]
            inc_times, full_times = [], []
            how, chars = "full", len(new)
            for _ in range(args.runs):
                source = Source(new, "bench.gpp")
                t0 = clock()
                done = reparse(text, old, source)
                if done is None:
                    parse(source)  # what ParseCache does then
                else:
                    how, chars = done.how, done.parsed_chars
                inc_times.append(clock() - t0)
                t0 = clock()
                parse(Source(new, "bench.gpp"))
                full_times.append(clock() - t0)
            inc, full = min(inc_times), min(full_times)
            print(
                f"{kind + ' at ' + where:<24} {how:<7} {chars:>12} {inc * 1000:>10.1f}ms {full * 1000:>9.1f}ms"
                f" {full / inc:>8.1f}x"
            )
    target = Source(text, "bench.gpp")

    def relocate_all() -> None:
        with paused_gc():  # as in a re-parse
            [relocate(d, target, 1) for d in old.program.declarations]

    moved = best(relocate_all, args.runs)
    print(f"relocating all {len(old.program.declarations)} declarations: {moved * 1000:.1f}ms")
    print("load average:", Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else "?")


if __name__ == "__main__":
    main()
