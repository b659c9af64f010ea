"""`gpp run --profile`: what the planner did, one table row per `plan`/`replan` trace event.

Fed by the trace (never by the planner itself), so a recorded trace can be profiled later.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from gpp.codes import R0010
from gpp.runtime.events import ErrorEvent, EventBase, PlanEvent, ReplanEvent

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

COLUMNS = (
    "#",
    "t",
    "event",
    "kind",
    "horizon",
    "value",
    "policy",
    "nodes",
    "cache hits",
    "pruned",
    "rewards",
    "time",
)


def plan_events(events: Iterable[EventBase]) -> list[PlanEvent | ReplanEvent]:
    return [e for e in events if isinstance(e, PlanEvent | ReplanEvent)]


def profile_table(events: Iterable[EventBase]) -> Table | None:
    """The profile as a rich Table, or None when the run planned nothing."""
    from rich.table import Table

    records = plan_events(events)
    if not records:
        return None
    table = Table(title="planner profile", title_justify="left")
    for name in COLUMNS:
        table.add_column(name, justify="left" if name in ("event", "kind") else "right", no_wrap=True)
    totals = {"nodes": 0, "cache_hits": 0, "pruned": 0, "reward_evaluations": 0, "seconds": 0.0}
    for i, r in enumerate(records, 1):
        totals["nodes"] += r.nodes
        totals["cache_hits"] += r.cache_hits
        totals["pruned"] += r.pruned
        totals["reward_evaluations"] += r.reward_evaluations
        totals["seconds"] += r.seconds
        table.add_row(
            str(i),
            _number(r.t),
            r.EVENT,
            r.kind,
            str(r.horizon),
            _value(r),
            str(len(r.policy)),
            _count(r.nodes),
            _count(r.cache_hits),
            _count(r.pruned),
            _count(r.reward_evaluations),
            _seconds(r.seconds),
        )
    if len(records) > 1:
        table.add_section()
        table.add_row(
            "",
            "",
            "total",
            "",
            "",
            "",
            "",
            _count(totals["nodes"]),
            _count(totals["cache_hits"]),
            _count(totals["pruned"]),
            _count(totals["reward_evaluations"]),
            _seconds(totals["seconds"]),
        )
    return table


PLANNING_ABORTED = R0010.code


def render_profile(events: Iterable[EventBase], console: Console) -> None:
    """Print the planner profile of a run: for every plan and re-plan its kind, horizon, value,
    policy length, nodes expanded, cache hits, pruned options, reward evaluations and time."""
    events = list(events)
    table = profile_table(events)
    # Planning that stopped on an error (R0010: a step bound, a loop without costed steps, a bad
    # horizon) made no plan record, but it was reached.
    aborted = [e for e in events if isinstance(e, ErrorEvent) and e.code == PLANNING_ABORTED]
    if table is None and not aborted:
        console.print("planner profile: the run did not plan (no `solve` or `search` was reached)")
        return
    if table is not None:
        console.print(table)
    for e in aborted:
        where = f" at {e.at}" if isinstance(e.at, str) else ""
        console.print(f"planner profile: planning stopped without a plan{where}: {e.message}", markup=False)


def _value(r: PlanEvent | ReplanEvent) -> str:
    if not r.feasible:
        return "no plan"
    if r.kind == "search":
        return "-"
    return _number(r.value)


def _number(v: object) -> str:
    if isinstance(v, bool) or not isinstance(v, int | float):
        return "" if v is None else str(v)
    return f"{v:g}"


def _count(v: object) -> str:
    return f"{v:,}" if isinstance(v, int) and not isinstance(v, bool) else ""


def _seconds(v: object) -> str:
    if isinstance(v, bool) or not isinstance(v, int | float):
        return ""
    return f"{v * 1000:.1f} ms" if v < 1 else f"{v:.2f} s"
