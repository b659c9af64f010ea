"""Debugger latency: a real `gpp dap` over stdio, driven as an editor drives it, on the
1,000-line bench program (bench/genprog.py).

Run: .venv/bin/python bench/dap.py [--quick] [--lines 1000] [--markdown]

It launches the program on the dummy platform with a line breakpoint on the `while` of the
first procedure (whose loop runs a transition per turn), then, as the client sees them:
* stop at a breakpoint: from sending `continue` to the `stopped` event of the breakpoint's
  next hit (the run goes through the loop's transitions between the two, on its own thread);
* what an editor asks at each stop: `stackTrace`, then `scopes` and the Fluents scope's
  `variables` (the program's fluents grouped by fluent);
* evaluate: an expression over a parameter, a fluent and a function in the stopped
  statement's scope (parsed and type-checked by the front end, then evaluated), and hover
  over a fluent;
* setBreakpoints with a condition (checked in the statement's scope).
Times are medians and 90th percentiles over the runs (100 of each; 20 with --quick); the
targets of the debugger (issue 28) are printed beside them.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from genprog import generate_program  # noqa: E402

from tests.support.dap_client import DapClient, dap_session, line_of  # noqa: E402

# What the debugger should reach (issue 28).
TARGETS = {"stop at a breakpoint": 0.050, "evaluate": 0.050}


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def timed(n: int, fn: Callable[[], object]) -> list[float]:
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def measure(dap: DapClient, program: Path, runs: int) -> dict[str, list[float]]:
    loop = line_of(program, "while (!done0())")
    t0 = time.perf_counter()
    dap.start({"program": str(program)}, {str(program): [{"line": loop}]})
    dap.stopped()
    results = {"launch to the first stop": [time.perf_counter() - t0]}

    def stop_again() -> None:
        dap.ok("continue", {"threadId": 1})
        assert dap.stopped()["reason"] == "breakpoint"

    def look() -> None:
        dap.ok("stackTrace", {"threadId": 1})
        scopes = dap.ok("scopes", {"frameId": 0})["scopes"]
        fluents = next(s for s in scopes if s["name"] == "Fluents")
        dap.ok("variables", {"variablesReference": fluents["variablesReference"]})

    results["stop at a breakpoint"] = timed(runs, stop_again)
    results["stack, scopes, fluents"] = timed(runs, look)
    # A new text each time: parsed and checked each time (a text asked again is checked once).
    texts = iter(range(10**9))
    results["evaluate"] = timed(
        runs, lambda: dap.evaluate(f"count0(o) + length(path0()) > {next(texts)} | !done0() & at0(o0b) != table0")
    )
    results["hover"] = timed(runs, lambda: dap.evaluate("at0(o0b)", context="hover"))
    condition = {"source": {"path": str(program)}, "breakpoints": [{"line": loop, "condition": "count0(o) >= 0"}]}
    results["setBreakpoints with a condition"] = timed(runs, lambda: dap.ok("setBreakpoints", condition))
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="20 runs of each instead of 100")
    parser.add_argument("--lines", type=int, default=1000)
    parser.add_argument("--markdown", action="store_true", help="print only the table (docs/performance.md)")
    args = parser.parse_args()
    runs = 20 if args.quick else 100
    with tempfile.TemporaryDirectory() as folder:
        program = Path(folder) / "bench.gpp"
        program.write_text(generate_program(args.lines), encoding="utf-8")
        with dap_session(cwd=Path(folder)) as dap:
            results = measure(dap, program, runs)
    name = f"{args.lines:,} lines"
    if not args.markdown:
        print(f"gpp dap on the {name} bench program, dummy platform ({runs} runs of each)\n")
    print("| program     | what                            | runs |    median |       p90 | target |")
    print("|-------------|---------------------------------|------|-----------|-----------|--------|")
    for what, times in results.items():
        target = TARGETS.get(what)
        shown = f"{target * 1000:.0f} ms" if target is not None else ""
        print(
            f"| {name:<11} | {what:<31} | {len(times):>4} | {statistics.median(times) * 1000:>6.1f} ms "
            f"| {percentile(times, 0.9) * 1000:>6.1f} ms | {shown:>6} |"
        )


if __name__ == "__main__":
    main()
