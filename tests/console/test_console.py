"""The operator console without a browser: its address and token rules on real HTTP requests,
the run control's Start, Stop and events (each an `operator` record of the trace), and the
options that do not apply. The page itself is tested in test_console_browser.py."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from gpp.console.access import Access, AccessError, Address, parse_address
from gpp.runtime.events import (
    CancelEvent,
    ErrorEvent,
    FinishEvent,
    OperatorEvent,
    UpdateEvent,
    decode,
    load_schema,
)
from tests.console.programs import endless_program, hidden_program
from tests.support.cli import run as gpp
from tests.support.console import ROOT, ConsoleRun

pytestmark = pytest.mark.slow


@pytest.fixture
def hidden(tmp_path: Path) -> tuple[Path, str]:
    return hidden_program(tmp_path)


def records(trace: Path) -> list[object]:
    return [decode(line) for line in trace.read_text(encoding="utf-8").splitlines()]


def test_waits_for_start_then_runs_with_the_operators_actions_in_the_trace(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    run = ConsoleRun(endless_program(tmp_path), "--console-wait", "--trace", str(trace))
    try:
        view = run.state_when(lambda v: v["status"] == "waiting for Start", "the wait for Start")
        assert view["fluents"] == [
            {"name": "rounds()", "value": "0", "changed": None},
            {"name": "halted()", "value": "false", "changed": None},
        ]
        assert view["can"] == {"start": True, "pause": False, "resume": False, "stop": True, "exog": True, "act": True}
        # An action run before the start: its effect shows at once.
        assert run.request("control", {"command": "act", "action": "tick", "args": {}}) == (200, {"ok": True})
        ticked = {"name": "rounds()", "value": "1", "changed": 1.0}
        run.state_when(lambda v: ticked in v["fluents"], "the tick's effect")
        assert run.request("control", {"command": "start"})[0] == 200
        run.state_when(lambda v: v["status"] == "running" and v["clock"] >= 3, "the run going on")
        assert run.request("control", {"command": "exog", "action": "halt", "args": {}})[0] == 200
        code, out = run.finish()
    finally:
        run.close()
    assert code == 0, out
    operator = [r for r in records(trace) if isinstance(r, OperatorEvent)]
    assert [(r.command, r.action, r.client) for r in operator] == [
        ("act", "tick()", "127.0.0.1"),
        ("start", None, "127.0.0.1"),
        ("exog", "halt()", "127.0.0.1"),
    ]
    # One validator for every line (`jsonschema.validate` checks the schema itself each time: a
    # run that went on longer before the halt took minutes).
    validator = jsonschema.Draft202012Validator(load_schema())
    for line in trace.read_text(encoding="utf-8").splitlines():
        validator.validate(json.loads(line))


def test_stop_ends_the_run_as_ctrl_c_does(tmp_path: Path) -> None:
    trace = tmp_path / "run.jsonl"
    run = ConsoleRun(endless_program(tmp_path), "--trace", str(trace))
    try:
        run.state_when(lambda v: v["clock"] >= 2, "the run going on")
        assert run.request("control", {"command": "stop"})[0] == 200
        code, _ = run.finish()
    finally:
        run.close()
    assert code == 130
    written = records(trace)
    stop = next(i for i, r in enumerate(written) if isinstance(r, OperatorEvent))
    assert written[stop] == OperatorEvent(t=written[stop].t, command="stop", client="127.0.0.1")  # type: ignore[attr-defined]
    after = written[stop + 1 :]
    # The stop's reason, the tick that ran if one did (cancelled, its end as the platform tells it), the finish.
    assert isinstance(after[0], ErrorEvent) and after[0].message == "stopped by the operator at the console"
    assert all(isinstance(r, CancelEvent | UpdateEvent) and r.action == "tick()" for r in after[1:-1])
    assert isinstance(after[-1], FinishEvent) and after[-1].status == "interrupted"


def test_the_token_and_the_origin(hidden: tuple[Path, str]) -> None:
    run = ConsoleRun(hidden[0], "--console-wait", "--console-token", "s3cret")
    try:
        assert run.url.endswith("/?token=s3cret")
        # No token, a wrong one: refused, the page and the live stream too.
        assert run.request("state")[0] == 401
        assert run.request("events?token=wrong")[0] == 401
        assert run.request("state?token=wrong")[0] == 401
        assert run.request("state?token=s3cret")[0] == 200
        # A control request takes the token in its header only, never from the query.
        assert run.request("control?token=s3cret", {"command": "stop"})[0] == 401
        assert run.request("control", {"command": "stop"}, {"X-Gpp-Token": "wrong"})[0] == 401
        # Another origin is refused even with the token (no CORS, no CSRF).
        other = {"X-Gpp-Token": "s3cret", "Origin": "http://robot-hijack.example"}
        assert run.request("control", {"command": "stop"}, other)[0] == 403
        assert run.request("control", {"command": "stop"}, {"X-Gpp-Token": "s3cret"})[0] == 200
        code, _ = run.finish()
    finally:
        run.close()
    assert code == 130


def test_loopback_without_a_token_is_allowed_and_another_origin_refused(hidden: tuple[Path, str]) -> None:
    run = ConsoleRun(hidden[0], "--console-wait")
    try:
        run.state_when(lambda v: v["status"] == "waiting for Start", "the wait for Start")
        status, answer = run.request("control", {"command": "start"}, {"Origin": "http://elsewhere.example"})
        assert status == 403 and "another origin" in answer["error"]
        status, answer = run.request("control", {"command": "start"}, {"Sec-Fetch-Site": "cross-site"})
        assert status == 403
        # An event with an argument that is not of its parameter's type: refused, said why.
        status, answer = run.request("control", {"command": "exog", "action": "ping", "args": {"n": "x", "r": "hall"}})
        assert status == 400 and "`n` of `ping`" in answer["error"]
        status, answer = run.request("control", {"command": "exog", "action": "pong", "args": {}})
        assert status == 400 and answer["error"] == "the program has no exogenous action `pong`"
        assert run.request("control", {"command": "stop"})[0] == 200
        run.finish()
    finally:
        run.close()


def test_a_host_name_other_than_loopback_is_refused_on_loopback() -> None:
    access = Access(Address("127.0.0.1", 8765), None)
    assert access.refusal({"host": "127.0.0.1:8765"}, {}, control=False) is None
    assert access.refusal({"host": "localhost:8765"}, {}, control=False) is None
    assert access.refusal({"host": "attacker.example:8765"}, {}, control=False) is not None


def test_addresses() -> None:
    assert parse_address("0.0.0.0:9000") == Address("0.0.0.0", 9000)
    assert parse_address("[::1]:80") == Address("::1", 80)
    assert parse_address("9000") == Address("127.0.0.1", 9000)
    assert parse_address("localhost:1").loopback and not parse_address("0.0.0.0:1").loopback
    with pytest.raises(AccessError):
        parse_address("nowhere")


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["--console-wait"], "--console-wait is for the operator console: it needs --console"),
        (["--console-token", "t"], "--console-token is for the operator console: it needs --console"),
        (["--console", "host:99999"], "--console: port 99999 is not a port number (0 to 65535)"),
        (["--console", "127.0.0.1:1", "--console-token", " "], "--console-token must not be empty"),
    ],
)
def test_options_that_do_not_apply_are_errors(args: list[str], said: str) -> None:
    result = gpp("run", str(ROOT / "tests/programs/control.gpp"), *args)
    assert result.returncode == 2
    assert f"error: {said}" in result.stderr


def test_gpp_test_has_no_console() -> None:
    result = gpp("test", str(ROOT / "tests/programs/control.gpp"), "--console")
    assert result.returncode == 2
    assert "No such option: --console" in result.stderr


def test_a_bare_console_takes_the_default_address() -> None:
    from gpp.cli.common import with_console_address

    assert with_console_address(["run", "a.gpp", "--console"]) == ["run", "a.gpp", "--console", "127.0.0.1:8765"]
    assert with_console_address(["run", "--console", "a.gpp"]) == ["run", "--console", "127.0.0.1:8765", "a.gpp"]
    assert with_console_address(["run", "--console", ":9"]) == ["run", "--console", ":9"]


def test_the_view_folds_a_runs_records() -> None:
    from gpp.console.state import RecordFold
    from gpp.runtime.events import EndEvent, PlanEvent, StartEvent, WaitingEvent

    state = RecordFold()
    plan = PlanEvent(
        t=0.0,
        kind="solve",
        feasible=True,
        value=1.0,
        horizon=2,
        policy=("go(a)", "go(b)"),
        nodes=3,
        cache_hits=0,
        pruned=0,
        reward_evaluations=1,
        seconds=0.0,
    )
    for event in (
        plan,
        StartEvent(
            t=1.0,
            action="go(a)",
            id=1,
            mapped="go",
            args={"to": {"symbol": "a"}},
            at=None,
            changes=({"fluent": "moving()", "value": True},),
        ),
        UpdateEvent(t=2.0, action="go(a)", status="failed", id=1, reason="blocked way"),
        WaitingEvent(t=2.0, statement="test(x)", at=None, condition="x is false"),
    ):
        state(event)
    view = state.view(clock=3.5)
    assert view["fluents"] == [{"name": "moving()", "value": "true", "changed": 1.0}]  # a start effect
    assert view["plan"]["step"] == 1 and view["plan"]["policy"] == ["go(a)", "go(b)"]
    assert view["activities"] == [
        {
            "id": 1,
            "action": "go(a)",
            "status": "failed",
            "cancelling": False,
            "started": 1.0,
            "elapsed": 2.5,
            "args": {"to": "a"},
        }
    ]
    assert view["failures"] == [{"t": 2.0, "action": "go(a)", "reason": "blocked way"}]
    assert view["waiting"] == {"statement": "test(x)", "at": None, "condition": "x is false"}
    state(EndEvent(t=4.0, action="go(a)", status="failed", hook="call"))
    assert state.view()["activities"] == []
