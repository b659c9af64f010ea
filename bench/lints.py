"""Lint speed: `run_lints` on generated programs (bench/genprog), and where its time goes.

Run: .venv/bin/python bench/lints.py [--sizes 1000 10000] [--runs N] [--against REV]

Times are the CPU time of the thread running the lints (the cyclic collector paused, as in
`gpp check`), best of N runs, on one code model per size; the model's reference index is
dropped before each run, as a fresh check has none. The table after it splits one run: the facts
several lints share (the node index, the used symbols, the statement lists), each computed once,
then every lint. `--against REV` also times the lints of a git revision (its
gpp/check/lints.py and gpp/syntax/walk.py, the rest of gpp as it is now), runs alternating
with the current ones under the same load, and checks that both give the same warnings.
"""

from __future__ import annotations

import argparse
import gc
import json
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from types import ModuleType

sys.path.insert(0, str(Path(__file__).resolve().parent))

from genprog import generate_program
from revision import modules_at

from gpp.base.diagnostics import Diagnostic
from gpp.base.perf import with_deep_stack
from gpp.check import lints
from gpp.model.build import build_model
from gpp.model.model import Model
from gpp.report.text import diagnostic_to_json
from gpp.syntax.loader import load

ROOT = Path(__file__).resolve().parent.parent


def cpu_time(fn: Callable[[], object]) -> float:
    start = time.thread_time()
    fn()
    return time.thread_time() - start


def fresh(model: Model) -> Model:
    """The model as a check hands it to the lints: without the reference index, built on demand."""
    return replace(model)


def timed_lints(module: ModuleType, model: Model, roots: set[Path]) -> tuple[float, list[Diagnostic]]:
    start = time.thread_time()
    found: list[Diagnostic] = module.run_lints(model, roots)
    return time.thread_time() - start, found


def shown(found: list[Diagnostic]) -> list[str]:
    return [json.dumps(diagnostic_to_json(d)) for d in found]


def measure(lines: int, runs: int, old: ModuleType | None) -> None:
    path = ROOT / f"generated-{lines}.gpp"
    loaded = load([path], {path: generate_program(lines)})
    model, _ = build_model(loaded.files)
    roots = {path}
    best = {"now": float("inf"), "before": float("inf")}
    results: dict[str, list[str]] = {}
    for k in range(runs):
        order = [("now", lints), ("before", old)] if k % 2 == 0 else [("before", old), ("now", lints)]
        for name, module in order:
            if module is not None:
                seconds, found = timed_lints(module, fresh(model), roots)
                best[name] = min(best[name], seconds)
                results[name] = shown(found)
    line = f"{lines:>7,} lines  run_lints {best['now'] * 1000:8.1f} ms"
    if old is not None:
        same = "same warnings" if results["before"] == results["now"] else "DIFFERENT WARNINGS"
        ratio = best["before"] / best["now"]
        line += f"   before {best['before'] * 1000:8.1f} ms   {ratio:.2f}x faster, {same}"
    print(line + f"   ({len(results['now'])} warnings, best of {runs})")
    program = lints._Program(fresh(model), roots)
    parts = {
        "node index": lambda: program._nodes,
        "used symbols": lambda: program._used,
        "statement lists": lambda: list(program.body_statements(model.files)),
    }
    times = {name: cpu_time(fn) for name, fn in parts.items()}
    for code, lint in lints.LINTS.items():
        times[f"{code} {lint.__name__}"] = cpu_time(lambda lint=lint: list(lint(program)))
    for name, seconds in sorted(times.items(), key=lambda item: -item[1])[:8]:
        print(f"          {name:<32} {seconds * 1000:7.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--against", metavar="REV", help="also time the lints of this git revision")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        old = None
        if args.against:
            copied = modules_at(args.against, ["gpp/syntax/walk.py", "gpp/check/lints.py"], Path(folder), "lints_at")
            old = copied["lints"]
        gc.disable()
        print("lints on generated programs, thread CPU time; the slowest parts of one run below each")
        for lines in args.sizes:
            with_deep_stack(
                lambda lines=lines: measure(lines, args.runs if lines <= 2000 else max(3, args.runs // 3), old)
            )


if __name__ == "__main__":
    main()
