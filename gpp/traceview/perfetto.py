"""`gpp trace perfetto`: the run as Chrome trace-event JSON (the "JSON object format"), which
ui.perfetto.dev and chrome://tracing open.

One process, the run. Its threads (tracks): `program` (waits as slices, errors), `exogenous
events`, `planner` and `fluents` (instant events), then one track per action and row of the
viewer's lanes, whose activities are complete events (`ph: X`). Numeric series are counters
(`ph: C`). Times are the platform clock in microseconds (`ts`, `dur`, integers).
"""

from __future__ import annotations

import json
from typing import Any

from gpp.runtime.events import ABSENT, SenseEvent
from gpp.traceview.model import RunModel, short_number, show_value

PID = 1
TID_PROGRAM = 1
TID_EXOG = 2
TID_PLANNER = 3
TID_FLUENTS = 4
TID_FIRST_LANE = 10


def micros(t: float) -> int:
    """Platform seconds as whole microseconds (the trace keeps 6 decimals, so nothing is lost)."""
    return round(t * 1_000_000)


def lane_tids(model: RunModel) -> dict[tuple[int, int], int]:
    """The thread id of each (lane, row)."""
    tids: dict[tuple[int, int], int] = {}
    for index, lane in enumerate(model.lanes):
        for row in range(lane.rows):
            tids[(index, row)] = TID_FIRST_LANE + len(tids)
    return tids


def chrome_trace(model: RunModel, *, trace_name: str) -> dict[str, Any]:
    """The trace-event JSON object for a run."""
    events: list[dict[str, Any]] = []
    program = model.program or trace_name

    def meta(name: str, tid: int, args: dict[str, Any]) -> None:
        events.append({"name": name, "ph": "M", "pid": PID, "tid": tid, "ts": 0, "args": args})

    meta("process_name", 0, {"name": f"gpp run: {program}"})
    meta("process_sort_index", 0, {"sort_index": 0})
    tracks = [
        (TID_PROGRAM, "program"),
        (TID_EXOG, "exogenous events"),
        (TID_PLANNER, "planner"),
        (TID_FLUENTS, "fluents"),
    ]
    tids = lane_tids(model)
    for (lane, row), tid in tids.items():
        name = model.lanes[lane].name
        tracks.append((tid, name if row == 0 else f"{name} ({row + 1})"))
    for sort, (tid, name) in enumerate(tracks):
        meta("thread_name", tid, {"name": name})
        meta("thread_sort_index", tid, {"sort_index": sort})

    for activity in model.activities:
        args: dict[str, Any] = {
            "id": activity.id,
            "status": activity.status,
            "mapped": activity.mapped,
            "args": {k: show_value(v) for k, v in activity.args.items()},
            "at": activity.at,
        }
        if activity.reason:
            args["reason"] = activity.reason
        if activity.result is not ABSENT:
            args["result"] = show_value(activity.result)
        if activity.cancelled_at is not None:
            args["cancelled_at_s"] = activity.cancelled_at
        if activity.consumed_at is not None:
            args["taken_at_s"] = activity.consumed_at
            args["taken_by"] = activity.hook
        if activity.unhandled:
            args["unhandled"] = True
        events.append(
            {
                "name": activity.action,
                "cat": f"activity,{activity.status}",
                "ph": "X",
                "pid": PID,
                "tid": tids[(activity.lane, activity.row)],
                "ts": micros(activity.start),
                "dur": micros(activity.stop) - micros(activity.start),
                "args": args,
            }
        )
    for wait in model.waits:
        stop = wait.stop if wait.stop is not None else model.end
        events.append(
            {
                "name": wait.condition if wait.condition.startswith("waiting ") else f"waiting: {wait.condition}",
                "cat": "wait",
                "ph": "X",
                "pid": PID,
                "tid": TID_PROGRAM,
                "ts": micros(wait.start),
                "dur": micros(stop) - micros(wait.start),
                "args": {"statement": wait.statement, "at": wait.at, "resumed": wait.stop is not None},
            }
        )
    for exog in model.exog:
        events.append(
            _instant(
                exog.action,
                "exog",
                exog.t,
                TID_EXOG,
                {"precondition": exog.precondition, "silent": exog.silent},
            )
        )
    for plan in model.plans:
        label = (
            f"{plan.EVENT} ({plan.kind}): value {short_number(plan.value)}"
            if plan.feasible
            else f"{plan.EVENT}: no plan"
        )
        events.append(
            _instant(
                label,
                plan.EVENT,
                plan.t,
                TID_PLANNER,
                {
                    "kind": plan.kind,
                    "feasible": plan.feasible,
                    "value": plan.value,
                    "horizon": plan.horizon,
                    "policy": list(plan.policy),
                    "nodes": plan.nodes,
                    "cache_hits": plan.cache_hits,
                    "pruned": plan.pruned,
                    "reward_evaluations": plan.reward_evaluations,
                    "planning_seconds_wall": plan.seconds,
                },
            )
        )
    for change in model.changes:
        args = {"value": show_value(change.value)}
        if isinstance(change, SenseEvent):
            args["by"] = change.action
        elif change.at:
            args["at"] = change.at
        events.append(
            _instant(f"{change.fluent} = {show_value(change.value)}", change.EVENT, change.t, TID_FLUENTS, args)
        )
    for problem in model.problems:
        args = {"message": problem.message}
        code = getattr(problem, "code", None)
        if code:
            args["code"] = code
        if isinstance(problem.at, str):
            args["at"] = problem.at
        events.append(_instant(f"{problem.EVENT}: {problem.message}", problem.EVENT, problem.t, TID_PROGRAM, args, "g"))
    if model.finish is not None:
        finish = model.finish
        events.append(
            _instant(
                f"finish: {finish.status}",
                "finish",
                finish.t,
                TID_PROGRAM,
                {"status": finish.status, "actions": finish.actions, "failures": finish.failures},
                "g",
            )
        )
    for series in model.series:
        for sample in series.samples:
            events.append(
                {
                    "name": series.name,
                    "cat": series.kind,
                    "ph": "C",
                    "pid": PID,
                    "tid": 0,
                    "ts": micros(sample.t),
                    "args": {"value": sample.value},
                }
            )
    other: dict[str, Any] = {"program": program, "status": model.status, "trace": trace_name, "clock": "platform time"}
    if model.header is not None:
        other["platform"] = model.header.platform
        other["gpp_version"] = model.header.gpp_version
    return {"traceEvents": events, "displayTimeUnit": "ms", "otherData": other}


def _instant(name: str, cat: str, t: float, tid: int, args: dict[str, Any], scope: str = "t") -> dict[str, Any]:
    return {"name": name, "cat": cat, "ph": "i", "s": scope, "pid": PID, "tid": tid, "ts": micros(t), "args": args}


def render_chrome_trace(model: RunModel, *, trace_name: str) -> str:
    return json.dumps(chrome_trace(model, trace_name=trace_name), ensure_ascii=False, indent=None) + "\n"


__all__ = ["chrome_trace", "lane_tids", "micros", "render_chrome_trace"]
