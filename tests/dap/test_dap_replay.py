"""`gpp dap` replaying a recorded run (`launch` with `"trace"`), driven by the Python DAP client
over a real `gpp dap` process: stepping to the end and back to the start with the fluent values
at each stop those of the live run at the same step (on the dummy and on the sim), breakpoints
hit in reverse, a split trace, a trace without steps and one of an old schema."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gpp.runtime.trace import TraceSplit
from gpp.runtime.values import show_json
from tests.support.dap_client import DapClient, Message, dap_session
from tests.support.replay import BLOCKSWORLD, REPLAY_AGENT, Watcher, record

# Processes: each test records a run, then replays it in a `gpp dap` process.
pytestmark = pytest.mark.slow


def position(stop: Message) -> int:
    """The 0-based position a stop's description names (`position 3 of 40 ...`)."""
    words = str(stop.get("description", "")).split("position ", 1)[1].split()
    return int(words[0]) - 1


def fluent(client: DapClient, instance: str) -> object:
    """A fluent instance's value at the stop, as the trace writes values, by `evaluate`."""
    return client.evaluate(instance)["result"]


def expect(client: DapClient, watcher: Watcher, at: int | None, instances: list[str], where: str) -> None:
    """The fluent values at the stop are the live run's at step `at` (None: at its end). An
    instance the run had not touched yet has its initial value (known by the run's end)."""
    live = watcher.states[at] if at is not None else watcher.final
    assert live is not None and watcher.final is not None
    for instance in instances:
        value = live.fluents.get(instance, watcher.final.initial[instance])
        assert fluent(client, instance) == show_json(value), (where, instance)


def test_stepping_to_the_end_and_back_shows_the_live_values_on_the_dummy(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, REPLAY_AGENT, "agent")
    watched = ["counter()", "robot_at()", "visits(office)", "visits(kitchen)"]
    with dap_session(tmp_path) as client:
        client.start({"trace": str(trace), "stopOnEntry": True})
        stop = client.stopped()
        assert stop["reason"] == "entry" and position(stop) == 0
        # The trace was recorded with steps: nothing is missing.
        assert not any("not in this trace" in o for o in client.outputs())
        at, visited = 0, []
        while True:
            expect(client, watcher, at if at in watcher.states else None, watched, f"forward at {at}")
            visited.append(at)
            client.ok("stepIn", {"threadId": 1})
            stop = client.stopped()
            if "the end of the recorded run" in stop["description"]:
                break
            at = position(stop)
        # A stop per statement, as live: not at the end of a call (`continues`).
        steps = [json.loads(line) for line in trace.read_text(encoding="utf-8").splitlines()]
        records = [r for r in steps if r["event"] == "step"]
        stops = [i for i, r in enumerate(records) if not r.get("continues")] + [len(records)]  # and `finish`
        assert visited == stops and len(stops) < max(watcher.states)
        while at > 0:
            client.ok("stepBack", {"threadId": 1})
            at = position(client.stopped())
            expect(client, watcher, at, watched, f"back at {at}")
        client.ok("stepBack", {"threadId": 1})
        assert "the start of the recorded run" in client.stopped()["description"]


def test_the_stack_scopes_and_evaluate_at_a_recorded_stop(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, REPLAY_AGENT, "stack")
    source = str(REPLAY_AGENT)
    with dap_session(tmp_path) as client:
        # Line 36 adds `n` to counter(): stop there in count_down(1), three calls deep.
        client.start({"trace": str(trace)}, {source: [{"line": 36, "condition": "n == 1"}]})
        stop = client.stopped()
        assert stop["reason"] == "breakpoint"
        frames = client.ok("stackTrace", {"threadId": 1})["stackFrames"]
        assert [f["name"] for f in frames] == ["count_down(1)", "count_down(2)", "count_down(3)", "main()"]
        assert [f["line"] for f in frames[:3]] == [36, 37, 37]
        assert client.scope("Arguments") == [
            {"name": "n", "value": "1", "type": "number", "variablesReference": 0, "evaluateName": "n"}
        ]
        assert client.evaluate("n * 10")["result"] == "10"
        assert client.evaluate("n", frame=2)["result"] == "3"
        fluents = {v["name"]: v["value"] for v in client.scope("Fluents")}
        assert fluents["counter()"] == show_json(watcher.states[position(stop)].fluents["counter()"])
        # A mistake in an expression is one located line.
        message = client.error("evaluate", {"expression": "counter() + ", "frameId": 0, "context": "repl"})
        assert "column" in message
        run = {v["name"]: v["value"] for v in client.scope("Run")}
        assert run["next"] == "counter() = 7"


def test_breakpoints_stop_in_reverse(tmp_path: Path) -> None:
    trace, watcher = record(tmp_path, REPLAY_AGENT, "reverse")
    source = str(REPLAY_AGENT)
    with dap_session(tmp_path) as client:
        # Line 38: `counter() = counter() - 1;`, once on each return from count_down.
        client.start({"trace": str(trace)}, {source: [{"line": 38}]})
        hits = [position(client.stopped())]
        for _ in range(2):
            client.ok("continue", {"threadId": 1})
            hits.append(position(client.stopped()))
        client.ok("continue", {"threadId": 1})
        assert "the end of the recorded run" in client.stopped()["description"]
        back = []
        for _ in range(3):
            client.ok("reverseContinue", {"threadId": 1})
            stop = client.stopped()
            assert stop["reason"] == "breakpoint"
            back.append(position(stop))
        assert back == hits[::-1]
        # counter() before each decrement: 7 after count_down(3) added 3 + 2 + 1, then 6, 5.
        assert [watcher.states[h].fluents["counter()"] for h in hits] == [7, 6, 5]
        client.ok("reverseContinue", {"threadId": 1})
        assert "the start of the recorded run" in client.stopped()["description"]
        # Conditional and function breakpoints, backwards from the end.
        client.ok("setBreakpoints", {"source": {"path": source}, "breakpoints": [{"line": 38, "condition": "n == 3"}]})
        client.ok("setFunctionBreakpoints", {"breakpoints": [{"name": "go"}]})
        client.ok("continue", {"threadId": 1})
        stops = [client.stopped()]
        while "the end" not in stops[-1]["description"]:
            client.ok("continue", {"threadId": 1})
            stops.append(client.stopped())
        forward = [(s["reason"], position(s)) for s in stops[:-1]]
        # From the start (the first `go` is the first position, where the replay already is):
        # the return from count_down(3), then the other three starts of `go`.
        assert [r for r, _ in forward] == ["breakpoint"] + ["function breakpoint"] * 3
        assert watcher.states[forward[0][1]].fluents["counter()"] == 5
        backward = []
        for _ in forward:
            client.ok("reverseContinue", {"threadId": 1})
            stop = client.stopped()
            backward.append((stop["reason"], position(stop)))
        assert backward == forward[::-1]


def test_a_sim_run_replays_with_its_values_and_a_split_trace_as_one_run(tmp_path: Path) -> None:
    whole, watcher = record(tmp_path, BLOCKSWORLD, "sim", platform="sim")
    split, split_watcher = record(
        tmp_path, BLOCKSWORLD, "split", platform="sim", trace_split=TraceSplit(max_bytes=3000)
    )
    assert (tmp_path / "split.2.jsonl").is_file()
    watched = ["loc(a)", "loc(b)", "loc(c)"]
    for trace, live in ((whole, watcher), (split, split_watcher)):
        with dap_session(tmp_path) as client:
            client.start({"trace": str(trace), "stopOnEntry": True})
            at = position(client.stopped())
            while True:
                expect(client, live, at if at in live.states else None, watched, f"{trace.name} at {at}")
                client.ok("next", {"threadId": 1})
                stop = client.stopped()
                if "the end of the recorded run" in stop["description"]:
                    break
                at = position(stop)
            client.ok("reverseContinue", {"threadId": 1})
            assert position(client.stopped()) == 0
            expect(client, live, 0, watched, f"{trace.name} back at the start")


def test_a_trace_without_steps_or_of_an_old_schema_says_what_it_cannot_show(tmp_path: Path) -> None:
    from gpp.run.runner import RunOptions, run_program

    plain = tmp_path / "plain.jsonl"
    run_program(REPLAY_AGENT, RunOptions(trace=plain))
    with dap_session(tmp_path) as client:
        client.start({"trace": str(plain), "stopOnEntry": True})
        client.stopped()
        assert any("--trace-steps" in o for o in client.outputs())
        assert client.top()["name"].endswith("[calls not recorded]")
        client.ok("setBreakpoints", {"source": {"path": str(REPLAY_AGENT)}, "breakpoints": [{"line": 31}]})
        client.ok("continue", {"threadId": 1})
        stop = client.stopped()
        assert stop["reason"] == "breakpoint" and client.top()["line"] == 31
        # Without steps, a stop says which record comes next, as `gpp run` prints it.
        assert "next: assign counter() = 1 (recorded run)" in stop["description"]
        # The trace has no calls: a parameter has no value to show, and says so.
        message = client.error("evaluate", {"expression": "r", "frameId": 0, "context": "repl"})
        assert "has no value" in message and "internal error" not in message
        client.ok("stepBack", {"threadId": 1})
        assert position(client.stopped()) == position(stop) - 1
    # As schema 1.3 wrote it (before snapshots, steps and the 1.5 fields): it still replays.
    old = tmp_path / "old.jsonl"
    lines = [json.loads(line) for line in plain.read_text(encoding="utf-8").splitlines()]
    lines[0]["schema_version"] = "1.3"
    old.write_text("".join(json.dumps(r) + "\n" for r in lines if r["event"] != "waiting"), encoding="utf-8")
    with dap_session(tmp_path) as client:
        client.start({"trace": str(old)})
        stop = client.stopped()
        assert "the end of the recorded run" in stop["description"]
        assert client.evaluate("robot_at()")["result"] == "hall"
        assert client.evaluate("visits(office)")["result"] == "11"


@pytest.mark.parametrize(
    ("launch", "message"),
    [
        ({"trace": "missing.jsonl"}, "launch's `trace`: no such file"),
        ({"trace": "headless.jsonl"}, "the trace has no header"),
        ({"trace": "moved.jsonl"}, "the program it recorded, gone.gpp, is not there"),
        ({"trace": "t.jsonl", "program": "a.gpp"}, "either `program` (a live run) or `trace`"),
        ({"trace": "t.jsonl", "stopOnEntyr": True}, "launch has no argument `stopOnEntyr`"),
    ],
)
def test_a_trace_that_cannot_be_replayed_is_one_line_of_error(tmp_path: Path, launch: Message, message: str) -> None:
    (tmp_path / "headless.jsonl").write_text(
        '{"t": 0.0, "event": "finish", "status": "finished", "actions": 0, "failures": 0, "exog_events": 0}\n',
        encoding="utf-8",
    )
    header = {
        "t": 0.0,
        "event": "header",
        "schema_version": "1.6",
        "gpp_version": "0.1.0",
        "program": "gone.gpp",
        "program_sha256": "0" * 64,
        "platform": "dummy",
        "started": "2026-01-01T00:00:00+00:00",
    }
    (tmp_path / "moved.jsonl").write_text(
        json.dumps(header) + "\n" + (tmp_path / "headless.jsonl").read_text(encoding="utf-8"), encoding="utf-8"
    )
    with dap_session(tmp_path) as client:
        client.ok("initialize", {"adapterID": "gpp"})
        error = client.error("launch", launch)
        assert message in error and "Traceback" not in error


def test_watcher_states_are_the_runs(tmp_path: Path) -> None:
    """The live states the replay is compared with change over the run (a comparison with a
    constant would pass whatever the replay showed)."""
    _, watcher = record(tmp_path, REPLAY_AGENT, "watched")
    assert isinstance(watcher, Watcher)
    values = {json.dumps(s.fluents.get("counter()")) for s in watcher.states.values()}
    assert len(values) >= 5


def test_the_walkthrough_of_debugging_md_works_as_written(tmp_path: Path) -> None:
    """docs/debugging.md, "Stepping back through a recorded run", on the tutorial's coffee agent."""
    from tests.support.cli import run

    tutorial = (Path(__file__).resolve().parents[2] / "docs" / "tutorial.md").read_text(encoding="utf-8")
    program = tutorial.split("```gpp run\n", 1)[1].split("```", 1)[0]
    assert program.splitlines()[30] == "    go(office);"  # line 31, as the walkthrough says
    (tmp_path / "coffee.gpp").write_text(program, encoding="utf-8")
    done = run("run", "coffee.gpp", "--trace", "coffee.jsonl", "--trace-steps", "-q", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    source = str(tmp_path / "coffee.gpp")
    with dap_session(tmp_path) as client:
        client.start({"trace": "coffee.jsonl", "cwd": str(tmp_path)}, {source: [{"line": 31}]})
        stop = client.stopped()
        assert "breakpoint hit: position 5 of 7 at 2.000 s, next: start(go(office))" in stop["description"]
        assert client.evaluate("has_coffee()")["result"] == "true"
        assert {v["name"]: v["value"] for v in client.scope("Fluents")}["robot_at()"] == "kitchen"
        client.ok("stepBack", {"threadId": 1})
        assert "next: start(take_coffee())" in client.stopped()["description"]
        assert client.top()["line"] == 30 and client.evaluate("has_coffee()")["result"] == "false"
        condition = {"line": 29, "condition": "robot_at() == office"}
        client.ok("setBreakpoints", {"source": {"path": source}, "breakpoints": [condition]})
        client.ok("reverseContinue", {"threadId": 1})
        stop = client.stopped()
        assert stop["reason"] == "breakpoint" and "at 1.000 s, next: end(go(kitchen))" in stop["description"]
        client.ok("continue", {"threadId": 1})
        assert "the end of the recorded run" in client.stopped()["description"]


def test_a_live_sessions_trace_replays_step_by_step(tmp_path: Path) -> None:
    with dap_session(tmp_path) as client:
        client.start({"program": str(REPLAY_AGENT), "traceFile": "live.jsonl", "cwd": str(tmp_path)})
        client.event("terminated")
    kinds = [json.loads(line)["event"] for line in (tmp_path / "live.jsonl").read_text(encoding="utf-8").splitlines()]
    assert kinds.count("step") == 21
    with dap_session(tmp_path) as client:
        client.start({"trace": "live.jsonl", "stopOnEntry": True})
        client.stopped()
        client.ok("next", {"threadId": 1})
        assert client.top()["name"] == "visit(kitchen)"


def test_the_failed_activity_filter_stops_after_each_failure_both_ways(tmp_path: Path) -> None:
    program = Path(__file__).resolve().parents[1] / "programs" / "during_on_fail.gpp"
    trace, watcher = record(tmp_path, program, "failing")
    with dap_session(tmp_path) as client:
        client.start({"trace": str(trace)}, exceptions=["failed"])
        stops = [client.stopped()]
        while "the end of the recorded run" not in stops[-1]["description"]:
            client.ok("continue", {"threadId": 1})
            stops.append(client.stopped())
        failures = [position(s) for s in stops if s["reason"] == "exception"]
        # The scenario fails the first drive to the kitchen and the first beep.
        assert len(failures) == 2
        said = [s["text"] for s in stops if s["reason"] == "exception"]
        assert said == ["`drive(kitchen)` failed", "`beep()` failed"]
        back = []
        for _ in failures:
            client.ok("reverseContinue", {"threadId": 1})
            back.append(position(client.stopped()))
        assert back == failures[::-1]
        # Just after a failure, the failed activity is there, not consumed yet.
        for at in failures:
            assert "failed" in {status for _, status in watcher.states[at].activities.values()}


def test_a_deep_recursion_shows_how_many_calls_the_trace_leaves_out(tmp_path: Path) -> None:
    program = tmp_path / "deep.gpp"
    program.write_text(
        "number fluent x() {\ninitially:\n    () = 0;\n}\n\n"
        "procedure down(number n) {\n    if (n > 0) {\n        x() = x() + 1;\n        down(n - 1);\n"
        "        x() = x() - 1;\n    }\n}\n\nprocedure main() {\n    down(40);\n    x() = 1000;\n}\n",
        encoding="utf-8",
    )
    trace, _ = record(tmp_path, program, "deep")
    with dap_session(tmp_path) as client:
        # Line 8 (`x() = x() + 1;`) in down(1): 41 calls deep.
        client.start({"trace": str(trace)}, {str(program): [{"line": 8, "condition": "n == 1"}]})
        assert client.stopped()["reason"] == "breakpoint"
        names = [f["name"] for f in client.ok("stackTrace", {"threadId": 1})["stackFrames"]]
        assert names[:2] == ["down(1)", "down(2)"] and names[-1] == "main()"
        assert names[-2] == "... 9 more calls (not in the trace)" and len(names) == 33
        assert client.evaluate("x()")["result"] == "39"


def test_the_plan_of_the_enclosing_solve_and_its_progress(tmp_path: Path) -> None:
    trace, _ = record(tmp_path, BLOCKSWORLD, "plan", platform="sim")
    with dap_session(tmp_path) as client:
        # `stack` runs the plan's steps; line 48 (`gripper_home();`) comes after the `solve`.
        client.start({"trace": str(trace)}, {str(BLOCKSWORLD): [{"line": 48}]}, functions=["stack"])
        marks = []
        for _ in range(4):
            stop = client.stopped()
            assert stop["reason"] == "function breakpoint"
            plan = {v["name"]: v["value"] for v in client.scope("Plan")}
            marks.append([name for name in plan if name.startswith("→")])
            assert plan["kind"].startswith("solve")
            client.ok("continue", {"threadId": 1})
        # Each start of `stack` is the next step of the plan.
        assert marks == [["→ 1"], ["→ 2"], ["→ 3"], ["→ 4"]]
        assert client.stopped()["reason"] == "breakpoint"
        scopes = [s["name"] for s in client.ok("scopes", {"frameId": 0})["scopes"]]
        assert "Plan" not in scopes and "Fluents" in scopes


Frames = tuple[tuple[str, int | None], ...]
# The stops of a session: the stack and a value at each.
Stops = list[tuple[Frames, str | None]]


def stops_to_the_end(client: DapClient, value: str | None = None, how: str = "stepIn") -> Stops:
    """Go on (`how`) from the first stop to the end of the run (live: until the session ends)
    or of the recording: at each stop the stack's (name, line) and `value` evaluated there."""
    seen: Stops = []
    while True:
        try:
            stop = client.stopped()
        except AssertionError:  # a live session ends with its run: no more stops
            return seen
        if "the end of the recorded run" in stop.get("description", ""):
            return seen
        frames = client.ok("stackTrace", {"threadId": 1})["stackFrames"]
        shown = client.evaluate(value)["result"] if value is not None else None
        seen.append((tuple((f["name"], f.get("line")) for f in frames), shown))
        client.ok(how, {"threadId": 1})


def live_and_replayed(
    tmp_path: Path, launch: Message, value: str | None = None, breakpoints: dict[str, list[Message]] | None = None
) -> tuple[Stops, Stops]:
    """The stops of a live session stepping in from its entry (with `breakpoints`: going from
    breakpoint to breakpoint), and of its trace replayed the same way."""
    entry, how = (True, "stepIn") if breakpoints is None else (False, "continue")
    with dap_session(tmp_path) as client:
        client.start({**launch, "traceFile": "live.jsonl", "stopOnEntry": entry}, breakpoints)
        live = stops_to_the_end(client, value, how)
    with dap_session(tmp_path) as client:
        client.start({"trace": "live.jsonl", "stopOnEntry": entry}, breakpoints)
        replayed = stops_to_the_end(client, value, how)
    return live, replayed


def test_a_replay_stops_where_the_live_session_stopped_with_the_same_stack_and_values(tmp_path: Path) -> None:
    """Stepping in through a live run and through its trace: the same statements, calls and
    values, stop by stop."""
    live, replayed = live_and_replayed(tmp_path, {"program": str(BLOCKSWORLD), "platform": "sim"}, "loc(a)")
    # Every stop is before a transition, at its statement, as the trace's steps are; the
    # replay's last stop is the end of the recording, where the run's last step left it.
    assert len(live) > 10
    assert replayed[: len(live)] == live and len(replayed) == len(live) + 1


def test_a_recursion_has_the_same_stack_live_and_replayed(tmp_path: Path) -> None:
    """Stepping in through count_down(3) (a recursion) and the tail call at the end: the stack
    at each stop is the calls with their arguments, each caller at its call, live and replayed."""
    stops, replayed = live_and_replayed(tmp_path, {"program": str(REPLAY_AGENT)}, "counter()")
    live = [frames for frames, _ in stops]
    main = ("main()", 46)
    assert live[2:8] == [
        (("count_down(3)", 36), main),
        (("count_down(2)", 36), ("count_down(3)", 37), main),
        (("count_down(1)", 36), ("count_down(2)", 37), ("count_down(3)", 37), main),
        (("count_down(1)", 38), ("count_down(2)", 37), ("count_down(3)", 37), main),
        (("count_down(2)", 38), ("count_down(3)", 37), main),
        (("count_down(3)", 38), main),
    ]
    # counter() before each: 2 after visit(kitchen), then + 3, + 2, + 1, then - 1 on each return.
    assert [value for _, value in stops[2:8]] == ["1", "4", "6", "7", "6", "5"]
    # The `pick`'s body begins with a call: the stop is inside it, at its first transition.
    assert live[8] == (("visit(office)", 30), ("main()", 48))
    # The last call is main's last statement: the caller shows at the call's first
    # transition, and nothing of it is left after (a tail call).
    assert live[-2:] == [(("visit(hall)", 30), ("main()", 56)), (("visit(hall)", 31),)]
    assert replayed[: len(stops)] == stops


def test_a_breakpoint_on_a_call_stops_at_its_first_transition_live_and_replayed(tmp_path: Path) -> None:
    """Line 37, `count_down(n - 1);`: the calls count_down(2) and count_down(1) begin with a
    transition (line 36); count_down(0) has none of its own, so no stop there."""
    breakpoints = {str(REPLAY_AGENT): [{"line": 37}]}
    live, replayed = live_and_replayed(tmp_path, {"program": str(REPLAY_AGENT)}, "n", breakpoints)
    main = ("main()", 46)
    assert live == [
        ((("count_down(2)", 36), ("count_down(3)", 37), main), "2"),
        ((("count_down(1)", 36), ("count_down(2)", 37), ("count_down(3)", 37), main), "1"),
    ]
    assert replayed == live
