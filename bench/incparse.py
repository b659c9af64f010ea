"""Incremental re-parsing: what re-parsing a file after a small edit costs, against a full parse.

Run: .venv/bin/python bench/incparse.py [--lines N] [--runs N] [--clock wall|cpu] [--against REF]

On a generated program (bench/genprog.py), in-process, best of `runs`, the incremental parse
(gpp.syntax.incremental.reparse, as loader.ParseCache uses it) and the full parse of the same
new text are timed one after the other in each run, for:
* a space typed at the start of a line near the start, in the middle and at the end of the file,
  and a letter typed into a name in a procedure body in the middle and at the end (the edited
  declaration is parsed again and spliced in);
* an unfinished call typed at the same line starts (a syntax error: the file is parsed again
  from the declaration before the edit to its end);
and the relocation alone: every declaration of the old parse moved into a new Source.
The cyclic garbage collector is paused while a run is timed and runs between runs, as in the
language server (lsp.gc_policy.GcPolicy). The `tokens` column is what reading the new parse's
tokens costs afterwards (a re-parse makes the list of the tokens it kept only when it is first
read, `gpp.syntax.lexer.Tokens`).
With `--against REF` (a git revision), gpp/syntax/incremental.py as it is at REF, with the
relocators and the node-building code they are generated from (gpp/syntax/fast.py at REF, or
gpp/syntax/build.py before that module existed), is timed as well, in the same runs
(interleaved: both see the same load), and the table shows the ratio.
"""

from __future__ import annotations

import argparse
import gc
import re
import sys
import tempfile
import time
from bisect import bisect_left
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program
from revision import modules_at, python_files_at

from gpp.base.source import Source
from gpp.syntax import incremental
from gpp.syntax.lexer import KEYWORDS
from gpp.syntax.parser import parse

# The clock the runs are timed with: wall time, or the process's CPU time (steadier when other
# processes compete for the cores: time spent waiting for one is not counted).
clock = time.perf_counter


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=1000)
    ap.add_argument("--runs", type=int, default=15)
    ap.add_argument("--clock", choices=["wall", "cpu"], default="wall")
    ap.add_argument("--against", metavar="REF", help="also time incremental.py as it is at this git revision")
    args = ap.parse_args()
    global clock
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    modules = {"now": incremental}
    if args.against:
        folder = Path(tempfile.mkdtemp())
        if "gpp/syntax/fast.py" in python_files_at(args.against, "gpp/syntax"):
            copied = modules_at(args.against, ["gpp/syntax/incremental.py", "gpp/syntax/fast.py"], folder, "at_ref")
        else:
            copied = modules_at(args.against, ["gpp/syntax/incremental.py", "gpp/syntax/build.py"], folder, "at_ref")
            copied["incremental"].build = copied["build"]  # imported as `from gpp.syntax import build`
        modules[args.against] = copied["incremental"]
    text = generate_program(args.lines)
    old = parse(Source(text, "bench.gpp"))
    for module in modules.values():
        module.relocators()  # made once per process, not part of a re-parse
    incremental.relocators(False)  # and those for the declarations before an edit
    starts = Source(text).line_starts
    places = {"start": starts[1], "middle": starts[len(starts) // 2], "end": starts[-2]}
    # A name in a procedure body: the first call after the middle of the file, the last one.
    calls = [m.start(1) for m in re.finditer(r"[{;]\s*([a-z]\w*)\(", text) if m.group(1) not in KEYWORDS]
    in_names = {"middle": calls[bisect_left(calls, len(text) // 2)] + 1, "end": calls[-1] + 1}
    edits = [(f"space at {where}", at, " ") for where, at in places.items()]
    edits += [(f"letter in a name at {where}", at, "x") for where, at in in_names.items()]
    edits += [(f"unfinished call at {where}", at, "x(") for where, at in places.items()]
    print(f"program: {args.lines} lines, {len(text)} characters, {len(old.tokens)} tokens ({args.clock} time)")
    against = f" {args.against[:10]:>11} {'gain':>6}" if args.against else ""
    print(
        f"{'edit':<28} {'how':<7} {'parsed chars':>12} {'incremental':>12} {'tokens':>8} {'full parse':>11}"
        f" {'speed-up':>9}{against}"
    )
    for name, at, typed in edits:
        new = text[:at] + typed + text[at:]
        inc_times: dict[str, list[float]] = {name: [] for name in modules}
        token_times = []
        full_times = []
        how, chars = "full", len(new)
        for _ in range(args.runs):
            gc.collect()
            gc.disable()
            try:
                for module_name, module in modules.items():
                    source = Source(new, "bench.gpp")
                    t0 = clock()
                    done = module.reparse(text, old, source)
                    result = parse(source) if done is None else done.result  # what ParseCache does then
                    inc_times[module_name].append(clock() - t0)
                    if module_name == "now":
                        if done is not None:
                            how, chars = done.how, done.parsed_chars
                        t0 = clock()
                        result.lazy_tokens.as_list()
                        token_times.append(clock() - t0)
                    del done, result  # freed here, not in the next timing
                t0 = clock()
                parse(Source(new, "bench.gpp"))
                full_times.append(clock() - t0)
            finally:
                gc.enable()
        inc, full = min(inc_times["now"]), min(full_times)
        row = f"{name:<28} {how:<7} {chars:>12} {inc * 1000:>10.2f}ms {min(token_times) * 1000:>6.2f}ms"
        row += f" {full * 1000:>9.1f}ms {full / inc:>8.1f}x"
        if args.against:
            ref = min(inc_times[args.against])
            row += f" {ref * 1000:>9.2f}ms {ref / inc:>5.2f}x"
        print(row)
    # The relocation alone, interleaved as above.
    target = Source(text, "bench.gpp")
    decls = old.program.declarations
    variants = {f"moved ({name})": (module.relocators(), 1) for name, module in modules.items()}
    variants["not moved (now)"] = (incremental.relocators(False), 0)
    moving_times: dict[str, list[float]] = {name: [] for name in variants}
    for _ in range(args.runs):
        gc.collect()
        gc.disable()
        try:
            for name, (table, delta) in variants.items():
                t0 = clock()
                moved = [table[type(d)](d, target, delta) for d in decls]
                moving_times[name].append(clock() - t0)
                del moved
        finally:
            gc.enable()
    for name, times in moving_times.items():
        print(f"relocating all {len(decls)} declarations, {name}: {min(times) * 1000:.2f}ms")
    print("load average:", Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else "?")


if __name__ == "__main__":
    main()
