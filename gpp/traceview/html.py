"""`gpp trace html`: the run as one self-contained HTML page (inline CSS and JS, the run's data
embedded as JSON, no network access needed to open it).

The page is the template `viewer.html` with `viewer.css`, `viewer.js` and the data put in.
The data (`page_data`) is plain JSON: the run's lanes, activities, exogenous events, plans,
fluent changes, waits, problems, numeric series, the bands of the other fluents' values, and
the source lines the records point at (read from the program files at generation time, when
they can be found).
"""

from __future__ import annotations

import html
import importlib.resources
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gpp import __version__
from gpp.runtime.events import ABSENT, SenseEvent
from gpp.traceview.model import RunModel, parse_location, show_value

SOURCE_CONTEXT = 1  # lines embedded before and after each line a record points at
MAX_SOURCE_LINE = 240  # characters of a source line kept


@dataclass(slots=True)
class Sources:
    """The program lines a page embeds: file (as the trace names it) → line number → text."""

    lines: dict[str, dict[int, str]] = field(default_factory=dict)
    missing: list[str] = field(default_factory=list)  # files named by the trace but not found


def collect_sources(model: RunModel, search: Sequence[Path]) -> Sources:
    """The lines around each source location of the trace, from the files as they are now.
    A relative file is looked for in each directory of `search` in turn."""
    wanted: dict[str, set[int]] = {}
    for at in model.locations():
        loc = parse_location(at)
        if loc is None:
            continue
        file, line, _ = loc
        around = wanted.setdefault(file, set())
        around.update(range(max(1, line - SOURCE_CONTEXT), line + SOURCE_CONTEXT + 1))
    sources = Sources()
    for file, numbers in wanted.items():
        text = _read_source(file, search)
        if text is None:
            sources.missing.append(file)
            continue
        lines = text.splitlines()
        sources.lines[file] = {n: lines[n - 1][:MAX_SOURCE_LINE] for n in sorted(numbers) if 0 < n <= len(lines)}
    return sources


def _read_source(file: str, search: Sequence[Path]) -> str | None:
    path = Path(file)
    candidates = [path] if path.is_absolute() else [directory / path for directory in search]
    for candidate in candidates:
        try:
            return candidate.read_text(encoding="utf-8", errors="replace")
        except OSError:
            continue
    return None


def page_data(model: RunModel, sources: Sources, *, trace_name: str, notes: Sequence[str] = ()) -> dict[str, Any]:
    """Everything the page shows, as JSON-ready data (indices refer into the lists)."""
    header = model.header
    index = {id(a): i for i, a in enumerate(model.activities)}
    all_notes = list(notes)
    if sources.missing:
        shown = ", ".join(sources.missing[:3]) + (" …" if len(sources.missing) > 3 else "")
        all_notes.append(f"Source lines are not shown for {shown}: not found when the page was made.")
    if model.finish is None:
        all_notes.append("The trace has no `finish` record: the run was killed, or was still running.")
    return {
        "gppVersion": __version__,
        "traceFile": trace_name,
        "records": len(model.events),
        "program": model.program,
        "platform": header.platform if header else None,
        "world": header.world if header else None,
        "scenario": header.scenario if header else None,
        "seed": header.seed if header else None,
        "started": header.started if header else None,
        "status": model.status,
        "start": model.start,
        "end": model.end,
        "notes": all_notes,
        "lanes": [
            {
                "name": lane.name,
                "rows": lane.rows,
                "count": len(lane.activities),
                "activities": [index[id(a)] for a in lane.activities],
            }
            for lane in model.lanes
        ],
        "activities": [
            {
                "id": a.id,
                "action": a.action,
                "lane": a.lane,
                "row": a.row,
                "start": a.start,
                "stop": a.stop,
                "status": a.status,
                "mapped": a.mapped,
                "args": [f"{k}: {show_value(v)}" for k, v in a.args.items()],
                "at": a.at,
                "silent": a.silent,
                "reason": a.reason,
                "result": None if a.result is ABSENT else show_value(a.result),
                "cancelledAt": a.cancelled_at,
                "cancelReason": a.cancel_reason,
                "consumedAt": a.consumed_at,
                "hook": a.hook,
                "unhandled": a.unhandled,
            }
            for a in model.activities
        ],
        "exog": [
            {"t": e.t, "action": e.action, "precondition": e.precondition, "silent": e.silent, "failed": e.failed}
            for e in model.exog
        ],
        "operator": [{"t": o.t, "command": o.command, "action": o.action, "client": o.client} for o in model.operator],
        "plans": [
            {
                "t": p.t,
                "event": p.EVENT,
                "kind": p.kind,
                "feasible": p.feasible,
                "value": p.value,
                "horizon": p.horizon,
                "policy": list(p.policy),
                "nodes": p.nodes,
                "cacheHits": p.cache_hits,
                "pruned": p.pruned,
                "rewardEvaluations": p.reward_evaluations,
                "seconds": p.seconds,
            }
            for p in model.plans
        ],
        "changes": [
            {
                "t": c.t,
                "event": c.EVENT,
                "fluent": c.fluent,
                "value": show_value(c.value),
                "action": c.action if isinstance(c, SenseEvent) else None,
                "at": None if isinstance(c, SenseEvent) else c.at,
            }
            for c in model.changes
        ],
        "waits": [
            {"start": w.start, "stop": w.stop, "statement": w.statement, "condition": w.condition, "at": w.at}
            for w in model.waits
        ],
        "problems": [
            {
                "t": p.t,
                "event": p.EVENT,
                "code": getattr(p, "code", None),
                "message": p.message,
                "at": p.at if isinstance(p.at, str) else None,
            }
            for p in model.problems
        ],
        "series": [
            {
                "name": s.name,
                "kind": s.kind,
                "samples": [{"t": x.t, "v": x.value, "label": x.label, "at": x.at} for x in s.samples],
            }
            for s in model.series
        ],
        "states": [
            {
                "name": s.name,
                "values": s.values,
                "segments": [
                    {"start": g.start, "stop": g.stop, "value": g.value, "label": g.label} for g in s.segments
                ],
            }
            for s in model.states
        ],
        "sources": {file: {str(n): text for n, text in lines.items()} for file, lines in sources.lines.items()},
    }


def _resource(name: str) -> str:
    return importlib.resources.files("gpp.traceview").joinpath(name).read_text("utf-8")


def embed_json(data: Mapping[str, Any]) -> str:
    """JSON that is safe inside a <script> element: `<`, `>` and `&` only ever occur inside
    JSON strings, where their \\u escapes mean the same."""
    text = json.dumps(data, ensure_ascii=False, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def render_page(data: Mapping[str, Any]) -> str:
    """The page: the template with its CSS, JS and data in place."""
    title = f"{data.get('program') or 'trace'} · gpp trace"
    page = _resource("viewer.html")
    for placeholder, value in (
        ("__GPP_VERSION__", html.escape(__version__)),
        ("__GPP_TITLE__", html.escape(title)),
        ("__GPP_CSS__", _resource("viewer.css")),
        ("__GPP_JS__", _resource("viewer.js")),
    ):
        page = page.replace(placeholder, value)
    # The data last: nothing in it is taken for a placeholder.
    return page.replace("__GPP_DATA__", embed_json(data))


def html_page(
    model: RunModel, *, trace_name: str, search: Sequence[Path], notes: Sequence[str] = ()
) -> tuple[str, Sources]:
    """The page for a run, and the sources it embeds (to report the missing ones)."""
    sources = collect_sources(model, search)
    return render_page(page_data(model, sources, trace_name=trace_name, notes=notes)), sources


__all__ = ["Sources", "collect_sources", "embed_json", "html_page", "page_data", "render_page"]
