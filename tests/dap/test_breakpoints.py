"""Breakpoints of `gpp dap`: lines (verified, moved), conditions (checked, located errors), hit
counts, logpoints, functions, and the exception filters."""

from __future__ import annotations

from pathlib import Path

from tests.support.dap_client import DapClient, line_of

ERRANDS_ARGS = {"first": "kitchen", "rounds": 2}


def errands(dap: DapClient, programs: Path, breakpoints: list[dict[str, object]], **more: object) -> Path:
    program = programs / "errands.gpp"
    dap.start({"program": str(program), "args": ERRANDS_ARGS}, {str(program): breakpoints}, **more)
    return program


def set_lines(dap: DapClient, program: Path, breakpoints: list[dict[str, object]]) -> list[dict[str, object]]:
    placed: list[dict[str, object]] = dap.ok(
        "setBreakpoints", {"source": {"path": str(program)}, "breakpoints": breakpoints}
    )["breakpoints"]
    return placed


def continue_to_stop(dap: DapClient) -> tuple[dict[str, object], dict[str, object]]:
    dap.ok("continue", {"threadId": 1})
    return dap.stopped(), dap.top()


def test_line_breakpoints_are_verified_and_moved_to_the_next_statement(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.ok("initialize", {})
    dap.ok("launch", {"program": str(program), "args": ERRANDS_ARGS, "stopOnEntry": True})
    blank = line_of(program, "collect(first);") + 1
    placed = set_lines(dap, program, [{"line": blank}, {"line": 9999}, {"line": 0}])
    assert placed[0] == {
        "id": placed[0]["id"],
        "verified": True,
        "line": line_of(program, "collect(lab);"),
        "column": 5,
        "endLine": line_of(program, "collect(lab);"),
    }
    assert placed[1]["verified"] is False and placed[1]["message"] == "there is no statement on or after this line"
    assert placed[2]["verified"] is False
    other = programs / "crash.gpp"
    elsewhere = dap.ok("setBreakpoints", {"source": {"path": str(other)}, "breakpoints": [{"line": 9}]})
    assert elsewhere["breakpoints"][0]["message"] == "this file is not part of the program being debugged"


def test_a_breakpoint_on_a_call_stops_at_the_calls_first_transition(dap: DapClient, programs: Path) -> None:
    program = errands(dap, programs, [{"line": line_of(programs / "errands.gpp", "collect(lab);")}])
    stop = dap.stopped()
    assert stop["reason"] == "breakpoint"
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("collect(lab)", line_of(program, "go(r);")),
        ("main(kitchen, 2)", line_of(program, "collect(lab);")),
    ]
    # The first call is over: the kitchen's cups are all carried.
    assert dap.evaluate("carried()")["result"] == "2"


def test_a_condition_stops_only_where_it_holds(dap: DapClient, programs: Path) -> None:
    program = errands(
        dap, programs, [{"line": line_of(programs / "errands.gpp", "pick_up();"), "condition": "r == lab"}]
    )
    stop = dap.stopped()
    assert stop["reason"] == "breakpoint"
    assert dap.top()["name"] == "collect(lab)"
    assert dap.evaluate("carried()")["result"] == "2"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0
    assert program.exists()


def test_a_condition_that_does_not_check_is_refused_with_its_place(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.ok("initialize", {})
    dap.ok("launch", {"program": str(program), "args": ERRANDS_ARGS})
    pick = line_of(program, "pick_up();")
    placed = set_lines(
        dap,
        program,
        [
            {"line": pick, "condition": "cups(rr) > 0"},
            {"line": pick, "condition": "cups(r)"},
            {"line": pick, "hitCondition": "often"},
            {"line": pick, "logMessage": "at {robot_at( }"},
        ],
    )
    assert [b["verified"] for b in placed] == [False, False, False, False]
    assert placed[0]["message"] == (
        "the condition does not check: column 6: unknown name `rr`: not a variable, parameter or symbol"
    )
    assert placed[1]["message"] == "the condition does not check: column 1: a condition is a `bool`, not a `number`"
    assert str(placed[2]["message"]).startswith("the hit count does not check: column 1: a hit count is a number")
    assert str(placed[3]["message"]).startswith("the log message does not check: column 15: in `{robot_at( }`:")


def test_hit_counts_stop_at_the_given_hit(dap: DapClient, programs: Path) -> None:
    pick = line_of(programs / "errands.gpp", "pick_up();")
    errands(dap, programs, [{"line": pick, "hitCondition": "3"}])
    dap.stopped()
    # The third pick-up is the lab's first: two were made in the kitchen.
    assert dap.top()["name"] == "collect(lab)"
    assert dap.evaluate("carried()")["result"] == "2"
    dap.ok("continue", {"threadId": 1})
    dap.event("exited")


def test_hit_counts_every_nth_and_at_least(dap: DapClient, programs: Path) -> None:
    pick = line_of(programs / "errands.gpp", "pick_up();")
    errands(dap, programs, [{"line": pick, "hitCondition": ">= 2"}])
    dap.stopped()
    assert dap.evaluate("carried()")["result"] == "1"
    _, top = continue_to_stop(dap)
    assert top["name"] == "collect(lab)"


def test_logpoints_print_their_interpolated_expressions_and_go_on(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    errands(
        dap,
        programs,
        [{"line": line_of(program, "pick_up();"), "logMessage": "{r}: {cups(r)} left, carrying {carried()}"}],
    )
    assert dap.event("exited")["body"]["exitCode"] == 0
    assert [o for o in dap.outputs() if "left" in o] == [
        "kitchen: 2 left, carrying 0\n",
        "kitchen: 1 left, carrying 1\n",
        "lab: 1 left, carrying 2\n",
    ]
    logged = next(e for e in dap.seen if e.get("event") == "output" and "left" in e["body"]["output"])
    assert logged["body"]["line"] == line_of(program, "pick_up();")


def test_function_breakpoints_stop_when_a_call_starts(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    dap.ok("initialize", {})
    dap.ok("launch", {"program": str(program), "args": ERRANDS_ARGS})
    placed = dap.ok(
        "setFunctionBreakpoints", {"breakpoints": [{"name": "collect"}, {"name": "go"}, {"name": "colect"}]}
    )
    assert [b["verified"] for b in placed["breakpoints"]] == [True, True, False]
    assert placed["breakpoints"][2]["message"] == (
        "`colect` is not an action or procedure of the program; did you mean `collect`?"
    )
    dap.ok("configurationDone")
    # collect(kitchen) starts with go(kitchen): the stop is inside it, where go starts.
    stop = dap.stopped()
    assert stop["reason"] == "function breakpoint"
    assert len(stop["hitBreakpointIds"]) == 2
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("collect(kitchen)", line_of(program, "go(r);")),
        ("main(kitchen, 2)", line_of(program, "collect(first);")),
    ]
    assert dap.evaluate("robot_at()")["result"] == "office"
    # collect(lab) with go(lab), then go(office) in main.
    stop, top = continue_to_stop(dap)
    assert (top["name"], len(stop["hitBreakpointIds"])) == ("collect(lab)", 2)
    stop, top = continue_to_stop(dap)
    assert (top["name"], top["line"], stop["hitBreakpointIds"]) == (
        "main(kitchen, 2)",
        line_of(program, "go(office);"),
        [placed["breakpoints"][1]["id"]],
    )


def test_the_failed_filter_stops_where_an_activity_failed(dap: DapClient, programs: Path) -> None:
    program = programs / "failing.gpp"
    dap.start({"program": str(program)}, exceptions=["failed"])
    stop = dap.stopped()
    assert (stop["reason"], stop["text"], stop["description"]) == (
        "exception",
        "action failed",
        "go(lab) failed: scenario",
    )
    assert dap.evaluate("robot_at()")["result"] == "office"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 0


def test_the_blocked_filter_says_why_as_r0011_does(dap: DapClient, programs: Path) -> None:
    program = programs / "blocked.gpp"
    dap.start({"program": str(program)})  # blocked, error and no-plan are on by default
    stop = dap.stopped()
    assert (stop["reason"], stop["text"]) == ("exception", "program blocked")
    assert stop["description"].startswith("the program is blocked: this test is false")
    assert "door_open() = false" in stop["description"]
    frames = dap.ok("stackTrace", {"threadId": 1})["stackFrames"]
    assert [(f["name"], f["line"]) for f in frames] == [
        ("wait_for_door()", line_of(program, "test(door_open());")),
        ("main()", line_of(program, "wait_for_door();")),
    ]
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 1


def test_the_error_filter_stops_before_the_run_ends(dap: DapClient, programs: Path) -> None:
    program = programs / "crash.gpp"
    dap.start({"program": str(program)})
    stop = dap.stopped()
    assert (stop["reason"], stop["text"], stop["description"]) == ("exception", "run-time error", "division by zero")
    assert dap.evaluate("n()")["result"] == "0"
    dap.ok("continue", {"threadId": 1})
    assert dap.event("exited")["body"]["exitCode"] == 1


def test_the_no_plan_filter_stops_when_solve_finds_none(dap: DapClient, programs: Path) -> None:
    dap.start({"program": str(programs / "noplan.gpp")}, exceptions=["no-plan"])
    stop = dap.stopped()
    assert (stop["reason"], stop["text"]) == ("exception", "no plan")
    assert stop["description"] == "`solve` found no feasible plan"


def test_filters_left_out_do_not_stop(dap: DapClient, programs: Path) -> None:
    dap.start({"program": str(programs / "failing.gpp")}, exceptions=[])
    assert dap.event("exited")["body"]["exitCode"] == 0
    assert not [e for e in dap.seen if e.get("event") == "stopped"]


def test_a_client_counting_lines_from_0_gets_lines_from_0(dap: DapClient, programs: Path) -> None:
    program = programs / "errands.gpp"
    pick = line_of(program, "pick_up();")
    dap.ok("initialize", {"adapterID": "gpp", "linesStartAt1": False, "columnsStartAt1": False})
    dap.ok("launch", {"program": str(program), "args": ERRANDS_ARGS})
    placed = set_lines(dap, program, [{"line": pick - 1}])
    assert (placed[0]["line"], placed[0]["column"]) == (pick - 1, 8)
    dap.ok("configurationDone")
    dap.stopped()
    assert (dap.top()["line"], dap.top()["column"]) == (pick - 1, 8)
