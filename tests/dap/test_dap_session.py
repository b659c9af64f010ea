"""`gpp dap` driven through a real DAP client over stdio: launching, the stack, the scopes,
evaluate, and the end of a session (tests.support.dap_client)."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from gpp.dap.protocol import encode_message, read_message
from tests.support.cli import Runner
from tests.support.dap_client import ROOT, DapClient, line_of

# A `gpp dap` process for each test.
pytestmark = pytest.mark.slow

ERRANDS_ARGS = {"first": "kitchen", "rounds": 2}


def assert_ended_by_the_debugger(trace: Path) -> None:
    """The run's trace says once that the debugger ended it, and ends with its `finish`."""
    records = [json.loads(line) for line in trace.read_text().splitlines()]
    errors = [r["message"] for r in records if r["event"] == "error"]
    assert errors == ["the debugger ended the run"]
    assert records[-1]["event"] == "finish" and records[-1]["status"] == "interrupted"


def launch_errands(dap: DapClient, programs: Path, **more: object) -> Path:
    program = programs / "errands.gpp"
    dap.start({"program": str(program), "platform": "dummy", "args": ERRANDS_ARGS, "stopOnEntry": True, **more})
    return program


def test_initialize_says_what_the_adapter_supports(dap: DapClient) -> None:
    capabilities = dap.ok("initialize", {"adapterID": "gpp"})
    assert capabilities["supportsConfigurationDoneRequest"] is True
    assert capabilities["supportsConditionalBreakpoints"] is True
    assert capabilities["supportsLogPoints"] is True
    assert capabilities["supportsFunctionBreakpoints"] is True
    filters = {f["filter"] for f in capabilities["exceptionBreakpointFilters"]}
    assert filters == {"failed", "blocked", "error", "no-plan"}


def test_stop_on_entry_stops_before_the_first_transition_of_main(dap: DapClient, programs: Path) -> None:
    program = launch_errands(dap, programs)
    stop = dap.stopped()
    assert stop["reason"] == "entry"
    # main's first transition is collect(kitchen)'s first (a call is no transition).
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("collect(kitchen)", line_of(program, "go(r);")),
        ("main(kitchen, 2)", line_of(program, "collect(first);")),
    ]
    assert frames[0]["source"]["path"] == str(program.resolve())
    assert dap.ok("threads")["threads"] == [{"id": 1, "name": "main"}]


def test_the_stack_shows_the_calls_with_their_arguments_and_places(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    push = line_of(program, "push_back(visited(), r);")
    dap.start({"program": str(program), "args": ERRANDS_ARGS}, {str(program): [{"line": push}]})
    assert dap.stopped()["reason"] == "breakpoint"
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("collect(kitchen)", push),
        ("main(kitchen, 2)", line_of(program, "collect(first);")),
    ]
    assert dap.ok("stackTrace", {"threadId": 1, "startFrame": 1, "levels": 1})["stackFrames"][0]["name"] == (
        "main(kitchen, 2)"
    )


def test_scopes_show_arguments_fluents_activities_and_pending_events(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    pick = line_of(program, "pick_up();")
    dap.start({"program": str(program), "args": ERRANDS_ARGS}, {str(program): [{"line": pick}]})
    dap.stopped()
    names = [s["name"] for s in dap.ok("scopes", {"frameId": 0})["scopes"]]
    assert names == ["Arguments", "Locals", "Fluents", "Activities", "Exogenous events"]
    assert [(v["name"], v["value"]) for v in dap.scope("Arguments")] == [("r", "kitchen")]
    assert [(v["name"], v["value"]) for v in dap.scope("Arguments", frame=1)] == [("first", "kitchen"), ("rounds", "2")]
    fluents = {v["name"]: v for v in dap.scope("Fluents")}
    assert fluents["robot_at()"]["value"] == "kitchen"
    assert fluents["carried()"]["value"] == "0"
    # Grouped by fluent: the instances of cups(r), each a golog++ literal.
    cups = dap.ok("variables", {"variablesReference": fluents["cups(r)"]["variablesReference"]})["variables"]
    assert [(v["name"], v["value"]) for v in cups] == [
        ("cups(office)", "0"),
        ("cups(kitchen)", "2"),
        ("cups(lab)", "1"),
    ]
    # A list and a compound are expandable; their parts say how to evaluate them.
    visited = fluents["visited()"]
    assert visited["value"] == "[kitchen]"
    items = dap.ok("variables", {"variablesReference": visited["variablesReference"]})["variables"]
    assert [(v["name"], v["value"], v["evaluateName"]) for v in items] == [("[0]", "kitchen", "visited()[0]")]
    pose = fluents["pose()"]
    assert pose["value"] == "Pose{x=1,y=2}"
    parts = dap.ok("variables", {"variablesReference": pose["variablesReference"]})["variables"]
    assert [(v["name"], v["value"], v["type"]) for v in parts] == [("x", "1", "number"), ("y", "2", "number")]
    assert dap.evaluate(parts[1]["evaluateName"])["result"] == "2"
    # Before the second pick-up the first has ended and was consumed: no activity runs.
    assert dap.scope("Activities") == []


def test_a_running_activity_shows_with_its_state_and_start(dap: DapClient, programs: Path) -> None:
    program = programs / "failing.gpp"
    dap.start({"program": str(program)}, {str(program): [{"line": line_of(program, "test(true);")}]})
    dap.stopped()
    activities = dap.scope("Activities")
    assert [(v["name"], v["value"]) for v in activities] == [("go(lab)", "running, started at 0.000 s")]


def test_evaluate_in_the_scope_of_the_stopped_statement(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.start(
        {"program": str(program), "args": ERRANDS_ARGS}, {str(program): [{"line": line_of(program, "pick_up();")}]}
    )
    dap.stopped()
    assert dap.evaluate("cups(r) > 1 & robot_at() == r") == {"result": "true", "type": "bool", "variablesReference": 0}
    assert dap.evaluate("cups(r)", context="hover")["result"] == "2"
    # The caller's frame has its own parameters in scope.
    assert dap.evaluate("rounds * 10", frame=1)["result"] == "20"
    assert dap.evaluate("exists(Room x) cups(x) == 1")["result"] == "true"
    listed = dap.evaluate("visited()")
    assert listed["result"] == "[kitchen]"
    assert listed["variablesReference"] > 0


def test_evaluate_locates_what_does_not_check(dap: DapClient, programs: Path) -> None:
    launch_errands(dap, programs)
    dap.stopped()
    assert dap.error("evaluate", {"expression": "cups(kichen) + 1", "frameId": 0}).startswith(
        "column 6: unknown name `kichen`"
    )
    assert dap.error("evaluate", {"expression": "carried() +", "frameId": 0}).startswith("column 12:")
    assert dap.error("evaluate", {"expression": "robot_at() + 1", "frameId": 0}).startswith(
        "column 12: cannot add `Room` and `number`"
    )
    assert dap.error("evaluate", {"expression": "1); go(lab", "frameId": 0}) == "column 1: one expression is expected"
    # In main's scope (the caller's frame), `r` (collect's parameter) is not visible.
    assert dap.evaluate("cups(r)")["result"] == "2"
    assert "unknown name `r`" in dap.error("evaluate", {"expression": "cups(r)", "frameId": 1})
    assert dap.error("evaluate", {"expression": "carried() / 0", "frameId": 0}) == "division by zero"


def test_questions_while_the_run_runs_or_before_launch_are_clear_errors(dap: DapClient, programs: Path) -> None:
    dap.ok("initialize", {})
    assert dap.error("stackTrace", {"threadId": 1}) == "nothing is launched yet"
    dap.ok("launch", {"program": str(programs / "forever.gpp")})
    dap.ok("configurationDone")
    assert dap.error("evaluate", {"expression": "ticks()"}) == "the run is running: pause it first"
    assert dap.error("scopes", {"frameId": 0}) == "the run is running: pause it first"


def test_launch_refuses_bad_input_with_one_clear_line(dap: DapClient, programs: Path) -> None:
    dap.ok("initialize", {})
    unchecked = dap.error("launch", {"program": str(programs / "unchecked.gpp")})
    assert unchecked.startswith("the program does not check: ")
    assert unchecked.endswith("unchecked.gpp:2:5: unknown action or procedure `undefined_action`")
    assert dap.error("launch", {"program": str(programs / "missing.gpp")}).startswith(
        "launch's `program`: no such file"
    )
    assert dap.error("launch", {"programm": "errands.gpp"}).startswith("launch has no argument `programm`")
    assert dap.error("launch", {}).startswith("launch needs `program`")
    assert dap.error("launch", {"program": "errands.gpp", "platform": "dumy"}).startswith(
        "launch's `platform`: unknown platform `dumy`"
    )
    assert dap.error("launch", {"program": "errands.gpp", "args": {"first": "garage", "rounds": 1}}).startswith(
        "launch's `args`:"
    )
    assert "needs a value for `rounds`" in dap.error("launch", {"program": "errands.gpp", "args": {"first": "lab"}})
    assert dap.error("launch", {"program": "errands.gpp", "stopOnEntry": "yes"}) == (
        'launch\'s `stopOnEntry` is true or false, not "yes"'
    )
    bad_option = dap.error("launch", {"program": "blocked.gpp", "platformOptions": {"sed": 3}})
    assert bad_option.startswith("the run cannot start:") and "sed" in bad_option
    assert dap.error("attach", {}).startswith("gpp dap launches runs")
    # After all that, a good launch still works.
    dap.ok("launch", {"program": "blocked.gpp", "stopOnEntry": True})
    dap.ok("configurationDone")
    assert dap.stopped()["reason"] == "entry"


def test_the_adapter_answers_every_request_and_survives_garbage(dap: DapClient, programs: Path) -> None:
    assert dap.error("flyToTheMoon", {}) == "`flyToTheMoon` is not a request gpp dap answers"
    assert dap.error("setBreakpoints", {"source": {}}) == "setBreakpoints needs `source.path`"
    assert dap.error("setExceptionBreakpoints", {"filters": ["oops"]}).startswith("unknown exception filter `oops`")
    assert dap.error("evaluate", {"expression": 3}) == "evaluate needs an `expression`"
    assert dap.process.stdin is not None
    dap.process.stdin.write(b"Content-Length: 5\r\n\r\nnot j")
    dap.process.stdin.flush()
    assert dap.event("output")["body"]["output"].startswith("gpp dap: a message that is not JSON")
    launch_errands(dap, programs)
    assert dap.stopped()["reason"] == "entry"
    assert dap.error("stackTrace", {"threadId": 1, "startFrame": "x"}) == "`startFrame` is a number"
    assert dap.error("variables", {"variablesReference": 999}).startswith("no variables under reference 999")
    assert dap.error("scopes", {"frameId": 7}) == "there is no stack frame 7"
    assert dap.error("stepBack", {"threadId": 1}).startswith("stepping back needs a recorded run")


def test_the_run_goes_to_its_end_and_the_session_says_so(dap: DapClient, programs: Path) -> None:
    launch_errands(dap, programs, traceFile="run.jsonl")
    dap.stopped()
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"] == {"exitCode": 0}
    dap.event("terminated")
    assert "errands.gpp: finished\n" in dap.outputs()
    records = [json.loads(line) for line in (programs / "run.jsonl").read_text().splitlines()]
    assert records[-1]["event"] == "finish" and records[-1]["status"] == "finished"


def test_disconnect_ends_the_run_and_finishes_its_trace(dap: DapClient, programs: Path) -> None:
    dap.start({"program": "forever.gpp", "traceFile": "run.jsonl"})
    dap.ok("pause", {"threadId": 1})
    assert dap.stopped()["reason"] == "pause"
    dap.ok("disconnect", {"terminateDebuggee": True})
    assert dap.close() == 0
    assert_ended_by_the_debugger(programs / "run.jsonl")


def test_terminate_ends_a_running_run(dap: DapClient, programs: Path) -> None:
    dap.start({"program": "forever.gpp", "traceFile": "run.jsonl"})
    dap.ok("terminate", {})
    dap.event("terminated")
    assert_ended_by_the_debugger(programs / "run.jsonl")
    assert dap.error("evaluate", {"expression": "ticks()"}) == "the run is running: pause it first"


def test_no_debug_runs_without_stopping(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.start(
        {"program": str(program), "args": ERRANDS_ARGS, "noDebug": True, "stopOnEntry": True},
        {str(program): [{"line": line_of(program, "pick_up();")}]},
    )
    assert dap.event("exited")["body"] == {"exitCode": 0}
    assert not [e for e in dap.seen if e.get("event") == "stopped"]


def test_sigterm_ends_the_session_and_its_run_with_the_trace_finished(dap: DapClient, programs: Path) -> None:
    dap.start({"program": "forever.gpp", "traceFile": "run.jsonl"})
    dap.ok("pause", {"threadId": 1})
    dap.stopped()
    dap.process.send_signal(signal.SIGTERM)
    assert dap.process.wait(timeout=60) == 143
    assert_ended_by_the_debugger(programs / "run.jsonl")


def test_the_adapter_serves_one_session_on_a_loopback_tcp_port(programs: Path) -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    server = subprocess.Popen(
        [sys.executable, "-m", "gpp", "dap", "--tcp", f"127.0.0.1:{port}"],
        cwd=programs,
        env=env,
        stderr=subprocess.PIPE,
    )
    try:
        assert server.stderr is not None
        assert server.stderr.readline().decode() == f"gpp dap: listening on 127.0.0.1:{port}\n"
        with socket.create_connection(("127.0.0.1", port), timeout=60) as connection:
            stream = connection.makefile("rwb")
            stream.write(encode_message({"seq": 1, "type": "request", "command": "initialize", "arguments": {}}))
            stream.flush()
            answer = read_message(stream)
            assert answer is not None and answer["success"] is True and answer["command"] == "initialize"
            stream.write(encode_message({"seq": 2, "type": "request", "command": "disconnect"}))
            stream.flush()
            assert read_message(stream) is not None
        assert server.wait(timeout=60) == 0
    finally:
        server.kill()
        server.wait()


def test_tcp_takes_loopback_addresses_only(gpp: Runner) -> None:
    refused = gpp("dap", "--tcp", "0.0.0.0:4711")
    assert refused.returncode == 2
    assert "loopback addresses only" in refused.stderr


def test_platform_options_reach_the_platform(dap: DapClient, programs: Path) -> None:
    # failing.gpp without its `// scenario:` line: the scenario comes from the launch instead.
    plain = programs / "plain.gpp"
    plain.write_text((programs / "failing.gpp").read_text().replace("// scenario: failing.toml\n", ""))
    dap.start(
        {"program": "plain.gpp", "platform": "dummy", "platformOptions": {"scenario": "failing.toml"}},
        exceptions=["failed"],
    )
    stop = dap.stopped()
    assert (stop["reason"], stop["description"]) == ("exception", "go(lab) failed: scenario")


ODD_ARGUMENTS: list[object] = [
    None,
    {},
    {"threadId": "one", "frameId": -1, "variablesReference": -5, "expression": "", "levels": -1},
    {"source": {"path": 3}, "breakpoints": [1, 2], "lines": "12", "filters": "failed"},
    {"breakpoints": [{"line": "ten", "condition": 5, "hitCondition": [], "logMessage": None}], "source": {"path": "x"}},
    {"expression": "(((", "context": 7, "frameId": 99},
]


def test_every_request_with_odd_arguments_gets_an_answer_and_no_internal_error(dap: DapClient, programs: Path) -> None:
    commands = [
        "threads", "stackTrace", "scopes", "variables", "evaluate", "setBreakpoints", "setFunctionBreakpoints",
        "setExceptionBreakpoints", "continue", "next", "stepIn", "stepOut", "stepBack", "reverseContinue", "pause",
        "source", "configurationDone",
    ]  # fmt: skip
    dap.ok("initialize", {})

    def ask_everything() -> None:
        for command in commands:
            for arguments in ODD_ARGUMENTS:
                answer = dap.request(command, arguments)  # type: ignore[arg-type]
                assert "internal error" not in str(answer.get("message", "")), (command, arguments, answer)

    ask_everything()  # before a launch
    dap.ok("launch", {"program": str(programs / "errands.gpp"), "args": ERRANDS_ARGS, "stopOnEntry": True})
    dap.stopped()
    ask_everything()  # stopped, or running after a continue among them
    dap.ok("pause", {"threadId": 1})
    assert dap.process.poll() is None
    dap.ok("disconnect", {})
    assert dap.close() == 0
    assert dap.process.stderr is not None
    assert b"Traceback" not in dap.process.stderr.read()
