"""`gpp trace summary`: the run on a terminal. A timeline with one row per action (its
activities as bars; one row per call, `goto(room1)`, `goto(room2)`, when an action has a few
different ones), rows for exogenous events, plans, waits and problems, a sparkline per numeric
series, a band row per fluent with other values (where the robot is) and a time axis in
seconds; then the plans, the exogenous events, what operators did at the console, what failed
or was cancelled, and how the run ended. Plain text (no colour) off a terminal."""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Sequence
from typing import TYPE_CHECKING

from gpp.runtime.events import ExogEvent
from gpp.traceview.model import (
    Activity,
    RunModel,
    Series,
    StateSeries,
    action_name,
    format_seconds,
    packed_rows,
    short_number,
)

if TYPE_CHECKING:
    from rich.console import Console, RenderableType
    from rich.text import Text

MIN_WIDTH = 60
LABEL_WIDTH = 20
LIST_LIMIT = 12  # rows per section before "... and N more"
CALL_ROWS = 6  # an action with at most this many different calls gets a row per call

# Glyph and style of a bar cell by activity status.
BAR: dict[str, tuple[str, str]] = {
    "final": ("█", "green"),
    "failed": ("▓", "red"),
    "cancelled": ("▒", "yellow"),
    "running": ("░", "blue"),
}
# Which activity a cell shared by several shows: the most telling.
PRECEDENCE = ("failed", "cancelled", "running", "final")
SPARK = "▁▂▃▄▅▆▇█"


class Timeline:
    """Maps platform time to the cells of a row `width` characters wide."""

    def __init__(self, start: float, end: float, width: int) -> None:
        self.start = start
        self.width = width
        self.span = end - start if end > start else 1.0

    def cell(self, t: float) -> int:
        return min(self.width - 1, max(0, int((t - self.start) / self.span * self.width)))

    def cells(self, t0: float, t1: float) -> range:
        """The cells an interval covers (at least one)."""
        first = self.cell(t0)
        last = max(first, min(self.width - 1, math.ceil((t1 - self.start) / self.span * self.width) - 1))
        return range(first, last + 1)

    def time(self, cell: int) -> float:
        return self.start + cell * self.span / self.width


def render_summary(model: RunModel, console: Console) -> None:
    """Print the summary at the console's width (at least MIN_WIDTH), without trailing blanks."""
    with console.capture() as capture:
        for part in summary_parts(model, max(MIN_WIDTH, console.width)):
            console.print(part)
    lines = [_TRAILING_BLANKS.sub(r"\1", line) for line in capture.get().split("\n")]
    console.file.write("\n".join(lines))
    console.file.flush()


# Blanks at the end of a line, before any closing colour codes.
_TRAILING_BLANKS = re.compile(r" +((?:\x1b\[[0-9;]*m)*)$")


def summary_parts(model: RunModel, width: int) -> list[RenderableType]:
    from rich.text import Text

    parts: list[RenderableType] = [_title(model, width), _counts(model, width), Text()]
    parts.extend(_timeline(model, width))
    parts.append(_legend(model, width))
    for section in (_plans, _exog, _operator, _troubles, _waits_section, _problems, _series, _states):
        body = section(model, width)
        if body:
            parts.append(Text())
            parts.extend(body)
    parts.append(Text())
    parts.append(_ending(model, width))
    return parts


# ---------------------------------------------------------------- heading


def _title(model: RunModel, width: int) -> Text:
    from rich.text import Text

    items = [Text(model.program or "trace", style="bold")]
    if model.header is not None:
        world = f" (world {model.header.world})" if model.header.world else ""
        items[0].append(f" on {model.header.platform}{world}", style="")
    items.append(Text(model.status, style=_status_style(model.status)))
    items.append(Text(f"{format_seconds(model.end)} platform time"))
    return _flow(items, width, " · ")


def _status_style(status: str) -> str:
    return {"finished": "bold green", "incomplete": "bold yellow"}.get(status, "bold red")


def _counts(model: RunModel, width: int) -> Text:
    from rich.text import Text

    by_status: dict[str, int] = defaultdict(int)
    for activity in model.activities:
        by_status[activity.status] += 1
    detail = ", ".join(f"{by_status[s]} {s}" for s in ("failed", "cancelled", "running") if by_status[s])
    items = [
        _plural(len(model.activities), "activity", "activities")
        + (f" ({detail})" if detail else "")
        + f" in {_plural(len(model.lanes), 'lane')}",
        _plural(len(model.exog), "exogenous event"),
        _plural(len(model.plans), "plan"),
    ]
    if model.waits:
        items.append(_plural(len(model.waits), "wait"))
    return _flow([Text(i, style="dim") for i in items], width, " · ", style="dim")


def _flow(items: Sequence[Text], width: int, separator: str, indent: int = 0, style: str = "") -> Text:
    """The items in a line, separated; a line that would be too wide breaks between items."""
    from rich.text import Text

    text = Text(" " * indent)
    column = indent
    for i, item in enumerate(items):
        if i and column + len(separator) + len(item) > width:
            text.append("\n" + " " * indent)
            column = indent
        elif i:
            text.append(separator, style=style)
            column += len(separator)
        text.append_text(item)
        column += len(item)
    return text


def _plural(n: int, word: str, plural: str | None = None) -> str:
    return f"{n} {word if n == 1 else plural or word + 's'}"


# ---------------------------------------------------------------- the timeline


def _timeline(model: RunModel, width: int) -> list[Text]:
    from rich.text import Text

    lanes = [(label, rows) for lane in model.lanes for label, rows in _lane_rows(lane.name, lane.activities)]
    states = model.states[:LIST_LIMIT]
    names = [label for label, _ in lanes] + [s.name for s in model.series] + [s.name for s in states]
    names += ["exogenous", "plans"]
    label_width = min(LABEL_WIDTH, max(len(n) for n in names))
    tw = max(10, width - label_width - 6)
    scale = Timeline(model.start, model.end, tw)
    rows: list[Text] = []

    def row(label: str, count: str, cells: Text, style: str = "") -> None:
        line = Text()
        line.append(_fit(label, label_width).ljust(label_width), style=style or "bold")
        line.append(count.rjust(4), style="dim")
        line.append(" │", style="dim")
        line.append_text(cells)
        rows.append(line)

    for label, activity_rows in lanes:
        count = sum(len(r) for r in activity_rows)
        for r, activities in enumerate(activity_rows):
            row(label if r == 0 else "", f"×{count}" if r == 0 else "", _bars(activities, scale))
    if model.exog:
        marks = [(e.t, "◇" if e.precondition is False else "◆", "magenta") for e in model.exog]
        row("exogenous", f"×{len(model.exog)}", _marks(marks, scale), "magenta")
    if model.plans:
        marks = [(p.t, ("▲" if p.EVENT == "plan" else "△") if p.feasible else "×", "cyan") for p in model.plans]
        row("plans", f"×{len(model.plans)}", _marks(marks, scale), "cyan")
    if model.waits:
        row("waiting", f"×{len(model.waits)}", _waits(model, scale), "yellow")
    if model.problems:
        marks = [(p.t, "!", "bold red") for p in model.problems]
        row(model.problems[-1].EVENT, "", _marks(marks, scale), "red")
    for series in model.series:
        row(series.name, "", _sparkline(series, scale), "blue")
    for state in states:
        row(state.name, "", _bands(state, scale), "green")
    if len(model.states) > len(states):
        rows.append(Text(f"  … and {len(model.states) - len(states)} more fluents (`gpp trace html` shows them all)"))
    rows.extend(_axis(scale, label_width))
    return rows


def _lane_rows(name: str, activities: Sequence[Activity]) -> list[tuple[str, list[list[Activity]]]]:
    """The rows of an action's activities: (label, rows of activities that do not overlap).
    An action with a few different calls gets a label and rows per call, so that which went
    where stays visible; one with many keeps one label, its calls written in the table below."""
    calls = list(dict.fromkeys(a.action for a in activities))
    groups = [(call, [a for a in activities if a.action == call]) for call in calls]
    if len(calls) > CALL_ROWS:
        groups = [(name, list(activities))]
    return [(label, packed_rows(members)) for label, members in groups]


def _fit(text: str, width: int) -> str:
    """The text cut to `width`; a call keeps its arguments and loses the end of its name
    (`navigate_to…(table)`), since its arguments tell the rows of one action apart."""
    if len(text) <= width:
        return text
    name, paren, args = text.partition("(")
    if paren and len(args) + 3 <= width:
        return name[: width - len(args) - 2] + "…(" + args
    return text[: width - 1] + "…"


def _bars(activities: Sequence[Activity], scale: Timeline) -> Text:
    from rich.text import Text

    rank = list(PRECEDENCE)
    owner: list[Activity | None] = [None] * scale.width
    starts: list[int] = [0] * scale.width
    for activity in activities:
        starts[scale.cell(activity.start)] += 1
        for c in scale.cells(activity.start, activity.stop):
            held = owner[c]
            if held is None or rank.index(activity.status) < rank.index(held.status):
                owner[c] = activity
    text = Text()
    previous: Activity | None = None
    shade = False
    for c, held in enumerate(owner):
        if held is None:
            text.append(" ")
            previous = None
            continue
        if starts[c] > 1 and held.status != "final":
            # Several attempts in one cell, one of them failed or cancelled (a quick retry):
            # their number, so that none is hidden behind another.
            text.append(str(starts[c]) if starts[c] < 10 else "+", style=f"bold {BAR[held.status][1]}")
            previous = held
            continue
        if previous is not None and held is not previous:
            shade = not shade  # neighbouring activities in alternating shades
        glyph, style = BAR.get(held.status, BAR["final"])
        text.append(glyph, style=f"bright_{style}" if shade else style)
        previous = held
    return text


def _marks(marks: Sequence[tuple[float, str, str]], scale: Timeline) -> Text:
    """Point marks; a cell with several shows their number."""
    from rich.text import Text

    count: list[int] = [0] * scale.width
    glyph: list[tuple[str, str]] = [(" ", "")] * scale.width
    for t, mark, style in marks:
        c = scale.cell(t)
        count[c] += 1
        glyph[c] = (mark, style)
    text = Text()
    for n, (mark, style) in zip(count, glyph, strict=True):
        text.append(mark if n <= 1 else (str(n) if n < 10 else "+"), style=style)
    return text


def _waits(model: RunModel, scale: Timeline) -> Text:
    from rich.text import Text

    cells = [" "] * scale.width
    for wait in model.waits:
        span = scale.cells(wait.start, wait.stop if wait.stop is not None else model.end)
        for c in span:
            cells[c] = "┄"
        cells[span.start] = "├"
    return Text("".join(cells), style="yellow")


def _sparkline(series: Series, scale: Timeline) -> Text:
    """The series as its value held from each sample to the next, scaled to its range."""
    from rich.text import Text

    values = [s.value for s in series.samples]
    low, high = min(values), max(values)
    cells: list[str] = []
    samples = sorted(series.samples, key=lambda s: s.t)
    index = -1
    for c in range(scale.width):
        t_end = scale.time(c + 1)
        while index + 1 < len(samples) and samples[index + 1].t < t_end:
            index += 1
        if index < 0:
            cells.append(" ")
            continue
        value = samples[index].value
        level = 3 if high == low else round((value - low) / (high - low) * (len(SPARK) - 1))
        cells.append(SPARK[level])
    return Text("".join(cells), style="blue")


def _bands(state: StateSeries, scale: Timeline) -> Text:
    """The fluent's values as bands: each value written where its band starts (cut to the
    band), the rest of the band drawn; neighbouring bands in alternating shades. Before the
    first change (the initial value, which the trace does not hold) the row is blank."""
    from rich.text import Text

    cells: list[tuple[str, int]] = [(" ", -1)] * scale.width
    shade = 0
    for segment in state.segments:
        span = scale.cells(segment.start, segment.stop)
        if segment.stop <= segment.start and span.start > 0 and cells[span.start][1] >= 0:
            continue  # a value held for no time, where a band is drawn already
        shade = 1 - shade
        name = segment.value
        for i, c in enumerate(span):
            cells[c] = (name[i] if i < len(name) and len(span) > 1 else "▬" if len(span) > 1 else "│", shade)
    text = Text()
    for glyph, band in cells:
        text.append(glyph, style="" if band < 0 else ("green" if band == 0 else "bright_cyan"))
    return text


def _axis(scale: Timeline, label_width: int) -> list[Text]:
    """The time axis: ticks at a round step in seconds, labelled where the label fits."""
    from rich.text import Text

    step = _tick_step(scale.span, scale.width)
    line = ["─"] * scale.width
    labels = [" "] * scale.width
    free = 0
    t = math.ceil(scale.start / step - 1e-9) * step
    while t <= scale.start + scale.span * (1 + 1e-9):
        c = scale.cell(t)
        line[c] = "┴"
        label = _tick_label(t, step)
        at = min(c, scale.width - len(label))  # the last label may end at the axis' end
        if at >= free:
            labels[at : at + len(label)] = list(label)
            free = at + len(label) + 2
        t += step
    axis = Text(" " * (label_width + 4) + " └" + "".join(line[1:]), style="dim")
    return [axis, Text("time".rjust(label_width + 4) + "  " + "".join(labels).rstrip(), style="dim")]


def _tick_step(span: float, width: int) -> float:
    """A round step (1, 2 or 5 × 10^k seconds) giving ticks at least 10 cells apart."""
    target = span * 10 / max(width, 1)
    power = 10 ** math.floor(math.log10(target)) if target > 0 else 1.0
    for factor in (1, 2, 5, 10):
        if factor * power >= target:
            return float(factor * power)
    return float(10 * power)


def _tick_label(t: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step))) if step < 1 else 0
    return f"{t:.{decimals}f} s"


def _legend(model: RunModel, width: int) -> Text:
    from rich.text import Text

    def item(glyph: str, style: str, meaning: str) -> Text:
        text = Text(glyph, style=style)
        text.append(f" {meaning}", style="dim")
        return text

    statuses = {a.status for a in model.activities}
    items = [
        item(glyph, style, status) for status, (glyph, style) in BAR.items() if status in statuses or status == "final"
    ]
    if model.exog:
        items.append(item("◆", "magenta", "exogenous"))
        if any(e.precondition is False for e in model.exog):
            items.append(item("◇", "magenta", "precondition false"))
    if model.plans:
        items.append(item("▲", "cyan", "plan"))
        if any(p.EVENT == "replan" for p in model.plans):
            items.append(item("△", "cyan", "replan"))
        if any(not p.feasible for p in model.plans):
            items.append(item("×", "cyan", "no plan"))
    if model.waits:
        items.append(item("├┄", "yellow", "waiting"))
    if model.problems:
        items.append(item("!", "bold red", model.problems[-1].EVENT))
    if model.exog or model.plans or model.problems or _quick_retries(model):
        items.append(item("2-9", "", "several at once"))
    return _flow(items, width, "  ", indent=2)


def _quick_retries(model: RunModel) -> bool:
    """Whether an activity that did not end `final` took no time (its cell may show a count)."""
    return any(a.status != "final" and a.stop <= a.start for a in model.activities)


# ---------------------------------------------------------------- the sections


def _heading(title: str) -> Text:
    from rich.text import Text

    return Text(title, style="bold underline")


def _table(columns: Sequence[tuple[str, str]], rows: Sequence[Sequence[str | Text]], width: int) -> RenderableType:
    """A borderless table; a column whose justify is `fold` wraps when the table is too wide."""
    from rich.table import Table

    table = Table(box=None, pad_edge=False, show_edge=False, header_style="dim", expand=False)
    for name, justify in columns:
        if justify == "fold":
            table.add_column(name, overflow="fold")
        else:
            table.add_column(name, justify="right" if justify == "right" else "left", no_wrap=True)
    for cells in rows:
        table.add_row(*cells)
    return table


def _more(count: int) -> list[RenderableType]:
    from rich.text import Text

    if count <= LIST_LIMIT:
        return []
    return [Text(f"  … and {count - LIST_LIMIT} more (`gpp trace html` shows them all)", style="dim")]


def _plans(model: RunModel, width: int) -> list[RenderableType]:
    if not model.plans:
        return []
    rows = []
    for plan in model.plans[:LIST_LIMIT]:
        policy = " → ".join(plan.policy) if plan.feasible else "no feasible plan"
        rows.append(
            [
                format_seconds(plan.t),
                plan.kind + (" (replan)" if plan.EVENT == "replan" else ""),
                short_number(plan.value),
                str(plan.horizon),
                str(plan.nodes),
                f"{plan.seconds:.3f} s",
                policy or "(nothing to do)",
            ]
        )
    columns = [
        ("at", "right"),
        ("kind", "left"),
        ("value", "right"),
        ("horizon", "right"),
        ("nodes", "right"),
        ("took", "right"),
        ("policy", "fold"),
    ]
    return [_heading("plans"), _table(columns, rows, width), *_more(len(model.plans))]


def _exog(model: RunModel, width: int) -> list[RenderableType]:
    if not model.exog:
        return []
    from rich.text import Text

    by_name: dict[str, list[ExogEvent]] = defaultdict(list)
    for event in model.exog:
        by_name[action_name(event.action)].append(event)
    rows: list[list[str | Text]] = []
    for name, events in list(by_name.items())[:LIST_LIMIT]:
        same = len({e.action for e in events}) == 1
        note = Text()
        for i, event in enumerate(events[:6]):
            if i:
                note.append(", ")
            note.append(format_seconds(event.t))
            if not same:
                note.append(" " + event.action[len(name) :], style="magenta")
            if event.precondition is False:
                note.append(" (precondition false)", style="yellow")
            if event.failed:
                note.append(" (effect failed)", style="red")
        if len(events) > 6:
            note.append(f", … {len(events) - 6} more", style="dim")
        rows.append([events[0].action if same else name, f"×{len(events)}", note])
    columns = [("action", "left"), ("", "right"), ("when", "fold")]
    return [_heading("exogenous events"), _table(columns, rows, width), *_more(len(by_name))]


def _operator(model: RunModel, width: int) -> list[RenderableType]:
    """What operators did at the console: when, what, who."""
    if not model.operator:
        return []
    rows: list[list[str | Text]] = [
        [format_seconds(e.t), e.command, e.action or "", e.client or ""] for e in model.operator[:LIST_LIMIT]
    ]
    columns = [("t", "right"), ("command", "left"), ("action", "fold"), ("who", "fold")]
    return [_heading("operator (console)"), _table(columns, rows, width), *_more(len(model.operator))]


def _troubles(model: RunModel, width: int) -> list[RenderableType]:
    from rich.text import Text

    troubles = [a for a in model.activities if a.status != "final"]
    if not troubles:
        return []
    rows: list[list[str | Text]] = []
    for activity in troubles[:LIST_LIMIT]:
        _, style = BAR.get(activity.status, BAR["final"])
        why = activity.reason or activity.cancel_reason or ""
        if activity.unhandled:
            why = (why + "; " if why else "") + "not handled by the program"
        rows.append(
            [
                format_seconds(activity.start),
                activity.action,
                Text(activity.status, style=style),
                why,
                activity.at or "",
            ]
        )
    columns = [("started", "right"), ("activity", "left"), ("status", "left"), ("why", "fold"), ("at", "left")]
    return [
        _heading("failed, cancelled and unfinished activities"),
        _table(columns, rows, width),
        *_more(len(troubles)),
    ]


def _waits_section(model: RunModel, width: int) -> list[RenderableType]:
    if not model.waits:
        return []
    rows = [
        [
            format_seconds(w.start),
            format_seconds(w.stop) if w.stop is not None else "end",
            w.statement,
            w.condition,
            w.at or "",
        ]
        for w in model.waits[:LIST_LIMIT]
    ]
    columns = [("from", "right"), ("until", "right"), ("statement", "fold"), ("waits for", "fold"), ("at", "left")]
    return [_heading("waits"), _table(columns, rows, width), *_more(len(model.waits))]


def _problems(model: RunModel, width: int) -> list[RenderableType]:
    from rich.text import Text

    if not model.problems:
        return []
    out: list[RenderableType] = [_heading("how the run stopped")]
    for problem in model.problems:
        text = Text(f"  {format_seconds(problem.t)}  ")
        code = getattr(problem, "code", None)
        text.append(f"{problem.EVENT}{f'[{code}]' if code else ''}: ", style="bold red")
        text.append(problem.message)
        at = problem.at if isinstance(problem.at, str) else None
        if at:
            text.append(f"  at {at}", style="dim")
        out.append(text)
    return out


def _series(model: RunModel, width: int) -> list[RenderableType]:
    if not model.series:
        return []
    rows = []
    for series in model.series[:LIST_LIMIT]:
        values = [s.value for s in series.samples]
        rows.append(
            [
                series.name,
                series.kind,
                str(len(values)),
                short_number(values[0]),
                short_number(values[-1]),
                short_number(min(values)),
                short_number(max(values)),
            ]
        )
    columns = [
        ("series", "left"),
        ("from", "left"),
        ("samples", "right"),
        ("first", "right"),
        ("last", "right"),
        ("min", "right"),
        ("max", "right"),
    ]
    return [_heading("numeric values over time"), _table(columns, rows, width), *_more(len(model.series))]


def _states(model: RunModel, width: int) -> list[RenderableType]:
    if not model.states:
        return []
    rows = []
    for state in model.states[:LIST_LIMIT]:
        first = state.segments[0]
        rows.append(
            [state.name, str(len(state.segments)), format_seconds(first.start), " → ".join(_values_in_order(state))]
        )
    columns = [("fluent", "left"), ("changes", "right"), ("first", "right"), ("values in order", "fold")]
    return [_heading("states over time"), _table(columns, rows, width), *_more(len(model.states))]


def _values_in_order(state: StateSeries, limit: int = 8) -> list[str]:
    """The values the fluent took, one per change (repeats kept), the first `limit` and the last."""
    values = [s.value for s in state.segments]
    return values if len(values) <= limit + 1 else [*values[:limit], "…", values[-1]]


def _ending(model: RunModel, width: int) -> Text:
    from rich.text import Text

    if model.finish is None:
        return _flow(
            [
                Text("the trace ends without a `finish` record", style="bold yellow"),
                Text(f"at {format_seconds(model.end)}", style="dim"),
                Text("(the run was killed, or is still running)", style="dim"),
            ],
            width,
            " ",
        )
    finish = model.finish
    head = Text("finish ", style="dim")
    head.append(finish.status, style=_status_style(finish.status))
    head.append(f" at {format_seconds(finish.t)}:")
    failures = Text(_plural(finish.failures, "failure"))
    if finish.unhandled_failures:
        failures.append(f" ({finish.unhandled_failures} not handled)", style="red")
    failures.append(",")
    items = [
        head,
        Text(f"{_plural(finish.actions, 'action')} started,"),
        failures,
        Text(_plural(finish.exog_events, "exogenous event")),
    ]
    return _flow(items, width, " ")


__all__ = ["Timeline", "render_summary", "summary_parts"]
