"""`gpp run --profile`: what the planner did, one table row per `plan`/`replan` trace record.

Fed by the trace (never by the planner itself), so a recorded trace can be profiled later.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

PLAN_EVENTS = ("plan", "replan")

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


def plan_records(trace_records: Iterable[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    return [r for r in trace_records if r.get("event") in PLAN_EVENTS]


def profile_table(trace_records: Iterable[Mapping[str, Any]]) -> Table | None:
    """The profile as a rich Table, or None when the run planned nothing."""
    from rich.table import Table

    records = plan_records(trace_records)
    if not records:
        return None
    table = Table(title="planner profile", title_justify="left")
    for name in COLUMNS:
        table.add_column(name, justify="left" if name in ("event", "kind") else "right", no_wrap=True)
    totals = {"nodes": 0, "cache_hits": 0, "pruned": 0, "reward_evaluations": 0, "seconds": 0.0}
    for i, r in enumerate(records, 1):
        for name in totals:
            totals[name] += r.get(name, 0) or 0
        table.add_row(
            str(i),
            _number(r.get("t")),
            str(r.get("event")),
            str(r.get("kind", "")),
            str(r.get("horizon", "")),
            _value(r),
            str(len(r.get("policy") or ())),
            _count(r.get("nodes")),
            _count(r.get("cache_hits")),
            _count(r.get("pruned")),
            _count(r.get("reward_evaluations")),
            _seconds(r.get("seconds")),
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


def render_profile(trace_records: Iterable[Mapping[str, Any]], console: Console) -> None:
    """Print the planner profile of a run: for every plan and re-plan its kind, horizon, value,
    policy length, nodes expanded, cache hits, pruned options, reward evaluations and time."""
    table = profile_table(trace_records)
    if table is None:
        console.print("planner profile: the run did not plan (no `solve` or `search` was reached)")
        return
    console.print(table)


def _value(r: Mapping[str, Any]) -> str:
    if r.get("feasible") is False:
        return "no plan"
    if r.get("kind") == "search":
        return "-"
    return _number(r.get("value"))


def _number(v: Any) -> str:
    if isinstance(v, bool) or not isinstance(v, int | float):
        return "" if v is None else str(v)
    return f"{v:g}"


def _count(v: Any) -> str:
    return f"{v:,}" if isinstance(v, int) and not isinstance(v, bool) else ""


def _seconds(v: Any) -> str:
    if isinstance(v, bool) or not isinstance(v, int | float):
        return ""
    return f"{v * 1000:.1f} ms" if v < 1 else f"{v:.2f} s"
