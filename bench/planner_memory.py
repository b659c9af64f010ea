"""Cost and memory per node of the production `solve` planner (gpp issue #27, item 3): CPU
microseconds per expanded node and bytes per node (the peak of tracemalloc over the planning,
divided by the nodes) on the tower reversals of bench/planner.py, without the bound (every node
the reference expands: the cost of a node) and with it.

Run: .venv/bin/python bench/planner_memory.py [--blocks 6 7] [--runs 3]

Times are CPU seconds of this process, best of --runs, without tracemalloc (which slows every
allocation down); the memory is measured in one more run under tracemalloc.
"""

from __future__ import annotations

import argparse
import gc
import time
import tracemalloc

from bench.planner import tower_problem


def measure(blocks: int, prune: bool, runs: int) -> tuple[int, float, int]:
    """Nodes, CPU seconds (best of `runs`) and the tracemalloc peak of planning the tower."""
    pb = tower_problem(blocks, 14)
    best = float("inf")
    nodes = 0
    for _ in range(runs):
        started = time.process_time()
        plan = pb.production(prune)
        best = min(best, time.process_time() - started)
        nodes = plan.stats.nodes
    gc.collect()
    tracemalloc.start()
    pb.production(prune)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return nodes, best, peak


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--blocks", type=int, nargs="+", default=[6, 7], help="towers (3 to 7 blocks; default 6 7)")
    parser.add_argument("--runs", type=int, default=3, help="timed runs, best taken (default 3)")
    args = parser.parse_args()
    if not all(3 <= b <= 7 for b in args.blocks):
        parser.error("--blocks: towers of 3 to 7 blocks")
    header = ["problem", "bound", "nodes", "cpu s", "µs/node", "peak MiB", "bytes/node"]
    print("  ".join(h.rjust(12) for h in header))
    for blocks in args.blocks:
        for prune in (False, True):
            nodes, seconds, peak = measure(blocks, prune, args.runs)
            cells = [
                f"{blocks} blocks, 14",
                "yes" if prune else "no",
                f"{nodes:,}",
                f"{seconds:.3f}",
                f"{seconds / nodes * 1e6:.1f}",
                f"{peak / 2**20:.1f}",
                f"{peak / nodes:,.0f}",
            ]
            print("  ".join(c.rjust(12) for c in cells), flush=True)
    with open("/proc/loadavg", encoding="ascii") as load:
        print(f"load average: {load.read().split()[0]}")


if __name__ == "__main__":
    main()
