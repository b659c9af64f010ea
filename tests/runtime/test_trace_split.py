"""A long run: its memory does not grow with its length (the trace keeps no records), a wait
writes one `waiting` record however many events arrive, and a split trace (`--trace-max-size`,
`--trace-max-time`) is parts that each validate, start with a header and a snapshot of the
state, and read back as the same run as an unsplit trace."""

from __future__ import annotations

import dataclasses
import json
import tracemalloc
from pathlib import Path

import jsonschema
import pytest

from bench import soak
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.events import (
    AssignEvent,
    EndEvent,
    ExogEvent,
    FinishEvent,
    HeaderEvent,
    JsonValue,
    PlanEvent,
    ReplanEvent,
    SenseEvent,
    SnapshotEvent,
    StartEvent,
    TraceEvent,
    UpdateEvent,
    WaitingEvent,
    decode,
    load_schema,
    waiting_fields,
)
from gpp.runtime.trace import Recording, TraceSplit, part_path, trace_parts
from gpp.traceview.model import build_run_model, load_trace
from tests.support.cli import run

LOOP = soak.PROGRAM  # rounds of `tick()` until `done()` reaches the given number

WAIT = """\
// scenario: wait.toml
number fluent n() {
initially:
    () = 0;
}

exog_action bump() {
effect:
    n() = n() + 1;
}

procedure main() {
    test(n() >= 300);
    n() = 0;
}
"""


def loop(tmp_path: Path) -> Path:
    program = tmp_path / "loop.gpp"
    program.write_text(LOOP, encoding="utf-8")
    return program


class MemoryProbe:
    """Memory Python holds (tracemalloc) when the loop has ended given numbers of rounds."""

    def __init__(self, *rounds: int) -> None:
        self.at = set(rounds)
        self.ended = 0
        self.held: dict[int, int] = {}

    def __call__(self, event: TraceEvent) -> None:
        if isinstance(event, EndEvent):
            self.ended += 1
            if self.ended in self.at:
                self.held[self.ended] = tracemalloc.get_traced_memory()[0]


@pytest.mark.slow  # a long run under tracemalloc: `make test` runs it, `make quick` does not
@pytest.mark.parametrize("traced", [False, True], ids=["no trace file", "split trace file"])
def test_memory_does_not_grow_with_the_length_of_a_run(tmp_path: Path, traced: bool) -> None:
    # 2,000 and 20,000 executor steps (two a round). Before the trace kept no records the
    # difference was about 1.65 KB a step: 30 MB.
    probe = MemoryProbe(1_000, 10_000)
    trace = tmp_path / "run.jsonl" if traced else None
    options = RunOptions(args={"rounds": 10_000}, trace=trace, trace_split=TraceSplit(max_bytes=200_000))
    tracemalloc.start()
    try:
        outcome = run_program(loop(tmp_path), options, listeners=[probe])
    finally:
        tracemalloc.stop()
    assert outcome.ok and outcome.result is not None and outcome.result.steps == 20_000
    grown = probe.held[10_000] - probe.held[1_000]
    assert grown < 256 * 1024, f"{grown / 1024:.0f} KB more at 20k steps than at 2k"
    if traced:
        assert len(trace_parts(tmp_path / "run.jsonl")) > 10


def test_a_recording_keeps_all_events_or_the_latest_or_some_kinds(tmp_path: Path) -> None:
    latest, plans, everything = Recording(keep=3), Recording(kinds=(PlanEvent, ReplanEvent)), Recording()
    outcome = run_program(loop(tmp_path), RunOptions(args={"rounds": 50}), [latest, plans, everything])
    assert outcome.ok and outcome.recording is None  # nothing kept unless asked for
    assert len(everything) == 1 + 3 * 50 + 1 and len(latest) == 3 and len(plans) == 0
    assert list(latest) == list(everything)[-3:]
    assert isinstance(list(latest)[-1], FinishEvent)
    assert len(everything.of(StartEvent)) == 50
    recorded = run_program(loop(tmp_path), RunOptions(args={"rounds": 50}, record=True))
    assert recorded.recording is not None and len(recorded.recording) == len(everything)


def test_a_wait_writes_one_waiting_record_however_many_events_arrive(tmp_path: Path) -> None:
    program = tmp_path / "wait.gpp"
    program.write_text(WAIT, encoding="utf-8")
    (tmp_path / "wait.toml").write_text(
        "".join(f'[[exog]]\nat = {t}.0\naction = "bump"\n\n' for t in range(1, 301)), encoding="utf-8"
    )
    outcome = run_program(program, RunOptions(record=True))
    assert outcome.ok and outcome.recording is not None
    assert len(outcome.recording.of(ExogEvent)) == 300
    waits = outcome.recording.of(WaitingEvent)
    assert [(w.t, w.resumed) for w in waits] == [(0.0, False), (300.0, True)]
    # The condition says what held when the wait began.
    assert waits[0].condition == "this test is false (n() = 0)"


# ---------------------------------------------------------------- split traces


def run_split(tmp_path: Path, name: str, split: TraceSplit | None, rounds: int = 300) -> Path:
    trace = tmp_path / name
    outcome = run_program(loop(tmp_path), RunOptions(args={"rounds": rounds}, trace=trace, trace_split=split))
    assert outcome.ok
    return trace


def comparable(events: list[TraceEvent]) -> list[TraceEvent]:
    """The events without what differs between two runs of one program (the start time)."""
    return [dataclasses.replace(e, started="") if isinstance(e, HeaderEvent) else e for e in events]


def replayed(events: list[TraceEvent]) -> tuple[dict[str, JsonValue], dict[int, tuple[str, str]]]:
    """The fluent values and the unconsumed activities the records tell, from the start."""
    fluents: dict[str, JsonValue] = {}
    activities: dict[int, tuple[str, str]] = {}
    for e in events:
        match e:
            case EndEvent() | ExogEvent():
                fluents.update({str(c["fluent"]): c["value"] for c in e.changes})
                if isinstance(e, EndEvent):
                    [key] = [k for k, (action, _) in activities.items() if action == e.action]
                    del activities[key]
            case AssignEvent() | SenseEvent():
                fluents[e.fluent] = e.value
            case StartEvent():
                activities[e.id] = (e.action, "running")
            case UpdateEvent():
                activities[e.id] = (e.action, e.status)
            case _:
                pass
    return fluents, activities


def lines(path: Path) -> list[str]:
    return path.read_text(encoding="utf-8").splitlines()


def test_a_split_trace_is_parts_that_each_validate_and_start_with_a_header_and_a_snapshot(tmp_path: Path) -> None:
    validator = jsonschema.Draft202012Validator(load_schema())
    first = run_split(tmp_path, "run.jsonl", TraceSplit(max_bytes=4_000))
    parts = trace_parts(first)
    assert len(parts) > 5
    assert [p.name for p in parts] == ["run.jsonl", *(f"run.{n}.jsonl" for n in range(1, len(parts)))]
    assert sorted(tmp_path.glob("run*.jsonl")) == sorted(parts)
    header = decode(lines(first)[0])
    assert isinstance(header, HeaderEvent) and header.part is None and header.previous is None
    for number, part in enumerate(parts):
        records = lines(part)
        for line in records:
            assert validator.is_valid(json.loads(line)), (part.name, line)
        head = decode(records[0])
        assert isinstance(head, HeaderEvent)
        # Each part holds about its size: at most the records of one more step.
        assert part.stat().st_size < 4_000 + 1_000
        assert (json.loads(records[-1])["event"] == "finish") == (part == parts[-1])
        if number == 0:
            continue
        assert head.part == number and head.previous == parts[number - 1].name
        assert dataclasses.replace(head, t=header.t, part=None, previous=None) == header
        assert isinstance(decode(records[1]), SnapshotEvent)


def test_each_snapshot_is_the_state_the_records_before_it_tell(tmp_path: Path) -> None:
    first = run_split(tmp_path, "run.jsonl", TraceSplit(max_bytes=3_000))
    before: list[TraceEvent] = []
    for part in trace_parts(first):
        events = [decode(line) for line in lines(part)]
        if before:
            snapshot = events[1]
            assert isinstance(snapshot, SnapshotEvent)
            fluents, activities = replayed(before)
            assert {str(f["fluent"]): f["value"] for f in snapshot.fluents} == fluents
            assert {int(str(a["id"])): (a["action"], a["status"]) for a in snapshot.activities} == activities
            assert snapshot.actions == len([e for e in before if isinstance(e, StartEvent)])
            assert snapshot.t >= before[-1].t
            events = events[2:]
        before.extend(events)


def test_a_snapshot_says_what_the_program_waits_for_as_its_waiting_record_does(tmp_path: Path) -> None:
    """tests/programs/solve_retries.gpp split every 0.5 s of platform time: the parts that begin
    while the program waits for a planned drive say which drive and which step of the plan."""
    trace = tmp_path / "retries.jsonl"
    program = Path(__file__).resolve().parents[1] / "programs" / "solve_retries.gpp"
    assert run_program(program, RunOptions(trace=trace, trace_split=TraceSplit(max_seconds=0.5))).ok
    waiting: dict[str, JsonValue] | None = None
    seen: list[dict[str, JsonValue]] = []
    for number, part in enumerate(trace_parts(trace)):
        events = [decode(line) for line in lines(part)]
        if number:
            snapshot = events[1]
            assert isinstance(snapshot, SnapshotEvent)
            assert snapshot.waiting == waiting
            if snapshot.waiting is not None:
                seen.append(snapshot.waiting)
            events = events[2:]
        for e in events:
            if isinstance(e, WaitingEvent):
                waiting = None if e.resumed else waiting_fields(e)
    assert any(w.get("reason") == "activity" and str(w.get("action", "")).startswith("goto(") for w in seen), seen


def test_a_split_trace_reads_back_as_the_same_run_as_an_unsplit_one(tmp_path: Path) -> None:
    whole = load_trace(run_split(tmp_path, "whole.jsonl", None))
    assert whole.warnings == [] and isinstance(whole.events[-1], FinishEvent)
    (tmp_path / "size").mkdir()
    by_size = run_split(tmp_path, "size/run.jsonl", TraceSplit(max_bytes=5_000))
    by_time = run_split(tmp_path, "timed.jsonl", TraceSplit(max_seconds=50.0))
    assert len(trace_parts(by_size)) > 3 and len(trace_parts(by_time)) == 300 // 50 + 1
    for first in (by_size, by_time):
        split = load_trace(first)
        assert split.warnings == []
        assert comparable(split.events) == comparable(whole.events)
    # Given the folder that holds it, the same.
    assert comparable(load_trace(tmp_path / "size").events) == comparable(whole.events)


def test_parts_left_by_an_earlier_run_are_not_read_as_this_one(tmp_path: Path) -> None:
    run_split(tmp_path, "run.jsonl", TraceSplit(max_bytes=2_000))
    many = len(trace_parts(tmp_path / "run.jsonl"))
    # The same name again, split in fewer parts: the earlier run's later parts are removed.
    run_split(tmp_path, "run.jsonl", TraceSplit(max_bytes=20_000))
    fewer = trace_parts(tmp_path / "run.jsonl")
    assert 1 < len(fewer) < many
    assert not part_path(tmp_path / "run.jsonl", len(fewer)).exists()
    # A file that only looks like the next part (not a part of this run) is not read.
    part_path(tmp_path / "run.jsonl", len(fewer)).write_text(lines(fewer[-1])[0] + "\n", encoding="utf-8")
    assert trace_parts(tmp_path / "run.jsonl") == fewer


def test_a_later_part_alone_reads_with_a_warning(tmp_path: Path) -> None:
    first = run_split(tmp_path, "run.jsonl", TraceSplit(max_bytes=4_000))
    loaded = load_trace(trace_parts(first)[2])
    assert isinstance(loaded.events[1], SnapshotEvent)
    [warning] = loaded.warnings
    assert "part 2 of a split trace (after run.1.jsonl)" in warning and "give the first part" in warning


# ---------------------------------------------------------------- gpp run and gpp trace


def test_gpp_run_splits_the_trace_and_gpp_trace_reads_the_parts_as_one_run(tmp_path: Path) -> None:
    program = loop(tmp_path)
    (tmp_path / "out").mkdir()
    done = run(
        "run",
        str(program),
        "--arg",
        "rounds=200",
        "-q",
        "--trace",
        "out/run.jsonl",
        "--trace-max-size",
        "5KB",
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    parts = trace_parts(tmp_path / "out" / "run.jsonl")
    assert len(parts) > 3
    whole = run("trace", "summary", "out/run.jsonl", "--width", "100", cwd=tmp_path)
    assert whole.returncode == 0 and whole.stderr == ""
    assert "200 activities" in whole.stdout and "finished" in whole.stdout
    assert run("trace", "summary", "out", "--width", "100", cwd=tmp_path).stdout == whole.stdout
    timed = run(
        "run", str(program), "--arg", "rounds=200", "-q", "--trace", "t.jsonl", "--trace-max-time", "1m", cwd=tmp_path
    )
    assert timed.returncode == 0 and len(trace_parts(tmp_path / "t.jsonl")) == 200 // 60 + 1


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--trace-max-size", "10MB"], "--trace-max-size splits the trace file: it needs --trace FILE"),
        (["--trace-max-time", "1h"], "--trace-max-time splits the trace file: it needs --trace FILE"),
        (
            ["--trace", "t.jsonl", "--trace-max-size", "ten"],
            "--trace-max-size takes a size such as 10MB, 500KB or 4096, not 'ten'",
        ),
        (
            ["--trace", "t.jsonl", "--trace-max-size", "0"],
            "--trace-max-size takes a size such as 10MB, 500KB or 4096, not '0'",
        ),
        (
            ["--trace", "t.jsonl", "--trace-max-time", "5x"],
            "--trace-max-time takes a time such as 90s, 30m or 2h, not '5x'",
        ),
        (
            ["--trace", "t.jsonl", "--trace-max-time", "-1"],
            "--trace-max-time takes a time such as 90s, 30m or 2h, not '-1'",
        ),
    ],
)
def test_the_split_options_are_usage_errors_where_they_do_not_apply(
    tmp_path: Path, args: list[str], message: str
) -> None:
    done = run("run", str(loop(tmp_path)), "--arg", "rounds=2", *args, cwd=tmp_path)
    assert (done.returncode, done.stdout, done.stderr) == (2, "", f"error: {message}\n")
    assert not list(tmp_path.glob("*.jsonl"))


def test_a_trace_of_an_older_schema_reads_as_before(tmp_path: Path) -> None:
    # The pinned trace as 1.3 wrote it (the same records, an older version): no warning, the
    # same run; and 1.3's `waiting` record after every event reads as the waits it was.
    golden = Path(__file__).resolve().parents[1] / "golden" / "trace" / "small.jsonl"
    now = load_trace(golden)
    old = tmp_path / "old.jsonl"
    old.write_text(
        golden.read_text(encoding="utf-8").replace('"schema_version": "1.4"', '"schema_version": "1.3"'),
        encoding="utf-8",
    )
    before = load_trace(old)
    assert before.warnings == [] and len(before.events) == len(now.events)
    assert build_run_model(before.events).activities == build_run_model(now.events).activities
    waits = [
        WaitingEvent(
            t=float(t), statement="test(n() >= 2);", at="a.gpp:3:5", condition=f"this test is false (n() = {t})"
        )
        for t in range(2)
    ]
    model = build_run_model([*waits, dataclasses.replace(waits[-1], t=2.0, resumed=True)])
    assert [(w.start, w.stop) for w in model.waits] == [(0.0, 1.0), (1.0, 2.0)]
