"""Scaling of the `solve` planners: reversing a tower of n blocks (3 to 7) in the blocks world
of examples/blocks_planning.gpp, for horizons up to 14.

Run: .venv/bin/python bench/planner.py [--quick] [--budget N] [--count]

For every (blocks, horizon) it runs the production planner (gpp.planner.dp) and the reference
planner (gpp.planner.reference, the plain recursive definition) and prints their node counts,
CPU seconds and the ratios. The reference is exponential: it is stopped after --budget nodes
and then shown as ">N" with the time it had taken so far, and the ratio as ">=" the budget over
the production's nodes: a lower bound, never an invented number. With --count the exact number
of nodes the reference would expand is counted as well (by a memoised count that
tests/test_planner.py checks against the reference's own count), for towers of up to five
blocks. Times are CPU seconds of this process (the machine may be shared), best of one run.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

from gpp.check import check_text
from gpp.planner.problem import PlanningProblem, first_solve
from gpp.planner.reference import NodeBudgetExceeded

NAMES = "abcdefg"


def tower_program(blocks: int, horizon: int) -> str:
    """A tower blocks[0] on blocks[1] on ... on the table, to be reversed: the optimum moves
    every block once (the top one to the table, each next one onto the one moved before)."""
    names = NAMES[:blocks]
    initially = " ".join(f"({names[i]}) = {names[i + 1] if i + 1 < blocks else 'table'};" for i in range(blocks))
    goal = " & ".join(f"loc({names[i]}) == {names[i - 1] if i > 0 else 'table'}" for i in range(blocks))
    return f"""
symbol domain block = {{{", ".join(names)}}}
symbol domain location = block | {{table}}
location fluent loc(block x) {{ initially: {initially} }}
action stack(block x, location y) {{
precondition:
    x != y & loc(x) != y & (!exists(block z) loc(z) == x) & (y == table | !exists(block z) loc(z) == y)
effect:
    loc(x) = y;
}}
bool function goal() = {goal}
number function reward() = if (goal()) 100 else -1
procedure main() {{
    solve({horizon}, reward()) while (!goal()) pick (block x) pick (location y) stack(x, y);
}}
"""


def tower_problem(blocks: int, horizon: int) -> PlanningProblem:
    result = check_text(tower_program(blocks, horizon), lint=False)
    assert result.errors == 0, [d.message for d in result.diagnostics]
    return first_solve(result.model)


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
    "ref nodes",
    "ref cpu s",
    "node ratio",
    "time ratio",
]
COUNT_HEADER = ["ref nodes (counted)", "counted ratio"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="3 to 5 blocks, horizons up to 10")
    parser.add_argument("--budget", type=int, default=20_000, help="reference node budget (default 20,000)")
    parser.add_argument("--count", action="store_true", help="count the reference's nodes exactly (<= 5 blocks)")
    args = parser.parse_args()
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
