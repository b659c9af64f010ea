"""Replaying a recorded run (gpp.traceview.replay): at every position the state the replay
reconstructs from the trace is the state the live run had there (recorded by a run control at
the same steps), stepping forward to the end and back to the start; split traces, breakpoints
searched backwards, a trace recorded without steps and an old-schema trace."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import gpp.traceview.replay as replay_module
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.trace import TraceSplit, trace_parts
from gpp.traceview.model import TraceReadError
from gpp.traceview.replay import Replay
from tests.support.replay import BLOCKSWORLD, Watcher, assert_same, record
from tests.support.replay import REPLAY_AGENT as AGENT


def assert_replays(trace: Path, watcher: Watcher) -> Replay:
    """Each position's state is the live run's at the same step, taken in order; stepping forward
    from the start to the end, then back to the start, stops at each statement's step (not at
    the end of a call, as the live debugger) with the same states."""
    replay = Replay.open(trace)
    assert replay.stepped
    steps = len(replay) - 1  # the last position is the `finish` record
    assert steps == max(watcher.states), "one position per transition"
    for index in range(len(replay)):
        assert_same(replay.state(index), watcher.states[index], f"at {index}")
    stops = [i for i in range(len(replay)) if not replay.position(i).continues]
    assert 0 < len(stops) < len(replay)  # calls end in these runs
    index, forward = 0, [0]
    while index < replay.last:
        index = replay.forward(index)
        forward.append(index)
        assert_same(replay.state(index), watcher.states[index], f"forward at {index}")
    assert forward == stops
    assert watcher.final is not None
    assert_same(replay.final, watcher.final, "after the last record")
    backward = [index]
    while index > 0:
        index = replay.backward(index)
        backward.append(index)
        assert_same(replay.state(index), watcher.states[index], f"backward at {index}")
    assert backward == stops[::-1]
    return replay


@pytest.fixture(autouse=True)
def small_keyframes(monkeypatch: pytest.MonkeyPatch) -> None:
    """Keyframes every 4 positions: these short runs step back across many of them."""
    monkeypatch.setattr(replay_module, "KEYFRAME_EVERY", 4)


def test_a_replay_on_the_dummy_has_the_live_runs_state_at_every_step(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, AGENT, "agent")
    with assert_replays(trace, watcher) as replay:
        assert replay.limits() == []
        # Random access both ways lands on the same states as stepping.
        for index in (replay.last, 0, 7, 3, 12, 2):
            assert_same(replay.state(index), watcher.states.get(index) or watcher.final, f"jump to {index}")  # type: ignore[arg-type]


def test_a_replay_on_the_sim_has_the_live_runs_state_at_every_step(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, BLOCKSWORLD, "sim", platform="sim")
    with assert_replays(trace, watcher) as replay:
        # The plan `solve` made is there while its steps run.
        planned = [i for i in range(len(replay)) if replay.state(i).plan is not None]
        assert planned and replay.state(planned[0]).plan is not None
        assert replay.state(planned[0]).plan.policy[0].startswith("stack(")  # type: ignore[union-attr]


def test_a_split_trace_replays_as_one_run_and_a_later_part_from_its_snapshot(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, BLOCKSWORLD, "split", platform="sim", trace_split=TraceSplit(max_bytes=3000))
    parts = trace_parts(trace)
    assert len(parts) >= 3
    assert_replays(trace, watcher).close()
    # Given a later part alone, the replay starts at its snapshot: the live state there.
    with Replay.open(parts[2]) as later, Replay.open(trace) as whole:
        assert any("part 2" in w for w in later.warnings)
        first = later.record(0)
        offset = next(i for i in range(len(whole)) if whole.record(i) == first)
        for index in range(len(later)):
            live = watcher.states.get(offset + index) or watcher.final
            assert live is not None
            assert_same(later.state(index), live, f"part 2 at {index}")


def test_positions_know_the_calls_and_stepping_over_and_out_follows_them(tmp_path: Path) -> None:
    trace, _ = record(tmp_path, AGENT, "calls")
    with Replay.open(trace) as replay:
        positions = [replay.position(i) for i in range(len(replay))]
        # count_down(3) recurses to count_down(1): three calls deep under main.
        deepest = max(positions, key=lambda p: p.depth)
        assert (deepest.procedure, deepest.depth) == ("count_down", 4)
        frames = replay.state(deepest.index).frames
        assert [(f["procedure"], f["args"]) for f in frames] == [
            ("count_down", {"n": 1}),
            ("count_down", {"n": 2}),
            ("count_down", {"n": 3}),
            ("main", {}),
        ]
        # Each call says where it was called.
        assert str(frames[0]["at"]).endswith("replay_agent.gpp:37:9")
        assert str(frames[2]["at"]).endswith("replay_agent.gpp:46:5")
        # Stepping out of count_down(1) reaches count_down(2)'s next statement; over it from the
        # first statement of count_down(3) skips the deeper calls.
        out = replay.forward(deepest.index, out=True)
        assert positions[out].depth == 3
        entry = next(p for p in positions if p.procedure == "count_down")
        over = replay.forward(entry.index, over=True)
        assert positions[over].depth <= entry.depth and over > deepest.index
        assert replay.backward(over, over=True) == entry.index
        # A pick's variable is a local of the frame it is bound in.
        local = [replay.state(i).frames for i in range(len(replay))]
        assert any(f.get("locals") == {"r": {"symbol": "office"}} for fs in local for f in fs)


def test_breakpoints_are_found_in_reverse(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, AGENT, "breakpoints")
    with Replay.open(trace) as replay:
        source = str(AGENT)
        line = 38  # `counter() = counter() - 1;`, once per return from count_down
        assert line in replay.lines(source)
        assert 1 not in replay.lines(source)
        on_line = replay.at_line(source, line)
        forward = _all(replay, -1, 1, on_line)
        assert len(forward) == 3
        backward = _all(replay, replay.last, -1, on_line)
        assert backward == forward[::-1]

        # A conditional breakpoint: its condition evaluated in each position's state.
        def counter_is_5(q: int) -> bool:
            return bool(on_line(q)) and replay.state(q).fluents.get("counter()") == 5

        hit = replay.find(replay.last, -1, counter_is_5)
        assert hit is not None and watcher.states[hit].fluents["counter()"] == 5
        # Function breakpoints: an action's starts; a procedure's entries (each recursive call).
        starts = _all(replay, replay.last, -1, replay.starts("go"))
        assert [replay.state(q).activities == {} for q in starts] == [True] * len(starts)
        assert [json.loads(json.dumps(replay.record(q).step)) for q in starts[::-1]] == [  # type: ignore[union-attr]
            "start(go(kitchen))",
            "start(go(office))",
            "start(go(kitchen))",
            "start(go(hall))",
        ]
        entries = _all(replay, replay.last, -1, replay.enters("count_down"))
        assert [replay.state(q).frames[0]["args"] for q in entries] == [{"n": 1}, {"n": 2}, {"n": 3}]
        assert replay.find(0, 1, replay.starts("no_such_action")) is None


def _all(replay: Replay, start: int, direction: int, hits: object) -> list[int]:
    found: list[int] = []
    q = replay.find(start, direction, hits)  # type: ignore[arg-type]
    while q is not None:
        found.append(q)
        q = replay.find(q, direction, hits)  # type: ignore[arg-type]
    return found


def test_a_trace_without_steps_replays_record_by_record(tmp_path: Path) -> None:
    trace = tmp_path / "plain.jsonl"
    run_program(AGENT, RunOptions(trace=trace))
    records = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
    with Replay.open(trace) as replay:
        assert not replay.stepped
        assert len(replay) == len(records) - 1  # every record but the header
        assert any("--trace-steps" in limit for limit in replay.limits())
        # Each position is just before its record: an assignment's value shows after it.
        assigns = [i for i in range(len(replay)) if replay.position(i).kind == "assign"]
        assert len(assigns) == 11
        for i in assigns:
            assigned = records[i + 1]  # the header is not a position
            assert replay.state(i).fluents.get(assigned["fluent"]) != assigned["value"]
            assert replay.state(i + 1).fluents[assigned["fluent"]] == assigned["value"]
        line = replay.position(assigns[0]).line
        assert line is not None and Path(line[0]).resolve() == AGENT.resolve() and line[1] == 31
        assert replay.state(replay.last).fluents["robot_at()"] == {"symbol": "hall"}
        # Without calls, a procedure breakpoint has nothing to stop at; an action's still has.
        assert replay.find(0, 1, replay.enters("visit")) is None
        assert replay.find(0, 1, replay.starts("go")) is not None


def test_an_old_schema_trace_replays_with_what_it_has(tmp_path: Path) -> None:
    # As schema 1.0 wrote it: no header, and no effects on `end` records.
    old = tmp_path / "old.jsonl"
    old.write_text(
        "\n".join(
            [
                '{"t": 0.0, "event": "start", "action": "go(kitchen)", "id": 1, "mapped": "go", "args": {}, '
                '"at": "a.gpp:3:5"}',
                '{"t": 1.0, "event": "update", "action": "go(kitchen)", "status": "final", "id": 1}',
                '{"t": 1.0, "event": "end", "action": "go(kitchen)", "status": "final", "hook": "call"}',
                '{"t": 1.0, "event": "assign", "fluent": "n()", "value": 2, "at": "a.gpp:4:5"}',
                '{"t": 1.0, "event": "finish", "status": "finished", "actions": 1, "failures": 0, "exog_events": 0}',
            ]
        )
        + "\n",
        encoding="utf-8",
    )
    with Replay.open(old) as replay:
        assert replay.header is None and len(replay) == 5
        limits = " ".join(replay.limits())
        assert "no header" in limits and "older than schema 1.1" in limits and "--trace-steps" in limits
        assert [a.action for a in replay.state(1).activities.values()] == ["go(kitchen)"]
        assert replay.state(1).activities[1].status == "running"
        assert replay.state(2).activities[1].status == "final"
        assert replay.state(3).activities == {}
        assert replay.state(4).fluents == {"n()": 2}
        # A position's place is its own record's, else the latest one named before it.
        assert [replay.state(i).location for i in range(5)] == ["a.gpp:3:5"] * 3 + ["a.gpp:4:5"] * 2


def test_what_is_not_a_trace_is_one_line_of_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"t": 0.0, "event": "finish"}\n', encoding="utf-8")
    with pytest.raises(TraceReadError, match="not a trace record"):
        Replay.open(bad)
    with pytest.raises(TraceReadError, match="no such file"):
        Replay.open(tmp_path / "missing.jsonl")
    # A run killed mid-write: the last line cut short is skipped with a warning.
    trace = tmp_path / "cut.jsonl"
    run_program(AGENT, RunOptions(trace=trace, trace_steps=True))
    text = trace.read_text(encoding="utf-8")
    trace.write_text(text[: len(text) - 20], encoding="utf-8")
    with Replay.open(trace) as replay:
        assert any("incomplete last line" in w for w in replay.warnings)
        assert replay.position(replay.last).kind != "finish"


def test_gpp_run_trace_steps_writes_step_records_and_needs_a_trace(tmp_path: Path) -> None:
    from tests.support.cli import run

    done = run("run", str(AGENT.resolve()), "-q", "--trace", "t.jsonl", "--trace-steps", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    kinds = [json.loads(line)["event"] for line in (tmp_path / "t.jsonl").read_text(encoding="utf-8").splitlines()]
    assert kinds.count("step") == 21  # one per transition, as the run's summary counts them
    assert "steps              21" in done.stdout
    refused = run("run", str(AGENT.resolve()), "-q", "--trace-steps", cwd=tmp_path)
    assert refused.returncode == 2
    assert "--trace-steps adds records to the trace file: it needs --trace FILE" in refused.stderr
    assert "Traceback" not in refused.stderr


def test_a_step_costs_the_same_at_the_end_of_a_long_trace_as_at_its_start(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from bench import soak

    monkeypatch.setattr(replay_module, "KEYFRAME_EVERY", 64)
    program = tmp_path / "loop.gpp"
    program.write_text(soak.PROGRAM, encoding="utf-8")
    trace = tmp_path / "loop.jsonl"
    run_program(program, RunOptions(trace=trace, trace_steps=True, args={"rounds": 2000}))
    records = len(trace.read_text(encoding="utf-8").splitlines())
    with Replay.open(trace) as replay:
        assert len(replay) == 4001  # a position per step, and the end
        # The index keeps the state at every 64th position, not the records.
        assert len(replay._keyframes) == -(-len(replay) // 64)
        per_position = -(-records // len(replay))

        def cost(index: int) -> int:
            before = replay.records_read
            replay.state(index)
            return replay.records_read - before

        # Stepping back reads at most a keyframe's worth of records, wherever it is.
        replay.state(replay.last)
        at_end = [cost(i) for i in range(replay.last - 1, replay.last - 200, -1)]
        replay.state(200)
        at_start = [cost(i) for i in range(199, 0, -1)]
        bound = 64 * per_position + 1
        assert max(at_end) <= bound and max(at_start) <= bound
        assert max(at_end) == max(at_start)
        # Stepping forward reads the records of one step (and the position's own).
        assert max(cost(i) for i in range(1, 200)) <= per_position + 2


def test_a_deep_recursion_lists_its_innermost_calls_and_how_many_there_are(tmp_path: Path) -> None:
    from gpp.runtime.callstack import MAX_FRAMES

    program = tmp_path / "deep.gpp"
    program.write_text(
        "number fluent x() {\ninitially:\n    () = 0;\n}\n\n"
        "procedure down(number n) {\n    if (n > 0) {\n        x() = x() + 1;\n        down(n - 1);\n"
        "        x() = x() - 1;\n    }\n}\n\nprocedure main() {\n    down(100);\n    x() = 1000;\n}\n",
        encoding="utf-8",
    )
    trace, watcher = record(tmp_path, program, "deep")
    with Replay.open(trace) as replay:
        deepest = max(range(len(replay)), key=lambda q: replay.position(q).depth)
        state = replay.state(deepest)
        # down(100) ... down(1) under main: 101 calls, the innermost 31 and main listed.
        assert replay.position(deepest).depth == state.calls == 101
        assert len(state.frames) == MAX_FRAMES
        assert [f["args"] for f in state.frames[:2]] == [{"n": 1}, {"n": 2}]
        assert state.frames[-1]["procedure"] == "main"
        assert_same(state, watcher.states[deepest], "at the deepest call")
        # Stepping out of the innermost call still knows the depth.
        assert replay.position(replay.forward(deepest, out=True)).depth == 100


def test_start_effects_are_in_the_replayed_state(tmp_path: Path) -> None:
    program = tmp_path / "start.gpp"
    program.write_text(
        "number fluent n() { initially: () = 1; }\n"
        "bool fluent busy() { initially: () = false; }\n"
        "action work() {\nprecondition:\n    !busy()\nstart_effect:\n    busy() = true;\n    n() = n() + 1;\n"
        "effect:\n    busy() = false;\n    n() = n() * 10;\n}\n"
        "procedure main() {\n    work();\n    work();\n}\n",
        encoding="utf-8",
    )
    trace, watcher = record(tmp_path, program, "start")
    with assert_replays(trace, watcher) as replay:
        # While an activity runs, its start effects hold: busy, and n() one more.
        running = [q for q in range(len(replay)) if replay.state(q).activities]
        assert running and all(replay.state(q).fluents.get("busy()") is True for q in running)
        assert replay.final.fluents["n()"] == 210  # ((1 + 1) * 10 + 1) * 10
