"""The run trace: one JSON object per line, written and flushed as each event happens, with `t`,
`event` and (for action events) `action` as ground action text; complete also when the run
is interrupted. In memory the records are typed events (gpp.runtime.events) with one JSON
encoding; tests/runtime/test_trace_schema.py checks real traces against the JSON Schema."""

from __future__ import annotations

import dataclasses
import io
import json
import math
import os
import re
from pathlib import Path

import pytest

from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import (
    AssignEvent,
    BlockedEvent,
    CancelEvent,
    EndEvent,
    ErrorEvent,
    EventBase,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    decode,
    encode,
    to_json_dict,
)
from gpp.runtime.executor import RunStatus
from gpp.runtime.state import GroundAction
from gpp.runtime.trace import Recording, Trace
from gpp.runtime.values import CompoundValue

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS = ROOT / "tests" / "programs"

EVENTS = {
    "header",
    "start",
    "end",
    "update",
    "exog",
    "sense",
    "assign",
    "plan",
    "replan",
    "blocked",
    "error",
    "finish",
    "cancel",
    "waiting",
}
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


def _read(path: Path) -> list[TraceEvent]:
    return [decode(line) for line in path.read_text(encoding="utf-8").splitlines()]


def _check_record(record: TraceEvent) -> None:
    assert isinstance(record.t, float) and record.t >= 0
    assert record.EVENT in EVENTS
    if record.EVENT in ACTION_EVENTS:
        action = getattr(record, "action", None)
        assert isinstance(action, str) and GROUND.match(action), action


@pytest.mark.parametrize(
    "program",
    ["during_on_fail", "during_on_cancel", "exog_events", "sensing", "solve", "search", "hooks", "lists"],
)
def test_every_record_has_the_required_fields(program: str, tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    outcome = run_program(PROGRAMS / f"{program}.gpp", RunOptions(record=True, trace=trace_file))
    records = _read(trace_file)
    assert outcome.recording is not None and records == outcome.recording.records
    for record in records:
        _check_record(record)
    assert [r.EVENT for r in records].count("finish") == 1
    finish = records[-1]
    assert isinstance(finish, FinishEvent) and finish.status == "finished"
    assert set(to_json_dict(finish)) >= {"actions", "failures", "unhandled_failures", "exog_events"}
    times = [r.t for r in records]
    assert times == sorted(times)


def test_all_event_kinds_appear_with_their_fields(tmp_path: Path) -> None:
    seen: dict[str, dict[str, object]] = {}
    for program in ("during_on_fail", "exog_events", "sensing", "solve", "concurrent"):
        outcome = run_program(PROGRAMS / f"{program}.gpp", RunOptions(record=True))
        assert outcome.recording is not None
        for record in outcome.recording.records:
            seen.setdefault(record.EVENT, to_json_dict(record))
    _write(tmp_path, "replan.toml", '[[exog]]\nat = 0.5\naction = "close"\nargs = ["c"]\n')
    outcome = run_program(_write(tmp_path, "replan.gpp", REPLAN), RunOptions(record=True))
    assert outcome.recording is not None
    [replan] = outcome.recording.of(ReplanEvent)
    blocked = run_program(ROOT / "tests" / "runtime_errors" / "blocked_test.gpp", RunOptions(record=True))
    error = run_program(ROOT / "tests" / "runtime_errors" / "division_by_zero.gpp", RunOptions(record=True))
    assert blocked.recording is not None and error.recording is not None
    seen["replan"] = to_json_dict(replan)
    seen["blocked"] = to_json_dict(blocked.recording.of(BlockedEvent)[0])
    seen["error"] = to_json_dict(error.recording.of(ErrorEvent)[0])
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
    run_program(PROGRAMS / "compounds.gpp", RunOptions(record=True, trace=trace_file))
    assigns = [to_json_dict(r) for r in _read(trace_file) if isinstance(r, AssignEvent)]
    assert assigns[0] == {
        "t": 0.0,
        "event": "assign",
        "fluent": "before()",
        "value": _pose(0, 0),
        "at": "tests/programs/compounds.gpp:42:5",
    }
    sym = run_program(PROGRAMS / "choose_pick.gpp", RunOptions(record=True))
    assert sym.recording is not None
    assert {"symbol": "office"} in [r.value for r in sym.recording.of(AssignEvent)]


def _pose(x: int, y: int) -> dict[str, object]:
    return {"compound": "Point", "fields": {"x": x, "y": y}}


def test_each_record_is_on_disk_when_its_event_happens(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    lines_seen: list[int] = []
    count = 0

    def listener(record: TraceEvent) -> None:
        nonlocal count
        count += 1
        lines = trace_file.read_text(encoding="utf-8").splitlines()
        lines_seen.append(len(lines))
        assert decode(lines[-1]) == record

    outcome = run_program(PROGRAMS / "concurrent.gpp", RunOptions(record=True, trace=trace_file), listeners=[listener])
    assert outcome.result is not None and outcome.result.status is RunStatus.FINISHED
    assert lines_seen == list(range(1, count + 1))


@pytest.mark.parametrize("stop_at", ["start", "update", "end", "assign"])
def test_interrupted_run_leaves_a_complete_trace(stop_at: str, tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"
    interrupted = False

    def ctrl_c(record: TraceEvent) -> None:
        nonlocal interrupted
        if stop_at == record.EVENT and not interrupted:
            interrupted = True
            raise KeyboardInterrupt

    outcome = run_program(
        PROGRAMS / "during_on_fail.gpp", RunOptions(record=True, trace=trace_file), listeners=[ctrl_c]
    )
    assert interrupted
    assert outcome.result is not None and outcome.result.status is RunStatus.INTERRUPTED
    assert outcome.postcond is None and outcome.exit_code == 1
    records = _read(trace_file)  # every line is valid JSON
    for record in records:
        _check_record(record)
    [stop] = [i for i, r in enumerate(records) if isinstance(r, ErrorEvent)]
    assert records[stop] == ErrorEvent(t=records[stop].t, message="interrupted")
    # After the interruption: running activities are cancelled and the platform acknowledges the
    # cancellations (an activity interrupted while being started never reached the platform, so
    # nothing acknowledges it), then the run finishes.
    after = records[stop + 1 : -1]
    cancelled = [r.id for r in after if isinstance(r, CancelEvent)]
    acknowledged = [r.id for r in after if isinstance(r, UpdateEvent) and r.status == "cancelled"]
    assert all(isinstance(r, CancelEvent | UpdateEvent) for r in after)
    assert acknowledged == (cancelled if stop_at == "assign" else [])
    finish = records[-1]
    assert isinstance(finish, FinishEvent) and finish.status == "interrupted"


def test_interrupt_while_an_activity_runs_cancels_it(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"

    def ctrl_c(record: TraceEvent) -> None:
        match record:
            # The step after `drive(kitchen)` started: the platform is running it.
            case AssignEvent(fluent="said()"):
                raise KeyboardInterrupt

    run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(record=True, trace=trace_file), listeners=[ctrl_c])
    records = _read(trace_file)
    cancel = [r for r in records if isinstance(r, CancelEvent)]
    assert [(r.action, r.reason) for r in cancel] == [("drive(kitchen)", "the program ended")]
    # The platform's acknowledgement is recorded before the run finishes.
    ack = records[-2]
    assert isinstance(ack, UpdateEvent)
    assert (ack.action, ack.status, ack.reason) == ("drive(kitchen)", "cancelled", "preempted")
    assert isinstance(records[-1], FinishEvent)


def test_interrupt_before_the_platform_took_an_activity_cancels_it_without_waiting(tmp_path: Path) -> None:
    trace_file = tmp_path / "trace.jsonl"

    def ctrl_c(record: TraceEvent) -> None:
        match record:
            case StartEvent(action="drive(kitchen)"):
                raise KeyboardInterrupt  # while the executor starts it: the platform never got it

    run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(record=True, trace=trace_file), listeners=[ctrl_c])
    records = _read(trace_file)
    assert [r.EVENT for r in records] == ["header", "start", "error", "cancel", "finish"]


def test_failure_shows_in_the_trace_and_on_fail_runs() -> None:
    outcome = run_program(PROGRAMS / "during_on_fail.gpp", RunOptions(record=True))
    assert outcome.recording is not None
    events = [
        (r.EVENT, getattr(r, "action", getattr(r, "fluent", None)), getattr(r, "status", None))
        for r in outcome.recording.records
    ]
    failed_update = events.index(("update", "drive(kitchen)", "failed"))
    failed_end = events.index(("end", "drive(kitchen)", "failed"))
    handler = events.index(("assign", "failed()", None))
    assert failed_update < failed_end < handler
    assert outcome.result is not None and outcome.result.failures == 2
    assert outcome.result.unhandled_failures == 1  # beep() fails once, with no handler


def test_exog_event_with_a_false_precondition_is_marked_and_still_applied() -> None:
    outcome = run_program(PROGRAMS / "exog_events.gpp", RunOptions(record=True))
    assert outcome.recording is not None and outcome.postcond is True
    marked = [(r.action, r.precondition) for r in outcome.recording.of(ExogEvent)]
    assert marked == [
        ('bell("ann")', True),
        ("door_opened(front)", True),
        ('bell("bob")', False),
        ("door_opened(back)", True),
        ('bell("cid")', False),
    ]
    lines = [encode(r) for r in outcome.recording.of(ExogEvent)]
    assert ['"precondition": false' in line for line in lines] == [False, False, True, False, True]
    assert not any('"precondition": true' in line for line in lines)


def test_records_of_silent_actions_are_marked() -> None:
    outcome = run_program(ROOT / "examples" / "exog_sensing.gpp", RunOptions(record=True))
    assert outcome.recording is not None
    silent = {getattr(r, "action", None) for r in outcome.recording.records if getattr(r, "silent", False)}
    assert silent == {"battery_report(80)"}
    assert all("silent" not in to_json_dict(r) for r in outcome.recording.of(StartEvent))


# ---------------------------------------------------------------- the pinned trace

GOLDEN = ROOT / "tests" / "golden" / "trace"
UPDATE_GOLDEN = os.environ.get("GPP_UPDATE_GOLDEN") == "1"
SECONDS = re.compile(r'"seconds": [0-9.eE+-]+')
STARTED = re.compile(r'"started": "[^"]*"')


def test_the_trace_of_a_small_program_is_pinned_byte_for_byte(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """tests/golden/trace/small.jsonl is the complete trace of small.gpp on the dummy platform
    (regenerate with GPP_UPDATE_GOLDEN=1); only the planning time varies between runs."""
    monkeypatch.chdir(ROOT)  # source locations in the trace are relative, as given
    trace_file = tmp_path / "trace.jsonl"
    outcome = run_program(Path("tests/golden/trace/small.gpp"), RunOptions(record=True, trace=trace_file))
    assert outcome.ok
    actual = STARTED.sub('"started": "2026-01-01T00:00:00+00:00"', trace_file.read_text(encoding="utf-8"))
    actual = SECONDS.sub('"seconds": 0.0', actual)
    golden = GOLDEN / "small.jsonl"
    if UPDATE_GOLDEN:
        golden.write_text(actual, encoding="utf-8")
    assert actual == golden.read_text(encoding="utf-8")
    # The same bytes from the events in memory, and back.
    assert outcome.recording is not None
    assert [encode(e) for e in outcome.recording.records] == trace_file.read_text(encoding="utf-8").splitlines()
    assert [decode(line) for line in actual.splitlines()] == [
        dataclasses.replace(e, seconds=0.0)
        if isinstance(e, PlanEvent | ReplanEvent)
        else dataclasses.replace(e, started="2026-01-01T00:00:00+00:00")
        if isinstance(e, HeaderEvent)
        else e
        for e in outcome.recording.records
    ]
    kinds = {e.EVENT for e in outcome.recording.records}
    assert kinds == {
        "header",
        "assign",
        "plan",
        "start",
        "waiting",
        "exog",
        "update",
        "end",
        "sense",
        "cancel",
        "finish",
    }


# ---------------------------------------------------------------- the events and their encoding


def test_consumers_get_the_events_of_one_kind_typed() -> None:
    outcome = run_program(PROGRAMS / "sensing.gpp", RunOptions(record=True))
    assert outcome.recording is not None
    starts = outcome.recording.of(StartEvent)
    assert [s.action for s in starts][:2] == ["measure(kitchen)", "measure(hall)"]
    assert all(type(s) is StartEvent for s in starts)
    assert outcome.recording.of(EventBase) == outcome.recording.records
    [finish] = outcome.recording.of(FinishEvent)
    assert finish == outcome.recording.records[-1]


def test_events_are_frozen_and_round_their_time() -> None:
    event = UpdateEvent(t=1.23456789, action="go(a)", status="final", id=1)
    assert event.t == 1.234568
    assert UpdateEvent(t=2, action="go(a)", status="final", id=1).t == 2.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        event.t = 3.0  # type: ignore[misc]
    assert not hasattr(event, "__dict__")  # slots


def test_optional_fields_are_left_out_at_their_default_and_null_is_kept() -> None:
    assert encode(UpdateEvent(t=0, action="a()", status="final", id=1)) == (
        '{"t": 0.0, "event": "update", "action": "a()", "status": "final", "id": 1}'
    )
    # A sensing result that is null is a result: it is written.
    update = UpdateEvent(t=0, action="a()", status="final", id=1, result=None)
    assert encode(update).endswith('"id": 1, "result": null}')
    assert decode(encode(update)) == update
    assert encode(ErrorEvent(t=0, message="interrupted")) == '{"t": 0.0, "event": "error", "message": "interrupted"}'
    assert encode(ErrorEvent(t=0, code="R0099", message="m", at=None)).endswith('"message": "m", "at": null}')
    with pytest.raises(ValueError, match="both `code` and `at`"):
        ErrorEvent(t=0, code="R0099", message="m")
    assert encode(EndEvent(t=0, action="a()", status="failed", hook="call", unhandled=True, silent=True)).endswith(
        '"hook": "call", "unhandled": true, "silent": true}'
    )
    assert encode(SenseEvent(t=0, action="a()", fluent="f()", value="é")) == (
        '{"t": 0.0, "event": "sense", "action": "a()", "fluent": "f()", "value": "é"}'
    )


def test_decode_ignores_unknown_keys_and_rejects_unknown_kinds_and_missing_fields() -> None:
    assert decode('{"t": 1.5, "event": "cancel", "action": "a()", "id": 2, "since": 0}') == CancelEvent(
        t=1.5, action="a()", id=2
    )
    with pytest.raises(ValueError, match="unknown trace event 'teleport'"):
        decode('{"t": 0, "event": "teleport"}')
    with pytest.raises(ValueError, match="without `id`"):
        decode('{"t": 0, "event": "cancel", "action": "a()"}')
    with pytest.raises(ValueError, match="JSON object"):
        decode("[1, 2]")


def test_every_event_of_real_traces_round_trips(tmp_path: Path) -> None:
    recording = Recording()
    trace = Trace(tmp_path / "t.jsonl", [recording])

    def record(event: TraceEvent) -> None:
        trace.emit(event)

    for program in ("during_on_fail", "exog_events", "sensing", "solve", "compounds", "hooks"):
        outcome = run_program(PROGRAMS / f"{program}.gpp", RunOptions(), listeners=[record])
        assert outcome.ok
    trace.close()
    assert _read(tmp_path / "t.jsonl") == recording.records
    for event in recording.records:
        assert decode(encode(event)) == event
        assert json.loads(encode(event)) == to_json_dict(event)


def test_the_run_view_shows_the_pinned_trace() -> None:
    """The console views are fed by events only: the plain view's lines for the pinned trace
    (tests/golden/trace/small.view.txt) and the live view's state after it."""
    from rich.console import Console

    from gpp.run.view import LiveView, PlainView

    events = [decode(line) for line in (GOLDEN / "small.jsonl").read_text(encoding="utf-8").splitlines()]
    out = io.StringIO()
    plain = PlainView(out)
    live = LiveView(Console(file=io.StringIO(), width=120, color_system=None), "small.gpp")
    for event in events:
        plain(event)
        live(event)
    golden = GOLDEN / "small.view.txt"
    if UPDATE_GOLDEN:
        golden.write_text(out.getvalue(), encoding="utf-8")
    assert out.getvalue() == golden.read_text(encoding="utf-8")
    assert live.counts == {"actions": 4, "failed": 1, "exog": 3}
    assert live.running == {} and live.time == 4.0
    assert live.plan == events[2] and isinstance(live.plan, PlanEvent)
    assert live.at == "tests/golden/trace/small.gpp:83:5  scan(1)"


# ---------------------------------------------------------------- what the trace explains


def test_the_header_says_what_was_run(tmp_path: Path) -> None:
    import hashlib

    from gpp import __version__

    program = ROOT / "examples" / "blocksworld_faults.gpp"
    outcome = run_program(program, RunOptions(record=True, platform="sim", trace=tmp_path / "t.jsonl"))
    assert outcome.recording is not None
    header = outcome.recording.records[0]
    assert isinstance(header, HeaderEvent)
    assert (header.gpp_version, header.program, header.platform) == (__version__, str(program), "sim")
    assert header.program_sha256 == hashlib.sha256(program.read_bytes()).hexdigest()
    assert (header.world, header.seed, header.scenario) == ("blocksworld_faults", 3, None)
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d[+-]\d\d:\d\d", header.started)
    dummy = run_program(PROGRAMS / "exog_events.gpp", RunOptions(record=True))
    assert dummy.recording is not None
    first = dummy.recording.records[0]
    assert isinstance(first, HeaderEvent) and first.platform == "dummy"
    assert first.scenario is not None and first.scenario.endswith("exog_events.toml") and first.seed is None


def test_end_and_exog_records_carry_the_fluent_changes() -> None:
    outcome = run_program(ROOT / "tests" / "golden" / "trace" / "small.gpp", RunOptions(record=True))
    assert outcome.recording is not None
    ends = {e.action: e.changes for e in outcome.recording.of(EndEvent)}
    assert ends["go(kitchen)"] == ({"fluent": "at()", "value": {"symbol": "kitchen"}},)
    failed = [e for e in outcome.recording.of(EndEvent) if e.status != "final"]
    assert failed and all(e.changes == () for e in failed)  # a failed activity changes nothing
    exogs = outcome.recording.of(ExogEvent)
    assert any(e.changes for e in exogs)
    for e in exogs:
        for change in e.changes:
            assert set(change) == {"fluent", "value"}


# ---------------------------------------------------------------- numbers (docs/semantics.md, "Numbers")


def _reject_constant(name: str) -> object:
    raise ValueError(f"not strict JSON: {name}")


def _strict(line: str) -> object:
    return json.loads(line, parse_constant=_reject_constant)


def test_numbers_at_the_edge_of_the_range_are_exact_in_a_strict_json_trace(tmp_path: Path) -> None:
    program = tmp_path / "edge.gpp"
    program.write_text(
        "number fluent n() { initially: () = 0; }\n"
        'string fluent s() { initially: () = ""; }\n'
        "procedure main() {\n"
        "    n() = 10 ** 308;\n"
        "    s() = to_string(n());\n"
        "    n() = -1.7976931348623157e308;\n"
        "    n() = 1e-400;\n"
        "}\n",
        encoding="utf-8",
    )
    trace_file = tmp_path / "trace.jsonl"
    outcome = run_program(program, RunOptions(record=True, trace=trace_file))
    assert outcome.ok
    records = [_strict(line) for line in trace_file.read_text(encoding="utf-8").splitlines()]
    values = [r["value"] for r in records if isinstance(r, dict) and r["event"] == "assign"]
    assert values == [10**308, "1" + "0" * 308, -1.7976931348623157e308, 0.0]


@pytest.mark.parametrize(
    ("value", "written"),
    [
        (math.nan, '"NaN"'),
        (math.inf, '"Infinity"'),
        ([1, -math.inf], '[1, "-Infinity"]'),
        ({"compound": "P", "fields": {"x": math.nan}}, '{"compound": "P", "fields": {"x": "NaN"}}'),
        (10**5000, '"Infinity"'),
        (-(10**400), "-1" + "0" * 400),  # beyond the range, but JSON
    ],
    ids=["nan", "inf", "list", "compound", "whole-5000-digits", "whole-negative"],
)
def test_a_number_beyond_the_range_from_a_platform_is_still_strict_json(value: object, written: str) -> None:
    # Program values never leave the range; a platform's value that does is written by name.
    line = encode(SenseEvent(t=1.5, action="a()", fluent="f()", value=value))  # type: ignore[arg-type]
    _strict(line)
    assert line == '{"t": 1.5, "event": "sense", "action": "a()", "fluent": "f()", "value": ' + written + "}"


def test_a_non_finite_clock_is_still_strict_json() -> None:
    assert encode(ErrorEvent(t=math.inf, message="m")) == '{"t": "Infinity", "event": "error", "message": "m"}'
