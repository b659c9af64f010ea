"""Scaling of the `solve` planners: reversing a tower of n blocks (3 to 7) in the blocks world
of examples/blocks_planning.gpp, for horizons up to 14.

Run: .venv/bin/python bench/planner.py [--quick] [--budget N] [--count]
     .venv/bin/python bench/planner.py --targets [--runs N] [--no-bound]
     .venv/bin/python bench/planner.py --profile [--blocks 6 7] [--no-bound]
     .venv/bin/python bench/planner.py --bound [--runs N]
     .venv/bin/python bench/planner.py --peers [--targets] [--runs N] [--limit SECONDS] [--quick]
     .venv/bin/python bench/planner.py --search [--quick]

For every (blocks, horizon) it runs the production planner (gpp.planner.dp) and the reference
planner (gpp.planner.reference, the plain recursive definition) and prints their node counts,
CPU seconds and the ratios. The reference is exponential: it is stopped after --budget nodes
and then shown as ">N" with the time it had taken so far, and the ratio as ">=" the budget over
the production's nodes: a lower bound, never an invented number. With --count the exact number
of nodes the reference would expand is counted as well (by a memoised count that
tests/planner/test_planner.py checks against the reference's own count), for towers of up to five
blocks. Times are CPU seconds of this process (the machine may be shared), best of one run.

--targets times the production planner on the three target problems (five blocks solve(10),
six and seven blocks solve(14)): CPU seconds of the first planning in the process ("cold":
its generated code written and compiled), of a program checked anew whose generated source
was compiled before ("fresh", best of the other --runs: gpp.runtime.codegen's compile cache)
and of the same problem planned again ("again": its generated code reused), nodes,
microseconds per node and nodes per second (of the best of cold and fresh), the ratio to the
planner before gpp issue #14 (measured on the same machine at commit 9252b1d) and the target,
checks that the plan is the one-move-per-block reversal, and reports the peak memory of the
process and the load average. With --no-bound the planner runs without branch
and bound, expanding every node the reference would (the cost of a node is what it measures).

--profile runs cProfile on `solve` for the given towers (horizon 14) and prints where the time
goes, grouped (the planner's loop and memo, `trans` and `final`, expressions, effects and
state updates, the reward, hashing and comparing), then the functions with the most time of
their own. cProfile slows every call down alike, so the shares matter, not the seconds.

--bound compares the production planner with and without the branch and bound of
gpp.planner.bounds (the same plan, checked): nodes, options skipped by the bound, CPU seconds
(interleaved, best of --runs), on the towers and on a case built for it (visit places avoiding
a trap: the best plan is worth 0, the most the reward can give).

--peers runs Fast Downward (A* with LM-cut, the `bench` extra) and gpp on the same blocksworld
instances, interleaved, and prints both, in-process and as whole processes, with the ratios
(bench/peers.py says how each figure is taken); the towers of 5 to 12 blocks and random
instances of 7 to 10 blocks, three seeds each, `solve(14)` (--quick: towers of 5 to 7 and the
random 7-block instances, one run). With --targets it adds the table of gpp issue #27: its
problems with the figures before, gpp's now, Fast Downward's, the target and pass or miss.

--search times `search` with iterative deepening (gpp.planner.search) on the towers and random
instances, each in a fresh process (its peak memory its own, at most SEARCH_LIMIT CPU seconds):
cut by the goal distance (the default), uncut on the generated successors (the same nodes as
before), and uncut on the semantics itself (what `search` ran on before); nodes, CPU seconds of
the search, µs per node and the peak memory; uncut only on the towers of 8 and 10 blocks
(--quick: the towers of 6 and 8 blocks).
"""

from __future__ import annotations

import argparse
import cProfile
import json
import math
import pstats
import resource
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from gpp.check import check_text
from gpp.planner.bounds import analyse
from gpp.planner.problem import PlanningProblem, first_solve
from gpp.planner.reference import NodeBudgetExceeded
from gpp.runtime.codegen import COMPILE_CACHE

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # run as a script: bench.blocksworld, bench.peers
from bench import peers as peer_bench
from bench.blocksworld import NAMES, program, tower


def tower_program(blocks: int, horizon: int, twice: bool = False) -> str:
    """A tower blocks[0] on blocks[1] on ... on the table, to be reversed: the optimum moves
    every block once (the top one to the table, each next one onto the one moved before).
    `twice`: a choice of two copies of the loop (the second is planned after the first)."""
    return program(tower(blocks), horizon, twice)


def hazards_program(places: int, trap: int, horizon: int) -> str:
    """Visit `horizon` of `places` places, one at a time; place `trap` is a trap that costs 10
    for every step from then on. The best plan avoids it and is worth 0, the most the reward
    can give: a case for the branch and bound of gpp.planner.bounds."""
    names = [f"d{i}" for i in range(places)]
    return f"""
symbol domain D = {{{", ".join(names)}}}
bool fluent visited(D x) {{ initially: (x) = false; }}
bool fluent trap(D x) {{ initially: (x) = false; ({names[trap]}) = true; }}
action visit(D x) {{ precondition: !visited(x) effect: visited(x) = true; }}
number function reward() = if (exists(D x) visited(x) & trap(x)) -10 else 0
procedure main() {{ solve({horizon}, reward()) while (true) pick (D x) visit(x); }}
"""


def problem_of(text: str) -> PlanningProblem:
    result = check_text(text, lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    return first_solve(result.model)


def tower_problem(blocks: int, horizon: int) -> PlanningProblem:
    return problem_of(tower_program(blocks, horizon))


@dataclass
class Row:
    blocks: int
    horizon: int
    value: float | None
    moves: int
    nodes: int
    seconds: float
    ref_nodes: int
    ref_seconds: float
    ref_finished: bool
    counted: int | None


def measure(blocks: int, horizon: int, budget: int, count: bool) -> Row:
    pb = tower_problem(blocks, horizon)
    started = time.process_time()
    plan = pb.production()
    seconds = time.process_time() - started
    started = time.process_time()
    try:
        reference = pb.reference(budget=budget)
        ref_nodes, finished = reference.stats.nodes, True
        assert (reference.feasible, reference.value, reference.steps) == (plan.feasible, plan.value, plan.steps)
    except NodeBudgetExceeded:
        ref_nodes, finished = budget, False
    ref_seconds = time.process_time() - started
    counted = pb.reference_nodes() if count and blocks <= 5 else None
    return Row(
        blocks,
        horizon,
        plan.value if plan.feasible else None,
        len(plan.actions()),
        plan.stats.nodes,
        seconds,
        ref_nodes,
        ref_seconds,
        finished,
        counted,
    )


def render(row: Row) -> list[str]:
    more = "" if row.ref_finished else ">"
    at_least = "" if row.ref_finished else ">="
    cells = [
        str(row.blocks),
        str(row.horizon),
        f"{row.value:g}" if row.value is not None else "none",
        str(row.moves),
        f"{row.nodes:,}",
        f"{row.seconds:.3f}",
        f"{row.seconds / max(row.nodes, 1) * 1e6:.1f}",
        f"{row.nodes / max(row.seconds, 1e-9):,.0f}",
        f"{more}{row.ref_nodes:,}",
        f"{more}{row.ref_seconds:.3f}",
        f"{at_least}{row.ref_nodes / max(row.nodes, 1):,.1f}",
        f"{at_least}{row.ref_seconds / max(row.seconds, 1e-9):,.1f}",
    ]
    if row.counted is not None:
        cells += [f"{row.counted:,}", f"{row.counted / max(row.nodes, 1):,.0f}"]
    return cells


HEADER = [
    "blocks",
    "horizon",
    "value",
    "moves",
    "prod nodes",
    "prod cpu s",
    "µs/node",
    "nodes/s",
    "ref nodes",
    "ref cpu s",
    "node ratio",
    "time ratio",
]
COUNT_HEADER = ["ref nodes (counted)", "counted ratio"]


# The planner before gpp issue #14 (commit 9252b1d), on this machine: CPU seconds and nodes.
BEFORE = {(5, 10): (0.499, 1_899), (6, 14): (8.25, 24_953), (7, 14): (92.1, 170_369)}
TARGETS = {(5, 10): 0.030, (6, 14): 0.3, (7, 14): 4.0}


def reversal(blocks: int) -> list[str]:
    """The optimal plan: each block once, top first, onto the one moved before (or the table)."""
    names = NAMES[:blocks]
    return [f"stack({names[i]},{names[i - 1] if i else 'table'})" for i in range(blocks)]


def targets(runs: int, prune: bool = True) -> None:
    header = ["problem", "nodes", "cold s", "fresh s", "again s", "µs/node", "nodes/s"]
    header += ["before", "speed-up", "target", "met", "plan"]
    print("  ".join(h.rjust(12) for h in header))
    for (blocks, horizon), target in TARGETS.items():
        # cold: a program planned first in this process (nothing compiled yet); fresh: a
        # program checked anew, its generated source compiled before (gpp.runtime.codegen's
        # cache); again: the same problem planned again (its generated code reused).
        times: dict[str, float] = {"cold": math.inf, "fresh": math.inf, "again": math.inf}
        plan = None
        for run in range(runs if blocks < 7 else 1):
            if run == 0:
                COMPILE_CACHE.clear()
            pb = tower_problem(blocks, horizon)
            for kind in ("cold" if run == 0 else "fresh", "again"):
                started = time.process_time()
                plan = pb.production(prune=prune)
                times[kind] = min(times[kind], time.process_time() - started)
        assert plan is not None
        best = min(times["fresh"], times["cold"])  # one run: the cold one
        before_seconds, before_nodes = BEFORE[(blocks, horizon)]
        nodes = plan.stats.nodes
        same = plan.actions() == reversal(blocks) and plan.value == 100 - blocks
        cells = [
            f"{blocks} blocks, {horizon}",
            f"{nodes:,}",
            f"{times['cold']:.3f}",
            "" if math.isinf(times["fresh"]) else f"{times['fresh']:.3f}",
            f"{times['again']:.3f}",
            f"{best / nodes * 1e6:.1f}",
            f"{nodes / best:,.0f}",
            f"{before_seconds:.3f}",
            f"{before_seconds / best:.1f}x",
            f"{target:g}",
            "yes" if best < target else "no",
            # The plan and its value are the optimal ones (the nodes column says how many the
            # search needed: fewer than before with the bound, the same without it).
            "same" if same and nodes <= before_nodes else "CHANGED",
        ]
        print("  ".join(c.rjust(12) for c in cells), flush=True)
    # ru_maxrss is in KiB on Linux.
    print(f"peak memory of this process: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    print("before: per node " + ", ".join(f"{s / n * 1e6:.0f} µs ({n / s:,.0f} nodes/s)" for s, n in BEFORE.values()))
    with open("/proc/loadavg", encoding="ascii") as load:
        print(f"load average: {load.read().split()[0]}")


# Where a function's own time goes, by the file (and, for hashing, the function) it is in.
CATEGORIES = (
    ("planner loop and memo (dp)", ("gpp/planner/dp.py",)),
    (
        "trans/final (successors, semantics, codegen)",
        (
            "gpp/planner/fast/successors.py",
            "gpp/runtime/semantics.py",
            "gpp/planner/fast/codegen.py",
            "gpp/runtime/codegen.py",
        ),
    ),
    ("expressions: preconditions, conditions (compiled)", ("gpp/runtime/compiled.py",)),
    ("state updates and hashing (state)", ("gpp/runtime/state.py",)),
    ("reward", ("gpp/planner/problem.py",)),
    ("value comparison (types)", ("gpp/model/types.py", "gpp/runtime/values.py")),
)


def profile(blocks_list: list[int], prune: bool = True) -> None:
    for blocks in blocks_list:
        pb = tower_problem(blocks, 14)
        profiler = cProfile.Profile()
        profiler.enable()
        plan = pb.production(prune=prune)
        profiler.disable()
        stats = pstats.Stats(profiler)
        entries = stats.stats  # type: ignore[attr-defined]
        total = sum(e[2] for e in entries.values())
        groups: dict[str, float] = {}
        for (filename, _, name), (_, _, own, _, _) in entries.items():
            group = next((g for g, files in CATEGORIES if any(filename.endswith(f) for f in files)), None)
            if filename.startswith("<gpp generated"):
                group = "generated code: trans, apply, conditions, reward (codegen)"
            if group is None:
                group = "hashing and comparing (dict, hash, __eq__)" if name in _HASHING else "other builtins"
            groups[group] = groups.get(group, 0.0) + own
        print(f"\n{blocks} blocks, solve(14): {plan.stats.nodes:,} nodes, {total:.2f} s under cProfile")
        for group, own in sorted(groups.items(), key=lambda g: -g[1]):
            print(f"  {own / total:6.1%}  {group}")
        print("  functions with the most time of their own:")
        ranked = sorted(entries.items(), key=lambda e: -e[1][2])[:12]
        for (filename, line, name), (_, calls, own, _, _) in ranked:
            where = filename.split("/gpp/")[-1] if "/gpp/" in filename else filename
            print(f"  {own / total:6.1%}  {calls:>10,} calls  {name} ({where}:{line})")


def bound_table(runs: int) -> None:
    """Nodes and CPU seconds of the production planner with and without branch and bound
    (interleaved, best of `runs`), on the towers and on the hazards case."""
    problems = [(f"tower {b}, {h}", tower_program(b, h)) for b, h in ((3, 8), (4, 10), (5, 10), (6, 14), (7, 14))]
    problems += [
        (f"hazards {p}/{trap}, {h}", hazards_program(p, trap, h))
        for p, trap, h in ((8, 0, 6), (8, 7, 6), (10, 0, 8), (10, 9, 8), (12, 0, 10), (12, 11, 10))
    ]
    header = ["problem", "bound", "nodes", "nodes b&b", "node ratio", "skipped", "cpu s", "cpu s b&b", "time ratio"]
    print("  ".join(h.rjust(14) for h in header))
    for name, text in problems:
        pb = problem_of(text)
        assert pb.solve is not None
        analysis = analyse(pb.sem.model, pb.solve)
        best = {False: math.inf, True: math.inf}
        plans = {}
        for _ in range(runs):
            for prune in (False, True):
                started = time.process_time()
                plans[prune] = pb.production(prune)
                best[prune] = min(best[prune], time.process_time() - started)
        full, pruned = plans[False], plans[True]
        assert (full.feasible, full.value, full.steps) == (pruned.feasible, pruned.value, pruned.steps)
        cells = [
            name,
            analysis.kind or "none",
            f"{full.stats.nodes:,}",
            f"{pruned.stats.nodes:,}",
            f"{full.stats.nodes / pruned.stats.nodes:.1f}",
            f"{pruned.stats.bound_skips:,}",
            f"{best[False]:.3f}",
            f"{best[True]:.3f}",
            f"{best[False] / best[True]:.2f}",
        ]
        print("  ".join(c.rjust(14) for c in cells), flush=True)
    with open("/proc/loadavg", encoding="ascii") as load:
        print(f"load average: {load.read().split()[0]}")


def peers(with_targets: bool, runs: int, limit: float, quick: bool) -> None:
    cases = peer_bench.peer_cases()
    if quick:
        quick_names = ("tower 5", "tower 6", "tower 7", "random 7 #")
        cases = [c for c in cases if c.instance.name.startswith(quick_names)]
        runs = 1
    if with_targets:
        cases += peer_bench.target_cases()
    driver = peer_bench.fast_downward()
    if driver is None:
        sys.exit(f"error: {peer_bench.NOT_INSTALLED}")

    def progress(line: str) -> None:
        print(line, file=sys.stderr, flush=True)

    rows = peer_bench.measure(driver, cases, runs, limit, progress)
    peer_bench.report(rows, limit, with_targets, lambda line: print(line, flush=True))


# `search` modes of --search: cut by the goal distance, uncut, uncut on the semantics itself.
SEARCH_MODES = ("cut", "uncut", "interpreted")
# The CPU seconds a --search child may take.
SEARCH_LIMIT = 150


def search_child() -> None:
    """In the child: search the instance given as JSON in argv[1] in the mode it names, and
    print the figures as JSON."""
    from bench.blocksworld import Instance
    from gpp.planner.search import DEFAULT_STEP_BOUND, GENERATED, INTERPRETED, ITERATIVE_DEEPENING

    spec = json.loads(sys.argv[1])
    instance = Instance(spec["name"], tuple(spec["blocks"]), tuple(spec["start"]), tuple(spec["goal"]))
    pb = first_solve(check_text(program(instance, 14), lint=False).model)
    mode = spec["mode"]
    tier = INTERPRETED if mode == "interpreted" else GENERATED
    started = time.process_time()
    plan = pb.search(DEFAULT_STEP_BOUND, ITERATIVE_DEEPENING, prune=mode == "cut", tier=tier)
    seconds = time.process_time() - started
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    print(json.dumps({"steps": len(plan.steps), "nodes": plan.stats.nodes, "seconds": seconds, "peak_mib": peak}))


def search_table(quick: bool) -> None:
    """`search` with iterative deepening, cut and uncut (see the module's docstring)."""
    from bench.blocksworld import random_instance

    # Every mode on the towers of 8 and 10 blocks; the others cut only (uncut, they take long).
    instances = [(tower(n), SEARCH_MODES) for n in ((6, 8) if quick else (8, 10))]
    if not quick:
        instances += [(tower(12), SEARCH_MODES[:1])]
        instances += [(random_instance(n, seed), SEARCH_MODES[:1]) for n in (8, 10) for seed in (1, 2, 3)]
    print("| problem | steps | mode | nodes | CPU | µs/node | peak |")
    print("|---|---:|---|---:|---:|---:|---:|")
    for instance, modes in instances:
        spec = {"name": instance.name, "blocks": instance.blocks, "start": instance.start, "goal": instance.goal}
        for mode in modes:
            code = "from bench.planner import search_child; search_child()"
            run = peer_bench.run_child(
                [sys.executable, "-c", code, json.dumps(spec | {"mode": mode})], peer_bench.ROOT, SEARCH_LIMIT
            )
            if run.ok:
                found = json.loads(run.output.strip().splitlines()[-1])
                nodes, seconds = found["nodes"], found["seconds"]
                cells = [str(found["steps"]), mode, f"{nodes:,}", f"{seconds:.3f} s"]
                cells += [f"{seconds / nodes * 1e6:.0f}", f"{found['peak_mib']:.0f} MiB"]
            else:
                cells = ["", mode, "", f">{SEARCH_LIMIT} s", "", ""]
            print(f"| {instance.name} | " + " | ".join(cells) + " |", flush=True)
    with open("/proc/loadavg", encoding="ascii") as load:
        print(f"\nload average: {load.read().split()[0]}")


_HASHING = {"<method 'get' of 'dict' objects>", "<built-in method builtins.hash>", "__eq__", "__hash__"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="3 to 5 blocks, horizons up to 10")
    parser.add_argument("--budget", type=int, default=20_000, help="reference node budget (default 20,000)")
    parser.add_argument("--count", action="store_true", help="count the reference's nodes exactly (<= 5 blocks)")
    parser.add_argument("--targets", action="store_true", help="time the three target problems of gpp issue #14")
    parser.add_argument("--runs", type=int, default=3, help="runs per target problem, best taken (default 3)")
    parser.add_argument("--profile", action="store_true", help="where the time of `solve` goes (cProfile)")
    parser.add_argument("--blocks", type=int, nargs="+", default=[6, 7], help="towers to profile (default 6 7)")
    parser.add_argument("--bound", action="store_true", help="nodes with and without branch and bound")
    parser.add_argument(
        "--no-bound",
        action="store_true",
        help="--targets/--profile without branch and bound (every node of the reference's)",
    )
    parser.add_argument(
        "--peers", action="store_true", help="beside Fast Downward (with --targets: the targets of gpp issue #27)"
    )
    parser.add_argument(
        "--limit", type=float, default=60, help="--peers: CPU seconds a gpp planning may take (default 60)"
    )
    parser.add_argument("--markdown", action="store_true", help="--peers: (its tables are Markdown anyway)")
    parser.add_argument("--search", action="store_true", help="`search` with iterative deepening, cut and uncut")
    args = parser.parse_args()
    if (args.limit != 60 or args.markdown) and not args.peers:
        parser.error("--limit and --markdown apply to --peers only")
    if args.peers:
        if args.no_bound or args.profile or args.bound or args.count:
            parser.error("--peers goes with --targets, --runs, --limit and --quick only")
        peers(args.targets, args.runs, args.limit, args.quick)
        return
    if args.search:
        if args.targets or args.no_bound or args.profile or args.bound or args.count:
            parser.error("--search goes with --quick only")
        search_table(args.quick)
        return
    if args.bound:
        bound_table(args.runs)
        return
    if args.no_bound and not (args.targets or args.profile):
        parser.error("--no-bound applies to --targets and --profile only")
    if args.targets:
        targets(args.runs, prune=not args.no_bound)
        return
    if args.profile:
        profile(args.blocks, prune=not args.no_bound)
        return
    sizes = range(3, 6) if args.quick else range(3, 8)
    horizons = range(2, 11, 2) if args.quick else range(2, 15, 2)
    header = HEADER + (COUNT_HEADER if args.count else [])
    widths = [max(len(h), 10) for h in header]
    print(f"reversing a tower of n blocks; reference stopped after {args.budget:,} nodes (shown as >N)")
    print("  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True)))
    for blocks in sizes:
        for horizon in horizons:
            cells = render(measure(blocks, horizon, args.budget, args.count))
            cells += [""] * (len(header) - len(cells))
            print("  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True)), flush=True)


if __name__ == "__main__":
    main()
