"""The trace viewer (`gpp trace summary|html|perfetto`, gpp.traceview): the terminal summary
against golden text (regenerate with GPP_UPDATE_GOLDEN=1 and review the diff), the HTML page's
structure and self-containedness, the Chrome trace-event JSON's structure, and the command's
behaviour on bad input. The page in a real browser: tests/traceview/test_traceview_browser.py."""

from __future__ import annotations

import json
import os
import re
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import (
    ExogEvent,
    FinishEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    decode,
    encode,
)
from gpp.traceview.html import embed_json, html_page
from gpp.traceview.model import build_run_model, load_trace, split_action
from gpp.traceview.perfetto import chrome_trace
from tests.support.cli import run
from tests.support.traces import stopped_run

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "tests" / "golden" / "traceview"
HERE = Path(__file__).parent
UPDATE_GOLDEN = os.environ.get("GPP_UPDATE_GOLDEN") == "1"
ANSI = re.compile(r"\x1b\[[0-9;]*m")


def check_golden(name: str, actual: str) -> None:
    path = GOLDEN / name
    if UPDATE_GOLDEN:
        path.write_text(actual, encoding="utf-8")
        return
    if not path.exists():
        pytest.fail(f"no golden file {path}; create it with GPP_UPDATE_GOLDEN=1")
    assert actual == path.read_text(encoding="utf-8")


def gpp(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """Run the `gpp` command in-process as its console script does: (exit code, stdout, stderr)."""
    result = run(*args)
    return result.returncode, result.stdout, result.stderr


def write_trace(path: Path, events: list[TraceEvent]) -> Path:
    path.write_text("".join(encode(e) + "\n" for e in events), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Real traces: programs of tests/programs and examples run now (relative paths, so their
    source locations are as a user's would be)."""
    out = tmp_path_factory.mktemp("traces")
    cwd = Path.cwd()
    os.chdir(ROOT)
    try:
        traces = {}
        for name, program, platform in (
            ("blocksworld", "examples/blocksworld.gpp", "sim"),
            ("durative", "examples/durative.gpp", None),
            ("sensing", "tests/programs/sensing.gpp", None),
            ("exog_events", "tests/programs/exog_events.gpp", None),
            ("small", "tests/golden/trace/small.gpp", None),
            ("blocked", "tests/runtime_errors/blocked_solve_infeasible.gpp", None),
        ):
            trace = out / f"{name}.jsonl"
            outcome = run_program(Path(program), RunOptions(platform=platform, trace=trace))
            assert outcome.result is not None, name
            traces[name] = trace
        return traces
    finally:
        os.chdir(cwd)


# ---------------------------------------------------------------- the model


def test_activities_are_paired_with_their_update_cancel_and_end() -> None:
    model = build_run_model(stopped_run())
    by_id = {a.id: a for a in model.activities}
    hi, go, again = by_id[1], by_id[2], by_id[3]
    assert (hi.start, hi.stop, hi.status, hi.consumed_at, hi.hook, hi.result) == (0, 1, "final", 1, "call", 21.5)
    assert (go.status, go.stop, go.cancelled_at, go.cancel_reason) == ("running", 4, 4, "the program ended")
    assert (again.status, again.reason, again.consumed_at) == ("failed", "no speaker", None)
    # say("hi") and say("again") overlap: one lane, two rows.
    assert [(lane.name, lane.rows, len(lane.activities)) for lane in model.lanes] == [("say", 2, 2), ("go", 1, 1)]
    assert (hi.row, again.row) == (0, 1)
    assert [(w.start, w.stop, w.condition) for w in model.waits] == [(1, 2, "door_open()")]
    assert [(s.name, s.kind, [x.value for x in s.samples]) for s in model.series] == [
        ("temperature()", "fluent", [21.5]),
        ("battery()", "fluent", [55, 40]),
    ]
    assert model.status == "error" and model.program == "agent.gpp"


def test_numeric_arguments_of_exogenous_events_are_series() -> None:
    events: list[TraceEvent] = [
        ExogEvent(t=1, action='report(80,"ok",[1,2])'),
        ExogEvent(t=2, action='report(75,"a,b",[3])'),
    ]
    [series] = build_run_model(events).series
    assert (series.name, series.kind, [s.value for s in series.samples]) == ("report(·,_,_)", "exog argument", [80, 75])


def test_ground_actions_split_at_top_level_commas_only() -> None:
    assert split_action('say("a, \\"b\\"",[1,2],P{x=1,y=2})') == ("say", ['"a, \\"b\\""', "[1,2]", "P{x=1,y=2}"])
    assert split_action("beep()") == ("beep", [])


# ---------------------------------------------------------------- gpp trace summary


def test_summary_of_the_pinned_small_trace_is_golden(capsys: pytest.CaptureFixture[str]) -> None:
    """tests/golden/traceview/small.jsonl is a copy of a real trace of small.gpp, kept here so
    the viewer's goldens change only when the viewer does."""
    code, out, err = gpp(capsys, "trace", "summary", str(GOLDEN / "small.jsonl"), "--width", "100")
    assert (code, err) == (0, "")
    assert not ANSI.search(out)
    check_golden("small.summary.txt", out)


def test_summary_of_a_run_that_stops_is_golden(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    trace = write_trace(tmp_path / "stopped.jsonl", stopped_run())
    code, out, err = gpp(capsys, "trace", "summary", str(trace), "--width", "80")
    assert (code, err) == (0, "")
    check_golden("stopped.summary.txt", out)


def test_summary_lists_what_operators_did_at_the_console(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    from tests.support.traces import operator_trace

    code, out, err = gpp(capsys, "trace", "summary", str(operator_trace(tmp_path)), "--width", "100")
    assert code == 0, err
    section = out[out.index("operator (console)") :].splitlines()
    rows = [line.split() for line in section[2:4]]
    assert rows == [
        ["0.000", "s", "exog", "door_opened(back)", "10.0.0.7", "via", "127.0.0.1"],
        ["0.000", "s", "start", "127.0.0.1"],
    ]
    model = build_run_model(load_trace(operator_trace(tmp_path)).events)
    assert [(o.command, o.client) for o in model.operator] == [
        ("exog", "10.0.0.7 via 127.0.0.1"),
        ("start", "127.0.0.1"),
    ]


@pytest.mark.parametrize("width", [80, 120])
def test_summary_fits_80_to_120_columns(
    capsys: pytest.CaptureFixture[str], runs: dict[str, Path], width: int, tmp_path: Path
) -> None:
    traces = [*runs.values(), write_trace(tmp_path / "stopped.jsonl", stopped_run())]
    for trace in traces:
        code, out, _ = gpp(capsys, "trace", "summary", str(trace), "--width", str(width))
        assert code == 0
        assert max(len(line) for line in out.splitlines()) <= width, trace.name
        assert out.endswith("\n") and not any(line != line.rstrip() for line in out.splitlines())


def test_summary_draws_one_bar_row_per_call_and_marks_events(
    capsys: pytest.CaptureFixture[str], runs: dict[str, Path]
) -> None:
    code, out, _ = gpp(capsys, "trace", "summary", str(runs["blocksworld"]), "--width", "100")
    assert code == 0
    rows = {line.split("│")[0].split()[0]: line for line in out.splitlines() if "│" in line}
    calls = {"stack(c,t3)", "stack(a,t2)", "stack(b,c)", "stack(a,b)", "get_block_pose(a)", "gripper_home()"}
    assert set(rows) >= calls | {"navigate_to_…(table)", "navigate_to_f…(home)", "exogenous", "plans"}
    assert all("×1" in rows[call] and "█" in rows[call] for call in calls if call.startswith("stack"))
    # Each stack went somewhere else: their bars follow one another, never in one column.
    starts = [rows[call].index("█") for call in ("stack(c,t3)", "stack(a,t2)", "stack(b,c)", "stack(a,b)")]
    assert starts == sorted(starts) and len(set(starts)) == 4
    # Where the blocks are, as bands of their values.
    assert "t3" in rows["loc(c)"] and "▬" in rows["loc(c)"]
    assert "states over time" in out
    assert rows["exogenous"].count("◆") + sum(int(c) for c in rows["exogenous"] if c.isdigit()) >= 6 - 1
    assert "▲" in rows["plans"]
    assert "time  0 s" in out and "stack(c,t3) → stack(a,t2)" in out
    assert out.rstrip().splitlines()[-1].startswith("finish finished at 35.817 s")


@pytest.fixture(scope="module")
def retries(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real trace of tests/traceview/programs/retries.gpp: two visitors arrive at once, a
    `goto(room1)` fails at once and is retried, then `goto(room2)` and `goto(lobby)`."""
    trace = tmp_path_factory.mktemp("retries") / "retries.jsonl"
    outcome = run_program(HERE / "programs" / "retries.gpp", RunOptions(trace=trace))
    assert outcome.result is not None and outcome.result.status.value == "finished"
    return trace


def test_summary_shows_which_call_went_where_a_quick_retry_and_the_state(
    capsys: pytest.CaptureFixture[str], retries: Path
) -> None:
    code, out, _ = gpp(capsys, "trace", "summary", str(retries), "--width", "100")
    assert code == 0
    rows = {line.split("│")[0].split()[0]: line.split("│", 1)[1] for line in out.splitlines() if "│" in line}
    counts = {line.split()[0]: line.split()[1] for line in out.splitlines() if line.startswith("goto(")}
    # One row per call, each with its own count.
    assert counts == {"goto(room1)": "×2", "goto(room2)": "×1", "goto(lobby)": "×1"}
    # The failed attempt took no time: the cell where both attempts started counts them.
    first = rows["goto(room1)"].lstrip(" ")
    assert first.startswith("2█"), rows["goto(room1)"]
    assert rows["goto(room2)"].index("█") > rows["goto(room1)"].index("█")
    # Where the robot is, as bands; waiting() (set by the exogenous events) as a series.
    assert rows["robot_at()"].lstrip().startswith("room1▬") and "room2▬" in rows["robot_at()"]
    assert "waiting()" in rows
    assert "robot_at()        3" in out and "room1 → room2 → lobby" in out
    assert "2-9 several at once" in out


def test_states_of_the_model(retries: Path) -> None:
    model = build_run_model(load_trace(retries).events)
    [state] = model.states
    assert state.name == "robot_at()"
    assert [(s.start, s.stop, s.value, s.label) for s in state.segments] == [
        (7.0, 11.0, "room1", "goto(room1)"),
        (11.0, 15.0, "room2", "goto(room2)"),
        (15.0, 15.0, "lobby", "goto(lobby)"),
    ]
    assert [(s.name, [x.value for x in s.samples]) for s in model.series] == [
        ("waiting()", [1, 2]),
        ("visitors_greeted_so_far()", [1, 2]),
    ]


def test_summary_colour_follows_the_option_and_no_color(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    trace = str(GOLDEN / "small.jsonl")
    _, coloured, _ = gpp(capsys, "trace", "summary", trace, "--color", "always")
    assert ANSI.search(coloured)
    _, plain, _ = gpp(capsys, "trace", "summary", trace, "--color", "never")
    assert not ANSI.search(plain) and ANSI.sub("", coloured) == plain
    monkeypatch.setenv("NO_COLOR", "1")
    monkeypatch.setenv("FORCE_COLOR", "1")
    _, auto, _ = gpp(capsys, "trace", "summary", trace)
    assert not ANSI.search(auto)


# ---------------------------------------------------------------- gpp trace html


def page_of(path: Path) -> dict[str, Any]:
    """The data embedded in a page."""
    page = path.read_text(encoding="utf-8")
    match = re.search(r'<script type="application/json" id="gpp-data">(.*?)</script>', page, re.S)
    assert match is not None
    data: dict[str, Any] = json.loads(match[1])
    return data


def assert_self_contained(page: str) -> None:
    """Nothing in the page is loaded from elsewhere: no external scripts, styles, images,
    fonts or imports, and no URL at all."""
    assert "http://" not in page and "https://" not in page
    assert not re.search(r"<script[^>]*\bsrc=", page)
    assert not re.search(r"<(img|iframe|object|embed|audio|video|source)\b", page)
    assert re.findall(r"<link\b[^>]*>", page) == ['<link rel="icon" href="data:,">']
    assert "@import" not in page and "url(" not in page.replace("url(#", "")
    assert page.count("<script") == page.count("</script>") == 2


def test_html_page_of_a_real_run_has_every_activity_and_its_source(
    capsys: pytest.CaptureFixture[str], runs: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT)
    out = tmp_path / "run.html"
    code, stdout, err = gpp(capsys, "trace", "html", str(runs["blocksworld"]), "-o", str(out))
    assert (code, err) == (0, "")
    assert stdout == f"wrote {out} (13 activities, 6 exogenous events, 1 plan)\n"
    page = out.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "__GPP_" not in page
    assert_self_contained(page)
    data = page_of(out)
    events = load_trace(runs["blocksworld"]).events
    starts = [e for e in events if isinstance(e, StartEvent)]
    assert [a["action"] for a in data["activities"]] == [s.action for s in starts]
    assert sorted(i for lane in data["lanes"] for i in lane["activities"]) == list(range(len(starts)))
    assert [lane["name"] for lane in data["lanes"]] == ["get_block_pose", "navigate_to_frame", "stack", "gripper_home"]
    assert len(data["exog"]) == 6 and [p["policy"] for p in data["plans"]] == [
        ["stack(c,t3)", "stack(a,t2)", "stack(b,c)", "stack(a,b)"]
    ]
    # battery() is set by each battery_report: a fluent series beside the argument's.
    assert [s["name"] for s in data["series"]] == ["battery()", "battery_report(·)"]
    # The source line of every start, as the program reads now.
    lines = (ROOT / "examples" / "blocksworld.gpp").read_text(encoding="utf-8").splitlines()
    for start in starts:
        assert start.at is not None
        file, line, _ = start.at.rsplit(":", 2)
        assert data["sources"][file][line] == lines[int(line) - 1]
    assert data["notes"] == []


def test_html_page_without_the_program_files_says_so(
    capsys: pytest.CaptureFixture[str], runs: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, _, err = gpp(capsys, "trace", "html", str(runs["sensing"]), "-o", "page.html")
    assert code == 0
    assert err.startswith("note: source lines not embedded: tests/programs/sensing.gpp not found")
    data = page_of(tmp_path / "page.html")
    assert data["sources"] == {} and "not found when the page was made" in data["notes"][0]
    # --source-root finds them.
    code, _, err = gpp(capsys, "trace", "html", str(runs["sensing"]), "-o", "page.html", "--source-root", str(ROOT))
    assert (code, err) == (0, "")
    assert set(page_of(tmp_path / "page.html")["sources"]) == {"tests/programs/sensing.gpp"}


def test_html_page_data_cannot_break_out_of_its_script(tmp_path: Path) -> None:
    nasty = 'say("</script><script>alert(1)</script>&<!--")'
    events: list[TraceEvent] = [
        StartEvent(t=0, action=nasty, id=1, mapped="speech", args={}, at=None),
        UpdateEvent(t=1, action=nasty, status="final", id=1),
        FinishEvent(t=1, status="finished", actions=1, failures=0, unhandled_failures=0, exog_events=0),
    ]
    page, _ = html_page(build_run_model(events), trace_name="x.jsonl", search=[tmp_path])
    assert page.count("</script>") == 2 and '<!--"' not in page
    (tmp_path / "x.html").write_text(page, encoding="utf-8")
    assert page_of(tmp_path / "x.html")["activities"][0]["action"] == nasty
    assert json.loads(embed_json({"a": "<&>"})) == {"a": "<&>"}


def test_html_page_of_a_run_that_stops(tmp_path: Path) -> None:
    trace = write_trace(tmp_path / "stopped.jsonl", stopped_run())
    (tmp_path / "agent.gpp").write_text("".join(f"line {n}\n" for n in range(1, 20)), encoding="utf-8")
    page, sources = html_page(build_run_model(load_trace(trace).events), trace_name="stopped.jsonl", search=[tmp_path])
    assert_self_contained(page)
    (tmp_path / "stopped.html").write_text(page, encoding="utf-8")
    data = page_of(tmp_path / "stopped.html")
    assert (data["status"], data["platform"], data["seed"]) == ("error", "dummy", 7)
    assert [(a["action"], a["status"], a["row"]) for a in data["activities"]] == [
        ('say("hi")', "final", 0),
        ("go(kitchen)", "running", 0),
        ('say("again")', "failed", 1),
    ]
    assert data["waits"] == [
        {"start": 1, "stop": 2, "statement": "test(door_open());", "condition": "door_open()", "at": "agent.gpp:12:5"}
    ]
    assert [(p["event"], p["code"]) for p in data["problems"]] == [("error", "R0002")]
    assert [p["event"] for p in data["plans"]] == ["plan", "replan"]
    assert data["sources"]["agent.gpp"]["14"] == "line 14" and sources.missing == []


# ---------------------------------------------------------------- gpp trace perfetto


def check_chrome_trace(doc: Any) -> None:
    """The structure of Chrome's JSON trace-event format (object form) as Perfetto reads it."""
    assert isinstance(doc, dict) and isinstance(doc["traceEvents"], list)
    assert doc["displayTimeUnit"] in ("ms", "ns")
    named_threads = {(e["pid"], e["tid"]) for e in doc["traceEvents"] if e["ph"] == "M" and e["name"] == "thread_name"}
    named_processes = {e["pid"] for e in doc["traceEvents"] if e["ph"] == "M" and e["name"] == "process_name"}
    slices: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for e in doc["traceEvents"]:
        assert {"name", "ph", "pid", "tid", "ts"} <= set(e), e
        assert isinstance(e["name"], str) and e["name"]
        assert all(type(e[k]) is int for k in ("pid", "tid", "ts")) and e["ts"] >= 0, e
        assert e["pid"] in named_processes
        ph = e["ph"]
        assert ph in ("X", "i", "C", "M"), e  # no B/E pairs: every slice is one complete event
        if ph == "M":
            assert e["name"] in ("process_name", "thread_name", "process_sort_index", "thread_sort_index")
            assert set(e["args"]) in ({"name"}, {"sort_index"})
        elif ph == "X":
            assert type(e["dur"]) is int and e["dur"] >= 0
            assert (e["pid"], e["tid"]) in named_threads
            slices.setdefault((e["pid"], e["tid"]), []).append((e["ts"], e["ts"] + e["dur"]))
        elif ph == "i":
            assert e["s"] in ("t", "p", "g") and (e["pid"], e["tid"]) in named_threads
        else:
            assert e["args"] and all(isinstance(v, int | float) and not isinstance(v, bool) for v in e["args"].values())
    # Slices on one track nest or follow each other, never overlap partly.
    for track in slices.values():
        open_ends: list[int] = []
        for begin, end in sorted(track, key=lambda s: (s[0], -s[1])):
            while open_ends and open_ends[-1] <= begin:
                open_ends.pop()
            assert not open_ends or end <= open_ends[-1], track
            open_ends.append(end)


def test_perfetto_json_of_the_pinned_trace(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "run.json"
    code, stdout, err = gpp(capsys, "trace", "perfetto", str(GOLDEN / "small.jsonl"), "-o", str(out))
    assert (code, err) == (0, "")
    assert stdout.startswith(f"wrote {out} (4 activities, 3 exogenous events, 1 plan)")
    doc = json.loads(out.read_text(encoding="utf-8"))
    check_chrome_trace(doc)
    events = doc["traceEvents"]
    threads = {e["tid"]: e["args"]["name"] for e in events if e["name"] == "thread_name"}
    slices = [(threads[e["tid"]], e["name"], e["ts"], e["dur"], e["args"]["status"]) for e in events if e["ph"] == "X"]
    assert slices == [
        ("go", "go(kitchen)", 0, 2_000_000, "final"),
        ("measure", "measure(kitchen)", 2_000_000, 1_000_000, "final"),
        ("beep", "beep()", 3_000_000, 1_000_000, "failed"),
        ("scan", "scan(1)", 4_000_000, 0, "cancelled"),
    ]
    instants = [(threads[e["tid"]], e["name"], e["ts"]) for e in events if e["ph"] == "i"]
    assert ("exogenous events", "bell()", 1_000_000) in instants
    assert ("exogenous events", "battery_report(80)", 1_500_000) in instants
    assert ("planner", "plan (solve): value 10", 0) in instants
    assert ("program", "finish: finished", 4_000_000) in instants
    counters = [(e["name"], e["ts"], e["args"]) for e in events if e["ph"] == "C"]
    assert counters == [
        ("temperature()", 3_000_000, {"value": 21.5}),
        ("battery_report(·)", 1_500_000, {"value": 80.0}),
    ]


def test_perfetto_json_of_real_runs_and_of_a_run_that_stops(runs: dict[str, Path], tmp_path: Path) -> None:
    traces = [*runs.values(), write_trace(tmp_path / "stopped.jsonl", stopped_run())]
    for trace in traces:
        events = load_trace(trace).events
        doc = chrome_trace(build_run_model(events), trace_name=trace.name)
        check_chrome_trace(json.loads(json.dumps(doc)))
        starts = Counter(e.action for e in events if isinstance(e, StartEvent))
        assert Counter(e["name"] for e in doc["traceEvents"] if e["ph"] == "X" and "activity" in e["cat"]) == starts
    stopped = chrome_trace(build_run_model(stopped_run()), trace_name="stopped.jsonl")["traceEvents"]
    threads = {e["tid"]: e["args"]["name"] for e in stopped if e["name"] == "thread_name"}
    assert sorted(threads[e["tid"]] for e in stopped if e["ph"] == "X") == ["go", "program", "say", "say (2)"]
    [error] = [e for e in stopped if e.get("cat") == "error"]
    assert (error["s"], error["ts"], error["args"]["code"]) == ("g", 4_000_000, "R0002")


def test_perfetto_to_stdout(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = gpp(capsys, "trace", "perfetto", str(GOLDEN / "small.jsonl"), "-o", "-")
    assert (code, err) == (0, "")
    check_chrome_trace(json.loads(out))


# ---------------------------------------------------------------- bad input


def bad_inputs(tmp_path: Path) -> dict[str, tuple[Path, int, str]]:
    """name → (file, exit code, the one-line error)."""
    good = (GOLDEN / "small.jsonl").read_text(encoding="utf-8").splitlines()
    written = "traces are written by `gpp run --trace`"
    cases: dict[str, tuple[str | bytes | None, int, str]] = {
        "missing": (None, 2, "error: cannot read '{f}': No such file or directory"),
        "empty": ("", 1, "error: {f}: empty trace (no records)"),
        "blank": ("\n\n", 1, "error: {f}: empty trace (no records)"),
        "program": (
            "procedure main() { }\n",
            1,
            "error: {f}:1: not a JSON trace record (Expecting value, column 1); " + written,
        ),
        "bad_line": (
            "\n".join([*good[:3], "{not json", *good[3:]]) + "\n",
            1,
            "error: {f}:4: not a JSON trace record (Expecting property name enclosed in double quotes, column 2)",
        ),
        "unknown_event": (
            good[0] + '\n{"t": 1, "event": "teleport"}\n',
            1,
            "error: {f}:2: not a trace record: unknown trace event 'teleport'",
        ),
        "missing_field": (
            '{"t": 0, "event": "start", "action": "go(a)"}\n',
            1,
            "error: {f}:1: not a trace record: a `start` record without `id`",
        ),
        "wrong_type": (
            '{"t": 0, "event": "exog", "action": 5}\n',
            1,
            "error: {f}:1: not a trace record: a `exog` record whose `action` is 5 (expected str)",
        ),
        "bad_time": (
            '{"t": "soon", "event": "exog", "action": "a()"}\n',
            1,
            "error: {f}:1: not a trace record: could not convert string to float: 'soon'",
        ),
        "not_an_object": ("[1, 2]\n", 1, "error: {f}:1: not a trace record: a trace record is a JSON object"),
        "binary": (b"\x89PNG\r\n\x1a\n\x00\xff", 1, "error: {f}: not a trace (not UTF-8 text); " + written),
    }
    out = {}
    for name, (content, code, message) in cases.items():
        path = tmp_path / f"{name}.jsonl"
        if isinstance(content, bytes):
            path.write_bytes(content)
        elif content is not None:
            path.write_text(content, encoding="utf-8")
        out[name] = (path, code, message.format(f=path))
    return out


@pytest.mark.parametrize("command", ["summary", "html", "perfetto", "mcap"])
def test_bad_input_is_one_line_and_an_exit_code(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, command: str
) -> None:
    for name, (path, expected_code, message) in bad_inputs(tmp_path).items():
        code, out, err = gpp(capsys, "trace", command, str(path))
        assert (code, out, err) == (expected_code, "", message + "\n"), name
    assert not list(tmp_path.glob("*.html")) and not list(tmp_path.glob("*.perfetto.json"))
    assert not list(tmp_path.glob("*.mcap"))


def test_a_folder_without_a_trace_is_not_a_trace(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    (tmp_path / "notes.jsonl").write_text('{"note": 1}\n', encoding="utf-8")
    expected = f"error: '{tmp_path}' holds no trace (no .jsonl file that starts with a header)\n"
    assert gpp(capsys, "trace", "summary", str(tmp_path)) == (2, "", expected)


def small_trace_with(tmp_path: Path, change: Callable[[list[dict[str, Any]]], None]) -> Path:
    """tests/golden/trace/small.jsonl with its records changed by `change`."""
    records = [json.loads(line) for line in (ROOT / "tests/golden/trace/small.jsonl").read_text().splitlines()]
    change(records)
    path = tmp_path / "changed.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in records), encoding="utf-8")
    return path


@pytest.mark.parametrize("command", [["summary"], ["html", "-o", "page.html"], ["perfetto", "-o", "run.json"]])
def test_a_time_beyond_what_a_trace_holds_is_an_error_not_a_crash(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, command: list[str]
) -> None:
    def far(records: list[dict[str, Any]]) -> None:
        records[1]["t"] = 1e308

    path = small_trace_with(tmp_path, far)
    code, _, err = gpp(capsys, "trace", command[0], str(path), *command[1:])
    assert code == 1
    says = "a `assign` record at time 1e+308, beyond what a trace holds (at most 1e15 s)"
    assert err == f"error: {path}:2: not a trace record: {says}\n"


def test_a_trace_of_a_newer_schema_is_read_with_a_warning(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    def newer(records: list[dict[str, Any]]) -> None:
        records[0]["schema_version"] = "2.0"

    path = small_trace_with(tmp_path, newer)
    code, out, err = gpp(capsys, "trace", "summary", str(path))
    assert code == 0 and out
    assert err.startswith(f"warning: {path}: written with trace schema 2.0 by gpp 0.1.0; this gpp reads schema ")


def test_an_incomplete_last_line_is_skipped_with_a_warning(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """A run killed while writing a record leaves half a line: the rest is still worth seeing."""
    text = (GOLDEN / "small.jsonl").read_text(encoding="utf-8")
    lines = text.splitlines()
    trace = tmp_path / "killed.jsonl"
    trace.write_text("\n".join(lines[:5]) + "\n" + lines[5][:20], encoding="utf-8")
    code, out, err = gpp(capsys, "trace", "summary", str(trace))
    assert code == 0
    assert err == f"warning: {trace}:6: ignoring the incomplete last line (the run was stopped mid-write)\n"
    assert "the trace ends without a `finish` record at 1.500 s" in out
    assert "░" in out  # go(kitchen) was still running


def test_options_that_do_not_apply_and_bad_outputs_are_usage_errors(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    trace = str(GOLDEN / "small.jsonl")
    for args in (
        ["summary", trace, "-o", "x.html"],
        ["summary", trace, "--source-root", "."],
        ["perfetto", trace, "--width", "100"],
        ["html", trace, "--color", "never"],
        ["perfetto", trace, "--source-root", "."],
    ):
        code, out, err = gpp(capsys, "trace", *args)
        assert code == 2 and out == "" and "No such option" in err, args
    assert gpp(capsys, "trace", "summary", trace, "--width", "20") == (
        2,
        "",
        "error: --width must be at least 60, not 20\n",
    )
    missing = tmp_path / "nowhere" / "run.html"
    assert gpp(capsys, "trace", "html", trace, "-o", str(missing)) == (
        2,
        "",
        f"error: cannot write '{missing}': the folder '{missing.parent}' does not exist\n",
    )
    assert gpp(capsys, "trace", "perfetto", trace, "-o", str(tmp_path)) == (
        2,
        "",
        f"error: cannot write '{tmp_path}': it is a directory (give a file name with -o)\n",
    )
    copy = tmp_path / "run.jsonl"
    copy.write_text((GOLDEN / "small.jsonl").read_text(encoding="utf-8"), encoding="utf-8")
    assert gpp(capsys, "trace", "html", str(copy), "-o", str(copy)) == (
        2,
        "",
        f"error: '{copy}' is the trace itself; give another file with -o\n",
    )
    assert [decode(line) for line in copy.read_text(encoding="utf-8").splitlines()]  # untouched
    assert gpp(capsys, "trace", "html", trace, "--source-root", str(tmp_path / "nope"))[0] == 2


def test_outputs_default_to_next_to_the_trace(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    trace.write_text((GOLDEN / "small.jsonl").read_text(encoding="utf-8"), encoding="utf-8")
    assert gpp(capsys, "trace", "html", str(trace))[0] == 0
    assert gpp(capsys, "trace", "perfetto", str(trace))[0] == 0
    assert (tmp_path / "run.html").is_file() and (tmp_path / "run.perfetto.json").is_file()


def test_the_real_command_never_shows_a_traceback(tmp_path: Path) -> None:
    """End to end, through the entry point: bad input gives one line and exit code 2 or 1."""
    (tmp_path / "bad.jsonl").write_text('{"t": 0, "event": "start"}\n', encoding="utf-8")
    for args, code in ((["missing.jsonl"], 2), (["bad.jsonl"], 1)):
        result = run("trace", "summary", *args, cwd=tmp_path)
        assert result.returncode == code
        assert result.stdout == "" and len(result.stderr.splitlines()) == 1 and "Traceback" not in result.stderr
