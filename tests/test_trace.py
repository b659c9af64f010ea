"""The run trace: one JSON object per line, written and flushed as each event happens, with `t`,
`event` and (for action events) `action` as ground action text; complete also when the run
is interrupted."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from gpp.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus
from gpp.runtime.state import GroundAction
from gpp.runtime.trace import TraceRecord
from gpp.runtime.values import CompoundValue

ROOT = Path(__file__).resolve().parent.parent
PROGRAMS = ROOT / "tests" / "programs"

EVENTS = {"start", "end", "update", "exog", "sense", "assign", "plan", "replan", "blocked", "error", "finish", "cancel"}
ACTION_EVENTS = {"start", "end", "update", "exog", "sense", "cancel"}
# name(arg,arg): no spaces outside string literals.
GROUND = re.compile(r'^[A-Za-z][A-Za-z0-9_]*\((?:[^" ]|"(?:[^"\\]|\\.)*")*\)$')

REPLAN = """// scenario: replan.toml
symbol domain Loc = {a, b, c}
Loc fluent at() { initially: () = a; }
bool fluent visited(Loc l) { initially: (l) = false; }
bool fluent closed(Loc l) { initially: (l) = false; }
exog_action close(Loc l) { effect: closed(l) = true; }
action go(Loc l) { precondition: at() != l & !closed(l) effect: at() = l; visited(l) = true; }
number function reward() = if (at() == c & visited(b)) 10 else 0
procedure main() {
    solve(3, reward())
        while (!(at() == c & visited(b)))
            pick (Loc l in {a, b, c}) go(l);
}
"""


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _read(path: Path) -> list[TraceRecord]:
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]


def _check_record(record: TraceRecord) -> None:
    assert isinstance(record["t"], float) and record["t"] >= 0
    assert record["event"] in EVENTS
    if record["event"] in ACTION_EVENTS:
        assert GROUND.match(record["action"]), record["action"]


@pytest.mark.parametrize(
    "program",
    ["during_on_fail", "during_on_cancel", "exog_events", "sensing", "solve", "search", "hooks", "lists"],
)
def test_every_record_has_the_required_fields(program: str, tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    outcome = run_program(PROGRAMS / f"{program}.gpp", RunOptions(trace=trace_file))
    records = _read(trace_file)
    assert outcome.trace is not None and records == outcome.trace.records
    for record in records:
        _check_record(record)
    assert [r["event"] for r in records].count("finish") == 1
    finish = records[-1]
    assert finish["event"] == "finish" and finish["status"] == "finished"
    assert set(finish) >= {"actions", "failures", "unhandled_failures", "exog_events"}
    times = [r["t"] for r in records]
    assert times == sorted(times)


def test_all_event_kinds_appear_with_their_fields(tmp_path: Path) -> None:
    seen: dict[str, TraceRecord] = {}
    for program in ("during_on_fail", "exog_events", "sensing", "solve", "concurrent"):
        outcome = run_program(PROGRAMS / f"{program}.gpp", RunOptions())
        assert outcome.trace is not None
        for record in outcome.trace.records:
            seen.setdefault(record["event"], record)
    _write(tmp_path, "replan.toml", '[[exog]]\nat = 0.5\naction = "close"\nargs = ["c"]\n')
    outcome = run_program(_write(tmp_path, "replan.gpp", REPLAN), RunOptions())
    assert outcome.trace is not None
    [replan] = outcome.trace.events("replan")
    blocked = run_program(ROOT / "tests" / "runtime_errors" / "blocked_test.gpp", RunOptions())
    error = run_program(ROOT / "tests" / "runtime_errors" / "division_by_zero.gpp", RunOptions())
    assert blocked.trace is not None and error.trace is not None
    seen["replan"] = replan
    seen["blocked"] = blocked.trace.events("blocked")[0]
    seen["error"] = error.trace.events("error")[0]
    assert set(seen) >= EVENTS - {"cancel"}
    assert set(seen["start"]) >= {"t", "event", "action", "id", "mapped", "args"}
    assert set(seen["update"]) >= {"action", "status", "id"}
    assert set(seen["end"]) >= {"action", "status", "hook"}
    assert set(seen["exog"]) >= {"action"}
    assert set(seen["sense"]) >= {"action", "fluent", "value"}
    assert set(seen["assign"]) >= {"fluent", "value"}
    assert set(seen["plan"]) >= {"kind", "feasible", "value", "horizon", "policy"}
    assert set(seen["replan"]) >= {"kind", "feasible", "policy"}
    assert set(seen["blocked"]) >= {"message", "at"}
    assert set(seen["error"]) >= {"code", "message", "at"}


def test_ground_action_text_is_name_and_arguments_without_spaces() -> None:
    from gpp.model.types import Sym

    pose = CompoundValue("Pose", (("x", 1), ("y", 2.5)))
    assert GroundAction("go", (Sym("kitchen"),)).text == "go(kitchen)"
    assert GroundAction("move", (1, 2.5, -3)).text == "move(1,2.5,-3)"
    assert GroundAction("say", ('hi "you"',)).text == 'say("hi \\"you\\"")'
    assert GroundAction("drive", (pose, (1, 2), None, True)).text == "drive(Pose{x=1,y=2.5},[1,2],null,true)"
    assert GroundAction("stop", ()).text == "stop()"
    for text in ("go(kitchen)", "move(1,2.5,-3)", 'say("hello world")', "drive(Pose{x=1,y=2.5},[1,2],null,true)"):
        assert GROUND.match(text)


def test_trace_values_are_json_with_tagged_symbols_and_compounds(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    run_program(PROGRAMS / "compounds.gpp", RunOptions(trace=trace_file))
    assigns = [r for r in _read(trace_file) if r["event"] == "assign"]
    assert assigns[0] == {
        "t": 0.0,
        "event": "assign",
        "fluent": "before()",
        "value": _pose(0, 0),
        "at": "tests/programs/compounds.gpp:42:5",
    }
    sym = run_program(PROGRAMS / "choose_pick.gpp", RunOptions())
    assert sym.trace is not None
    assert {"symbol": "office"} in [r["value"] for r in sym.trace.events("assign")]


def _pose(x: int, y: int) -> dict[str, object]:
    return {"compound": "Point", "fields": {"x": x, "y": y}}


def test_each_record_is_on_disk_when_its_event_happens(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    lines_seen: list[int] = []
    count = 0

    def listener(record: TraceRecord) -> None:
        nonlocal count
        count += 1
        lines = trace_file.read_text(encoding="utf-8").splitlines()
        lines_seen.append(len(lines))
        assert json.loads(lines[-1]) == record

    outcome = run_program(PROGRAMS / "concurrent.gpp", RunOptions(trace=trace_file), listeners=[listener])
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert lines_seen == list(range(1, count + 1))


@pytest.mark.parametrize("stop_at", ["start", "update", "end", "assign"])
def test_interrupted_run_leaves_a_complete_trace(stop_at: str, tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    interrupted = False

    def ctrl_c(record: TraceRecord) -> None:
        nonlocal interrupted
        if record["event"] == stop_at and not interrupted:
            interrupted = True
            raise KeyboardInterrupt

    outcome = run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(trace=trace_file), listeners=[ctrl_c])
    assert interrupted
    assert outcome.result is not None and outcome.result.status is RunStatus.INTERRUPTED
    assert outcome.postcond is None and outcome.exit_code == 1
    records = _read(trace_file)  # every line is valid JSON
    for record in records:
        _check_record(record)
    [stop] = [i for i, r in enumerate(records) if r["event"] == "error"]
    assert records[stop]["message"] == "interrupted"
    # After the interruption: running activities are cancelled and the platform acknowledges the
    # cancellations (an activity interrupted while being started never reached the platform, so
    # nothing acknowledges it), then the run finishes.
    after = records[stop + 1 : -1]
    cancelled = [r["id"] for r in after if r["event"] == "cancel"]
    acknowledged = [r["id"] for r in after if r["event"] == "update" and r["status"] == "cancelled"]
    assert {r["event"] for r in after} <= {"cancel", "update"}
    assert acknowledged == (cancelled if stop_at == "assign" else [])
    assert records[-1]["event"] == "finish" and records[-1]["status"] == "interrupted"


def test_interrupt_while_an_activity_runs_cancels_it(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"

    def ctrl_c(record: TraceRecord) -> None:
        # The step after `drive(kitchen)` started: the platform is running it.
        if record["event"] == "assign" and record["fluent"] == "said()":
            raise KeyboardInterrupt

    run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(trace=trace_file), listeners=[ctrl_c])
    records = _read(trace_file)
    cancel = [r for r in records if r["event"] == "cancel"]
    assert [(r["action"], r["reason"]) for r in cancel] == [("drive(kitchen)", "the program ended")]
    # The platform's acknowledgement is recorded before the run finishes.
    assert [(r["event"], r["action"], r["status"], r["reason"]) for r in records[-2:-1]] == [
        ("update", "drive(kitchen)", "cancelled", "preempted")
    ]
    assert records[-1]["event"] == "finish"


def test_interrupt_before_the_platform_took_an_activity_cancels_it_without_waiting(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"

    def ctrl_c(record: TraceRecord) -> None:
        if record["event"] == "start" and record["action"] == "drive(kitchen)":
            raise KeyboardInterrupt  # while the executor starts it: the platform never got it

    run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(trace=trace_file), listeners=[ctrl_c])
    records = _read(trace_file)
    assert [r["event"] for r in records] == ["start", "error", "cancel", "finish"]


def test_failure_shows_in_the_trace_and_on_fail_runs() -> None:
    outcome = run_program(PROGRAMS / "during_on_fail.gpp", RunOptions())
    assert outcome.trace is not None
    events = [(r["event"], r.get("action", r.get("fluent")), r.get("status")) for r in outcome.trace.records]
    failed_update = events.index(("update", "drive(kitchen)", "failed"))
    failed_end = events.index(("end", "drive(kitchen)", "failed"))
    handler = events.index(("assign", "failed()", None))
    assert failed_update < failed_end < handler
    assert outcome.result is not None and outcome.result.failures == 2
    assert outcome.result.unhandled_failures == 1  # beep() fails once, with no handler


def test_exog_event_with_a_false_precondition_is_marked_and_still_applied() -> None:
    outcome = run_program(PROGRAMS / "exog_events.gpp", RunOptions())
    assert outcome.trace is not None and outcome.postcond is True
    marked = [(r["action"], r.get("precondition")) for r in outcome.trace.events("exog")]
    assert marked == [
        ('bell("ann")', None),
        ("door_opened(front)", None),
        ('bell("bob")', False),
        ("door_opened(back)", None),
        ('bell("cid")', False),
    ]


def test_records_of_silent_actions_are_marked() -> None:
    outcome = run_program(ROOT / "examples" / "exog_sensing.gpp", RunOptions())
    assert outcome.trace is not None
    silent = {r["action"] for r in outcome.trace.records if r.get("silent")}
    assert silent == {"battery_report(80)"}
    assert all("silent" not in r for r in outcome.trace.events("start"))
